"""The ``spline`` motion law against independent references: a Cox–de Boor evaluation written
here (values and derivatives to the fifth), the end conditions it is built on, its pieces, its
peaks against dense sampling, and designs with spline segments through the command line."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.polynomial import polynomial as P

from camfab.motion.bspline import BSplineLaw, spline_knots
from camfab.motion.program import build_program
from camfab.pipeline import design_from_mapping

from .conftest import run_cli


def de_boor_basis(knots: np.ndarray, degree: int, u: np.ndarray) -> np.ndarray:
    """Every B-spline basis function of *degree* on *knots* at *u* by the Cox–de Boor recursion:
    (n, len(u)); each u in the span t_s ≤ u < t_(s+1) (the last non-empty span at its end)."""
    t = np.asarray(knots, dtype=float)
    last = int(np.flatnonzero(t[1:] > t[:-1])[-1])  # the last non-empty span
    span = np.minimum(np.searchsorted(t, u, side="right") - 1, last)
    basis = (np.arange(len(t) - 1)[:, None] == span[None, :]).astype(float)
    for p in range(1, degree + 1):
        nxt = np.zeros((len(t) - 1 - p, len(u)))
        for i in range(len(t) - 1 - p):
            left = t[i + p] - t[i]
            right = t[i + p + 1] - t[i + 1]
            if left > 0:
                nxt[i] += (u - t[i]) / left * basis[i]
            if right > 0:
                nxt[i] += (t[i + p + 1] - u) / right * basis[i + 1]
        basis = nxt
    return basis


def de_boor(knots: np.ndarray, values: np.ndarray, degree: int, u: np.ndarray,
            order: int) -> np.ndarray:
    """f and its derivatives up to *order* at *u*: (order + 1, len(u)), each derivative from
    the derivative's own control values, q_i = p (c_(i+1) − c_i)/(t_(i+p+1) − t_(i+1))."""
    t, c, p = np.asarray(knots, dtype=float), np.asarray(values, dtype=float), degree
    rows = []
    for _ in range(order + 1):
        rows.append(de_boor_basis(t, p, u).T @ c if p >= 0 else np.zeros_like(u))
        if p > 0:
            width = t[p + 1 : len(c) + p] - t[1 : len(c)]
            c = p * np.diff(c) / width
            t, p = t[1:-1], p - 1
        else:
            c, p = np.zeros(1), -1
    return np.array(rows)


LAWS = [
    BSplineLaw.smooth(6, 4),
    BSplineLaw(7, [0.1, 0.4, 0.6, 0.9]),
    BSplineLaw(6, [0.05, 0.5, 0.7], start=[0.8, -2.0, 5.0, 30.0], end=[0.3, 1.0, -4.0, 10.0]),
    BSplineLaw.smooth(4, 6, start=[1.2, 0.0], end=[0.0, -3.0]),
    BSplineLaw.smooth(5, 0),
    BSplineLaw.smooth(10, 3),
]
IDS = ["order6-smooth", "order7-given", "order6-moving-ends", "order4", "order5-none",
       "order10"]


@pytest.mark.parametrize("law", LAWS, ids=IDS)
def test_values_and_derivatives_match_cox_de_boor(law: BSplineLaw) -> None:
    u = np.concatenate([np.linspace(0.0, 1.0, 401), [1e-9, 1.0 - 1e-9]])
    top = law.top_order
    got = law.derivatives(u, top)
    want = de_boor(law.knots, law.control_values, law.order - 1, u, top)
    for n in range(top + 1):
        scale = max(1.0, float(np.max(np.abs(want[n]))))
        np.testing.assert_allclose(got[n], want[n], rtol=0, atol=1e-10 * scale, err_msg=f"n={n}")
    np.testing.assert_array_equal(law.evaluate(u), got[:4])


