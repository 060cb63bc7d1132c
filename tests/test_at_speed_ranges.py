"""The keys of a cam at its speed at the edges of floating point: a follower of 1e-300 kg or a cam
of 5e-324 rpm is refused on its line (exit 2, nothing written) instead of ending in an internal
error inside the dynamics, and ``camfab check`` and ``camfab build`` never disagree on a design.
Within the ranges the design file allows, the follower train's numbers stay finite at their
extremes (a natural frequency from 1e-8 to 1e13 times the cam's)."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from camfab.design import Design
from camfab.design.rules import MIN_AT_SPEED
from camfab.pipeline import analyse, design_from_text, render

from .conftest import DESIGNS, run_cli

#: Tiny and huge positive values of every key, each past what floating point holds for some
#: product of them (a subnormal, a square that underflows, a cube that overflows).
EDGES = [1e-300, 5e-324, 1e-12, 1e12, 1e300]


def _valve() -> dict[str, Any]:
    """The valve example: a spring-held, elastic follower train with a roller bearing."""
    data = yaml.safe_load((DESIGNS / "demo-valve-at-speed.yaml").read_text())
    data["limits"] = {"contact_stress": "1200 MPa"}
    return data


def _pair() -> dict[str, Any]:
    """A conjugate pair (no spring: the follower held on both sides) with an elastic train."""
    data = yaml.safe_load((DESIGNS / "demo-conjugate.yaml").read_text())
    data["follower"].update({"stiffness": 800, "roller_load_rating": "5 kN",
                             "roller_length": 10})
    data["limits"] = {"contact_stress": "1500 MPa"}
    return data


BASES = {"valve": _valve, "pair": _pair}
KEYS = {"valve": ["cam.speed_rpm", "follower.mass", "follower.stiffness",
                  "follower.damping_ratio", "follower.roller_load_rating", "spring.rate",
                  "spring.preload", "spring.damping", "spring.external_load"],
        "pair": ["cam.speed_rpm", "follower.mass", "follower.stiffness",
                 "follower.damping_ratio"]}
CASES = [(base, key, value) for base, keys in KEYS.items() for key in keys for value in EDGES]


@pytest.mark.parametrize(("base", "key", "value"), CASES,
                         ids=[f"{b}-{k}-{v:g}" for b, k, v in CASES])
def test_check_and_build_agree_at_the_edges_of_each_key(tmp_path: Path, base: str, key: str,
                                                        value: float) -> None:
    data = BASES[base]()
    section, name = key.split(".")
    data[section][name] = value
    path = tmp_path / "d.yaml"
    path.write_text(yaml.safe_dump(data))
    checked = run_cli("check", str(path))
    out = tmp_path / "out"
    built = run_cli("build", str(path), "-o", str(out))
    for result in (checked, built):
        assert "internal error" not in result.output, result.output
    assert checked.exit_code == built.exit_code, (checked.output, built.output)
    if checked.exit_code != 2:
        assert checked.exit_code in (0, 1)
        return
    for result in (checked, built):
        [line] = result.stderr.strip().splitlines()
        found = re.match(rf"{re.escape(str(path))}:(\d+): {re.escape(key)}: ", line)
        assert found is not None, line
        assert name in path.read_text().splitlines()[int(found.group(1)) - 1]
    assert not out.exists()
    least = MIN_AT_SPEED.get((section, name))
    if least is not None and value < least[0]:
        assert f"must be at least {least[0]:g} {least[1]}" in checked.stderr


def _finite(value: Any) -> bool:
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    if isinstance(value, list):
        return all(_finite(v) for v in value)
    return not isinstance(value, float) or math.isfinite(value)


def _trains(speed: float, mass: float, stiffness: float) -> Iterator[Design]:
    """The valve (a spring-held follower) and the pair (a positive drive) at *speed* (rpm),
    their followers of *mass* (kg) and *stiffness* (N/mm), the valve's spring as stiff."""
    for data in (_valve(), _pair()):
        data["cam"]["speed_rpm"] = speed
        data["follower"].update({"mass": mass, "stiffness": stiffness})
        if "spring" in data:
            data["spring"]["rate"] = stiffness
        yield design_from_text(yaml.safe_dump(data))


def test_the_train_s_numbers_stay_finite_at_the_ranges_ends() -> None:
    """At the least values the design file allows for the cam's speed and the follower's mass
    and the largest for its stiffness (the train 1e13 times as fast as the cam), every number
    of the follower train is computed: finite, none left out, the natural frequency
    √((k_f + k_s)/m)."""
    speed, mass, stiffness = 1e-3, 1e-6, 1e9
    for design in _trains(speed, mass, stiffness):
        files = render(analyse(design)).files
        dynamics = json.loads(files[f"{design.name}-report.json"])["dynamics"]
        assert _finite(dynamics)
        for key in ("natural_frequency_Hz", "dynamic_error_max_mm", "residual_vibration_mm",
                    "dynamic_min_contact_force_N", "contact_stress_max_MPa"):
            assert isinstance(dynamics[key], float), key
        total = stiffness * (2.0 if design.spring is not None else 1.0) * 1000.0
        assert dynamics["natural_frequency_Hz"] == pytest.approx(
            math.sqrt(total / mass) / (2 * math.pi), rel=1e-9)


def test_a_train_far_slower_than_the_cam_is_an_error_with_what_to_change() -> None:
    """At the largest speed and mass and the least stiffness the design file allows (the train
    1e-8 times as fast as the cam: its ringing adds up over some 1e7 turns), the follower
    cannot follow the cam: the ``train_vibration`` check fails, says the train is far too
    soft (not that it resonates) and what to change, and no number of the train is claimed."""
    speed, mass, stiffness = 1e6, 1e6, 1e-3
    for design in _trains(speed, mass, stiffness):
        analysis = analyse(design)
        found = {f.id: f for f in analysis.findings}
        assert found["train_vibration"].ok is False
        message = found["train_vibration"].message
        assert "far too soft" in message and "follower.stiffness" in message
        assert "resonates" not in message
        dynamics = json.loads(render(analysis).files[f"{design.name}-report.json"])["dynamics"]
        assert _finite(dynamics)
        assert dynamics["dynamic_error_max_mm"] is None
