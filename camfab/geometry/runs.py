"""Chains of points with corners fitted with lines and arcs run by run: an arc is never fitted
across a corner (the arc fit measures only the points it is given, so an arc through a corner
and the points either side of it can bow far from the chords between them).

The corners are a trimmed cam's: where the loops of an envelope that folds over were cut away
(vertices that are not sampled points of the envelope), and a velocity step's kinks.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from camfab.arrays import Array, Mask
from camfab.curves.plane import signed_angle
from camfab.curves.profile import Profile
from camfab.geometry.arcfit import fit_arcs


def among(points: Array, table: Array) -> Mask:
    """Whether each of (N, 2) *points* is one of the (M, 2) points *table*, coordinate by
    coordinate equal (as floats compare: −0 is 0, NaN is nothing)."""
    def joined(xy: Array) -> Array:
        out = np.empty(len(xy), dtype=np.complex128)
        out.real, out.imag = xy[:, 0], xy[:, 1]
        return out

    return np.isin(joined(points), joined(table))


def fit_runs(chain: Array, corners: Mask, tolerance: float,
             chords: bool = False) -> tuple[Array, Array]:
    """An open chain of points (mm) as lines and arcs within *tolerance* (mm), fitted run by run
    between its *corners* (an arc is never fitted across a corner): vertices and the bulges of
    the edges after them, the last vertex's bulge 0. With *chords* the arcs hold the chords
    between the points too (:func:`~camfab.geometry.arcfit.fit_arcs`)."""
    cuts = [0, *np.flatnonzero(corners[1:-1]) + 1, len(chain) - 1]
    vertices, bulges = [], []
    for a, b in itertools.pairwise(cuts):
        if b <= a:
            continue
        fitted = fit_arcs(chain[a:b + 1], tolerance, closed=False, chords=chords)
        vertices.append(fitted.vertices[:-1])
        bulges.append(fitted.bulges[:-1])
    vertices.append(chain[-1:])
    bulges.append(np.zeros(1))
    return np.concatenate(vertices), np.concatenate(bulges)


def fit_closed(ring: Array, corners: Mask, tolerance: float, chords: bool = False) -> Profile:
    """A closed chain (mm, without a repeated closing point) as lines and arcs within
    *tolerance* (mm), no arc across a vertex marked in *corners*; with *chords* the arcs hold
    the chords between the points too."""
    if not corners.any():
        return fit_arcs(ring, tolerance, chords=chords)
    first = int(np.flatnonzero(corners)[0])
    ring, corners = np.roll(ring, -first, axis=0), np.roll(corners, -first)
    vertices, bulges = fit_runs(np.vstack((ring, ring[:1])), np.append(corners, True),
                                tolerance, chords)
    return Profile(vertices[:-1], bulges[:-1])


#: The longest chord of a chain handed to the arc fit after an offset (mm): the fit measures only
#: the points it is given, so long straight edges (the base line, a dwell) are cut into pieces
#: this short and an arc cannot bow away from them between points.
MAX_CHORD_MM = 0.25

#: A turn sharper than this between two chords (rad) is a corner no arc is fitted across: far
#: sharper than a curve sampled within the tolerance turns between points of its smooth parts.
CORNER_TURN = math.radians(30.0)


def densify(ring: Array, step: float) -> Array:
    """A closed chain of points with each edge cut into pieces no longer than *step* (mm)."""
    following = np.roll(ring, -1, axis=0)
    count = np.maximum(1, np.ceil(np.hypot(*(following - ring).T) / step).astype(int))
    index = np.repeat(np.arange(len(ring)), count)
    frac = (np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)) / np.repeat(
        count, count)
    return ring[index] + frac[:, None] * (following[index] - ring[index])


def fit_grown(ring: Array, distance: float, tolerance: float) -> Profile:
    """A closed chain an offset by *distance* (mm) made (round joins of that radius cut into
    chords, straight edges as long as those of the chain it grew from, corners where a hole's
    corners stay sharp) as lines and arcs within *tolerance* (mm), no arc across a turn sharper
    than :data:`CORNER_TURN`.

    The fit measures only the points it is given, and an arc that takes in a round join bends
    about as tightly as the join: one of radius R bows h²/8R from a chord h long between two
    of its points. So the edges are cut into pieces no longer than √(4·|distance|·tolerance)
    (and :data:`MAX_CHORD_MM`): an arc of half the join's radius or more then stays within
    *tolerance* between points too."""
    step = min(MAX_CHORD_MM, math.sqrt(4.0 * abs(distance) * tolerance))
    ring = densify(ring, step)
    turn_step = np.roll(ring, -1, axis=0) - ring
    turn = np.abs(signed_angle(np.roll(turn_step, 1, axis=0), turn_step))
    return fit_closed(ring, turn > CORNER_TURN, tolerance)