@pytest.mark.parametrize("law", LAWS, ids=IDS)
def test_the_ends_meet_their_conditions(law: BSplineLaw) -> None:
    k = law.order
    top = min(k - 2, law.top_order)
    ends = law.derivatives(np.array([0.0, 1.0]), law.top_order)
    assert ends[0, 0] == 0.0 and ends[0, 1] == 1.0  # f(0) = 0 and f(1) = 1 exactly
    peaks = np.max(np.abs(law.derivatives(np.linspace(0, 1, 4001), law.top_order)), axis=1)
    for n in range(1, top + 1):
        tol = 1e-12 * max(1.0, float(peaks[n]))
        assert abs(ends[n, 0] - law.start[n - 1]) <= tol, n
        assert abs(ends[n, 1] - law.end[n - 1]) <= tol, n
    # the knots are clamped k-fold at 0 and 1, uniform between
    t = law.knots
    assert np.all(t[:k] == 0.0) and np.all(t[-k:] == 1.0)
    inner = t[k:-k]
    np.testing.assert_allclose(np.diff(np.concatenate([[0.0], inner, [1.0]])),
                               1.0 / (len(inner) + 1), rtol=1e-12)
    assert len(law.control_values) == 2 * (k - 1) + len(law.free)


def test_ends_at_rest_fix_the_end_values_at_zero_and_one() -> None:
    law = BSplineLaw(6, [0.2, 0.5, 0.8])
    assert list(law.control_values) == [0.0] * 5 + [0.2, 0.5, 0.8] + [1.0] * 5
    assert law.free == (0.2, 0.5, 0.8)


@pytest.mark.parametrize("law", LAWS, ids=IDS)
def test_the_pieces_reproduce_the_law(law: BSplineLaw) -> None:
    breaks, pieces = law.pieces()
    assert breaks[0] == 0.0 and breaks[-1] == 1.0 and np.all(np.diff(breaks) > 0)
    assert len(pieces) == len(breaks) - 1
    u = np.linspace(0.0, 1.0, 1001)
    span = np.clip(np.searchsorted(breaks, u, side="right") - 1, 0, len(pieces) - 1)
    got = law.derivatives(u, law.top_order)
    for n in range(law.top_order + 1):
        values = np.array([P.polyval(x - breaks[s], P.polyder(pieces[s], n))
                           for x, s in zip(u, span, strict=True)])
        scale = max(1.0, float(np.max(np.abs(got[n]))))
        np.testing.assert_allclose(values, got[n], rtol=0, atol=1e-10 * scale, err_msg=f"n={n}")


@pytest.mark.parametrize("law", LAWS, ids=IDS)
def test_peaks_equal_dense_sampling(law: BSplineLaw) -> None:
    u = np.union1d(np.linspace(0.0, 1.0, 200_001), law.breakpoints)  # a cubic's f″ kinks there
    sampled = np.max(np.abs(law.evaluate(u)[1:]), axis=1)
    for n in (1, 2, 3):
        assert law.peak(n) >= sampled[n - 1] * (1 - 1e-12)
        assert law.peak(n) == pytest.approx(sampled[n - 1], rel=1e-6)


def test_order_below_six_gives_derivatives_to_the_jerk() -> None:
    cubic, quintic = BSplineLaw.smooth(4, 2), BSplineLaw.smooth(6, 2)
    assert cubic.top_order == 3 and quintic.top_order == 5
    assert cubic.inner_step_order == 3  # its jerk steps at the knots
    assert quintic.inner_step_order is None
    with pytest.raises(ValueError, match="up to 3"):
        cubic.derivatives([0.5], 4)


def test_the_default_free_values_are_the_smooth_rise_at_the_greville_abscissae() -> None:
    """Order 6: the 5-6-7-8-9 polynomial at each free value's mean of its five inner knots."""
    law = BSplineLaw.smooth(6, 4)
    t = spline_knots(6, 4)
    greville = [t[i + 1 : i + 6].mean() for i in range(5, 9)]
    rise = [0, 0, 0, 0, 0, 126, -420, 540, -315, 70]
    np.testing.assert_allclose(law.free, P.polyval(greville, rise), rtol=1e-12)


def test_a_tuner_reads_and_sets_the_free_values() -> None:
    law = BSplineLaw(6, [0.1, 0.4, 0.6, 0.9], start=[0.5, 0, 0, 0])
    other = law.with_free([0.2, 0.3, 0.7, 0.8, 0.95])
    assert other.free == (0.2, 0.3, 0.7, 0.8, 0.95)
    assert other.order == 6 and other.start == law.start and other.end == law.end
    np.testing.assert_array_equal(other.control_values[5:10], other.free)


# ---- in a program and a design ---------------------------------------------------------------

