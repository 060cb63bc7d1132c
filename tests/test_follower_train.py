"""The elastic follower train against an independent integration of the same equation of motion
(scipy's solve_ivp, segment by segment so that no step crosses a law's discontinuity, at
tolerances of 1e-11): the periodic steady state reached from rest over many damped cycles, the
undamped one by shooting, the rigid limit, the refusal at undamped resonance, the speed at which
the follower first leaves the cam, and a positive drive's sides.

The equation, written here from THEORY §J and not from camfab's code, at the trace point (m, s,
N): m x″ = k_f (s − x) + c (s′ − x′) − k_s x − c_s x′ − P, c = 2ζ√(m(k_f + k_s)), contact force
F_c = k_f (s − x) + c (s′ − x′).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from camfab.errors import DesignError
from camfab.pipeline import analyse, design_from_text

DISC = """\
name: train
cam: {{type: disc, base_radius: 30, speed_rpm: {rpm}, thickness: 10}}
follower: {{type: roller, roller_radius: 8, mass: 0.6, stiffness: {k}, damping_ratio: {zeta}}}
motion:
  - rise:   {{angle: 120, lift: 18, law: {rise}}}
  - dwell:  {{angle: 40}}
  - return: {{angle: 110, law: polynomial-345}}
  - dwell:  {{angle: 90}}
spring: {{rate: 5, preload: 120, damping: {cs}, external_load: 10, gravity: true}}
"""


@dataclass(frozen=True)
class Ode:
    """The follower train of a design as the test writes it: SI, at the trace point."""

    design: object
    m: float
    kf: float
    ks: float
    c: float
    cs: float
    load: float
    omega: float
    scale: float

    @classmethod
    def of(cls, design: object) -> Ode:
        fol, spring = design.follower, design.spring  # type: ignore[attr-defined]
        kf = fol.stiffness * 1000.0
        ks = 0.0 if spring is None else spring.rate * 1000.0
        zeta = fol.damping_ratio if fol.damping_ratio is not None else 0.05
        c = 2 * zeta * math.sqrt(fol.mass * (kf + ks))
        cs = 0.0 if spring is None else spring.damping
        load = 0.0 if spring is None else (spring.preload + spring.external_load
                                           + (fol.mass * 9.80665 if spring.gravity else 0.0))
        scale = (fol.arm_length / 1000.0) if fol.oscillating else 1e-3
        return cls(design, fol.mass, kf, ks, c, cs, load, design.cam.omega,  # type: ignore
                   scale)

    def lift(self, theta: np.ndarray) -> np.ndarray:
        """s and s′ (m, m/s) at cam angles *theta*."""
        motion = self.design.program.evaluate(theta)  # type: ignore[attr-defined]
        return np.array([motion[0] * self.scale, motion[1] * self.scale * self.omega])

    def rhs(self, t: float, y: np.ndarray, forced: bool = True) -> list[float]:
        x, v = y
        s, ds = self.lift(np.array([self.omega * t]))[:, 0] if forced else (0.0, 0.0)
        force = self.kf * (s - x) + self.c * (ds - v)
        extra = self.ks * x + self.cs * v + (self.load if forced else 0.0)
        return [v, (force - extra) / self.m]

    def run(self, y0: np.ndarray, turns: float = 1, forced: bool = True,
            at: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The state after *turns* from *y0*, and the states at the cam angles *at* (rad, in
        the last turn), integrated segment by segment."""
        program = self.design.program  # type: ignore[attr-defined]
        edges = sorted({seg.start for seg in program.segments} | {2 * math.pi})
        y = np.asarray(y0, dtype=float)
        samples = np.zeros((2, 0 if at is None else at.size))
        for turn in range(math.ceil(turns)):
            for a, b in itertools.pairwise(edges):
                sol = solve_ivp(lambda t, yy, turn=turn: self.rhs(
                                    t + turn * 2 * math.pi / self.omega, yy, forced),
                                (a / self.omega, b / self.omega), y, method="DOP853",
                                rtol=1e-11, atol=1e-15, dense_output=True)
                if at is not None and turn == math.ceil(turns) - 1:
                    inside = (at >= a) & (at <= b)
                    samples[:, inside] = sol.sol(at[inside] / self.omega)
                y = sol.y[:, -1]
        return y, samples

    def periodic(self, at: np.ndarray) -> np.ndarray:
        """The periodic state at the cam angles *at*, by shooting: the turn's map y ↦ My + q
        from three integrations, then y₀ = (I − M)⁻¹ q."""
        q, _ = self.run(np.zeros(2))
        columns = [self.run(np.eye(2)[k], forced=False)[0] for k in range(2)]
        start = np.linalg.solve(np.eye(2) - np.column_stack(columns), q)
        return self.run(start, at=at)[1]

    def contact(self, theta: np.ndarray, states: np.ndarray) -> np.ndarray:
        s, ds = self.lift(theta)
        return self.kf * (s - states[0]) + self.c * (ds - states[1])


