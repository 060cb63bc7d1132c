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
    from camfab.design.model import Design, Segment
    from camfab.motion.program import MotionProgram

#: Smallest wall of material camfab accepts between a groove or bore and the part's edge (mm):
#: thinner walls do not survive printing or machining.
MIN_WALL_MM = 1.0


def wall_need(bore: float = 0.0, depth: float = 0.0) -> float:
    """The least radius (mm) that leaves :data:`MIN_WALL_MM` of material beyond what reaches
    out from the axis: a bore of diameter *bore*, and *depth* further (a keyway's depth, or a
    drum's groove reaching in from its surface). The design file's rules and the sizing both
    judge a radius against it, so that a radius sized to it exactly passes the rules."""
    return bore / 2 + depth + MIN_WALL_MM


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


def check_rules(design: Design, sizing: frozenset[str] = frozenset()) -> None:
    """Raise :class:`RuleViolation` for the first broken rule: the rules every design has, and
    at their places those of its cam type (:class:`~camfab.design.cam_types.CamTypeSpec`).

    *sizing* names the keys (``cam.base_radius``, ``follower.offset``, ``cam.radius``) the
    design leaves to camfab (``auto``): they are missing, and the rules that need them wait for
    the sized design, which is checked in full."""
    _check_cam(design, sizing)
    _check_follower(design, sizing)
    if design.motion_target == "output":
        _check_polydyne_train(design)
    program = _check_motion(design, sizing)
    if not sizing:
        _check_oscillating(design, program.max_lift)
        design.cam.spec.check_fit(design, program)
    _check_swinging_face(design, program)
    _check_manufacturing(design)
    if design.machining is not None:
        design.machining.check(design, program, sizing)
    _check_other(design)
    _check_at_speed_ranges(design)
    _check_train(design)
    _check_at_speed(design)
    _check_size(design, program.max_lift)


def _check_cam(design: Design, sizing: frozenset[str]) -> None:
    cam, spec = design.cam, design.cam.spec
    for key in spec.required:
        if getattr(cam, key) is None and f"cam.{key}" not in sizing:
            fail(("cam", key), f"required for a {cam.type} cam", show_got=False)
    tolerance = design.manufacturing.tolerance
    if cam.base_radius is not None and cam.base_radius <= tolerance:
        fail(("cam", "base_radius"), f"must be larger than the export tolerance "
             f"({mm(tolerance)}): a smaller cam cannot be drawn within it")
    if cam.groove_depth is not None and cam.groove_depth <= tolerance:
        fail(("cam", "groove_depth"), f"must be larger than the export tolerance "
             f"({mm(tolerance)}): a shallower groove cannot be cut to it")
    spec.check_cam(design)
    # a radius left to the sizing is sized to keep the bore and keyway inside
    if spec.bore_within is not None and f"cam.{spec.bore_within}" not in sizing:
        rb = getattr(cam, spec.bore_within) or 0.0
        if cam.bore is not None and rb < wall_need(cam.bore):
            fail(("cam", "bore"),
                 f"leaves less than {MIN_WALL_MM:g} mm of material inside the base circle "
                 f"(bore radius {mm(cam.bore / 2)} vs base radius {mm(rb)})")
    if cam.keyway is not None:
        if cam.bore is None:
            fail(("cam", "keyway"), "a keyway needs a bore", show_got=False)
        assert cam.bore is not None
        if cam.keyway.width >= cam.bore:
            fail(("cam", "keyway", "width"), f"must be narrower than the bore ({mm(cam.bore)})")
        outer = (None if spec.keyway_within is None or f"cam.{spec.keyway_within}" in sizing
                 else getattr(cam, spec.keyway_within))
        if outer is not None and outer < wall_need(cam.bore, cam.keyway.depth):
            fail(("cam", "keyway", "depth"),
                 f"cuts to within {MIN_WALL_MM:g} mm of the cam's edge")


