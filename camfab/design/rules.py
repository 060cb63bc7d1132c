"""Design rules: what a cam designer needs checked before anything is computed.

Field types, units and simple ranges are checked by the models; these rules relate fields to each
other (a roller needs a radius, the prime circle must be larger than the offset, the program must be
periodic, ...). A broken rule raises :class:`RuleViolation`, which carries the field path so the
loader can name the line.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NoReturn

from camfab.curves.follower import FollowerGeometry
from camfab.errors import CamfabError, DesignError

if TYPE_CHECKING:
    from camfab.design.model import Design
    from camfab.motion.program import MotionProgram

#: Cam types this version builds; the others are part of the design format but not built yet.
SUPPORTED_CAM_TYPES = ("disc", "cylindrical", "circular-arc", "tangent", "groove", "conjugate",
                       "constant-breadth", "linear")

#: Smallest wall of material camfab accepts between a groove or bore and the part's edge (mm):
#: thinner walls do not survive printing or machining.
MIN_WALL_MM = 1.0

#: Shortest motion segment (degrees of cam angle). Far shorter than any real cam's, it keeps
#: s‴ = Δ·Cj/β³ finite in floating point.
MIN_SEGMENT_DEG = 1e-6

#: Finest export tolerance (mm), a tenth of a micrometre: below any machine's accuracy (and an
#: STL's float32 coordinates), and a build at 1e-6 mm already takes minutes.
MIN_TOLERANCE_MM = 1e-4

#: Finest step of the motion table (degrees): 36,000 rows, finer than any dial gauge reads; a
#: step of a millionth of a degree would ask for 360 million rows.
MIN_TABLE_STEP_DEG = 0.01

#: Most motion segments camfab builds. Far more than any real cam's; analysis and exports take
#: time in proportion to the count (a disc cam of a thousand segments builds in some 8 s).
MAX_SEGMENTS = 1000

#: Smallest nose radius of a circular-arc or tangent cam, as a share of its largest radius:
#: the nose's normals come from points 1e-16 of that apart, and a nose much smaller has none.
MIN_NOSE_SHARE = 1e-8

#: Follower contact shapes per cam type.
FOLLOWERS_FOR_CAM = {"disc": ("knife", "roller", "flat", "mushroom"), "cylindrical": ("roller",),
                     "circular-arc": ("knife", "roller", "flat", "mushroom"),
                     "tangent": ("knife", "roller", "flat", "mushroom"),
                     "groove": ("roller",), "conjugate": ("roller",),
                     "constant-breadth": ("flat", "roller"), "linear": ("roller", "knife")}

#: Why a cam type refuses a follower it cannot drive, where the list alone does not say.
FOLLOWER_HINTS = {
    ("linear", "flat"): "a flat face perpendicular to its motion rests on the highest point of "
                        "a cam sliding under it, so a linear cam cannot move it",
}

#: Keys each cam type requires.
REQUIRED_CAM_KEYS = {"disc": ("base_radius",), "cylindrical": ("radius", "length", "groove_depth"),
                     "circular-arc": ("base_radius", "lift", "lift_angle"),
                     "tangent": ("base_radius", "lift"),
                     "groove": ("base_radius", "thickness", "groove_depth"),
                     "conjugate": ("base_radius",), "constant-breadth": ("base_radius",),
                     "linear": ("stroke", "base_height")}

#: Cam types that drive a translating follower only.
TRANSLATING_ONLY = ("cylindrical", "circular-arc", "tangent", "constant-breadth", "linear")


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
    _check_groove_fit(design)
    _check_swinging_face(design, program)
    _check_manufacturing(design)
    _check_other(design)
    _check_size(design, program.max_lift)


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
    tolerance = design.manufacturing.tolerance
    if cam.base_radius is not None and cam.base_radius <= tolerance:
        fail(("cam", "base_radius"), f"must be larger than the export tolerance "
             f"({mm(tolerance)}): a smaller cam cannot be drawn within it")
    if cam.groove_depth is not None and cam.groove_depth <= tolerance:
        fail(("cam", "groove_depth"), f"must be larger than the export tolerance "
             f"({mm(tolerance)}): a shallower groove cannot be cut to it")
    if cam.shaped:
        _check_shape(design)
    if cam.type == "groove":
        _check_groove(design)
    if cam.type == "linear":
        _check_linear(design)
    if cam.type not in ("cylindrical", "linear"):
        rb = cam.base_radius or 0.0
        if cam.bore is not None and cam.bore / 2 > rb - MIN_WALL_MM:
            fail(("cam", "bore"),
                 f"leaves less than {MIN_WALL_MM:g} mm of material inside the base circle "
                 f"(bore radius {mm(cam.bore / 2)} vs base radius {mm(rb)})")
    if cam.keyway is not None:
        if cam.bore is None:
            fail(("cam", "keyway"), "a keyway needs a bore", show_got=False)
        assert cam.bore is not None
        if cam.keyway.width >= cam.bore:
            fail(("cam", "keyway", "width"), f"must be narrower than the bore ({mm(cam.bore)})")
        outer = cam.radius if cam.type == "cylindrical" else cam.base_radius
        if outer is not None and cam.bore / 2 + cam.keyway.depth > outer - MIN_WALL_MM:
            fail(("cam", "keyway", "depth"),
                 f"cuts to within {MIN_WALL_MM:g} mm of the cam's edge")


def _check_groove(design: Design) -> None:
    """The groove is a pocket: it must leave a floor under it."""
    cam = design.cam
    assert cam.thickness is not None and cam.groove_depth is not None
    if cam.groove_depth > cam.thickness - MIN_WALL_MM:
        fail(("cam", "groove_depth"), f"must leave at least {MIN_WALL_MM:g} mm of floor under "
             f"the groove (thickness {mm(cam.thickness)})")


def _check_groove_fit(design: Design) -> None:
    """A groove cam's roller (its radius plus half the clearance) must reach the prime circle
    from an oscillating follower's pivot. (That the plate's ``outer_radius`` leaves a wall of
    material outside the groove takes the groove's geometry: the groove kind checks it.)"""
    cam, fol = design.cam, design.follower
    if cam.type != "groove":
        return
    half = (fol.roller_radius or 0.0) + fol.groove_clearance / 2
    rp = (cam.base_radius or 0.0) + half
    if fol.oscillating:
        a, arm = fol.pivot_distance or 0.0, fol.arm_length or 0.0
        if not abs(a - arm) < rp < a + arm:
            fail(("follower", "arm_length"), f"the arm cannot reach the prime circle of the "
                 f"groove's centre line: need |pivot_distance − arm_length| < {mm(rp)} < "
                 "pivot_distance + arm_length")


