"""The follower of a plate cam pressed onto a flank's grid of points: each node bounds the
follower by itself, in closed form, at each row's cam angle (:class:`Rider`).

In the frame at cam angle θ (the plate turned by σθ about its centre, as
:func:`camfab.geometry.simulate.simulate` turns it) a node at (x, y) holds off

- a roller or mushroom of radius R on the line x = e: its centre at y ± √(R² − (x − e)²);
- a roller on an arm: its centre where the circle of radius R about the node meets the arm's
  circle about the pivot, the arm angle Ψ there;
- a translating flat face: at the face height y; an oscillating one at the arm angle whose face
  line passes through the node (:func:`~camfab.geometry.simulate.face_angle`);
- a knife (no width: it touches no node but between them): where its path crosses the chord
  from the node to the same column's node of the next row.

A flank that pushes its follower toward its +coordinate (a disc cam's profile, a groove's
inner wall, each plate of a pair seen from its own roller) takes the larger root, one that
pulls it back (a groove's outer wall) the smaller. The row's bound is the extreme over the
nodes of the rows within the rider's window (:func:`~camfab.inspect.surface.windowed_run`). On
the exact grid the node of the row itself is the one the follower touches, so the run is the
design's coordinate to the rounding of the arithmetic; the nodes of the neighbouring rows fall
away from the follower by the curvature of the flank and of the roller.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camfab.arrays import Array
from camfab.curves.plane import dot, rotate
from camfab.geometry.conjugate import half_turned, mirrored
from camfab.geometry.disc import DiscCam
from camfab.geometry.simulate import arm_angle, face_angle
from camfab.inspect.surface import windowed_run

#: How far (mm, at the trace point) a node may stand proud of the design's flank and still be
#: sought by the run in a row's window: the rows whose nodes would carry the follower if they
#: stood this much further out than the row's own, or lie within this distance of its contact.
#: Deviations of a made part are well inside it.
WINDOW_MARGIN_MM = 0.5

#: Slack on the share along a knife's chord, so a crossing exactly at a node is not lost to
#: rounding (each chord takes its own end).
CHORD_SLACK = 1e-9

#: Shifts of rows tried at once when the window is fitted; a block without a node in reach ends
#: the search (beyond the follower's footprint no node of a simple outline comes back).
WINDOW_BLOCK = 32


@dataclass(frozen=True)
class Rider:
    """The follower on one flank of a plate cam.

    Attributes
    ----------
    cam
        The exact evaluators of the plate in the frame it is computed in: its follower (a
        groove's gauge roller, of the roller's radius plus half the clearance) and sense of
        turning σ.
    push
        −1: the flank pushes the follower toward its own +coordinate (it bounds it from below),
        +1: back (from above).
    spacing
        A conjugate pair's cam b: the rollers' distance (mm) or the arms' angle (rad) that joins
        its follower's coordinate y_b to the model's, q = spacing − y_b; None: q is the
        follower's own coordinate.
    mirror
        How the flank's points in the STL's frame reach the frame *cam* is computed in: None
        (they are in it), False (turned half a turn), True (mirrored in the line of centres);
        each move is its own inverse.
    window
        Rows either side of a row whose nodes the follower may touch at its angle.
    """

    cam: DiscCam
    push: int
    spacing: float | None = None
    mirror: bool | None = None
    window: int = 0

    @property
    def side(self) -> int:
        """The flank's side for the model's q (a pair's cam b bounds q the other way)."""
        return -self.push if self.spacing is not None else self.push

    @property
    def knife(self) -> bool:
        fol = self.cam.follower
        return not fol.flat and fol.radius == 0.0

    def nodes(self, points: Array) -> Array:
        """What the bounds take of (R, C, 3) *points* (mm): the points, or for a knife each
        point with the same column's point of the next row, (R, C, 6): the chords."""
        if not self.knife:
            return points
        return np.concatenate((points, np.roll(points, -1, axis=0)), axis=-1)

    def run(self, points: Array, theta: Array) -> Array:
        """The follower run over (R, C, 3) *points* (mm, NaN where unscanned) touched at the
        cam angles *theta* (rad): the bound of q at each row (q's unit; NaN where none)."""
        return windowed_run(self.nodes(points), theta, self.side, self.window, self.bounds)

    def bounds(self, nodes: Array, theta: Array, side: int) -> Array:
        """q at which the follower touches each of *nodes* at the cam angles *theta* (rad,
        broadcast with the nodes' leading shape); NaN where it cannot (*side* is the rider's)."""
        own = self.own(nodes, theta)
        return own if self.spacing is None else self.spacing - own

    def own(self, nodes: Array, theta: Array) -> Array:
        """The follower's own coordinate (mm or rad) at which it touches each of *nodes* at
        *theta*; NaN where it cannot."""
        fol = self.cam.follower
        xy = self._frame(nodes[..., :2], theta)
        with np.errstate(invalid="ignore", divide="ignore"):
            if fol.flat:
                value = (face_angle(xy, fol.face_offset, self.cam.pivot, fol)
                         if fol.oscillating else xy[..., 1])
            elif self.knife:
                value = self._chord(xy, self._frame(nodes[..., 3:5], theta))
            elif fol.oscillating:
                value = self._ring(xy)
            else:
                rise = np.sqrt(fol.radius**2 - (xy[..., 0] - fol.offset) ** 2)
                value = xy[..., 1] - self.push * rise
        return np.where(np.isfinite(value), value, np.nan)

    def _frame(self, xy: Array, theta: Array) -> Array:
        """(..., 2) points of the STL's frame in the follower's frame at cam angles *theta*."""
        if self.mirror is not None:
            xy = mirrored(xy) if self.mirror else half_turned(xy)
        return rotate(xy, self.cam.sigma * theta)

    def _pick(self, first: Array, second: Array) -> Array:
        """The root that bounds: the larger for a flank that pushes, else the smaller (NaN and
        −inf, no root, ignored)."""
        first, second = (np.where(np.isfinite(v), v, np.nan) for v in (first, second))
        return np.fmax(first, second) if self.push < 0 else np.fmin(first, second)

    def _ring(self, xy: Array) -> Array:
        """The arm angles at which the roller's centre, on the arm's circle about the pivot,
        stands its radius R from frame points *xy*: a point ρ from the pivot at the arm angle γ
        (as Ψ is measured) has the centre, L from the pivot, R from it at Ψ = γ ± δ, cos δ =
        (L² + ρ² − R²)/(2Lρ); the trace point above the line of centres (0 ≤ Ψ ≤ π)."""
        fol = self.cam.follower
        arm = fol.arm_length
        across = fol.pivot_distance - fol.pivot_sign * xy[..., 0]
        up = xy[..., 1]
        rho2 = across * across + up * up
        delta = np.arccos((arm * arm + rho2 - fol.radius**2) / (2.0 * arm * np.sqrt(rho2)))
        gamma = np.arctan2(up, across)
        high, low = gamma + delta, gamma - delta
        high = np.where(high > np.pi, high - 2.0 * np.pi, high)
        low = np.where(low < -np.pi, low + 2.0 * np.pi, low)
        return self._pick(*(np.where((psi >= 0.0) & (psi <= np.pi), psi, np.nan)
                            for psi in (high, low)))

    def _chord(self, a: Array, b: Array) -> Array:
        """Where the knife's path crosses the chords from frame points *a* to *b*."""
        fol = self.cam.follower
        d = b - a
        if not fol.oscillating:
            t = (fol.offset - a[..., 0]) / d[..., 0]
            on = (t >= -CHORD_SLACK) & (t <= 1.0 + CHORD_SLACK)
            return np.where(on, a[..., 1] + t * d[..., 1], np.nan)
        rel = a - self.cam.pivot
        qa, qb = dot(d, d), 2.0 * dot(d, rel)
        qc = dot(rel, rel) - fol.arm_length**2
        root = np.sqrt(qb * qb - 4.0 * qa * qc)
        found = []
        for t in ((-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa)):
            on = (t >= -CHORD_SLACK) & (t <= 1.0 + CHORD_SLACK)
            found.append(np.where(on, arm_angle(a + t[..., None] * d, fol), np.nan))
        return self._pick(*found)


def fit_window(rider: Rider, column: Array, theta: Array, own: Array, margin: float) -> int:
    """The rows either side of a row whose nodes the follower may touch at its angle: those
    whose node, on the design's flank, holds the follower within *margin* (its own unit) of
    its design coordinate *own* (R,) there, or lies within :data:`WINDOW_MARGIN_MM` of the
    row's contact. *column* is one column of the flank's exact grid, (R, 3) mm (a plate's
    columns are the same outline); *theta* the rows' cam angles (rad)."""
    rows = len(theta)
    nodes = rider.nodes(column[:, None, :])[:, 0, :]
    contact = column[:, :2]
    every = np.arange(rows)
    widest = 0
    for start in range(1, rows // 2 + 1, WINDOW_BLOCK):
        shifts = np.arange(start, min(start + WINDOW_BLOCK, rows // 2 + 1))
        reached = np.zeros(len(shifts), dtype=bool)
        for sign in (1, -1):
            index = (every[None, :] + sign * shifts[:, None]) % rows
            with np.errstate(invalid="ignore"):
                holds = rider.push * (rider.own(nodes[index], theta) - own) < margin
            gap = contact[index] - contact
            near = np.hypot(gap[..., 0], gap[..., 1]) <= WINDOW_MARGIN_MM
            reached |= (holds | near).any(axis=1)
        if not reached.any():
            break
        widest = int(shifts[reached].max())
    return widest
