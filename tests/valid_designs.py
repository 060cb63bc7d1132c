"""Random but ordinary valid designs of every cam type and follower camfab builds: what a designer
would write, with the keys varied over their documented ranges.

One definition serves both the property test of the whole build (through hypothesis, which can
then shrink a failing design) and ``scripts/random_builds.py`` (through a seeded
:class:`random.Random`, so a run is reproducible from its seed): :func:`design` draws a design's
data from any :class:`Draw` — ``random.Random`` is one, :class:`HypothesisDraw` another — and
:func:`designs` is the hypothesis strategy.

Every pair of cam type and follower the design file takes is a *kind* here (:data:`KINDS`), such
as ``disc/roller/oscillating`` or ``globoidal/convex``. The values stay where a design is
plausibly buildable: radii, lifts and swings in proportion to each other, the tolerance from
0.0001 mm to 0.1 mm (or the default), both units and rotations, offsets, pivots, every motion law
(the blend of modified uniform velocity, polynomials with matched conditions, tables of points),
kerf, cutter, clearance, bore and keyway. Some designs the loader still refuses (exit 2), and
some fail design checks (exit 1): both are ordinary outcomes of a designer's first try.

Lengths are drawn in millimetres; a design in inches has every length converted (rounded as a
designer would write it). Angles are degrees, as in the design file.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from typing import Any, Protocol, TypeVar

from hypothesis import strategies as st

T = TypeVar("T")

#: Every cam type and follower pair (the follower's type, its motion, or a globoid's blank).
KINDS: tuple[str, ...] = (
    "disc/knife/translating", "disc/roller/translating", "disc/flat/translating",
    "disc/mushroom/translating", "disc/knife/oscillating", "disc/roller/oscillating",
    "disc/flat/oscillating", "disc/mushroom/oscillating",
    "cylindrical/roller",
    "circular-arc/knife", "circular-arc/roller", "circular-arc/flat", "circular-arc/mushroom",
    "tangent/knife", "tangent/roller", "tangent/flat", "tangent/mushroom",
    "groove/translating", "groove/oscillating",
    "conjugate/translating", "conjugate/oscillating",
    "constant-breadth/flat", "constant-breadth/roller",
    "globoidal/concave", "globoidal/convex",
    "linear/roller", "linear/knife",
)

#: Every motion law the design file names (its canonical names), and some aliases a designer
#: writes instead.
LAWS: tuple[str, ...] = (
    "uniform-velocity", "modified-uniform-velocity", "uniform-acceleration", "harmonic",
    "cycloidal", "polynomial-23", "polynomial-345", "polynomial-4567", "modified-trapezoid",
    "modified-sine", "double-harmonic", "polynomial", "table", "spline",
)
ALIASES: tuple[str, ...] = ("shm", "cubic", "parabolic", "simple-harmonic")
#: The laws a linear cam takes (a polynomial's or a table's conditions are per cam angle; a
#: spline's are never drawn for one).
STANDARD_LAWS = tuple(law for law in LAWS if law not in ("polynomial", "table"))
#: The smooth laws most designs use: a designer picks one of these more often than not.
SMOOTH_LAWS = ("cycloidal", "polynomial-345", "modified-sine", "modified-trapezoid",
               "polynomial-4567", "double-harmonic")

MM_PER_IN = 25.4


class Draw(Protocol):
    """Where the random choices come from: :class:`random.Random`, or hypothesis's data."""

    def random(self) -> float: ...

    def uniform(self, a: float, b: float) -> float: ...

    def randint(self, a: int, b: int) -> int: ...

    def choice(self, seq: Sequence[T]) -> T: ...