def _check_linear(design: Design) -> None:
    """The plate must stand under the follower at its lowest."""
    cam, fol = design.cam, design.follower
    assert cam.base_height is not None
    low = cam.base_height - fol.trace_radius
    if low < MIN_WALL_MM:
        fail(("cam", "base_height"), f"leaves {mm(low)} of plate under the follower at zero "
             f"lift (base height less the roller radius); at least {MIN_WALL_MM:g} mm is needed")


def _check_shape(design: Design) -> None:
    """A circular-arc or tangent cam's dimensions must make one (and the nose, flanks and base
    circle must all be there)."""
    from camfab.curves.shaped import ShapeError

    cam = design.cam
    if cam.type == "tangent" and cam.lift_angle is None and cam.nose_radius is None:
        fail(("cam", "lift_angle"), "required for a tangent cam (or nose_radius)", show_got=False)
    if cam.type == "circular-arc" and cam.nose_radius is None and cam.flank_angle is None:
        fail(("cam", "nose_radius"), "required for a circular-arc cam (or flank_angle)",
             show_got=False)
    try:
        shape = design.shape
    except ShapeError as exc:
        fail(("cam", exc.field), exc.problem)
    size = shape.base_radius + shape.lift
    if shape.nose_radius < MIN_NOSE_SHARE * size:
        given = ("nose_radius" if cam.nose_radius is not None else
                 "lift_angle" if cam.type == "tangent" else "flank_angle")
        fail(("cam", given), f"gives a nose of radius {mm(shape.nose_radius)}: it must be at "
             f"least {MIN_NOSE_SHARE:g} of the cam's radius ({mm(size)}), or rounding loses which "
             "way the nose faces")


