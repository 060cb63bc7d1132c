"""The groove of a drum cam as one closed tube mesh (numpy only), to be subtracted from the drum
once (THEORY §C: unions of hull pieces leave slivers that break after the float32 round trip).

At each station (a cam angle) the tube's cross-section runs up the lower wall from the groove's
floor to beyond the drum's surface, back down the upper wall, and across the floor along the
floor's circle. The walls are the exact envelope (``Drum.walls``) at radii placed so that the
straight pieces between them stay within the tolerance; stations are placed by the chord error
of the walls developed at the surface, the faster-moving outer wall deciding.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Index, Mask, signed_volume
from camfab.curves.sampling import SURFACE_ACROSS, probe_angles, spread, spread_count
from camfab.geometry.drum import ANALYSIS_STEP, Drum, Walls, polar_to_xy
from camfab.motion.program import MotionProgram

#: Largest step of cam angle between stations, however straight the groove runs.
MAX_STATION_STEP = math.radians(1.0)

#: How far past the drum's surface the tube reaches (mm, at least), so the subtraction cuts
#: cleanly through the surface instead of grazing it.
SURFACE_MARGIN_MM = 1.0


@dataclass(frozen=True)
class Tube:
    """A closed, consistently wound triangle mesh: (V, 3) vertices (mm) and (F, 3) faces; with
    the stations' cam angles (rad) and the radii of the wall rows (mm, floor first)."""

    vertices: Array
    faces: Array
    stations: Array
    radii: Array


def stations(d: Drum, program: MotionProgram, tolerance: float) -> Array:
    """Cam angles (rad, one turn, joints included) at which the groove's chords stay within
    *tolerance* (mm) of the walls developed at the drum's surface."""
    return spread(*_station_density(d, program, tolerance), len(program.segments))


def _station_density(d: Drum, program: MotionProgram,
                     tolerance: float) -> tuple[Index, Array, Array]:
    """The stations a radian needs (1/rad) on the program's segment grid: its segment index,
    cam angle (rad) and density."""
    segment, theta, m = program.segment_grid(ANALYSIS_STEP)
    r = d.radius
    speed = np.hypot(r, m[1])
    rho = np.abs(d.developed_radius(m[1], m[2], r))
    with np.errstate(invalid="ignore", divide="ignore"):
        # a chord of the outer wall (radius ρ + R, moving at speed·(ρ + R)/ρ) strays
        # (speed·(ρ+R)/ρ·Δθ)²/(8(ρ+R)) from it
        step = np.sqrt(8.0 * tolerance / (rho + d.roller)) * rho / speed
    density = 1.0 / np.where(np.isfinite(step), np.minimum(step, MAX_STATION_STEP),
                             MAX_STATION_STEP)
    return segment, theta, _reaching(segment, theta, density)


def _reaching(segment: Index, theta: Array, density: Array) -> Array:
    """*density* (1/rad, on the segment grid *theta*, rad) raised, within each segment, to that
    of every grid point whose own step (1/density) reaches it.

    A chord's error bound ``(v·Δθ)²/(8ρ)`` holds for a curve of radius ρ all along the chord.
    Where the curvature drops inside a segment (a law's blend ending in a straight stretch, an
    acceleration step), a step spread evenly in the density's integral reaches from the curved
    stretch far into the straight one, and the chord then strays from the curve up to four times
    that bound (its curved part's offset from the tangent, κa²/2, not κa²/8). With each point's
    density at least that of every point within its step, no chord is longer than the step the
    sharpest curve it spans asks for, and its error stays within the bound."""
    out = density.copy()
    step = 1.0 / density
    for k in range(1, theta.size):
        same = segment[k:] == segment[:-k]
        gap = theta[k:] - theta[:-k]
        behind = same & (gap <= step[k:])  # the point k further on reaches back to this one
        ahead = same & (gap <= step[:-k])  # this one reaches k points further on
        if not (behind.any() or ahead.any()):  # nor does any point reach further
            break
        out[:-k] = np.maximum(out[:-k], np.where(behind, density[k:], 0.0))
        out[k:] = np.maximum(out[k:], np.where(ahead, density[:-k], 0.0))
    return out


