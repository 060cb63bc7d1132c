"""A globoidal cam's blank and groove (docs/THEORY.md §H): where the groove lies along the arm,
the blank's half-section, the groove's tube sampled to the tolerance, the roller's end sweeping
the floor, and the centre path developed (the roller run through a groove read back:
:mod:`camfab.geometry.globoid_run`).

Distances along the arm are from the pivot (mm). ``inward`` is +1 for a concave globoid (the
roller reaches from the pivot toward the cam axis: the cam's inside lies farther from the pivot)
and −1 for a convex one (the cam's inside lies nearer the pivot). The blank's surface is the
circle of radius ``surface`` about the pivot in every plane through the cam axis, revolved; the
groove runs from it ``depth`` inward to its floor.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array, Index
from camfab.curves.sampling import (
    SURFACE_ACROSS,
    ahead_and_middle,
    probe_angles,
    spread,
    spread_count,
)
from camfab.geometry.globoid import Globoid, groove_tube, to_cam
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.motion.program import MotionProgram

#: Cam-angle step of the analysis' dense grid (rad), as for the drum.
ANALYSIS_STEP = math.radians(0.05)
#: Distances along the roller's contact line at which the analysis measures (count).
ANALYSIS_ROWS = 9
#: How far the floor stands past the farthest reach of the roller's end face (mm): a running
#: clearance, so that the floor never touches the roller.
FLOOR_GAP_MM = 0.5
#: How far outside the blank the groove's tube reaches (mm, at least), so that the subtraction
#: cuts cleanly through the blank's surface instead of grazing it.
TOP_MARGIN_MM = 1.0
#: Largest step of cam angle between the tube's stations (rad), however straight it runs.
MAX_STATION_STEP = math.radians(1.0)
#: The most rows along the arm the tube takes (count).
MAX_ROWS = 257
#: Cam-angle step at which the roller is run through the groove read back (rad).
VERIFY_STEP = math.radians(0.5)


@dataclass(frozen=True)
class GloboidCam:
    """A globoidal cam: the follower's geometry (:class:`Globoid`) and the blank's (mm)."""

    follower: Globoid
    inward: float
    surface: float
    depth: float
    width: float
    bore: float

    @property
    def floor(self) -> float:
        """The groove's floor: its distance from the pivot along the arm (mm)."""
        return self.surface + self.inward * self.depth

    @property
    def outer_radius(self) -> float:
        """The blank's radius at its waist (concave) or crown (convex) (mm)."""
        return abs(self.follower.centre - self.surface)

    @property
    def roller_outer(self) -> float:
        """The roller's end the arm holds: its distance from the pivot (mm)."""
        g = self.follower
        return g.arm - self.inward * g.length / 2.0

    @property
    def roller_inner(self) -> float:
        """The roller's end inside the groove: its distance from the pivot (mm)."""
        g = self.follower
        return g.arm + self.inward * g.length / 2.0

    def contact(self, count: int = ANALYSIS_ROWS) -> Array:
        """*count* distances from the pivot (mm) along the roller inside the groove: from the
        blank's surface (or the roller's outer end, if inside it) to its inner end."""
        outside = self.inward * (self.surface - self.roller_outer) > 0
        start = self.surface if outside else self.roller_outer
        return np.linspace(start, self.roller_inner, count)

    def radius_at(self, ell: Array, psi: Array) -> Array:
        """The distance (mm) from the cam axis of the roller axis' point *ell* from the pivot
        with the arm at *psi*: |C − ℓ cos ψ|."""
        return np.abs(self.follower.centre - ell * np.cos(psi))

    def ends_radius(self) -> float:
        """The blank's radius at its end faces (mm), z = ±width/2."""
        c, s, half = self.follower.centre, self.surface, self.width / 2.0
        root = math.sqrt(max(s * s - half * half, 0.0))
        return c - root if self.inward > 0 else root - c

    def section(self) -> Profile:
        """The blank's half-section in (r, z) (mm), counter-clockwise: the end face at
        z = −width/2, the surface (an exact arc about the pivot: at r = C for a concave
        globoid, at r = −C, mirrored, for a convex one), the end face at +width/2, and the bore
        (or the axis)."""
        from camfab.curves.profile import Profile

        half = self.width / 2.0
        end = self.ends_radius()
        # the arc from (end, −half) up to (end, +half): about (C, 0) clockwise through the
        # waist (concave), about (−C, 0) counter-clockwise through the crown (convex)
        sweep = -self.inward * 2.0 * math.asin(min(1.0, half / self.surface))
        vertices = np.array([[self.bore, -half], [end, -half], [end, half], [self.bore, half]])
        bulges = np.array([0.0, math.tan(sweep / 4.0), 0.0, 0.0])
        return Profile(vertices, bulges)

    def tube_span(self) -> tuple[float, float]:
        """The tube's top (outside the blank) and floor, along the arm (mm)."""
        g = self.follower
        margin = TOP_MARGIN_MM + g.radius * g.radius / self.surface
        return self.surface - self.inward * margin, self.floor


