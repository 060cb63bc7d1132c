"""The report's page driven in Debian's Chromium through Selenium (chromium-driver; nothing
downloads a browser): for one design of every cam kind the slider is moved to several cam
angles, and the follower's drawn position, the cam's turn and the readout are held to the
motion table and to the follower's geometry (SPEC §2, computed here from the report's numbers);
the page raises no script error and draws something; the figures of the cam at its speed follow
the slider too, and the drawing's title says the frame's cam angle; no legend box covers a
plotted curve (from the SVG's geometry), and no text of a figure covers another, crosses a legend
box or leaves the figure (as Chromium lays the text out); the figures fill their cards with text
of 11 px and more; in windows 1024 to 1600 px wide nothing is wider than its card and the page
does not scroll sideways; printed to PDF, no page of any design ends on a heading, alone or with
only the words that lead into its table or figure. The JSON report carries every input of the design
that the design file takes for its cam type and follower (the design model's fields walked)."""

from __future__ import annotations

import html
import json
import math
import re
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from pydantic import BaseModel

from camfab.design import Design
from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGN_FILES, DESIGNS, chromium, tool

#: One design of every cam kind (and of every follower of a disc cam).
KINDS = ["seed-10-4", "seed-10-3-oscillating", "demo-oscillating-flat", "demo-inch-flat",
         "demo-mushroom-cw", "demo-cylindrical", "seed-7-10-circular-arc", "demo-tangent-roller",
         "demo-groove-roller", "demo-conjugate", "demo-conjugate-oscillating",
         "demo-constant-breadth", "demo-linear-roller"]

#: Frames the slider is moved to.
FRAMES = (0, 37, 90, 181, 270, 359)


@pytest.fixture(scope="module")
def browser() -> Any:
    driver = chromium("--disable-gpu", "--window-size=1280,1000")
    yield driver
    driver.quit()


def _page(name: str, folder: Path) -> tuple[Path, dict[str, Any], str]:
    design = load_design(DESIGNS / f"{name}.yaml")
    files = render(analyse(design)).files
    page = folder / f"{name}-report.html"
    page.write_bytes(files[page.name])
    report = json.loads(files[f"{name}-report.json"])
    csv = files[f"{name}-motion.csv"].decode()
    return page, report, csv


def _frame(browser: Any, index: int) -> None:
    browser.execute_script(
        "var s = document.getElementById('angle'); s.value = arguments[0];"
        "s.dispatchEvent(new Event('input'));", index)


def _matrix(browser: Any, element_id: str) -> tuple[list[float], list[float]]:
    """The group's transform as the browser reads it (a, b, c, d, e, f), and its data map."""
    return browser.execute_script(
        "var g = document.getElementById(arguments[0]);"
        "var t = g.transform.baseVal.consolidate();"
        "var m = t ? t.matrix : {a: 1, b: 0, c: 0, d: 1, e: 0, f: 0};"
        "return [[m.a, m.b, m.c, m.d, m.e, m.f], g.getAttribute('data-map').split(' ')"
        ".map(Number)];", element_id)


def _moved(point: tuple[float, float], matrix: list[float], mapping: list[float]) -> np.ndarray:
    """A drawing point (mm) moved by the group's transform, back in mm."""
    a, b, c, d, e, f = matrix
    ox, oy, kx, ky = mapping
    px, py = ox + kx * point[0], oy - ky * point[1]
    qx, qy = a * px + c * py + e, b * px + d * py + f
    return np.array([(qx - ox) / kx, (oy - qy) / ky])


