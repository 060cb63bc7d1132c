"""Polydyne cams: the cam's lift s(θ) that makes the follower's mass move exactly as a program
x(θ) asks, through the elastic follower train, at one cam speed (THEORY §J; Dudley 1948,
Stoddart 1953).

The train (:mod:`camfab.design.train`) is a mass m on a spring k_f and a damper c to the cam,
held by a return spring k_s (damper c_s) under a constant load P. With x measured from where the
mass rests on the base circle (the load's static compression taken out), the mass follows x
exactly when the cam's lift s, in the program's units and per radian of cam angle at the cam
speed ω, solves

    s + τ s′ = g,    g = (K/k_f) x + ((c + c_s) ω / k_f) x′ + (m ω² / k_f) x″,    τ = c ω / k_f,

(K = k_f + k_s). Without damping s = g. With damping s is the equation's periodic solution: on
each polynomial piece of the program (every law a polydyne cam may follow is piecewise
polynomial), g is a polynomial, its particular solution the finite sum Σ (−τ)ᵏ g⁽ᵏ⁾ (exact: the
sum ends at g's degree), and the rest a term A e^{−v/τ} (v the angle into the piece) whose
constants make s continuous all round the turn, a cyclic recurrence solved in closed form. The
cam's s″ carries the output's x⁗, and its s‴ the fifth derivative: a polydyne cam's laws need
their first four derivatives continuous at every joint (:func:`rough_joints`).

A dwell of x is a dwell of the mass: the cam there is x·K/k_f plus, with damping, the tail of
the last motion's A e^{−v/τ} (some 1e-5 mm, dying over a few degrees).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import polynomial as P
from numpy.typing import ArrayLike

from camfab.motion.law import Array, Law, as_unit_array
from camfab.motion.laws import DWELL
from camfab.motion.program import MotionProgram, ProgramSegment

#: Derivatives 1…4 of the output at a joint differ by at most this share of their largest value
#: over the program (matched polynomials agree to some 1e-12; a real step is a sizeable share).
RELATIVE_STEP = 1e-7

#: A polydyne segment's peak values are taken from this many points over it, each then refined
#: by the parabola through it and its neighbours (a share some 1e-10 of the peak).
PEAK_SAMPLES = 4001


@dataclass(frozen=True)
class TrainTerms:
    """The follower train in the polydyne equation, per the program's units: the stiffness ratio
    K/k_f, the damping term (c + c_s) ω/k_f (rad), the inertia term m ω²/k_f (rad²) and the lag
    τ = c ω/k_f (rad) of the train's own damper."""

    stiffness: float
    damping: float
    inertia: float
    lag: float

    @classmethod
    def of(cls, mass: float, stiffness: float, spring: float, damper: float,
           spring_damper: float, omega: float) -> TrainTerms:
        """The terms of a train of *mass* (kg), *stiffness* k_f and return *spring* k_s (N/m),
        *damper* c and *spring_damper* c_s (N·s/m), at the cam speed *omega* (rad/s)."""
        return cls((stiffness + spring) / stiffness, (damper + spring_damper) * omega / stiffness,
                   mass * omega * omega / stiffness, damper * omega / stiffness)


@dataclass(frozen=True)
class _Pieces:
    """The cam's lift, piece by piece round the turn: each piece's start angle and length
    (rad), its particular solution's ascending coefficients in the angle v into the piece
    (padded to one length), and its homogeneous term's constant A; how many pieces each
    segment of the program has, in order."""

    start: Array
    length: Array
    particular: Array
    homogeneous: Array
    lag: float
    counts: tuple[int, ...]

    def values(self, piece: Array, v: Array, orders: int = 4) -> Array:
        """s and its derivatives to *orders* − 1 at *v* (rad) into each *piece*: (orders, N)."""
        coefficients = self.particular[piece]  # (N, D)
        out = np.empty((orders, v.size))
        powers = np.arange(coefficients.shape[1])
        current = coefficients
        for n in range(orders):
            out[n] = np.sum(current * v[:, None] ** powers[None, :], axis=1) if v.size else 0.0
            current = current[:, 1:] * powers[None, 1 : current.shape[1]]
            powers = powers[: current.shape[1]]
        if self.lag > 0.0:
            tail = self.homogeneous[piece] * np.exp(-v / self.lag)
            out += tail[None, :] * ((-1.0 / self.lag) ** np.arange(orders))[:, None]
        return out


