"""The validated, immutable design: what a design file says, in internal units.

Lengths are millimetres and angles radians (converted from the design's ``units`` and degrees at
this boundary); ``speed_rpm`` is rpm, spring ``rate`` N/mm, ``preload`` N, ``damping`` N·s/m,
``mass`` kg. Motion lifts are millimetres for translating followers and radians of swing for
oscillating ones. Field names are the design file's keys (SPEC §3).

Build a :class:`Design` with :func:`camfab.design.load_design` (from a file) or
:func:`camfab.design.design_from_mapping`; both run the structural checks of the loader, the
field validation here and the design rules of :mod:`camfab.design.rules`.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import (
    AfterValidator,
    BeforeValidator,
    Discriminator,
    Field,
    Tag,
    ValidationInfo,
    field_validator,
    model_validator,
)

from camfab.design import units as U
from camfab.design.cam_types import CAM_TYPES, CamTypeSpec
from camfab.design.fields import (
    Angle,
    Frozen,
    Length,
    Lift,
    NonNegativeAngle,
    NonNegativeLength,
    PositiveAngle,
    PositiveLength,
    as_kind,
    carried,
    context,
    converted,
    lift_kind,
    problem,
)
from camfab.design.machining import Machining
from camfab.errors import DesignError, did_you_mean

if TYPE_CHECKING:
    from camfab.curves.shaped import ShapedCam
    from camfab.motion.program import MotionProgram

#: The ``cam.type`` names, from the registry of cam types.
CamTypeName = Literal[tuple(CAM_TYPES)]  # type: ignore[valid-type]
FollowerType = Literal["knife", "roller", "flat", "mushroom"]
OutputName = Literal["dxf", "svg", "stl", "report", "csv", "step", "gcode"]


class Keyway(Frozen):
    """A keyway cut into the bore, centred on +Y at θ = 0 (mm)."""

    width: PositiveLength
    depth: PositiveLength


class Cam(Frozen):
    """The cam body. Disc: ``base_radius`` (+ ``thickness``, ``bore``, ``keyway``).
    Cylindrical: ``radius`` (outer), ``length``, ``groove_depth``, ``groove_start``, ``bore``.
    Circular-arc and tangent: ``base_radius``, ``lift``, ``lift_angle`` (the angle of ascent),
    ``nose_radius`` (or ``flank_angle`` for a circular-arc cam; a tangent cam takes either
    ``lift_angle`` or ``nose_radius``), ``top_dwell``, and the plate's keys.
    Groove: a disc's keys with ``groove_depth`` and ``outer_radius``. Conjugate and
    constant-breadth: a disc's keys. Linear: ``stroke``, ``base_height``, ``thickness``.
    Globoidal: ``globoid`` (``concave`` or ``convex``), ``groove_depth``, ``outer_radius`` (at
    the waist or crown), ``width`` (along the axis), ``bore``."""

    type: CamTypeName
    rotation: Literal["ccw", "cw"] = "ccw"
    speed_rpm: Annotated[float, as_kind(U.SPEED), Field(gt=0)] | None = None
    base_radius: PositiveLength | None = None
    thickness: PositiveLength | None = None
    bore: PositiveLength | None = None
    keyway: Keyway | None = None
    radius: PositiveLength | None = None
    length: PositiveLength | None = None
    groove_depth: PositiveLength | None = None
    groove_start: Length | None = None
    lift: PositiveLength | None = None
    lift_angle: PositiveAngle | None = None
    nose_radius: PositiveLength | None = None
    flank_angle: PositiveAngle | None = None
    top_dwell: NonNegativeAngle = 0.0
    outer_radius: PositiveLength | None = None
    stroke: PositiveLength | None = None
    base_height: PositiveLength | None = None
    globoid: Literal["concave", "convex"] | None = None
    width: PositiveLength | None = None

    @property
    def spec(self) -> CamTypeSpec:
        """What the design file takes for this cam's type, and its rules
        (:mod:`camfab.design.cam_types`)."""
        return CAM_TYPES[self.type]

    @property
    def sigma(self) -> int:
        """+1 for a counter-clockwise cam, −1 for clockwise (SPEC §2)."""
        return 1 if self.rotation == "ccw" else -1

    @property
    def omega(self) -> float | None:
        """Angular speed in rad/s, or None without ``speed_rpm``."""
        return None if self.speed_rpm is None else self.speed_rpm * 2.0 * math.pi / 60.0


class Follower(Frozen):
    """The follower: contact shape (``type``) and ``motion`` with their dimensions (mm, kg)."""

    type: FollowerType
    motion: Literal["translating", "oscillating"] = "translating"
    offset: Length = 0.0
    roller_radius: PositiveLength | None = None
    face_radius: PositiveLength | None = None
    face_width: PositiveLength | None = None
    pivot_distance: PositiveLength | None = None
    arm_length: PositiveLength | None = None
    pivot_side: Literal["right", "left"] = "right"
    face_offset: Length = 0.0
    groove_clearance: NonNegativeLength = 0.0
    roller_spacing: PositiveLength | None = None
    arm_angle: PositiveAngle | None = None
    roller_length: PositiveLength | None = None
    rest_angle: Angle | None = None
    mass: Annotated[float, as_kind(U.MASS), Field(gt=0)] | None = None
    stiffness: Annotated[float, as_kind(U.RATE), Field(gt=0)] | None = None
    damping_ratio: Annotated[float, Field(ge=0)] | None = None
    roller_load_rating: Annotated[float, as_kind(U.FORCE), Field(gt=0)] | None = None
    roller_bearing: Literal["needle", "ball"] | None = None

    @field_validator("type", mode="before")
    @classmethod
    def _spherical(cls, value: Any) -> Any:
        return "mushroom" if value == "spherical" else value

    @property
    def oscillating(self) -> bool:
        return self.motion == "oscillating"

    @property
    def train_damping_ratio(self) -> float:
        """ζ of the follower train's own damper: ``damping_ratio``, or
        :data:`DEFAULT_DAMPING_RATIO` with a ``stiffness`` (0 without one)."""
        if self.damping_ratio is not None:
            return self.damping_ratio
        return DEFAULT_DAMPING_RATIO if self.stiffness is not None else 0.0

    @property
    def life_exponent(self) -> float:
        """The exponent p of the roller bearing's life, L₁₀ = (C/P)ᵖ: 10/3 for a needle
        (roller) bearing, the default, 3 for a ball bearing (ISO 281)."""
        return 3.0 if self.roller_bearing == "ball" else 10.0 / 3.0

    @property
    def trace_radius(self) -> float:
        """Distance from the trace point to the contact surface: Rp − Rb (mm)."""
        if self.type == "roller":
            return self.roller_radius or 0.0
        if self.type == "mushroom":
            return self.face_radius or 0.0
        return 0.0


class Conditions(Frozen):
    """Boundary conditions of a polynomial, table or spline segment at one end.

    Values are derivatives of the lift per radian of cam angle (mm/rad, mm/rad², mm/rad³,
    mm/rad⁴; rad/rad… for oscillating followers), or ``"match"`` to take the neighbouring
    segment's value. The snap is the fourth derivative.
    """

    velocity: float | str | None = None
    acceleration: float | str | None = None
    jerk: float | str | None = None
    snap: float | str | None = None

    @field_validator("velocity", "acceleration", "jerk", "snap", mode="before")
    @classmethod
    def _value(cls, value: Any, info: ValidationInfo) -> Any:
        if value is None or (isinstance(value, str) and value.strip().lower() == "match"):
            return None if value is None else "match"
        order = {"velocity": 1, "acceleration": 2, "jerk": 3,
                 "snap": 4}[info.field_name or "velocity"]
        try:
            return U.convert(value, U.angle_rate(order, lift_kind(info)),
                             context(info).get("units", "mm"))
        except DesignError as exc:
            raise carried(DesignError(exc.problem + " or 'match'", allowed=exc.allowed)) from None

    def items(self) -> list[tuple[int, float | str]]:
        """(order, value) for each condition given."""
        given = ((1, self.velocity), (2, self.acceleration), (3, self.jerk), (4, self.snap))
        return [(order, value) for order, value in given if value is not None]


def _point(value: Any, info: ValidationInfo) -> Any:
    """A table/polynomial point ``[angle, displacement]`` -> (radians, mm or radians)."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise problem("must be a pair [angle, displacement]")
    return (converted(value[0], U.ANGLE, info), converted(value[1], lift_kind(info), info))


