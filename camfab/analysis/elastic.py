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

import numpy as np

from camfab.arrays import Array

#: Below this |λH| the φ-functions are summed as their Taylor series (to its last term that
#: counts); above it, by their recurrence from e^{λH}, which is then well conditioned.
_SERIES_BELOW = 1.0
_SERIES_TERMS = 22


@dataclass(frozen=True)
class Train:
    """The follower train's lumped model, SI: the mass (kg), the train's stiffness k_f and the
    return spring's k_s (N/m), the train's damping ratio ζ (of its own damper, c = 2ζ√(mK)),
    the spring's damping c_s (N·s/m) and the constant load P on the mass (N: preload, external
    load and weight)."""

    mass: float
    stiffness: float
    spring: float
    zeta: float
    spring_damping: float = 0.0
    load: float = 0.0

    @property
    def total_stiffness(self) -> float:
        return self.stiffness + self.spring

    @property
    def natural(self) -> float:
        """ω_n = √((k_f + k_s)/m) (rad/s)."""
        return math.sqrt(self.total_stiffness / self.mass)

    @property
    def damping(self) -> float:
        """The train's damper c = 2ζ√(m(k_f + k_s)) (N·s/m)."""
        return 2.0 * self.zeta * math.sqrt(self.mass * self.total_stiffness)

    @property
    def total_zeta(self) -> float:
        """ζ_t = (c + c_s)/(2√(mK)): the train's damping and the spring's together."""
        return self.zeta + self.spring_damping / (2.0 * math.sqrt(self.mass
                                                                  * self.total_stiffness))


@dataclass(frozen=True)
class Response:
    """The periodic steady state on the grid: the dynamic error e = x − s (m), its rate de/dθ
    (m/rad) and the contact force F_c (N) at each grid angle (rad)."""

    theta: Array
    error: Array
    error_rate: Array
    force: Array


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


def periodic_response(train: Train, omega: Array | float, theta: Array, force: Array,
                      rate: Array) -> tuple[Array, Array]:
    """The periodic dynamic error e (m) and its rate de/dθ (m/rad) at the grid angles *theta*
    (rad, increasing over one turn from 0 to 2π, a joint twice) under the rigid force *force*
    (N) and its derivative *rate* (N/rad), at the cam speeds *omega* (rad/s): a scalar, or one
    per row of *force* and *rate* (S, N) for several speeds at once.

    Raises ``ZeroDivisionError`` at undamped resonance (the design rules refuse it first)."""
    omega_arr = np.asarray(omega, dtype=np.float64)
    force = np.asarray(force, dtype=np.float64)
    rate = np.asarray(rate, dtype=np.float64)
    batch = omega_arr.ndim > 0
    if batch:
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
    error = 2.0 * w.real
    error_rate = 2.0 * (lam * w).real * q  # de/dθ = (de/dτ)·q
    return error, error_rate


def contact_force(train: Train, omega: Array | float, error: Array,
                  error_rate: Array) -> Array:
    """F_c = −k_f e − c e˙ (N) of the dynamic error *error* (m) and its rate (m/rad) at the cam
    speed(s) *omega* (rad/s)."""
    omega_arr = np.asarray(omega, dtype=np.float64)
    if omega_arr.ndim > 0:
        omega_arr = omega_arr[:, None]
    return -train.stiffness * error - train.damping * omega_arr * error_rate


def respond(train: Train, omega: float, theta: Array, motion: Array) -> Response:
    """The periodic response at the cam speed *omega* (rad/s) to the *motion* (s … s‴ in m
    and per radian, (4, N)) on the grid *theta* (rad)."""
    force, rate = rigid_force(train, omega, motion)
    error, error_rate = periodic_response(train, omega, theta, force, rate)
    return Response(theta, error, error_rate, contact_force(train, omega, error, error_rate))
