"""The cam types of the design file, one row each: the one registry keyed by ``cam.type``.

A row (:class:`CamTypeSpec`) says what the design file takes for its type — the keys of its
``cam:`` section and those it requires, the followers it drives and the keys their section
adds, how its motion is given (angles, travels, or the cam's own shape), which radius a bore
and a keyway must stay inside, and whether it drives its follower both ways — holds
the design file's rules that belong to that type alone, and names the module of
:mod:`camfab.kinds` that builds it (imported only when a design of the type is built). The
design file's rules (:mod:`camfab.design.rules`) ask the row; none of them names a type.

Lengths are millimetres and angles radians, as in the design model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Literal

from camfab.design.rules import (
    MIN_NOSE_SHARE,
    MIN_SEGMENT_DEG,
    MIN_WALL_MM,
    fail,
    mm,
    wall_need,
)

if TYPE_CHECKING:
    from camfab.curves.shaped import ShapedCam
    from camfab.design.model import Cam, Design, Segment
    from camfab.motion.program import MotionProgram

#: The keys every rotating cam's section takes, before its type's own.
_TURNING = ("type", "rotation", "speed_rpm")
#: The keys of a plate's blank: its thickness, the bore and its keyway.
_BLANK = ("thickness", "bore", "keyway")
#: The follower contact shapes a disc cam drives.
_ANY_FOLLOWER = ("knife", "roller", "flat", "mushroom")


@dataclass(frozen=True)
class CamTypeSpec:
    """What the design file takes for one cam type, its rules, and the kind that builds it.

    The methods are the design rules of the type alone, each called at its place among the
    design file's rules (:func:`camfab.design.rules.check_rules`) and raising
    :class:`~camfab.design.rules.RuleViolation`; the defaults here check nothing more.
    """

    #: The ``cam.type`` of the design file.
    name: str
    #: The module of :mod:`camfab.kinds` implementing it, as ``module`` (its ``KIND``) or
    #: ``module:NAME`` for a module holding more than one kind.
    kind: str
    #: The keys its ``cam:`` section takes, in the order a message lists them.
    cam_keys: tuple[str, ...]
    #: The keys of its ``cam:`` section it cannot do without.
    required: tuple[str, ...]
    #: The follower contact shapes it drives.
    followers: tuple[str, ...]
    #: Why it refuses a follower it cannot drive, where the list alone does not say:
    #: (follower type, reason) pairs.
    follower_hints: tuple[tuple[str, str], ...] = ()
    #: The keys its follower section takes beyond the follower's own, for a translating and
    #: for an oscillating follower.
    translating_keys: tuple[str, ...] = ()
    oscillating_keys: tuple[str, ...] = ()
    #: True when it drives a translating follower only.
    translating_only: bool = False
    #: True when it drives its follower both ways (positive drive): a spring has nothing to do.
    positive_drive: bool = False
    #: True when it holds its follower on both sides of its motion (a groove's walls, a pair's two
    #: cams, a drum's or a globoid's flanks), spring or none: without a spring the force on the
    #: follower is its inertia alone, and where the force changes sign the follower crosses to
    #: the other side (it cannot leave the cam).
    two_sided: bool = False
    #: The key of the cam's extent across the follower's motion that a line contact spans (with a
    #: roller's length): a plate's ``thickness``, a groove's ``groove_depth``; None where the
    #: cam's geometry gives it (a globoid's roller inside its groove).
    contact_extent: str | None = "thickness"
    #: True for a plate turning about its centre with a disc cam's exact curves: the follower's
    #: line must cross its prime circle, an oscillating arm must reach it.
    disc_curves: bool = False
    #: True when the cam's shape defines the motion (THEORY §D): the design has no motion list.
    shaped: bool = False
    #: What a motion segment gives its length in: ``"angle"`` of cam rotation, or ``"travel"``
    #: along a cam that slides.
    span: Literal["angle", "travel"] = "angle"
    #: The key of the radius a bore must leave a wall of material inside (the base circle of a
    #: plate), or None where the bore is checked otherwise or there is none.
    bore_within: str | None = "base_radius"
    #: The key of the radius a keyway must stop a wall of material short of, or None.
    keyway_within: str | None = "base_radius"
    #: The keys camfab sizes when the design gives ``auto`` (``section.key``): the radius the
    #: type is sized by, and a translating follower's offset.
    auto_keys: tuple[str, ...] = ()
    #: The export tolerance (mm) when the design gives none, where the type's own differs from
    #: the design file's (:data:`camfab.design.model.DEFAULT_TOLERANCE_MM`).
    default_tolerance: float | None = None
    #: How its machining program cuts it (:mod:`camfab.machining`): a plate milled round its
    #: contours on three axes, a drum's groove on a rotary A axis, a globoid's on A and a
    #: swinging B.
    machining: Literal["plate", "drum", "globoid"] = "plate"

    def hint_for(self, follower: str) -> str | None:
        """Why this type refuses the *follower* type, where the list alone does not say."""
        return dict(self.follower_hints).get(follower)

    def follower_keys(self, oscillating: bool) -> tuple[str, ...]:
        """The keys its follower section takes beyond the follower's own."""
        return self.oscillating_keys if oscillating else self.translating_keys

    def check_cam(self, design: Design) -> None:
        """Rules of its ``cam:`` section, after its required keys are there."""

    def check_follower(self, design: Design) -> None:
        """Rules of its follower, after the follower's type and motion suit the cam."""

    def check_span(self, design: Design, index: int, segment: Segment) -> None:
        """Rules of one motion segment's length (an angle: not vanishingly small)."""
        if math.degrees(segment.angle or 0.0) < MIN_SEGMENT_DEG:
            fail(("motion", index, "angle"), f"must be at least {MIN_SEGMENT_DEG:g}°")

    def check_motion(self, design: Design) -> None:
        """Rules of the motion list as a whole, before its program is built."""

    def check_program(self, design: Design, program: MotionProgram) -> None:
        """Rules of the motion program once built."""

    def check_fit(self, design: Design, program: MotionProgram) -> None:
        """Rules of the follower's fit to the cam over the whole motion."""

    def surface(self, design: Design, program: MotionProgram) -> float:
        """How far the cam's surface under the follower moves per radian of the cycle (mm): a
        plate's prime circle and lift."""
        cam, fol = design.cam, design.follower
        arm = (fol.arm_length or 0.0) if fol.oscillating else 1.0
        return (cam.base_radius or 0.0) + fol.trace_radius + program.max_lift * arm

    def program(self, design: Design) -> MotionProgram:
        """The motion program s(θ) of the design's motion list."""
        from camfab.motion.program import build_program

        assert design.motion is not None, "the design rules require a motion list"
        return build_program(list(design.motion))  # type: ignore[arg-type]

    def shape(self, cam: Cam) -> ShapedCam:
        """The dimensions and outline of a cam whose shape defines its motion."""
        raise TypeError(f"a {self.name} cam's motion is not defined by its shape")