CAM = {"type": "disc", "base_radius": 40, "speed_rpm": 300}
FOLLOWER = {"type": "roller", "roller_radius": 8}


def design(motion: list[dict]):
    return design_from_mapping({"name": "t", "cam": CAM, "follower": FOLLOWER, "motion": motion})


def test_a_spline_next_to_dwells_is_at_rest_at_its_ends() -> None:
    d = design([{"rise": {"angle": 120, "lift": 20, "law": "spline"}}, {"dwell": {"angle": 60}},
                {"return": {"angle": 120, "law": "spline", "order": 7,
                            "controls": [0.1, 0.4, 0.6, 0.9]}},
                {"dwell": {"angle": 60}}])
    program = build_program(d.motion)
    rise, back = program.segments[0], program.segments[2]
    assert rise.law.order == 6 and len(rise.law.free) == 4  # the defaults
    assert back.law.free == (0.1, 0.4, 0.6, 0.9)
    assert d.motion[2].controls == (0.1, 0.4, 0.6, 0.9)
    for seg in (rise, back):
        ends = seg.end_values(5)
        assert ends[0][0] == seg.s0 and ends[1][0] == pytest.approx(seg.s1, abs=1e-12)
        assert np.all(ends[:, 1:5] == 0.0)  # at rest: f′ … f⁗ exactly 0
    assert program.evaluate(np.radians([0.0, 120.0, 300.0]))[0] == pytest.approx([0, 20, 0])


def test_match_takes_a_neighbouring_polynomials_derivatives_to_the_snap() -> None:
    """A polynomial rise that ends moving, then a spline that matches its velocity, acceleration,
    jerk and snap: both sides of the joint agree to 1e-12 of each derivative's size."""
    d = design([
        {"rise": {"angle": 90, "lift": 10, "law": "polynomial",
                  "start": {"velocity": 0, "acceleration": 0, "jerk": 0},
                  "end": {"velocity": 6, "acceleration": -2, "jerk": 5, "snap": -20}}},
        {"rise": {"angle": 90, "lift": 10, "law": "spline", "controls": 5,
                  "start": {"velocity": "match", "acceleration": "match", "jerk": "match",
                            "snap": "match"}}},
        {"dwell": {"angle": 30}},
        {"return": {"angle": 150, "law": "polynomial-56789"}},
    ])
    program = build_program(d.motion)
    before, after = program.segments[0].end_values(4)[1], program.segments[1].end_values(4)[0]
    np.testing.assert_allclose(before, [10.0, 6.0, -2.0, 5.0, -20.0], rtol=1e-9)
    for n in range(5):
        assert after[n] == pytest.approx(before[n], rel=1e-12, abs=1e-12), n


def test_a_spline_takes_no_condition_beyond_its_order() -> None:
    from camfab.errors import DesignError

    with pytest.raises(DesignError, match=r"motion\[0\]\.start\.jerk: a spline of order 4 fixes"):
        design([{"rise": {"angle": 180, "lift": 10, "law": "spline", "order": 4,
                          "start": {"jerk": 0}}},
                {"return": {"angle": 180, "law": "cycloidal"}}])


def test_the_snap_cannot_be_matched_from_a_law_that_stops_at_the_jerk() -> None:
    from camfab.errors import DesignError

    with pytest.raises(DesignError, match=r"start\.snap: cannot match the snap"):
        design([{"rise": {"angle": 120, "lift": 10, "law": "cycloidal"}},
                {"rise": {"angle": 60, "lift": 5, "law": "spline", "start": {"snap": "match"}}},
                {"return": {"angle": 180, "law": "cycloidal"}}])


BASE = """\
name: spline-cam
cam: {type: disc, base_radius: 40, speed_rpm: 300, bore: 10}
follower: {type: roller, roller_radius: 8}
motion:
  - rise: {angle: 120deg, lift: 20mm, law: spline, order: 6, controls: 4}
  - dwell: {angle: 60}
  - return: {angle: 120deg, law: spline, order: 7, controls: [0.1, 0.4, 0.6, 0.9],
             start: {velocity: match}, end: {jerk: 0}}
  - dwell: {angle: 60}
"""


def test_a_design_with_spline_segments_builds(tmp_path: Path) -> None:
    (tmp_path / "design.yaml").write_text(BASE)
    result = run_cli("build", "design.yaml", cwd=tmp_path)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "exports" / "spline-cam" / "spline-cam.dxf").is_file()


