"""Dynamics of a force-closed cam (THEORY §E): contact force, jump, preload and camshaft torque.

The follower (mass m) is held on the cam by a spring of rate k, preloaded kδ₀ at zero lift,
with optional viscous damping c, an external load toward the cam and its weight (``gravity``,
the follower above the cam). Along the follower's motion, compression positive:

    F(θ) = m ω² s″ + c ω s′ + k(δ₀ + s) + F_ext (+ m g)

Contact needs F ≥ 0 everywhere. The follower jumps off the cam above the least speed at which
that same F first reaches zero somewhere (the least positive root in ω, over the cam; undamped,
ω_j² = min over s″ < 0 of (k(δ₀ + s) + F_ext (+ m g)) / (−m s″)); the preload needed at the design
speed is max[−m ω² s″ − c ω s′ − k s − F_ext (− m g)], and the camshaft torque without friction
is T = F s′. The spring force that keeps the follower on the cam at the design speed must reach
max[−m ω² s″ − c ω s′ − F_ext (− m g)] where that is largest: a follower mass and a speed alone
give this (the textbooks' "minimum spring force"), before any spring is chosen. An oscillating
follower's mass and spring are taken at its trace point, along its arc (s = arm length × swing).
SI units throughout: N, m, rad/s, N·m.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camfab.analysis.findings import Finding
from camfab.arrays import Array
from camfab.design import Design
from camfab.design.train import G
from camfab.motion.program import MotionProgram

#: Cam-angle step of the dense evaluation (as for the geometry).
STEP = math.radians(0.05)


@dataclass(frozen=True)
class Dynamics:
    """Contact force and torque over the cycle, and the numbers derived from them.

    ``theta`` (rad) with ``force_N`` and ``torque_N_m`` at the design speed (None without a
    speed or a spring); ``static_N`` is the spring's and the loads' part alone (F at ω = 0).
    ``required_spring_force_N`` is the largest spring force the follower needs to stay on the
    cam at the design speed, at ``required_spring_force_at_deg``.
    """

    theta: Array
    force_N: Array | None
    torque_N_m: Array | None
    static_N: Array
    jump_speed_rad_s: float | None
    jump_at_deg: float | None
    required_preload_N: float | None
    preload_N: float
    min_force_N: float | None
    min_force_at_deg: float | None
    max_force_N: float | None
    max_torque_N_m: float | None
    required_spring_force_N: float | None = None
    required_spring_force_at_deg: float | None = None

    @property
    def jump_speed_rpm(self) -> float | None:
        return None if self.jump_speed_rad_s is None else self.jump_speed_rad_s * 30 / math.pi


def trace_scale(design: Design) -> float:
    """Metres of the follower's motion per unit of the program's lift (mm, or rad of swing)."""
    fol = design.follower
    if fol.oscillating:
        return (fol.arm_length or 0.0) / 1000.0
    return 1.0 / 1000.0


def dynamics(design: Design, program: MotionProgram) -> Dynamics | None:
    """The dynamics of *design*, or None without a follower mass (or without both a spring and
    a speed)."""
    spring, mass, omega = design.spring, design.follower.mass, design.cam.omega
    if mass is None or (spring is None and omega is None):
        return None
    segment, theta, m = program.segment_grid(STEP)
    scale = trace_scale(design)
    s, ds, dds = m[0] * scale, m[1] * scale, m[2] * scale  # m, m/rad, m/rad²
    damping, load = (0.0, 0.0) if spring is None else (spring.damping, spring.external_load)
    weight = mass * G if spring is not None and spring.gravity else 0.0
    # what pulls the follower off the cam at the design speed: inertia, damping and loads
    pull = None if omega is None else -(mass * omega**2 * dds + damping * omega * ds + load
                                         + weight)
    needed = needed_at = None
    if pull is not None:
        worst = int(np.argmax(pull))
        needed, needed_at = max(0.0, float(pull[worst])), math.degrees(float(theta[worst]))
    if spring is None:
        return Dynamics(theta, None, None, np.zeros_like(theta), None, None, None, 0.0, None,
                        None, None, None, needed, needed_at)
    k = spring.rate * 1000.0  # N/m
    preload = spring.preload if spring.preload is not None else k * (
        (spring.initial_compression or 0.0) / 1000.0)
    static = preload + k * s + load + weight

    def motion_at(index: Array, t: Array) -> Array:
        return program.evaluate_local(index, t) * scale

    # jump: the least speed at which the force, inertia and damping with the holding force,
    # first reaches zero somewhere on the cam
    roots = _loss_speed(mass, damping, static, ds, dds)
    jump = jump_at = None
    if np.isfinite(roots).any():
        def roots_at(i: Array, t: Array) -> Array:
            lift, rate, accel = motion_at(i, t)[:3]
            return _loss_speed(mass, damping, preload + k * lift + load + weight, rate, accel)

        least, where = _least_along(program, segment, theta, roots, roots_at)
        jump, jump_at = max(least, 0.0), math.degrees(where)
    force = torque = None
    required = min_force = min_at = max_force = max_torque = None
    if pull is not None:
        force = preload + k * s - pull  # = m ω² s″ + c ω s′ + static
        torque = force * ds

        def force_at(i: Array, t: Array) -> Array:
            lift, rate, accel = motion_at(i, t)[:3]
            return (mass * omega**2 * accel + damping * omega * rate + preload + k * lift
                    + load + weight)

        min_force, where = _least_along(program, segment, theta, force, force_at)
        min_at = math.degrees(where)
        max_force = float(force.max())
        max_torque = float(np.max(np.abs(torque)))
        required = max(0.0, float(np.max(preload - force)))
    return Dynamics(theta, force, torque, static, jump, jump_at, required, preload, min_force,
                    min_at, max_force, max_torque, needed, needed_at)


def _loss_speed(mass: float, damping: float, static: Array, ds: Array, dds: Array) -> Array:
    """The least speed (rad/s) at which the force m ω² s″ + c ω s′ + P (P the *static* part:
    the spring and the loads, N) falls below zero at each point of the cam (s′, s″ in m per
    radian, and per radian²), inf where it never does: the least positive root of that
    quadratic in ω, 0 where P < 0 already."""
    a, b, c = mass * dds, damping * ds, static
    disc = b * b - 4.0 * a * c
    root = np.sqrt(np.maximum(disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        # b < 0: 2P/(√D − b), the smaller positive root (a > 0 needs D > 0); b ≥ 0: one
        # positive root only where a < 0, (b + √D)/(2|a|)
        falling = np.where(((a <= 0.0) & (disc >= 0.0)) | (disc > 0.0), 2.0 * c / (root - b),
                           np.inf)
        rising = np.where(a < 0.0, (b + root) / (-2.0 * a), np.inf)
        speed = np.where(b < 0.0, falling, rising)
    return np.where(c < 0.0, 0.0, np.where(np.isnan(speed), np.inf, speed))


#: Rounds of the search for a least between grid points, each sampling the bracket at this many
#: points and keeping the best one's neighbours (16 times narrower a round).
ZOOM_ROUNDS = 4
ZOOM_SAMPLES = 33


def _least_along(program: MotionProgram, segment: Array, theta: Array, values: Array,
                 value_at: Callable[[Array, Array], Array]) -> tuple[float, float]:
    """The least of a smooth function over the turn and its cam angle (rad): its *values* on
    the grid (*segment*, *theta*), refined between the grid's points next to their least, in
    that segment, by :data:`ZOOM_ROUNDS` rounds of sampling (*value_at* of the segments'
    indices and the angles into them, rad)."""
    k = int(np.argmin(values))
    best, at = float(values[k]), float(theta[k])
    seg = int(segment[k])
    lo = k - 1 if k > 0 and segment[k - 1] == seg else k
    hi = k + 1 if k + 1 < theta.size and segment[k + 1] == seg else k
    start = float(program.table.start[seg])
    a, b = float(theta[lo]) - start, float(theta[hi]) - start
    index = np.full(ZOOM_SAMPLES, seg)
    for _ in range(ZOOM_ROUNDS):
        t = np.linspace(a, b, ZOOM_SAMPLES)
        found = value_at(index, t)
        j = int(np.argmin(found))
        if found[j] < best:
            best, at = float(found[j]), start + float(t[j])
        a, b = float(t[max(j - 1, 0)]), float(t[min(j + 1, ZOOM_SAMPLES - 1)])
    return best, at


def safe_rpm(speed: float) -> str:
    """A speed the follower must stay below (rpm), to five figures rounded down: never above
    the speed it stands for."""
    if not speed > 0.0 or math.isinf(speed):
        return f"{speed:.5g}"
    scale = 10.0 ** (4 - math.floor(math.log10(speed)))
    return f"{math.floor(speed * scale) / scale:.5g}"


def jump_finding(design: Design, dyn: Dynamics) -> Finding:
    """Contact lost at the design speed is an error (the follower leaves the cam and hammers
    back); without a speed, the jump speed alone is reported."""
    speed = design.cam.speed_rpm
    limit = dyn.jump_speed_rpm
    jump = (f"the follower jumps above {safe_rpm(limit)} rpm ({dyn.jump_speed_rad_s:.5g} "
            f"rad/s, first at {dyn.jump_at_deg:.4g}°)" if limit is not None else
            "the follower never decelerates away from the cam: it cannot jump")
    if dyn.min_force_N is None or speed is None:
        return Finding("jump", True, "error", f"{jump}; no speed given to check against",
                       None, limit, "rpm")
    at = f"{dyn.min_force_at_deg:.4g}°"
    if dyn.min_force_N >= 0.0:
        return Finding("jump", True, "error",
                       f"the contact force stays positive at {speed:.5g} rpm (smallest "
                       f"{dyn.min_force_N:.4g} N at {at}); {jump}", speed, limit, "rpm")
    return Finding(
        "jump", False, "error",
        f"the follower loses contact at {speed:.5g} rpm: the contact force falls to "
        f"{dyn.min_force_N:.4g} N at {at}; {jump}; a preload of at least "
        f"{dyn.required_preload_N:.4g} N (now {dyn.preload_N:.4g} N), a stiffer spring or a "
        f"lower speed keeps it on the cam", speed, limit, "rpm", _negative_ranges(dyn))


def _negative_ranges(dyn: Dynamics) -> tuple[tuple[float, float], ...]:
    from camfab.angles import ranges_deg

    assert dyn.force_N is not None
    return ranges_deg(dyn.theta, dyn.force_N < 0.0)