def rough_joints(program: MotionProgram) -> list[tuple[int, str]]:
    """The segments of *program* a polydyne cam cannot follow, each with why: a law that is
    not piecewise polynomial with four derivatives (:attr:`Law.top_order` below 5), or a joint
    where one of the first four derivatives steps (given for the segment after it)."""
    bad: list[tuple[int, str]] = []
    for seg in program.segments:
        if seg.kind != "dwell" and (seg.law.top_order < 5 or seg.law.pieces() is None):
            bad.append((seg.index, f"the {seg.law_name} law has no continuous fourth "
                                   "derivative"))
    if bad:
        return bad
    n = len(program.segments)
    ends = [_derivatives(seg, np.array([0.0, seg.span]), 4) for seg in program.segments]
    # each derivative's scale over the program, from samples of every segment
    scale = np.max(np.abs(np.concatenate(
        [_derivatives(seg, np.linspace(0.0, seg.span, 65), 4) for seg in program.segments],
        axis=1)), axis=1)
    for i, seg in enumerate(program.segments):
        left, right = ends[(i - 1) % n][:, 1], ends[i][:, 0]
        for order, name in ((1, "velocity"), (2, "acceleration"), (3, "jerk"), (4, "snap")):
            if abs(left[order] - right[order]) > RELATIVE_STEP * max(scale[order], 1e-300):
                bad.append((seg.index, f"its {name} steps where it starts "
                                       f"({left[order]:.6g} before, {right[order]:.6g} after, "
                                       "per radian)"))
                break
    return bad


def _derivatives(seg: ProgramSegment, t: Array, order: int) -> Array:
    """x and its derivatives to *order* (per radian) at *t* radians into *seg*."""
    f = seg.law.derivatives(t / seg.span, order)
    out = f * (seg.delta / seg.span ** np.arange(order + 1))[:, None]
    out[0] += seg.s0
    return out


def _solve(program: MotionProgram, terms: TrainTerms) -> _Pieces:
    """The cam's lift piece by piece (:class:`_Pieces`): each law's pieces as polynomials in the
    angle into them, g and its particular solution, and the homogeneous constants that join
    them all round the turn."""
    starts, lengths, particular, forcing, counts = [], [], [], [], []
    for seg in program.segments:
        pieces = seg.law.pieces()
        assert pieces is not None, "rough_joints refuses laws without polynomial pieces"
        breaks, coefficients = pieces
        counts.append(len(coefficients))
        for a, b, c in zip(breaks[:-1], breaks[1:], coefficients, strict=True):
            # x on the piece in v = θ − its start (rad): s₀ + Δ Σ cₖ (v/β)ᵏ
            x = np.asarray(c, dtype=np.float64) * seg.delta / seg.span ** np.arange(len(c))
            x = P.polyadd(x, [seg.s0])
            g = P.polyadd(P.polyadd(terms.stiffness * x, terms.damping * P.polyder(x)),
                          terms.inertia * P.polyder(x, 2))
            p, term = np.zeros(1), np.asarray(g)
            for k in range(len(g)):  # Σ (−τ)ᵏ g⁽ᵏ⁾, ending at g's degree
                p = P.polyadd(p, (-terms.lag) ** k * term)
                term = P.polyder(term)
                if not term.size or terms.lag == 0.0:
                    break
            starts.append(seg.start + a * seg.span)
            lengths.append((b - a) * seg.span)
            particular.append(p)
            forcing.append(g)
    width = max(len(p) for p in particular)
    table = np.zeros((len(particular), width))
    for i, p in enumerate(particular):
        table[i, : len(p)] = p
    length = np.array(lengths)
    homogeneous = np.zeros(len(particular))
    if terms.lag > 0.0:
        # continuity at each piece's start: A_j = d_j + E_{j−1} A_{j−1}, d_j the particular
        # solutions' mismatch there, E the homogeneous term's decay over a piece
        mismatch = np.array([_mismatch(forcing[i - 1], length[i - 1], forcing[i], terms.lag)
                             for i in range(len(forcing))])
        decay = np.exp(-length / terms.lag)
        homogeneous = _cyclic(mismatch, np.roll(decay, 1))
    return _Pieces(np.array(starts), length, table, homogeneous, terms.lag, tuple(counts))


def _mismatch(before: Array, length: float, after: Array, lag: float) -> float:
    """The particular solutions' mismatch where a piece of forcing *before* (over *length*
    rad) meets one of forcing *after*: Σ (−τ)ᵏ (g⁽ᵏ⁾ before − g⁽ᵏ⁾ after), from k = 3. Below
    that the terms vanish (g, g′, g″ are continuous where the output's first four derivatives
    are, as :func:`rough_joints` makes them): taken from k = 0, their rounding (some 1e-16 of
    the lift) divided by τⁿ in the cam's derivatives would swamp a slow cam's."""
    total, left, right = 0.0, np.asarray(before), np.asarray(after)
    for k in range(max(len(left), len(right))):
        if k >= 3:
            total += (-lag) ** k * (P.polyval(length, left) - (right[0] if right.size else 0.0))
        left, right = P.polyder(left), P.polyder(right)
        if not left.size and not right.size:
            break
    return float(total)