@lru_cache(maxsize=4)
def globoid_cam(design: Design) -> GloboidCam:
    """The globoidal cam of *design* (validated): its blank's size as given or by default
    (:func:`default_surface`, :func:`default_width`). Kept for the last few designs: the kind's
    rules ask for it as the design is loaded, its analysis again (the default floor's search
    costs some 0.1 s)."""
    cam, program = design.cam, design.program
    follower = follower_of(design, program)
    inward = 1.0 if cam.globoid == "concave" else -1.0
    depth = cam.groove_depth or 0.0
    bore = (cam.bore or 0.0) / 2.0
    surface = (follower.centre - inward * cam.outer_radius if cam.outer_radius is not None
               else default_surface(follower, inward, depth, program))
    blank = GloboidCam(follower, inward, surface, depth, 0.0, bore)
    width = cam.width if cam.width is not None else default_width(blank, program)
    return GloboidCam(follower, inward, surface, depth, width, bore)


def follower_of(design: Design, program: MotionProgram) -> Globoid:
    """The follower of *design* as a :class:`Globoid` (the wall's radius: the roller's and half
    the clearance; ψ₀ as given, or minus half the largest swing)."""
    cam, fol = design.cam, design.follower
    assert fol.pivot_distance is not None and fol.arm_length is not None
    assert fol.roller_length is not None and fol.roller_radius is not None
    rest = fol.rest_angle if fol.rest_angle is not None else -program.max_lift / 2.0
    return Globoid(fol.pivot_distance, fol.arm_length, fol.roller_length,
                   fol.roller_radius + fol.groove_clearance / 2.0, rest, cam.sigma)


def default_surface(g: Globoid, inward: float, depth: float, program: MotionProgram) -> float:
    """The blank's surface (mm from the pivot) that puts the groove's floor
    :data:`FLOOR_GAP_MM` past the farthest reach of the roller's end face."""
    inner = g.arm + inward * g.length / 2.0
    floor = inner + inward * (end_reach(g, inner, program) + FLOOR_GAP_MM)
    return floor - inward * depth


def default_width(blank: GloboidCam, program: MotionProgram) -> float:
    """The blank's width along its axis (mm): the groove's extent, with a wall of the roller's
    radius beyond it at each end (at least 3 mm)."""
    _, _, z = groove_extent(blank, program)
    return 2.0 * (z + max(blank.follower.radius, 3.0))


def groove_extent(blank: GloboidCam, program: MotionProgram) -> tuple[float, float, float]:
    """The groove inside the blank (mm): the least distance of its floor from the cam axis,
    the least distance of a flank point from it (the floor's corners), and the largest |z| of
    any point of its flanks between the blank's surface and its floor."""
    g = blank.follower
    _, _, m = program.segment_grid(ANALYSIS_STEP * 4)
    psi = g.rest + m[0]
    ell = np.linspace(blank.surface, blank.floor, 5)[:, None]
    floor_r = blank.radius_at(np.asarray(blank.floor), psi)
    z = []
    corner = np.inf
    for side in (1, -1):
        p = g.flank(0.0, ell, m, side)  # (as at θ = 0: the distances do not turn with the cam)
        z.append(float(np.max(np.abs(p[..., 2]))))
        corner = min(corner, float(np.min(np.hypot(p[-1, :, 0], p[-1, :, 1]))))
    return float(np.min(floor_r)), corner, max(z)