Point = Annotated[tuple[float, float], BeforeValidator(_point)]


def _spline_order(value: Any) -> Any:
    """A spline's ``order`` (degree + 1): a whole number in the range the law takes."""
    from camfab.motion.bspline import MAX_SPLINE_ORDER, MIN_SPLINE_ORDER

    if isinstance(value, bool) or not isinstance(value, int) or not (
            MIN_SPLINE_ORDER <= value <= MAX_SPLINE_ORDER):
        raise problem(f"must be a whole number from {MIN_SPLINE_ORDER} (a cubic) to "
                      f"{MAX_SPLINE_ORDER}: the B-spline's degree + 1")
    return value


def _control_count(value: Any) -> Any:
    """A spline's ``controls`` as a count: a whole number of free control values."""
    from camfab.motion.bspline import MAX_SPLINE_CONTROLS

    if isinstance(value, bool) or not isinstance(value, int) or not (
            0 <= value <= MAX_SPLINE_CONTROLS):
        raise problem(f"must be a whole number of free control values from 0 to "
                      f"{MAX_SPLINE_CONTROLS}, or a list of them (numbers from 0 to 1)")
    return value


def _control_value(value: Any) -> Any:
    """One of a spline's free control values: a number from 0 to 1 (normalised lift)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
            0.0 <= value <= 1.0):
        raise problem("must be a number from 0 to 1 (a control value of the normalised lift)")
    return float(value)


def _control_values(value: Any) -> Any:
    from camfab.motion.bspline import MAX_SPLINE_CONTROLS

    if len(value) > MAX_SPLINE_CONTROLS:
        raise problem(f"has {len(value)} control values; a spline takes at most "
                      f"{MAX_SPLINE_CONTROLS}")
    return value


#: The tags of a spline's ``controls`` two forms, which pydantic's errors carry in their
#: location.
CONTROLS_TAGS = ("controls-count", "controls-values")


def _controls_form(value: Any) -> str:
    """Which form of a spline's ``controls`` *value* is: its values (a list), else a count."""
    return CONTROLS_TAGS[1] if isinstance(value, (list, tuple)) else CONTROLS_TAGS[0]


