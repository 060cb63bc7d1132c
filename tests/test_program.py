"""Motion programs: placement, periodicity, right limits, continuity reporting, ``match``.

The continuity findings are checked against one-sided finite differences of s(θ) — an independent
reading of whether velocity or acceleration steps at each joint."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from camfab.motion.continuity import joint_steps
from camfab.motion.program import build_program
from camfab.pipeline import analyse, design_from_mapping


def design(motion: list[dict], follower: dict | None = None, speed: float | None = 100.0):
    cam = {"type": "disc", "base_radius": 40}
    if speed is not None:
        cam["speed_rpm"] = speed
    return design_from_mapping({
        "name": "t", "cam": cam,
        "follower": follower or {"type": "roller", "roller_radius": 5},
        "motion": motion,
    })


def continuity(d) -> dict[str, object]:
    return {f.quantity: f for f in analyse(d).findings if f.id == "continuity"}


def test_segments_are_placed_in_order() -> None:
    d = design([{"rise": {"angle": 120, "lift": 40, "law": "harmonic"}}, {"dwell": {"angle": 60}},
                {"return": {"angle": 80, "law": "parabolic"}}, {"dwell": {"angle": 100}}])
    program = build_program(d.motion)
    starts = [math.degrees(s.start) for s in program.segments]
    assert starts == pytest.approx([0, 120, 180, 260])
    s = program.evaluate(np.radians([0, 60, 120, 150, 220, 260, 300, 360]))[0]
    assert s == pytest.approx([0, 20, 40, 40, 20, 0, 0, 0], abs=1e-12)


def test_evaluation_at_a_step_gives_the_value_after_it() -> None:
    d = design([{"rise": {"angle": 120, "lift": 40, "law": "harmonic"}}, {"dwell": {"angle": 60}},
                {"return": {"angle": 120, "law": "harmonic"}}, {"dwell": {"angle": 60}}])
    program = build_program(d.motion)
    at = program.evaluate(np.radians([0.0, 120.0]))
    assert at[2, 0] == pytest.approx(40 * math.pi**2 / 2 / math.radians(120) ** 2)  # rise starts
    assert at[2, 1] == 0.0  # the dwell, not the end of the rise


@pytest.mark.parametrize(
    ("law", "expected"),
    [("uniform-velocity", {"velocity"}), ("harmonic", {"acceleration"}),
     ("uniform-acceleration", {"acceleration"}), ("polynomial-23", {"acceleration"}),
     ("cycloidal", {"jerk"}), ("polynomial-345", {"jerk"}), ("modified-trapezoid", {"jerk"}),
     ("modified-sine", {"jerk"}), ("polynomial-4567", set())],
)
def test_continuity_class_next_to_dwells(law: str, expected: set[str]) -> None:
    """THEORY §A: the continuity class of each law between dwells. A step in velocity or
    acceleration fails its check; a step in jerk is reported but passes (every law short of
    the 4-5-6-7 polynomial's steps it next to a dwell)."""
    d = design([{"rise": {"angle": 90, "lift": 20, "law": law}}, {"dwell": {"angle": 90}},
                {"return": {"angle": 90, "law": law}}, {"dwell": {"angle": 90}}])
    found = {q for q, f in continuity(d).items() if f.ranges_deg}
    assert found == expected
    assert {q for q, f in continuity(d).items() if not f.ok} == expected - {"jerk"}
    if "velocity" in expected:
        finding = continuity(d)["velocity"]
        assert finding.severity == "error"
        assert [r[0] for r in finding.ranges_deg] == pytest.approx([0, 90, 180, 270])
        assert analyse(d).exit_code == 1
    else:
        assert analyse(d).exit_code == 0


def test_double_harmonic_rise_into_return_is_smooth_at_the_top() -> None:
    d = design([{"rise": {"angle": 100, "lift": 20, "law": "double-harmonic"}},
                {"return": {"angle": 100, "law": "double-harmonic"}}, {"dwell": {"angle": 160}}])
    steps = joint_steps(build_program(d.motion))
    assert all(not math.isclose(math.degrees(s.angle), 100) or s.order == 3 for s in steps)
    # with a dwell at the top the acceleration must step there
    d2 = design([{"rise": {"angle": 100, "lift": 20, "law": "double-harmonic"}},
                 {"dwell": {"angle": 20}}, {"return": {"angle": 100, "law": "double-harmonic"}},
                 {"dwell": {"angle": 140}}])
    steps2 = joint_steps(build_program(d2.motion))
    assert any(math.isclose(math.degrees(s.angle), 100) and s.order == 2 for s in steps2)


def test_match_takes_the_neighbours_values() -> None:
    d = design([
        {"rise": {"angle": 90, "lift": 10, "law": "uniform-velocity"}},
        {"rise": {"angle": 90, "lift": 20, "law": "polynomial",
                  "start": {"velocity": "match", "acceleration": "match"},
                  "end": {"velocity": 0, "acceleration": 0}}},
        {"return": {"angle": 180, "law": "cycloidal"}},
    ])
    program = build_program(d.motion)
    joint = program.joints()[1]
    assert joint.right[1] == pytest.approx(joint.left[1])  # velocity matched
    assert joint.right[1] == pytest.approx(10 / math.radians(90))
    assert joint.right[2] == pytest.approx(0.0, abs=1e-9)
    # f(0), f(1) and v, a at both ends: six conditions, a quintic
    assert program.segments[1].law.degree == 5


def test_mutual_match_is_an_error() -> None:
    from camfab.errors import DesignError

    poly = {"law": "polynomial", "start": {"velocity": "match"}, "end": {"velocity": "match"}}
    with pytest.raises(DesignError, match="match"):
        design([{"rise": {"angle": 180, "lift": 10, **poly}},
                {"return": {"angle": 180, **poly}}])


# ---- property-based: random valid programs -------------------------------------------------

LAWS = ["uniform-velocity", "modified-uniform-velocity", "uniform-acceleration", "harmonic",
        "cycloidal", "polynomial-23", "polynomial-345", "polynomial-4567", "modified-trapezoid",
        "modified-sine", "double-harmonic"]


@st.composite
def programs(draw) -> list[dict]:
    n = draw(st.integers(2, 8))
    cuts = sorted(draw(st.lists(st.integers(1, 359), min_size=n - 1, max_size=n - 1,
                                unique=True)))
    angles = [b - a for a, b in zip([0, *cuts], [*cuts, 360], strict=True)]
    out, level = [], 0.0
    for i, angle in enumerate(angles):
        last = i == n - 1
        if last:
            kind = "return" if level > 0 else "dwell"
        else:
            options = ["rise", "dwell"] + (["return"] if level > 0 else [])
            kind = draw(st.sampled_from(options))
        if kind == "dwell":
            out.append({"dwell": {"angle": angle}})
            continue
        law = draw(st.sampled_from(LAWS))
        body: dict = {"angle": angle, "law": law}
        if kind == "rise":
            lift = draw(st.floats(0.5, 30.0))
            body["lift"] = lift
            level += lift
        elif not last and draw(st.booleans()):
            drop = draw(st.floats(0.1, 0.9)) * level  # a partial return
            body["lift"] = drop
            level -= drop
        else:
            level = 0.0
        out.append({kind: body})
    return out


def _one_sided(program, joint, order: int, side: int, h: float) -> float:
    """Second-order one-sided finite difference of s at a joint (side -1: left, +1: right)."""
    k = np.arange(4)
    s = program.evaluate(joint.angle + side * h * k)[0]
    if side < 0:  # s at the joint from the left: the end of the previous segment
        s[0] = joint.left[0]
    if order == 1:
        return float(side * (-3 * s[0] + 4 * s[1] - s[2]) / (2 * h))
    return float((2 * s[0] - 5 * s[1] + 4 * s[2] - s[3]) / h**2)


@given(programs(), st.sampled_from(["translating", "oscillating"]))
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@example(motion=[{"dwell": {"angle": 1}},
                 {"rise": {"angle": 292, "law": "uniform-velocity", "lift": 1.0}},
                 {"return": {"angle": 66, "law": "polynomial-4567"}},
                 {"dwell": {"angle": 1}}], kind="translating")
@example(motion=[{"dwell": {"angle": 1}}, {"dwell": {"angle": 1}},
                 {"rise": {"angle": 357, "law": "uniform-velocity", "lift": 1.0}},
                 {"return": {"angle": 1, "law": "polynomial-4567"}}], kind="translating")
@example(motion=[{"dwell": {"angle": 1}}, {"dwell": {"angle": 1}},
                 {"rise": {"angle": 179, "law": "modified-uniform-velocity", "lift": 1.0}},
                 {"return": {"angle": 179, "law": "polynomial-4567"}}], kind="translating")
def test_random_programs_are_periodic_and_continuity_is_reported(motion, kind) -> None:
    follower = ({"type": "roller", "roller_radius": 5} if kind == "translating" else
                {"type": "roller", "motion": "oscillating", "roller_radius": 5,
                 "pivot_distance": 200, "arm_length": 180})
    if kind == "oscillating":  # lifts become degrees of swing: keep them modest
        for seg in motion:
            body = next(iter(seg.values()))
            if "lift" in body:
                body["lift"] = body["lift"] / 10
    d = design(motion, follower)
    program = build_program(d.motion)
    theta = np.linspace(0, 2 * math.pi, 7201)
    s = program.evaluate(theta)[0]
    assert s.min() >= -1e-9  # never below zero
    assert s[0] == pytest.approx(s[-1], abs=1e-9)  # periodic
    steps = {(round(math.degrees(j.angle), 6), j.order): j for j in joint_steps(program)}
    for joint in program.joints():
        assert joint.left[0] == pytest.approx(joint.right[0], abs=1e-9)  # no displacement step
        before, after = program.segments[joint.before], program.segments[joint.after]
        # finite-difference step local to the joint: the stencils' truncation (∝ h²) stays far
        # below the tolerance, and their roundoff (∝ 1/h^order) with it
        h = 3e-4 * min(before.span, after.span)
        a = round(math.degrees(joint.angle), 6)
        for order in (1, 2):
            scale = max(before.peak(order), after.peak(order))
            if not math.isfinite(scale):
                break
            left = _one_sided(program, joint, order, -1, h)
            right = _one_sided(program, joint, order, +1, h)
            # truncation (relative to the peak) + roundoff of the stencil (the polynomial laws
            # lose a few digits of the lift to cancellation near their ends)
            tol = 1e-4 * scale + 1e-12 * program.max_lift / h**order + 1e-12
            if (a, order) in steps:  # reported: the differences see the same step
                step = steps[(a, order)]
                assert right - left == pytest.approx(step.right - step.left, abs=tol)
                break
            assert abs(right - left) < tol  # not reported: the differences see none
    # the findings name every stepping joint
    findings = continuity(d)
    for order, name in ((1, "velocity"), (2, "acceleration"), (3, "jerk")):
        listed = {round(r[0], 6) for r in findings[name].ranges_deg}
        assert listed == {a for a, o in steps if o == order}
        assert findings[name].ok == (not listed or name == "jerk")  # a jerk step passes