def _check_follower(design: Design, sizing: frozenset[str]) -> None:
    cam, fol, spec = design.cam, design.follower, design.cam.spec
    allowed = spec.followers
    if fol.type not in allowed:
        fail(("follower", "type"), f"a {cam.type} cam takes a {' or '.join(allowed)} follower",
             allowed=", ".join(allowed), hint=spec.hint_for(fol.type))
    if spec.translating_only and fol.oscillating:
        fail(("follower", "motion"), f"a {cam.type} cam drives a translating follower",
             allowed="translating")
    spec.check_follower(design)
    if fol.type == "roller" and fol.roller_radius is None:
        fail(("follower", "roller_radius"), "required for a roller follower", show_got=False)
    if fol.type == "mushroom" and fol.face_radius is None:
        fail(("follower", "face_radius"), "required for a mushroom follower", show_got=False)
    if fol.oscillating:
        for key in ("pivot_distance", "arm_length"):
            if getattr(fol, key) is None:
                fail(("follower", key), "required for an oscillating follower", show_got=False)
    elif spec.disc_curves and fol.type != "flat" and not sizing:
        rp = (cam.base_radius or 0.0) + fol.trace_radius
        if abs(fol.offset) >= rp:
            fail(("follower", "offset"),
                 f"|offset| must be smaller than the prime circle radius {mm(rp)}")


def _check_motion(design: Design, sizing: frozenset[str]) -> MotionProgram:
    from camfab.motion.program import ProgramError

    spec = design.cam.spec
    if spec.shaped:
        if design.motion is not None:
            fail(("motion",), f"a {design.cam.type} cam's shape defines the motion: remove the "
                 "motion list", show_got=False)
        return design.program
    if design.motion is None:
        fail(("motion",), "required (a list of rise, dwell and return segments)", show_got=False)
    if len(design.motion) > MAX_SEGMENTS:
        fail(("motion",), f"has {len(design.motion):,} segments; camfab builds at most "
             f"{MAX_SEGMENTS:,}", show_got=False)
    for i, seg in enumerate(design.motion):
        if getattr(seg, spec.span) is None:
            fail(("motion", i, spec.span), "required", show_got=False)
        spec.check_span(design, i, seg)
        if seg.kind == "dwell":
            continue
        if seg.law is None:
            fail(("motion", i, "law"), f"required for a {seg.kind}", show_got=False,
                 allowed=_law_names())
        _check_law_keys(i, seg)
        if seg.law == "table" and not seg.points:
            fail(("motion", i, "points"), "a table law needs points (or a csv file)",
                 show_got=False)
        if seg.lift is None and seg.kind == "rise" and seg.law != "table":
            fail(("motion", i, "lift"), "required for a rise", show_got=False)
    spec.check_motion(design)
    try:
        if design.motion_target == "output":
            _check_polydyne_laws(design)
        program = design.program
    except ProgramError as exc:
        path: tuple[str | int, ...] = ("motion",) if exc.index is None else ("motion", exc.index)
        if exc.field:
            path = (*path, *_split(exc.field))
        fail(path, exc.problem, show_got=False)
    _check_excursion(design, program)
    if not sizing:
        _check_steepness(design, program)
    spec.check_program(design, program)
    return program


def _check_polydyne_train(design: Design) -> None:
    """A polydyne cam (``motion_target: output``) needs a motion list and the elastic follower
    train it is computed through: the follower's stiffness and mass and the cam's speed."""
    if design.motion is None:
        fail(("motion_target",), f"a {design.cam.type} cam's motion comes from its shape: only "
             "a motion list can describe the follower's mass (motion_target: output)")
    if design.follower.stiffness is None:
        fail(("motion_target",), "a polydyne cam is computed through the elastic follower "
             "train: give follower.stiffness (N/mm), follower.mass (kg) and cam.speed_rpm")
    _check_at_speed_ranges(design)
    _check_train(design)


#: The laws a polydyne cam's output motion may follow, as the refusal names them.
POLYDYNE_LAWS = "polynomial-56789 or spline (of order 6 or more)"


def _check_polydyne_laws(design: Design) -> None:
    """Under ``motion_target: output`` the cam's acceleration carries the output's fourth
    derivative: every law must have its first four derivatives continuous, at its joints too."""
    from camfab.motion.polydyne import rough_joints

    for index, why in rough_joints(design.output_program):
        fail(("motion", index, "law"), f"{why}: a polydyne cam's acceleration carries the "
             f"follower's fourth derivative (motion_target: output), so its laws need four "
             f"continuous derivatives at every joint: use {POLYDYNE_LAWS}", show_got=False)


#: The segment keys that belong to some laws (the others take them as not given).
LAW_KEYS = ("blend", "start", "end", "points", "order", "controls")