class HypothesisDraw:
    """A :class:`Draw` drawing through hypothesis's *draw* (so a failing design shrinks)."""

    def __init__(self, draw: st.DrawFn) -> None:
        self.draw = draw

    def random(self) -> float:
        return self.draw(st.floats(0.0, 1.0, exclude_max=True))

    def uniform(self, a: float, b: float) -> float:
        return self.draw(st.floats(min(a, b), max(a, b)))

    def randint(self, a: int, b: int) -> int:
        return self.draw(st.integers(a, b))

    def choice(self, seq: Sequence[T]) -> T:
        return self.draw(st.sampled_from(list(seq)))


# ---- numbers as a designer writes them -----------------------------------------------------


def _chance(d: Draw, p: float) -> bool:
    return d.random() < p


def _round(value: float, step: float) -> float:
    """*value* to a multiple of *step*, written without float noise."""
    digits = max(0, -math.floor(math.log10(step)) + 1)
    return round(round(value / step) * step, digits)


def _length(d: Draw, lo: float, hi: float, step: float = 0.5) -> float:
    """A length (mm) in [lo, hi], to *step*."""
    return max(_round(d.uniform(lo, hi), step), _round(lo, step) if lo >= step else lo)


def _angle(d: Draw, lo: float, hi: float, step: float = 5.0) -> float:
    return _round(d.uniform(lo, hi), step)


def _one_figure(value: float) -> float:
    """*value* to one significant figure (a tolerance, a kerf)."""
    exponent = math.floor(math.log10(value))
    return round(round(value / 10**exponent) * 10**exponent, max(0, -exponent))


# ---- the motion ------------------------------------------------------------------------------


def _law(d: Draw, laws: Sequence[str] = LAWS) -> str:
    """A law: half the time a smooth one, else any (aliases now and then)."""
    if _chance(d, 0.5):
        return d.choice([law for law in SMOOTH_LAWS if law in laws])
    law = d.choice(list(laws))
    if _chance(d, 0.15):
        alias = {"harmonic": "shm", "polynomial-23": "cubic",
                 "uniform-acceleration": "parabolic"}.get(law)
        return alias or law
    return law


def _table_points(d: Draw, angle: float, lift: float, rising: bool,
                  start: float = 0.0) -> list[list[float]]:
    """A table of 5–9 points of a smooth rise (or return) of *lift* over *angle* degrees from
    the lift *start*: a cycloid sampled at round angles."""
    count = d.randint(5, 9)
    points = []
    for i in range(count):
        x = angle * i / (count - 1)
        u = x / angle
        s = lift * (u - math.sin(2 * math.pi * u) / (2 * math.pi))
        points.append([round(x, 3), round(start + (s if rising else lift - s), 6)])
    return points


def _segment(d: Draw, kind: str, span: float, lift: float | None, rising: bool,
             laws: Sequence[str], span_key: str = "angle", start: float = 0.0) -> dict[str, Any]:
    """One rise or return over *span* (degrees, or a travel) by *lift* from the lift *start*."""
    law = _law(d, laws)
    body: dict[str, Any] = {span_key: span}
    if law == "table":
        assert lift is not None
        body["law"] = "table"
        body["points"] = _table_points(d, span, lift, rising, start)
        return {kind: body}
    if lift is not None:
        body["lift"] = lift
    body["law"] = law
    if law == "modified-uniform-velocity" and _chance(d, 0.6):
        body["blend"] = _round(d.uniform(0.05, 0.45), 0.05)
    if law == "polynomial":
        zero: dict[str, Any] = {"velocity": 0, "acceleration": 0}
        if _chance(d, 0.5):
            zero["jerk"] = 0
        body["start"] = dict(zero)
        body["end"] = dict(zero)
        if _chance(d, 0.3):
            body["start"] = {k: "match" for k in zero}
    if law == "spline":
        if _chance(d, 0.5):
            body["order"] = d.randint(4, 8)
        if _chance(d, 0.4):
            body["controls"] = d.randint(0, 8)
        elif _chance(d, 0.5):  # increasing values: a rise (or return) that never turns back
            body["controls"] = sorted(_round(d.uniform(0.0, 1.0), 0.01)
                                      for _ in range(d.randint(1, 6)))
        if span_key == "angle" and _chance(d, 0.3):
            body["start"] = {"velocity": "match", "acceleration": "match"}
    return {kind: body}