#: A spline's free control values: how many (the smooth rise's values), or the values.
Controls = Annotated[
    Annotated[Annotated[int, BeforeValidator(_control_count)], Tag(CONTROLS_TAGS[0])]
    | Annotated[Annotated[tuple[Annotated[float, BeforeValidator(_control_value)], ...],
                          AfterValidator(_control_values)], Tag(CONTROLS_TAGS[1])],
    Discriminator(_controls_form)]


#: The follower train's damping ratio ζ when a design gives a ``stiffness`` and no
#: ``damping_ratio``: 0.05, the middle of the 0.02–0.1 that measured cam-follower trains show
#: (Norton, *Cam Design and Manufacturing Handbook*, ch. 10).
DEFAULT_DAMPING_RATIO = 0.05


#: Smallest blend of the modified-uniform-velocity law (a share of the segment at each end).
#: The acceleration grows as 1/blend and the samples that hold the tolerance over the blend with
#: it; at 1e-7 a check takes seconds and hundreds of megabytes, and under a thousandth of the
#: segment the blend is a velocity step in all but name.
MIN_BLEND = 0.001


class Segment(Frozen):
    """One segment of the motion program (``kind`` comes from the one-key map in the file)."""

    kind: Literal["rise", "return", "dwell"]
    angle: PositiveAngle | None = None
    travel: PositiveLength | None = None
    lift: Lift | None = None
    law: str | None = None
    blend: Annotated[float, Field(ge=MIN_BLEND, le=0.5)] | None = None
    start: Conditions | None = None
    end: Conditions | None = None
    points: tuple[Point, ...] | None = None
    csv: str | None = None
    order: Annotated[int, BeforeValidator(_spline_order)] | None = None
    controls: Controls | None = None

    @field_validator("law", mode="before")
    @classmethod
    def _canonical_law(cls, value: Any) -> Any:
        from camfab.motion.laws import ALIASES, LAW_NAMES, canonical_law_name

        if not isinstance(value, str):
            raise problem("must be a law name", LAW_NAMES, kind="shape")
        name = canonical_law_name(value)
        if name is None:
            raise problem("unknown motion law", LAW_NAMES,
                           did_you_mean(value, [*LAW_NAMES, *ALIASES]), kind="shape")
        return name