@pytest.mark.parametrize(("old", "new", "line", "field", "words"), [
    ("order: 6", "order: 3", 5, "motion[0].order", "from 4"),
    ("order: 6", "order: 6.5", 5, "motion[0].order", "whole number"),
    ("controls: 4", "controls: -2", 5, "motion[0].controls", "whole number"),
    ("[0.1, 0.4, 0.6, 0.9]", "[0.1, 0.4, big, 0.9]", 7, "motion[2].controls[2]", "from 0 to 1"),
    ("[0.1, 0.4, 0.6, 0.9]", "[0.1, 1.4]", 7, "motion[2].controls[1]", "from 0 to 1"),
    ("order: 7,", "order: 4,", 8, "motion[2].end.jerk", "order 4 fixes"),
    ("law: spline, order: 6", "law: harmonic, order: 6", 5, "motion[0].order",
     "only the spline law takes"),
    ("end: {jerk: 0}", "end: {jerk: 0, snapp: 1}", 8, "motion[2].end.snapp", "'snap'"),
])
def test_a_bad_spline_is_one_located_line_and_exit_2(tmp_path: Path, old: str, new: str,
                                                     line: int, field: str, words: str) -> None:
    assert old in BASE
    (tmp_path / "design.yaml").write_text(BASE.replace(old, new, 1))
    result = run_cli("build", "design.yaml", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    message = result.stderr.strip()
    assert "\n" not in message and "Traceback" not in message
    assert message.startswith(f"design.yaml:{line}: {field}: "), message
    assert words in message, message
    assert not (tmp_path / "exports").exists()


def test_a_linear_cams_spline_is_at_rest_at_its_ends() -> None:
    from camfab.errors import DesignError

    def linear(rise: dict):
        return design_from_mapping({
            "name": "t", "cam": {"type": "linear", "stroke": 200, "base_height": 30,
                                 "thickness": 10},
            "follower": {"type": "roller", "roller_radius": 5},
            "motion": [{"rise": {"travel": 80, "lift": 10, **rise}}, {"dwell": {"travel": 20}},
                       {"return": {"travel": 80, "law": "cycloidal"}},
                       {"dwell": {"travel": 20}}]})

    program = linear({"law": "spline", "controls": 3}).program
    assert program.segments[0].law.free == pytest.approx(BSplineLaw.smooth(6, 3).free)
    with pytest.raises(DesignError, match=r"motion\[0\]\.start: a linear cam's spline"):
        linear({"law": "spline", "start": {"velocity": 0}})


def test_a_polynomial_takes_the_snap_and_a_table_refuses_it() -> None:
    from camfab.errors import DesignError

    d = design([{"rise": {"angle": 180, "lift": 10, "law": "polynomial",
                          "start": {"velocity": 0, "acceleration": 0, "jerk": 0, "snap": 0},
                          "end": {"velocity": 0, "acceleration": 0, "jerk": 0, "snap": 0}}},
                {"return": {"angle": 180, "law": "polynomial-56789"}}])
    rise = build_program(d.motion).segments[0].law
    np.testing.assert_allclose(rise.pieces()[1][0], [0, 0, 0, 0, 0, 126, -420, 540, -315, 70],
                               atol=1e-8)
    with pytest.raises(DesignError, match=r"start\.snap: a table takes"):
        design([{"rise": {"angle": 180, "law": "table", "points": [[0, 0], [90, 4], [180, 10]],
                          "start": {"snap": 0}}},
                {"return": {"angle": 180, "law": "cycloidal"}}])


def test_peaks_scale_to_the_segment() -> None:
    d = design([{"rise": {"angle": 90, "lift": 12, "law": "spline"}}, {"dwell": {"angle": 90}},
                {"return": {"angle": 90, "law": "spline"}}, {"dwell": {"angle": 90}}])
    program = build_program(d.motion)
    seg = program.segments[0]
    theta = np.linspace(0.0, math.radians(90), 100_001)
    sampled = np.max(np.abs(program.evaluate(theta)[1:]), axis=1)
    for n in (1, 2, 3):
        assert seg.peak(n) == pytest.approx(sampled[n - 1], rel=1e-6)