def _cyclic(d: Array, e: Array) -> Array:
    """The periodic solution of A_j = d_j + e_j A_{j−1} (indices mod n): A_0 from the whole
    turn's product, then the rest forward."""
    n = d.size
    # A_0 = d_0 + e_0 d_{n−1} + e_0 e_{n−1} d_{n−2} + … + (Π e) A_0
    total, product = d[0], 1.0
    for j in range(n - 1, 0, -1):
        product *= e[(j + 1) % n]
        total += product * d[j]
    whole = float(np.prod(e))
    out = np.empty(n)
    out[0] = total / (1.0 - whole) if whole < 1.0 else 0.0
    for j in range(1, n):
        out[j] = d[j] + e[j] * out[j - 1]
    return out


class PolydyneLaw(Law):
    """One segment of a polydyne cam as a law: f(u) = (s(θ) − s₀)/Δ over the segment, from the
    cam's pieces (:class:`_Pieces`) that lie in it."""

    def __init__(self, name: str, pieces: _Pieces, first: int, count: int, start: float,
                 span: float, s0: float, delta: float) -> None:
        self.name = name
        self._pieces, self._first, self._count = pieces, first, count
        self._start, self._span, self._s0, self._delta = start, span, s0, delta
        self.breakpoints = tuple(float((pieces.start[k] - start) / span)
                                 for k in range(first + 1, first + count))
        self.inner_step_order = 3 if count > 1 else None

    def evaluate(self, u: ArrayLike) -> Array:
        u = as_unit_array(u)
        v_all = u * self._span
        local = self._pieces.start[self._first : self._first + self._count] - self._start
        k = np.clip(np.searchsorted(local, v_all, side="right") - 1, 0, self._count - 1)
        if u.size and u[-1] >= 1.0:
            k[u >= 1.0] = self._count - 1
        values = self._pieces.values(self._first + k, v_all - local[k])
        values[0] -= self._s0
        return values * (self._span ** np.arange(4) / self._delta)[:, None]

    def _peaks(self) -> tuple[float, float, float]:
        u = np.linspace(0.0, 1.0, PEAK_SAMPLES)
        values = np.abs(self.evaluate(u))
        peaks = []
        for order in (1, 2, 3):
            row = values[order]
            i = int(np.clip(np.argmax(row), 1, row.size - 2))
            a, b, c = row[i - 1], row[i], row[i + 1]
            bend = a - 2 * b + c
            peaks.append(float(max(row.max(), b - (a - c) ** 2 / (8 * bend) if bend < 0 else 0)))
        return (peaks[0], peaks[1], peaks[2])


class PolydyneProgram(MotionProgram):
    """A polydyne cam's lift s(θ), segment by segment as the *output* program's, with the
    output program x(θ) it makes the follower's mass follow at the *speed_rpm* it is cut for."""

    def __init__(self, output: MotionProgram, terms: TrainTerms, speed_rpm: float) -> None:
        self.output, self.terms, self.speed_rpm = output, terms, speed_rpm
        pieces = _solve(output, terms)
        segments, first = [], 0
        for seg, count in zip(output.segments, pieces.counts, strict=True):
            ends = pieces.values(np.array([first, first + count - 1]),
                                 np.array([0.0, pieces.length[first + count - 1]]), 1)[0]
            s0, delta = float(ends[0]), float(ends[1] - ends[0])
            law: Law = DWELL if delta == 0.0 else PolydyneLaw(
                seg.law_name, pieces, first, count, seg.start, seg.span, s0, delta)
            segments.append(ProgramSegment(seg.index, seg.kind, seg.law_name, law, seg.start,
                                           seg.span, s0, delta))
            first += count
        super().__init__(segments)

    @functools.cached_property
    def max_lift(self) -> float:  # type: ignore[override]
        """The cam's largest lift (mm or rad): over the segments' samples, not only their ends
        (the inertia term can carry s past a rise's end)."""
        theta = np.linspace(0.0, 2.0 * math.pi, 20 * PEAK_SAMPLES, endpoint=False)
        return max(float(np.max(self.evaluate(theta)[0])),
                   max(max(seg.s0, seg.s1) for seg in self.segments))
