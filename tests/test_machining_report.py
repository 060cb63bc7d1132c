"""The machining programs' setup sheets in the reports, from setup sheets built as the program
writers build them (:mod:`tests.machining_setups`: a plate's outline toolpath, a drum's unrolled
groove, a globoid's swing) and from the drum's program as camfab writes it: the page's
"Machining" section and the JSON's ``machining`` key there exactly when a program was written,
and the rest of both reports unchanged; the numbers as the setup sheet holds them (the cycle time
the operations' times summed, a row per tool and per operation, lengths and feeds in the
program's units); the toolpath's picture holding the path (read back from the SVG through its
ticks: its extents, cutting moves solid and rapid ones dashed, one scale on a plan view only);
the work zero's sketch; the line a build prints; and the page laid out in Debian's Chromium
(nothing wider than its card from the studio's 992 px column up, no text of a picture over
another, text of 11 px and more, no page of the PDF ending on a heading, the section's style
kept when the studio puts a report's body in place)."""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from camfab.analysis.record import Analysis
from camfab.analysis.setup_sheet import Operation, Setup, Tool
from camfab.export.machining_figures import same_length_unit, thinned, toolpath_figure
from camfab.export.machining_page import cycle_time_line, minutes_words
from camfab.export.report_html import render_report_html
from camfab.export.report_json import render_report_json
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS, chromium
from .machining_setups import drum_setup, globoid_setup, plate_setup, with_setups
from .test_report_page import (
    _FIGURE_TEXT,
    STICKING_OUT,
    _lead_ins,
    _overlap,
    legends_over_curves,
    printed,
)

#: An example design of each way of machining, with the setup sheet its program would have.
CASES = {"seed-10-4": plate_setup, "demo-cylindrical": drum_setup,
         "demo-globoidal-concave": globoid_setup}

SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def built() -> dict[str, tuple[Analysis, Analysis]]:
    """Each case's analysis without and with its program's setup sheet."""
    out = {}
    for name, make in CASES.items():
        plain = analyse(load_design(DESIGNS / f"{name}.yaml"))
        out[name] = (plain, replace(plain, machining=(make(plain),)))
    return out


@pytest.fixture(scope="module")
def written() -> Analysis:
    """The drum's program as camfab writes it (outputs: [gcode], a tool of the groove's width),
    its analysis as the build leaves it."""
    text = (DESIGNS / "demo-cylindrical.yaml").read_text() + (
        "outputs: [report, gcode]\nmachining:\n  tool_diameter: 12.1\n  feed: 600\n")
    artifacts = render(analyse(design_from_text(text, "drum.yaml", DESIGNS)))
    assert artifacts.analysis is not None and "demo-cylindrical.ngc" in artifacts.files
    return artifacts.analysis


def _section(page: str) -> str:
    found = re.search(r'<section id="machining">.*?</section>\n', page, flags=re.S)
    assert found is not None
    return found.group(0)


@pytest.mark.parametrize("name", list(CASES))
def test_the_section_and_the_key_are_there_exactly_when_a_program_was_written(
        built: dict[str, tuple[Analysis, Analysis]], name: str) -> None:
    """Without a program, no section (nor its style) and no key; with one, both, and the rest
    of each report the same bytes."""
    plain, machined = built[name]
    page, json_text = render_report_html(plain).decode(), render_report_json(plain)
    assert 'id="machining"' not in page and "machining-style" not in page
    assert "machining" not in json.loads(json_text)
    with_page = render_report_html(machined).decode()
    section = _section(with_page)
    assert section.count('<style id="machining-style">') == 1
    assert with_page.replace(section, "") == page
    report = json.loads(render_report_json(machined))
    assert len(report["machining"]) == 1
    del report["machining"]
    assert report == json.loads(json_text)


