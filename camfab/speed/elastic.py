"""The elastic follower train (THEORY §J): one mass on a spring and damper driven by the cam, its
periodic steady state at the cam's speed, computed exactly for this linear model.

The follower's mass m sits at x; between it and the cam's kinematic lift s the follower train
is a spring k_f and a damper c = 2ζ√(mK) (K = k_f + k_s); the return spring k_s (with its
preload), the spring's own damping c_s, the loads and gravity act on the mass. With the
dynamic error e = x − s:

    m e¨ + (c + c_s) e˙ + K e = −F_r(t),    F_r = m s¨ + c_s s˙ + k_s s + P,

F_r being the rigid model's contact force (:mod:`camfab.analysis.dynamics`), and the contact
force is F_c = k_f (s − x) + c (s˙ − x˙) = −k_f e − c e˙. As k_f grows, e → −F_r/K and F_c →
F_r: the rigid model. A positive-drive cam has no return spring: k_s = c_s = P = 0.

The solution: in the time τ = ω_n t (ω_n = √(K/m)) and the follower's one complex mode
w (e = 2 Re w), w′ = λw + u/(2iω_d) with u = −F_r/K, λ = −ζ_t + iω_d, ω_d = √(1 − ζ_t²).
Over each step of the analysis grid the forcing is the cubic that matches F_r and its
derivative at both ends (both exact, from s … s‴), and the step's response to it is exact:
the exponential and its φ-functions, w₁ = e^{λH} w₀ + Σ φ_k(λH)… (Hochbruck & Ostermann,
*Exponential integrators*, 2010). The forcing's cubic departs from F_r by at most
H⁴ max|F_r⁗|/384 per step (some 1e-13 of it on the 0.05° grid), so the response is exact to
that. The steps are chained by a prefix scan of their affine maps (log₂ N passes of whole
arrays), and the periodic start is the fixed point w₀ = v/(1 − e^{λT}) of the whole turn; it
does not exist at undamped resonance, ω_n T = 2πk, which the design file's rules refuse.

Units: SI inside (m, s, N, kg); the grid's angles in rad, its derivatives per radian.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array

if TYPE_CHECKING:
    from camfab.design.train import Train

#: Below this |λH| the φ-functions are summed as their Taylor series (to its last term that
#: counts); above it, by their recurrence from e^{λH}, which is then well conditioned.
_SERIES_BELOW = 1.0
_SERIES_TERMS = 22


@dataclass(frozen=True)
class Response:
    """The periodic steady state on the grid: the dynamic error e = x − s (m), its rate de/dθ
    (m/rad) and the contact force F_c (N) at each grid angle (rad); the least contact force of
    the continuous response (N) and its cam angle (rad)."""

    theta: Array
    error: Array
    error_rate: Array
    force: Array
    least: float = math.nan
    least_at: float = math.nan


def rigid_force(train: Train, omega: float, motion: Array) -> tuple[Array, Array]:
    """F_r = m ω² s″ + c_s ω s′ + k_s s + P (N) and dF_r/dθ (N/rad) at the *motion* (s, s′, s″,
    s‴ in m and per radian, (4, N)) at the cam speed *omega* (rad/s)."""
    m, cs, ks = train.mass, train.spring_damping, train.spring
    s, v, a, j = motion
    force = m * omega * omega * a + cs * omega * v + ks * s + train.load
    rate = m * omega * omega * j + cs * omega * a + ks * v
    return force, rate


def phi_functions(z: Array) -> tuple[Array, Array, Array, Array, Array]:
    """e^z and φ₁…φ₄(z) (φ_k(z) = Σ zʲ/(j + k)!) of complex *z*: the series where |z| is
    small, the recurrence φ_{k+1} = (φ_k − 1/k!)/z elsewhere."""
    z = np.asarray(z, dtype=np.complex128)
    small = np.abs(z) < _SERIES_BELOW
    zs = np.where(small, z, 0.0)
    series = []
    for k in range(1, 5):
        term = np.full(z.shape, 1.0 / math.factorial(k), dtype=np.complex128)
        total = term.copy()
        for j in range(1, _SERIES_TERMS):
            term = term * zs / (j + k)
            total += term
        series.append(total)
    exp = np.exp(z)
    zr = np.where(small, 1.0, z)
    out = [exp]
    previous = exp
    for k in range(1, 5):
        previous = (previous - 1.0 / math.factorial(k - 1)) / zr
        out.append(np.where(small, series[k - 1], previous))
    return exp, out[1], out[2], out[3], out[4]


def _scan(mult: Array, add: Array) -> tuple[Array, Array]:
    """The prefix compositions of the affine maps w ↦ mult·w + add along the last axis: after
    it, entry k maps the state before step 0 to the state after step k (Hillis–Steele: log₂ N
    passes over whole arrays)."""
    mult, add = mult.copy(), add.copy()
    n = mult.shape[-1]
    d = 1
    while d < n:
        new_add = mult[..., d:] * add[..., :-d] + add[..., d:]
        mult[..., d:] = mult[..., d:] * mult[..., :-d]
        add[..., d:] = new_add
        d *= 2
    return mult, add


def _modes(train: Train, omega: Array | float, theta: Array, force: Array,
           rate: Array) -> tuple[Array, Array, complex, Array, Array]:
    """The periodic response's complex mode w at the grid angles (see
    :func:`periodic_response`, whose arguments these are), with q (τ per radian of cam angle:
    a scalar, or (S, 1) for several speeds), λ and the forcing u = −F_r/K and du/dτ."""
    omega_arr = np.asarray(omega, dtype=np.float64)
    force = np.asarray(force, dtype=np.float64)
    rate = np.asarray(rate, dtype=np.float64)
    if omega_arr.ndim > 0:
        omega_arr = omega_arr[:, None]
    stiffness = train.total_stiffness
    q = train.natural / omega_arr  # τ per radian of cam angle
    zeta = train.total_zeta
    wd = math.sqrt(max(1.0 - zeta * zeta, 0.0))
    lam = complex(-zeta, wd)
    u = -force / stiffness
    du = -rate / (stiffness * q)  # du/dτ
    # the steps (rad) take a few lengths, one per segment (and 0 at a joint): the φ-functions
    # once per length, to 1e-15 rad
    lengths, which = np.unique(np.round(np.diff(theta), 15), return_inverse=True)
    steps = lengths * q  # in τ
    exp, p1, p2, p3, p4 = (f[..., which] for f in phi_functions(lam * steps))
    h = steps[..., which]
    g0 = h * (p1 - 6.0 * p3 + 12.0 * p4)
    g0d = h * h * (p2 - 4.0 * p3 + 6.0 * p4)
    g1 = h * (6.0 * p3 - 12.0 * p4)
    g1d = h * h * (-2.0 * p3 + 6.0 * p4)
    beta = 1.0 / complex(0.0, 2.0 * wd)
    add = beta * (g0 * u[..., :-1] + g0d * du[..., :-1] + g1 * u[..., 1:] + g1d * du[..., 1:])
    mult, add = _scan(exp, add)
    turn = mult[..., -1]  # e^{λ T}: the whole turn
    start = add[..., -1] / (1.0 - turn)
    w = np.concatenate((start[..., None], mult * start[..., None] + add), axis=-1)
    return w, q, lam, u, du


def periodic_response(train: Train, omega: Array | float, theta: Array, force: Array,
                      rate: Array) -> tuple[Array, Array]:
    """The periodic dynamic error e (m) and its rate de/dθ (m/rad) at the grid angles *theta*
    (rad, increasing over one turn from 0 to 2π, a joint twice) under the rigid force *force*
    (N) and its derivative *rate* (N/rad), at the cam speeds *omega* (rad/s): a scalar, or one
    per row of *force* and *rate* (S, N) for several speeds at once.

    Raises ``ZeroDivisionError`` at undamped resonance (the design rules refuse it first)."""
    w, q, lam, _, _ = _modes(train, omega, theta, force, rate)
    error = 2.0 * w.real
    error_rate = 2.0 * (lam * w).real * q  # de/dθ = (de/dτ)·q
    return error, error_rate


#: Where the least contact force may lie inside a step of the grid, the step is sampled this
#: far apart in τ = ω_n t (radians of the train's own vibration: a dozen samples and more a
#: period of its ringing), and each sample polished by :data:`NEWTON` steps of Newton's method
#: on the force's exact derivative.
SUB_STEP = 0.5
NEWTON = 6
#: At most this many samples a step, and this many at once (a stiff train's long steps on a
#: coarse grid take many).
MOST_SAMPLES = 4096
CHUNK = 1_000_000
#: A step's ringing is spent where its amplitude in force, 2|κ||C|, is within this share of the
#: forces at its ends (plus 1 N): the least is then the forcing's cubic's, found exactly.
RINGING_SPENT = 1e-12


def least_force(train: Train, omega: Array | float, theta: Array, force: Array, rate: Array,
                floor: float = math.inf,
                modes: tuple[Array, Array, complex, Array, Array] | None = None
                ) -> tuple[Array, Array]:
    """The least contact force (N) over the turn of the continuous periodic response — not of
    its grid values alone: the trough of the train's ringing may fall between them — and the
    cam angle (rad) where it lies, at the cam speeds *omega* (the arguments as for
    :func:`periodic_response`; (S,) results for S speeds, else scalars).

    Over a step of the grid the forcing is a cubic in τ, u = Σ aⱼτʲ, and the response exact:
    w = C e^{λτ} + p(τ), p the cubic with p′ = λp + βu (pⱼ = ((j + 1)p_{j+1} − βaⱼ)/λ, β =
    1/(2iω_d)), C = w₀ − p(0); the contact force is F = −2 Re[κ w], κ = k_f + c ω_n λ. A step
    can hold a force below its ends' by at most h²/8 · max|F″| (|F″| ≤ 2|κ|(|C| + |p″|), as
    |λ| = 1 and ζ ≥ 0); the steps whose bound falls below the grid's least are sampled every
    :data:`SUB_STEP` and polished by Newton's method on F′ = 0.

    With a finite *floor* (N) the answer is exact only as far as it decides the comparison
    with it: a speed whose grid already falls below *floor* is not refined, and elsewhere only
    the steps that might fall below *floor* are. *modes*: :func:`_modes` of these arguments,
    where already computed."""
    w, q, lam, u, du = modes or _modes(train, omega, theta, force, rate)
    batch = w.ndim > 1
    w, u, du = np.atleast_2d(w), np.atleast_2d(u), np.atleast_2d(du)
    q = np.broadcast_to(np.asarray(q, dtype=np.float64).reshape(-1, 1), (w.shape[0], 1))
    zeta = train.total_zeta
    wd = math.sqrt(max(1.0 - zeta * zeta, 0.0))
    beta = 1.0 / complex(0.0, 2.0 * wd)
    kappa = train.stiffness + train.damping * train.natural * lam
    grid = -2.0 * (kappa * w).real
    k_grid = np.argmin(grid, axis=1)
    rows = np.arange(w.shape[0])
    best = grid[rows, k_grid]
    where = np.broadcast_to(theta, grid.shape)[rows, k_grid].astype(np.float64)
    if math.isinf(floor):
        threshold = best
    else:
        threshold = np.where(best < floor, -math.inf, floor)
    # the steps' cubics in τ from the Hermite data at their ends
    h = np.diff(theta)[None, :] * q
    inside = h > 0.0
    hs = np.where(inside, h, 1.0)
    u0, u1, d0, d1 = u[:, :-1], u[:, 1:], du[:, :-1], du[:, 1:]
    a2 = (3.0 * (u1 - u0) / hs - 2.0 * d0 - d1) / hs
    a3 = (2.0 * (u0 - u1) / hs + d0 + d1) / (hs * hs)
    p3 = -beta * a3 / lam
    p2 = (3.0 * p3 - beta * a2) / lam
    p1 = (2.0 * p2 - beta * d0) / lam
    p0 = (p1 - beta * u0) / lam
    c = w[:, :-1] - p0
    curve = 2.0 * abs(kappa) * (np.abs(c) + np.maximum(np.abs(2.0 * p2),
                                                       np.abs(2.0 * p2 + 6.0 * p3 * h)))
    # the dip below the ends, or (a step many periods long) the cubic's least less the ringing
    with np.errstate(all="ignore"):
        dip = np.minimum(grid[:, :-1], grid[:, 1:]) - h * h / 8.0 * curve
        ring = _cubic_least([-2.0 * (kappa * coefficient).real for coefficient in
                             (p0, p1, p2, p3)], h) - 2.0 * abs(kappa) * np.abs(c)
    bound = np.where(np.isnan(ring), dip, np.maximum(dip, ring))
    pick = inside & (bound < threshold[:, None]) & np.isfinite(h)
    # a step whose ringing is spent (its force within RINGING_SPENT of the forcing's cubic, as
    # with a train far faster than the cam) has the cubic's least: no sampling
    spent = pick & (2.0 * abs(kappa) * np.abs(c)
                    <= RINGING_SPENT * (1.0 + np.abs(grid[:, :-1]) + np.abs(grid[:, 1:])))
    if spent.any():
        rows_s, steps_s = np.nonzero(spent)
        with np.errstate(all="ignore"):
            cubic, tau_s = _cubic_least_at([-2.0 * (kappa * coefficient[rows_s, steps_s]).real
                                            for coefficient in (p0, p1, p2, p3)],
                                           h[rows_s, steps_s])
        order = np.lexsort((cubic, rows_s))
        first = np.concatenate(([True], rows_s[order][1:] != rows_s[order][:-1]))
        rows_c, found_c = rows_s[order][first], cubic[order][first]
        at_c = (theta[steps_s] + tau_s / q[rows_s, 0])[order][first]
        better = found_c < best[rows_c]
        best[rows_c[better]] = found_c[better]
        where[rows_c[better]] = at_c[better]
        pick &= ~spent
    rows_all, steps_all = np.nonzero(pick)
    longest = float(np.max(h[pick], initial=0.0))
    count = min(max(1, math.ceil(longest / SUB_STEP)), MOST_SAMPLES)
    chunk = max(1, CHUNK // (count + 1))
    for first_row in range(0, rows_all.size, chunk):
        row = rows_all[first_row:first_row + chunk]
        step = steps_all[first_row:first_row + chunk]
        span = h[row, step]
        fraction = np.linspace(0.0, 1.0, count + 1)
        tau = span[:, None] * fraction[None, :]
        low = span[:, None] * np.concatenate(([0.0], fraction[:-1]))[None, :]
        high = span[:, None] * np.concatenate((fraction[1:], [1.0]))[None, :]
        kc = (kappa * c[row, step])[:, None]
        kp = [(kappa * coefficient[row, step])[:, None] for coefficient in (p0, p1, p2, p3)]
        for _ in range(NEWTON):
            e = np.exp(lam * tau)
            slope = -2.0 * (kc * lam * e + kp[1] + tau * (2.0 * kp[2] + 3.0 * tau * kp[3])).real
            bend = -2.0 * (kc * lam * lam * e + 2.0 * kp[2] + 6.0 * tau * kp[3]).real
            with np.errstate(divide="ignore", invalid="ignore"):
                move = np.where(bend > 0.0, slope / bend, 0.0)
            tau = np.clip(tau - move, low, high)
        value = -2.0 * (kc * np.exp(lam * tau)
                        + kp[0] + tau * (kp[1] + tau * (kp[2] + tau * kp[3]))).real
        j = np.argmin(value, axis=1)
        found = value[np.arange(row.size), j]
        at = theta[step] + tau[np.arange(row.size), j] / q[row, 0]
        order = np.lexsort((found, row))  # each speed's least first among its candidates
        first = np.concatenate(([True], row[order][1:] != row[order][:-1]))
        rows_c, found_c, at_c = row[order][first], found[order][first], at[order][first]
        better = found_c < best[rows_c]
        best[rows_c[better]] = found_c[better]
        where[rows_c[better]] = at_c[better]
    if not batch:
        return best[0], where[0]
    return best, where


def _cubic_least(r: list[Array], h: Array) -> Array:
    """The least of the real cubic Σ rⱼτʲ over [0, *h*] (at the ends or where its derivative
    3r₃τ² + 2r₂τ + r₁ vanishes inside), less a rounding's worth of its coefficients."""
    return _cubic_least_at(r, h)[0]


