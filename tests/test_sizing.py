"""Sizing: the least base radius (a drum's radius) that meets a design's limits.

Every follower kind is sized, the sized cam built and its report read: every limit holds, and
0.01 mm less breaks the one said to govern. The sizes are checked against closed forms where
they exist (THEORY §B, §C), computed here from the motion program alone: a translating knife or
roller, √(Rp² − e²) ≥ max(|σs′ − e|/tan α − s); a translating flat face,
Rb ≥ ρ_min − min(s + s″); a drum, its floor radius ≥ max|s′|/tan α.
"""

from __future__ import annotations

import copy
import json
import math
import re
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from scipy.optimize import minimize_scalar

from camfab.analysis.sizing import Sizing
from camfab.design import Design
from camfab.design.loader import unsized_design
from camfab.errors import DesignError
from camfab.pipeline import analyse, build, design_from_text, load_design, size_design

from .conftest import DESIGNS, run_cli

RADIUS_KEYS = frozenset({"cam.base_radius", "cam.radius"})


def starter(kind: str) -> dict[str, Any]:
    text = (resources.files("camfab") / "starters" / f"{kind}.yaml").read_text(encoding="utf-8")
    data: dict[str, Any] = yaml.safe_load(text)
    return data


def _variant(kind: str, **follower: Any) -> dict[str, Any]:
    data = starter(kind)
    data["follower"].update(follower)
    return data


#: (id, design data): every follower of a disc cam, translating and oscillating, offset and
#: radial; groove and conjugate plates; a drum.
CASES: list[tuple[str, dict[str, Any]]] = [
    ("roller-offset", starter("disc-roller")),
    ("roller-cw", {**starter("disc-roller"), "cam": {**starter("disc-roller")["cam"],
                                                      "rotation": "cw"}}),
    ("knife-offset", starter("disc-knife")),
    ("knife-radial", _variant("disc-knife", offset=0)),
    ("flat", starter("disc-flat")),
    ("mushroom", _variant("disc-mushroom", offset=4)),
    ("oscillating-roller", starter("oscillating")),
    ("oscillating-knife", _variant("oscillating", type="knife", roller_radius=None)),
    ("oscillating-mushroom", _variant("oscillating", type="mushroom", roller_radius=None,
                                      face_radius=20)),
    ("oscillating-flat", starter("oscillating-flat")),
    ("groove", starter("groove")),
    ("conjugate", starter("conjugate")),
    ("drum", starter("cylindrical")),
]