def end_reach(g: Globoid, inner: float, program: MotionProgram) -> float:
    """How far past the roller's inner end *inner* (mm from the pivot) its end face reaches
    the groove's sections at other cam angles (mm, along the arm): the tube's sections are
    strips across the flanks at each cam angle, and as the arm tilts the end face's rim lies on
    the sections of nearby angles beyond the end. The floor must stand past this.

    Each point of the rim (and of a ring at half its radius), fixed on the cam at the pose
    θ, is followed to the cam angle θ′ at which it lies in that section's plane (a, n) by the
    secant method, where its distance along the arm is read."""
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    beta = np.linspace(0.0, 2 * math.pi, 25)[:-1]
    m = program.evaluate(theta)
    psi = g.rest + m[0]
    a = g.axis_direction(psi)
    n = g.normal(np.full(theta.size, inner), psi, m[1])
    b = np.cross(a, n)
    q = g.axis_point(np.full(theta.size, inner), psi)
    reach = 0.0
    inward = 1.0 if g.concave else -1.0
    for share in (1.0, 0.5):
        ring = (np.cos(beta)[None, :, None] * n[:, None, :]
                + np.sin(beta)[None, :, None] * b[:, None, :])
        x = to_cam(q[:, None, :] + share * g.radius * ring, g.sigma * theta[:, None])
        t0 = np.broadcast_to(theta[:, None], x.shape[:2])

        def off(t: Array, x: Array = x) -> tuple[Array, Array]:
            """The point's distance from the plane (a, n) at cam angle t, and along the arm."""
            flat = program.evaluate(t.ravel()).reshape(4, *t.shape)
            p = to_cam(x, -g.sigma * t)  # the point in the frame at t
            ps = g.rest + flat[0]
            axis = g.axis_direction(ps)
            rel = p - np.array([g.centre, 0.0, 0.0])
            along = np.einsum("...i,...i->...", rel, axis)
            normal = g.normal(along, ps, flat[1])
            return np.einsum("...i,...i->...", rel, np.cross(axis, normal)), along

        lo, hi = t0 - 0.02, t0 + 0.02
        f_lo, _ = off(lo)
        f_hi, _ = off(hi)
        for _ in range(30):
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.where(np.abs(f_hi - f_lo) > 1e-15,
                             hi - f_hi * (hi - lo) / (f_hi - f_lo), hi)
            t = np.clip(t, t0 - 0.5, t0 + 0.5)
            f_t, along = off(t)
            lo, f_lo, hi, f_hi = hi, f_hi, t, f_t
            if float(np.max(np.abs(f_t))) < 1e-9:
                break
        _, along = off(hi)
        reach = max(reach, float(np.max(inward * (along - inner))))
    return max(reach, 0.0)


def stations(blank: GloboidCam, program: MotionProgram, rows: Array, tolerance: float) -> Array:
    """Cam angles (rad, one turn, every segment's start included) at which the tube's chords
    along both flanks, on every row of *rows* (mm from the pivot), stay within *tolerance*
    (mm) of the exact flanks: placed by the chord error c²/(8ρ) of each row's path on the cam,
    then every chord measured at its middle and the stations halved where one strays."""
    return _halved(blank, program, rows, tolerance,
                   spread(*_station_density(blank, program, rows, tolerance),
                          len(program.segments)))