def _design(rpm: float = 900, k: float | str = 120, zeta: float | str = 0.05,
            rise: str = "harmonic", cs: float = 4.0) -> object:
    return design_from_text(DISC.format(rpm=rpm, k=k, zeta=zeta, rise=rise, cs=cs))


def _interior(theta: np.ndarray) -> np.ndarray:
    """Grid points other than the second of a joint's pair (the state is one; the grid keeps
    each segment's one-sided values)."""
    keep = np.ones(theta.size, dtype=bool)
    keep[1:] = theta[1:] != theta[:-1]
    return keep


def test_steady_state_is_the_state_many_damped_cycles_reach() -> None:
    """From rest, the transient decays as e^(−ζ ω_n t): after 14 turns it is below 1e-12 of
    the motion, and the last turn is the periodic state camfab computes."""
    design = _design()
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None
    ode = Ode.of(design)
    theta = shaken.theta[::40]
    _, states = ode.run(np.zeros(2), turns=14, at=theta)
    s, _ = ode.lift(theta)
    scale = float(np.max(np.abs(shaken.error_m)))
    np.testing.assert_allclose(shaken.error_m[::40], states[0] - s, rtol=0, atol=1e-8 * scale)
    force = ode.contact(theta, states)
    np.testing.assert_allclose(shaken.force_N[::40], force, rtol=0,
                               atol=1e-7 * float(np.max(np.abs(force))))


@pytest.mark.parametrize(("k", "zeta", "cs"), [(120, 0.0, 0.0), (40, 0.0, 0.0), (300, 0.7, 4.0)])
def test_periodic_state_by_shooting(k: float, zeta: float, cs: float) -> None:
    """Undamped (away from resonance: the natural frequency some 5.8 and 3.4 times the cam's)
    and heavily damped trains: the periodic state found by shooting an integration."""
    design = _design(k=k, zeta=zeta, cs=cs)
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None
    ode = Ode.of(design)
    keep = np.flatnonzero(_interior(shaken.theta))[::25]
    theta = shaken.theta[keep]
    states = ode.periodic(theta)
    s, _ = ode.lift(theta)
    scale = float(np.max(np.abs(shaken.error_m)))
    np.testing.assert_allclose(shaken.error_m[keep], states[0] - s, rtol=0, atol=1e-8 * scale)
    force = ode.contact(theta, states)
    np.testing.assert_allclose(shaken.force_N[keep], force, rtol=0,
                               atol=1e-7 * float(np.max(np.abs(force))))
    # the residual vibration is the peak-to-peak error over each dwell
    for dwell in shaken.dwells:
        inside = shaken.segment == dwell.segment
        assert dwell.peak_to_peak_m == pytest.approx(float(np.ptp(shaken.error_m[inside])))