def _motion(d: Draw, total: float, lift: float, laws: Sequence[str] = LAWS,
            span_key: str = "angle", least: float = 40.0) -> list[dict[str, Any]]:
    """A motion program of spans summing to *total* (360°, 180° or a stroke): rise, dwell,
    return, dwell, the dwells sometimes left out, sometimes a rise in two steps."""
    step = 5.0 if span_key == "angle" else max(1.0, _round(total / 72, 1.0))
    two_step = _chance(d, 0.15)
    rise = _round(d.uniform(0.22, 0.40) * total, step)
    ret = _round(d.uniform(0.22, 0.40) * total, step)
    rise, ret = max(rise, least), max(ret, least)
    dwells = total - rise - ret
    top = _round(dwells * d.uniform(0.0, 1.0), step) if _chance(d, 0.8) else 0.0
    bottom = total - rise - ret - top
    if bottom < 0:
        top, bottom = 0.0, total - rise - ret
    lift = float(lift)
    segments: list[dict[str, Any]] = []
    if two_step:
        first = _round(lift * d.uniform(0.3, 0.7), 0.01 if lift < 2 else 0.5)
        half = _round(rise / 2, step)
        segments.append(_segment(d, "rise", half, first, True, laws, span_key))
        segments.append(_segment(d, "rise", rise - half, _round(lift - first, 0.0001), True, laws,
                                 span_key, start=first))
    else:
        segments.append(_segment(d, "rise", rise, lift, True, laws, span_key))
    if top > 0:
        segments.append({"dwell": {span_key: top}})
    if two_step:
        lift = first + _round(lift - first, 0.0001)
    back = _segment(d, "return", ret, lift, False, laws, span_key)
    body = back["return"]
    if "points" not in body and _chance(d, 0.7):
        body.pop("lift", None)  # "back to zero", as most designs write it
    segments.append(back)
    if bottom > 0:
        segments.append({"dwell": {span_key: _round(bottom, 1e-6)}})
    return segments


def _half_turn_motion(d: Draw, lift: float) -> list[dict[str, Any]]:
    """A constant-breadth cam's first half turn: a rise and a dwell (camfab mirrors it)."""
    rise = _angle(d, 100, 170)
    body = _segment(d, "rise", rise, lift, True, [*SMOOTH_LAWS, "harmonic", "table"])
    segments = [body]
    if rise < 180:
        segments.append({"dwell": {"angle": 180 - rise}})
    return segments


# ---- the blank and the manufacturing --------------------------------------------------------


def _blank(d: Draw, inside: float, cam: dict[str, Any], keyway: bool = True) -> None:
    """A plate's thickness, and a bore (with a keyway) leaving a wall inside *inside* (mm)."""
    if "thickness" not in cam:
        cam["thickness"] = _length(d, 4, 20, 1)
    if _chance(d, 0.75):
        bore = _length(d, 6, max(6.0, min(40.0, 1.2 * inside - 6)), 1)
        if bore / 2 + 3 < inside:
            cam["bore"] = bore
            if keyway and _chance(d, 0.35):
                width = _length(d, 2, max(2.0, min(8.0, bore / 3)), 0.5)
                depth = _length(d, 1, max(1.0, min(3.5, (inside - bore / 2) / 3)), 0.1)
                cam["keyway"] = {"width": width, "depth": depth}


def _manufacturing(d: Draw, tool_room: float | None, finest: float = 1e-4) -> dict[str, Any]:
    """Tolerance (mm, from *finest* to 0.1), kerf and cutter: each left at its default about
    half the time."""
    out: dict[str, Any] = {}
    if _chance(d, 0.65):
        out["tolerance"] = _one_figure(10 ** d.uniform(math.log10(finest), math.log10(0.1)))
    if _chance(d, 0.25):
        out["kerf"] = d.choice([0, 0.1, 0.15, 0.2, 0.25, 0.3])
    if tool_room is not None and _chance(d, 0.25):
        out["cutter_radius"] = d.choice([0, 1, 1.5, 2, 3, 4, 5, 6, 8])
    return out