def _check_follower(design: Design) -> None:
    cam, fol = design.cam, design.follower
    allowed = FOLLOWERS_FOR_CAM[cam.type]
    if fol.type not in allowed:
        fail(("follower", "type"), f"a {cam.type} cam takes a {' or '.join(allowed)} follower",
             allowed=", ".join(allowed), hint=FOLLOWER_HINTS.get((cam.type, fol.type)))
    if cam.type in TRANSLATING_ONLY and fol.oscillating:
        fail(("follower", "motion"), f"a {cam.type} cam drives a translating follower",
             allowed="translating")
    if cam.shaped and fol.offset != 0.0:
        fail(("follower", "offset"), f"a {cam.type} cam's follower moves along a line through "
             "the cam centre: the offset must be 0")
    if cam.type == "linear" and fol.offset != 0.0:
        fail(("follower", "offset"), "a linear cam's follower line is where the travel starts: "
             "the offset must be 0 (a dwell shifts the motion along the cam)")
    if cam.type == "constant-breadth" and fol.type == "roller" and fol.offset != 0.0:
        fail(("follower", "offset"), "the two rollers of a constant-diameter cam lie on a line "
             "through the cam centre: the offset must be 0")
    if cam.type == "conjugate" and not fol.oscillating and fol.roller_spacing is None:
        fail(("follower", "roller_spacing"), "required for a conjugate cam (the distance between "
             "the two rollers' centres along the follower)", show_got=False)
    if cam.type == "conjugate" and fol.oscillating and fol.arm_angle is None:
        fail(("follower", "arm_angle"), "required for an oscillating conjugate cam (the angle "
             "at the pivot between the bell-crank's two arms)", show_got=False)
    if fol.type == "roller" and fol.roller_radius is None:
        fail(("follower", "roller_radius"), "required for a roller follower", show_got=False)
    if fol.type == "mushroom" and fol.face_radius is None:
        fail(("follower", "face_radius"), "required for a mushroom follower", show_got=False)
    if fol.oscillating:
        for key in ("pivot_distance", "arm_length"):
            if getattr(fol, key) is None:
                fail(("follower", key), "required for an oscillating follower", show_got=False)
    elif cam.plate and fol.type != "flat":
        rp = (cam.base_radius or 0.0) + fol.trace_radius
        if abs(fol.offset) >= rp:
            fail(("follower", "offset"),
                 f"|offset| must be smaller than the prime circle radius {mm(rp)}")


def _check_motion(design: Design) -> MotionProgram:
    from camfab.motion.program import ProgramError

    if design.cam.shaped:
        if design.motion is not None:
            fail(("motion",), f"a {design.cam.type} cam's shape defines the motion: remove the "
                 "motion list", show_got=False)
        return design.program
    if design.motion is None:
        fail(("motion",), "required (a list of rise, dwell and return segments)", show_got=False)
    if len(design.motion) > MAX_SEGMENTS:
        fail(("motion",), f"has {len(design.motion):,} segments; camfab builds at most "
             f"{MAX_SEGMENTS:,}", show_got=False)
    linear = design.cam.linear
    span_key = "travel" if linear else "angle"
    for i, seg in enumerate(design.motion):
        span = seg.travel if linear else seg.angle
        if span is None:
            fail(("motion", i, span_key), "required", show_got=False)
        if linear:
            if seg.law in ("polynomial", "table"):
                fail(("motion", i, "law"), "a linear cam's segments take the standard laws (a "
                     "polynomial's or a table's conditions and points are per cam angle)",
                     allowed=", ".join(n for n in _law_names().split(", ")
                                       if n not in ("polynomial", "table")))
        elif math.degrees(span) < MIN_SEGMENT_DEG:
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
    if linear:
        _check_travel(design)
    try:
        program = design.program
    except ProgramError as exc:
        path: tuple[str | int, ...] = ("motion",) if exc.index is None else ("motion", exc.index)
        if exc.field:
            path = (*path, *_split(exc.field))
        fail(path, exc.problem, show_got=False)
    _check_excursion(design, program)
    _check_steepness(design, program)
    if design.cam.type == "constant-breadth":
        _check_half_turn(design, program)
    return program


#: How far (a share of the top lift) a segment may stray below zero lift or above the program's
#: top between its ends: a table's spline through measured points swings a little past them.
EXCURSION_SHARE = 0.1


def _check_excursion(design: Design, program: MotionProgram) -> None:
    """A polynomial's or table's curve must stay near zero lift and the program's top lift (the
    largest lift at a segment's end) inside its segment, not only at its ends: boundary
    conditions or points can swing it far below zero (the follower would leave the cam) or far
    above (the cam would be larger than every check and fit assumes)."""
    import numpy as np

    segment, theta, m = program.segment_grid(math.radians(0.1))
    top = program.max_lift
    slack = EXCURSION_SHARE * top + 1e-9
    low, high = int(np.argmin(m[0])), int(np.argmax(m[0]))
    if m[0][low] >= -slack and m[0][high] <= top + slack:
        return
    k = low if m[0][low] < -slack else high
    show = (lambda v: f"{math.degrees(v):.6g}°") if design.follower.oscillating else mm
    where = f"s = {show(float(m[0][k]))} at θ = {math.degrees(float(theta[k])):.6g}°"
    problem = ("goes below zero lift inside the segment, by more than a tenth of the top lift "
               f"{show(top)}" if k == low else f"overshoots the program's top lift {show(top)} "
               "inside the segment by more than a tenth of it")
    fail(("motion", int(segment[k])), f"{problem} ({where}): change its boundary conditions "
         "or points", show_got=False)