class Spring(Frozen):
    """The return spring of a force-closed cam: ``rate`` N/mm, ``preload`` N at zero lift (or
    ``initial_compression`` mm), ``damping`` N·s/m, ``external_load`` N toward the cam."""

    rate: Annotated[float, as_kind(U.RATE), Field(gt=0)]
    preload: Annotated[float, as_kind(U.FORCE), Field(ge=0)] | None = None
    initial_compression: NonNegativeLength | None = None
    gravity: bool = False
    damping: Annotated[float, as_kind(U.DAMPING), Field(ge=0)] = 0.0
    external_load: Annotated[float, as_kind(U.FORCE)] = 0.0

    @field_validator("gravity", mode="before")
    @classmethod
    def _boolean(cls, value: Any) -> Any:
        if not isinstance(value, bool):
            raise problem("must be true or false")
        return value


#: The least convex radius of curvature (mm) of a profile a flat or mushroom face rides, where
#: the design gives no ``limits.min_radius_of_curvature``. A radius near zero is an edge, not a
#: curve: the face bears on a sliver of it (its Hertz stress without bound), wears it flat in its
#: first hours, and no finishing pass holds its shape — a cusp in all but name, which would
#: otherwise pass the undercut check as long as the radius stays above zero (a flat face's
#: sizing drives it there). 1 mm allows miniature cams and stays well under the 3 mm nose of the
#: source notes' exhaust-valve cam, the sharpest real profile among them. A roller's or a knife's
#: profile is held by the undercut check (its pitch curve against the roller) instead.
DEFAULT_FACE_MIN_RADIUS_MM = 1.0


class Limits(Frozen):
    """Design limits: ``pressure_angle`` (rad; default 30° translating, 35° oscillating), the
    least ``min_radius_of_curvature`` (mm) of the convex working curve (default
    :data:`DEFAULT_FACE_MIN_RADIUS_MM` under a flat or mushroom face, none else), the allowed
    Hertz ``contact_stress`` (MPa) and the least ``roller_life`` (hours); the last two are
    checked only where given."""

    pressure_angle: PositiveAngle | None = None
    min_radius_of_curvature: NonNegativeLength | None = None
    contact_stress: Annotated[float, as_kind(U.STRESS), Field(gt=0)] | None = None
    roller_life: Annotated[float, as_kind(U.DURATION), Field(gt=0)] | None = None


class Elastic(Frozen):
    """A material given by its elastic constants: Young's modulus ``E`` (MPa) and Poisson's
    ratio ``poisson``."""

    E: Annotated[float, as_kind(U.STRESS), Field(gt=0)]
    poisson: Annotated[float, Field(ge=0, le=0.5)]


def _material(value: Any) -> Any:
    """A material's name (one of :data:`~camfab.design.materials.MATERIALS`, or an alias) as
    its canonical name (a mapping is an :class:`Elastic`)."""
    from camfab.design.materials import ALIASES, MATERIALS, material

    if not isinstance(value, str):
        raise problem("must be a material's name or {E, poisson}", ", ".join(MATERIALS),
                       kind="shape")
    if material(value) is None:
        raise problem("unknown material", ", ".join(MATERIALS) + ", or {E, poisson}",
                       did_you_mean(value.strip().lower(), [*MATERIALS, *ALIASES]),
                       kind="shape")
    key = value.strip().lower()
    return ALIASES.get(key, key)


#: The tags of a material's two forms, which pydantic's errors carry in their location.
MATERIAL_TAGS = ("material-name", "material-constants")
#: The tags of the design's tagged unions, left out of the locations errors give.
UNION_TAGS = (*MATERIAL_TAGS, *CONTROLS_TAGS)



def _material_form(value: Any) -> str:
    """Which form of a material *value* is: its constants (a mapping), else a name."""
    return MATERIAL_TAGS[1] if isinstance(value, (dict, Elastic)) else MATERIAL_TAGS[0]


#: A material: its name, or its constants (the error of the form given, not of both).
MaterialSpec = Annotated[
    Annotated[Annotated[str, BeforeValidator(_material)], Tag(MATERIAL_TAGS[0])]
    | Annotated[Elastic, Tag(MATERIAL_TAGS[1])],
    Discriminator(_material_form)]