def test_the_json_holds_each_setup_sheet_and_the_cycle_time_is_the_operations_summed(
        built: dict[str, tuple[Analysis, Analysis]]) -> None:
    _, machined = built["demo-cylindrical"]
    setup = machined.machining[0]
    [sheet] = json.loads(render_report_json(machined))["machining"]
    assert list(sheet) == ["file", "stock", "work_zero", "axes", "tools", "operations",
                           "cycle_time_min", "notes"]
    assert sheet["file"] == "demo-cylindrical.ngc" and sheet["axes"] == "XZA"
    assert sheet["work_zero"] == setup.work_zero and sheet["stock"] == setup.stock
    assert sheet["cycle_time_min"] == pytest.approx(6.25 + 3.5)
    assert sheet["cycle_time_min"] == pytest.approx(sum(op["minutes"]
                                                        for op in sheet["operations"]))
    assert sheet["tools"] == [
        {"number": 1, "what": "flat end mill", "diameter_mm": 12.0, "flutes": 3,
         "cut_length_mm": 30.0},
        {"number": 2, "what": "flat end mill", "diameter_mm": 8.0, "flutes": 2,
         "cut_length_mm": 20.0}]
    assert [op["name"] for op in sheet["operations"]] == [op.name for op in setup.operations]
    assert sheet["operations"][0] == {"name": "groove, roughing down the middle", "tool": 2,
                                      "passes": 4, "feed_mm_min": 400.0, "minutes": 6.25}
    assert sheet["notes"] == list(setup.notes)


