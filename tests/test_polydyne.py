"""Polydyne cams (``motion_target: output``): the cam's lift computed so that the follower's
mass moves as the motion list asks at the design speed. Proven by an independent integration
of the follower train (scipy's solve_ivp, :class:`~tests.test_follower_train.Ode`, written from
THEORY §J) run on the computed cam: the mass follows the program, the dwells are still at the
design speed, and off it the vibration camfab reports is the integration's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camfab.errors import DesignError
from camfab.motion.laws import standard_law
from camfab.pipeline import analyse, design_from_text

from .conftest import DESIGNS, run_cli
from .test_follower_train import Ode

VALVE = """\
name: polydyne
cam: {{type: disc, base_radius: 30, speed_rpm: {rpm}, thickness: 14}}
follower: {{type: roller, roller_radius: 11, mass: 0.35, stiffness: 600, damping_ratio: {zeta}}}
motion_target: output
motion:
  - rise:   {{angle: 110, lift: 9, law: {law}}}
  - dwell:  {{angle: 20}}
  - return: {{angle: 110, law: polynomial-56789}}
  - dwell:  {{angle: 120}}
spring: {{rate: 25, preload: 250, damping: {cs}}}
"""


def _design(rpm: float = 1500, zeta: float = 0.06, law: str = "polynomial-56789",
            cs: float = 3.0) -> object:
    return design_from_text(VALVE.format(rpm=rpm, zeta=zeta, law=law, cs=cs))


def test_the_56789_polynomial_has_four_derivatives_zero_at_both_ends() -> None:
    law = standard_law("polynomial-56789")
    ends = law.derivatives(np.array([0.0, 1.0]), 5)
    assert ends[0].tolist() == [0.0, 1.0]
    assert np.abs(ends[1:5]).max() == 0.0
    assert ends[5, 0] == pytest.approx(126 * 120)  # 5! · 126
    # its peak velocity at u = ½: 315/128 (by hand from f′ = 630 u⁴(1 − u)⁴)
    assert law.peak(1) == pytest.approx(315 / 128, rel=1e-12)


@pytest.mark.parametrize(("zeta", "law"), [(0.0, "polynomial-56789"),
                                           (0.06, "polynomial-56789"),
                                           (0.06, "spline, order: 7, controls: [0.1, 0.5, 0.8]")])
def test_the_mass_follows_the_program_at_the_design_speed(zeta: float, law: str) -> None:
    """The independent integration, run on the polydyne cam to its periodic state, moves the
    mass as the motion list asks (from its rest on the base circle) to 1e-6 of the lift, and
    leaves no vibration in the dwells."""
    design = _design(zeta=zeta, law=law)
    ode = Ode.of(design)
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    states = ode.periodic(theta)
    x = design.output_program.evaluate(theta)[0] * ode.scale  # type: ignore[attr-defined]
    rest = -ode.load / (ode.kf + ode.ks)  # the mass's rest on the base circle (m)
    lift = 9e-3
    assert np.max(np.abs(states[0] - rest - x)) < 1e-6 * lift
    for segment in design.output_program.segments:  # type: ignore[attr-defined]
        if segment.kind == "dwell":
            inside = (theta > segment.start) & (theta < segment.end)
            assert np.ptp(states[0][inside]) < 1e-9  # m: 1e-6 mm


def test_camfab_reports_no_vibration_at_the_design_speed_and_the_integrations_off_it() -> None:
    """At the design speed the dwells are still; at ±20 % the vibration camfab reports for the
    polydyne cam (the largest swing of the mass over a dwell) is what the integration of the
    same cam at that speed gives."""
    design = _design()
    speed = analyse(design).at_speed  # type: ignore[union-attr]
    assert speed.vibration.residual_m < 1e-9
    band = speed.band
    assert band.polydyne_m[list(band.speeds_rpm).index(1500.0)] < 1e-9
    assert band.low_rpm < 1500.0 < band.high_rpm
    dwells = [seg for seg in design.program.segments if seg.kind == "dwell"]  # type: ignore
    at = np.concatenate([np.linspace(seg.start, seg.end, 2001) for seg in dwells])  # 0.01°
    for factor in (0.8, 1.2):
        k = int(np.argmin(np.abs(band.speeds_rpm - 1500 * factor)))
        ode = Ode.of(design)
        ode = Ode(design, ode.m, ode.kf, ode.ks, ode.c, ode.cs, ode.load,
                  band.speeds_rpm[k] * math.pi / 30, ode.scale)
        mass = ode.periodic(at)[0].reshape(len(dwells), -1)
        # camfab's grid is 0.05° apart, the integration's samples 0.01°: a swing's extremes
        # between points differ by some (0.05°)² of its curvature
        assert band.polydyne_m[k] == pytest.approx(np.ptp(mass, axis=1).max(), rel=1e-5)
        assert band.polydyne_m[k] > 1e-6  # off its speed, it rings


def test_a_law_without_four_continuous_derivatives_is_refused_where_it_is_named() -> None:
    with pytest.raises(DesignError) as caught:
        _design(law="cycloidal")
    text = str(caught.value)
    assert "motion[0].law" in text and "polynomial-56789" in text


def test_a_polydyne_cam_needs_its_train() -> None:
    text = VALVE.format(rpm=1500, zeta=0.06, law="polynomial-56789", cs=3.0)
    with pytest.raises(DesignError) as caught:
        design_from_text(text.replace("stiffness: 600, ", ""))
    assert "motion_target" in str(caught.value) and "stiffness" in str(caught.value)


def test_the_polydyne_example_builds_and_its_report_shows_both_motions(tmp_path) -> None:
    result = run_cli("build", str(DESIGNS / "demo-polydyne.yaml"), "-o", str(tmp_path))
    assert result.exit_code in (0, 1), result.output
    assert (tmp_path / "demo-polydyne.dxf").exists()


def test_the_studio_offers_what_the_motion_describes_as_a_choice() -> None:
    from camfab.serve.yamledit import fields

    found = [f.as_json() for f in fields((DESIGNS / "demo-polydyne.yaml").read_text())
             if f.path == "motion_target"]
    assert found == [{"path": "motion_target", "kind": "choice", "value": "output",
                      "choices": ["cam", "output"]}]


def test_a_slow_polydyne_cam_is_as_smooth_as_its_program() -> None:
    """At 0.0015 rpm the train's lag τ is some 1e-8 rad: the joins of its damped solution must
    not carry the rounding of the lift (some 1e-15 mm) into the cam's derivatives as 1/τⁿ
    (found by the fuzzer: an acceleration step of 1e2 mm/rad² at every joint)."""
    from camfab.motion.continuity import joint_steps

    design = _design(rpm=0.0015)
    program = design.program  # type: ignore[attr-defined]
    assert joint_steps(program) == []
    assert program.peak(3) < 2.0 * design.output_program.peak(3)  # type: ignore[attr-defined]