#: The fewest points round the tube's section: four wall rows on either wall (the fewest
#: :func:`_rows` gives) and none between the walls' feet on the floor.
FEWEST_RING = 8


def tube_facets(d: Drum, program: MotionProgram, tolerance: float, most: int) -> int:
    """The facets (count) of :func:`groove_tube`'s tube at *tolerance* (mm), two per station
    and point round its section. When the stations alone (with the fewest points round,
    :data:`FEWEST_RING`) make more than *most*, that lower bound, counted before any station
    is placed: the count never costs more than a tube of *most* facets would."""
    segment, theta, density = _station_density(d, program, tolerance)
    count = len(program.segments)
    lower = 2 * spread_count(segment, theta, density, count) * FEWEST_RING
    if lower > most:
        return lower
    placed, m, added = fanned(d, program, spread(segment, theta, density, count), tolerance)
    radii = _rows(d, placed, m, tolerance)
    floor = creased(d, program, placed, added, radii[:1],
                    [d.walls(placed, m[0], m[1], radii[0])])[0]
    return 2 * placed.size * (2 * radii.size + _across(d, floor, tolerance) - 1)


def _rows(d: Drum, theta: Array, m: Array, tolerance: float) -> Array:
    """Radii of the wall rows (mm): from the floor in equal steps to half a step beyond the
    surface, as many as keep the straight pieces between rows within *tolerance* (mm) of the
    wall, then one row further out.

    No row lies on the surface: the drum's surface (chords of its circle) would cross the faces
    next to such a row a fraction of the tolerance from its vertices, and the subtraction would
    leave edges of a micrometre and less along the groove's edge. The surface cuts the last
    piece halfway instead. There is always a row between the floor and the surface: the
    read-back check (:func:`groove_lift`) runs the roller over the wall vertices strictly
    between them."""
    outer = d.radius + max(SURFACE_MARGIN_MM, 0.1 * d.depth)
    count = 2
    while True:
        step = d.depth / (count + 0.5)
        radii = d.root + step * np.arange(count + 2)  # the last, half a step past the surface
        worst = 0.0
        for lo, hi in itertools.pairwise(radii):
            a, b, c = (_points(d, theta, m, r) for r in (lo, hi, 0.5 * (lo + hi)))
            worst = max(worst, float(np.max(np.linalg.norm(0.5 * (a + b) - c, axis=-1))))
        if worst <= tolerance or count >= 64:
            return radii if outer <= radii[-1] else np.append(radii, outer)
        count *= 2


def _across(d: Drum, floor: Walls, tolerance: float) -> int:
    """The steps across the floor (count) between the walls' feet *floor*: enough points on
    the floor's circle for its widest stretch to hold *tolerance* (mm)."""
    span = float(np.max(np.abs(floor.phi_upper - floor.phi_lower)))
    step = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / d.root))
    return max(1, math.ceil(span / step))


def _points(d: Drum, theta: Array, m: Array, r: float) -> Array:
    """Both walls at radius *r*: (2, N, 3) points, lower wall first."""
    walls = d.walls(theta, m[0], m[1], r)
    lower = np.concatenate((polar_to_xy(r, walls.phi_lower), walls.z_lower[:, None]), axis=-1)
    upper = np.concatenate((polar_to_xy(r, walls.phi_upper), walls.z_upper[:, None]), axis=-1)
    return np.stack((lower, upper))


def velocity_steps(program: MotionProgram) -> list[tuple[float, float, float]]:
    """The joints where s′ steps: their cam angle (rad) and s′ just before and after (mm/rad)."""
    return [(j.angle, float(j.left[1]), float(j.right[1])) for j in program.joints()
            if not math.isclose(j.left[1], j.right[1], rel_tol=1e-9, abs_tol=1e-12)]