def _turning(d: Draw, cam: dict[str, Any], rpm: tuple[float, float]) -> None:
    if _chance(d, 0.6):
        cam["rotation"] = d.choice(["ccw", "cw"])
    if _chance(d, 0.7):
        cam["speed_rpm"] = _round(d.uniform(*rpm), 10)


def _pivot(d: Draw, fol: dict[str, Any], reach: float) -> None:
    """An oscillating follower's pivot, its arm reaching a circle of radius *reach* (mm)."""
    a = _length(d, 1.6 * reach, 3.2 * reach, 1)
    arm = _length(d, max(0.45 * a, a - 0.85 * reach), min(1.05 * a, a + 0.3 * reach), 1)
    fol["pivot_distance"] = a
    fol["arm_length"] = arm
    if _chance(d, 0.5):
        fol["pivot_side"] = d.choice(["right", "left"])


# ---- the kinds ------------------------------------------------------------------------------


def _disc(d: Draw, follower: str, motion: str) -> dict[str, Any]:
    rb = _length(d, 15, 80)
    cam: dict[str, Any] = {"type": "disc"}
    _turning(d, cam, (60, 1500))
    cam["base_radius"] = rb
    _blank(d, rb, cam)
    fol: dict[str, Any] = {"type": follower, "motion": motion}
    lift: float
    if motion == "translating":
        lift = _length(d, 0.1 * rb, 0.7 * rb)
        if follower in ("knife", "roller") and _chance(d, 0.4):
            fol["offset"] = _length(d, -0.2 * rb, 0.2 * rb)
        if follower == "flat" and _chance(d, 0.3):
            fol["offset"] = _length(d, -0.1 * rb, 0.1 * rb)
    if follower == "roller":
        fol["roller_radius"] = _length(d, 3, max(3.0, min(0.5 * rb, 20)))
    elif follower == "mushroom":
        fol["face_radius"] = _length(d, max(rb, 15), 4 * rb, 1)
    if motion == "oscillating":
        lift = _angle(d, 5, 12 if follower == "flat" else 16, 1)
        _pivot(d, fol, rb + fol.get("roller_radius", 0.0) + fol.get("face_radius", 0.0))
    elif follower == "flat":
        if motion == "oscillating":
            if _chance(d, 0.4):
                fol["face_offset"] = _length(d, -0.2 * rb, 0.2 * rb)
        elif _chance(d, 0.6):
            fol["face_width"] = _length(d, 2.0 * rb, 4.0 * rb, 5)
    if _chance(d, 0.3):
        fol["mass"] = _round(d.uniform(0.05, 2.0), 0.05)
    data: dict[str, Any] = {"cam": cam, "follower": fol, "motion": _motion(d, 360, lift)}
    if "mass" in fol and _chance(d, 0.5) and motion == "translating":
        data["spring"] = {"rate": f"{_round(d.uniform(5, 60), 1)} N/mm",
                          "preload": f"{_round(d.uniform(50, 400), 10)} N"}
    if motion == "oscillating" and _chance(d, 0.3):
        data["limits"] = {"pressure_angle": d.choice([35, 40, 45])}
    elif _chance(d, 0.2):
        data["limits"] = {"pressure_angle": d.choice([25, 30, 35, 40])}
    data["manufacturing"] = _manufacturing(d, rb)
    return data


