"""Design rules: what a cam designer needs checked before anything is computed.

Field types, units and simple ranges are checked by the models; these rules relate fields to each
other (a roller needs a radius, the prime circle must be larger than the offset, the program must be
periodic, ...). A broken rule raises :class:`RuleViolation`, which carries the field path so the
loader can name the line.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NoReturn

from camfab.errors import CamfabError, DesignError
from camfab.geometry.follower import FollowerGeometry

if TYPE_CHECKING:
    from camfab.design.model import Design
    from camfab.motion.program import MotionProgram

#: Cam types this version builds; the others are part of the design format but not built yet.
SUPPORTED_CAM_TYPES = ("disc", "cylindrical", "circular-arc", "tangent")

#: Smallest wall of material camfab accepts between a groove or bore and the part's edge (mm):
#: thinner walls do not survive printing or machining.
MIN_WALL_MM = 1.0

#: Shortest motion segment (degrees of cam angle). Far shorter than any real cam's, it keeps
#: s‴ = Δ·Cj/β³ finite in floating point.
MIN_SEGMENT_DEG = 1e-6

#: Follower contact shapes per cam type.
FOLLOWERS_FOR_CAM = {"disc": ("knife", "roller", "flat", "mushroom"), "cylindrical": ("roller",),
                     "circular-arc": ("knife", "roller", "flat", "mushroom"),
                     "tangent": ("knife", "roller", "flat", "mushroom")}

#: Keys each cam type requires.
REQUIRED_CAM_KEYS = {"disc": ("base_radius",), "cylindrical": ("radius", "length", "groove_depth"),
                     "circular-arc": ("base_radius", "lift", "lift_angle"),
                     "tangent": ("base_radius", "lift")}


class RuleViolation(CamfabError):
    """A broken design rule at *path*; deliberately not a ValueError so that pydantic lets it
    through unchanged. ``show_got`` asks the loader to quote the value written at *path*."""

    def __init__(self, path: tuple[str | int, ...], error: DesignError, show_got: bool = True):
        self.path = path
        self.error = error
        self.show_got = show_got
        super().__init__(str(error))


def fail(path: tuple[str | int, ...], problem: str, *, show_got: bool = True,
         allowed: str | None = None, hint: str | None = None) -> NoReturn:
    raise RuleViolation(path, DesignError(problem, allowed=allowed, hint=hint), show_got)


def check_rules(design: Design) -> None:
    """Raise :class:`RuleViolation` for the first broken rule."""
    _check_cam(design)
    _check_follower(design)
    program = _check_motion(design)
    _check_cam_fit(design, program.max_lift)
    _check_oscillating(design, program.max_lift)
    _check_swinging_face(design, program)
    _check_manufacturing(design)
    _check_other(design)


def check_cam_type(cam_type: str) -> None:
    """Fail for a cam type of the design format that this version does not build."""
    if cam_type not in SUPPORTED_CAM_TYPES:
        fail(("cam", "type"), f"'{cam_type}' cams are not built by this version of camfab",
             show_got=False, allowed=", ".join(SUPPORTED_CAM_TYPES))


def _check_cam(design: Design) -> None:
    cam = design.cam
    check_cam_type(cam.type)
    for key in REQUIRED_CAM_KEYS[cam.type]:
        if getattr(cam, key) is None:
            fail(("cam", key), f"required for a {cam.type} cam", show_got=False)
    if cam.shaped:
        _check_shape(design)
    if cam.type != "cylindrical":
        rb = cam.base_radius or 0.0
        if cam.bore is not None and cam.bore / 2 > rb - MIN_WALL_MM:
            fail(("cam", "bore"),
                 f"leaves less than {MIN_WALL_MM:g} mm of material inside the base circle "
                 f"(bore radius {_mm(cam.bore / 2)} vs base radius {_mm(rb)})")
    if cam.keyway is not None:
        if cam.bore is None:
            fail(("cam", "keyway"), "a keyway needs a bore", show_got=False)
        assert cam.bore is not None
        if cam.keyway.width >= cam.bore:
            fail(("cam", "keyway", "width"), f"must be narrower than the bore ({_mm(cam.bore)})")
        outer = cam.radius if cam.type == "cylindrical" else cam.base_radius
        if outer is not None and cam.bore / 2 + cam.keyway.depth > outer - MIN_WALL_MM:
            fail(("cam", "keyway", "depth"),
                 f"cuts to within {MIN_WALL_MM:g} mm of the cam's edge")


def _check_shape(design: Design) -> None:
    """A circular-arc or tangent cam's dimensions must make one (and the nose, flanks and base
    circle must all be there)."""
    from camfab.geometry.shaped import ShapeError

    cam = design.cam
    if cam.type == "tangent" and cam.lift_angle is None and cam.nose_radius is None:
        fail(("cam", "lift_angle"), "required for a tangent cam (or nose_radius)", show_got=False)
    if cam.type == "circular-arc" and cam.nose_radius is None and cam.flank_angle is None:
        fail(("cam", "nose_radius"), "required for a circular-arc cam (or flank_angle)",
             show_got=False)
    try:
        design.shape  # noqa: B018 - building it checks it
    except ShapeError as exc:
        fail(("cam", exc.field), exc.problem)


def _check_follower(design: Design) -> None:
    cam, fol = design.cam, design.follower
    allowed = FOLLOWERS_FOR_CAM[cam.type]
    if fol.type not in allowed:
        fail(("follower", "type"), f"a {cam.type} cam takes a {' or '.join(allowed)} follower",
             allowed=", ".join(allowed))
    if cam.type in ("cylindrical", "circular-arc", "tangent") and fol.oscillating:
        fail(("follower", "motion"), f"a {cam.type} cam drives a translating follower",
             allowed="translating")
    if cam.shaped and fol.offset != 0.0:
        fail(("follower", "offset"), f"a {cam.type} cam's follower moves along a line through "
             "the cam centre: the offset must be 0")
    if fol.type == "roller" and fol.roller_radius is None:
        fail(("follower", "roller_radius"), "required for a roller follower", show_got=False)
    if fol.type == "mushroom" and fol.face_radius is None:
        fail(("follower", "face_radius"), "required for a mushroom follower", show_got=False)
    if fol.oscillating:
        for key in ("pivot_distance", "arm_length"):
            if getattr(fol, key) is None:
                fail(("follower", key), "required for an oscillating follower", show_got=False)
    elif cam.type == "disc" and fol.type != "flat":
        rp = (cam.base_radius or 0.0) + fol.trace_radius
        if abs(fol.offset) >= rp:
            fail(("follower", "offset"),
                 f"|offset| must be smaller than the prime circle radius {_mm(rp)}")


def _check_motion(design: Design) -> MotionProgram:
    from camfab.motion.program import ProgramError

    if design.cam.shaped:
        if design.motion is not None:
            fail(("motion",), f"a {design.cam.type} cam's shape defines the motion: remove the "
                 "motion list", show_got=False)
        return design.program
    if design.motion is None:
        fail(("motion",), "required (a list of rise, dwell and return segments)", show_got=False)
    for i, seg in enumerate(design.motion):
        if math.degrees(seg.angle) < MIN_SEGMENT_DEG:
            fail(("motion", i, "angle"), f"must be at least {MIN_SEGMENT_DEG:g}°")
        if seg.kind == "dwell":
            continue
        if seg.law is None:
            fail(("motion", i, "law"), f"required for a {seg.kind}", show_got=False,
                 allowed=_law_names())
        if seg.blend is not None and seg.law != "modified-uniform-velocity":
            fail(("motion", i, "blend"), "only the modified-uniform-velocity law takes a blend")
        if seg.law not in ("polynomial", "table"):
            for key in ("start", "end", "points"):
                if getattr(seg, key) is not None:
                    fail(("motion", i, key), "only polynomial and table laws take " + key,
                         show_got=False)
        if seg.law == "table" and not seg.points:
            fail(("motion", i, "points"), "a table law needs points (or a csv file)",
                 show_got=False)
        if seg.lift is None and seg.kind == "rise" and seg.law != "table":
            fail(("motion", i, "lift"), "required for a rise", show_got=False)
    try:
        return design.program
    except ProgramError as exc:
        path: tuple[str | int, ...] = ("motion",) if exc.index is None else ("motion", exc.index)
        if exc.field:
            path = (*path, *_split(exc.field))
        fail(path, exc.problem, show_got=False)


def _check_cam_fit(design: Design, max_lift: float) -> None:
    cam, fol = design.cam, design.follower
    if cam.type != "cylindrical":
        return
    assert cam.radius is not None and cam.length is not None and cam.groove_depth is not None
    if cam.groove_depth > cam.radius - MIN_WALL_MM:
        fail(("cam", "groove_depth"), f"must leave at least {MIN_WALL_MM:g} mm below the groove "
             f"(radius {_mm(cam.radius)})")
    if cam.bore is not None and cam.bore / 2 > cam.radius - cam.groove_depth - MIN_WALL_MM:
        fail(("cam", "bore"), "reaches the groove root "
             f"(root radius {_mm(cam.radius - cam.groove_depth)})")
    half = (fol.roller_radius or 0.0) + fol.groove_clearance / 2
    needed = max_lift + 2 * half + 2 * MIN_WALL_MM
    if needed > cam.length:
        fail(("cam", "length"), f"the groove needs {_mm(needed)} (lift {_mm(max_lift)} + roller "
             f"and {MIN_WALL_MM:g} mm walls)")
    if cam.groove_start is not None:
        low = cam.groove_start - half
        high = cam.groove_start + max_lift + half
        if low < MIN_WALL_MM or high > cam.length - MIN_WALL_MM:
            fail(("cam", "groove_start"), f"puts the groove at z = {_mm(low)} … {_mm(high)}, "
                 f"outside the drum's length less {MIN_WALL_MM:g} mm walls")


def _check_oscillating(design: Design, max_swing: float) -> None:
    fol = design.follower
    if not fol.oscillating or design.cam.type != "disc":
        return
    a, arm = fol.pivot_distance or 0.0, fol.arm_length or 0.0
    rb = design.cam.base_radius or 0.0
    if fol.type == "flat":
        ratio = (rb + fol.face_offset) / a
        if not 0.0 < ratio < 1.0:
            fail(("follower", "face_offset"), "the face line cannot touch the base circle from "
                 f"this pivot: (base radius + face_offset)/pivot_distance = {ratio:.4g} must lie "
                 "in (0, 1)")
    else:
        rp = rb + fol.trace_radius
        if not abs(a - arm) < rp < a + arm:
            fail(("follower", "arm_length"), f"the arm cannot reach the prime circle: need "
                 f"|pivot_distance − arm_length| < {_mm(rp)} < pivot_distance + arm_length")
    psi0 = FollowerGeometry.from_design(design).rest_position(rb)
    if psi0 + max_swing >= math.pi:
        fail(("follower", "arm_length"), f"the arm starts at {math.degrees(psi0):.4g}° from the "
             f"line of centres and swings {math.degrees(max_swing):.4g}°: it would pass 180°")
    # the cam's largest radius: the face line's farthest distance from the cam centre, or the
    # trace point's farthest distance less the roller radius; the pivot must lie beyond it
    top = psi0 + max_swing
    if fol.type == "flat":
        reach = a * math.sin(min(top, math.pi / 2)) - fol.face_offset
    else:
        reach = math.sqrt(a * a + arm * arm - 2 * a * arm * math.cos(top)) - fol.trace_radius
    if reach >= a:
        fail(("follower", "pivot_distance"), f"the cam would reach {_mm(reach)} from its centre, "
             f"past the pivot: the pivot must lie outside the cam", show_got=True)


#: An oscillating flat face touches the cam at l = a·cos Ψ/(1 + σψ′) from the pivot (THEORY §B):
#: the face must turn slower than the cam, 1 + σψ′ above this, or contact runs off toward infinity.
MIN_FACE_TURN_MARGIN = 0.05


def _check_swinging_face(design: Design, program: MotionProgram) -> None:
    import numpy as np

    fol = design.follower
    if not (fol.oscillating and fol.type == "flat" and design.cam.type == "disc"):
        return
    theta = np.linspace(0.0, 2 * math.pi, 7201)
    sign = design.cam.sigma * (1 if fol.pivot_side == "right" else -1)
    margin = 1.0 + sign * program.evaluate(theta)[1]
    worst = int(np.argmin(margin))
    if margin[worst] < MIN_FACE_TURN_MARGIN:
        index = next(seg.index for seg in reversed(program.segments)
                     if seg.start <= theta[worst] % (2 * math.pi))
        fail(("motion", index), f"an oscillating flat face must swing slower than the cam "
             f"turns: 1 + σψ′ falls to {margin[worst]:.3g} at {math.degrees(theta[worst]):.4g}° "
             f"(at least {MIN_FACE_TURN_MARGIN:g}), so the contact runs off the face; spread "
             f"the swing over a larger angle", show_got=False)


def _check_manufacturing(design: Design) -> None:
    """The laser's kerf must leave the holes something to cut (the beam runs kerf/2 inside)."""
    cam, kerf = design.cam, design.manufacturing.kerf
    if kerf <= 0.0 or cam.bore is None:
        return
    if kerf >= cam.bore:
        fail(("manufacturing", "kerf"), f"must be smaller than the bore ({_mm(cam.bore)})")
    if cam.keyway is not None and kerf >= cam.keyway.width:
        fail(("manufacturing", "kerf"),
             f"must be smaller than the keyway's width ({_mm(cam.keyway.width)})")