def fanned(d: Drum, program: MotionProgram, theta: Array,
           tolerance: float) -> tuple[Array, Array, Mask]:
    """The *theta* (rad, the stations, every joint among them) and s, s′, s″, s‴ there, with
    sections added at each joint where s′ steps: the roller stands still there while its
    contact turns from the line of s′ before to that of s′ after, and its own surface is the
    wall between (a wall point, for any s′, lies on the roller at its cam angle: see
    :meth:`~camfab.geometry.drum.Drum.walls`). As many sections as keep the chords of that
    surface (the roller's radius R) within *tolerance* (mm) at the groove's floor, where the
    contact turns furthest. Third, which sections are the added ones."""
    m = program.evaluate(theta)
    steps = velocity_steps(program)
    if not steps:
        return theta, m, np.zeros(theta.size, dtype=bool)
    chord = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / d.roller))
    angles, columns = [theta], [m]
    for angle, before, after in steps:
        turn = abs(math.atan2(after, d.root) - math.atan2(before, d.root))
        count = max(2, math.ceil(turn / chord))
        ds = before + (after - before) * np.arange(count) / count  # s′ after is the joint's
        at = program.evaluate(np.full(count, angle))
        at[1], at[2], at[3] = ds, 0.0, 0.0
        angles.append(np.full(count, angle))
        columns.append(at)
    # at a joint the added sections (s′ from before on) come before the joint's own (s′ after)
    theta = np.concatenate(angles)
    added = np.concatenate([np.zeros(angles[0].size, dtype=bool),
                            *[np.ones(a.size, dtype=bool) for a in angles[1:]]])
    order = np.lexsort((~added, np.mod(theta, 2.0 * math.pi)))
    return theta[order], np.concatenate(columns, axis=1)[:, order], added[order]


#: Points along each wall's track either side of a velocity step where its crease is sought,
#: then again between the two found to cross, :data:`CREASE_ROUNDS` times in all.
CREASE_POINTS = 32
CREASE_ROUNDS = 3


@dataclass(frozen=True)
class Crease:
    """Where a wall swept before a velocity step and the same wall swept after it cross, at
    each of some radii: the cam angle of the crossing on either (rad), its polar angle (rad,
    unwrapped about the step's axis angle) and height (mm); ``found`` False where they do not
    cross."""

    before: Array
    after: Array
    phi: Array
    z: Array
    found: Mask


def creased(d: Drum, program: MotionProgram, theta: Array, added: Mask, radii: Array,
            walls: list[Walls]) -> list[Walls]:
    """*walls* at each of *radii* (mm) at the sections *theta* (rad; *added*: the sections of
    :func:`fanned`) trimmed at each velocity step's crease: on the inside of the bend the wall
    swept before the step and the one swept after cross, and what lies beyond their crossing is
    inside the roller at other angles (air, not wall). Every section between the crossing's cam
    angle before the step and its cam angle after it has its inner wall point there instead:
    the crease, where the two walls meet. (On the outside of the bend the added sections are
    the roller's own surface, and nothing is trimmed.)"""
    out = [{f: np.array(getattr(w, f)) for f in ("phi_lower", "z_lower", "phi_upper",
                                                 "z_upper")} for w in walls]
    for angle, before, _ in velocity_steps(program):
        delta = np.mod(theta - angle + math.pi, 2.0 * math.pi) - math.pi
        for lower in (True, False):
            crease = crossings(d, program, angle, before, radii, lower)
            key = "lower" if lower else "upper"
            for k in np.flatnonzero(crease.found):
                trim = (added & (delta == 0.0)) | (
                    (delta < 0.0) & (delta > crease.before[k] - angle)) | (
                    (delta >= 0.0) & ~added & (delta < crease.after[k] - angle))
                phi = out[k][f"phi_{key}"]  # the crease, on the turn each section's wall is on
                phi_x = crease.phi[k]
                phi[trim] = phi_x + 2.0 * math.pi * np.round((phi[trim] - phi_x)
                                                             / (2.0 * math.pi))
                out[k][f"z_{key}"][trim] = crease.z[k]
    return [Walls(**w) for w in out]