def _shaped(d: Draw, shape: str, follower: str) -> dict[str, Any]:
    rb = _length(d, 15, 60)
    lift = _length(d, 0.15 * rb, 0.6 * rb)
    cam: dict[str, Any] = {"type": shape}
    _turning(d, cam, (100, 1500))
    cam.update({"base_radius": rb, "lift": lift})
    if shape == "circular-arc":
        cam["lift_angle"] = _angle(d, 50, 90)
        flanks = _flank_angles(rb, lift, cam["lift_angle"])
        if follower == "flat" and flanks and _chance(d, 0.5):
            cam["flank_angle"] = d.choice(flanks)
        else:
            # a convex flank needs rn < (rb − (rb + h) cos α) / (1 − cos α)
            cos = math.cos(math.radians(cam["lift_angle"]))
            most = min(0.35 * rb, 0.95 * (rb - (rb + lift) * cos) / (1 - cos))
            cam["nose_radius"] = _length(d, 0.12 * (rb + lift), max(most, 0.12 * (rb + lift)))
    elif _chance(d, 0.6):
        cam["lift_angle"] = _angle(d, 45, 80)
    else:
        cam["nose_radius"] = _length(d, 0.12 * (rb + lift), 0.4 * rb)
    if shape == "tangent" and follower in ("knife", "roller"):  # its flanks are steep
        cam["lift"] = lift = _length(d, 0.1 * rb, 0.3 * rb)
        cam.pop("nose_radius", None)
        cam["lift_angle"] = _angle(d, 60, 85)
    if _chance(d, 0.3):
        cam["top_dwell"] = _angle(d, 5, 40)
    _blank(d, rb, cam)
    fol: dict[str, Any] = {"type": follower, "motion": "translating"}
    if follower == "roller":
        fol["roller_radius"] = _length(d, 3, max(3.0, min(0.4 * rb, 15)))
    elif follower == "mushroom":
        fol["face_radius"] = _length(d, max(rb, 15), 3 * rb, 1)
    elif follower == "flat" and _chance(d, 0.5):
        fol["face_width"] = _length(d, 2.5 * rb, 4.0 * rb, 5)
    if _chance(d, 0.3):
        fol["mass"] = _round(d.uniform(0.05, 1.0), 0.05)
    return {"cam": cam, "follower": fol, "manufacturing": _manufacturing(d, rb)}


def _flank_angles(rb: float, lift: float, lift_angle: float) -> list[float]:
    """The flank angles (deg, whole degrees) that make a circular-arc cam of base radius *rb*,
    *lift* and *lift_angle* (deg) with a nose of some 0.12–0.35 of its radius (the relation of
    :meth:`camfab.curves.shaped.ShapedCam.circular_arc`)."""
    alpha = math.radians(lift_angle)
    out = []
    for degrees in range(1, int(lift_angle)):
        phi = math.radians(degrees)
        pq = lift * math.sin(alpha) / (math.sin(phi) + math.sin(alpha - phi) - math.sin(alpha))
        nose = rb - pq * (1.0 - math.sin(alpha - phi) / math.sin(alpha))
        if 0.12 * (rb + lift) < nose < 0.35 * rb and rb - nose > (rb + lift - nose) * math.cos(
                alpha):
            out.append(float(degrees))
    return out


def _drum(d: Draw) -> dict[str, Any]:
    roller = _length(d, 3, 12)
    clearance = d.choice([0, 0.02, 0.05, 0.1, 0.2])
    radius = _length(d, max(25, 2.5 * roller + 10), 120, 1)
    lift = _length(d, 6, max(6, min(60, 0.4 * radius)), 1)
    depth = _length(d, max(3.0, 0.6 * roller), min(1.4 * roller, radius - 10), 0.5)
    cam: dict[str, Any] = {"type": "cylindrical"}
    _turning(d, cam, (30, 400))
    need = lift + 2 * roller + clearance + 2
    cam.update({"radius": radius, "length": _length(d, need + 4, need + 40, 5),
                "groove_depth": depth})
    if _chance(d, 0.6):
        room = 2 * (radius - depth) - 8
        if room > 8:
            cam["bore"] = _length(d, 8, min(40, room), 1)
    fol: dict[str, Any] = {"type": "roller", "motion": "translating", "roller_radius": roller}
    if clearance or _chance(d, 0.5):
        fol["groove_clearance"] = clearance
    if _chance(d, 0.3):
        fol["mass"] = _round(d.uniform(0.1, 2.0), 0.1)
    return {"cam": cam, "follower": fol, "motion": _motion(d, 360, lift),
            "manufacturing": _manufacturing(d, roller)}