def _clean(data: dict[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(data)
    out["follower"] = {k: v for k, v in out["follower"].items() if v is not None}
    return out


def _write(tmp: Path, data: dict[str, Any], name: str = "design.yaml") -> Path:
    path = tmp / name
    path.write_text(yaml.safe_dump(_clean(data), sort_keys=False), encoding="utf-8")
    return path


def sized(tmp: Path, data: dict[str, Any], offset: bool = False,
          pivot: bool = False) -> tuple[Design, Sizing]:
    keys = RADIUS_KEYS | ({"follower.offset"} if offset else set())
    design, left = unsized_design(_write(tmp, data, "unsized.yaml"), frozenset(keys))
    return design, size_design(design, left, pivot)


def _with(data: dict[str, Any], key: str, value: float, sizing: Sizing) -> dict[str, Any]:
    out = _clean(data)
    out["cam"][key] = value
    if sizing.offset is not None:
        out["follower"]["offset"] = sizing.offset
    if sizing.pivot_distance is not None:
        out["follower"]["pivot_distance"] = sizing.pivot_distance
    return out


def _failed(data: dict[str, Any]) -> set[str]:
    """The error checks a design fails, or the key a design-file rule names."""
    try:
        analysis = analyse(design_from_text(yaml.safe_dump(data)))
    except DesignError as exc:
        return {exc.location.field.split(".")[-1] if exc.location else "rule"}
    return {f.id for f in analysis.findings if not f.ok and f.severity == "error"}


def _governing_broken(governing: str, failed: set[str]) -> bool:
    """*governing* (a limit id) broken: its check fails, or the design-file rule of its key."""
    if governing in failed:
        return True
    rules = {"bore": {"bore"}, "keyway": {"depth", "keyway"}, "depth": {"groove_depth"},
             "offset": {"offset"}, "reach": {"arm_length", "pivot_distance", "face_offset"},
             "partner_b": {"arm_angle", "roller_spacing"}}
    return bool(rules.get(governing, set()) & failed)


@pytest.mark.parametrize("data", [c[1] for c in CASES], ids=[c[0] for c in CASES])
def test_the_sized_cam_meets_every_limit_and_a_hundredth_less_breaks_the_governing_one(
        tmp_path: Path, data: dict[str, Any]) -> None:
    design, sizing = sized(tmp_path, data)
    size = sizing.size
    assert size is not None and sizing.found.governing is not None
    assert all(limit.ok for limit in sizing.found.limits)
    key = sizing.key
    path = _write(tmp_path, _with(data, key, size, sizing))
    result = build(path, tmp_path / "out")
    report = json.loads((result.folder / f"{design.name}-report.json").read_text())
    errors = [c for c in report["checks"] if c["severity"] == "error" and not c["ok"]]
    assert not errors, errors
    if key == "base_radius":
        assert report["geometry"]["base_radius_mm"] == pytest.approx(size, abs=1e-9)
    governing = sizing.found.governing.id
    assert _governing_broken(governing, _failed(_with(data, key, size - 0.01, sizing))), governing


def _motion(program: Any, sigma: int) -> tuple[Any, Any]:
    """s and σs′ on a fine grid holding every segment's ends and middle, and a function giving
    (s, s′, s″) at one cam angle (independent of camfab's sampling)."""
    starts = np.array([seg.start for seg in program.segments])
    ends = np.append(starts[1:], 2 * math.pi)
    theta = np.unique(np.concatenate([np.linspace(0.0, 2 * math.pi, 720_001), starts,
                                      0.5 * (starts + ends), ends - 1e-12]))
    return theta, program.evaluate(theta)


def _max_refined(theta: Any, values: Any, at: Any) -> float:
    """The largest of a function sampled as *values* on *theta*, refined by a bounded scalar
    search round each of the ten largest samples."""
    best = float(values.max())
    for k in np.argsort(values)[-10:]:
        lo, hi = theta[max(k - 1, 0)], theta[min(k + 1, len(theta) - 1)]
        res = minimize_scalar(lambda t: -at(t), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-12})
        best = max(best, -float(res.fun))
    return best


@pytest.mark.parametrize("kind, offset, rotation", [("disc-roller", 10.0, "ccw"),
                                                    ("disc-roller", -6.0, "cw"),
                                                    ("disc-knife", 5.0, "ccw"),
                                                    ("disc-knife", 0.0, "ccw")])
def test_a_translating_follower_agrees_with_the_closed_form(tmp_path: Path, kind: str,
                                                            offset: float,
                                                            rotation: str) -> None:
    data = starter(kind)
    data["cam"].pop("bore", None)
    data["cam"].pop("keyway", None)
    data["cam"]["rotation"] = rotation
    data["follower"]["offset"] = offset
    design, sizing = sized(tmp_path, data)
    assert sizing.found.governing is not None
    assert sizing.found.governing.id == "pressure_angle"
    sigma = 1 if rotation == "ccw" else -1
    r = design.follower.trace_radius
    tan = math.tan(design.pressure_angle_limit)
    program = design.program
    theta, m = _motion(program, sigma)

    def need(t: float) -> float:
        s, ds = program.evaluate(t)[:2, 0]
        return abs(sigma * ds - offset) / tan - s

    d = _max_refined(theta, np.abs(sigma * m[1] - offset) / tan - m[0], need)
    closed = math.sqrt(d * d + offset * offset) - r
    assert sizing.size == pytest.approx(closed, abs=1e-4)


@pytest.mark.parametrize("margin", [0.0, 5.0])
def test_a_translating_flat_face_agrees_with_the_closed_form(tmp_path: Path,
                                                             margin: float) -> None:
    data = starter("disc-flat")
    data["cam"].pop("bore", None)
    data["cam"].pop("keyway", None)
    data["limits"] = {"min_radius_of_curvature": margin}
    design, sizing = sized(tmp_path, data)
    program = design.program
    theta, m = _motion(program, 1)

    def minus(t: float) -> float:
        s, _, dds = program.evaluate(t)[:3, 0]
        return -(s + dds)

    closed = margin + _max_refined(theta, -(m[0] + m[2]), minus)
    assert sizing.size == pytest.approx(closed, abs=1e-4)
    # on the side that passes: the grid's extreme is within some 1e-7 mm of the exact one
    assert sizing.size >= closed - 1e-6


def test_a_drum_agrees_with_the_closed_form(tmp_path: Path) -> None:
    data = starter("cylindrical")
    data["cam"].pop("bore", None)
    design, sizing = sized(tmp_path, data)
    theta, m = _motion(design.program, 1)
    steepest = _max_refined(theta, np.abs(m[1]),
                            lambda t: abs(float(design.program.evaluate(t)[1, 0])))
    closed = (design.cam.groove_depth or 0.0) + steepest / math.tan(design.pressure_angle_limit)
    assert sizing.key == "radius"
    assert sizing.size == pytest.approx(closed, abs=1e-4)


def test_the_best_offset_balances_the_rise_and_the_return(tmp_path: Path) -> None:
    data = yaml.safe_load((DESIGNS / "seed-10-4.yaml").read_text())
    design, sizing = sized(tmp_path, data, offset=True)
    assert sizing.offset is not None and sizing.size is not None
    # seed-10-4's return is steeper: the offset moves toward -X (ccw), and the base radius is
    # far below the least at the design's offset of +10 mm
    assert sizing.offset < 0.0
    _, at_design = sized(tmp_path, data)
    assert at_design.size is not None and sizing.size < at_design.size - 20.0
    built = analyse(design_from_text(yaml.safe_dump(_with(data, "base_radius", sizing.size,
                                                          sizing))))
    result = built.result
    worst = result.numbers.segment_pressure  # type: ignore[attr-defined]
    rise, ret = worst[0].value, worst[2].value
    limit = math.degrees(design.pressure_angle_limit)
    assert max(rise, ret) <= limit
    assert abs(rise - ret) < 0.01, (rise, ret)
    # and no offset does better: the least base radius either side is larger
    for step in (-0.05, 0.05):
        other = _clean(data)
        other["follower"]["offset"] = sizing.offset + step
        _, there = sized(tmp_path, other)
        assert there.size is not None and there.size > sizing.size


def test_a_flat_face_offset_centres_the_face(tmp_path: Path) -> None:
    data = starter("disc-flat")
    data["follower"]["face_width"] = 1000.0
    design, sizing = sized(tmp_path, data, offset=True)
    _, m = _motion(design.program, 1)
    assert sizing.offset == pytest.approx(0.5 * (m[1].max() + m[1].min()), abs=1e-3)


def test_an_oscillating_pivot_is_sized_for_its_arm(tmp_path: Path) -> None:
    data = starter("oscillating")
    _, sizing = sized(tmp_path, data, pivot=True)
    _, fixed = sized(tmp_path, data)
    assert sizing.pivot_distance is not None and sizing.size is not None
    assert fixed.size is not None and sizing.size <= fixed.size
    ok = _with(data, "base_radius", sizing.size, sizing)
    assert not _failed(ok)


def test_a_design_says_auto_and_the_report_says_what_was_sized(tmp_path: Path) -> None:
    data = yaml.safe_load((DESIGNS / "seed-10-4.yaml").read_text())
    data["cam"]["base_radius"] = "auto"
    data["follower"]["offset"] = "auto"
    data["sizing"] = {"round_to": 0.5}
    result = build(_write(tmp_path, data), tmp_path / "out")
    report = json.loads((result.folder / "seed-10-4-report.json").read_text())
    sizing = report["sizing"]
    assert sizing["base_radius_mm"] == report["geometry"]["base_radius_mm"]
    assert sizing["base_radius_mm"] % 0.5 == pytest.approx(0.0, abs=1e-9)
    assert sizing["round_to_mm"] == 0.5
    assert sizing["governed_by"] == "pressure_angle" and sizing["unit"] == "deg"
    assert sizing["at_deg"] is not None and "offset_mm" in sizing
    assert all(c["ok"] for c in report["checks"] if c["severity"] == "error")
    html = (result.folder / "seed-10-4-report.html").read_text()
    assert "sized (auto): base radius 52.0000 mm" in html or "sized (auto): base radius" in html
    assert "governed by pressure angle" in html
    # a design without auto says so with null
    plain = build(DESIGNS / "seed-10-4.yaml", tmp_path / "plain")
    assert json.loads((plain.folder / "seed-10-4-report.json").read_text())["sizing"] is None


def test_an_inch_design_is_sized_in_millimetres_and_written_in_inches(tmp_path: Path) -> None:
    data = starter("disc-roller")
    data["cam"].pop("keyway", None)
    mm = sized(tmp_path, data)[1].size
    inch = copy.deepcopy(data)
    inch["units"] = "in"
    inch["cam"].pop("keyway", None)
    for key in ("thickness", "bore"):
        inch["cam"][key] = inch["cam"][key] / 25.4
    for key in ("offset", "roller_radius"):
        inch["follower"][key] = inch["follower"][key] / 25.4
    inch["motion"] = [{k: ({**v, "lift": v["lift"] / 25.4} if "lift" in v else v)
                       for k, v in seg.items()} for seg in inch["motion"]]
    inch["cam"]["base_radius"] = "auto"
    design = design_from_text(yaml.safe_dump(inch))
    assert design.sized is not None and mm is not None
    assert design.sized.base_radius == pytest.approx(mm, abs=1e-6)
    assert design.cam.base_radius == pytest.approx(mm, abs=1e-9)


def test_camfab_size_answers_with_numbers() -> None:
    result = run_cli("size", str(DESIGNS / "seed-10-4.yaml"))
    assert result.exit_code == 0, result.output
    assert re.search(r"least base radius 90\.07\d\d mm", result.output)
    assert "governed by pressure angle" in result.output
    result = run_cli("size", str(DESIGNS / "seed-10-4.yaml"), "--offset")
    assert result.exit_code == 0, result.output
    assert re.search(r"with the offset -12\.5\d+ mm", result.output)


def test_camfab_size_says_when_no_size_meets_the_limits(tmp_path: Path) -> None:
    data = starter("disc-roller")
    data["limits"] = {"pressure_angle": 0.1}
    result = run_cli("size", str(_write(tmp_path, data)))
    assert result.exit_code == 1, result.output
    assert "no base radius up to" in result.output
    assert re.search(r"pressure angle is [\d.]+° at best, at a base radius of [\d.]+ mm \(it "
                     r"must be at most 0\.1°\)", result.output), result.output
    face = starter("disc-flat")
    face["follower"]["face_width"] = 5
    result = run_cli("size", str(_write(tmp_path, face)))
    assert result.exit_code == 1, result.output
    assert "the face width the contact needs is" in result.output
    assert "whatever the base radius (it must be at most 5.0000 mm)" in result.output


def test_camfab_size_refuses_what_it_does_not_size(tmp_path: Path) -> None:
    for args, words in ((["new-tangent"], "cam.type: a tangent cam is not sized: its shape sets "
                                          "its motion; camfab sizes the base radius of disc, "
                                          "groove, conjugate cams and the radius of cylindrical"),
                        (["globoidal"], "cam.type: a globoidal cam is not sized; camfab sizes"),
                        (["linear"], "cam.type: a linear cam is not sized; camfab sizes"),
                        (["oscillating", "--offset"], "an oscillating follower has no offset"),
                        (["disc-roller", "--pivot"], "--pivot")):
        kind = args[0].removeprefix("new-")
        path = _write(tmp_path, starter(kind))
        result = run_cli("size", str(path), *args[1:])
        assert result.exit_code == 2, result.output
        assert words in result.output, result.output
        if "cam.type" in words:  # on the line of the key it names (not one the design lacks)
            number = int(result.output.split(":")[1])
            assert path.read_text().splitlines()[number - 1].strip().startswith("type:")


def test_camfab_size_says_what_a_limit_on_the_size_itself_asks() -> None:
    """A wall round the bore, the export tolerance: limits on the radius being sized, said as
    the least radius they allow, not as a check whose value is the size."""
    result = run_cli("size", str(DESIGNS / "demo-auto-size.yaml"))
    assert result.exit_code == 0, result.output
    assert "✔ bore: a 1 mm wall round the bore: a size of at least 6.0000 mm" in result.output
    assert "✔ tolerance: the export tolerance: a size of more than 0.0010 mm" in result.output


def test_a_symmetric_motions_best_offset_is_zero(tmp_path: Path) -> None:
    """seed-poly-345's rise and return mirror each other: the best offset is 0, not the
    golden-section search's last digit (−0.0002 mm)."""
    result = run_cli("size", str(DESIGNS / "seed-poly-345.yaml"), "--offset")
    assert result.exit_code == 0, result.output
    assert "with the offset 0.0000 mm" in result.output


def test_advice_at_the_best_offset_names_no_other() -> None:
    """demo-undercut's symmetric program is at its best offset (0): the advice says so rather
    than offering the same size "with the offset 0.0000 mm"."""
    analysis = analyse(load_design(DESIGNS / "demo-undercut.yaml"))
    message = next(f.message for f in analysis.findings if f.id == "undercut")
    assert "passes with this offset, which is about the best (camfab size --offset)" in message
    assert "with the offset 0.0000 mm" not in message


def test_auto_where_camfab_does_not_size_is_a_clear_error(tmp_path: Path) -> None:
    data = starter("tangent")
    data["cam"]["base_radius"] = "auto"
    result = run_cli("build", str(_write(tmp_path, data)), "-o", str(tmp_path / "o"))
    assert result.exit_code == 2
    assert "design.yaml:" in result.output and "cam.base_radius" in result.output
    assert not (tmp_path / "o").exists()


def test_a_failing_build_names_the_size_that_passes(tmp_path: Path) -> None:
    data = yaml.safe_load((DESIGNS / "seed-10-4.yaml").read_text())
    analysis = analyse(design_from_text(yaml.safe_dump(data)))
    message = next(f.message for f in analysis.findings if f.id == "pressure_angle")
    assert "on the return an offset toward -X lowers it" in message
    found = re.search(r"a base radius of ([\d.]+) mm passes with this offset, and ([\d.]+) mm "
                      r"with the offset (-?[\d.]+) mm \(near the least", message)
    assert found, message
    here, best, offset = (float(g) for g in found.groups())
    for radius, e in ((here, data["follower"]["offset"]), (best, offset)):
        suggested = _clean(data)
        suggested["cam"]["base_radius"] = radius + 1e-4  # the message rounds to 1e-4 mm
        suggested["follower"]["offset"] = e
        assert "pressure_angle" not in _failed(suggested), (radius, e)


def test_an_offset_alone_is_sized_and_the_base_radius_stays(tmp_path: Path) -> None:
    data = yaml.safe_load((DESIGNS / "seed-10-4.yaml").read_text())
    data["cam"]["base_radius"] = 60
    _, both = sized(tmp_path, data, offset=True)
    data["follower"]["offset"] = "auto"
    design = design_from_text(yaml.safe_dump(data))
    assert design.cam.base_radius == 60
    assert design.sized is not None and design.sized.base_radius is None
    assert design.follower.offset == pytest.approx(both.offset, abs=1e-9)
    assert design.sized.offset == pytest.approx(both.offset, abs=1e-9)


def _rounds_badly(start: float, extra: float) -> float:
    """A bore radius x ≥ *start* whose x + *extra* less *extra* comes out above x in floating
    point (x + *extra* crossing a power of two rounds it): where a rule written as
    x > R − extra would refuse R = x + extra sized exactly."""
    found = next((x for x in start + 1e-3 * np.arange(10_000) if x > (x + extra) - extra),
                 None)
    assert found is not None
    return float(found)


@pytest.mark.parametrize("kind, key, extra", [("disc-mushroom", "base_radius", 1.0),
                                               ("cylindrical", "radius", 9.0)])
def test_a_radius_sized_to_the_bore_passes_the_rules_exactly(tmp_path: Path, kind: str, key: str,
                                                            extra: float) -> None:
    data = starter(kind)
    data["cam"].pop("keyway", None)
    # a bore that governs, and rounds the wrong way: x + extra just past 32 or 64
    half = _rounds_badly(31.5 if extra == 1.0 else 55.5, extra)
    data["cam"]["bore"] = 2.0 * half
    if kind == "cylindrical":
        data["cam"]["groove_depth"] = extra - 1.0
    data["cam"][key] = "auto"
    design = design_from_text(yaml.safe_dump(data))
    assert design.sized is not None and design.sized.governed_by == "bore"
    assert getattr(design.cam, key) == pytest.approx(half + extra, abs=1e-9)


def test_a_flat_face_is_never_sized_to_a_point(tmp_path: Path) -> None:
    """A flat face's profile ρ = Rb + s + s″ only has to stay above zero for its envelope not
    to fold: its sizing used to stop at a pointed cam (ρ of some 1e-5 mm) that passed every
    check. Without limits.min_radius_of_curvature a flat or mushroom face keeps the default 1 mm
    (its closed form: Rb ≥ 1 − min(s + s″)); a cam sharper than that fails; 0 given asks for
    none."""
    data = starter("disc-flat")
    data["cam"]["base_radius"] = "auto"
    built = analyse(design_from_text(yaml.safe_dump(data)))
    _, m = _motion(built.design.program, 1)
    assert built.design.cam.base_radius == pytest.approx(1.0 - float(np.min(m[0] + m[2])),
                                                         abs=1e-5)
    profile = built.result.numbers.profile_min_convex.value  # type: ignore[attr-defined]
    assert profile == pytest.approx(1.0, abs=1e-5) and built.exit_code == 0
    sharp = starter("disc-flat")
    sharp["cam"]["base_radius"] = 1.0 - float(np.min(m[0] + m[2])) - 0.5
    assert "curvature" in _failed(sharp)
    sharp["limits"] = {"min_radius_of_curvature": 0}
    assert "curvature" not in _failed(sharp)