def crossings(d: Drum, program: MotionProgram, angle: float, before: float, radii: Array,
              lower: bool) -> Crease:
    """Where a wall's track at each of *radii* (mm) swept before the velocity step at *angle*
    (rad; s′ *before* there, mm/rad) crosses the one swept after it, both followed within
    twice the roller's angular reach of the step: the crossing of the tracks' polylines, found
    again between the pieces found to cross, :data:`CREASE_POINTS` to each."""
    reach = 2.0 * _reach(d)
    u = np.linspace(0.0, 1.0, CREASE_POINTS)
    count = radii.size
    rows = np.arange(count)
    t_before = np.broadcast_to(angle - reach * u[::-1], (count, u.size))
    t_after = np.broadcast_to(angle + reach * u, (count, u.size))
    found = np.ones(count, dtype=bool)
    for _ in range(CREASE_ROUNDS):
        a = _tracks(d, program, angle, before, radii, lower, t_before)
        b = _tracks(d, program, angle, before, radii, lower, t_after)
        i, j, fa, fb, hit = _polylines_cross(a, b)
        found &= hit
        t1 = t_before[rows, i] + fa * (t_before[rows, i + 1] - t_before[rows, i])
        t2 = t_after[rows, j] + fb * (t_after[rows, j + 1] - t_after[rows, j])
        point = a[rows, i] + fa[:, None] * (a[rows, i + 1] - a[rows, i])
        t_before = np.linspace(t_before[rows, i], t_before[rows, i + 1], CREASE_POINTS, axis=1)
        t_after = np.linspace(t_after[rows, j], t_after[rows, j + 1], CREASE_POINTS, axis=1)
    return Crease(t1, t2, point[:, 0], point[:, 1], found)


def _tracks(d: Drum, program: MotionProgram, angle: float, before: float, radii: Array,
            lower: bool, t: Array) -> Array:
    """A wall's tracks at *radii* (mm, R of them) over cam angles *t* ((R, N) rad, on one side
    of the velocity step at *angle*, which takes s′ *before* there when *t* runs before it):
    (R, N, 2) polar angle (rad, unwrapped about the step's axis angle) and height (mm)."""
    m = program.evaluate(t.ravel()).reshape(4, *t.shape)
    if t[0, -1] <= angle:  # the track before the step reaches it with s′ before
        at = t == angle
        m[1] = np.where(at, before, m[1])
        m[2:] = np.where(at, 0.0, m[2:])
    w = d.walls(t, m[0], m[1], radii[:, None])
    phi, z = (w.phi_lower, w.z_lower) if lower else (w.phi_upper, w.z_upper)
    centre = float(d.axis_angle(np.array([angle]))[0])
    return np.stack((np.mod(phi - centre + math.pi, 2.0 * math.pi) - math.pi + centre, z),
                    axis=-1)


def _polylines_cross(a: Array, b: Array) -> tuple[Index, Index, Array, Array, Mask]:
    """The first crossing of each pair of polylines *a* and *b* ((R, N, 2) each): the pieces'
    indices and how far along each (0 to 1), and whether they cross (where not, the first
    pieces)."""
    p, q = a[:, :-1, None, :], b[:, None, :-1, :]
    da, db = (a[:, 1:] - a[:, :-1])[:, :, None, :], (b[:, 1:] - b[:, :-1])[:, None, :, :]
    denom = da[..., 0] * db[..., 1] - da[..., 1] * db[..., 0]
    gap = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        fa = (gap[..., 0] * db[..., 1] - gap[..., 1] * db[..., 0]) / denom
        fb = (gap[..., 0] * da[..., 1] - gap[..., 1] * da[..., 0]) / denom
    inside = (denom != 0.0) & (fa >= 0.0) & (fa <= 1.0) & (fb >= 0.0) & (fb <= 1.0)
    # the crossing nearest the step: the last piece before it, the first after it
    pieces_a, pieces_b = inside.shape[1:]
    order = (np.arange(pieces_a)[:, None] * pieces_b
             + (pieces_b - 1 - np.arange(pieces_b))[None, :])
    best = np.argmax(np.where(inside, order, -1).reshape(len(a), -1), axis=1)
    rows = np.arange(len(a))
    i, j = best // pieces_b, best % pieces_b
    hit = inside[rows, i, j]
    return (i, j, np.where(hit, fa[rows, i, j], 0.0), np.where(hit, fb[rows, i, j], 0.0),
            hit)


