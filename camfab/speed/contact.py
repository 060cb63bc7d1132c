"""Where a cam meets its follower over the cycle, and what the contact bears (THEORY §I): the
Hertz stress along the profile and the life of the roller's bearing.

A kind describes its contact as a :class:`Contact` (its result's ``contact`` hook): on the
analysis grid, for each side that can carry the follower (a plate's profile; a groove's two
walls; a conjugate pair's two cams; a drum's or a globoid's two flanks), the cam's curvature at
the contact (along the contact line where it varies), the normal force per newton of force
along the follower's motion, and how fast a roller rolls over it. The force along the motion
(the rigid model's, or the elastic train's) then gives the stress at every cam angle:

* a roller, a flat face: line contact of two cylinders, Σκ = κ_cam + 1/r_follower;
* a mushroom (spherical) face: point contact of the sphere and the cam's surface (κ_cam in
  the plane of the cam, 0 across it), solved exactly over its contact ellipse;
* a knife edge: none (its contact has no area to bear a load).

Units: mm, N, MPa; curvatures in 1/mm (convex positive, as the cam's material sees it); angles
in rad inside, deg in the records' ``_deg`` names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from camfab.arrays import Array, Index
from camfab.design import Design
from camfab.speed.hertz import effective_modulus, line_contact, point_contact

#: Why a knife edge gets no contact stress.
KNIFE_NOTE = ("a knife edge's contact has no area, so Hertz gives its stress no finite value: "
              "camfab reports none")


@dataclass(frozen=True)
class ContactSide:
    """One side of the cam that can carry the follower, over the analysis grid.

    Attributes
    ----------
    name
        What it is, in words: "the profile", "the inner wall", "cam b", "the lower flank".
    carries
        +1 where it carries the follower when the force along the follower's motion is
        positive (it pushes the follower along its motion), −1 when negative.
    curvature
        The cam's curvature at the contact (1/mm, convex positive, 0 straight), (N,), or
        (rows, N) along a contact line whose curvature varies.
    normal
        The normal force at the contact per newton of force along the follower's motion (N,).
    rolling
        How fast a roller rolls over this side (mm of its surface per radian of cam angle),
        None for a follower that slides.
    roller
        Which of the contact's rollers rides it (an index into :attr:`Contact.rollers`).
    always
        True when its roller rides it loaded or not (a conjugate pair's, a yoke's), False when
        the roller is on it only while it carries (a groove's walls).
    place
        The contact point on the cam (mm, in *frame*: the cam's, or a linear cam's plate's),
        (N, 2), where it is a point of a plate.
    rows
        Where each row of a varying *curvature* lies along the contact line (mm), and what
        that distance is measured from (``rows_from``).
    """

    name: str
    carries: int
    curvature: Array
    normal: Array
    rolling: Array | None = None
    roller: int = 0
    always: bool = True
    place: Array | None = None
    rows: Array | None = None
    rows_from: str = ""
    frame: str = "the cam's frame"


@dataclass(frozen=True)
class Contact:
    """How a cam's follower touches it over the cycle: on the grid *theta* (rad), line or point
    contact (``shape``), the follower's curvature across the contact (1/mm: 1/r of a roller or
    a mushroom's face, 0 for a flat face), the contact's length (mm, line contact), the sides
    that carry the follower, and the rollers' radius (mm) and names; ``note`` says why there
    is no stress to compute (a knife, a contact of unknown length)."""

    theta: Array
    shape: Literal["line", "point", "none"]
    follower_curvature: float = 0.0
    length: float | None = None
    sides: tuple[ContactSide, ...] = ()
    roller_radius: float | None = None
    rollers: tuple[str, ...] = ("the roller",)
    note: str | None = None

    @property
    def computable(self) -> bool:
        return self.shape != "none" and self.note is None


def contact_length(design: Design) -> tuple[float | None, str | None]:
    """The length of a line contact (mm): the overlap of the cam's extent across the
    follower's motion (a plate's thickness, a groove's depth: its type's
    :attr:`~camfab.design.cam_types.CamTypeSpec.contact_extent`) and a roller's length; with
    neither, None and the reason."""
    length = design.contact_length
    if length is None:
        roller = " or follower.roller_length" if design.follower.type == "roller" else ""
        return None, (f"the contact's length is not known: give "
                      f"cam.{design.cam.spec.contact_extent}{roller}")
    return length, None


@dataclass(frozen=True)
class ContactStress:
    """The Hertz stress over the cycle (MPa; 0 where the side is unloaded) at the grid angles
    ``theta`` (rad), the side carrying (an index into ``sides``; −1 where none does) and the
    row of the contact line where it is largest; the effective modulus E* (MPa)."""

    theta: Array
    stress: Array
    side: Index
    row: Index
    contact: Contact
    modulus: float

    @property
    def index(self) -> int:
        """The grid index of the largest stress."""
        return int(np.argmax(self.stress))

    @property
    def max_MPa(self) -> float:
        return float(self.stress[self.index])

    @property
    def max_at_deg(self) -> float:
        return round(math.degrees(float(self.theta[self.index])), 9) + 0.0

    @property
    def max_side(self) -> ContactSide | None:
        side = int(self.side[self.index])
        return self.contact.sides[side] if side >= 0 else None

    def cam_radius_at(self, index: int) -> float:
        """The cam's radius of curvature at the contact at grid *index* (mm, convex positive;
        ±inf straight): a plate's profile's, or the inverse of a flank's curvature across the
        contact line (the sum of its principal curvatures)."""
        side = self.contact.sides[max(int(self.side[index]), 0)]
        curvature = side.curvature
        value = float(curvature[int(self.row[index]), index] if curvature.ndim == 2
                      else curvature[index])
        return math.inf if value == 0.0 else 1.0 / value

    def shape_at(self, index: int) -> str:
        """The cam's shape at the contact at grid *index*: ``convex``, ``concave`` or
        ``straight`` as its material sees it."""
        rho = self.cam_radius_at(index)
        return "straight" if math.isinf(rho) else "convex" if rho > 0 else "concave"

    def shape_words(self, index: int) -> str:
        """The cam at the contact at grid *index* in words: a plate's profile, convex or
        concave with its radius of curvature, or straight; a flank (a surface) by how it
        curves across the contact line."""
        rho, shape = self.cam_radius_at(index), self.shape_at(index)
        side = self.contact.sides[max(int(self.side[index]), 0)]
        if side.rows is None:
            return ("the cam is straight" if shape == "straight" else
                    f"the cam is {shape}, of radius of curvature {abs(rho):.4g} mm")
        return ("the flank is straight across the contact line" if shape == "straight" else
                f"the flank curves across the contact line as a {shape} radius of "
                f"{abs(rho):.4g} mm")

    def where_words(self) -> str:
        """Where the largest stress is: the side, its point on the cam or along the line."""
        k = self.index
        side = self.max_side
        if side is None:
            return ""
        words = side.name
        if side.place is not None:
            x, y = side.place[k]
            words += f" at ({x:.4g}, {y:.4g}) mm in {side.frame}"
        if side.rows is not None:
            words += f", {side.rows[int(self.row[k])]:.4g} mm {side.rows_from}"
        return words


def contact_stress(design: Design, contact: Contact, force: Array) -> ContactStress | None:
    """The stress of *contact* under the force along the follower's motion *force* (N, at
    the contact's grid angles), or None where it cannot be computed."""
    if not contact.computable:
        return None
    e1, nu1 = design.materials.constants("cam")
    e2, nu2 = design.materials.constants("follower")
    modulus = effective_modulus(e1, nu1, e2, nu2)
    n = contact.theta.size
    best = np.zeros(n)
    side_of = np.full(n, -1, dtype=np.intp)
    row_of = np.zeros(n, dtype=np.intp)
    for k, side in enumerate(contact.sides):
        load = np.where(side.carries * force > 0.0, np.abs(force) * side.normal, 0.0)
        curvature = np.atleast_2d(side.curvature)
        if contact.shape == "point":
            stress = point_contact(load, curvature + contact.follower_curvature,
                                   contact.follower_curvature, modulus)[0]
        else:
            assert contact.length is not None
            stress = line_contact(load, contact.length, curvature + contact.follower_curvature,
                                  modulus)[0]
        # surfaces that conform or cross (a cam hollower than the roller: an undercut) bear a
        # load nowhere Hertz measures: unbounded where loaded
        stress = np.where(load > 0.0, np.nan_to_num(stress, nan=np.inf), 0.0)
        row = np.argmax(stress, axis=0)
        stress = stress[row, np.arange(n)]
        better = (load > 0.0) & (stress > best)
        best = np.where(better, stress, best)
        side_of = np.where(better, k, side_of)
        row_of = np.where(better, row, row_of)
    return ContactStress(contact.theta, best, side_of, row_of, contact, modulus)