class Materials(Frozen):
    """What the cam and the follower are made of: a material's name (steel, cast-iron, bronze,
    aluminium, pom, ...) or its constants ``{E, poisson}``; steel on steel unless given."""

    cam: MaterialSpec = "steel"
    follower: MaterialSpec = "steel"

    def constants(self, part: Literal["cam", "follower"]) -> tuple[float, float]:
        """Young's modulus (MPa) and Poisson's ratio of the *part*'s material."""
        from camfab.design.materials import material

        spec = getattr(self, part)
        if isinstance(spec, Elastic):
            return spec.E, spec.poisson
        found = material(spec)
        assert found is not None, "the model refuses unknown names"
        return found.youngs_modulus, found.poisson


#: Default chord tolerance of exported curves: a thousandth of a millimetre, well inside what a
#: laser, water jet or mill holds, so the exported file never limits the part's accuracy.
DEFAULT_TOLERANCE_MM = 0.001


class SizingOptions(Frozen):
    """How a size camfab chooses (``auto``) is finished: ``round_to`` rounds the chosen radius up
    to a stock step (mm)."""

    round_to: PositiveLength | None = None


class Sized(Frozen):
    """What camfab sized of a design that said ``auto``: the values chosen (mm; None where the
    design gave the value) and the limit that governs them — its check id, the limit in words,
    its value at the chosen size and the limit (in ``unit``: ``mm`` or ``deg``), and the cam
    angle where it binds (deg; None for a limit of the part's fit, such as the bore)."""

    base_radius: float | None = None
    offset: float | None = None
    radius: float | None = None
    governed_by: str
    what: str
    value: float | None = None
    limit: float | None = None
    unit: str = "mm"
    at_deg: float | None = None
    rounded_to: float | None = None


#: The tolerance a made cam's profile is inspected to when the design gives none (mm): ±0.025 mm
#: (±0.001 in), what a finish-milled or ground cam profile is commonly held to — some five times
#: a good dial gauge's or CMM's uncertainty (2–5 µm), so a clean part passes whatever the
#: instrument's noise, and well inside what a follower feels. Not the export tolerance (0.001 mm:
#: how closely the files follow the exact curves, far finer than any part is made or measured);
#: a 3-D printed prototype asks for some 0.1–0.2 mm (``inspection: {tolerance: 0.15}``).
DEFAULT_INSPECTION_TOLERANCE_MM = 0.025
#: The same for a design in inches: ±0.001 in.
DEFAULT_INSPECTION_TOLERANCE_IN = 0.001


class Inspection(Frozen):
    """How a made cam is inspected (``camfab inspect``, the report's lift table): the
    ``tolerance`` (mm) its profile's deviation is held to."""

    tolerance: PositiveLength | None = None


class Manufacturing(Frozen):
    """Manufacturing settings (mm): export ``tolerance``, laser ``kerf``, CNC ``cutter_radius``."""

    tolerance: PositiveLength = DEFAULT_TOLERANCE_MM
    kerf: NonNegativeLength = 0.0
    cutter_radius: NonNegativeLength = 0.0


#: What a design's ``name`` may be (it names the output files and folders): it starts with a
#: letter or digit, so that neither ``".."`` nor ``"."`` nor a hidden ``".x"`` can place the
#: files elsewhere, and holds no separator.
NAME_PATTERN = r"^[a-z0-9][a-z0-9._-]*$"
#: :data:`NAME_PATTERN` in words, as a refusal gives it.
NAME_RULE = "must start with a letter or digit and use only a-z, 0-9, '.', '_' and '-'"
#: The longest ``name`` (characters).
NAME_LENGTH = 100