def groove_tube(d: Drum, program: MotionProgram, tolerance: float) -> Tube:
    """The groove as one closed tube, its chords within *tolerance* (mm) of the exact walls."""
    theta, m, added = fanned(d, program, stations(d, program, tolerance), tolerance)
    radii = _rows(d, theta, m, tolerance)
    walls = creased(d, program, theta, added, radii,
                    [d.walls(theta, m[0], m[1], r) for r in radii])
    floor = walls[0]
    across = _across(d, floor, tolerance)
    # the cross-section, per station: (phi, r, z) columns around the ring
    phi = [w.phi_lower for w in walls] + [w.phi_upper for w in reversed(walls)]
    rad = [np.full(theta.size, r) for r in radii] + [np.full(theta.size, r) for r in radii[::-1]]
    z = [w.z_lower for w in walls] + [w.z_upper for w in reversed(walls)]
    for k in range(1, across):
        f = k / across  # from the upper wall's foot back to the lower wall's
        phi.append(floor.phi_upper + f * (floor.phi_lower - floor.phi_upper))
        rad.append(np.full(theta.size, d.root))
        z.append(floor.z_upper + f * (floor.z_lower - floor.z_upper))
    ring_phi, ring_r, ring_z = (np.stack(c, axis=1) for c in (phi, rad, z))  # (N, M)
    xy = polar_to_xy(ring_r, ring_phi)
    vertices = np.concatenate((xy, ring_z[..., None]), axis=-1).reshape(-1, 3)
    n, size = ring_phi.shape
    i = np.arange(n)[:, None]
    j = np.arange(size)[None, :]
    a = i * size + j
    b = i * size + (j + 1) % size
    c = ((i + 1) % n) * size + (j + 1) % size
    e = ((i + 1) % n) * size + j
    faces = np.concatenate((np.stack((a, b, c), -1).reshape(-1, 3),
                            np.stack((a, c, e), -1).reshape(-1, 3)))
    if signed_volume(vertices, faces) < 0:
        faces = faces[:, ::-1]
    return Tube(vertices, faces, theta, radii)


@dataclass(frozen=True)
class Development:
    """The groove developed (unrolled) at the drum's surface (mm): x = R·ϕ measured from the
    θ = 0 line counter-clockwise about +Z (the surface as seen from outside with +Z up, shifted
    to run from 0 to 2πR), y = z. ``lower``/``upper`` are the walls and ``centre`` the roller
    axis's track, each (N, 2) from θ = 0 to one full turn (both ends included)."""

    lower: Array
    upper: Array
    centre: Array
    width: float
    height: float


