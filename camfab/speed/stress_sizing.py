"""The contact stress as a limit of the sizing (:mod:`camfab.analysis.sizing`): the largest Hertz
stress at a trial size against ``limits.contact_stress``, measured as the build measures it
(:mod:`camfab.speed.contact`) on the sizing's grids.

The force along the follower's motion does not depend on the cam's size (its mass, spring and
motion do not), so it is computed once per sizing on each grid; at each trial size only the
cam's curvature under the follower and the pressure angle change. Stresses in MPa, lengths in
mm, angles in degrees.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.sizing import Grid, LimitValue
from camfab.arrays import Array
from camfab.speed.hertz import effective_modulus, line_contact, point_contact

if TYPE_CHECKING:
    from camfab.design import Design


@dataclass(frozen=True)
class StressLimit:
    """What a sizing needs to hold a cam to ``limits.contact_stress``: the limit and the
    contact's effective modulus (MPa), its shape (line or point), the follower's curvature
    across it (1/mm) and its length (mm), and the force along the follower's motion (N) on
    each of the sizing's grids (the build's, and with the finer one)."""

    limit: float
    modulus: float
    shape: str
    follower_curvature: float
    length: float | None
    forces: tuple[Array, Array]

    def at(self, grid: Grid, fine: bool, sides: Sequence[tuple[int, Array, Array]],
           suffix: str = "") -> LimitValue:
        """The largest stress over *grid* (the sizing's grid *fine* or not) of the cam's
        *sides*: (+1 where the force along the motion is positive, −1 where negative; the
        cam's curvature at the contact, 1/mm, (N,) or (rows, N); the normal force per newton
        along the motion)."""
        force = self.forces[fine]
        worst = np.zeros(force.size)
        for carries, curvature, normal in sides:
            load = np.where(carries * force > 0.0, np.abs(force) * normal, 0.0)
            total = np.atleast_2d(curvature) + self.follower_curvature
            if self.shape == "point":
                stress = point_contact(load, total, self.follower_curvature, self.modulus)[0]
            else:
                assert self.length is not None
                stress = line_contact(load, self.length, total, self.modulus)[0]
            # surfaces that conform or cross bear a load nowhere Hertz measures: past any limit
            # where loaded, as the build's stress sees it (contact.contact_stress)
            stress = np.where(load > 0.0, np.nan_to_num(stress, nan=np.inf), 0.0)
            worst = np.fmax(worst, np.max(stress, axis=0))
        k = int(np.argmax(worst))
        return LimitValue("contact_stress" + suffix, "the contact stress",
                          not bool((worst > self.limit).any()), float(worst[k]), self.limit,
                          "MPa", "max", math.degrees(float(grid.theta[k])))


def stress_limit(design: Design, grid_pair: tuple[Grid, Grid]) -> StressLimit | None:
    """The contact stress as a limit of *design*'s sizing on *grid_pair*, or None where the
    design gives no ``limits.contact_stress`` (the design file's rules refuse one whose stress
    cannot be computed: a knife, no force, a contact of unknown length)."""
    from camfab.speed.contact import contact_length

    limit, fol = design.limits.contact_stress, design.follower
    held_by_spring = design.spring is not None
    if limit is None:
        return None
    length, _ = contact_length(design)
    e1, nu1 = design.materials.constants("cam")
    e2, nu2 = design.materials.constants("follower")
    radius = {"roller": fol.roller_radius, "mushroom": fol.face_radius}.get(fol.type)
    return StressLimit(limit, effective_modulus(e1, nu1, e2, nu2),
                       "point" if fol.type == "mushroom" else "line",
                       0.0 if radius is None else 1.0 / radius, length,
                       forces(design, grid_pair, held_by_spring))


#: The forces of the last few sizings' grids, by the ids of the design and the grids (held, so
#: the ids stay theirs): a search for an offset or a pivot sizes the same design some hundred
#: times, and an elastic train's response costs a few milliseconds a grid.
_FORCES: dict[tuple[int, int, int], tuple[object, tuple[Grid, Grid], tuple[Array, Array]]] = {}


def forces(design: Design, grid_pair: tuple[Grid, Grid],
           held_by_spring: bool) -> tuple[Array, Array]:
    """The force along the follower's motion (N) on the pair's grids: the build's, and the
    build's followed by the finer one's, each solved on its own (an elastic train's response
    runs over one turn); the roller life's sizing takes the build's
    (:mod:`camfab.speed.life_sizing`)."""
    from camfab.speed.model import drive_force

    build, both = grid_pair
    key = (id(design), id(build), id(both))
    hit = _FORCES.get(key)
    if hit is not None and hit[0] is design and hit[1][0] is build and hit[1][1] is both:
        return hit[2]
    first = drive_force(design, build.theta, build.motion, held_by_spring)
    count = build.theta.size
    if both.theta.size == count:
        both_forces = (first, first)
    else:
        rest = drive_force(design, both.theta[count:], both.motion[:, count:], held_by_spring)
        both_forces = (first, np.concatenate((first, rest)))
    if len(_FORCES) >= 8:
        _FORCES.pop(next(iter(_FORCES)))
    _FORCES[key] = (design, grid_pair, both_forces)
    return both_forces


def plate_sides(cam_radius: Array, normal: Array, groove_radius: float | None,
                pitch_radius: Array | None) -> list[tuple[int, Array, Array]]:
    """A plate's sides for :meth:`StressLimit.at`: its profile of radius of curvature
    *cam_radius* (mm) carrying where the force is positive, and for a groove of half width
    *groove_radius* its outer wall (−(ρ_p + R), of the pitch radius *pitch_radius*) where it
    is negative."""
    with np.errstate(divide="ignore"):
        sides = [(1, 1.0 / cam_radius, normal)]
        if groove_radius is not None:
            assert pitch_radius is not None
            sides.append((-1, -1.0 / (pitch_radius + groove_radius), normal))
    return sides