def _station_density(blank: GloboidCam, program: MotionProgram, rows: Array,
                     tolerance: float) -> tuple[Index, Array, Array]:
    """The stations a radian needs (1/rad) on the program's segment grid, by the chord error
    c²/(8ρ) of each row's path (see :func:`stations`): its segment index, cam angle (rad) and
    density."""
    g = blank.follower
    even = cycle_angles(ANALYSIS_STEP)  # evenly spaced, for the differences
    m = program.evaluate(even)
    density = np.zeros(even.size)
    ell = np.asarray(rows)[:, None]
    step = float(even[1] - even[0])
    for side in (1, -1):
        p = g.flank(even[None, :], ell, m[:, None, :], side)
        ahead, behind = np.roll(p, -1, axis=1), np.roll(p, 1, axis=1)
        d1 = (ahead - behind) / (2 * step)
        d2 = (ahead - 2 * p + behind) / (step * step)
        speed = np.linalg.norm(d1, axis=-1)
        bend = np.linalg.norm(np.cross(d1, d2), axis=-1) / np.maximum(speed, 1e-12) ** 3
        # a chord Δθ long strays (speed·Δθ)²·bend/8: the stations a radian needs
        need = speed * np.sqrt(np.maximum(bend, 0.0) / (8.0 * tolerance))
        density = np.maximum(density, need.max(axis=0))
    segment, theta, _ = program.segment_grid(ANALYSIS_STEP)
    density = np.interp(theta, even, density, period=2 * math.pi)
    density = np.maximum(density, 1.0 / MAX_STATION_STEP)
    return segment, theta, density


def _halved(blank: GloboidCam, program: MotionProgram, rows: Array, tolerance: float,
            placed: Array, most: int | None = None) -> Array:
    """The stations *placed* (rad) with every chord that strays further than *tolerance* (mm)
    from the flanks on *rows* halved, round after round (at most eight); with *most*, no
    further once they are more than that (count)."""
    g = blank.follower
    ell = np.asarray(rows)[:, None]
    for _ in range(8):  # halve the chords that stray
        if most is not None and placed.size > most:
            break
        ahead, middle = ahead_and_middle(placed)
        motion = [program.evaluate(t)[:, None, :] for t in (placed, ahead, middle)]
        worst = np.zeros(placed.size)
        for side in (1, -1):
            a, c, mid = (g.flank(t[None, :], ell, m, side)
                         for t, m in zip((placed, ahead, middle), motion, strict=True))
            worst = np.maximum(worst, _chord_miss(mid, a, c).max(axis=0))
        stray = worst > tolerance
        if not stray.any():
            break
        placed = np.sort(np.concatenate((placed, np.mod(middle[stray], 2 * math.pi))))
    return placed