def _expected(report: dict[str, Any], theta_deg: float, lift: float, lift0: float) -> tuple[
        np.ndarray, np.ndarray]:
    """Where the follower's trace point is at θ and at 0 (mm), from the report's numbers and
    SPEC §2 (independent of the drawing's code)."""
    geometry, follower, cam = report["geometry"], report["follower"], report["design"]["cam"]
    if report["cam_type"] == "cylindrical":
        sigma = 1 if report["rotation"] == "ccw" else -1
        radius, start = geometry["radius_mm"], geometry["groove_start_mm"]
        shift = 2 * math.pi if sigma > 0 else 0.0

        def at(t: float, s: float) -> np.ndarray:
            return np.array([radius * (shift - sigma * math.radians(t)), start + s])

        return at(theta_deg, lift), at(0.0, lift0)
    if report["cam_type"] == "linear":
        base = cam["base_height"] * (25.4 if report["units"] == "in" else 1.0)
        return np.array([0.0, base + lift]), np.array([0.0, base + lift0])
    if follower["motion"] == "oscillating":
        a, arm = follower["pivot_distance_mm"], follower["arm_length_mm"]
        side = 1 if follower["pivot_side"] == "right" else -1
        rest = math.radians(geometry["rest_arm_angle_deg"])

        def swing(s_deg: float) -> np.ndarray:
            psi = rest + math.radians(s_deg)
            return np.array([side * (a - arm * math.cos(psi)), arm * math.sin(psi)])

        return swing(lift), swing(lift0)
    e = follower["offset_mm"]
    if follower["type"] == "flat":
        y0 = geometry["base_radius_mm"]
    else:
        y0 = math.sqrt(geometry["prime_radius_mm"] ** 2 - e * e)
    return np.array([e, y0 + lift]), np.array([e, y0 + lift0])


@pytest.mark.parametrize("name", KINDS)
def test_the_slider_moves_the_follower_the_cam_and_the_readout_as_the_motion_table_says(
        browser: Any, tmp_path: Path, name: str) -> None:
    page, report, csv = _page(name, tmp_path)
    rows = [[float(v) if v else math.nan for v in line.split(",")]
            for line in csv.strip().splitlines()[1:]]
    table = report["lift_table"]["rows"]
    browser.get(page.as_uri())
    assert browser.execute_script("return document.body.dataset.ready") == "yes"
    sigma = 1 if report["rotation"] == "ccw" else -1
    oscillating = report["follower"]["motion"] == "oscillating"
    lift_column = 2 if report["cam_type"] == "linear" else 1
    frames = int(browser.execute_script("return +document.getElementById('angle').max")) + 1
    assert frames == len(table)  # 1° steps: every row of the motion table
    lift0 = rows[0][lift_column]
    for index in FRAMES:
        _frame(browser, index)
        theta = rows[index][0]
        lift = rows[index][lift_column]
        readout = browser.execute_script(
            "return Array.prototype.map.call(document.querySelectorAll('#readout td'),"
            "function (td) { return td.textContent; });")
        assert float(readout[0]) == pytest.approx(theta)
        shown = lift / (25.4 if report["units"] == "in" and not oscillating else 1.0)
        assert float(readout[lift_column]) == pytest.approx(shown, rel=1e-5, abs=1e-5)
        assert table[index][1] == pytest.approx(lift, abs=2e-6)
        matrix, mapping = _matrix(browser, "drawing-follower")
        want, start = _expected(report, theta, lift, lift0)
        drawn = _moved(tuple(start), matrix, mapping)
        resolution = 0.25 / mapping[2]  # a quarter of a point of the drawing, in mm
        assert np.allclose(drawn, want, atol=max(resolution, 1e-3)), (index, drawn, want)
        if report["cam_type"] not in ("cylindrical",):
            matrix, mapping = _matrix(browser, "drawing-cam")
            if report["cam_type"] == "linear":
                stroke = report["design"]["cam"]["stroke"] * (
                    25.4 if report["units"] == "in" else 1.0)
                assert matrix[4] / mapping[2] == pytest.approx(-stroke * theta / 360.0,
                                                               abs=1e-3)
            else:  # the plate turns σθ about its centre (SVG's y runs down)
                turned = math.degrees(math.atan2(-matrix[1], matrix[0]))
                assert (turned - sigma * theta + 180.0) % 360.0 - 180.0 == pytest.approx(
                    0.0, abs=1e-3)
    # the cursor stands at the last frame's cam angle on the diagrams
    shift = browser.execute_script(
        "var c = document.querySelector('[data-cursor]');"
        "return [c.transform.baseVal.consolidate().matrix.e, +c.getAttribute('data-cursor')"
        ".split(' ')[1]];")
    assert shift[0] == pytest.approx(shift[1] * rows[FRAMES[-1]][0], abs=0.01)
    assert browser.execute_script("return document.body.dataset.errors") == "0"
    logs = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
    assert not logs, logs
    # the drawing is drawn: many pixels that are not the background
    shot = tmp_path / "drawing.png"
    drawing = browser.find_element("id", "drawing")
    browser.execute_script("arguments[0].scrollIntoView(true);", drawing)
    drawing.screenshot(str(shot))
    from PIL import Image

    pixels = np.asarray(Image.open(shot).convert("L"))
    assert np.count_nonzero(pixels < 200) > 2000


