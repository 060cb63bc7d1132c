"""An independent reference for the speed at which a spring-held follower first leaves its cam:
the elastic follower train (THEORY §J) and the rigid one (THEORY §E), written here from those
sections and not from camfab's code.

The elastic train, SI at the trace point: m x″ = k_f (s − x) + c (s′ − x′) − k_s x − c_s x′ − P,
c = 2ζ√(m(k_f + k_s)), contact force F_c = k_f (s − x) + c (s′ − x′), ′ time derivatives. Its
periodic state: the response from rest over one turn, integrated by scipy's ``solve_ivp``
(DOP853, segment by segment, so that no step crosses a law's joint, at a relative tolerance of
1e-10), plus the free motion e^{At} y₀ (from the eigenvectors of A) from the start y₀ that
closes the turn. The least contact force over the turn is the least of the integration's dense
output, sampled 40 times a natural period and then refined by ``minimize_scalar`` at its lowest
troughs; the speed at which it first falls below zero is found by bisection.

The rigid model: F = m ω² s″ + c_s ω s′ + k_s s + P (the same loads), least over the turn by
``minimize_scalar`` from a fine sampling of each segment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

G = 9.80665


@dataclass(frozen=True)
class Follower:
    """A design's follower as this reference reads it (SI, at the trace point)."""

    program: Any
    m: float
    kf: float
    ks: float
    c: float
    cs: float
    load: float
    scale: float

    @classmethod
    def of(cls, design: Any) -> Follower:
        fol, spring = design.follower, design.spring
        kf = (fol.stiffness or 0.0) * 1000.0
        ks = spring.rate * 1000.0
        zeta = fol.damping_ratio if fol.damping_ratio is not None else 0.05
        c = 2 * zeta * math.sqrt(fol.mass * (kf + ks)) if kf else 0.0
        preload = (spring.preload if spring.preload is not None
                   else ks * (spring.initial_compression or 0.0) / 1000.0)
        load = preload + spring.external_load + (fol.mass * G if spring.gravity else 0.0)
        scale = fol.arm_length / 1000.0 if fol.oscillating else 1e-3
        return cls(design.program, fol.mass, kf, ks, c, spring.damping, load, scale)

    def lift(self, segment: Any, theta: np.ndarray, omega: float) -> np.ndarray:
        """s, ṡ, s̈ (m, m/s, m/s²) at the cam angles *theta* (rad) of the *segment* (one of
        the program's: its own values up to its ends) at *omega* (rad/s)."""
        motion = segment.evaluate_local(np.atleast_1d(theta) - segment.start)
        return np.array([motion[0], motion[1] * omega, motion[2] * omega**2]) * self.scale

    # ---- the elastic train ----

    def least_elastic(self, rpm: float) -> float:
        """The least contact force (N) over the turn of the periodic state at *rpm*."""
        omega = rpm * math.pi / 30.0
        m, kf, ks, c, cs = self.m, self.kf, self.ks, self.c, self.cs
        a = np.array([[0.0, 1.0], [-(kf + ks) / m, -(c + cs) / m]])
        roots, vectors = np.linalg.eig(a)
        inverse = np.linalg.inv(vectors)

        def free(t: np.ndarray, y0: np.ndarray) -> np.ndarray:
            """e^{At} y₀ at the times *t*, (2, T)."""
            modes = np.exp(np.outer(roots, t)) * (inverse @ y0)[:, None]
            return (vectors @ modes).real

        y = np.zeros(2)
        pieces = []
        for segment in self.program.segments:
            def rhs(t: float, y: np.ndarray, segment: Any = segment) -> np.ndarray:
                s, ds, _ = self.lift(segment, np.array([omega * t]), omega)[:, 0]
                return a @ y + np.array([0.0, (kf * s + c * ds - self.load) / m])

            lo, hi = segment.start / omega, (segment.start + segment.span) / omega
            sol = solve_ivp(rhs, (lo, hi), y, method="DOP853", rtol=1e-10, atol=1e-15,
                            dense_output=True)
            pieces.append((segment, lo, hi, sol.sol))
            y = sol.y[:, -1]
        period = 2 * math.pi / omega
        turn = np.column_stack([free(np.array([period]), e)[:, 0] for e in np.eye(2)])
        start = np.linalg.solve(np.eye(2) - turn, y)

        def force(t: np.ndarray, segment: Any, piece: Any) -> np.ndarray:
            t = np.atleast_1d(t)
            state = piece(t) + free(t, start)
            s, ds, _ = self.lift(segment, omega * t, omega)
            return kf * (s - state[0]) + c * (ds - state[1])

        natural = math.sqrt((kf + ks) / m)
        best = math.inf
        for segment, lo, hi, piece in pieces:
            count = max(200, math.ceil(40 * (hi - lo) * natural / (2 * math.pi)))
            t = np.linspace(lo, hi, count + 1)
            f = force(t, segment, piece)
            best = min(best, float(f.min()))
            # the troughs of the samples, an end of the segment among them
            troughs = [i for i in range(count + 1) if (i == 0 or f[i] <= f[i - 1])
                       and (i == count or f[i] <= f[i + 1])]
            for i in sorted(troughs, key=lambda i: f[i])[:4]:
                found = minimize_scalar(
                    lambda x, segment=segment, piece=piece: float(force(x, segment, piece)[0]),
                    bounds=(t[max(i - 1, 0)], t[min(i + 1, count)]), method="bounded",
                    options={"xatol": 1e-13 * period})
                best = min(best, float(found.fun))
        return best

    # ---- the rigid model ----

    def least_rigid(self, rpm: float) -> float:
        """The least rigid contact force (N) over the turn at *rpm*."""
        omega = rpm * math.pi / 30.0

        def force(theta: np.ndarray, segment: Any) -> np.ndarray:
            s, ds, dds = self.lift(segment, theta, omega)
            return self.m * dds + self.cs * ds + self.ks * s + self.load

        best = math.inf
        for segment in self.program.segments:
            theta = np.linspace(segment.start, segment.start + segment.span, 2001)
            f = force(theta, segment)
            best = min(best, float(f.min()))
            i = int(np.argmin(f))
            if 0 < i < theta.size - 1:
                found = minimize_scalar(
                    lambda x, segment=segment: float(force(np.array([x]), segment)[0]),
                    bounds=(theta[i - 1], theta[i + 1]), method="bounded",
                    options={"xatol": 1e-14})
                best = min(best, float(found.fun))
        return best


def bisect(least: Any, low: float, high: float, rel: float = 1e-7) -> float:
    """The speed (rpm) in [*low*, *high*] at which *least* (the least force at a speed) first
    falls below zero, by bisection from a bracket where it holds at *low* and not at *high*
    (which the caller has checked)."""
    while high - low > rel * high:
        middle = 0.5 * (low + high)
        if least(middle) >= 0.0:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)