def test_an_oscillating_arm_is_taken_at_its_trace_point() -> None:
    text = """\
name: arm
cam: {type: disc, base_radius: 40, speed_rpm: 600}
follower: {type: roller, motion: oscillating, roller_radius: 8, pivot_distance: 90,
           arm_length: 60, mass: 0.4, stiffness: 80, damping_ratio: 0.04}
motion:
  - rise:   {angle: 120, lift: 20, law: cycloidal}
  - dwell:  {angle: 60}
  - return: {angle: 120, law: cycloidal}
  - dwell:  {angle: 60}
spring: {rate: 3, preload: 40}
"""
    design = design_from_text(text)
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and shaken.trace_m == pytest.approx(0.06)
    ode = Ode.of(design)
    keep = np.flatnonzero(_interior(shaken.theta))[::30]
    states = ode.periodic(shaken.theta[keep])
    force = ode.contact(shaken.theta[keep], states)
    np.testing.assert_allclose(shaken.force_N[keep], force, rtol=0,
                               atol=1e-7 * float(np.max(np.abs(force))))


def test_a_stiff_train_is_the_rigid_model() -> None:
    """As k_f → ∞ the elastic contact force is the rigid model's: to 1e-6 at 1e9 N/mm on a law
    whose jerk is continuous (a step of the acceleration or the jerk sets the train ringing,
    which no stiffness removes, only shortens)."""
    text = DISC.format(rpm=900, k="1e9", zeta=0.05, rise="polynomial-4567", cs=4).replace(
        "law: polynomial-345", "law: polynomial-4567")
    analysis = analyse(design_from_text(text))
    shaken = analysis.at_speed.vibration  # type: ignore[union-attr]
    rigid = analysis.dynamics.force_N  # type: ignore[union-attr]
    assert shaken is not None and rigid is not None
    error = np.max(np.abs(shaken.force_N - rigid)) / np.max(np.abs(rigid))
    assert error < 1e-6


def test_undamped_resonance_is_refused_on_the_stiffness() -> None:
    """ω_n = 5ω exactly with ζ = 0 (and no damping in the spring): no steady state; one
    located line."""
    omega = 900 * math.pi / 30
    stiffness = (0.6 * (5 * omega) ** 2 - 5000.0) / 1000.0
    with pytest.raises(DesignError) as info:
        _design(k=f"{stiffness!r}", zeta=0, cs=0.0)
    message = str(info.value)
    assert message.startswith("<design>:3: follower.stiffness:")
    assert "resonate" in message and "5 times" in message
    # damped, the same train is fine
    assert _design(k=f"{stiffness!r}", zeta=0, cs=4.0).follower.stiffness == pytest.approx(
        stiffness)


def _least_force(design: object) -> float:
    ode = Ode.of(design)
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    return float(np.min(ode.contact(theta, ode.periodic(theta))))


def test_the_dynamic_jump_speed_is_where_contact_is_first_lost() -> None:
    """The speed camfab reports: an integration holds contact 0.3 % below it and loses it
    0.3 % above; the check fails above it with the ranges where the force is negative."""
    design = _design(rpm=900, k=60)
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and shaken.jump_speed_rpm is not None
    jump = shaken.jump_speed_rpm
    assert _least_force(_design(rpm=jump * 0.997, k=60)) > 0.0
    assert _least_force(_design(rpm=jump * 1.003, k=60)) < 0.0
    above = analyse(_design(rpm=jump * 1.05, k=60))
    finding = next(f for f in above.findings if f.id == "dynamic_jump")
    assert not finding.ok and above.exit_code == 1 and finding.ranges_deg
    force = above.at_speed.vibration  # type: ignore[union-attr]
    negative = force.theta[force.force_N < 0.0]
    assert all(any(a - 1e-6 <= math.degrees(t) <= b + 1e-6 for a, b in finding.ranges_deg)
               for t in negative)


