"""A build's cost follows its points, not its segments: the motion of many segments evaluated
with one call per law, every segment's curve sampled in the same rounds, and a point's distance
from an outline measured against the edges near it; each gives exactly the numbers of the
segment-by-segment, edge-by-edge computation it replaces (written out here as the reference)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from camfab.arrays import Array, spaced
from camfab.curves import nearest
from camfab.curves.plane import CurvePoints, signed_angle
from camfab.curves.profile import MERGE_DISTANCE, Profile
from camfab.curves.sampling import (
    _MAX_ROUNDS,
    _PROBES,
    MAX_STEP,
    arc_points,
    chord_deviation,
    sample_curves,
)
from camfab.geometry.disc import DiscCam
from camfab.geometry.disc_geometry import disc_cam, sample_closed
from camfab.motion.program import MotionProgram
from camfab.pipeline import design_from_text

LAWS = ("cycloidal", "harmonic", "polynomial-345", "modified-sine", "uniform-velocity",
        "double-harmonic", "modified-trapezoid", "polynomial-4567")


def design_text(count: int, law: Callable[[int], str], follower: str = "roller_radius: 4") -> str:
    """A disc cam whose motion is *count* rise–return pairs and dwells (a multiple of 3)."""
    lines = ["name: many", "cam: {type: disc, base_radius: 40, thickness: 8}",
             f"follower: {{type: roller, {follower}, offset: 3}}", "motion:"]
    angle = 360.0 / count
    for i in range(count // 3):
        lift = 30.0 * math.radians(angle) ** 2
        lines.append(f"  - rise: {{angle: {angle!r}, lift: {lift!r}, law: {law(i)}}}")
        lines.append(f"  - return: {{angle: {angle!r}, law: {law(i + 1)}}}")
        lines.append(f"  - dwell: {{angle: {angle!r}}}")
    return "\n".join(lines) + "\n"


def program_of(count: int, laws: tuple[str, ...] = LAWS) -> MotionProgram:
    return design_from_text(design_text(count, lambda i: laws[i % len(laws)])).program


def reference_sample(curve_at: Callable[[Array], CurvePoints], span: float,
                     tolerance: float) -> tuple[Array, Array]:
    """One curve sampled alone, as camfab sampled each segment before: the reference."""
    grid = np.linspace(0.0, span, max(9, math.ceil(4 * span / MAX_STEP) + 1))
    probe = curve_at(grid)
    with np.errstate(divide="ignore", invalid="ignore"):
        density = probe.speed / np.sqrt(8.0 * np.abs(probe.radius) * tolerance)
    density = np.maximum(np.nan_to_num(density, nan=0.0, posinf=0.0), 1.0 / MAX_STEP)
    cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1])
                                                  * np.diff(grid))))
    count = max(1, math.ceil(cumulative[-1]))
    t = np.interp(np.linspace(0.0, cumulative[-1], count + 1), cumulative, grid)
    t[0], t[-1] = 0.0, span
    xy = curve_at(t).xy
    for _ in range(_MAX_ROUNDS):
        lo, hi = t[:-1], t[1:]
        inner = (lo[:, None] + (hi - lo)[:, None] * _PROBES).ravel()
        exact = curve_at(inner).xy.reshape(len(lo), len(_PROBES), 2)
        start = np.repeat(xy[:-1], len(_PROBES), axis=0)
        end = np.repeat(xy[1:], len(_PROBES), axis=0)
        dev = chord_deviation(exact.reshape(-1, 2), start, end).reshape(len(lo), -1).max(axis=1)
        bad = dev > tolerance
        if not bad.any():
            break
        where = np.flatnonzero(bad) + 1
        t = np.insert(t, where, 0.5 * (lo[bad] + hi[bad]))
        xy = np.insert(xy, where, exact[bad, 1], axis=0)
    return t, xy


def reference_closed(cam: DiscCam, program: MotionProgram, working: bool,
                     tolerances: Array) -> tuple[Array, Array]:
    """The closed curve segment by segment, corner arcs included, as camfab sampled it before."""
    evaluator = cam.working if working else cam.pitch
    thetas, points = [], []
    segments = program.segments
    for i, seg in enumerate(segments):
        def curve_at(t: Array, seg=seg) -> CurvePoints:  # type: ignore[no-untyped-def]
            return evaluator(seg.start + t, seg.evaluate_local(t))

        t, xy = reference_sample(curve_at, seg.span, float(tolerances[i]))
        thetas.append(seg.start + t)
        points.append(xy)
        nxt = segments[(i + 1) % len(segments)]
        if working and cam.follower.radius > 0.0:
            joint = np.array([nxt.start])
            m_right = nxt.evaluate_local(np.zeros(1))
            start, end = xy[-1], evaluator(joint, m_right).xy[0]
            if np.hypot(*(end - start)) > MERGE_DISTANCE:
                centre = cam.pitch(joint, m_right).xy[0]
                sweep = float(signed_angle((start - centre)[None], (end - centre)[None])[0])
                arc = arc_points(centre, start, sweep, float(tolerances[i]))[1:-1]
                thetas.append(np.full(len(arc), nxt.start))
                points.append(arc)
    theta, xy = np.concatenate(thetas), np.concatenate(points)
    keep = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T) > MERGE_DISTANCE
    return theta[keep], xy[keep]


def test_spaced_gives_the_numbers_of_linspace() -> None:
    rng = np.random.default_rng(1)
    stop, count = rng.uniform(1e-4, 7.0, 300), rng.integers(2, 60, 300)
    index, values = spaced(stop, count)
    assert np.array_equal(index, np.repeat(np.arange(300), count))
    assert np.array_equal(values, np.concatenate([np.linspace(0.0, s, c)
                                                  for s, c in zip(stop, count, strict=True)]))


def test_the_program_evaluates_many_segments_as_each_segment_alone() -> None:
    program = program_of(96)
    rng = np.random.default_rng(2)
    index = rng.integers(0, len(program.segments), 5000)
    span = np.array([seg.span for seg in program.segments])
    t = rng.uniform(0.0, 1.0, index.size) * span[index]
    t[:96], index[:96] = 0.0, np.arange(96)  # the joints' right limits
    values = program.evaluate_local(index, t)
    for seg in program.segments:
        mine = index == seg.index
        assert np.array_equal(values[:, mine], seg.evaluate_local(t[mine]))


def test_the_joints_take_each_segments_end_values() -> None:
    program = program_of(60)
    n = len(program.segments)
    for joint, seg in zip(program.joints(), program.segments, strict=True):
        assert np.array_equal(joint.right, seg.end_values()[0])
        assert np.array_equal(joint.left, program.segments[(seg.index - 1) % n].end_values()[1])


def test_the_grid_and_the_cycle_are_evaluated_as_segment_by_segment() -> None:
    program = program_of(60)
    step = math.radians(0.05)
    segment, theta, m = program.segment_grid(step)
    for seg in program.segments:
        t = np.linspace(0.0, seg.span, max(3, math.ceil(seg.span / step) + 1))
        mine = segment == seg.index
        assert np.array_equal(theta[mine], seg.start + t)
        assert np.array_equal(m[:, mine], seg.evaluate_local(t))
    angles = np.linspace(-1.0, 8.0, 3001)
    wrapped = np.mod(angles, 2 * math.pi)
    index = np.clip(np.searchsorted([s.start for s in program.segments], wrapped, "right") - 1,
                    0, None)
    expected = np.stack([program.segments[i].evaluate_local(
        np.array([a - program.segments[i].start]))[:, 0] for i, a in zip(index, wrapped,
                                                                           strict=True)], axis=1)
    assert np.array_equal(program.evaluate(angles), expected)


def test_curves_sampled_together_are_the_curves_sampled_alone() -> None:
    spans = np.array([0.01, 0.3, 1.0, 2.5, 6.0])
    tolerances = np.array([1e-3, 1e-4, 5e-4, 1e-3, 2e-5])
    radius = np.array([5.0, 40.0, 0.7, 300.0, 12.0])

    def one(i: int) -> Callable[[Array], CurvePoints]:
        def curve_at(t: Array) -> CurvePoints:  # a spiral: radius of curvature changing
            r = radius[i] * (1.0 + 0.3 * t)
            xy = np.stack((r * np.cos(t), r * np.sin(t)), axis=-1)
            speed = radius[i] * np.hypot(0.3, 1.0 + 0.3 * t)
            return CurvePoints(xy, xy, speed, speed**3 / (r * r + 2 * (0.3 * radius[i]) ** 2))
        return curve_at

    def many(index: Array, t: Array) -> CurvePoints:
        r = radius[index] * (1.0 + 0.3 * t)
        xy = np.stack((r * np.cos(t), r * np.sin(t)), axis=-1)
        speed = radius[index] * np.hypot(0.3, 1.0 + 0.3 * t)
        return CurvePoints(xy, xy, speed, speed**3 / (r * r + 2 * (0.3 * radius[index]) ** 2))

    index, t, xy = sample_curves(many, spans, tolerances)
    for i in range(len(spans)):
        ref_t, ref_xy = reference_sample(one(i), float(spans[i]), float(tolerances[i]))
        assert np.array_equal(t[index == i], ref_t)
        assert np.array_equal(xy[index == i], ref_xy)


@pytest.mark.parametrize("laws", [LAWS, ("uniform-velocity",)], ids=["mixed", "corners"])
@pytest.mark.parametrize("working", [False, True], ids=["pitch", "working"])
def test_a_closed_curve_is_sampled_as_segment_by_segment(laws: tuple[str, ...],
                                                         working: bool) -> None:
    design = design_from_text(design_text(45, lambda i: laws[i % len(laws)]))
    cam, program = disc_cam(design), design.program
    tolerances = np.linspace(2e-4, 5e-4, len(program.segments))
    sampled = sample_closed(cam, program, "working" if working else "pitch", tolerances)
    theta, xy = reference_closed(cam, program, working, tolerances)
    assert np.array_equal(sampled.theta, theta)
    assert np.array_equal(sampled.xy, xy)


def test_a_thousand_segments_are_sampled_with_few_calls_of_their_laws(
        monkeypatch: pytest.MonkeyPatch) -> None:
    design = design_from_text(design_text(999, lambda i: LAWS[i % 4]))
    calls = {"n": 0}
    for law in {id(seg.law): seg.law for seg in design.program.segments}.values():
        original = law.evaluate

        def counted(u: Array, original=original) -> Array:  # type: ignore[no-untyped-def]
            calls["n"] += 1
            return original(u)
        monkeypatch.setattr(law, "evaluate", counted)
    sample_closed(disc_cam(design), design.program, "working", 5e-4)
    # five laws (four and the dwell), a few rounds each: not thousands of segment calls
    assert calls["n"] <= 5 * 2 * (_MAX_ROUNDS + 3)


def contour(rng: np.random.Generator, count: int, arcs: float) -> Profile:
    angle = np.sort(rng.uniform(0.0, 2 * math.pi, count))
    radius = 40.0 + 5.0 * np.sin(angle * rng.integers(1, 9)) + rng.normal(0.0, 0.3, count)
    vertices = np.stack((radius * np.cos(angle), radius * np.sin(angle)), axis=-1)
    bulges = np.where(rng.random(count) < arcs, rng.uniform(-0.4, 0.4, count), 0.0)
    return Profile.from_points(vertices, bulges)


@pytest.mark.parametrize("arcs", [0.0, 0.5, 1.0])
def test_a_distance_is_the_distance_from_every_edge(arcs: float) -> None:
    rng = np.random.default_rng(int(10 * arcs))
    for _ in range(20):
        profile = contour(rng, int(rng.integers(20, 400)), arcs)
        near = profile.vertices[rng.integers(0, len(profile.vertices), 2000)]
        points = np.vstack((near + rng.normal(0.0, 10.0 ** rng.uniform(-6, 0.5), near.shape),
                            rng.uniform(-150.0, 150.0, (50, 2)),  # inside and outside the grid
                            near[:10]))  # on vertices
        assert len(points) * len(profile.vertices) > nearest.ALL_PAIRS_LIMIT
        expected = nearest.all_pairs(nearest.Edges.of(profile), points)
        assert np.array_equal(profile.distance(points), expected)


def test_a_distance_from_a_far_point_or_none() -> None:
    profile = contour(np.random.default_rng(3), 300, 0.5)
    far = np.array([[1e6, -2e6], [0.0, 0.0], [45.0, 1e-3]] * 100)
    expected = nearest.all_pairs(nearest.Edges.of(profile), far)
    assert np.array_equal(profile.distance(far), expected)
    assert profile.distance(np.zeros((0, 2))).shape == (0,)
