"""How a drum cam's groove is cut on a rotary A axis: the laps of a radial end mill round the
drum, layer by layer, and the wall they leave.

A tool as wide as the groove (within :data:`SAME_SIZE_MM`) follows the roller's axis: its
cylinder is the roller's, so the walls it sweeps are the roller's envelope, exact by
construction. A narrower tool roughs the groove down its middle (and, where the groove is wider
than that leaves within ``finish_allowance`` of its walls, in laps stepping out towards them),
then finishes each wall at each depth layer placed against the exact wall
(:func:`~camfab.machining.drum_walls.touching`). No radial tool narrower than the roller can
lie against the whole wall: the wall's slope along the drum's axis, the pressure angle
tan φ = s′/r, changes with the radius, and the tool's does not; placed so that it crosses the
wall nowhere it touches it at the drum's surface, where the wall is least steep, and leaves
material that grows towards the floor, about (R − ρ)(1 − cos φ_floor / cos φ_surface) thick
(R the groove's half-width, ρ the tool's radius). That wall error is measured point by point
from the exact walls (:func:`~camfab.machining.drum_walls.clearance`).

Angles here: A (rad or °) is the drum's turn on the machine, A = σθ, and the tool's axis lies
at the cam frame's polar angle β = −A (:mod:`camfab.machining.drum`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.design.machining import Machining
from camfab.geometry.drum import Drum
from camfab.machining import drum_walls as W
from camfab.motion.program import MotionProgram

TWO_PI = 2.0 * math.pi

#: A tool whose diameter is within this (mm) of the groove's width is the groove's size: it
#: follows the roller's axis. A micrometre: what a tool's diameter is measured to.
SAME_SIZE_MM = 1e-3
#: The share of ``manufacturing.tolerance`` a straight X–A move may stray from the path it
#: stands for, along the drum's axis (which bounds its distance across the path, at every
#: radius: the move is a helix on each cylinder, a straight line on it developed). The rest is
#: left to the sampling of the walls and the program's rounding (0.1 µm, 0.0001°).
CHORD_SHARE = 0.5
#: The smallest tool that meets the tolerance is sought to this (mm on its diameter).
SIZE_STEP_MM = 0.01
#: The most rounds of that search (each places both walls' laps and measures them).
SIZE_ROUNDS = 12


@dataclass(frozen=True)
class Lap:
    """One turn of the tool round the drum at one depth, as its program points: A (°, from
    0 to 360 ascending) and the axial position x (mm) of the tool's axis there, run with A
    rising (*forward*) or falling; its tip's distance from the drum's axis (mm) and the radius
    (mm) at which its feed is held: the top of the layer it cuts."""

    a_deg: Array
    x: Array
    tip: float
    cutting_radius: float
    forward: bool


@dataclass(frozen=True)
class Cut:
    """An operation: its name and its laps in order."""

    name: str
    laps: tuple[Lap, ...]


@dataclass(frozen=True)
class Plan:
    """How the groove is cut: the operations; the tips of the depth layers (mm from the drum's
    axis, the last the floor the tool cuts to); the largest distance (mm) between the exact
    walls and the walls cut, and the cam angle (°) where; whether the tool is the groove's
    size; the smallest tool diameter (mm) whose walls meet the tolerance, when this one's do
    not."""

    cuts: tuple[Cut, ...]
    layers: Array
    wall_error: float
    wall_error_at_deg: float
    exact: bool
    smallest_tool: float | None


def plan(d: Drum, program: MotionProgram, settings: Machining, tolerance: float,
         resolution: float) -> Plan:
    """The operations that cut the groove of *d* with the tool of *settings*, their paths
    within *tolerance* (mm) and rounded to *resolution* (mm, the program's last digit)."""
    rho = settings.tool_radius
    exact = abs(2.0 * rho - 2.0 * d.roller) <= SAME_SIZE_MM
    chord = CHORD_SHARE * tolerance
    walls = W.exact_walls(d, program, tolerance)
    measure = walls.every(W.MEASURE_EVERY)
    centre = _centre(d, program)
    if exact:
        floor = _floor(d, [centre], measure, rho)
    else:
        full = {upper: W.touching(walls, rho, -np.inf, upper) for upper in (False, True)}
        floor = _floor(d, [_placed(full[upper][0]) for upper in (False, True)], measure, rho)
    layers = _layers(d.radius, floor, settings.depth_step)
    tops = np.concatenate(([d.radius], layers[:-1]))
    forward_upper = settings.direction == "climb"
    chosen: dict[int, tuple[Array, Array]] = {}

    def lap(path: tuple[Array, Array], k: int, forward: bool) -> Lap:
        if id(path) not in chosen:  # the same path at every layer: its points once
            chosen[id(path)] = _program_points(*path, chord, resolution)
        a, x = chosen[id(path)]
        return Lap(a, x, float(layers[k]), float(tops[k]), forward)

    if exact:
        laps = tuple(lap(centre, k, True) for k in range(layers.size))
        cuts: tuple[Cut, ...] = (Cut(f"the groove: the tool on the roller's axis, "
                                     f"{layers.size} depth passes", laps),)
        measured = {False: laps, True: laps}
    else:
        roughing = _roughing(d, program, settings, tolerance)
        rough_laps = tuple(lap(path, k, upper is not False if forward_upper else upper is False)
                           for k in range(layers.size) for upper, path in
                           [(None, centre), *roughing])
        finishing = {}
        for upper in (False, True):
            forward = upper == forward_upper
            placed = _placed(full[upper][0])
            paths = [placed if k < layers.size - 1 and np.nanmin(full[upper][1]) >= tip
                     else _placed(W.touching(walls, rho, float(tip), upper)[0])
                     for k, tip in enumerate(layers)]
            finishing[upper] = tuple(lap(path, k, forward) for k, path in enumerate(paths))
        cuts = (Cut(f"roughing the groove: {1 + len(roughing)} lap(s) a layer, "
                    f"{layers.size} depth layers", rough_laps),
                *(Cut(f"finishing the {'upper' if upper else 'lower'} wall, {layers.size} "
                      f"depth passes", finishing[upper]) for upper in (False, True)))
        measured = finishing
    error, at_deg = _wall_error(measure, measured, rho)
    smallest = None
    if error > tolerance and not exact:
        smallest = _smallest_tool(d, walls, rho, error, (1.0 - CHORD_SHARE) * tolerance)
    return Plan(cuts, layers, error, at_deg, exact, smallest)


def _centre(d: Drum, program: MotionProgram) -> tuple[Array, Array]:
    """The roller's axis over a turn, densely: A (rad, 0 to 2π ascending; A = σθ) and its
    axial position (mm), every joint of the motion among the points."""
    theta = program.segment_grid(W.GRID_STEP)[1]
    a = np.mod(d.sigma * theta, TWO_PI)
    a[np.isclose(theta, TWO_PI if d.sigma > 0 else 0.0, rtol=0.0, atol=1e-9)] = TWO_PI
    x = d.start + program.evaluate(theta)[0]
    a, first = np.unique(a, return_index=True)
    return a, x[first]


def _placed(x: Array) -> tuple[Array, Array]:
    """A path placed at the grid's polar angles β of the tool's axis, as A (rad, 0 to 2π
    ascending, the turn closed; A = −β) and x (mm)."""
    a = np.mod(-W.grid(x.size), TWO_PI)
    order = np.argsort(a)
    a, x = a[order], x[order]
    return np.append(a, TWO_PI), np.append(x, x[0])


def _program_points(a: Array, x: Array, chord: float, resolution: float) -> tuple[Array, Array]:
    """The program points of a dense path (A, rad; x, mm): the fewest of its points (by
    :func:`~camfab.machining.drum_walls.chords`) whose straight moves stay within *chord* (mm)
    of it, as A in degrees rounded to the program's 0.0001° and x to *resolution* (mm)."""
    kept = W.chords(a, x, chord)
    a_deg = np.round(np.degrees(a[kept]), 4)
    x = np.round(x[kept] / resolution) * resolution
    distinct = np.concatenate(([True], np.diff(a_deg) > 0.0))
    return a_deg[distinct], x[distinct]


def _laps(paths: list[tuple[Array, Array, float]], count: int) -> W.Laps:
    """Laps through paths of A (rad, ascending over the turn, closed), x (mm) and a tip (mm)
    on a grid of *count* polar angles of the tool's axis (β = −A)."""
    return W.Laps.of([(-a[:-1], x[:-1], tip) for a, x, tip in paths], count)


def _floor(d: Drum, paths: list[tuple[Array, Array]], walls: W.Walls, rho: float) -> float:
    """The tip's distance from the drum's axis (mm) at the last layer: as deep as the walls'
    feet (the rows at the floor's radius) lie along the axis of the tool positions nearest
    them, so that the tool's flat end reaches every one. (A wall's foot lies beside the tool's
    axis, whose flat end is a chord of the floor's circle: the tip goes below the floor's
    radius by up to r(1 − cos δ), δ the foot's angle off the tool's axis.)"""
    laps = _laps([(a, x, -np.inf) for a, x in paths], walls.count)
    feet = W.Walls(walls.radii[:1], walls.lower[:1], walls.upper[:1], walls.theta_lower[:1],
                   walls.theta_upper[:1])
    heights = [W.clearance(feet, upper, laps, rho)[1] for upper in (False, True)]
    return float(min(d.root, np.nanmin(np.concatenate(heights))))


def _layers(radius: float, floor: float, step: float) -> Array:
    """The tips (mm from the drum's axis) of the depth layers from the surface to *floor*, in
    equal layers no deeper than *step*."""
    count = max(1, math.ceil((radius - floor) / step - 1e-9))
    return radius - (radius - floor) * np.arange(1, count + 1) / count


def _roughing(d: Drum, program: MotionProgram, settings: Machining,
              tolerance: float) -> list[tuple[bool, tuple[Array, Array]]]:
    """The roughing laps beside the middle one, by side (upper or not): where the groove is
    wider than the middle lap leaves within ``finish_allowance`` of its walls, laps against
    the walls of rollers of half-widths stepping out from the tool's radius by at most that
    radius to the groove's less the allowance."""
    rho = settings.tool_radius
    outer = d.roller - settings.finish_allowance
    if outer <= rho + SAME_SIZE_MM:
        return []
    count = math.ceil((outer - rho) / rho)
    out = []
    for k in range(1, count + 1):
        walls = W.exact_walls(d, program, tolerance, roller=rho + k * (outer - rho) / count)
        out += [(upper, _placed(W.touching(walls, rho, -np.inf, upper)[0]))
                for upper in (False, True)]
    return out


def _wall_error(walls: W.Walls, laps: dict[bool, tuple[Lap, ...]],
                rho: float) -> tuple[float, float]:
    """The largest distance (mm) between a wall's points and the tool's cut by *laps* (what
    it leaves, or how far it passes them), and the cam angle (°) of that point."""
    worst, at = 0.0, 0.0
    for upper, mine in laps.items():
        paths = [(np.radians(lap.a_deg), lap.x, lap.tip) for lap in mine]
        gap = np.abs(W.clearance(walls, upper, _laps(paths, walls.count), rho)[0])
        k = np.unravel_index(int(np.argmax(gap)), gap.shape)
        if gap[k] > worst:
            worst, at = float(gap[k]), math.degrees(float(walls.side(upper)[1][k]))
    return worst, at % 360.0


def _smallest_tool(d: Drum, walls: W.Walls, rho: float, error: float, target: float) -> float:
    """The smallest tool diameter (mm, to :data:`SIZE_STEP_MM` above it) whose finishing laps
    at full depth leave the walls within *target* (mm: the tolerance less what the program's
    chords may add), sought between this tool's radius *rho* (which leaves *error*) and the
    groove's half-width (which leaves none) by regula falsi (the error falls about in
    proportion to R − ρ), the bracket kept by the Illinois rule."""
    measure = walls.every(W.MEASURE_EVERY)

    def leaves(radius: float) -> float:
        worst = 0.0
        for upper in (False, True):
            laps = _laps([(*_placed(W.touching(walls, radius, -np.inf, upper)[0]), -np.inf)],
                         measure.count)
            worst = max(worst, float(np.abs(W.clearance(measure, upper, laps, radius)[0]).max()))
        return worst - target

    low, high = rho, d.roller
    f_low, f_high = error - target, -target
    side = 0
    for _ in range(SIZE_ROUNDS):
        if high - low <= SIZE_STEP_MM / 2:
            break
        middle = high - f_high * (high - low) / (f_high - f_low)
        middle = min(max(middle, low + SIZE_STEP_MM / 8), high - SIZE_STEP_MM / 8)
        f_middle = leaves(middle)
        if f_middle > 0.0:
            low, f_low = middle, f_middle
            f_high = f_high / 2 if side == 1 else f_high
            side = 1
        else:
            high, f_high = middle, f_middle
            f_low = f_low / 2 if side == -1 else f_low
            side = -1
    return math.ceil(2.0 * high / SIZE_STEP_MM - 1e-9) * SIZE_STEP_MM
