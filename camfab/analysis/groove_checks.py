"""Checks of a groove cam (THEORY §F): both walls must be true offsets of the pitch curve, and a
milling cutter must fit the groove.

The disc cam's checks of pressure angle and continuity stay as they are. The ``groove`` check —
|ρ_p| > R on convex and concave stretches alike, R the roller radius plus half the clearance —
takes the place of the disc's ``undercut`` check, which speaks of the inner wall alone and of
the roller's radius without the clearance; and the groove's ``cutter`` check (the cutter runs
inside the groove) that of the disc's, which assumes a cutter outside the outline.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.cam_checks import fmt, where
from camfab.analysis.findings import Finding
from camfab.angles import Extreme, extreme, merge, ranges_deg
from camfab.geometry.groove import GrooveWalls, groove_walls, wall_lift_check

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis


def with_groove(analysis: Analysis) -> tuple[GrooveWalls, list[Finding]]:
    """The groove's walls of *analysis* (a disc cam's, its working curve the inner wall) and its
    findings: the ``groove`` check takes the place of the disc's ``undercut`` (which speaks of
    the inner wall alone), and the groove's ``cutter`` check that of the disc's."""
    geom = analysis.geometry
    assert geom is not None
    walls = groove_walls(analysis.design, geom)
    at = next((i for i, f in enumerate(analysis.findings) if f.id == "undercut"), 0)
    findings = [f for f in analysis.findings if f.id not in ("undercut", "cutter", "kerf")]
    found = [groove_finding(analysis, walls), cutter_finding(analysis, walls)]
    findings[at:at] = [f for f in found if f is not None]
    return walls, findings


def groove_finding(analysis: Analysis, walls: GrooveWalls) -> Finding:
    """Both walls offsets of the pitch curve: |ρ_p| > R on convex and concave stretches, and
    neither wall crossing itself; else where each folds and the motion error of the walls
    written (the boundary of the roller's sweep)."""
    theta, rho, radius = walls.dense_theta, walls.pitch_radius, walls.radius
    convex = extreme(theta, rho, rho > 0, largest=False)
    concave = extreme(theta, -rho, rho < 0, largest=False)
    values = [v for v in (convex.value, concave.value) if v is not None]
    value = min(values) if values else None
    size = (f"the groove's half width R = {fmt(radius)} mm (roller {fmt(walls.roller_radius)} mm "
            f"+ half the clearance {fmt(walls.clearance / 2)} mm)")

    def side(smallest: Extreme, name: str) -> str:
        if smallest.value is None:
            return f"no {name} stretch"
        return f"smallest {name} radius {fmt(smallest.value)} mm at {fmt(smallest.at_deg or 0.0)}°"

    if not walls.folded:
        return Finding("groove", True, "error",
                       f"the pitch curve bends less sharply than {size} everywhere "
                       f"({side(convex, 'convex')}, {side(concave, 'concave')}): both walls are "
                       f"true offsets of it", value, radius, "mm")
    geom = analysis.geometry
    assert geom is not None
    inner = ranges_deg(theta, walls.inner_folds)
    outer = ranges_deg(theta, walls.outer_folds)
    causes = []
    if inner:
        causes.append(f"its convex radius falls to {fmt(convex.value or 0.0)} mm at "
                      f"{where(inner)}: the inner wall folds over (an undercut)")
    elif walls.inner_trimmed:
        inner = ranges_deg(geom.working.theta, geom.cut) or inner
        causes.append(f"the inner wall crosses itself at {where(inner)}")
    if outer:
        causes.append(f"its concave radius falls to {fmt(concave.value or 0.0)} mm at "
                      f"{where(outer)}: the outer wall folds over")
    crossing: tuple[tuple[float, float], ...] = ()
    if walls.outer_crossing and not outer:
        crossing = _crossing_ranges(walls)
        causes.append(f"the outer wall crosses itself at {where(crossing)}")
    error = wall_lift_check(geom.cam, analysis.program, radius, walls.inner, walls.outer)
    folds = walls.inner_folds.any() or walls.outer_folds.any()
    least = value if value is not None else radius
    if folds:
        lead = f"the pitch curve bends more sharply than {size}"
        advice = (f"a roller radius + half clearance below {fmt(least)} mm, a larger base "
                  f"radius or a longer rise or return avoids it")
    else:
        lead = f"the roller cannot follow the pitch curve in a groove {fmt(walls.width)} mm wide"
        advice = ("a corner of the pitch curve (a velocity step) or two stretches of the groove "
                  f"closer than its width {fmt(walls.width)} mm make a wall cross itself: a "
                  "motion law without a velocity step, or a larger base radius, avoids it")
    return Finding("groove", False, "error",
                   f"{lead}: {'; '.join(causes)}; the walls written are the boundary of the "
                   f"roller's sweep, and they move the follower up to {fmt(error.max_mm)} mm "
                   f"off the design at {fmt(error.at_deg)}°; {advice}", value, radius, "mm",
                   merge([*inner, *outer, *crossing]))


def _crossing_ranges(walls: GrooveWalls) -> tuple[tuple[float, float], ...]:
    """Where the exact outer wall strays from the trimmed one written (the loops cut away)."""
    import shapely

    ring = shapely.LinearRing(walls.outer_points)
    far = shapely.distance(ring, shapely.points(walls.outer_dense.xy)) > 1e-3 * walls.radius
    return ranges_deg(walls.dense_theta, np.asarray(far, dtype=bool))


def cutter_finding(analysis: Analysis, walls: GrooveWalls) -> Finding | None:
    """Does a milling cutter of ``cutter_radius`` fit the groove? It must be no wider than the
    groove; then, with walls that do not fold, it follows both of them (seen from inside the
    groove, a wall's concave radius is |ρ_p| + R, never below R)."""
    cutter = analysis.design.manufacturing.cutter_radius
    if cutter <= 0.0:
        return None
    radius = walls.radius
    if cutter > radius:
        return Finding("cutter", False, "error",
                       f"a cutter of radius {fmt(cutter)} mm is wider than the groove "
                       f"({fmt(walls.width)} mm): a cutter radius of at most {fmt(radius)} mm "
                       f"mills it", cutter, radius, "mm")
    path = ("its centre runs along the pitch curve" if cutter == radius else
            f"its centre runs {fmt(radius - cutter)} mm either side of the pitch curve, one "
            f"pass along each wall (TOOLPATH)")
    return Finding("cutter", True, "error",
                   f"a cutter of radius {fmt(cutter)} mm fits the groove ({fmt(walls.width)} mm "
                   f"wide): {path}", cutter, radius, "mm")