def _cubic_least_at(r: list[Array], h: Array) -> tuple[Array, Array]:
    """:func:`_cubic_least` and the τ in [0, *h*] where the cubic takes its least."""
    r0, r1, r2, r3 = r

    def value(t: Array) -> Array:
        return r0 + t * (r1 + t * (r2 + t * r3))

    at = np.where(value(h) < value(np.zeros_like(h)), h, 0.0)
    least = value(at)
    disc = np.sqrt(np.maximum(r2 * r2 - 3.0 * r3 * r1, 0.0))
    big = -(r2 + np.where(r2 >= 0.0, disc, -disc))  # the root's larger part, without cancelling
    for root in (big / (3.0 * r3), r1 / big):
        inside = np.isfinite(root) & (root > 0.0) & (root < h)
        there = value(np.where(inside, root, 0.0))
        lower = inside & (there < least)
        least = np.where(lower, there, least)
        at = np.where(lower, root, at)
    scale = np.abs(r0) + h * (np.abs(r1) + h * (np.abs(r2) + h * np.abs(r3)))
    return least - 1e-12 * scale, at


def contact_force(train: Train, omega: Array | float, error: Array,
                  error_rate: Array) -> Array:
    """F_c = −k_f e − c e˙ (N) of the dynamic error *error* (m) and its rate (m/rad) at the cam
    speed(s) *omega* (rad/s)."""
    omega_arr = np.asarray(omega, dtype=np.float64)
    if omega_arr.ndim > 0:
        omega_arr = omega_arr[:, None]
    return -train.stiffness * error - train.damping * omega_arr * error_rate


def periodic_error(train: Train, omega: Array | float, theta: Array, force: Array,
                   rate: Array) -> Array:
    """The periodic dynamic error e (m) alone on the grid *theta* (rad), at the cam speed
    *omega* (rad/s) or at several ((S,), with *force* and *rate* of :func:`rigid_force` (S, N)):
    what :func:`respond` gives, without the contact force and its least."""
    return 2.0 * _modes(train, omega, theta, force, rate)[0].real


def respond(train: Train, omega: float, theta: Array, motion: Array) -> Response:
    """The periodic response at the cam speed *omega* (rad/s) to the *motion* (s … s‴ in m
    and per radian, (4, N)) on the grid *theta* (rad), with its least contact force between
    the grid's points too (:func:`least_force`)."""
    force, rate = rigid_force(train, omega, motion)
    modes = _modes(train, omega, theta, force, rate)
    w, q, lam = modes[:3]
    error, error_rate = 2.0 * w.real, 2.0 * (lam * w).real * q
    with np.errstate(all="ignore"):
        least, least_at = least_force(train, omega, theta, force, rate, modes=modes)
    return Response(theta, error, error_rate, contact_force(train, omega, error, error_rate),
                    float(least), float(least_at))
