"""The reports' SVG charts: ticks against matplotlib's MaxNLocator, the data drawn where its
limits put it (read back with an independent SVG path reader), equal aspect, broken lines,
escaped text, unique ids on a page, and the same bytes for the same figure."""

from __future__ import annotations

import itertools
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from camfab.export.chart import Figure, nice_ticks, tick_labels

NS = "{http://www.w3.org/2000/svg}"


def _paths(svg: str, **attrs: str) -> list[ET.Element]:
    root = ET.fromstring(svg)
    return [p for p in root.iter(f"{NS}path")
            if all(p.get(k) == v for k, v in attrs.items())]


def _points(d: str) -> np.ndarray:
    from svgelements import Path as SvgPath

    path = SvgPath(d)
    return np.array([[seg.end.x, seg.end.y] for seg in path if seg.end is not None])


@settings(max_examples=300, deadline=None)
@given(st.floats(-1e7, 1e7), st.floats(1e-6, 1e7), st.integers(2, 9))
def test_ticks_match_matplotlib(low: float, span: float, bins: int) -> None:
    """The ticks inside the range are those of matplotlib's MaxNLocator with the same steps
    (away from spans that are a nice step times the bins to within rounding, where either
    choice is right)."""
    from matplotlib.ticker import MaxNLocator

    high = low + span
    raw = (high - low) / bins
    mantissa = raw / 10.0 ** math.floor(math.log10(raw))
    assume(all(abs(mantissa - s) > 1e-6 * s for s in (1.0, 2.0, 2.5, 5.0, 10.0)))
    ticks = nice_ticks(low, high, bins)
    reference = MaxNLocator(nbins=bins, steps=[1, 2, 2.5, 5, 10]).tick_values(low, high)
    step = float(reference[1] - reference[0])
    # away from a tick at an end of the range to within rounding, too (the rounding of the ends
    # themselves: some 1e-9 at 1e7)
    rounding = max(1e-6 * step, 16.0 * float(np.spacing(max(abs(low), abs(high)))))
    assume(not np.any(np.isclose(reference[:, None], [low, high], rtol=0.0, atol=rounding)))
    reference = reference[(reference >= low) & (reference <= high)]
    assert ticks.size == reference.size
    np.testing.assert_allclose(ticks, reference, rtol=1e-9, atol=1e-9 * span)


def test_tick_labels_use_the_decimals_of_the_step_and_a_factor_for_extremes() -> None:
    assert tick_labels(np.array([-50.0, -25.0, 0.0, 25.0])) == (["−50", "−25", "0", "25"], "")
    assert tick_labels(np.array([0.0, 2.5, 5.0])) == (["0.0", "2.5", "5.0"], "")
    assert tick_labels(np.array([-1e6, 0.0, 1e6])) == (["−1", "0", "1"], "×10⁶")
    assert tick_labels(np.array([0.0, 1e-5, 2e-5])) == (["0", "1", "2"], "×10⁻⁵")


def test_a_line_lands_where_its_limits_put_it() -> None:
    fig = Figure(4.0, 3.0, "t", left=0.25, right=0.75, top=0.8, bottom=0.2)
    [ax] = fig.subplots()
    ax.set_xlim(0.0, 10.0)
    ax.set_ylim(-5.0, 5.0)
    ax.plot([0.0, 10.0, 5.0], [-5.0, 5.0, 0.0], color="#123456")
    svg = fig.svg()
    [line] = _paths(svg, stroke="#123456")
    points = _points(line.get("d") or "")
    # the box: 72 pt per inch, y down in SVG
    left, right = 0.25 * 288.0, 0.75 * 288.0
    top, bottom = 0.2 * 216.0, 0.8 * 216.0
    np.testing.assert_allclose(points, [[left, bottom], [right, top],
                                        [(left + right) / 2, (top + bottom) / 2]], atol=0.01)
    root = ET.fromstring(svg)
    assert root.get("width") == "288.00pt" and root.get("viewBox") == "0 0 288.00 216.00"


def test_nan_breaks_a_line_and_autoscale_ignores_it() -> None:
    fig = Figure(4.0, 3.0, "t")
    [ax] = fig.subplots()
    ax.plot([0.0, 1.0, 2.0, 3.0, 4.0], [0.0, 1.0, np.nan, 3.0, 4.0], color="#abcdef")
    (x0, x1), (y0, y1) = ax.limits()
    assert (x0, x1) == pytest.approx((-0.2, 4.2)) and (y0, y1) == pytest.approx((-0.2, 4.2))
    ax.axhline(float("inf"), color="#fedcba")  # a follower radius of a flat face, say
    svg = fig.svg()
    [line] = _paths(svg, stroke="#abcdef")
    assert (line.get("d") or "").count("M") == 2
    assert not _paths(svg, stroke="#fedcba") and "inf" not in svg