class _Shaped(CamTypeSpec):
    """A cam drawn from its shape (circular-arc, tangent): the shape defines the motion, and
    the follower moves along a line through the cam centre."""

    #: The two keys either of which completes the shape: (first, second).
    either: ClassVar[tuple[str, str]] = ("nose_radius", "flank_angle")

    def check_cam(self, design: Design) -> None:
        """The dimensions must make one such cam (nose, flanks and base circle all there)."""
        from camfab.curves.shaped import ShapeError

        cam = design.cam
        first, second = self.either
        if getattr(cam, first) is None and getattr(cam, second) is None:
            fail(("cam", first), f"required for a {self.name} cam (or {second})",
                 show_got=False)
        try:
            shape = design.shape
        except ShapeError as exc:
            fail(("cam", exc.field), exc.problem)
        size = shape.base_radius + shape.lift
        if shape.nose_radius < MIN_NOSE_SHARE * size:
            other = first if second == "nose_radius" else second
            given = "nose_radius" if cam.nose_radius is not None else other
            fail(("cam", given), f"gives a nose of radius {mm(shape.nose_radius)}: it must be "
                 f"at least {MIN_NOSE_SHARE:g} of the cam's radius ({mm(size)}), or rounding "
                 "loses which way the nose faces")

    def check_follower(self, design: Design) -> None:
        if design.follower.offset != 0.0:
            fail(("follower", "offset"), f"a {self.name} cam's follower moves along a line "
                 "through the cam centre: the offset must be 0")

    def program(self, design: Design) -> MotionProgram:
        """The follower's motion on the cam's outline, piece by piece in closed form."""
        from camfab.curves.contact import contact_program
        from camfab.curves.follower import FollowerGeometry

        fol = FollowerGeometry.from_design(design)
        return contact_program(design.shape.pieces(), fol.radius, fol.flat)