@dataclass(frozen=True)
class RollerLife:
    """The basic rating life of each roller's bearing at the design speed: its revolutions per
    turn of the cam, the equivalent load over the turn P = (Σ Fᵖ Δn / Σ Δn)^(1/p) (N) and L₁₀
    (hours; inf for a roller that carries nothing), for the rollers ``names``."""

    names: tuple[str, ...]
    revolutions: tuple[float, ...]
    load_N: tuple[float, ...]
    hours: tuple[float, ...]

    @property
    def least(self) -> int:
        return int(np.argmin(self.hours))

    @property
    def hours_min(self) -> float:
        return self.hours[self.least]


def roller_life(design: Design, contact: Contact, force: Array) -> RollerLife | None:
    """L₁₀ of the rollers of *contact* under the force along the follower's motion *force*
    (N), or None without a load rating, a roller or a speed (ISO 281: L₁₀ = (C/P)ᵖ·10⁶
    revolutions, p = 10/3 for a needle or roller bearing, 3 for a ball bearing)."""
    fol, speed = design.follower, design.cam.speed_rpm
    rating, radius = fol.roller_load_rating, contact.roller_radius
    if rating is None or radius is None or speed is None or not contact.sides:
        return None
    p = fol.life_exponent
    weights = trapezoid_weights(contact.theta)
    names = contact.rollers
    revolutions, loads, hours = [], [], []
    for roller in range(len(names)):
        turns = np.zeros(contact.theta.size)
        work = np.zeros(contact.theta.size)
        for side in contact.sides:
            if side.roller != roller or side.rolling is None:
                continue
            carrying = side.carries * force > 0.0
            load = np.where(carrying, np.abs(force) * side.normal, 0.0)
            rides = np.ones_like(carrying) if side.always else carrying
            dn = np.where(rides, side.rolling, 0.0) * weights / (2.0 * math.pi * radius)
            turns += dn
            work += load**p * dn
        total = float(turns.sum())
        equivalent = (float(work.sum()) / total) ** (1.0 / p) if total > 0.0 else 0.0
        revolutions.append(total)
        loads.append(equivalent)
        life = (rating / equivalent) ** p * 1e6 if equivalent > 0.0 else math.inf
        hours.append(life / (total * speed * 60.0) if total > 0.0 else math.inf)
    return RollerLife(names, tuple(revolutions), tuple(loads), tuple(hours))


def trapezoid_weights(theta: Array) -> Array:
    """The trapezoid rule's weights (rad) on the grid *theta* (a joint twice: its step is 0)."""
    step = np.diff(theta)
    weights = np.zeros(theta.size)
    weights[:-1] += 0.5 * step
    weights[1:] += 0.5 * step
    return weights