def test_a_positive_drive_changes_sides_where_its_force_changes_sign() -> None:
    """A groove cam's train has no spring: its contact force is m x″, whose mean over a turn
    is 0; the sides change where the force changes sign."""
    text = """\
name: groove-train
cam: {type: groove, base_radius: 30, thickness: 12, groove_depth: 6, speed_rpm: 600}
follower: {type: roller, roller_radius: 7, groove_clearance: 0.1, mass: 0.4, stiffness: 50}
motion:
  - rise:   {angle: 120, lift: 18, law: cycloidal}
  - dwell:  {angle: 60}
  - return: {angle: 120, law: cycloidal}
  - dwell:  {angle: 60}
"""
    design = design_from_text(text)
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and not shaken.one_sided
    ode = Ode.of(design)
    keep = np.flatnonzero(_interior(shaken.theta))[::25]
    force = ode.contact(shaken.theta[keep], ode.periodic(shaken.theta[keep]))
    np.testing.assert_allclose(shaken.force_N[keep], force, rtol=0,
                               atol=1e-7 * float(np.max(np.abs(force))))
    theta = shaken.theta
    keep = _interior(theta)
    mean = np.trapezoid(shaken.force_N[keep], theta[keep]) / (2 * math.pi)
    assert abs(mean) < 1e-6 * float(np.max(np.abs(shaken.force_N)))
    assert shaken.flank_changes
    # the side changes where the force passes 1 % of its largest on the other side (ringing
    # about no force in a dwell floats the follower in its clearance, it does not knock it)
    threshold = 0.01 * float(np.max(np.abs(shaken.force_N)))
    for deg, onto in shaken.flank_changes:
        before, after = np.interp(np.radians([deg - 0.06, deg + 0.06]) % (2 * math.pi),
                                  theta[keep], shaken.force_N[keep])
        assert onto * after > threshold >= onto * before


def test_the_error_is_the_trains_compression_and_its_vibration_about_it() -> None:
    """x − s holds the train's compression under the rigid force, −F_r/K, which a train that
    did not vibrate would show; the rest is its vibration, and in a dwell the compression is
    constant, so the residual vibration is the error's swing there."""
    design = _design()
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None
    ode = Ode.of(design)
    # the grid's one-sided values at a joint, as the analysis holds them
    _, theta, motion = design.program.segment_grid(math.radians(0.05))  # type: ignore
    np.testing.assert_array_equal(theta, shaken.theta)
    s, v, a = (motion[k] * ode.scale * ode.omega**k for k in range(3))
    rigid = ode.m * a + ode.cs * v + ode.ks * s + ode.load
    np.testing.assert_allclose(shaken.static_m, -rigid / (ode.kf + ode.ks), rtol=1e-12,
                               atol=1e-15)
    assert shaken.max_ringing_m < shaken.max_error_m


def test_a_drum_held_by_a_spring_changes_flanks_rather_than_jumping() -> None:
    """A drum's groove holds its roller on both sides: where the elastic force falls below
    zero the roller crosses to the other flank, which then carries it; no dynamic jump."""
    text = """\
name: drum-spring
cam: {type: cylindrical, speed_rpm: 600, radius: 60, length: 80, groove_depth: 10}
follower: {type: roller, roller_radius: 8, mass: 0.5, stiffness: 100, roller_length: 10}
motion:
  - rise:   {angle: 150, lift: 30, law: modified-trapezoid}
  - dwell:  {angle: 30}
  - return: {angle: 150, law: modified-trapezoid}
  - dwell:  {angle: 30}
spring: {rate: 1, preload: 10}
"""
    analysis = analyse(design_from_text(text))
    speed = analysis.at_speed
    assert speed is not None and speed.vibration is not None
    assert not speed.vibration.one_sided and speed.vibration.flank_changes
    assert not any(f.id == "dynamic_jump" for f in analysis.findings)
    assert speed.stress is not None
    negative = speed.force_N < -0.01 * np.max(np.abs(speed.force_N))
    assert negative.any()
    upper = speed.stress.contact.sides.index(next(side for side in speed.stress.contact.sides
                                                   if side.name == "the upper flank"))
    assert np.all(speed.stress.side[negative] == upper)