def _check_other(design: Design) -> None:
    limit = design.limits.pressure_angle
    if limit is not None and limit >= math.pi / 2:
        fail(("limits", "pressure_angle"), "must be below 90°")
    step_deg = math.degrees(design.table_step)
    count = 360.0 / step_deg
    if step_deg > 30.0 or abs(count - round(count)) > 1e-6:
        fail(("table_step",), "must divide 360° and be at most 30°")
    if design.manufacturing.tolerance > 1.0:
        fail(("manufacturing", "tolerance"), "must be at most 1 mm (it is the largest allowed "
             "deviation of the exported curves)")
    if design.outputs is not None and len(set(design.outputs)) != len(design.outputs):
        fail(("outputs",), "lists an output twice")
    spring = design.spring
    if spring is not None and spring.preload is not None and spring.initial_compression is not None:
        fail(("spring", "initial_compression"), "give either preload or initial_compression, "
             "not both", show_got=False)


def _split(field: str) -> tuple[str | int, ...]:
    """``"points[3]"`` -> ``("points", 3)``."""
    out: list[str | int] = []
    for part in field.replace("]", "").split("."):
        name, _, index = part.partition("[")
        out.append(name)
        if index:
            out.append(int(index))
    return tuple(out)


def _law_names() -> str:
    from camfab.motion.laws import LAW_NAMES

    return ", ".join(LAW_NAMES)


def _mm(value: float) -> str:
    return f"{value:.6g} mm"