#: Steepest motion camfab builds: the follower at most this many times as fast as the cam's
#: surface under it (a pressure angle of some 89.4°). Far past any working cam (the pressure
#: angle limit is some 30°), it keeps the curves countable: the pitch curve turns ever sharper
#: corners, and the points it needs grow as the square of the steepness.
MAX_STEEPNESS = 100.0


def _check_steepness(design: Design, program: MotionProgram) -> None:
    """No segment may move the follower more than :data:`MAX_STEEPNESS` times as fast as the
    cam's surface under it (a plate's prime circle and lift, a drum's surface, a linear cam's
    travel)."""
    cam, fol = design.cam, design.follower
    arm = (fol.arm_length or 0.0) if fol.oscillating else 1.0
    if cam.linear:
        surface = (cam.stroke or 0.0) / (2.0 * math.pi)  # travel per radian of the cycle
    elif cam.type == "cylindrical":
        surface = cam.radius or 0.0
    else:
        surface = (cam.base_radius or 0.0) + fol.trace_radius + program.max_lift * arm
    worst = max(program.segments, key=lambda seg: seg.peak(1))
    ratio = worst.peak(1) * arm / surface if surface > 0.0 else 0.0
    if ratio > MAX_STEEPNESS:
        fail(("motion", worst.index), f"is too steep to build: the follower moves {ratio:.3g} "
             f"times as fast as the cam's surface under it (at most {MAX_STEEPNESS:g}, a "
             f"pressure angle of {math.degrees(math.atan(MAX_STEEPNESS)):.4g}°); spread the "
             f"{worst.kind} over a {'longer travel' if cam.linear else 'larger angle'}",
             show_got=False)


def _check_travel(design: Design) -> None:
    """A linear cam's segments must cover its stroke exactly."""
    stroke = design.cam.stroke or 0.0
    motion = design.motion or ()
    total = sum(seg.travel or 0.0 for seg in motion)
    if not math.isclose(total, stroke, rel_tol=1e-9, abs_tol=1e-9):
        fail(("motion",), f"the segment travels sum to {mm(total)}; they must sum to the "
             f"stroke {mm(stroke)}", show_got=False)


def _check_half_turn(design: Design, program: MotionProgram) -> None:
    """A constant-breadth (or constant-diameter) cam's motion must satisfy s(θ + 180°) =
    h − s(θ): only the first half turn is free."""
    from camfab.motion.mirror import half_turn_mismatch

    theta, error = half_turn_mismatch(program)
    worst = int(abs(error).argmax())
    if abs(error[worst]) <= 1e-9 * max(program.max_lift, 1.0):
        return
    at = float(theta[worst])
    index = next(seg.index for seg in reversed(program.segments) if seg.start <= at + 1e-12)
    fail(("motion", index), "a constant-breadth cam's two faces (or rollers) stay the same "
         "distance apart, so the motion must satisfy s(θ + 180°) = h − s(θ); at "
         f"θ = {math.degrees(at) - 180.0:.6g}° and {math.degrees(at):.6g}° it is off by "
         f"{mm(abs(float(error[worst])))}", show_got=False,
         hint="give only the first 180° of the motion and camfab completes the rest")


def _check_cam_fit(design: Design, max_lift: float) -> None:
    cam, fol = design.cam, design.follower
    if cam.type != "cylindrical":
        return
    assert cam.radius is not None and cam.length is not None and cam.groove_depth is not None
    if cam.groove_depth > cam.radius - MIN_WALL_MM:
        fail(("cam", "groove_depth"), f"must leave at least {MIN_WALL_MM:g} mm below the groove "
             f"(radius {mm(cam.radius)})")
    if cam.bore is not None and cam.bore / 2 > cam.radius - cam.groove_depth - MIN_WALL_MM:
        fail(("cam", "bore"), "reaches the groove root "
             f"(root radius {mm(cam.radius - cam.groove_depth)})")
    half = (fol.roller_radius or 0.0) + fol.groove_clearance / 2
    needed = max_lift + 2 * half + 2 * MIN_WALL_MM
    if needed > cam.length:
        fail(("cam", "length"), f"the groove needs {mm(needed)} (lift {mm(max_lift)} + roller "
             f"and {MIN_WALL_MM:g} mm walls)")
    if cam.groove_start is not None:
        low = cam.groove_start - half
        high = cam.groove_start + max_lift + half
        if low < MIN_WALL_MM or high > cam.length - MIN_WALL_MM:
            fail(("cam", "groove_start"), f"puts the groove at z = {mm(low)} … {mm(high)}, "
                 f"outside the drum's length less {MIN_WALL_MM:g} mm walls")