def test_the_figures_at_speed_follow_the_slider_and_the_readout_shows_their_numbers(
        browser: Any, tmp_path: Path) -> None:
    """Every figure over the cam angle (the diagrams, the contact stress, the follower train)
    moves its cursor to the frame's angle, and the readout gives the motion table's contact
    stress, dynamic displacement and dynamic contact force of that row."""
    page, _, csv = _page("demo-valve-at-speed", tmp_path)
    header = csv.splitlines()[0].split(",")
    rows = [[float(v) for v in line.split(",")] for line in csv.strip().splitlines()[1:]]
    browser.get(page.as_uri())
    assert browser.execute_script("return document.body.dataset.ready") == "yes"
    labels = browser.execute_script(
        "return Array.prototype.map.call(document.querySelectorAll('#readout th'),"
        "function (th) { return th.textContent; });")
    for label in ("contact stress (MPa)", "dynamic displacement (mm)",
                  "dynamic contact force (N)"):
        assert label in labels
    for index in (0, 90, 200, 333):
        _frame(browser, index)
        readout = browser.execute_script(
            "return Array.prototype.map.call(document.querySelectorAll('#readout td'),"
            "function (td) { return td.textContent; });")
        for name, label in (("contact_stress_MPa", "contact stress (MPa)"),
                            ("dynamic_displacement_mm", "dynamic displacement (mm)"),
                            ("dynamic_contact_force_N", "dynamic contact force (N)")):
            want = rows[index][header.index(name)]
            assert float(readout[labels.index(label)]) == pytest.approx(want, rel=1e-5,
                                                                          abs=1e-6)
        shifts = browser.execute_script(
            "return Array.prototype.map.call(document.querySelectorAll('[data-cursor]'),"
            "function (c) { var m = c.transform.baseVal.consolidate();"
            "return [m ? m.matrix.e : 0, +c.getAttribute('data-cursor').split(' ')[1]]; });")
        assert len(shifts) == 3
        for shift, per_degree in shifts:
            assert shift == pytest.approx(per_degree * rows[index][0], abs=0.01)
    assert browser.execute_script("return document.body.dataset.errors") == "0"


#: One design of each drawing: a plate, a drum, a globoid, a linear cam.
DRAWINGS = ["seed-10-4", "demo-cylindrical", "demo-globoidal-concave", "demo-linear-roller"]


