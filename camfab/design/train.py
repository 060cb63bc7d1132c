"""The follower train's lumped model, built from the design: the mass on the train's spring and
damper and the return spring's rate, damping and constant load, at the follower's trace point
(THEORY §J). The at-speed model (:mod:`camfab.speed`) drives it; the design layer builds it.

Units: SI (kg, N/m, N·s/m, N, m/s²); the design's spring rate (N/mm) and the follower's
stiffness (N/mm) are converted here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.design.model import Design
    from camfab.motion.polydyne import TrainTerms

#: Standard gravity (m/s²).
G = 9.80665


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


def spring_load(design: Design) -> float:
    """The constant load on a spring-held follower (N): the spring's preload, the external load
    and, with ``gravity``, the follower's weight."""
    spring, mass = design.spring, design.follower.mass or 0.0
    assert spring is not None
    rate = spring.rate * 1000.0
    preload = spring.preload if spring.preload is not None else rate * (
        (spring.initial_compression or 0.0) / 1000.0)
    return preload + spring.external_load + (mass * G if spring.gravity else 0.0)


def train_of(design: Design, held_by_spring: bool) -> Train | None:
    """The design's follower train at its trace point (SI), or None without a stiffness; a
    positive-drive cam's has no spring (*held_by_spring* False)."""
    fol, spring = design.follower, design.spring
    if fol.stiffness is None or fol.mass is None:
        return None
    if not held_by_spring or spring is None:
        return Train(fol.mass, fol.stiffness * 1000.0, 0.0, fol.train_damping_ratio)
    return Train(fol.mass, fol.stiffness * 1000.0, spring.rate * 1000.0,
                 fol.train_damping_ratio, spring.damping, spring_load(design))


def rigid_train(design: Design, held_by_spring: bool) -> Train:
    """The rigid model's follower at its trace point, SI: its mass, and with *held_by_spring*
    the spring's rate, damping and constant load (preload, external load, weight), for the
    force F = m ω² s″ + c ω s′ + k s + P along its motion
    (:func:`camfab.speed.elastic.rigid_force`)."""
    fol, spring = design.follower, design.spring
    assert fol.mass is not None
    if not held_by_spring or spring is None:
        return Train(fol.mass, 0.0, 0.0, 0.0)
    return Train(fol.mass, 0.0, spring.rate * 1000.0, 0.0, spring.damping,
                 spring_load(design))


def polydyne_terms(design: Design) -> TrainTerms:
    """The terms of a polydyne cam's equation (:mod:`camfab.motion.polydyne`) for the design's
    train at its speed: held by its spring where it has one, as the model at speed holds it."""
    from camfab.motion.polydyne import TrainTerms

    train, omega = train_of(design, design.spring is not None), design.cam.omega
    assert train is not None and omega is not None, "the rules require a train and a speed"
    return TrainTerms.of(train.mass, train.stiffness, train.spring, train.damping,
                         train.spring_damping, omega)