def test_equal_aspect_draws_a_circle_round() -> None:
    fig = Figure(6.0, 3.0, "t")
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    angle = np.linspace(0.0, 2.0 * math.pi, 721)
    ax.plot(10.0 * np.cos(angle), 10.0 * np.sin(angle), color="#0000ff")
    [line] = _paths(fig.svg(), stroke="#0000ff")
    points = _points(line.get("d") or "")
    width, height = np.ptp(points[:, 0]), np.ptp(points[:, 1])
    assert width == pytest.approx(height, rel=1e-3)


def test_text_is_escaped_ids_are_per_figure_and_bytes_repeat() -> None:
    def page() -> str:
        figures = []
        for name in ("drawing", "diagrams"):
            fig = Figure(4.0, 3.0, name)
            axes = fig.subplots(2, sharex=True)
            for ax in axes:
                ax.plot([0, 1], [0, 1], color="#000000", label="a < b & c")
                ax.legend()
            axes[0].set_title("x < 1")
            figures.append(fig.svg())
        return "".join(figures)

    first = page()
    assert first == page()
    ids = [e.get("id") for svg in first.split("</svg>")[:-1]
           for e in ET.fromstring(svg + "</svg>").iter() if e.get("id")]
    assert len(ids) == 4 and len(set(ids)) == 4
    assert "a &lt; b &amp; c" in first and "x &lt; 1" in first


def test_only_the_bottom_panel_labels_a_shared_axis() -> None:
    fig = Figure(4.0, 4.0, "t")
    axes = fig.subplots(3, sharex=True)
    for k, ax in enumerate(axes):
        ax.plot([0.0, 360.0], [0.0, k + 1.0])
        ax.set_xticks([0, 120, 240, 360])
    root = ET.fromstring(fig.svg())
    labels = [t.text for t in root.iter(f"{NS}text")]
    assert labels.count("120") == 1 and labels.count("240") == 1


def test_a_legend_entry_of_several_lines_is_as_tall_as_its_lines() -> None:
    """Each entry of a legend stands in its own band of the box: a label of two lines takes
    two lines' height, so it neither spills out of the box nor over the entry below it."""
    fig = Figure(6.0, 3.0, "legend")
    [ax] = fig.subplots()
    ax.plot([0, 1], [0, 1], label="largest roller radius\nthe flanks take")
    ax.plot([0, 1], [1, 0], label="roller 8 mm")
    ax.legend(fontsize=8.5, outside_right=True)
    root = ET.fromstring(fig.svg())
    [box] = [r for r in root.iter(f"{NS}rect") if r.get("stroke") == "#cccccc"]
    top = float(box.get("y"))
    bottom = top + float(box.get("height"))
    lines = []  # (centre y, size) of every line of text in the legend
    for text in root.iter(f"{NS}text"):
        if text.get("text-anchor") != "start":
            continue
        size, y = float(text.get("font-size")), float(text.get("y"))
        spans = list(text.iter(f"{NS}tspan"))
        for span in spans or [text]:
            y += float(span.get("dy", 0.0)) if span is not text else 0.0
            lines.append((y, size))
    assert len(lines) == 3
    lines.sort()
    for (y0, s0), (y1, s1) in itertools.pairwise(lines):
        assert y1 - y0 >= 0.5 * (s0 + s1) * 1.1  # a line's height apart, and some room
    assert lines[0][0] - 0.5 * lines[0][1] >= top
    assert lines[-1][0] + 0.5 * lines[-1][1] <= bottom


def test_a_title_with_the_cam_angle_is_written_at_0_and_carries_its_template() -> None:
    """``{θ}`` in a title: written at θ = 0 (``{θ×k}`` k times it), the template on the
    element for the page's script; a title without it is written as given."""
    from camfab.export.chart import frame_title

    assert frame_title("cam at θ = {θ}°, travel {θ×0.5} mm", 0.0) == "cam at θ = 0°, travel 0 mm"
    assert frame_title("cam at θ = {θ}°, travel {θ×0.5} mm", 37.0) == (
        "cam at θ = 37°, travel 18.5 mm")
    fig = Figure(6.0, 3.0, "titled")
    first, second = fig.subplots(2)
    first.set_title("cam at θ = {θ}°")
    second.set_title("plain {braces}")
    root = ET.fromstring(fig.svg())
    texts = {t.text: t for t in root.iter(f"{NS}text")}
    assert texts["cam at θ = 0°"].get("data-title") == "cam at θ = {θ}°"
    assert texts["plain {braces}"].get("data-title") is None