def _cells(table: str) -> list[list[str]]:
    """The body rows of an HTML *table* (not its head or foot), as the text of their cells."""
    body = re.sub(r"<thead>.*?</thead>|<tfoot>.*?</tfoot>|<caption>.*?</caption>", "", table,
                  flags=re.S)
    return [[re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", body, flags=re.S)]


def _tables(section: str) -> dict[str, str]:
    """The section's tables by caption (the setup rows' table as ``setup``)."""
    tables = re.findall(r"<table>.*?</table>", section, flags=re.S)
    out = {}
    for table in tables:
        caption = re.search(r"<caption>(.*?)</caption>", table)
        out[caption.group(1) if caption else "setup"] = table
    return out


def test_a_program_camfab_writes_gets_its_sheet_in_both_reports(written: Analysis) -> None:
    """The drum's program as its writer makes it: one sheet, the JSON's numbers its setup's,
    the page's section with its sketch and toolpath."""
    [setup] = written.machining
    [sheet] = json.loads(render_report_json(written))["machining"]
    assert sheet["file"] == setup.file == "demo-cylindrical.ngc" and sheet["axes"] == "XZA"
    assert sheet["cycle_time_min"] == pytest.approx(sum(op.minutes for op in setup.operations))
    assert len(sheet["operations"]) == len(setup.operations) > 0
    assert [t["number"] for t in sheet["tools"]] == [t.number for t in setup.tools]
    section = _section(render_report_html(written).decode())
    assert section.count('class="work-zero"') == 1 and section.count("<figure") == 1
    assert f"<h3>{setup.file}</h3>" in section


def test_the_page_shows_the_stock_the_work_zero_each_tool_each_operation_and_the_total(
        built: dict[str, tuple[Analysis, Analysis]]) -> None:
    _, machined = built["demo-cylindrical"]
    setup = machined.machining[0]
    section = _section(render_report_html(machined).decode())
    assert "<h3>demo-cylindrical.ngc</h3>" in section
    tables = _tables(section)
    rows = dict((re.sub(r"<[^>]+>", "", th), td) for th, td in re.findall(
        r"<tr><th>(.*?)</th><td>(.*?)</td></tr>", tables["setup"]))
    assert rows["stock"] == "a bored cylinder ⌀100 × 70 mm on a mandrel"
    assert rows["work zero"] == setup.work_zero.replace("'", "&#39;")
    assert rows["axes"] == "X, Z, A (turns about X)"
    assert rows["estimated cycle time"] == "9.75 min"
    notes = re.search(r'<div class="notes">.*?</div>', section, flags=re.S)
    assert notes is not None
    assert re.findall(r"<li>(.*?)</li>", notes.group(0)) == list(setup.notes)
    assert _cells(tables["Tools"]) == [["1", "flat end mill", "12", "3", "30"],
                                       ["2", "flat end mill", "8", "2", "20"]]
    assert _cells(tables["Operations, in order"]) == [
        ["1", "groove, roughing down the middle", "T2", "4", "400", "6.25"],
        ["2", "groove walls, roller-diameter tool", "T1", "2", "300", "3.5"]]
    total = re.search(r"<tfoot>.*?</tfoot>", tables["Operations, in order"], flags=re.S)
    assert total is not None and "estimated cycle time" in total.group(0)
    assert re.findall(r'class="num">(.*?)</td>', total.group(0)) == ["9.75"]
    assert section.count('class="work-zero"') == 1 and section.count("<figure") == 1


def test_an_inch_program_s_sheet_is_in_inches_and_its_json_in_millimetres() -> None:
    machined = with_setups("demo-inch-flat", lambda a: plate_setup(a, tool_diameter=6.35))
    section = _section(render_report_html(machined).decode())
    tables = _tables(section)
    assert "diameter (in)" in tables["Tools"] and "feed (in/min)" in tables[
        "Operations, in order"]
    assert _cells(tables["Tools"])[0][2] == "0.25"
    assert _cells(tables["Operations, in order"])[0][4] == f"{600 / 25.4:.5g}"
    sheet = json.loads(render_report_json(machined))["machining"][0]
    assert sheet["tools"][0]["diameter_mm"] == pytest.approx(6.35)


def test_several_programs_each_get_their_sheet_in_order() -> None:
    """A conjugate pair's two plates, say: two sheets, each its own total."""
    def second(analysis: Analysis) -> Setup:
        setup = plate_setup(analysis)
        return replace(setup, file="plate-b.ngc", operations=(
            Operation("profile", 1, 500.0, 75.5, 3),), toolpath=None)

    machined = with_setups("seed-10-4", plate_setup, second)
    page = render_report_html(machined).decode()
    section = _section(page)
    assert re.findall(r"<h3>(.*?)</h3>", section) == ["seed-10-4.ngc", "plate-b.ngc"]
    assert "1 h 16 min" in section  # 75.5 min, the second's cycle time in words
    assert section.count("<figure") == 1  # the second has no toolpath to draw
    sheets = json.loads(render_report_json(machined))["machining"]
    assert [s["file"] for s in sheets] == ["seed-10-4.ngc", "plate-b.ngc"]
    assert sheets[1]["cycle_time_min"] == 75.5


def test_the_times_and_the_build_s_line_in_words() -> None:
    assert minutes_words(0.452) == "0.452 min"
    assert minutes_words(9.75) == "9.75 min"
    assert minutes_words(59.4) == "59.4 min"
    assert minutes_words(59.6) == "1 h 00 min"
    assert minutes_words(125.2) == "2 h 05 min"
    setup = Setup("cam.ngc", "plate", "centre", "XYZ", (Tool(1, "flat end mill", 6.0),),
                  (Operation("a", 1, 600.0, 1.25), Operation("b", 1, 600.0, 2.0)))
    assert cycle_time_line(setup) == ("cam.ngc: estimated cycle time 3.25 min (2 operations, "
                                      "at the feeds; rapid moves not counted)")


def test_a_build_prints_each_program_s_cycle_time(monkeypatch: pytest.MonkeyPatch,
                                                   tmp_path: Path) -> None:
    """One line a program, after the files written (the writers of the programs stood in for
    by a build whose analysis carries a setup sheet)."""
    import camfab.pipeline as pipeline
    from camfab.cli import _build_one

    real = pipeline.build

    def build(*args: Any, **kwargs: Any) -> pipeline.BuildResult:
        result = real(*args, **kwargs)
        return replace(result, analysis=replace(result.analysis, machining=(
            plate_setup(result.analysis),)))

    monkeypatch.setattr(pipeline, "build", build)
    outcome = _build_one(str(DESIGNS / "seed-10-4.yaml"), tmp_path)
    lines = [line for line in outcome.out if "estimated cycle time" in line]
    assert lines == ["  seed-10-4.ngc: estimated cycle time 2.15 min (3 operations, at the "
                     "feeds; rapid moves not counted)"]
    monkeypatch.undo()
    plain = _build_one(str(DESIGNS / "seed-10-4.yaml"), tmp_path)
    assert not any("cycle time" in line for line in plain.out)
    assert [line for line in outcome.out if line not in lines] == plain.out


# --- the toolpath's picture, read back ---------------------------------------------------------

def _numbers(d: str) -> np.ndarray:
    """The points of an SVG path's data (pt), rows of (x, y)."""
    values = [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", d)]
    return np.array(values).reshape(-1, 2)


def _scale(root: ET.Element) -> tuple[np.ndarray, np.ndarray]:
    """The picture's map from pt back to data, from its tick labels: (offset, per pt) across
    and up, as data = offset + per_pt · pt."""
    texts = [(float(t.get("x", 0)), float(t.get("y", 0)), (t.text or "").replace("−", "-"))
             for t in root.iter(f"{SVG}text")]
    ticks = [(x, y, float(s)) for x, y, s in texts if re.fullmatch(r"-?\d+(\.\d+)?", s)]
    bottom = max(y for _, y, _ in ticks)
    across = [(x, v) for x, y, v in ticks if y == bottom]
    up = [(y, v) for x, y, v in ticks if y != bottom]
    fits = [np.polyfit(*np.array(pairs).T, 1) for pairs in (across, up)]
    return np.array([f[1] for f in fits]), np.array([f[0] for f in fits])


def _drawn(svg: str, colour: str) -> tuple[np.ndarray, ET.Element]:
    """The points (data units) of the lines drawn in *colour* in the panel, and the last such
    path element."""
    root = ET.fromstring(svg)
    offset, per_pt = _scale(root)
    paths = [p for g in root.iter(f"{SVG}g") if "clip-path" in g.attrib
             for p in g.iter(f"{SVG}path") if p.get("stroke") == colour
             and not re.search("[aA]", p.get("d", ""))]  # (lines, not a marker's circle)
    assert paths
    points = np.vstack([_numbers(p.get("d", "")) for p in paths])
    return offset + per_pt * points, paths[-1]


@pytest.mark.parametrize("name", [*CASES, "written"])
def test_the_toolpath_picture_holds_the_path_s_extents(
        built: dict[str, tuple[Analysis, Analysis]], written: Analysis, name: str) -> None:
    """The cutting moves drawn (red, solid) span what the program's cutting moves span, and the
    rapid moves drawn (grey, dashed) theirs, to a point of the figure (the drum's program as
    camfab writes it too)."""
    from camfab.export.figures import CUT, REFERENCE

    setup = (written if name == "written" else built[name][1]).machining[0]
    svg = toolpath_figure(setup, "t")
    assert svg is not None
    root = ET.fromstring(svg)
    _, per_pt = _scale(root)
    for colour, points, dashed in ((CUT, setup.toolpath.cutting, False),
                                   (REFERENCE, setup.toolpath.rapid, True)):
        drawn, path = _drawn(svg, colour)
        good = points[np.isfinite(points).all(axis=1)]
        np.testing.assert_allclose(drawn.min(axis=0), good.min(axis=0),
                                   atol=float(np.max(np.abs(per_pt))))
        np.testing.assert_allclose(drawn.max(axis=0), good.max(axis=0),
                                   atol=float(np.max(np.abs(per_pt))))
        assert ("stroke-dasharray" in path.attrib) == dashed
    labels = [t.text for t in root.iter(f"{SVG}text")]
    assert setup.toolpath.x_label in labels
    assert setup.toolpath.y_label in labels or any(
        setup.toolpath.y_label.split()[0] in (t.text or "")
        for t in root.iter(f"{SVG}tspan"))
    plan = name == "seed-10-4"  # (the drum's writer: X along the axis against A)
    # a plan view at one scale; an unrolled path or a swing at the scales that fill the panel
    assert np.isclose(abs(per_pt[0]), abs(per_pt[1]), rtol=1e-3) == plan
    assert ("work zero" in labels) == plan


def test_a_plan_view_is_in_one_length_unit() -> None:
    assert same_length_unit("X (mm)", "Y (mm)")
    assert not same_length_unit("X (mm)", "Y (in)")
    assert not same_length_unit("cam angle A (deg)", "X, along the drum's axis (mm)")
    assert not same_length_unit("cam angle A (deg)", "swing B (deg)")


def test_thinning_keeps_each_piece_s_ends_and_moves_the_path_less_than_a_cell() -> None:
    t = np.linspace(0.0, 2.0 * np.pi, 20001)
    circle = np.column_stack((np.cos(t), np.sin(t)))
    path = np.vstack((circle, [[np.nan, np.nan]], circle[:5000] * 0.5))
    cell = np.array([0.01, 0.01])
    kept = thinned(path, cell)
    assert len(kept) < len(path) / 10
    assert np.isnan(kept).any(axis=1).sum() == 1
    pieces = np.split(kept, np.flatnonzero(np.isnan(kept).any(axis=1)))
    np.testing.assert_array_equal(pieces[0][[0, -1]], circle[[0, -1]])
    np.testing.assert_array_equal(pieces[1][1:][[0, -1]], 0.5 * circle[[0, 4999]])
    # every point of the path within a cell's diagonal of the polyline kept (its vertices)
    gaps = np.min(np.hypot(*(circle[:, None, :] - pieces[0][None, ::1, :]).T), axis=0)
    assert gaps.max() < float(np.hypot(*cell))


def test_no_legend_covers_the_toolpath(built: dict[str, tuple[Analysis, Analysis]]) -> None:
    for _, machined in built.values():
        svg = toolpath_figure(machined.machining[0], "t")
        assert svg is not None
        assert legends_over_curves(svg) == []


def _grinder_setup() -> tuple[Analysis, Setup]:
    """A grinding program's sheet as camfab writes it: the wheel's centre against the cam
    angle, on X and C (a wheel 40 mm across, which the plate's hollows take)."""
    from camfab.machining.grinding import grind_files

    text = (DESIGNS / "seed-10-4.yaml").read_text() + (
        "machining:\n  tool_diameter: 6\n  feed: 600\n  wheel_diameter: 40\n")
    analysis = analyse(design_from_text(text, "grind.yaml", DESIGNS))
    assert analysis.design.machining is not None
    [setup] = grind_files(analysis, analysis.design.machining).setups
    return analysis, setup


def _marks(svg: str) -> tuple[np.ndarray, list[np.ndarray], list[float]]:
    """The sketch's work zero (the centre of its black dot, pt; of the last view's, where there
    are two), the outlines of the part's faces drawn, and the x (pt) of its dashed upright lines
    (a bore's hidden edges, its axis)."""
    from camfab.export.machining_figures import PART

    root = ET.fromstring(svg)
    dots, bodies, hidden = [], [], []
    for path in root.iter(f"{SVG}path"):
        d = path.get("d", "")
        if path.get("fill") == "#000000" and " a" in d:
            x, y, r = (float(v) for v in re.match(r"M(\S+) (\S+) a(\S+)", d).groups())
            dots.append((x + r, y))
        elif path.get("fill") == PART:
            bodies.append(_numbers(d.replace(" Z", "")))
        elif "stroke-dasharray" in path.attrib and path.get("stroke-width") == "0.60":
            points = _numbers(d)
            if np.ptp(points[:, 0]) < 0.01:
                hidden.append(float(points[0, 0]))
    assert len(dots) in (1, 2), dots
    return np.array(dots[-1]), bodies, hidden


def test_the_work_zero_s_sketch_puts_it_where_the_program_s_axes_have_it(
        built: dict[str, tuple[Analysis, Analysis]]) -> None:
    """A plate's on its top face over the bore's axis; a drum's on its axis at its face at
    axial position 0; a globoid's at the cam's centre; a grinder's at the cam's centre; no
    sketch for axes it does not know."""
    from camfab.export.machining_figures import work_zero_sketch

    def sketch(analysis: Analysis, setup: Setup) -> str:
        geometry = analysis.result.report_geometry(analysis)
        svg = work_zero_sketch(setup, analysis, geometry, "w")
        assert svg is not None
        return svg

    plate = built["seed-10-4"][1]
    svg = sketch(plate, plate.machining[0])
    zero, [body], hidden = _marks(svg)
    assert zero[1] == pytest.approx(body[:, 1].min(), abs=0.02)  # the top face (y down)
    assert body[:, 0].min() < zero[0] < body[:, 0].max()
    # the bore's hidden edges either side of its axis, the axis through the work zero
    assert len(hidden) == 3 and np.mean(hidden) == pytest.approx(zero[0], abs=0.02)
    assert sorted(hidden)[1] == pytest.approx(zero[0], abs=0.02)
    assert "Z0:" in svg and ">Y<" in svg
    drum = built["demo-cylindrical"][1]
    zero, [body], _ = _marks(sketch(drum, drum.machining[0]))
    assert zero[0] == pytest.approx(body[:, 0].min(), abs=0.02)  # the face at axial 0
    assert zero[1] == pytest.approx(body[:, 1].mean(), abs=0.02)  # on the axis
    globoid = built["demo-globoidal-concave"][1]
    svg = sketch(globoid, globoid.machining[0])
    zero, [body], _ = _marks(svg)
    np.testing.assert_allclose(zero, (body.min(axis=0) + body.max(axis=0)) / 2.0, atol=0.05)
    assert ">A<" in svg and ">B<" in svg
    grinder, setup = _grinder_setup()
    assert setup.axes == "XC"
    svg = sketch(grinder, setup)
    zero, [body], _ = _marks(svg)
    np.testing.assert_allclose(zero, (body.min(axis=0) + body.max(axis=0)) / 2.0, atol=0.05)
    assert ">C<" in svg and "wheel" in svg
    assert work_zero_sketch(replace(plate.machining[0], axes="UV"), plate, {}, "w") is None


# --- the page in Chromium -------------------------------------------------------------------

#: Every picture of the section: its text boxes as Chromium lays them out, the figure's size,
#: the smallest text on the screen (px), and its width against its card's inner width.
PICTURES = _FIGURE_TEXT.replace("'figure svg'", "'#machining svg'").replace(
    "texts: boxes, legends: legends};",
    "texts: boxes, legends: legends, sketch: !svg.closest('figure'),"
    " smallest: Math.min.apply(null, Array.prototype.map.call(svg.querySelectorAll('text'),"
    "  function (t) { return parseFloat(getComputedStyle(t).fontSize)"
    "                        * svg.getScreenCTM().a; })),"
    " shown: svg.getBoundingClientRect().width,"
    " inner: (function (s) { var c = getComputedStyle(s); return s.clientWidth"
    "  - parseFloat(c.paddingLeft) - parseFloat(c.paddingRight); })(svg.closest('section'))};")


@pytest.fixture(scope="module")
def browser() -> Any:
    driver = chromium("--disable-gpu", "--window-size=1280,1000")
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def pages(built: dict[str, tuple[Analysis, Analysis]], written: Analysis,
          tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("machining-pages")
    out = {}
    for name, machined in [*((k, v[1]) for k, v in built.items()), ("written", written)]:
        out[name] = folder / f"{name}-report.html"
        out[name].write_bytes(render_report_html(machined))
    return out


@pytest.mark.parametrize("name", [*CASES, "written"])
def test_the_section_is_laid_out_readably_from_the_studio_s_column_up(
        browser: Any, pages: dict[str, Path], name: str) -> None:
    """At 992 px (the report's column in the studio at 1280), 1024, 1280 and 1600 px: nothing
    wider than its card, the page not scrolling sideways, no script error; at 1280 px every
    text of the pictures inside them and clear of every other, 11 px and more, the toolpath
    filling its card and the sketch at its own size."""
    try:
        for width in (992, 1024, 1280, 1600):
            browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
                "width": width, "height": 900, "deviceScaleFactor": 1, "mobile": False})
            browser.get(pages[name].as_uri())
            out, sideways = browser.execute_script(STICKING_OUT)
            assert out == [] and sideways == 0, (width, out, sideways)
            assert browser.execute_script("return document.body.dataset.errors") == "0"
            if width != 1280:
                continue
            pictures = browser.execute_script(PICTURES)
            assert sorted(p["sketch"] for p in pictures) == [False, True]
            for picture in pictures:
                assert picture["smallest"] >= 11.0, picture["smallest"]
                if not picture["sketch"]:
                    assert picture["shown"] >= 0.9 * picture["inner"]
                texts = picture["texts"]
                for text, *box in texts:
                    assert box[0] > -0.5 and box[1] > -0.5, (text, box)
                    assert box[2] < picture["width"] + 0.5, (text, box)
                    assert box[3] < picture["height"] + 0.5, (text, box)
                for k, (text, *box) in enumerate(texts):
                    for other, *other_box in texts[k + 1:]:
                        assert not _overlap(box, other_box), (text, other)
                    for legend in picture["legends"]:
                        inside = (box[0] > legend[0] - 0.5 and box[1] > legend[1] - 0.5
                                  and box[2] < legend[2] + 0.5 and box[3] < legend[3] + 0.5)
                        assert inside or not _overlap(box, legend), (text, legend)
    finally:
        browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})