def _check_law_keys(index: int, segment: Segment) -> None:
    """A key of a law's own (a blend, conditions, points, a spline's order and controls) only
    on a segment of a law that takes it (:data:`camfab.motion.laws.LAWS`' params)."""
    from camfab.motion.laws import LAW_INFO, laws_taking

    takes = LAW_INFO[segment.law].params if segment.law in LAW_INFO else ()
    for key in LAW_KEYS:
        if getattr(segment, key) is not None and key not in takes:
            fail(("motion", index, key), f"only {laws_taking(key)} {key}",
                 show_got=key == "blend")


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
    travel: :meth:`~camfab.design.cam_types.CamTypeSpec.surface`)."""
    fol, spec = design.follower, design.cam.spec
    arm = (fol.arm_length or 0.0) if fol.oscillating else 1.0
    surface = spec.surface(design, program)
    worst = max(program.segments, key=lambda seg: seg.peak(1))
    ratio = worst.peak(1) * arm / surface if surface > 0.0 else 0.0
    if ratio > MAX_STEEPNESS:
        fail(("motion", worst.index), f"is too steep to build: the follower moves {ratio:.3g} "
             f"times as fast as the cam's surface under it (at most {MAX_STEEPNESS:g}, a "
             f"pressure angle of {math.degrees(math.atan(MAX_STEEPNESS)):.4g}°); spread the "
             f"{worst.kind} over a {'longer travel' if spec.span == 'travel' else 'larger angle'}",
             show_got=False)


def _check_oscillating(design: Design, max_swing: float) -> None:
    fol = design.follower
    if not fol.oscillating or not design.cam.spec.disc_curves:
        return
    broken = oscillating_fit(FollowerGeometry.from_design(design), design.cam.base_radius or 0.0,
                             max_swing)
    if broken is not None:
        key, problem = broken
        fail(("follower", key), problem)


def oscillating_fit(fol: FollowerGeometry, rb: float, max_swing: float) -> tuple[str, str] | None:
    """Whether an oscillating follower *fol* fits a plate cam of base radius *rb* (mm) through a
    swing of *max_swing* (rad): None, or the follower key to blame and the problem. The arm must
    reach the prime circle (a flat face: touch the base circle), stay short of 180° from the line
    of centres (a flat face: of 90°, where its distance from the cam centre stops growing), and
    keep the pivot outside the cam."""
    a, arm = fol.pivot_distance, fol.arm_length
    if fol.flat:
        ratio = (rb + fol.face_offset) / a
        if not 0.0 < ratio < 1.0:
            return ("face_offset", "the face line cannot touch the base circle from this pivot: "
                    f"(base radius + face_offset)/pivot_distance = {ratio:.4g} must lie in (0, 1)")
    else:
        rp = rb + fol.radius
        if not abs(a - arm) < rp < a + arm:
            return ("arm_length", f"the arm cannot reach the prime circle: need "
                    f"|pivot_distance − arm_length| < {mm(rp)} < pivot_distance + arm_length")
    psi0 = fol.rest_position(rb)
    if fol.flat and psi0 + max_swing >= math.pi / 2:
        # past 90° the face line's distance from the cam centre, a·sin Ψ − f, falls as Ψ grows:
        # the contact passes behind the pivot's foot and the cam would drive the face back
        return ("pivot_distance", f"the face starts at {math.degrees(psi0):.4g}° from the line "
                f"of centres (sin ψ₀ = (base radius + face_offset)/pivot_distance) and swings "
                f"{math.degrees(max_swing):.4g}°: past 90° the cam cannot drive it (the contact "
                "passes behind the pivot); a longer pivot_distance, or a smaller base radius, "
                "face_offset or swing, keeps it below")
    if psi0 + max_swing >= math.pi:
        return ("arm_length", f"the arm starts at {math.degrees(psi0):.4g}° from the line of "
                f"centres and swings {math.degrees(max_swing):.4g}°: it would pass 180°")
    # the cam's largest radius: the face line's farthest distance from the cam centre, or the
    # trace point's farthest distance less the roller radius; the pivot must lie beyond it
    top = psi0 + max_swing
    if fol.flat:
        reach = a * math.sin(top) - fol.face_offset
    else:
        reach = math.sqrt(a * a + arm * arm - 2 * a * arm * math.cos(top)) - fol.radius
    if reach >= a:
        return ("pivot_distance", f"the cam would reach {mm(reach)} from its centre, past the "
                "pivot: the pivot must lie outside the cam")
    return None


#: An oscillating flat face touches the cam at l = a·cos Ψ/(1 + σψ′) from the pivot (THEORY §B):
#: the face must turn slower than the cam, 1 + σψ′ above this, or contact runs off toward infinity.
MIN_FACE_TURN_MARGIN = 0.05


def _check_swinging_face(design: Design, program: MotionProgram) -> None:
    import numpy as np

    fol = design.follower
    if not (fol.oscillating and fol.type == "flat" and design.cam.spec.disc_curves):
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


def _check_other(design: Design) -> None:
    if design.spring is not None and design.cam.spec.positive_drive:
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
    if design.outputs is not None and "step" in design.outputs and not step_available():
        fail(("outputs",), STEP_MISSING, show_got=False)
    if design.outputs is not None and "gcode" in design.outputs and design.machining is None:
        fail(("outputs",), GCODE_UNSET, show_got=False)
    spring = design.spring
    if spring is not None and spring.preload is not None and spring.initial_compression is not None:
        fail(("spring", "initial_compression"), "give either preload or initial_compression, "
             "not both", show_got=False)


#: The least values of the keys of a cam at its speed, far below any real cam's and its
#: follower's, yet where the follower train's and the rigid model's numbers stay finite (a
#: follower of 1e-300 kg or a cam of 1e-300 rpm puts them past floating point): the speed, a
#: turn in some 11.6 days (rpm); the follower's mass, a milligram (kg); the follower train's
#: stiffness and the spring's rate, 1 N/m (N/mm); a roller bearing's load rating, a newton
#: (N), where catalogues start at hundreds. Within them and the largest values each quantity
#: takes (:mod:`camfab.design.units`), the follower train's natural frequency lies between
#: 1e-8 and 1e13 times the cam's, all of which camfab computes.
MIN_AT_SPEED = {("cam", "speed_rpm"): (1e-3, "rpm"), ("follower", "mass"): (1e-6, "kg"),
                ("follower", "stiffness"): (1e-3, "N/mm"), ("spring", "rate"): (1e-3, "N/mm"),
                ("follower", "roller_load_rating"): (1.0, "N")}


def _check_at_speed_ranges(design: Design) -> None:
    """Each key of the cam at its speed at least its least value (:data:`MIN_AT_SPEED`)."""
    for (section, key), (least, unit) in MIN_AT_SPEED.items():
        part = getattr(design, section)
        value = None if part is None else getattr(part, key)
        if value is not None and value < least:
            fail((section, key), f"must be at least {least:g} {unit}: a smaller one is no real "
                 "cam's, and its forces and vibration leave floating point")


#: How near a whole number the undamped follower train's natural frequency may come to a
#: multiple of the cam's turning frequency before camfab refuses it as resonance: nearer, its
#: steady state would be some 1e6 times the lift.
RESONANCE_SHARE = 1e-6


def _check_train(design: Design) -> None:
    """An elastic follower train (``follower.stiffness``) needs the follower's mass and the
    cam's speed; its damping ratio is below 1 (the model is of a train that rings), with the
    spring's own damping too; an undamped train may not resonate with the cam."""
    fol, spring, omega = design.follower, design.spring, design.cam.omega
    if fol.stiffness is None:
        if fol.damping_ratio is not None:
            fail(("follower", "damping_ratio"), "only an elastic follower train has a damping "
                 "ratio: give follower.stiffness (N/mm) too")
        return
    if fol.mass is None:
        fail(("follower", "stiffness"), "an elastic follower train needs the follower's mass: "
             "give follower.mass (kg)", show_got=False)
    if omega is None:
        fail(("follower", "stiffness"), "an elastic follower train needs the cam's speed: give "
             "cam.speed_rpm", show_got=False)
    assert fol.mass is not None and omega is not None
    zeta = fol.train_damping_ratio
    if zeta >= 1.0:
        fail(("follower", "damping_ratio"), "must be below 1: camfab's elastic model is of a "
             "follower train that rings (ζ of 0.02–0.1 is usual); at 1 and above it does not "
             "vibrate, and the rigid model (no stiffness) says what it does")
    # the trace point's equivalents, as in the rigid model: N/m and kg
    total = (fol.stiffness + (spring.rate if spring is not None else 0.0)) * 1000.0
    damping = spring.damping if spring is not None else 0.0
    total_zeta = zeta + damping / (2.0 * math.sqrt(fol.mass * total))
    if total_zeta >= 1.0:
        fail(("spring", "damping"), f"with the follower train's damping ratio {zeta:.4g}, makes "
             f"the train critically damped or more (ζ = {total_zeta:.4g}); camfab's elastic "
             "model is of a train that rings: lower the damping")
    if total_zeta == 0.0:
        order = math.sqrt(total / fol.mass) / omega
        if abs(order - round(order)) <= RESONANCE_SHARE * order:
            fail(("follower", "stiffness"), f"makes the undamped follower train resonate: its "
                 f"natural frequency is {round(order)} times the cam's at "
                 f"{design.cam.speed_rpm:.6g} rpm, and its vibration grows without bound; give a "
                 "damping_ratio, or change the stiffness, the mass or the speed")


