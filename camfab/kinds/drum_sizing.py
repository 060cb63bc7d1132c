"""The sizing of a drum cam's radius (mm): the pressure angle at the groove's floor, the developed
groove's curvature, the contact stress and the roller's life at speed where the design limits
them, and the wall the design file's rules ask for (:mod:`camfab.analysis.sizing` searches it).
"""

from __future__ import annotations

import math

import numpy as np

from camfab.analysis.sizing import SEARCH_FACTOR, Grid, LimitValue, SizeProblem, passes
from camfab.design import Design
from camfab.geometry.drum import Drum


def drum_problem(design: Design, grid_pair: tuple[Grid, Grid]) -> SizeProblem:
    """The sizing of a drum's radius (mm): the pressure angle at the groove's floor (tan φ =
    s′/r), the developed groove's curvature against the roller at every radius of the groove
    (the build's ``groove`` check), the contact stress on the flanks and the roller bearing's
    life where the design limits them, and the drum's fit as the design file's rules judge it: a
    wall under the groove, round the bore and beyond the keyway. Measured on *grid_pair* (the
    build's grid of cam angles, and with a finer one)."""
    from dataclasses import replace

    from camfab.design.rules import MIN_WALL_MM, wall_need
    from camfab.geometry.drum import ANALYSIS_RADII
    from camfab.speed.life_sizing import LifeSide, life_limit
    from camfab.speed.stress_sizing import stress_limit

    cam = design.cam
    program = design.program
    depth = cam.groove_depth or 0.0
    limit_deg = math.degrees(design.pressure_angle_limit)
    wall = f"a {MIN_WALL_MM:g} mm wall"
    needs = [("depth", f"{wall} under the groove", wall_need(depth=depth))]
    if cam.bore is not None:
        needs.append(("bore", f"{wall} between the bore and the groove's floor",
                      wall_need(cam.bore, depth)))
        if cam.keyway is not None:
            needs.append(("keyway", f"{wall} beyond the keyway",
                          wall_need(cam.bore, cam.keyway.depth)))
    # the drum of the design at radius 1: only its radius changes
    base = replace(_drum_of(design), radius=1.0)
    stress = stress_limit(design, grid_pair)
    life = life_limit(design, grid_pair)

    def evaluate(radius: float, fine: bool, until: bool = False) -> list[LimitValue]:
        fit = [LimitValue(key, what, radius >= need, radius, need, least=need, of_size=True)
               for key, what, need in needs]
        if not all(limit.ok for limit in fit):
            return fit
        grid = grid_pair[fine]
        drum = replace(base, radius=radius)
        theta, ds, dds = grid.theta, grid.motion[1], grid.motion[2]
        phi = np.degrees(np.abs(drum.pressure_angle(ds, drum.root)))
        k = int(np.argmax(phi))
        worst_ds = float(np.max(np.abs(ds)))
        least = depth + worst_ds / math.tan(design.pressure_angle_limit)
        size = np.abs(np.stack([drum.developed_radius(ds, dds, r) for r in
                                np.linspace(drum.root, drum.radius, ANALYSIS_RADII)]))
        row, col = np.unravel_index(int(np.argmin(size)), size.shape)
        out = [*fit,
               LimitValue("pressure_angle", "pressure angle at the groove's floor",
                          not bool((phi > limit_deg).any()), float(phi[k]), limit_deg, "deg",
                          "max", math.degrees(float(theta[k])), least=least),
               LimitValue("groove", "the developed groove's radius of curvature against the "
                          "roller", not bool((size <= drum.roller).any()),
                          float(size[row, col]), drum.roller, "mm", "min",
                          math.degrees(float(theta[col])))]
        if (stress is None and life is None) or (until and not passes(out)):
            return out
        # the flanks as the build's contact has them (camfab.kinds.drum)
        radii = np.linspace(drum.root, drum.radius, ANALYSIS_RADII)[:, None]
        normal = 1.0 / np.mean(np.cos(drum.pressure_angle(ds, radii)), axis=0)
        if stress is not None:
            out.append(stress.at(grid, fine, [
                (1, drum.flank_curvature(ds, dds, radii, True), normal),
                (-1, drum.flank_curvature(ds, dds, radii, False), normal)]))
        if life is not None and not (until and not passes(out)):
            # the roller rolls along the groove at its pitch radius, on the flank that carries
            rolling = np.hypot(drum.pitch, ds)
            out.append(life.at(grid, [LifeSide(1, normal, rolling, always=False),
                                      LifeSide(-1, normal, rolling, always=False)]))
        return out

    low = max(need for _, _, need in needs)
    return SizeProblem("radius", evaluate, low, low + SEARCH_FACTOR * program.max_lift)


def _drum_of(design: Design) -> Drum:
    """The drum of *design*, whose radius may be left to the sizing (taken as its depth)."""
    from camfab.geometry.drum import drum

    cam = design.cam
    if cam.radius is not None:
        return drum(design)
    return drum(design.model_copy(update={"cam": cam.model_copy(
        update={"radius": cam.groove_depth})}))