def _check_oscillating(design: Design, max_swing: float) -> None:
    fol = design.follower
    if not fol.oscillating or not design.cam.plate:
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
                 f"|pivot_distance − arm_length| < {mm(rp)} < pivot_distance + arm_length")
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
        fail(("follower", "pivot_distance"), f"the cam would reach {mm(reach)} from its centre, "
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
        fail(("manufacturing", "kerf"), f"must be smaller than the bore ({mm(cam.bore)})")
    if cam.keyway is not None and kerf >= cam.keyway.width:
        fail(("manufacturing", "kerf"),
             f"must be smaller than the keyway's width ({mm(cam.keyway.width)})")


#: Cams that drive their follower both ways (positive drive): a spring has nothing to do.
POSITIVE_DRIVE = ("groove", "conjugate", "constant-breadth")


def _check_other(design: Design) -> None:
    if design.spring is not None and design.cam.type in POSITIVE_DRIVE:
        fail(("spring",), f"a {design.cam.type} cam drives its follower both ways (positive "
             "drive): it has no return spring; remove the spring section", show_got=False)
    limit = design.limits.pressure_angle
    if limit is not None and limit >= math.pi / 2:
        fail(("limits", "pressure_angle"), "must be below 90°")
    step_deg = math.degrees(design.table_step)
    count = 360.0 / step_deg
    if step_deg < MIN_TABLE_STEP_DEG:
        rows = 360.0 / MIN_TABLE_STEP_DEG
        fail(("table_step",), f"must be at least {MIN_TABLE_STEP_DEG:g}° ({rows:,.0f} rows of "
             "the motion table)")
    if step_deg > 30.0 or abs(count - round(count)) > 1e-6:
        fail(("table_step",), "must divide 360° and be at most 30°")
    if design.manufacturing.tolerance > 1.0:
        fail(("manufacturing", "tolerance"), "must be at most 1 mm (it is the largest allowed "
             "deviation of the exported curves)")
    if design.manufacturing.tolerance < MIN_TOLERANCE_MM:
        fail(("manufacturing", "tolerance"), f"must be at least {MIN_TOLERANCE_MM:g} mm: no "
             "machine holds less, and the exports' points grow without bound as it shrinks")
    if design.outputs is not None and len(set(design.outputs)) != len(design.outputs):
        fail(("outputs",), "lists an output twice")
    spring = design.spring
    if spring is not None and spring.preload is not None and spring.initial_compression is not None:
        fail(("spring", "initial_compression"), "give either preload or initial_compression, "
             "not both", show_got=False)


#: Largest cam size per unit of export tolerance. An STL's float32 coordinates round by up to
#: 3e-8 of the part's size, which stays under a tenth of the tolerance; and the exports' points
#: grow with the ratio (a cam 3 m across at 0.001 mm already takes seconds and gigabytes).
MAX_SIZE_PER_TOLERANCE = 3e6


def _check_size(design: Design, max_lift: float) -> None:
    """The tolerance must suit the cam's size (roughly its largest dimension: body, lift and
    follower)."""
    cam, fol = design.cam, design.follower
    body = max(v or 0.0 for v in (cam.base_radius, cam.radius, cam.length, cam.outer_radius,
                                  cam.stroke, cam.base_height, fol.roller_spacing))
    lift = max_lift * (fol.arm_length or 0.0) if fol.oscillating else max_lift
    size = body + lift + fol.trace_radius
    tolerance = design.manufacturing.tolerance
    if size > MAX_SIZE_PER_TOLERANCE * tolerance:
        least = size / MAX_SIZE_PER_TOLERANCE
        step = 10.0 ** (math.floor(math.log10(least)) - 1)
        least = math.ceil(least / step) * step  # rounded up to two digits
        fail(("manufacturing", "tolerance"), f"must be at least {least:.2g} mm for a cam of some "
             f"{size:.4g} mm: no file holds a finer one on a part that large (an STL's "
             f"coordinates round by {size * 3e-8:.2g} mm)")


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


def mm(value: float) -> str:
    """A length for a message: 6 significant digits and its unit (mm)."""
    return f"{value:.6g} mm"