def _check_at_speed(design: Design) -> None:
    """A limit of the cam at its speed must be one camfab can check: the contact stress of a
    follower that has one (not a knife's) over a contact of known length, a roller's bearing
    life with its load rating; both on the force on the follower, which needs its mass, the
    cam's speed and a spring (or a cam that holds the follower both ways)."""
    fol, limits = design.follower, design.limits
    if fol.roller_bearing is not None and fol.roller_load_rating is None:
        fail(("follower", "roller_bearing"), "only with follower.roller_load_rating (the "
             "bearing's basic dynamic load rating C, from its catalogue)")
    rating = "follower.roller_load_rating (the bearing's basic dynamic load rating C, from its " \
             "catalogue)"
    if limits.roller_life is not None:
        if fol.type != "roller":
            fail(("limits", "roller_life"), f"only a roller has a bearing life (this follower "
                 f"is a {fol.type})")
        if fol.roller_load_rating is None:
            fail(("limits", "roller_life"), f"needs {rating}")
    if limits.contact_stress is not None:
        if fol.type == "knife":
            fail(("limits", "contact_stress"), "a knife edge's contact has no area, so Hertz "
                 "gives it no stress to check")
        if fol.type != "mushroom" and design.contact_length is None:
            roller = " or follower.roller_length" if fol.type == "roller" else ""
            fail(("limits", "contact_stress"), f"needs the contact's length: give "
                 f"cam.{design.cam.spec.contact_extent}{roller}")
    for key in ("contact_stress", "roller_life"):
        if getattr(limits, key) is None:
            continue
        if fol.mass is None:
            fail(("limits", key), "needs the force on the follower: give follower.mass (kg)")
        if design.cam.speed_rpm is None:
            fail(("limits", key), "needs the force on the follower: give cam.speed_rpm")
        if design.spring is None and not design.cam.spec.two_sided:
            fail(("limits", key), "needs the force on the follower: give the spring that holds "
                 "it on the cam")