class _CircularArc(_Shaped):
    """The circular-arc cam: base circle, two flank arcs and a nose arc."""

    def shape(self, cam: Cam) -> ShapedCam:
        from camfab.curves.shaped import ShapedCam

        assert cam.base_radius is not None and cam.lift is not None
        assert cam.lift_angle is not None
        return ShapedCam.circular_arc(cam.base_radius, cam.lift, cam.lift_angle,
                                      cam.nose_radius, cam.flank_angle, cam.top_dwell)


class _Tangent(_Shaped):
    """The tangent cam: base circle, two straight flanks and a nose arc."""

    either: ClassVar[tuple[str, str]] = ("lift_angle", "nose_radius")

    def shape(self, cam: Cam) -> ShapedCam:
        from camfab.curves.shaped import ShapedCam

        assert cam.base_radius is not None and cam.lift is not None
        return ShapedCam.tangent(cam.base_radius, cam.lift, cam.lift_angle, cam.nose_radius,
                                 cam.top_dwell)


class _Drum(CamTypeSpec):
    """The cylindrical (drum) cam: a groove round a drum, its bore checked against the groove's
    root."""


    def surface(self, design: Design, program: MotionProgram) -> float:
        """The drum's surface."""
        return design.cam.radius or 0.0

    def check_fit(self, design: Design, program: MotionProgram) -> None:
        """The groove must leave walls below it and at the drum's ends, and the bore must stop
        short of its root."""
        cam, fol = design.cam, design.follower
        max_lift = program.max_lift
        assert cam.radius is not None and cam.length is not None
        assert cam.groove_depth is not None
        if cam.radius < wall_need(depth=cam.groove_depth):
            fail(("cam", "groove_depth"), f"must leave at least {MIN_WALL_MM:g} mm below the "
                 f"groove (radius {mm(cam.radius)})")
        if cam.bore is not None and cam.radius < wall_need(cam.bore, cam.groove_depth):
            fail(("cam", "bore"), "reaches the groove root "
                 f"(root radius {mm(cam.radius - cam.groove_depth)})")
        half = (fol.roller_radius or 0.0) + fol.groove_clearance / 2
        needed = max_lift + 2 * half + 2 * MIN_WALL_MM
        if needed > cam.length:
            fail(("cam", "length"), f"the groove needs {mm(needed)} (lift {mm(max_lift)} + "
                 f"roller and {MIN_WALL_MM:g} mm walls)")
        if cam.groove_start is not None:
            low = cam.groove_start - half
            high = cam.groove_start + max_lift + half
            if low < MIN_WALL_MM or high > cam.length - MIN_WALL_MM:
                fail(("cam", "groove_start"), f"puts the groove at z = {mm(low)} … {mm(high)}, "
                     f"outside the drum's length less {MIN_WALL_MM:g} mm walls")


class _Groove(CamTypeSpec):
    """The face-groove cam: a groove milled into a plate's face holds the roller both ways."""


    def check_cam(self, design: Design) -> None:
        """The groove is a pocket: it must leave a floor under it."""
        cam = design.cam
        assert cam.thickness is not None and cam.groove_depth is not None
        if cam.groove_depth > cam.thickness - MIN_WALL_MM:
            fail(("cam", "groove_depth"), f"must leave at least {MIN_WALL_MM:g} mm of floor "
                 f"under the groove (thickness {mm(cam.thickness)})")

    def check_fit(self, design: Design, program: MotionProgram) -> None:
        """The roller (its radius plus half the clearance) must reach the prime circle from an
        oscillating follower's pivot. (That the plate's ``outer_radius`` leaves a wall of
        material outside the groove takes the groove's geometry: the groove kind checks it.)"""
        cam, fol = design.cam, design.follower
        half = (fol.roller_radius or 0.0) + fol.groove_clearance / 2
        rp = (cam.base_radius or 0.0) + half
        if fol.oscillating:
            a, arm = fol.pivot_distance or 0.0, fol.arm_length or 0.0
            if not abs(a - arm) < rp < a + arm:
                fail(("follower", "arm_length"), f"the arm cannot reach the prime circle of the "
                     f"groove's centre line: need |pivot_distance − arm_length| < {mm(rp)} < "
                     "pivot_distance + arm_length")