@pytest.mark.parametrize("name", DRAWINGS)
def test_the_drawing_s_title_says_the_frame_s_cam_angle(browser: Any, tmp_path: Path,
                                                       name: str) -> None:
    """The title over the drawing names the cam angle the slider shows (and a linear cam's
    travel there), so a screenshot or a print at any frame is labelled with its own angle."""
    page, report, csv = _page(name, tmp_path)
    rows = [[float(v) if v else math.nan for v in line.split(",")]
            for line in csv.strip().splitlines()[1:]]
    browser.get(page.as_uri())
    for index in (0, 37, 90, 270):
        _frame(browser, index)
        titles = browser.execute_script(
            "var name = arguments[0];"
            "return Array.prototype.map.call(document.querySelectorAll('#drawing svg text'),"
            "function (t) { return t.textContent; }).filter(function (t) {"
            "return t.indexOf(name) === 0; });", name)
        assert len(titles) == 1, titles
        theta = rows[index][0]
        assert f"θ = {theta:g}°" in titles[0], (index, titles[0])
        if report["cam_type"] == "linear":  # the travel: a stroke is 360° of cam angle
            travel = report["design"]["cam"]["stroke"] * theta / 360.0
            assert f"travel {travel:.6g} mm" in titles[0], (index, titles[0])
    assert browser.execute_script("return document.body.dataset.errors") == "0"


#: Every figure's text and legend boxes in the SVG's units, as Chromium lays the text out (a
#: label of several lines one box a line, a turned label's box turned); the figure's size.
_FIGURE_TEXT = r"""
return Array.prototype.map.call(document.querySelectorAll('figure svg'), function (svg) {
  var view = svg.viewBox.baseVal, back = svg.getCTM().inverse();
  var boxes = [];
  svg.querySelectorAll('text').forEach(function (t) {
    var spans = t.querySelectorAll('tspan');
    (spans.length ? Array.prototype.slice.call(spans) : [t]).forEach(function (part) {
      var b = part.getBBox(), m = back.multiply(t.getCTM());
      var xs = [], ys = [];
      [[b.x, b.y], [b.x + b.width, b.y], [b.x, b.y + b.height],
       [b.x + b.width, b.y + b.height]].forEach(function (q) {
        var p = svg.createSVGPoint(); p.x = q[0]; p.y = q[1]; p = p.matrixTransform(m);
        xs.push(p.x); ys.push(p.y); });
      boxes.push([part.textContent, Math.min.apply(null, xs), Math.min.apply(null, ys),
                  Math.max.apply(null, xs), Math.max.apply(null, ys)]);
    });
  });
  var legends = Array.prototype.map.call(svg.querySelectorAll('rect[stroke="#cccccc"]'),
    function (r) { var x = +r.getAttribute('x'), y = +r.getAttribute('y');
                   return [x, y, x + +r.getAttribute('width'), y + +r.getAttribute('height')]; });
  return {where: svg.closest('section').id, width: view.width, height: view.height,
          texts: boxes, legends: legends};
});
"""


def _overlap(a: list[float], b: list[float], slack: float = 0.5) -> bool:
    """Whether boxes (x0, y0, x1, y1) overlap by more than *slack* (pt) both ways."""
    return (min(a[2], b[2]) - max(a[0], b[0]) > slack
            and min(a[3], b[3]) - max(a[1], b[1]) > slack)


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_no_text_of_a_figure_covers_another_crosses_a_legend_or_leaves_the_figure(
        browser: Any, tmp_path: Path, path: Path) -> None:
    """Measured on the text as Chromium lays it out (:func:`test_no_legend_covers_a_curve`
    holds legend boxes against the curves only: a legend beside its panel covers none, and a
    label of two lines that overflowed its box onto the next entry, as the globoid's undercut
    limit's did, went unseen)."""
    page, _, _ = _page(path.stem, tmp_path)
    browser.get(page.as_uri())
    figures = browser.execute_script(_FIGURE_TEXT)
    assert figures
    for figure in figures:
        texts, where = figure["texts"], figure["where"]
        for legend in figure["legends"]:
            assert legend[0] > -0.5 and legend[2] < figure["width"] + 0.5, (where, legend)
        for text, *box in texts:
            assert box[0] > -0.5 and box[1] > -0.5, (where, text, box)
            assert box[2] < figure["width"] + 0.5 and box[3] < figure["height"] + 0.5, (
                where, text, box, figure["width"])
        for k, (text, *box) in enumerate(texts):
            for other, *other_box in texts[k + 1:]:
                assert not _overlap(box, other_box), (where, text, other)
            for legend in figure["legends"]:  # inside a legend box, or clear of it
                inside = (box[0] > legend[0] - 0.5 and box[1] > legend[1] - 0.5
                          and box[2] < legend[2] + 0.5 and box[3] < legend[3] + 0.5)
                assert inside or not _overlap(box, legend), (where, text, legend)