def _groove(d: Draw, motion: str) -> dict[str, Any]:
    rb = _length(d, 20, 70)
    roller = _length(d, 3, max(3.0, min(0.3 * rb, 12)))
    clearance = d.choice([0.02, 0.05, 0.1, 0.2])
    thickness = _length(d, 8, 24, 1)
    cam: dict[str, Any] = {"type": "groove"}
    _turning(d, cam, (60, 600))
    cam.update({"base_radius": rb, "thickness": thickness,
                "groove_depth": _length(d, 2, thickness - 2, 0.5)})
    fol: dict[str, Any] = {"type": "roller", "motion": motion, "roller_radius": roller,
                           "groove_clearance": clearance}
    if motion == "translating":
        lift = _length(d, 0.15 * rb, 0.6 * rb)
        if _chance(d, 0.4):
            fol["offset"] = _length(d, -0.15 * rb, 0.15 * rb)
        outer = rb + lift + 2 * roller + clearance
    else:
        lift = _angle(d, 6, 25, 1)
        _pivot(d, fol, rb + roller)
        swing = math.radians(lift) * fol["arm_length"]
        outer = rb + swing + 2 * roller + clearance
    if _chance(d, 0.4):
        cam["outer_radius"] = _length(d, outer + 4, outer + 20, 1)
    _blank(d, rb, cam)
    if _chance(d, 0.3):
        fol["mass"] = _round(d.uniform(0.1, 1.5), 0.1)
    return {"cam": cam, "follower": fol, "motion": _motion(d, 360, lift),
            "manufacturing": _manufacturing(d, roller)}


def _conjugate(d: Draw, motion: str) -> dict[str, Any]:
    rb = _length(d, 20, 60)
    roller = _length(d, 4, max(4.0, min(0.35 * rb, 12)))
    cam: dict[str, Any] = {"type": "conjugate"}
    _turning(d, cam, (60, 800))
    cam["base_radius"] = rb
    _blank(d, rb, cam)
    fol: dict[str, Any] = {"type": "roller", "motion": motion, "roller_radius": roller}
    if motion == "translating":
        lift = _length(d, 0.15 * rb, 0.6 * rb)
        fol["roller_spacing"] = _length(d, 2 * (rb + roller) + lift + 5,
                                        2 * (rb + roller) + lift + 40, 1)
        if _chance(d, 0.3):
            fol["offset"] = _length(d, -0.1 * rb, 0.1 * rb)
    else:
        lift = _angle(d, 5, 16, 1)
        _pivot(d, fol, rb + roller)
        fol["arm_angle"] = _angle(d, 50, 90, 1)
    return {"cam": cam, "follower": fol, "motion": _motion(d, 360, lift),
            "manufacturing": _manufacturing(d, roller)}


def _constant_breadth(d: Draw, follower: str) -> dict[str, Any]:
    rb = _length(d, 20, 60)
    lift = _length(d, 0.15 * rb, 0.6 * rb)
    cam: dict[str, Any] = {"type": "constant-breadth"}
    _turning(d, cam, (60, 600))
    cam["base_radius"] = rb
    _blank(d, rb, cam)
    fol: dict[str, Any] = {"type": follower, "motion": "translating"}
    if follower == "roller":
        fol["roller_radius"] = _length(d, 3, max(3.0, min(0.3 * rb, 12)))
    elif _chance(d, 0.4):
        fol["face_width"] = _length(d, 2.5 * rb, 4 * rb, 5)
    return {"cam": cam, "follower": fol, "motion": _half_turn_motion(d, lift),
            "manufacturing": _manufacturing(d, rb)}