class _Conjugate(CamTypeSpec):
    """The conjugate pair: two plates on one shaft, each driving one roller of the follower."""


    def check_follower(self, design: Design) -> None:
        """The second roller's place: along the follower, or the bell-crank's second arm."""
        fol = design.follower
        if not fol.oscillating and fol.roller_spacing is None:
            fail(("follower", "roller_spacing"), "required for a conjugate cam (the distance "
                 "between the two rollers' centres along the follower)", show_got=False)
        if fol.oscillating and fol.arm_angle is None:
            fail(("follower", "arm_angle"), "required for an oscillating conjugate cam (the "
                 "angle at the pivot between the bell-crank's two arms)", show_got=False)


class _ConstantBreadth(CamTypeSpec):
    """The constant-breadth (or constant-diameter) cam: two faces or two rollers on opposite
    sides, the same distance apart all round; only the first half turn of the motion is free."""


    def check_follower(self, design: Design) -> None:
        fol = design.follower
        if fol.type == "roller" and fol.offset != 0.0:
            fail(("follower", "offset"), "the two rollers of a constant-diameter cam lie on a "
                 "line through the cam centre: the offset must be 0")

    def check_program(self, design: Design, program: MotionProgram) -> None:
        """The motion must satisfy s(θ + 180°) = h − s(θ)."""
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

    def program(self, design: Design) -> MotionProgram:
        """The whole turn; a motion list of the first half turn only is completed by the
        mirror image."""
        assert design.motion is not None, "the design rules require a motion list"
        specs = list(design.motion)
        if math.isclose(sum(seg.angle or 0.0 for seg in specs), math.pi, abs_tol=1e-9):
            from camfab.motion.mirror import half_turn

            return half_turn(specs)  # type: ignore[arg-type]
        return super().program(design)


class _Linear(CamTypeSpec):
    """The linear (translating, wedge) cam: a plate sliding along X; its segments give their
    travel along the cam, which sum to its stroke."""


    def check_cam(self, design: Design) -> None:
        """The plate must stand under the follower at its lowest."""
        cam, fol = design.cam, design.follower
        assert cam.base_height is not None
        low = cam.base_height - fol.trace_radius
        if low < MIN_WALL_MM:
            fail(("cam", "base_height"), f"leaves {mm(low)} of plate under the follower at zero "
                 f"lift (base height less the roller radius); at least {MIN_WALL_MM:g} mm is "
                 "needed")

    def check_follower(self, design: Design) -> None:
        if design.follower.offset != 0.0:
            fail(("follower", "offset"), "a linear cam's follower line is where the travel "
                 "starts: the offset must be 0 (a dwell shifts the motion along the cam)")

    def check_span(self, design: Design, index: int, segment: Segment) -> None:
        """A travel takes the standard laws, and a spline at rest at its ends."""
        if segment.law in ("polynomial", "table"):
            from camfab.motion.laws import LAW_NAMES

            fail(("motion", index, "law"), "a linear cam's segments take the standard laws (a "
                 "polynomial's or a table's conditions and points are per cam angle)",
                 allowed=", ".join(n for n in LAW_NAMES if n not in ("polynomial", "table")))
        for key in ("start", "end"):
            if segment.law == "spline" and getattr(segment, key) is not None:
                fail(("motion", index, key), "a linear cam's spline takes no end conditions "
                     "(they are per cam angle): it starts and ends at rest", show_got=False)

    def check_motion(self, design: Design) -> None:
        """The segments must cover the stroke exactly."""
        stroke = design.cam.stroke or 0.0
        motion = design.motion or ()
        total = sum(seg.travel or 0.0 for seg in motion)
        if not math.isclose(total, stroke, rel_tol=1e-9, abs_tol=1e-9):
            fail(("motion",), f"the segment travels sum to {mm(total)}; they must sum to the "
                 f"stroke {mm(stroke)}", show_got=False)

    def surface(self, design: Design, program: MotionProgram) -> float:
        """The travel per radian of the cycle."""
        return (design.cam.stroke or 0.0) / (2.0 * math.pi)

    def program(self, design: Design) -> MotionProgram:
        """The motion along the stroke: a travel is that share of a cycle."""
        from camfab.motion.program import build_program

        assert design.motion is not None, "the design rules require a motion list"
        stroke = design.cam.stroke or 1.0
        specs = [seg.model_copy(update={"angle": 2.0 * math.pi * (seg.travel or 0.0) / stroke})
                 for seg in design.motion]
        return build_program(specs)  # type: ignore[arg-type]