@pytest.mark.parametrize("name", ["seed-10-4", "demo-globoidal-concave", "demo-valve-at-speed"])
def test_the_figures_fill_their_cards_with_text_of_11_px_and_more(browser: Any, tmp_path: Path,
                                                                  name: str) -> None:
    """At 100 % zoom in a window 1280 px wide: every figure (the drawing, the diagrams, the
    figures of the cam at its speed) at least 90 % of its section's inner width, and the
    smallest text of each (tick labels, legends, axis labels) at least 11 px high on the
    screen."""
    page, _, _ = _page(name, tmp_path)
    browser.get(page.as_uri())
    figures = browser.execute_script(
        "return Array.prototype.map.call(document.querySelectorAll('figure svg'),"
        "function (svg) { var s = svg.closest('section'), c = getComputedStyle(s);"
        "var inner = s.clientWidth - parseFloat(c.paddingLeft) - parseFloat(c.paddingRight);"
        "var scale = svg.getScreenCTM().a;"
        "var sizes = Array.prototype.map.call(svg.querySelectorAll('text'), function (t) {"
        "  return parseFloat(getComputedStyle(t).fontSize) * scale; });"
        "return [s.id, svg.getBoundingClientRect().width, inner, Math.min.apply(null, sizes)];"
        "});")
    assert {f[0] for f in figures} >= {"drawing", "diagrams"}
    for where, width, inner, smallest in figures:
        assert width >= 0.9 * inner, (where, width, inner)
        assert smallest >= 11.0, (where, smallest)


#: What sticks out of the page's cards (the header, each section): each element (an SVG figure
#: as a whole) that reaches past its card's sides, but for those inside a box of the card that
#: scrolls sideways (a wide table's), as [card, tag, px past the card's right side]; and how far
#: the page itself scrolls sideways (px).
STICKING_OUT = r"""
const out = [];
for (const card of document.querySelectorAll('body > header, main > section')) {
  const box = card.getBoundingClientRect();
  for (const el of card.querySelectorAll('*')) {
    if (el.closest('svg') && el.tagName !== 'svg') { continue; }
    let scroller = null;
    for (let p = el.parentElement; p && p !== card && !scroller; p = p.parentElement) {
      const o = getComputedStyle(p).overflowX;
      if (o === 'auto' || o === 'scroll') { scroller = p; }
    }
    const r = el.getBoundingClientRect();
    if (scroller || (r.width === 0 && r.height === 0)) { continue; }
    if (r.right > box.right + 0.5 || r.left < box.left - 0.5) {
      out.push([card.id || card.tagName, el.tagName, Math.round(r.right - box.right)]);
    }
  }
}
const page = document.documentElement;
return [out.slice(0, 5), page.scrollWidth - page.clientWidth];
"""


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_nothing_is_wider_than_its_card_and_the_page_never_scrolls_sideways(
        browser: Any, tmp_path: Path, path: Path) -> None:
    """In windows 1024, 1280 and 1600 px wide: no table, figure or line of the page wider than
    the card it is in (a wide table scrolls sideways in a box of its own), and the page as a
    whole not wider than the window."""
    page, _, _ = _page(path.stem, tmp_path)
    try:
        for width in (1024, 1280, 1600):
            browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
                "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": False})
            browser.get(page.as_uri())
            out, sideways = browser.execute_script(STICKING_OUT)
            assert out == [] and sideways == 0, (width, out, sideways)
    finally:
        browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})