def test_a_follower_with_nothing_holding_it_in_a_dwell_leaves_at_every_speed() -> None:
    text = DISC.format(rpm=600, k=200, zeta=0.05, rise="cycloidal", cs=0).replace(
        "preload: 120", "preload: 0").replace(", external_load: 10, gravity: true", "")
    analysis = analyse(design_from_text(text))
    shaken = analysis.at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and shaken.jump_at_every_speed
    assert shaken.jump_speed_rpm == pytest.approx(0.02 * 600)
    finding = next(f for f in analysis.findings if f.id == "dynamic_jump")
    assert "at every speed searched" in finding.message


def _globoid_at_resonance(zeta: str) -> object:
    """The convex globoid demo with an elastic arm whose natural frequency is the cam's own
    (a 0.5 kg follower on a train of m(2π·1 Hz)² at 60 rpm)."""
    from .conftest import DESIGNS

    stiffness = 0.5 * (2 * math.pi) ** 2 / 1000.0
    text = (DESIGNS / "demo-globoidal-convex.yaml").read_text().replace(
        "  rest_angle: -10\n", f"  rest_angle: -10\n  mass: 0.5\n  stiffness: {stiffness!r}\n"
        f"  damping_ratio: {zeta}\n")
    return design_from_text(text, folder=DESIGNS)


@pytest.mark.parametrize("zeta", ["1e-15", "1e-300"])
def test_a_train_resonating_with_next_to_no_damping_is_an_error_without_numbers(
        zeta: str) -> None:
    """At a resonance with ζ = 1e-15 or 1e-300 the ringing adds up over some 1e14 turns or
    more: no steady state camfab can compute (the rounding of the turn's phase decides it), so
    the build fails on `train_vibration`, saying what to change, and gives no vibration, force
    or stress (it used to pass with 1e14 mm, the same for both)."""
    from camfab.export.report_json import at_speed_dict

    analysis = analyse(_globoid_at_resonance(zeta))
    assert analysis.exit_code == 1
    finding = next(f for f in analysis.findings if f.id == "train_vibration")
    assert not finding.ok and finding.severity == "error"
    for key in ("damping_ratio", "stiffness", "mass", "speed_rpm", "resonates"):
        assert key in finding.message
    speed = analysis.at_speed  # type: ignore[union-attr]
    assert speed.vibration is None and speed.force_N is None and speed.stress is None
    dynamics = at_speed_dict(analysis)
    assert dynamics["natural_frequency_Hz"] is None and dynamics["dynamic_error_max_mm"] is None
    assert "resonates" in dynamics["vibration_note"]


def test_a_train_far_from_rigid_is_an_error_with_its_numbers() -> None:
    """With ζ = 1e-3 at the same resonance the state is computable, and right: the first
    harmonic's steady response, a₁/(2ζω_n²) (a₁ the trace point's first harmonic of
    acceleration, from an FFT of the motion here), is the vibration, some 280 times the follower's
    lift: an error, with the numbers."""
    design = _globoid_at_resonance("1e-3")
    analysis = analyse(design)
    shaken = analysis.at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and analysis.exit_code == 1
    finding = next(f for f in analysis.findings if f.id == "train_vibration")
    assert not finding.ok and finding.value == pytest.approx(1000 * shaken.max_ringing_m)
    omega = 2 * math.pi  # 60 rpm
    theta = np.linspace(0, 2 * math.pi, 4096, endpoint=False)
    accel = design.program.evaluate(theta)[2] * 0.110 * omega**2  # type: ignore[attr-defined]
    first = 2 * abs(np.fft.rfft(accel)[1]) / theta.size
    expected = first / (2 * 1e-3 * omega**2)
    assert shaken.max_ringing_m == pytest.approx(expected, rel=3e-3)
    lift = math.radians(25) * 0.110
    assert shaken.max_ringing_m > 100 * lift