def development(d: Drum, program: MotionProgram, tolerance: float) -> Development:
    """The groove at the drum's surface, its walls at the stations of :func:`stations` with the
    sections a velocity step adds and its creases (:func:`fanned`, :func:`creased`), as the
    tube has them; the roller axis's track at the stations."""
    placed = stations(d, program, tolerance)
    theta, m, added = fanned(d, program, placed, tolerance)
    # one turn later, the first section again: the walls close across the seam as they start
    theta, added = np.append(theta, theta[0] + 2.0 * math.pi), np.append(added, added[0])
    m = np.concatenate((m, m[:, :1]), axis=1)
    walls = creased(d, program, theta, added, np.array([d.radius]),
                    [d.walls(theta, m[0], m[1], d.radius)])[0]
    shift = 2.0 * math.pi if d.sigma > 0 else 0.0

    def unrolled(phi: Array, z: Array) -> Array:
        return np.stack((d.radius * (phi + shift), z), -1)

    track = np.append(placed, 2.0 * math.pi)
    s = program.evaluate(track)[0]
    s[-1] = s[0]
    return Development(unrolled(walls.phi_lower, walls.z_lower),
                       unrolled(walls.phi_upper, walls.z_upper),
                       unrolled(d.axis_angle(track), d.start + s), 2.0 * math.pi * d.radius,
                       d.length)


def _reach(d: Drum) -> float:
    """Half the angle (rad) over which the roller can touch a wall: its radius seen from the
    axis at the groove's floor."""
    return math.asin(min(1.0, d.roller / d.root)) + 1e-9


def _inside(d: Drum, r: Array) -> Mask:
    """Radii (mm) strictly between the groove's floor and the drum's surface."""
    return (r > d.root + 1e-3 * d.depth) & (r < d.radius - 1e-3 * d.depth)


def wall_pieces(d: Drum, vertices: Array, edges: Index) -> tuple[Array, Array]:
    """The pieces of a drum's mesh (mm, as read back from a file) the roller can meet on its
    walls: each edge that runs round the drum at one radius (a wall row, from one station to
    the next; its ends at one radius to the float32 of an STL) strictly between the floor and
    the surface, and each vertex there on no such edge (a piece of no length): their (P, 3)
    starts and ends. *edges* are the mesh's edges, each once (E, 2).

    (Edges across the rows, from the floor toward the surface, are left: the straight piece of
    a twisted quad's diagonal strays further from the wall than the rows and stations do.)"""
    radius = np.hypot(vertices[:, 0], vertices[:, 1])
    inside = _inside(d, radius)
    ra, rb = radius[edges[:, 0]], radius[edges[:, 1]]
    rows = edges[np.isclose(ra, rb, rtol=1e-6, atol=0.0) & inside[edges[:, 0]]
                 & inside[edges[:, 1]]]
    on_row = np.zeros(len(vertices), dtype=bool)
    on_row[rows.ravel()] = True
    alone = np.flatnonzero(inside & ~on_row)
    return (np.concatenate((vertices[rows[:, 0]], vertices[alone])),
            np.concatenate((vertices[rows[:, 1]], vertices[alone])))


