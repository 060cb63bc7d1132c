"""The speeds at which a spring-held follower first leaves its cam, elastic and rigid, against an
independent integration of the same models (:mod:`tests.jump_reference`): camfab's speed is the
safe end of its bracket — the reference holds contact there — and within 1e-5 of the reference's
speed, found by bisection; the least contact force at the design speed is the continuous
response's, which may fall between the grid's points.
"""

from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

import camfab
from camfab.pipeline import analyse, design_from_text, load_design

from .conftest import DESIGNS
from .jump_reference import Follower, bisect

STARTERS = Path(camfab.__file__).parent / "starters"

#: The agreement asked of a jump speed (relative).
AGREE = 1e-5


def _eccentric() -> object:
    """The seed's eccentric cam with an elastic train (its stiffness some 20 times the
    spring's)."""
    text = (DESIGNS / "seed-jump-eccentric.yaml").read_text().replace(
        "  mass: 1.75\n", "  mass: 1.75\n  stiffness: 500\n  damping_ratio: 0.04\n")
    return design_from_text(text, folder=DESIGNS)


def _starter(kind: str, stiffness: float) -> object:
    """A starter with its commented keys given (as `camfab new` writes it), the train's
    stiffness *stiffness* (N/mm)."""
    text = re.sub(r"# stiffness: \d+ ", f"# stiffness: {stiffness} ",
                  (STARTERS / f"{kind}.yaml").read_text())
    lines = []
    for line in text.splitlines():
        match = re.match(r"^(\s*)# ((?:mass|stiffness|damping_ratio|spring)\b.*)$", line)
        nested = re.match(r"^#   ((?:rate|preload): .*)$", line)
        lines.append(match.group(1) + match.group(2) if match else
                     "  " + nested.group(1) if nested else line)
    return design_from_text("\n".join(lines) + "\n", folder=DESIGNS)


RANDOM = """\
name: random-train
cam: {{type: disc, base_radius: {base}, speed_rpm: {rpm}, thickness: 10}}
follower: {{type: roller, roller_radius: 8, mass: {mass}, stiffness: {k}, damping_ratio: {zeta}}}
motion:
  - rise:   {{angle: {rise}, lift: {lift}, law: {law}}}
  - dwell:  {{angle: {dwell}}}
  - return: {{angle: {back}, law: {law_back}}}
  - dwell:  {{angle: {rest}}}
spring: {{rate: {rate}, preload: {preload}, damping: {cs}}}
"""

LAWS = ("cycloidal", "harmonic", "polynomial-345", "polynomial-4567", "modified-sine",
        "modified-trapezoid")


def _random(seed: int) -> object:
    """A plate cam with a random motion and train, run at half the speed its rigid model
    jumps at."""
    rng = random.Random(seed)
    rise = rng.choice((90, 100, 120, 140))
    back = rng.choice((90, 110, 130))
    dwell = rng.choice((20, 30, 40))
    values = {"base": rng.choice((25, 30, 40)), "rpm": 1000,
              "mass": round(rng.uniform(0.2, 1.0), 3),
              "k": rng.choice((40, 80, 150, 300)), "zeta": rng.choice((0.02, 0.05, 0.08)),
              "rise": rise, "lift": rng.choice((6, 10, 15)), "law": rng.choice(LAWS),
              "dwell": dwell, "back": back, "law_back": rng.choice(LAWS),
              "rest": 360 - rise - back - dwell, "rate": rng.choice((5, 10, 20)),
              "preload": rng.choice((60, 120, 200)), "cs": rng.choice((0, 2, 5))}
    design = design_from_text(RANDOM.format(**values))
    rigid = analyse(design).dynamics.jump_speed_rpm  # type: ignore[union-attr]
    values["rpm"] = round(0.5 * rigid, 1)
    return design_from_text(RANDOM.format(**values))


CASES = {
    "demo-valve-at-speed": lambda: load_design(DESIGNS / "demo-valve-at-speed.yaml"),
    "seed-jump-eccentric": _eccentric,
    "starter disc-flat": lambda: _starter("disc-flat", 400),
    "random 3": lambda: _random(3),
    "random 11": lambda: _random(11),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_dynamic_jump_speed_is_the_integrations_at_its_safe_end(case: str) -> None:
    design = CASES[case]()
    shaken = analyse(design).at_speed.vibration  # type: ignore[union-attr]
    assert shaken is not None and shaken.one_sided
    jump = shaken.jump_speed_rpm
    assert jump is not None and not shaken.jump_at_every_speed, case
    follower = Follower.of(design)
    # it holds at camfab's speed, and leaves the cam within the agreement above it
    assert follower.least_elastic(jump) >= 0.0
    assert follower.least_elastic(jump * (1 + AGREE)) < 0.0
    true = bisect(follower.least_elastic, jump, jump * (1 + AGREE), rel=AGREE / 4)
    assert abs(jump - true) <= AGREE * true
    # the least contact force at the design speed: the continuous response's
    speed = design.cam.speed_rpm  # type: ignore[attr-defined]
    least = follower.least_elastic(speed)
    assert shaken.min_force_N == pytest.approx(least, rel=1e-7, abs=1e-7 * shaken.max_force_N)


RIGID = {
    "seed-jump-eccentric, damped": (DESIGNS / "seed-jump-eccentric.yaml").read_text().replace(
        "  gravity: true", "  gravity: true\n  damping: 150"),
    "cycloidal, damped and loaded": """\
name: rigid
cam: {type: disc, base_radius: 30, speed_rpm: 900}
follower: {type: roller, roller_radius: 8, mass: 0.6}
motion:
  - rise:   {angle: 120, lift: 18, law: cycloidal}
  - dwell:  {angle: 40}
  - return: {angle: 110, law: polynomial-345}
  - dwell:  {angle: 90}
spring: {rate: 5, preload: 60, gravity: true, damping: 40, external_load: 15}
""",
}


@pytest.mark.parametrize("case", sorted(RIGID))
def test_the_rigid_jump_speed_is_where_the_reported_force_reaches_zero(case: str) -> None:
    """The rigid model's jump speed and its contact force are one model, the spring's damping
    in both: the reference's least force (its damping too) holds just below camfab's speed
    and not just above, and the jump check at a speed either side agrees with it."""
    design = design_from_text(RIGID[case], folder=DESIGNS)
    dyn = analyse(design).dynamics  # type: ignore[union-attr]
    assert dyn is not None and dyn.jump_speed_rpm is not None
    jump = dyn.jump_speed_rpm
    follower = Follower.of(design)
    assert follower.least_rigid(jump * (1 - 1e-7)) >= 0.0
    assert follower.least_rigid(jump * (1 + 1e-7)) < 0.0
    true = bisect(follower.least_rigid, jump * (1 - 1e-7), jump * (1 + 1e-7), rel=1e-9)
    assert jump == pytest.approx(true, rel=1e-7)
    for share, holds in ((1 - 1e-6, True), (1 + 1e-6, False)):
        text = re.sub(r"speed_rpm: \d+", f"speed_rpm: {jump * share!r}", RIGID[case])
        at = analyse(design_from_text(text, folder=DESIGNS))
        finding = next(f for f in at.findings if f.id == "jump")
        assert finding.ok is holds and (at.dynamics.min_force_N >= 0.0) is holds  # type: ignore