def _globoid(d: Draw, blank: str) -> dict[str, Any]:
    roller = _length(d, 4, 10)
    length = _length(d, max(10, 1.8 * roller), 3.2 * roller, 1)
    depth = _length(d, 0.4 * length, 0.85 * length, 0.5)
    if blank == "concave":
        c = _length(d, 100, 220, 5)
        arm = _length(d, 0.3 * c, 0.62 * c - length / 2, 1)
    else:  # the pitch radius arm − c, the roller and its crown inside the pivot axis
        c = _length(d, 50, 110, 5)
        top = c - length / 2 - 6
        arm = c + _length(d, max(length / 2 + 8, depth + 12, 0.7 * top), top, 1)
    swing = _angle(d, 15, 50, 1) if blank == "concave" else _angle(d, 8, 22, 1)
    cam: dict[str, Any] = {"type": "globoidal", "globoid": blank}
    _turning(d, cam, (20, 120))
    cam["groove_depth"] = depth
    fol: dict[str, Any] = {"type": "roller", "motion": "oscillating", "pivot_distance": c,
                           "arm_length": arm, "roller_radius": roller, "roller_length": length,
                           "groove_clearance": d.choice([0.02, 0.05, 0.1])}
    if _chance(d, 0.3):
        fol["rest_angle"] = _angle(d, -swing / 2 - 10, -swing / 2 + 10, 1)
    floor = (c - arm if blank == "concave" else arm - c) - depth  # about
    if _chance(d, 0.5) and floor > 12:
        cam["bore"] = _length(d, 8, min(30, 2 * floor - 10), 1)
    return {"cam": cam, "follower": fol, "motion": _motion(d, 360, swing, least=60),
            "limits": {"pressure_angle": d.choice([35, 40, 45])},
            "manufacturing": _manufacturing(d, None, finest=0.008)}


def _linear(d: Draw, follower: str) -> dict[str, Any]:
    stroke = _length(d, 100, 400, 10)
    lift = _length(d, 0.03 * stroke, 0.1 * stroke)
    fol: dict[str, Any] = {"type": follower}
    base = _length(d, 10, 50)
    if follower == "roller":
        fol["roller_radius"] = _length(d, 3, 15)
        base = max(base, fol["roller_radius"] + 4)
    cam: dict[str, Any] = {"type": "linear"}
    if _chance(d, 0.5):
        cam["speed_rpm"] = _round(d.uniform(5, 60), 1)
    cam.update({"stroke": stroke, "base_height": base, "thickness": _length(d, 4, 15, 1)})
    return {"cam": cam, "follower": fol,
            "motion": _motion(d, stroke, lift, STANDARD_LAWS, "travel", least=0.1 * stroke),
            "manufacturing": _manufacturing(d, None)}


def _by_kind(d: Draw, kind: str) -> dict[str, Any]:
    parts = kind.split("/")
    if parts[0] == "disc":
        return _disc(d, parts[1], parts[2])
    if parts[0] in ("circular-arc", "tangent"):
        return _shaped(d, parts[0], parts[1])
    if parts[0] == "cylindrical":
        return _drum(d)
    if parts[0] == "groove":
        return _groove(d, parts[1])
    if parts[0] == "conjugate":
        return _conjugate(d, parts[1])
    if parts[0] == "constant-breadth":
        return _constant_breadth(d, parts[1])
    if parts[0] == "globoidal":
        return _globoid(d, parts[1])
    if parts[0] == "linear":
        return _linear(d, parts[1])
    raise ValueError(f"unknown kind {kind!r}")


# ---- inches ---------------------------------------------------------------------------------

#: The keys of each section whose bare values are lengths (in the design's units).
_LENGTH_KEYS = {
    "cam": ("base_radius", "thickness", "bore", "radius", "length", "groove_depth",
            "groove_start", "lift", "nose_radius", "outer_radius", "stroke", "base_height",
            "width"),
    "follower": ("offset", "roller_radius", "face_radius", "face_width", "pivot_distance",
                 "arm_length", "face_offset", "groove_clearance", "roller_spacing",
                 "roller_length"),
    "manufacturing": ("cutter_radius",),
}


