"""A cutter's passes round a plate's contours as moves (mm, mm/min), and those moves as G-code
blocks, cutting time and a plan view.

A pass runs round a closed contour from a point in the middle of one of its edges: the tool comes
down in the air above the work, enters along a straight move and a tangent quarter circle,
ramps down lap after lap along the contour (never straight down into material), makes a last
lap at the pass's depth and leaves along a tangent arc. The contour is the tool centre's path
(``compensation: path``), or the part's contour that the control offsets by the tool's radius
(``control``: G41/G42 with D1, entered by that straight move, longer than the radius, as
LinuxCNC asks); both make the same moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array, Index
from camfab.curves.profile import Profile
from camfab.curves.sampling import arc_points
from camfab.machining.rs274 import Program

#: An arc whose sagitta is under this (mm) is written as a straight move: the two differ by
#: less than a tenth of the 0.1 µm a program writes, and a control given a nearly straight arc
#: must work with its huge radius.
FLAT_ARC_MM = 1e-5
#: An arc whose chord is under this (mm) is written as a straight move: its ends, rounded as
#: written, could meet, and a control reads an arc whose ends meet as a whole circle.
SHORT_ARC_MM = 1e-3
#: Moves shorter than this (mm) are left out: nothing a control can do with them.
NO_MOVE_MM = 1e-7


@dataclass(frozen=True)
class Move:
    """One block: ``G0``/``G1`` to *end*, ``G2``/``G3`` to *end* about *centre*, or *words*
    alone (*code* ``words``: ``G41 D1``, ``G40``; ``comment``: a comment's text); positions in
    mm, *feed* in mm/min."""

    code: str
    end: tuple[float, float, float] | None = None
    centre: tuple[float, float] | None = None
    feed: float | None = None
    words: str = ""


@dataclass(frozen=True)
class Lead:
    """How a pass enters and leaves: the tool centre's tangent arcs' radii (mm; 0 leaves with
    no arc), the height of the air it enters in and of its rapid moves (mm), the feeds."""

    lead_in: float
    lead_out: float
    entry_z: float
    safe_z: float
    feed: float
    plunge: float


def directed(profile: Profile, edge: int, point: Array, clockwise: bool, along: Array,
             at: float, lap: float) -> tuple[Profile, Array]:
    """The closed counter-clockwise *profile* as a path starting at *point* (mm, on its edge
    *edge*), in the direction asked, its vertices in the order travelled; and how far into the
    lap each lies, as a share of it (0 at *point*, 1 back there): from *along*, a length (mm)
    per vertex of *profile* counted counter-clockwise round a lap of *lap* (mm), and *at*, that
    of *point*."""
    v, b = profile.vertices, profile.bulges
    n = len(v)
    first = b[edge]
    if first != 0.0:
        sweep = 4.0 * math.atan(first)
        arcs = profile.arcs()
        centre = arcs.centre[int(np.flatnonzero(arcs.index == edge)[0])]
        start = math.atan2(*(v[edge] - centre)[::-1])
        angle = math.atan2(*(point - centre)[::-1])
        part = (angle - start) % (2 * math.pi) if sweep > 0 else -((start - angle) % (2 * math.pi))
        before, after = math.tan(part / 4.0), math.tan((sweep - part) / 4.0)
    else:
        before = after = 0.0
    following = (np.arange(1, n + 1) + edge) % n
    vertices = np.vstack((point, v[following]))
    bulges = np.concatenate(([after], b[following[:-1]], [before]))
    lengths = np.concatenate(([at], along[following]))
    if clockwise:
        k = np.arange(n + 1)
        vertices, bulges, lengths = (vertices[-k % (n + 1)], -bulges[(-k - 1) % (n + 1)],
                                     lengths[-k % (n + 1)])
    share = np.mod((lengths - at) * (-1.0 if clockwise else 1.0), lap) / lap
    share[0] = 0.0
    return Profile(vertices, bulges), share


def along_centre(where: Index, count: int, centre: Profile, centre_where: Index) -> Array:
    """How far along the edges of the tool centre's path (mm, counter-clockwise from its first
    vertex; its joins round the part's corners counting nothing) each vertex of an offset of
    the same contour lies: *count* vertices, the edge of the contour's edge k at *where[k]*
    (the joins between), those of the centre path *centre* at *centre_where*.

    A ramp descends in proportion to this: level round each corner, where the control's
    compensation puts a level arc of its own, so that the program's contour for the control
    and the centre path descend alike."""
    length = np.zeros(len(centre.vertices))
    length[centre_where] = element_lengths(centre)[centre_where]
    end = np.cumsum(length)
    out = np.empty(count)
    joins = np.ones(count, dtype=bool)
    joins[where] = False
    out[where] = end[centre_where - 1] % end[-1]
    after = np.flatnonzero(joins[(where - 1) % count])  # edges with a join before them
    out[(where[after] - 1) % count] = end[centre_where[after - 1]] % end[-1]
    return out


def edges_length(path: Profile, where: Index) -> float:
    """The length (mm) of the edges at *where* of a closed path (its joins left out)."""
    return float(element_lengths(path)[where].sum())


def element_lengths(path: Profile) -> Array:
    """The length (mm) of each edge of a closed path of lines and arcs."""
    v = path.vertices
    length = np.hypot(*(np.roll(v, -1, axis=0) - v).T)
    arcs = path.arcs()
    length[arcs.index] = arcs.radius * np.abs(arcs.sweep)
    return length


def start_tangent(path: Profile) -> Array:
    """The unit direction (2,) a path leaves its first vertex in."""
    v0, v1 = path.vertices[0], path.vertices[1 % len(path.vertices)]
    if path.bulges[0] == 0.0:
        d = v1 - v0
        return d / math.hypot(*d)
    arcs = path.arcs()
    centre = arcs.centre[int(np.flatnonzero(arcs.index == 0)[0])]
    radial = (v0 - centre) / math.hypot(*(v0 - centre))
    turn = math.copysign(1.0, float(arcs.sweep[np.flatnonzero(arcs.index == 0)[0]]))
    return turn * np.array([-radial[1], radial[0]])


def laps(path: Profile, share: Array, depths: Array, ramp: float, lead: Lead) -> list[Move]:
    """A lap round *path* (mm, its vertices at *share* of a lap) at each of *depths* (z, mm),
    from the height before the first (``lead.entry_z``): each lap ramps down from the last
    depth to its own along the path up to the first vertex at least *ramp* of a lap on, at
    ``lead.plunge``, and runs level from there at ``lead.feed`` (a level lap at a depth
    repeated)."""
    v = path.vertices
    n = len(v)
    following = np.roll(v, -1, axis=0)
    chord = np.hypot(*(following - v).T)
    arcs = path.arcs()
    centre = np.full((n, 2), np.nan)
    centre[arcs.index] = arcs.centre
    sagitta = np.zeros(n)
    sagitta[arcs.index] = arcs.radius * (1.0 - np.cos(arcs.sweep / 2.0))
    straight = (path.bulges == 0.0) | (sagitta < FLAT_ARC_MM) | (chord < SHORT_ARC_MM)
    ends = np.concatenate((share[1:], [1.0]))
    last = ends[ends >= ramp - 1e-12].min()  # where each lap's ramp ends
    down = np.minimum(ends / last, 1.0)  # share of the drop done at each vertex
    tops = np.concatenate(([lead.entry_z], depths[:-1]))
    z = tops[:, None] + (depths - tops)[:, None] * down[None, :]
    # the ramp at the plunge feed, the corners within it too: a control's compensation turns
    # round them at the ramp's feed (and round a corner where the ramp ends at the next move's)
    ramping = (tops > depths)[:, None] & (share < last - 1e-12)[None, :]
    feeds = np.where(ramping, lead.plunge, lead.feed).ravel()
    moves = []
    for k, z_end, feed in zip(np.tile(np.arange(n), len(depths)), z.ravel(), feeds,
                              strict=True):
        end = (float(following[k, 0]), float(following[k, 1]), float(z_end))
        if straight[k]:
            moves.append(Move("G1", end, feed=float(feed)))
        else:
            moves.append(Move("G3" if path.bulges[k] > 0.0 else "G2", end,
                              (float(centre[k, 0]), float(centre[k, 1])), float(feed)))
    return moves


def lead_arc(start: Array, centre: Array, end: Array, left: bool, z: float,
             feed: float) -> Move:
    """A level arc from *start* to *end* about *centre* (mm), turning left (G3) or right."""
    return Move("G3" if left else "G2", (float(end[0]), float(end[1]), z),
                (float(centre[0]), float(centre[1])), feed)


def pass_moves(path: Profile, share: Array, left: bool, radius: float, control: bool,
               lead: Lead, depths: Array, ramp: float) -> list[Move]:
    """A whole pass round *path* (directed, mm; its vertices at *share* of a lap), the tool of
    *radius* (mm) on its *left* (the waste's side) when so: *path* the tool centre's, or with
    *control* the part's contour that the control's compensation offsets; a lap at each of
    *depths* (z, mm), each ramping down over *ramp* of a lap or a little more (see
    :func:`laps`).

    The tool comes down over the waste and enters along a straight move twice its radius long
    (the control's entry move, which must be longer than the radius) then a quarter circle onto
    the contour; both forms make the same moves."""
    start = path.vertices[0]
    t = start_tangent(path)
    n = (1.0 if left else -1.0) * np.array([-t[1], t[0]])  # toward the waste
    offset = radius if control else 0.0
    centre_in = start + (lead.lead_in + offset) * n
    enter = centre_in - (lead.lead_in + offset) * t
    # where the tool stands before the entry: the same place in both forms
    above = centre_in - (lead.lead_in + radius) * t + 2.0 * radius * n

    def at(p: Array, z: float) -> tuple[float, float, float]:
        return (float(p[0]), float(p[1]), z)

    moves = [Move("G0", at(above, lead.safe_z)),
             Move("G1", at(above, lead.entry_z), feed=lead.plunge)]
    if control:
        moves.append(Move("words", words=f"G{41 if left else 42} D1"))
    moves += [Move("G1", at(enter, lead.entry_z), feed=lead.plunge),
              lead_arc(enter, centre_in, start, left, lead.entry_z, lead.plunge)]
    moves += laps(path, share, depths, ramp, lead)
    if lead.lead_out > 0.0:
        radius_out = lead.lead_out + offset
        centre_out = start + radius_out * n
        moves.append(lead_arc(start, centre_out, centre_out + radius_out * t, left,
                              float(depths[-1]), lead.feed))
    end = moves[-1].end
    assert end is not None
    moves.append(Move("G0", (end[0], end[1], lead.safe_z)))
    if control:
        moves.append(Move("words", words="G40"))
    return moves


def write(program: Program, moves: list[Move], position: Array) -> Array:
    """*moves* as blocks of *program*, from *position* (3,) (mm, the last programmed one): the
    axes a move changes, its feed where it changes; returns the last programmed position."""
    feed = math.nan
    for move in moves:
        if move.end is None:
            if move.code == "words":
                program.block(move.words)
            else:
                program.comment(move.words)
            continue
        end = np.array(move.end)
        words = [move.code]
        arc = move.centre is not None
        for axis, k in (("X", 0), ("Y", 1), ("Z", 2)):
            if (arc and k < 2) or abs(end[k] - position[k]) > NO_MOVE_MM:
                words.append(program.word(axis, float(end[k])))
        if len(words) == 1:
            continue
        if arc:
            assert move.centre is not None
            words += [program.word("I", move.centre[0] - float(position[0])),
                      program.word("J", move.centre[1] - float(position[1]))]
        if move.feed is not None and move.code != "G0" and move.feed != feed:
            feed = move.feed
            words.append(program.word("F", feed))
        program.block(*words)
        position = end
    return position


def minutes(moves: list[Move], position: Array) -> float:
    """The time (min) the feed moves of *moves* take at their feeds, from *position* (3,)
    (mm; rapid moves not counted)."""
    total = 0.0
    for move in moves:
        if move.end is None:
            continue
        end = np.array(move.end)
        if move.code != "G0":
            assert move.feed is not None
            if move.centre is None:
                length = float(np.linalg.norm(end - position))
            else:
                centre = np.array(move.centre)
                sweep = _sweep(position[:2], end[:2], centre, move.code == "G3")
                length = math.hypot(math.hypot(*(position[:2] - centre)) * sweep,
                                    end[2] - position[2])
            total += length / move.feed
        position = end
    return total


def _sweep(start: Array, end: Array, centre: Array, ccw: bool) -> float:
    a0 = math.atan2(*(start - centre)[::-1])
    a1 = math.atan2(*(end - centre)[::-1])
    sweep = (a1 - a0) % (2 * math.pi) if ccw else -((a0 - a1) % (2 * math.pi))
    return sweep if abs(sweep) > 1e-12 else (2 * math.pi if ccw else -2 * math.pi)


def plan(moves: list[Move], position: Array, tolerance: float) -> tuple[Array, Array]:
    """The plan view (XY, mm) of *moves* from *position*: the points of the moves that cut
    (below the top face, z = 0; arcs within *tolerance*, mm) and of those that do not (rapid
    moves, and feed moves in the air: the way down to a pass and its entry), each run of one
    kind split from the next by a row of NaN."""
    cutting: list[Array] = []
    rapid: list[Array] = []
    gap = np.full((1, 2), np.nan)
    last = None
    for move in moves:
        if move.end is None:
            continue
        end = np.array(move.end)
        air = move.code == "G0" or min(end[2], position[2]) >= 0.0
        kind = "rapid" if air else "cut"
        if move.centre is None:
            piece = np.array([position[:2], end[:2]])
        else:
            centre = np.array(move.centre)
            piece = arc_points(centre, position[:2], _sweep(position[:2], end[:2], centre,
                                                             move.code == "G3"), tolerance)
        if np.hypot(*(piece[-1] - piece[0])) > 0.0 or move.centre is not None:
            into = rapid if kind == "rapid" else cutting
            if last != kind:
                into.append(gap)
            into.append(piece if last != kind else piece[1:])
            last = kind
        position = end
    return (np.vstack(cutting[1:]) if cutting else np.empty((0, 2)),
            np.vstack(rapid[1:]) if rapid else np.empty((0, 2)))