class Design(Frozen):
    """A whole cam design, validated."""

    #: Names the output files and folder (:data:`NAME_PATTERN`).
    name: Annotated[str, Field(min_length=1, max_length=NAME_LENGTH, pattern=NAME_PATTERN)]
    description: str = ""
    units: Literal["mm", "in"] = "mm"
    cam: Cam
    follower: Follower
    motion: Annotated[tuple[Segment, ...], Field(min_length=1)] | None = None
    #: What ``motion`` describes: the cam's lift (``cam``), or the motion of the follower's
    #: mass (``output``: a polydyne cam, its lift computed through the elastic train at
    #: ``cam.speed_rpm``).
    motion_target: Literal["cam", "output"] = "cam"
    spring: Spring | None = None
    limits: Limits = Limits()
    materials: Materials = Materials()
    manufacturing: Manufacturing = Manufacturing()
    inspection: Inspection = Inspection()
    #: The tool and feeds of the machining programs (``outputs: [gcode]``).
    machining: Machining | None = None
    outputs: tuple[OutputName, ...] | None = None
    table_step: PositiveAngle = math.radians(1.0)
    sizing: SizingOptions = SizingOptions()
    source: str = Field(default="", exclude=True)
    #: What camfab sized where the design file said ``auto`` (None: nothing).
    sized: Sized | None = Field(default=None, exclude=True)

    @model_validator(mode="after")
    def _rules(self, info: ValidationInfo) -> Design:
        from camfab.design.rules import check_rules

        check_rules(self, frozenset(context(info).get("sizing", ())))
        return self

    @cached_property
    def program(self) -> MotionProgram:
        """The motion program s(θ) of the cam's lift: of ``motion``, or of the cam's shape for a
        circular-arc or tangent cam, or, with ``motion_target: output``, the polydyne cam's
        lift that makes the follower's mass follow ``motion`` (built once; the rules build it
        to check it)."""
        output = self.output_program
        if self.motion_target == "cam":
            return output
        from camfab.design.train import polydyne_terms
        from camfab.motion.polydyne import PolydyneProgram

        assert self.cam.speed_rpm is not None, "the rules require a speed"
        return PolydyneProgram(output, polydyne_terms(self), self.cam.speed_rpm)

    @cached_property
    def output_program(self) -> MotionProgram:
        """The follower's motion the design asks for: the cam's lift (:attr:`program`) unless
        ``motion_target`` is ``output``, where it is the motion of the follower's mass."""
        return self.cam.spec.program(self)

    @cached_property
    def shape(self) -> ShapedCam:
        """The dimensions and outline of a circular-arc or tangent cam (raises ShapeError for
        dimensions no such cam has; the design rules have checked them)."""
        return self.cam.spec.shape(self.cam)

    @property
    def pressure_angle_limit(self) -> float:
        """The pressure-angle limit in radians (SPEC §3 defaults when not given)."""
        if self.limits.pressure_angle is not None:
            return self.limits.pressure_angle
        return math.radians(35.0 if self.follower.oscillating else 30.0)

    @property
    def inspection_tolerance(self) -> float:
        """The tolerance (mm) a made cam's profile is inspected to: ``inspection.tolerance``, or
        :data:`DEFAULT_INSPECTION_TOLERANCE_MM` (±0.001 in for a design in inches)."""
        if self.inspection.tolerance is not None:
            return self.inspection.tolerance
        if self.units == "in":
            return DEFAULT_INSPECTION_TOLERANCE_IN * self.mm_per_unit
        return DEFAULT_INSPECTION_TOLERANCE_MM

    @property
    def min_profile_radius(self) -> float:
        """The least convex radius of curvature of the profile (mm): ``limits.
        min_radius_of_curvature``, or :data:`DEFAULT_FACE_MIN_RADIUS_MM` for a flat or mushroom
        face (0: none, for a roller or a knife, whose undercut check holds the profile)."""
        given = self.limits.min_radius_of_curvature
        if given is not None:
            return given
        return DEFAULT_FACE_MIN_RADIUS_MM if self.follower.type in ("flat", "mushroom") else 0.0

    @property
    def contact_length(self) -> float | None:
        """The length of the follower's line contact with the cam (mm): the shorter of the cam's
        extent across the follower's motion (its type's
        :attr:`~camfab.design.cam_types.CamTypeSpec.contact_extent`: a plate's thickness, a
        groove's depth) and a roller's length; None where neither is given."""
        key, fol = self.cam.spec.contact_extent, self.follower
        lengths = [v for v in (None if key is None else getattr(self.cam, key),
                               fol.roller_length if fol.type == "roller" else None)
                   if v is not None]
        return min(lengths) if lengths else None

    @property
    def mm_per_unit(self) -> float:
        """Millimetres per design length unit (1 or 25.4)."""
        return U.MM_PER_UNIT[self.units]