def _inches(value: float) -> float:
    """*value* mm in inches, to the 0.0001 in a drawing in inches gives (five figures)."""
    inches = value / MM_PER_IN
    if inches == 0:
        return 0.0
    figures = max(4, 5 - math.floor(math.log10(abs(inches))) - 1)
    return round(inches, min(figures, 7))


def _to_inches(data: dict[str, Any]) -> None:
    """Every bare length of *data* from millimetres to inches, in place (a swing stays
    degrees)."""
    for section, keys in _LENGTH_KEYS.items():
        body = data.get(section, {})
        for key in keys:
            if isinstance(body.get(key), (int, float)):
                body[key] = _inches(body[key])
    made = data.get("manufacturing", {})
    for key in ("tolerance", "kerf"):  # one figure, no finer than the millimetres' value
        if made.get(key):
            inches = _one_figure(made[key] / MM_PER_IN)
            made[key] = inches if inches * MM_PER_IN >= made[key] else _one_figure(
                1.5 * made[key] / MM_PER_IN)
    keyway = data.get("cam", {}).get("keyway")
    if keyway:
        keyway.update({k: _inches(v) for k, v in keyway.items()})
    angular = data["follower"].get("motion") == "oscillating"
    bodies = [next(iter(segment.values())) for segment in data.get("motion", ())]
    for body in bodies:
        if "travel" in body:
            body["travel"] = _inches(body["travel"])
        if not angular and "lift" in body:
            body["lift"] = _inches(body["lift"])
        if not angular and "points" in body:
            body["points"] = [[x, _inches(s)] for x, s in body["points"]]
    if bodies and "travel" in bodies[-1]:  # the travels still sum to the stroke
        rest = data["cam"]["stroke"] - sum(b["travel"] for b in bodies[:-1])
        bodies[-1]["travel"] = round(rest, 7)
    if not angular:  # the lifts (a table's last point) still come back to zero
        height = 0.0
        for segment, body in zip(data.get("motion", ()), bodies, strict=True):
            kind = next(iter(segment))
            if "points" in body:
                body["points"][0][1] = height
                height = body["points"][-1][1]
            elif kind == "rise":
                height = round(height + body["lift"], 7)
            elif kind == "return" and "lift" in body:
                body["lift"] = height
                height = 0.0


# ---- the design -----------------------------------------------------------------------------


def design(d: Draw, kind: str | None = None, name: str = "random") -> tuple[str, dict[str, Any]]:
    """A random valid design of *kind* (any of :data:`KINDS` when None), drawn from *d*:
    ``(kind, data)`` with *data* the design file's mapping, ready to dump as YAML."""
    kind = kind or d.choice(KINDS)
    body = _by_kind(d, kind)
    data: dict[str, Any] = {"name": name, "description": f"random {kind} design"}
    if _chance(d, 0.2):
        data["units"] = "in"
    elif _chance(d, 0.3):
        data["units"] = "mm"
    data.update(body)
    if not data.get("manufacturing"):
        data.pop("manufacturing", None)
    if data.get("units") == "in":
        _to_inches(data)
    return kind, data


def design_of_seed(seed: int, kind: str | None = None) -> tuple[str, dict[str, Any]]:
    """The design :func:`design` draws from ``random.Random(seed)``: the same on every run."""
    return design(random.Random(seed), kind, name=f"random-{seed}")


@st.composite
def designs(draw: st.DrawFn, kinds: Sequence[str] = KINDS) -> tuple[str, dict[str, Any]]:
    """The hypothesis strategy of :func:`design`: ``(kind, data)`` of one of *kinds*."""
    kind = draw(st.sampled_from(list(kinds)))
    return design(HypothesisDraw(draw), kind)