def groove_lift(d: Drum, vertices: Array, edges: Index, theta: Array,
                centre: Array) -> tuple[Array, Array]:
    """Run the roller through a groove given by a mesh (mm, as read back from a file: its
    *vertices* and *edges*, each once): at each cam angle *theta* the lowest and highest
    heights (mm) its centre can take between the walls, against the wall rows' edges and the
    lone vertices (:func:`wall_pieces`) within its reach. *centre* (mm) is the design's height
    there, which tells the lower wall's pieces from the upper's.

    Each piece is met exactly, however long: the roller is the cylinder of radius R about its
    radial axis, and a point w = r sin(ϕ − α) across the axis keeps the centre at least
    √(R² − w²) above it (on the lower wall) or below it (on the upper wall). Along a straight
    piece w and z are linear, so z + √(R² − w²) is concave in it, and its highest point is an
    end or where the piece runs along the roller's surface, w = R z′/√(w′² + z′²) (the upper
    wall: the lowest of z − √(R² − w²), at −w), whichever lies within the roller's reach."""
    start, end = wall_pieces(d, vertices, edges)
    phi_start = np.arctan2(-start[:, 0], start[:, 1])
    turn = np.mod(np.arctan2(-end[:, 0], end[:, 1]) - phi_start + math.pi,
                  2 * math.pi) - math.pi
    low_phi = np.minimum(phi_start, phi_start + turn)
    order = np.argsort(low_phi)
    # three turns side by side, so a window round the seam is one slice
    shifts = np.repeat(np.array([-2 * math.pi, 0.0, 2 * math.pi]), order.size)
    low_phi = np.tile(low_phi[order], 3) + shifts
    high_phi = low_phi + np.tile(np.abs(turn[order]), 3)
    start, end = np.tile(start[order], (3, 1)), np.tile(end[order], (3, 1))
    reach = _reach(d)
    span = float(np.max(high_phi - low_phi, initial=0.0))
    alpha = np.mod(d.axis_angle(theta) + math.pi, 2 * math.pi) - math.pi
    first = np.searchsorted(low_phi, alpha - reach - span)
    last = np.searchsorted(low_phi, alpha + reach, side="right")
    # a block of angles at a time, each block's windows at once: (angles, widest window),
    # padded and masked; as many angles to a block as keep it within LIFT_BLOCK_ELEMENTS
    widest = max(1, int(np.max(last - first, initial=0)))
    block = max(1, LIFT_BLOCK_ELEMENTS // widest)
    pieces = (start, end, high_phi)
    low, high = np.empty(theta.size), np.empty(theta.size)
    for at in range(0, theta.size, block):
        rows = slice(at, at + block)
        low[rows], high[rows] = _lift_window(d, pieces, alpha[rows], first[rows], last[rows],
                                             centre[rows])
    return low, high


#: Most (angle, piece) pairs :func:`groove_lift` holds at once: 2 M, some 16 MB per array of
#: float64 (a groove of a hundred thousand stations has millions of pieces within the
#: roller's reach of all its angles, gigabytes at once).
LIFT_BLOCK_ELEMENTS = 1 << 21


def _lift_window(d: Drum, pieces: tuple[Array, Array, Array], alpha: Array, first: Index,
                 last: Index, centre: Array) -> tuple[Array, Array]:
    """:func:`groove_lift` at the axis angles *alpha* (rad), whose windows of the sorted
    *pieces* (starts and ends, mm, and the polar angle each reaches to, rad) run from *first*
    to *last*, the design's heights *centre* (mm) there."""
    start, end, high_phi = pieces
    reach, big = _reach(d), d.roller
    index = first[:, None] + np.arange(max(1, int(np.max(last - first))))[None, :]
    present = (index < last[:, None])
    index = np.minimum(index, high_phi.size - 1)
    present &= high_phi[index] >= (alpha - reach)[:, None]
    # across the roller's axis, w = −x cos α − y sin α, and the height, at either end
    cos, sin = np.cos(alpha)[:, None], np.sin(alpha)[:, None]
    a, b = start[index], end[index]
    w0 = -a[..., 0] * cos - a[..., 1] * sin
    dw = -(b[..., 0] - a[..., 0]) * cos - (b[..., 1] - a[..., 1]) * sin
    z0, dz = a[..., 2], b[..., 2] - a[..., 2]
    below = z0 + 0.5 * dz < centre[:, None]
    # the stretch of the piece within the roller's reach, |w| ≤ R: t from lo to hi
    moving = dw != 0.0
    step = np.where(moving, dw, 1.0)
    t1, t2 = (-big - w0) / step, (big - w0) / step
    lo = np.where(moving, np.maximum(np.minimum(t1, t2), 0.0), 0.0)
    hi = np.where(moving, np.minimum(np.maximum(t1, t2), 1.0), 1.0)
    present &= (lo <= hi) & (moving | (np.abs(w0) < big))
    # where the piece runs along the roller's surface (the lower wall's w; the upper's is −w)
    side = np.where(below, 1.0, -1.0)
    along = np.hypot(dw, dz)
    w_touch = side * big * dz * np.sign(dw) / np.where(along > 0.0, along, 1.0)
    touch = np.clip((w_touch - w0) / step, lo, hi)
    best = np.full(index.shape, -np.inf)
    for t in (lo, hi, touch):
        w = w0 + t * dw
        best = np.maximum(best, side * (z0 + t * dz) + np.sqrt(np.maximum(big * big - w * w,
                                                                          0.0)))
    low = np.max(np.where(present & below, best, -np.inf), axis=1)
    high = np.min(np.where(present & ~below, -best, np.inf), axis=1)
    return low, high


def tube_surfaces(d: Drum, program: MotionProgram, tube: Tube) -> tuple[tuple[Array, ...],
                                                                        Array]:
    """The tube as grids of exact points (mm) at its stations, for B-spline surfaces through
    them: the lower wall and the upper wall over the rows' radii (floor first), the floor across
    on its circle from the lower wall's foot to the upper's, and the top across beyond the
    surface (:class:`camfab.export.part.Mesh`); and probes, points of the exact walls halfway
    between the stations and between the rows, to measure the surfaces by."""
    # one grid row per cam angle: the sections a velocity step adds (:func:`fanned`) share
    # theirs with the joint's own
    theta, radii = np.unique(tube.stations), tube.radii
    m = program.evaluate(theta)

    def wall(side: int, t: Array, mm: Array, r: Array) -> Array:
        w = d.walls(t[:, None], mm[0][:, None], mm[1][:, None], r[None, :])
        phi, z = (w.phi_lower, w.z_lower) if side < 0 else (w.phi_upper, w.z_upper)
        return np.concatenate((polar_to_xy(r[None, :], phi), z[..., None]), axis=-1)

    def across(r: float) -> Array:
        w = d.walls(theta, m[0], m[1], r)
        f = np.linspace(0.0, 1.0, SURFACE_ACROSS)[None, :]
        phi = w.phi_lower[:, None] + f * (w.phi_upper - w.phi_lower)[:, None]
        z = w.z_lower[:, None] + f * (w.z_upper - w.z_lower)[:, None]
        return np.concatenate((polar_to_xy(r, phi), z[..., None]), axis=-1)

    grids = (wall(-1, theta, m, radii), wall(1, theta, m, radii), across(d.root),
             across(float(radii[-1])))
    middle = probe_angles(theta)
    mid_m = program.evaluate(middle)
    mid_r = 0.5 * (radii[1:] + radii[:-1])
    inside = mid_r <= d.radius  # the walls the drum keeps
    probes = np.concatenate([wall(side, middle, mid_m, mid_r[inside]).reshape(-1, 3)
                             for side in (-1, 1)])
    return grids, probes


#: Radii from the groove's floor to the drum's surface at which a velocity step's crease is
#: found to measure the roller's play there (:func:`corner_play`).
PLAY_RADII = 33


def corner_play(d: Drum, program: MotionProgram) -> list[tuple[float, float]]:
    """At each velocity step of *program*: its cam angle (rad) and how far (mm) the roller can
    move off the design there in the exact groove (the union of the roller's positions).

    On the inside of the bend the walls swept before and after the step meet in a crease
    (:func:`crossings`) further from the roller's axis than its radius: at the step the roller
    touches neither, and can move toward the crease until it meets it; on the outside of the
    bend it touches its own surface, swept as it turns, and cannot move. A crease point at w
    across the axis and height z stops the centre √(R² − w²) from it. The play is the largest
    over the crease's radii (from the floor to the surface)."""
    out = []
    radii = np.linspace(d.root, d.radius, PLAY_RADII)
    for angle, before, _ in velocity_steps(program):
        centre = d.start + float(program.evaluate(np.array([angle]))[0, 0])
        alpha = float(d.axis_angle(np.array([angle]))[0])
        play = 0.0
        for lower in (True, False):
            crease = crossings(d, program, angle, before, radii, lower)
            w = radii * np.sin(crease.phi - alpha)
            gap = np.sqrt(np.maximum(d.roller**2 - w * w, 0.0))
            stop = crease.z + gap if lower else crease.z - gap
            play = max(play, float(np.max(np.abs(centre - stop), where=crease.found,
                                          initial=0.0)))
        out.append((angle, play))
    return out
