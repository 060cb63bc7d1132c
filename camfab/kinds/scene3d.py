"""The cam and its follower in three dimensions over the report's animation: where each part
camfab writes as STL stands at each frame, and the follower's solids and where they stand, as
4×4 rigid transforms in the coordinates of the STL files (mm).

A transform maps a body's own frame onto the STL's coordinates. A part's own frame is its STL
file's: at the cam angle θ a turning cam's transform is its turn by σθ about its axis, a linear
cam's its slide toward −X by its travel. The follower is one rigid body: its transform at each
frame places its frame (origin and axes, mm), and each of its solids (:class:`Shape`) carries
its own transform into that frame. Each kind gives its scene (:meth:`CamKind.scene`) from its
exact geometry; this module holds the record, the transforms, and the scene of the plate cams
(disc, shaped, groove, conjugate and constant-breadth), which share it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from camfab.curves.plane import perp, rotate

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array
    from camfab.geometry.disc import DiscCam

ShapeKind = Literal["cylinder", "box", "wedge", "cap"]

#: The names of a shape's ``dims`` by its kind (mm, and rad for a cap's angle).
DIM_NAMES: dict[str, tuple[str, ...]] = {
    "cylinder": ("radius", "length"),
    "box": ("x", "y", "z"),
    "wedge": ("width", "height", "length"),
    "cap": ("radius", "angle"),
}

#: A plate's thickness where the design gives none (it then has no STL): this share of its base
#: radius, so that the follower still has a depth to be drawn with.
NO_THICKNESS_SHARE = 0.2

#: The follower's parts drawn for show, sized as shares of the cam's base radius (or a drum's or
#: globoid's radius): a stem's or arm's width, a stem's length, a flat face's thickness, a knife
#: wedge's width and height; and as shares of the plate's thickness: an arm's height and its
#: gap above the plate.
ARM_WIDTH_SHARE = 0.1
STEM_LENGTH_SHARE = 0.8
FACE_THICKNESS_SHARE = 0.06
KNIFE_WIDTH_SHARE = 0.12
KNIFE_HEIGHT_SHARE = 0.3
ARM_HEIGHT_SHARE = 0.5
ARM_GAP_SHARE = 0.2

#: A mushroom's face is drawn this far (rad) beyond the largest pressure angle, where its
#: contact lies on it, and at most :data:`MAX_CAP_ANGLE` from its pole.
CAP_MARGIN = 0.25
MAX_CAP_ANGLE = 1.3


@dataclass(frozen=True)
class Shape:
    """A solid of the follower in the follower's frame (mm).

    ``kind`` and its ``dims`` (:data:`DIM_NAMES`):

    - ``cylinder`` (radius, length): along its Z axis, centred on its origin (a roller, a pin);
    - ``box`` (x, y, z): its lengths along its axes, centred on its origin (a stem, an arm, a
      flat face);
    - ``wedge`` (width, height, length): a knife's edge along its Z axis through its origin,
      opening toward +Y to *width* at *height*, *length* long centred on the origin;
    - ``cap`` (radius, angle): the sphere of *radius* about its origin within *angle* (rad) of
      its −Y pole, closed by the plane there (a mushroom's face, its pole toward the cam).

    ``matrix`` (4, 4) maps the shape's frame into the follower's; ``role`` names the piece:
    ``roller``, ``knife``, ``face``, ``stem``, ``arm``, ``pin`` or ``pivot``.
    """

    kind: ShapeKind
    role: str
    dims: tuple[float, ...]
    matrix: Array


@dataclass(frozen=True)
class Scene3D:
    """A cam and its follower at the cam angles *theta* (rad, the report's animation frames):
    every transform maps a body's frame into the coordinates of the STL files (mm).

    Attributes
    ----------
    theta
        (F,) the cam angles (rad).
    part_matrices
        (P, F, 4, 4): each STL file's part at each frame, in the order the files are written
        (one file for every kind: a conjugate pair's two plates are one solid).
    follower_shapes
        The follower's solids in its frame.
    follower_matrices
        (F, 4, 4): the follower's frame at each frame.
    extent
        (2, 3): the least and greatest corners of a box holding the parts in their own frame.
    axis
        (2, 3): a point of the axis the cam turns about and its unit direction; for a cam that
        slides, a point of it and the unit direction it slides in.
    slides
        True for a cam that slides (a linear cam), False for one that turns.
    """

    theta: Array
    part_matrices: Array
    follower_shapes: tuple[Shape, ...]
    follower_matrices: Array
    extent: Array
    axis: Array
    slides: bool = False


# -- transforms ---------------------------------------------------------------------------------


def rigid(rotation: Array, translation: Array) -> Array:
    """(..., 4, 4) transforms: the (..., 3, 3) *rotation*, then the (..., 3) *translation* (mm),
    broadcast together."""
    rotation, translation = np.asarray(rotation, float), np.asarray(translation, float)
    lead = np.broadcast_shapes(rotation.shape[:-2], translation.shape[:-1])
    out = np.zeros((*lead, 4, 4))
    out[..., :3, :3] = rotation
    out[..., :3, 3] = translation
    out[..., 3, 3] = 1.0
    return out


def turns_z(angles: Array | float) -> Array:
    """(..., 3, 3) rotations counter-clockwise by *angles* (rad) about Z."""
    angles = np.asarray(angles, dtype=np.float64)
    c, s = np.cos(angles), np.sin(angles)
    out = np.zeros((*angles.shape, 3, 3))
    out[..., 0, 0], out[..., 0, 1] = c, -s
    out[..., 1, 0], out[..., 1, 1] = s, c
    out[..., 2, 2] = 1.0
    return out


def turning(angles: Array) -> Array:
    """(F, 4, 4) turns of a cam by *angles* (rad, counter-clockwise) about Z through the
    origin."""
    return rigid(turns_z(angles), np.zeros(3))


def upright(away: Array) -> Array:
    """(3, 3) the rotation taking +Y onto the unit plane vector *away* (2,), Z kept."""
    ax, ay = float(away[0]), float(away[1])
    return np.array([[ay, ax, 0.0], [-ax, ay, 0.0], [0.0, 0.0, 1.0]])


def along_x() -> Array:
    """(3, 3) the rotation taking +Z onto +X (a cylinder's axis laid along X), Y kept."""
    return np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])


def along_y() -> Array:
    """(3, 3) the rotation taking +Z onto +Y (a cylinder's axis laid along Y), X kept."""
    return np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def bar(role: str, start: Array, end: Array, width: float, height: float) -> Shape:
    """A box from *start* to *end* (3,) (mm) in the follower's frame, *width* across in the
    plane square to Z and *height* along Z (an arm or a stem; the ends at one height)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    run = end[:2] - start[:2]
    length = float(np.hypot(*run))
    away = run / length if length > 0.0 else np.array([0.0, 1.0])
    return Shape("box", role, (width, length, height),
                 rigid(upright(away), (start + end) / 2.0))


def box_extent(lo: Array | list[float], hi: Array | list[float]) -> Array:
    """(2, 3) a box from its least corner *lo* to its greatest *hi* (mm)."""
    return np.array([lo, hi], dtype=np.float64)


# -- plate cams ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class FaceLine:
    """A flat face's line in the fixed frame at each frame: its unit normal (F, 2) pointing away
    from the cam, its distance *h* (F,) from the cam centre along it (mm), and where the cam
    touches it (F, 2) (mm)."""

    normal: Array
    h: Array
    contact: Array


@dataclass(frozen=True)
class PlateContact:
    """Where a contact of the follower stands on a plate cam, in the fixed frame at each frame
    (mm): its trace point (F, 2) (a roller's or a mushroom's centre, a knife's edge, a flat
    face's point on its stem or arm), the unit direction it moves away from the cam in on a rise
    (F, 2; or (2,) where it stays the same), its span along Z (from, to), and a flat face's line
    (None for another contact)."""

    trace: Array
    away: Array
    z: tuple[float, float]
    face: FaceLine | None = None


def face_line(cam: DiscCam, theta: Array, motion: Array, half_turn: bool = False) -> FaceLine:
    """A flat face's line from the cam's exact face lines (:meth:`DiscCam.face_lines`) at the
    cam angles *theta* with their *motion* (4, F), in the fixed frame; *half_turn*: the line
    those give half a turn on (a constant-breadth cam's other face at θ − π)."""
    lines = cam.face_lines(theta, motion)
    turn = cam.sigma * theta
    normal = np.stack((np.cos(lines.beta + turn), np.sin(lines.beta + turn)), axis=-1)
    contact = rotate(lines.contact(), turn)
    if half_turn:
        normal, contact = -normal, -contact
    return FaceLine(normal, lines.h, contact)


def first_contact(analysis: Analysis, theta: Array, z: tuple[float, float]) -> PlateContact:
    """The follower on a plate cam: its trace point (:meth:`DiscCam.trace`), its face line for
    a flat face, over *z* (mm)."""
    cam = analysis.geometry.cam
    motion = analysis.program.evaluate(theta)
    trace, _, _, rise = cam.trace(motion)
    face = face_line(cam, theta, motion) if cam.follower.flat else None
    return PlateContact(trace, rise, z, face)


def plate_thickness(analysis: Analysis) -> float:
    """The plate's thickness (mm), or a share of its base radius where it has none
    (:data:`NO_THICKNESS_SHARE`)."""
    design = analysis.design
    given = design.cam.thickness
    return given if given is not None else NO_THICKNESS_SHARE * analysis.geometry.cam.base_radius


def roller_span(analysis: Analysis, low: float, high: float) -> tuple[float, float]:
    """The span along Z (mm) of the follower's contact on a plate between *low* and *high*: a
    roller's length (``roller_length``, else the plate's) centred on it."""
    length = analysis.design.follower.roller_length or (high - low)
    middle = (low + high) / 2.0
    return middle - length / 2.0, middle + length / 2.0


def plate_scene(analysis: Analysis, theta: Array, contacts: list[PlateContact], radius: float,
                height: float, raised: bool = False) -> Scene3D:
    """The scene of a plate cam: its STL (the plate, or a pair's plates stacked, from z = 0 to
    *height*, within *radius* of its centre, mm) turning by σθ about Z, and the follower moving
    with its first contact's trace point (and for an oscillating one turning about its pivot)
    with each of *contacts*: its shape (a roller, a knife's wedge, a mushroom's cap, a flat
    face) and a stem along its motion or an arm from the pivot; *raised*: the stems ride above
    the plate's face (a roller in a groove), on a pin from the roller."""
    geom = analysis.geometry
    cam = geom.cam
    fol = cam.follower
    first = contacts[0]
    origin = first.trace
    if fol.oscillating:
        arm = origin - cam.pivot
        gamma = np.arctan2(arm[:, 1], arm[:, 0])
    else:
        gamma = np.zeros(theta.size)
    follower = rigid(turns_z(gamma), np.column_stack((origin, np.zeros(theta.size))))
    sizes = _Sizes.of(analysis)
    shapes: list[Shape] = []
    for k, contact in enumerate(contacts):
        point = _local(contact.trace[0], origin[0], gamma[0])
        away = _turned(np.broadcast_to(contact.away, contact.trace.shape)[0], -gamma[0])
        shape, back = _contact_shapes(analysis, contact, point, away, origin, gamma, sizes)
        shapes.append(shape)
        if fol.oscillating:
            pivot = _local(cam.pivot, origin[0], gamma[0])
            below = k == 0 and len(contacts) > 1  # a pair's arm a under the plates
            shapes += _arm(point, pivot, contact, sizes, height, below, not fol.flat)
        elif raised:
            shapes += _raised_stem(point, away, contact, sizes, height)
        else:
            shapes.append(_stem(contact, point, away, back, sizes))
    extent = box_extent([-radius, -radius, 0.0], [radius, radius, height])
    return Scene3D(theta, turning(cam.sigma * theta)[None], tuple(shapes), follower, extent,
                   np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))


@dataclass(frozen=True)
class _Sizes:
    """The follower's parts drawn for show (mm): a roller's or mushroom's radius, a stem's or
    arm's width, a stem's length, a flat face's thickness, an arm's height and its gap above
    the plate, the cam's base radius, and a flat face's width (``face_width``, or None)."""

    radius: float
    width: float
    stem: float
    face: float
    arm_height: float
    gap: float
    base: float
    face_width: float | None

    @classmethod
    def of(cls, analysis: Analysis) -> _Sizes:
        cam = analysis.geometry.cam
        base = cam.base_radius
        thick = plate_thickness(analysis)
        radius = cam.follower.radius
        width = 0.5 * radius if radius > 0.0 else ARM_WIDTH_SHARE * base
        return cls(radius, width, STEM_LENGTH_SHARE * base, FACE_THICKNESS_SHARE * base,
                   ARM_HEIGHT_SHARE * thick, ARM_GAP_SHARE * thick, base,
                   analysis.design.follower.face_width)


def _turned(vector: Array, angle: float) -> Array:
    """A plane *vector* (2,) turned counter-clockwise by *angle* (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])


def _local(point: Array, origin: Array, gamma: float) -> Array:
    """A fixed-frame plane *point* (mm) in the follower's frame at *origin* turned by
    *gamma*."""
    return _turned(np.asarray(point, float) - origin, -gamma)


def _contact_shapes(analysis: Analysis, contact: PlateContact, point: Array, away: Array,
                    origin: Array, gamma: Array, sizes: _Sizes) -> tuple[Shape, float]:
    """The shape touching the cam at a contact, in the follower's frame: a roller, a knife's
    wedge, a mushroom's cap or a flat face; and how far (mm) its back stands from the contact's
    *point* along *away*, where a stem starts."""
    fol = analysis.geometry.cam.follower
    low, high = contact.z
    middle, length = (low + high) / 2.0, high - low
    at = np.array([point[0], point[1], middle])
    if fol.contact == "roller":  # the roller as made (a groove's cam adds half its clearance)
        radius = analysis.design.follower.roller_radius or fol.radius
        return Shape("cylinder", "roller", (radius, length), rigid(np.eye(3), at)), radius
    if fol.contact == "knife":
        height = KNIFE_HEIGHT_SHARE * sizes.base
        return Shape("wedge", "knife", (KNIFE_WIDTH_SHARE * sizes.base, height, length),
                     rigid(upright(away), at)), height
    if fol.contact == "mushroom":
        numbers = analysis.result.numbers
        angle = min(math.radians(abs(numbers.pressure_angle.value)) + CAP_MARGIN, MAX_CAP_ANGLE)
        return (Shape("cap", "face", (fol.radius, angle), rigid(upright(away), at)),
                -fol.radius * math.cos(angle))
    assert contact.face is not None
    normal, h = _line_here(contact.face, origin, gamma)
    back = h - float(np.dot(point, normal)) + sizes.face
    return _face(contact.face, normal, h, origin, gamma, fol.oscillating, sizes, middle,
                 length), back


def _line_here(face: FaceLine, origin: Array, gamma: Array) -> tuple[Array, float]:
    """A flat face's line in the follower's frame: its unit normal away from the cam and its
    distance (mm) from the frame's origin along it (the same at every frame: take the
    first)."""
    normal = _turned(face.normal[0], -gamma[0])
    return normal, float(face.h[0] - np.dot(face.normal[0], origin[0]))


def _face(face: FaceLine, normal: Array, h: float, origin: Array, gamma: Array,
          oscillating: bool, sizes: _Sizes, middle: float, length: float) -> Shape:
    """A flat face as a box on its line (*normal*, *h* in the follower's frame), on the side
    away from the cam, as wide as ``face_width`` (else as its contacts over the frames need)
    about its stem (or about the middle of its contacts, on an arm)."""
    along = perp(normal)
    # where the cam touches the face at each frame, along it, in the follower's frame
    relative = face.contact - origin
    c, s = np.cos(-gamma), np.sin(-gamma)
    local = np.column_stack((c * relative[:, 0] - s * relative[:, 1],
                             s * relative[:, 0] + c * relative[:, 1]))
    spots = local @ along
    centre = 0.5 * float(spots.min() + spots.max()) if oscillating else 0.0
    reach = float(np.max(np.abs(spots - centre)))
    width = sizes.face_width or 2.0 * reach + 0.2 * sizes.base
    at = (h + sizes.face / 2.0) * normal + centre * along
    return Shape("box", "face", (width, sizes.face, 1.2 * length),
                 rigid(upright(normal), np.array([at[0], at[1], middle])))


def _stem(contact: PlateContact, point: Array, away: Array, back: float,
          sizes: _Sizes) -> Shape:
    """A translating follower's stem along its motion (*away*), from the back of its
    contact's shape (*back*, mm from *point*), in the plane of its contact."""
    low, high = contact.z
    start = point + back * away
    end = start + sizes.stem * away
    middle = (low + high) / 2.0
    return bar("stem", np.append(start, middle), np.append(end, middle), sizes.width, high - low)


def _raised_stem(point: Array, away: Array, contact: PlateContact, sizes: _Sizes,
                 height: float) -> list[Shape]:
    """A stem above the plate's face (*height*, mm) along the motion, on a pin from the
    contact's shape."""
    level = height + sizes.gap + sizes.arm_height / 2.0
    return [_pin(point, contact.z[1], level, sizes),
            bar("stem", np.append(point, level), np.append(point + sizes.stem * away, level),
                sizes.width, sizes.arm_height)]


def _pin(point: Array, low: float, high: float, sizes: _Sizes) -> Shape:
    """A pin along Z at *point* from *low* to *high* (mm)."""
    bottom, top = min(low, high), max(low, high)
    return Shape("cylinder", "pin", (0.35 * sizes.width, top - bottom),
                 rigid(np.eye(3), np.array([point[0], point[1], (bottom + top) / 2.0])))


def _arm(point: Array, pivot: Array, contact: PlateContact, sizes: _Sizes, height: float,
         below: bool, pinned: bool) -> list[Shape]:
    """An oscillating follower's arm from its *pivot* to its contact at *point*, clear of the
    plates (above them, or *below* them), with a pin down (up) to the contact's shape where
    *pinned*, and the pivot's hub."""
    half = sizes.gap + sizes.arm_height / 2.0
    level = -half if below else height + half
    shapes = [bar("arm", np.append(pivot, level), np.append(point, level), sizes.width,
                  sizes.arm_height)]
    if pinned:
        shapes.append(_pin(point, contact.z[0] if below else contact.z[1], level, sizes))
    hub = Shape("cylinder", "pivot", (sizes.width, sizes.arm_height * 1.6),
                rigid(np.eye(3), np.array([pivot[0], pivot[1], level])))
    return [*shapes, hub]