def test_printed_no_page_ends_on_the_section_s_headings(pages: dict[str, Path],
                                                        tmp_path: Path) -> None:
    """Printed to PDF (A4), no page but the last ends on a heading of the page with a setup
    sheet, alone or with only the words that lead into what it heads."""
    page = pages["demo-cylindrical"]
    assert "demo-cylindrical.ngc" in _lead_ins(page.read_text())
    printed_pages, alone = printed(page, tmp_path)
    assert any("Operations, in order" in line for lines in printed_pages for line in lines)
    assert alone == []


#: What the studio does with a later report (camfab/serve/static/studio.js, ``patch``): the
#: new page's body put in place of the one shown, whose head stays.
PUT_IN_PLACE = """
var parsed = new DOMParser().parseFromString(arguments[0], "text/html");
var nodes = Array.from(parsed.body.childNodes);
document.body.replaceChildren(...nodes.map(function (n) { return document.adoptNode(n); }));
var setup = document.querySelector('#machining .setup');
return setup ? getComputedStyle(setup).display : null;
"""


def test_the_section_keeps_its_layout_when_the_studio_puts_it_in_place(
        browser: Any, pages: dict[str, Path], built: dict[str, tuple[Analysis, Analysis]],
        tmp_path: Path) -> None:
    """The studio shows first a report without a program (its first analysis), then the
    verified one with it, whose body it puts in place: the section's style comes with the
    body, and in the report's column at 1280 px (992 px) nothing sticks out."""
    plain = tmp_path / "plain-report.html"
    plain.write_bytes(render_report_html(built["seed-10-4"][0]))
    try:
        browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
            "width": 992, "height": 800, "deviceScaleFactor": 1, "mobile": False})
        browser.get(plain.as_uri())
        shown = browser.execute_script(PUT_IN_PLACE, pages["seed-10-4"].read_text())
        assert shown == "flex"
        out, sideways = browser.execute_script(STICKING_OUT)
        assert out == [] and sideways == 0, (out, sideways)
    finally:
        browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})