#: Largest cam size per unit of export tolerance. An STL's float32 coordinates round by up to
#: 3e-8 of the part's size, which stays under a tenth of the tolerance; and the exports' points
#: grow with the ratio (a cam 3 m across at 0.001 mm already takes seconds and gigabytes).
MAX_SIZE_PER_TOLERANCE = 3e6


def _check_size(design: Design, max_lift: float) -> None:
    """The tolerance must suit the cam's size (roughly its largest dimension: body, lift and
    follower)."""
    cam, fol = design.cam, design.follower
    body = max(v or 0.0 for v in (cam.base_radius, cam.radius, cam.length, cam.outer_radius,
                                  cam.stroke, cam.base_height, cam.width,
                                  fol.roller_spacing))
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


#: What asking for a machining program without the tool and feeds is told.
GCODE_UNSET = ("gcode needs the tool and feeds: a machining section (tool_diameter, feed, ...) "
               "in the design, or a shop's settings file (camfab build --machining FILE)")
#: What asking for STEP without the optional extra is told.
STEP_MISSING = ("step needs camfab's optional STEP extra (the OpenCASCADE bindings): "
                "pip install 'camfab[step]'")


def step_available() -> bool:
    """Whether the OpenCASCADE bindings of the ``step`` extra are installed (not imported)."""
    from importlib.util import find_spec

    return find_spec("OCP") is not None


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
