"""Dynamics of a force-closed cam (THEORY §E): contact force, jump, preload and camshaft torque.

The follower (mass m) is held on the cam by a spring of rate k, preloaded kδ₀ at zero lift,
with optional viscous damping c, an external load toward the cam and its weight (``gravity``,
the follower above the cam). Along the follower's motion, compression positive:

    F(θ) = m ω² s″ + c ω s′ + k(δ₀ + s) + F_ext (+ m g)

Contact needs F ≥ 0 everywhere. The follower jumps off the cam (undamped) above
ω_j² = min over s″ < 0 of (k(δ₀ + s) + F_ext (+ m g)) / (−m s″); the preload needed at the design
speed is max[−m ω² s″ − c ω s′ − k s − F_ext (− m g)], and the camshaft torque without friction
is T = F s′. The spring force that keeps the follower on the cam at the design speed must reach
max[−m ω² s″ − c ω s′ − F_ext (− m g)] where that is largest: a follower mass and a speed alone
give this (the textbooks' "minimum spring force"), before any spring is chosen. An oscillating
follower's mass and spring are taken at its trace point, along its arc (s = arm length × swing).
SI units throughout: N, m, rad/s, N·m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.analysis.findings import Finding
from camfab.arrays import Array
from camfab.design import Design
from camfab.motion.program import MotionProgram

#: Standard gravity (m/s²).
G = 9.80665

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
    del segment
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
    # jump: the speed at which inertia first overcomes the holding force, where s″ < 0
    falling = dds < 0.0
    jump = jump_at = None
    if falling.any():
        ratio = static[falling] / (-mass * dds[falling])
        index = int(np.argmin(ratio))
        jump = math.sqrt(max(float(ratio[index]), 0.0))
        jump_at = math.degrees(float(theta[falling][index]))
    force = torque = None
    required = min_force = min_at = max_force = max_torque = None
    if pull is not None:
        force = preload + k * s - pull  # = m ω² s″ + c ω s′ + static
        torque = force * ds
        worst = int(np.argmin(force))
        min_force, min_at = float(force[worst]), math.degrees(float(theta[worst]))
        max_force = float(force.max())
        max_torque = float(np.max(np.abs(torque)))
        required = max(0.0, float(np.max(preload - force)))
    return Dynamics(theta, force, torque, static, jump, jump_at, required, preload, min_force,
                    min_at, max_force, max_torque, needed, needed_at)


def jump_finding(design: Design, dyn: Dynamics) -> Finding:
    """Contact lost at the design speed is an error (the follower leaves the cam and hammers
    back); without a speed, the jump speed alone is reported."""
    speed = design.cam.speed_rpm
    limit = dyn.jump_speed_rpm
    jump = (f"the follower jumps above {limit:.5g} rpm ({dyn.jump_speed_rad_s:.5g} rad/s, first "
            f"at {dyn.jump_at_deg:.4g}°)" if limit is not None else
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