class _Globoidal(CamTypeSpec):
    """The globoidal cam: a groove round a globoid (hourglass or barrel) drives a roller on an
    oscillating arm whose pivot axis crosses the cam axis at right angles, apart from it
    (THEORY §H). These rules need no geometry; the kind checks the groove in the blank."""

    def check_follower(self, design: Design) -> None:
        fol = design.follower
        if not fol.oscillating:
            fail(("follower", "motion"), "a globoidal cam drives an oscillating follower (its "
                 "arm swings about a pivot axis square to the cam axis)", allowed="oscillating")
        if fol.roller_length is None:
            fail(("follower", "roller_length"), "required for a globoidal cam (the roller's "
                 "length along its axis, the arm)", show_got=False)

    def check_fit(self, design: Design, program: MotionProgram) -> None:
        """The roller on the side of the pivot its globoid puts it, its ends on the arm, the
        arm's swing short of square to the line of centres, the groove shallower than the
        roller is long, and a concave globoid's waist outside the cam axis."""
        cam, fol = design.cam, design.follower
        c, arm = fol.pivot_distance or 0.0, fol.arm_length or 0.0
        length = fol.roller_length or 0.0
        if cam.globoid == "concave" and arm + length / 2.0 >= c:
            fail(("follower", "arm_length"), f"a concave globoid's roller lies between the pivot "
                 f"and the cam axis: arm_length + roller_length/2 ({mm(arm + length / 2.0)}) must "
                 f"be less than pivot_distance ({mm(c)}), or the roller passes the cam axis",
                 hint="for a roller reaching past the cam axis, give globoid: convex")
        if cam.globoid == "convex" and arm - length / 2.0 <= c:
            fail(("follower", "arm_length"), f"a convex globoid's roller lies beyond the cam "
                 f"axis from the pivot: arm_length − roller_length/2 ({mm(arm - length / 2.0)}) "
                 f"must be more than pivot_distance ({mm(c)})",
                 hint="for a roller between the pivot and the cam axis, give globoid: concave")
        if length / 2.0 >= arm:
            fail(("follower", "roller_length"), f"puts the roller's end at the pivot or behind "
                 f"it: half the roller's length must be less than the arm_length ({mm(arm)})")
        rest = fol.rest_angle if fol.rest_angle is not None else -program.max_lift / 2.0
        low, high = math.degrees(rest), math.degrees(rest + program.max_lift)
        if low <= -MAX_GLOBOID_SWING_DEG or high >= MAX_GLOBOID_SWING_DEG:
            fail(("follower", "rest_angle") if fol.rest_angle is not None else ("motion",),
                 f"the arm swings from {low:.6g}° to {high:.6g}° about the line of centres; it "
                 f"must stay within ±{MAX_GLOBOID_SWING_DEG:g}° of it", show_got=False)
        depth = cam.groove_depth or 0.0
        if depth >= length:
            fail(("cam", "groove_depth"), f"must be less than the roller's length "
                 f"({mm(length)}): the roller's outer end, where the arm holds it, stands "
                 "outside the blank")
        if cam.globoid == "concave" and cam.outer_radius is not None and cam.outer_radius >= c:
            fail(("cam", "outer_radius"), f"a concave globoid's waist lies between the cam "
                 f"axis and the pivot: it must be less than pivot_distance ({mm(c)})")

    def surface(self, design: Design, program: MotionProgram) -> float:
        """The pitch globoid at the line of centres: |C − L|."""
        fol = design.follower
        return abs((fol.pivot_distance or 0.0) - (fol.arm_length or 0.0))


#: The arm of a globoidal cam's follower swings at most this far (deg) either side of the line
#: of centres: at 90° its roller would lie along the cam axis.
MAX_GLOBOID_SWING_DEG = 80.0

