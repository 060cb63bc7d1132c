"""Will the cam survive at speed: the elastic follower train, the Hertz contact stress around the
cycle and the roller bearing's life, with their checks (THEORY §I, §J, §K).

The force along the follower's motion comes from the rigid model (:mod:`camfab.analysis.dynamics`:
the spring, the inertia, the loads), or from the elastic train where the design gives the
follower's ``stiffness`` (:mod:`camfab.speed.vibration`); a cam that drives its follower both
ways (a groove, a conjugate pair, a globoid, a drum without a spring) supplies the inertia
force alone, m·ω²·s″, on whichever side carries it. The kind says where its follower touches it
(:meth:`~camfab.analysis.record.CamResult.contact`); the normal force there gives the stress
(:mod:`camfab.speed.contact`) and, for a roller, its bearing's life.

Forces in N, stresses in MPa, lengths in mm, lives in hours.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.cam_checks import fmt, where
from camfab.analysis.dynamics import STEP, safe_rpm, trace_scale
from camfab.analysis.findings import Finding
from camfab.angles import ranges_deg
from camfab.arrays import Array
from camfab.design import Design
from camfab.design.train import rigid_train, train_of
from camfab.speed.contact import (
    Contact,
    ContactStress,
    RollerLife,
    contact_stress,
    roller_life,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.speed.vibration import SpeedBand, Vibration


@dataclass(frozen=True)
class AtSpeed:
    """The cam at its speed.

    Attributes
    ----------
    contact
        How the follower touches the cam (None: not modelled for the kind).
    theta
        The analysis grid (rad) of the forces and the stress.
    force_N
        The force along the follower's motion the contact bears (N; the elastic train's where
        it has a stiffness, else the rigid model's), or None with no force to compute.
    held_by_spring
        True for a spring-held follower, False for a cam that drives it both ways.
    vibration
        The elastic follower train (None without a stiffness).
    stress, life
        The contact stress and the roller bearing's life (None where not computed).
    force_note, stress_note, life_note
        Why a number is missing, where it is.
    band
        A polydyne cam's vibration against speed beside its motion list cut directly (None for
        other cams, and without the elastic train's state).
    """

    contact: Contact | None
    theta: Array
    force_N: Array | None
    held_by_spring: bool
    vibration: Vibration | None
    stress: ContactStress | None
    life: RollerLife | None
    force_note: str | None = None
    stress_note: str | None = None
    life_note: str | None = None
    band: SpeedBand | None = None


def force_note(design: Design, held_by_spring: bool, two_sided: bool) -> str | None:
    """Why the force along the follower's motion cannot be computed, or None when it can: it
    needs the follower's mass and the cam's speed, and a spring or a cam that drives the
    follower both ways (*two_sided*)."""
    if design.follower.mass is None:
        return "no follower mass: give follower.mass (kg) for the forces"
    if design.cam.omega is None:
        return "no speed: give cam.speed_rpm for the forces"
    if not held_by_spring and not two_sided:
        return ("no spring holds the follower on the cam, so the force on it is not known: give "
                "the spring section")
    return None


def drive_force(design: Design, theta: Array, motion: Array, held_by_spring: bool) -> Array:
    """The force along the follower's motion (N) on the grid *theta* (rad, one turn increasing
    from 0 to 2π, a joint twice) of the *motion* (s … s‴ per radian, (4, N)): the elastic
    train's contact force where the design gives a stiffness, else the rigid model's (the
    design has a force: :func:`force_note`)."""
    from camfab.speed.elastic import respond, rigid_force

    omega = design.cam.omega
    assert omega is not None
    scaled = motion * trace_scale(design)
    train = train_of(design, held_by_spring)
    if train is not None:
        return respond(train, omega, theta, scaled).force
    return rigid_force(rigid_train(design, held_by_spring), omega, scaled)[0]


def at_speed(analysis: Analysis) -> Analysis:
    """*analysis* with the cam at its speed (:class:`AtSpeed`) and the checks of it:
    ``dynamic_jump`` (an elastic, spring-held follower leaving the cam), ``contact_stress``
    (against ``limits.contact_stress``) and ``roller_life`` (against ``limits.roller_life``)."""
    from camfab.speed.vibration import resonance_note, vibration

    design = analysis.design
    held_by_spring = design.spring is not None
    _, theta, motion = analysis.program.segment_grid(STEP)
    missing = force_note(design, held_by_spring, design.cam.spec.two_sided)
    resonant = None
    if missing is None:
        train = train_of(design, held_by_spring)
        resonant = missing = None if train is None else resonance_note(design, train)
    force = shaken = contact = None
    if missing is None:
        contact = analysis.result.contact(analysis)
        shaken = vibration(design, analysis.program, held_by_spring, design.cam.spec.two_sided,
                           STEP)
        force = (shaken.force_N if shaken is not None
                 else drive_force(design, theta, motion, held_by_spring))
    stress = life = None
    stress_note = life_note = missing
    if force is not None and contact is None:
        stress_note = life_note = "the contact of this kind of cam is not modelled"
    elif force is not None and contact is not None:
        stress = contact_stress(design, contact, force)
        stress_note = contact.note
        if design.follower.type == "roller":
            life = roller_life(design, contact, force)
    if design.follower.type != "roller":
        life_note = f"only a roller has a bearing life (this follower is a {design.follower.type})"
    elif design.follower.roller_load_rating is None:
        life_note = ("no load rating: give follower.roller_load_rating (the bearing's basic "
                     "dynamic load rating C) for its life")
    band = None
    if shaken is not None and design.motion_target == "output":
        from camfab.speed.vibration import speed_band

        assert design.cam.speed_rpm is not None
        band = speed_band(shaken.train, analysis.program, design.output_program,
                          design.cam.speed_rpm, trace_scale(design), STEP)
    record = AtSpeed(contact, theta, force, held_by_spring, shaken, stress, life, missing,
                     None if stress is not None else stress_note,
                     None if life is not None else life_note, band)
    lift = float(np.ptp(motion[0]))
    findings = [*analysis.findings, *_findings(analysis, record, resonant, lift)]
    return replace(analysis, at_speed=record, findings=findings)


def _findings(analysis: Analysis, record: AtSpeed, resonant: str | None,
              lift: float) -> list[Finding]:
    out = []
    shaken = record.vibration
    if resonant is not None:
        out.append(Finding("train_vibration", False, "error", resonant))
    if shaken is not None:
        out.append(train_vibration_finding(shaken, lift))
    if shaken is not None and shaken.one_sided:
        out.append(dynamic_jump_finding(analysis.design.cam.speed_rpm or 0.0, shaken))
    limits = analysis.design.limits
    if limits.contact_stress is not None:
        out.append(stress_finding(record, limits.contact_stress))
    if limits.roller_life is not None:
        out.append(life_finding(analysis, record, limits.roller_life))
    return out


def train_vibration_finding(shaken: Vibration, lift: float) -> Finding:
    """The elastic train's vibration about its compression against the follower's whole
    *lift* (mm, or rad of an arm's swing; taken at the trace point): a train that rings more
    than the cam moves it is nowhere near rigid (a resonance with little damping), an error
    whatever else holds."""
    lift = lift * shaken.trace_m * 1000.0
    ringing = shaken.max_ringing_m * 1000.0
    train = (f"natural frequency {shaken.natural_Hz:.4g} Hz, {shaken.frequency_ratio:.4g} times "
             f"the cam's, damping ratio {shaken.train.total_zeta:.3g}")
    if ringing <= lift:
        return Finding("train_vibration", True, "error",
                       f"the follower train vibrates at most {fmt(ringing)} mm about its "
                       f"compression, within the follower's lift of {fmt(lift)} mm ({train})",
                       ringing, lift, "mm")
    return Finding("train_vibration", False, "error",
                   f"the follower train vibrates up to {fmt(ringing)} mm about its compression "
                   f"at {fmt(shaken.speed_rpm)} rpm, more than the follower's whole lift of "
                   f"{fmt(lift)} mm: it is nowhere near rigid ({train}); a stiffer train or a "
                   "lighter follower (a higher natural frequency), more damping "
                   "(follower.damping_ratio), or a speed at which no strong harmonic of the "
                   "motion meets the natural frequency keeps it a cam follower", ringing, lift,
                   "mm")


def dynamic_jump_finding(speed: float, shaken: Vibration) -> Finding:
    """The elastic follower's contact force against zero at the design *speed* (rpm): where it
    falls below, the follower leaves the cam although the rigid model may say it holds."""
    jump = shaken.jump_speed_rpm
    least, at = shaken.min_force_N, shaken.min_force_at_deg
    first = _first_words(shaken, speed, least >= 0.0)
    train = (f"the elastic follower train (natural frequency {shaken.natural_Hz:.4g} Hz, "
             f"{shaken.frequency_ratio:.4g} times the cam's)")
    if least >= 0.0:
        return Finding("dynamic_jump", True, "error",
                       f"{train} keeps contact at {speed:.5g} rpm: its contact force stays "
                       f"positive (least {least:.4g} N at {at:.4g}°); {first}", speed, jump,
                       "rpm")
    # the continuous response's trough may fall below zero between the grid's points
    lost = ranges_deg(shaken.theta, shaken.force_N < 0.0) or ((at, at),)
    return Finding("dynamic_jump", False, "error",
                   f"{train} leaves the cam at {speed:.5g} rpm: its contact force falls to "
                   f"{least:.4g} N at {at:.4g}° (contact lost at {where(lost)}), although the "
                   f"rigid model may hold; {first}; a stiffer follower train, more preload, a "
                   "smoother motion law or a lower speed keeps it on the cam", speed, jump,
                   "rpm", lost)


def _first_words(shaken: Vibration, speed: float, holds: bool) -> str:
    """Where the speed search found the follower first leaving the cam, in words, beside the
    verdict at the design *speed* (rpm; *holds*: it keeps contact there)."""
    jump = shaken.jump_speed_rpm
    if jump is None:
        return f"it does not leave the cam up to {shaken.searched_to_rpm:.5g} rpm"
    if shaken.jump_at_every_speed:
        return (f"it leaves the cam at every speed searched, from {jump:.5g} rpm (nothing "
                "holds it in a dwell: more preload)")
    if holds and jump < speed:
        return (f"it leaves the cam at lower speeds, first at {safe_rpm(jump)} rpm: a "
                "resonance the cam runs through on its way to speed")
    return f"it first leaves the cam at {safe_rpm(jump)} rpm"



def stress_finding(record: AtSpeed, limit: float) -> Finding:
    """The largest Hertz stress over the cycle against ``limits.contact_stress`` (MPa)."""
    stress = record.stress
    if stress is None:
        return Finding("contact_stress", True, "error",
                       f"not computed: {record.stress_note}", None, limit, "MPa",
                       applicable=False)
    value, at = stress.max_MPa, stress.max_at_deg
    detail = f"at {fmt(at)}° on {stress.where_words()}, where {stress.shape_words(stress.index)}"
    if value <= limit:
        return Finding("contact_stress", True, "error",
                       f"largest contact stress {fmt(value)} MPa {detail}, within the allowed "
                       f"{fmt(limit)} MPa", value, limit, "MPa", at_deg=at)
    over = ranges_deg(stress.theta, stress.stress > limit)
    return Finding("contact_stress", False, "error",
                   f"contact stress reaches {fmt(value)} MPa {detail}, over the allowed "
                   f"{fmt(limit)} MPa at {where(over)}: a flatter profile there (a larger cam), "
                   "a larger roller or face, a longer contact, a lighter load or a tougher "
                   "material lowers it or bears it", value, limit, "MPa", over, at_deg=at)


def life_finding(analysis: Analysis, record: AtSpeed, limit: float) -> Finding:
    """The roller bearing's L₁₀ against ``limits.roller_life`` (hours)."""
    life = record.life
    if life is None:
        return Finding("roller_life", True, "error", f"not computed: {record.life_note}", None,
                       limit, "h", applicable=False)
    k = life.least
    fol = analysis.design.follower
    exponent = "3" if fol.roller_bearing == "ball" else "10/3"
    detail = (f"{life.names[k]}'s bearing lasts {fmt(life.hours[k])} h (L10 at "
              f"{fmt(analysis.design.cam.speed_rpm or 0.0)} rpm: an equivalent load of "
              f"{fmt(life.load_N[k])} N over {fmt(life.revolutions[k])} revolutions a turn, "
              f"C = {fmt(fol.roller_load_rating or 0.0)} N, exponent {exponent})")
    if life.hours[k] >= limit:
        return Finding("roller_life", True, "error",
                       f"{detail}, at least the required {fmt(limit)} h", life.hours[k], limit,
                       "h")
    return Finding("roller_life", False, "error",
                   f"{detail}, less than the required {fmt(limit)} h: a roller of higher load "
                   "rating, a lighter load (less preload, a lower speed), a larger roller or a "
                   "smaller cam (its roller turns less often) lasts longer", life.hours[k],
                   limit, "h")


def sample_at(grid: Array, values: Array, theta: Array) -> Array:
    """*values* on the analysis *grid* (rad, from 0 to 2π, a joint twice) at the cam angles
    *theta* (rad, in [0, 2π)), linearly between grid points; at a joint, the value just after
    it."""
    k = np.clip(np.searchsorted(grid, theta, side="right") - 1, 0, grid.size - 2)
    t0, t1 = grid[k], grid[k + 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(t1 > t0, (theta - t0) / (t1 - t0), 0.0)
    return values[k] * (1.0 - w) + values[k + 1] * w