def _curves_and_legends(svg: str) -> tuple[list[np.ndarray], list[tuple[float, ...]]]:
    """The plotted curves' points (pt) and the legend boxes of an SVG figure."""
    root = ET.fromstring(svg)
    ns = "{http://www.w3.org/2000/svg}"
    curves, legends = [], []
    for group in root.iter(f"{ns}g"):
        if "clip-path" not in group.attrib:
            continue
        for path in group.iter(f"{ns}path"):
            numbers = [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", path.get("d", ""))]
            if len(numbers) >= 4:
                curves.append(np.array(numbers[: len(numbers) // 2 * 2]).reshape(-1, 2))
    for rect in root.iter(f"{ns}rect"):
        if rect.get("stroke") == "#cccccc":
            legends.append(tuple(float(rect.get(k, 0)) for k in ("x", "y", "width",
                                                                  "height")))
    return curves, legends


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_no_legend_covers_a_curve(path: Path) -> None:
    from camfab.export import figures, speed_figures

    analysis = analyse(load_design(path))
    for svg in (figures.cam_drawing(analysis), figures.diagrams(analysis),
                speed_figures.stress_figure(analysis), speed_figures.vibration_figure(analysis),
                speed_figures.spectrum_figure(analysis)):
        if svg is None:
            continue
        assert legends_over_curves(svg) == [], path.stem


def legends_over_curves(svg: str) -> list[tuple[float, ...]]:
    """The legend boxes of an SVG figure (it has one at least) that a plotted curve runs
    into."""
    curves, legends = _curves_and_legends(svg)
    assert legends
    return [(x, y, w, h) for x, y, w, h in legends for points in curves
            if ((points[:, 0] > x) & (points[:, 0] < x + w)
                & (points[:, 1] > y) & (points[:, 1] < y + h)).any()]


def _lead_ins(page: str) -> dict[str, tuple[str, bool]]:
    """Each heading (h2, h3) of the page: the words of the paragraphs right after it, all
    spaces taken out, and whether its section goes on past them (a table, a figure)."""
    out = {}
    for body in re.findall(r"<section[^>]*>(.*?)</section>", page, flags=re.S):
        parts = re.split(r"<h[23][^>]*>(.*?)</h[23]>", body, flags=re.S)
        for heading, rest in zip(parts[1::2], parts[2::2], strict=True):
            lead = re.match(r"(\s*<p(?:\s[^>]*)?>.*?</p>)*", rest, flags=re.S)
            words = re.sub(r"<[^>]+>", "", lead.group(0))
            more = re.sub(r"<[^>]+>", "", rest[lead.end():]).strip()
            out[html.unescape(heading).strip()] = (
                re.sub(r"\s+", "", html.unescape(words)), bool(more))
    return out


@pytest.mark.parametrize("name", [p.stem for p in DESIGN_FILES])
def test_printed_no_page_ends_on_a_heading(tmp_path: Path, name: str) -> None:
    """Printed to PDF (A4, the page's print rules), no page but the last ends with a section's
    or a table's heading, alone or with only (some of) the paragraphs that lead into the table or
    figure of its section: the heading goes to the next page with what it introduces."""
    page, _, _ = _page(name, tmp_path)
    pages, alone = printed(page, tmp_path)
    assert len(pages) > 1
    assert alone == []


def printed(page: Path, folder: Path) -> tuple[list[list[str]], list[tuple[int, str, list[str]]]]:
    """The report *page* printed to PDF by Chromium (in *folder*): the lines of each page's
    text, and each page but the last that ends on a heading alone or with only the words that
    lead into what it heads (its number, the heading, the lines after it)."""
    chromium = tool("chromium", "chromium")
    pdftotext = tool("pdftotext", "poppler-utils")
    pdf = folder / "report.pdf"
    subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu",
                    f"--user-data-dir={folder / 'profile'}", "--no-pdf-header-footer",
                    f"--print-to-pdf={pdf}", page.as_uri()], capture_output=True, timeout=180,
                   check=False)
    assert pdf.exists() and pdf.stat().st_size > 10_000
    lead_ins = _lead_ins(page.read_text())
    info = subprocess.run([pdftotext, str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout
    pages = [[line.strip() for line in text.splitlines() if line.strip()]
             for text in info.split("\f")]
    pages = [lines for lines in pages if lines]
    alone = []
    for number, lines in enumerate(pages[:-1], start=1):
        last = max((k for k, line in enumerate(lines) if line in lead_ins), default=None)
        if last is None:
            continue
        after = re.sub(r"\s+", "", "".join(lines[last + 1:]))
        lead, more = lead_ins[lines[last]]
        if not after or (lead.startswith(after) and (more or after != lead)):
            alone.append((number, lines[last], lines[last + 1:]))
    return pages, alone


def _fields(model: BaseModel) -> dict[str, Any]:
    """The design model's fields, nested, as the report must carry them."""
    out: dict[str, Any] = {}
    for name in type(model).model_fields:
        if name in ("source", "sized"):
            continue
        value = getattr(model, name)
        if isinstance(value, BaseModel):
            out[name] = _fields(value)
        elif isinstance(value, tuple) and value and isinstance(value[0], BaseModel):
            out[name] = [_fields(v) for v in value]
        else:
            out[name] = value
    return out


def _same_keys(want: Any, got: Any, where: str) -> None:
    if isinstance(want, dict):
        assert isinstance(got, dict), where
        assert set(want) == set(got), (where, set(want) ^ set(got))
        for key in want:
            _same_keys(want[key], got[key], f"{where}.{key}")
    elif isinstance(want, list) and want and isinstance(want[0], dict):
        assert isinstance(got, list) and len(got) == len(want), where
        for i, (w, g) in enumerate(zip(want, got, strict=True)):
            _same_keys(w, g, f"{where}[{i}]")
    else:
        assert (want is None) == (got is None), where


def _accepted(design: Design) -> dict[str, tuple[str, ...]]:
    """The keys the design file takes in its cam and follower sections for this design's cam
    type and follower: the loader's lists, which refuse any other key."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import follower_keys

    spec = CAM_TYPES[design.cam.type]
    fol = design.follower
    return {"cam": spec.cam_keys,
            "follower": follower_keys(spec, {"type": fol.type, "motion": fol.motion})}


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_the_json_carries_every_input_of_the_design(path: Path) -> None:
    """Every field of the design model, but in the cam and follower sections only the keys
    the design file takes for the cam type and follower (no pivot_side on a drum, no arm on a
    translating follower, no offset on an oscillating one)."""
    design: Design = load_design(path)
    report = json.loads(render(analyse(design)).files[f"{design.name}-report.json"])
    want = _fields(design)
    for section, keys in _accepted(design).items():
        want[section] = {k: v for k, v in want[section].items() if k in keys}
    _same_keys(want, report["design"], "design")
    follower = report["design"]["follower"]
    if design.follower.oscillating:
        assert "offset" not in follower and "pivot_distance" in follower
    else:
        assert "pivot_distance" not in follower and "pivot_side" not in follower
    if design.follower.type != "flat":
        assert "face_offset" not in follower
    scale = design.mm_per_unit
    cam = report["design"]["cam"]
    for key in ("base_radius", "radius", "thickness", "bore"):
        value = getattr(design.cam, key)
        if value is not None:
            assert cam[key] == pytest.approx(value / scale, rel=1e-9)
    assert report["design"]["table_step"] == pytest.approx(math.degrees(design.table_step))
    follower = report["follower"]
    assert follower["roller_radius_mm"] == design.follower.roller_radius
    assert follower["offset_mm"] == pytest.approx(design.follower.offset, abs=1e-9)
    lift = report["lift_table"]
    assert len(lift["rows"]) == round(2 * math.pi / design.table_step)
    least = design.manufacturing.tolerance  # the band: at least the tolerance, at φ = 0
    if design.follower.oscillating:
        least = math.degrees(least / (design.follower.arm_length or 1.0))
    assert all(row[2] >= least - 1e-6 for row in lift["rows"])