#: A globoidal cam's export tolerance by default (mm). Its groove is a surface in space, made
#: from the STL (printed, or milled along it): at 0.001 mm, the design file's default for plate
#: outlines, its mesh would take some hundred times the facets for accuracy no printer or
#: 3-axis finish holds; 0.01 mm stays under a printer's layer and a finishing pass's scallop.
GLOBOID_TOLERANCE_MM = 0.01

#: The facts of the cam types that share them.
_SHAPED = {"shaped": True, "translating_only": True}
_POSITIVE_PLATE = {"disc_curves": True, "positive_drive": True, "two_sided": True}
_GROOVE_KEYS = {"translating_keys": ("groove_clearance",),
                "oscillating_keys": ("groove_clearance",)}
_SIZED_PLATE = ("cam.base_radius", "follower.offset")

#: ``cam.type`` -> its row, in the order the design file's messages list the types.
CAM_TYPES: dict[str, CamTypeSpec] = {spec.name: spec for spec in (
    CamTypeSpec("disc", "camfab.kinds.disc", (*_TURNING, "base_radius", *_BLANK), ("base_radius",),
                _ANY_FOLLOWER, disc_curves=True, auto_keys=_SIZED_PLATE),
    _Drum("cylindrical", "camfab.kinds.drum",
          (*_TURNING, "radius", "length", "groove_depth", "groove_start", "bore"),
          ("radius", "length", "groove_depth"), ("roller",), **_GROOVE_KEYS,
          translating_only=True, bore_within=None, keyway_within="radius",
          auto_keys=("cam.radius",), two_sided=True, contact_extent="groove_depth",
          machining="drum"),
    _CircularArc("circular-arc", "camfab.kinds.shaped",
                 (*_TURNING, "base_radius", "lift", "lift_angle", "nose_radius", "flank_angle",
                  "top_dwell", *_BLANK), ("base_radius", "lift", "lift_angle"), _ANY_FOLLOWER,
                 **_SHAPED),
    _Tangent("tangent", "camfab.kinds.shaped",
             (*_TURNING, "base_radius", "lift", "lift_angle", "nose_radius", "top_dwell",
              *_BLANK), ("base_radius", "lift"), _ANY_FOLLOWER, **_SHAPED),
    _Groove("groove", "camfab.kinds.groove",
            (*_TURNING, "base_radius", "thickness", "groove_depth", "outer_radius", "bore",
             "keyway"), ("base_radius", "thickness", "groove_depth"), ("roller",),
            **_GROOVE_KEYS, **_POSITIVE_PLATE, auto_keys=_SIZED_PLATE,
            contact_extent="groove_depth"),
    _Conjugate("conjugate", "camfab.kinds.pair:CONJUGATE", (*_TURNING, "base_radius", *_BLANK),
               ("base_radius",), ("roller",), translating_keys=("roller_spacing",),
               oscillating_keys=("arm_angle",), **_POSITIVE_PLATE, auto_keys=_SIZED_PLATE),
    _ConstantBreadth("constant-breadth", "camfab.kinds.pair:CONSTANT_BREADTH",
                     (*_TURNING, "base_radius", *_BLANK), ("base_radius",), ("flat", "roller"),
                     translating_only=True, **_POSITIVE_PLATE),
    _Globoidal("globoidal", "camfab.kinds.globoid",
               (*_TURNING, "globoid", "groove_depth", "outer_radius", "width", "bore"),
               ("globoid", "groove_depth"), ("roller",),
               oscillating_keys=("groove_clearance", "roller_length", "rest_angle"),
               translating_keys=("groove_clearance", "roller_length", "rest_angle"),
               positive_drive=True, two_sided=True, contact_extent=None, bore_within=None,
               keyway_within=None, default_tolerance=GLOBOID_TOLERANCE_MM,
               machining="globoid"),
    _Linear("linear", "camfab.kinds.linear", ("type", "speed_rpm", "stroke", "base_height",
                                              "thickness"), ("stroke", "base_height"),
            ("roller", "knife"), span="travel", translating_only=True, bore_within=None,
            keyway_within=None, follower_hints=(
                ("flat", "a flat face perpendicular to its motion rests on the highest point "
                         "of a cam sliding under it, so a linear cam cannot move it"),)),
)}