def _chord_miss(points: Array, start: Array, end: Array) -> Array:
    """Distance (mm) of each of *points* (..., 3) from the segment *start*–*end*."""
    d = end - start
    rel = points - start
    length2 = np.einsum("...i,...i->...", d, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip(np.where(length2 > 0, np.einsum("...i,...i->...", rel, d) / length2, 0.0),
                    0.0, 1.0)
    return np.linalg.norm(rel - t[..., None] * d, axis=-1)


def tube_rows(blank: GloboidCam, program: MotionProgram, tolerance: float) -> Array:
    """Distances from the pivot (mm) of the tube's rows, from its top outside the blank to the
    floor: as many equal steps as keep the straight pieces between rows within *tolerance*
    (mm) of the exact flanks at every cam angle."""
    g = blank.follower
    top, floor = blank.tube_span()
    _, _, m = program.segment_grid(ANALYSIS_STEP * 4)
    count = 2
    while True:
        rows = np.linspace(top, floor, count + 1)
        worst = 0.0
        for side in (1, -1):
            p = g.flank(0.0, rows[:, None], m[:, None, :], side)
            mid = g.flank(0.0, 0.5 * (rows[1:] + rows[:-1])[:, None], m[:, None, :], side)
            worst = max(worst, float(np.max(_chord_miss(mid, p[:-1], p[1:]))))
        if worst <= tolerance or count + 1 >= MAX_ROWS:
            return rows
        count *= 2


@dataclass(frozen=True)
class Tube:
    """The groove's closed tube (mm): (V, 3) vertices, (F, 3) faces (outward), the stations'
    cam angles (rad) and the rows' distances from the pivot."""

    vertices: Array
    faces: Array
    stations: Array
    rows: Array


def tube(blank: GloboidCam, program: MotionProgram, tolerance: float,
         twist: bool = True) -> Tube:
    """The groove as one closed tube whose flanks stay within *tolerance* (mm) of the exact
    ones, its floor across in chords within it too (without *twist*, the facets' diagonals are
    not held to it: for a groove that folds, which no solid is made of).

    The rows and stations hold each row's and each section's chords to the tolerance; a quad
    between them is not flat (the flank twists: its points move at speeds that differ along the
    arm), and its two triangles meet along a diagonal whose middle strays from the flank by
    about |∂²P/∂θ∂ℓ|·Δθ·Δℓ/4, so the rows are doubled until no diagonal strays further."""
    plan = tube_plan(blank, program, tolerance, twist)
    assert plan.stations is not None, "a plan without a most is complete"
    vertices, faces = groove_tube(blank.follower, plan.stations, program.evaluate(plan.stations),
                                  plan.rows, plan.across)
    return Tube(vertices, faces, plan.stations, plan.rows)


@dataclass(frozen=True)
class TubePlan:
    """Where :func:`tube` puts the tube's points: its stations (rad; None when the plan was
    given up, see :func:`tube_plan`), its rows (mm from the pivot) and the steps across the
    floor and the top (count); and the facets (count) they make, two per station and point
    round the section."""

    stations: Array | None
    rows: Array
    across: int
    facets: int


def _facets(stations: int, rows: int, across: int) -> int:
    """The tube's facets (count) at *stations* stations, *rows* rows and *across* steps."""
    return 2 * stations * (2 * rows + 2 * (across - 1))


#: The plans made whole, for each motion program (held weakly: kept while the design is) by
#: blank, tolerance and twist: the design's rules plan the tube to count its facets as the file
#: loads, and its part plans the same tube again.
_PLANS: weakref.WeakKeyDictionary[MotionProgram, dict[tuple[GloboidCam, float, bool],
                                                      TubePlan]] = weakref.WeakKeyDictionary()


def tube_plan(blank: GloboidCam, program: MotionProgram, tolerance: float, twist: bool = True,
              most: int | None = None) -> TubePlan:
    """The stations, rows and steps across of :func:`tube` at *tolerance* (mm) (see there).
    With *most*, the plan is given up (its stations None) once it would make more facets than
    that: its facets then count what it had reached, more than *most*, so that planning a
    tube costs no more than a tube of *most* facets would. (A plan made whole is what any
    *most* it fits gives: it is kept for the program, and given again.)"""
    plans = _PLANS.setdefault(program, {})
    known = plans.get((blank, tolerance, twist))
    if known is not None and (most is None or known.facets <= most):
        return known
    plan = _planned(blank, program, tolerance, twist, most)
    if plan.stations is not None:
        plan.stations.setflags(write=False)  # (given again: no one may change them)
        plan.rows.setflags(write=False)
        plans[(blank, tolerance, twist)] = plan
    return plan


def _planned(blank: GloboidCam, program: MotionProgram, tolerance: float, twist: bool,
             most: int | None) -> TubePlan:
    """:func:`tube_plan`, planned."""
    g = blank.follower
    rows = tube_rows(blank, program, tolerance)
    across = max(2, math.ceil(2 * g.radius / max(math.sqrt(8.0 * tolerance * g.radius), 1e-6)))
    across = min(across, 64)
    segment, grid, density = _station_density(blank, program, rows, tolerance)
    if most is not None:
        count = spread_count(segment, grid, density, len(program.segments))
        if _facets(count, rows.size, across) > most:
            return TubePlan(None, rows, across, _facets(count, rows.size, across))
    placed = spread(segment, grid, density, len(program.segments))
    most_stations = most // _facets(1, rows.size, across) if most is not None else None
    theta = _halved(blank, program, rows, tolerance, placed, most_stations)
    if most is not None and _facets(theta.size, rows.size, across) > most:
        return TubePlan(None, rows, across, _facets(theta.size, rows.size, across))
    m = program.evaluate(theta)
    ahead, middle = ahead_and_middle(theta)
    m_ahead, m_mid = program.evaluate(ahead), program.evaluate(middle)
    while twist and rows.size < MAX_ROWS:
        mid_rows = 0.5 * (rows[1:] + rows[:-1])[:, None]
        worst = 0.0
        for side in (1, -1):
            # the diagonal from (θₖ, ℓⱼ₊₁) to (θₖ₊₁, ℓⱼ) against the flank at the quad's middle
            a = g.flank(theta[None, :], rows[1:, None], m[:, None, :], side)
            c = g.flank(ahead[None, :], rows[:-1, None], m_ahead[:, None, :], side)
            mid = g.flank(middle[None, :], mid_rows, m_mid[:, None, :], side)
            worst = max(worst, float(np.max(np.linalg.norm(0.5 * (a + c) - mid, axis=-1))))
        if worst <= tolerance:
            break
        rows = np.linspace(rows[0], rows[-1], 2 * rows.size - 1)
        if most is not None and _facets(theta.size, rows.size, across) > most:
            return TubePlan(None, rows, across, _facets(theta.size, rows.size, across))
    return TubePlan(theta, rows, across, _facets(theta.size, rows.size, across))


@dataclass(frozen=True)
class Development:
    """The groove's centre path developed on the pitch globoid (mm): around, the cam angle
    times the pitch globoid's radius at the line of centres (|C − L|); up, the arc along the
    pitch circle about the pivot (L·ψ)."""

    centre: Array
    width: float
    low: float
    high: float


def development(blank: GloboidCam, program: MotionProgram, step: float) -> Development:
    """The centre path developed (see :class:`Development`) at cam angles *step* apart (rad)
    and at every segment's ends."""
    g = blank.follower
    _, theta, m = program.segment_grid(step)
    radius = abs(g.centre - g.arm)
    psi = g.rest + m[0]
    centre = np.column_stack((radius * theta, g.arm * psi))
    return Development(centre, radius * 2 * math.pi, float(g.arm * (g.rest)),
                       float(g.arm * (g.rest + program.max_lift)))


def tube_surfaces(blank: GloboidCam, program: MotionProgram, made: Tube) -> tuple[
        tuple[Array, ...], Array]:
    """The tube as grids of exact points on the cam (mm) at its stations, for B-spline surfaces
    through them: the flank on the + side and on the − side over the rows (top first), the
    floor across from + to − and the top across likewise (:class:`camfab.export.part.Mesh`);
    and probes, points of the exact flanks inside the blank and of the floor, halfway between
    the stations and between the rows (across the floor, between the grid's points), to measure
    the surfaces by."""
    g = blank.follower
    theta, rows = made.stations, made.rows
    m = program.evaluate(theta)

    def across(t: Array, mt: Array, ell: float, u: Array) -> Array:
        return g.across(t[:, None], np.full((t.size, 1), ell), mt[:, :, None], u[None, :])

    u = np.linspace(1.0, -1.0, SURFACE_ACROSS)
    plus, minus = (g.flank(theta[:, None], rows[None, :], m[:, :, None], side)
                   for side in (1, -1))
    grids = (plus, minus, across(theta, m, float(rows[-1]), u),
             across(theta, m, float(rows[0]), u))
    middle = probe_angles(theta)
    mid_rows = 0.5 * (rows[1:] + rows[:-1])
    low, high = sorted((blank.surface, blank.floor))
    mid_rows = mid_rows[(mid_rows >= low) & (mid_rows <= high)]
    mid_m = program.evaluate(middle)
    flanks = [g.flank(middle[:, None], mid_rows[None, :], mid_m[:, :, None], side).reshape(-1, 3)
              for side in (1, -1)]
    floor = across(middle, mid_m, float(rows[-1]), 0.5 * (u[1:] + u[:-1])).reshape(-1, 3)
    return grids, np.concatenate((*flanks, floor))
