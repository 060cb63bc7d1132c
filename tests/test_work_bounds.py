"""Work and memory bounded for long motion programs and fine tolerances, on every cam kind.

A drum's and a globoid's groove is a mesh whose facets grow as the tolerance shrinks and as the
motion bends more tightly: a design whose mesh would pass what camfab builds is refused as it
is loaded, on ``manufacturing.tolerance`` (or ``motion``), with the size it would take and the
finest tolerance the cam can be built to; a build at that tolerance ends in seconds. The plate
kinds' work on a thousand segments stays within seconds too: a linear cam's undercut test is
indexed, a flat face's is measured against the face lines near each point. Each reproducer is a
``camfab build`` in a child process limited by CPU time and memory
(:func:`tests.limited_child.run_forked`); the pieces that bound the work are checked against the
plain computations they replace.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from camfab.geometry.tube_budget import MAX_TUBE_FACETS

from .limited_child import ChildRun, run_forked

ROOT = Path(__file__).resolve().parents[1]
STARTERS = ROOT / "camfab" / "starters"

linux_only = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="forks children and reads /proc")

#: CPU seconds a refusal may take in a child forked with camfab imported: the mesh's size is
#: counted without building it, and the finest tolerance within the limit found in a few tries.
REFUSAL_CPU_S = 5.0
#: CPU seconds (and growth of memory, MB) a build may take: the heaviest designs inside
#: camfab's limits (a concave globoid's mesh at the most camfab builds) take some 13 s of CPU
#: and 1 GB.
BUILD_CPU_S = 18.0
BUILD_MEMORY_MB = 1500.0
#: The child's CPU limit: past it a runaway is killed (before these bounds, the reproducers
#: ran out of memory, crashed, or took minutes).
CHILD_CPU_S = 30.0


def starter(kind: str) -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load((STARTERS / f"{kind}.yaml").read_text("utf-8"))
    return data


def many_segments(data: dict[str, Any], count: int = 1000) -> dict[str, Any]:
    """*data* with a motion of *count* small cycloidal rises and returns (the loader's most):
    0.2 mm each (0.05° of an arm's swing), *count* of them over the cycle (the stroke)."""
    linear = data["cam"]["type"] == "linear"
    span = "travel" if linear else "angle"
    step = (float(data["cam"]["stroke"]) if linear else 360.0) / count
    lift = 0.05 if data["follower"].get("motion") == "oscillating" else 0.2
    data["motion"] = [{"rise": {span: step, "lift": lift, "law": "cycloidal"}} if i % 2 == 0
                      else {"return": {span: step, "law": "cycloidal"}} for i in range(count)]
    return data


def with_tolerance(data: dict[str, Any], tolerance: float) -> dict[str, Any]:
    data.setdefault("manufacturing", {})["tolerance"] = tolerance
    return data


def build(tmp_path: Path, data: dict[str, Any]) -> tuple[ChildRun, Path]:
    """``camfab build design.yaml -o out`` in a limited child; its run and its output folder."""
    (tmp_path / "design.yaml").write_text(yaml.safe_dump(data, sort_keys=False), "utf-8")
    run = run_forked(["build", "design.yaml", "-o", "out"], tmp_path, CHILD_CPU_S)
    return run, tmp_path / "out"


def refusal(run: ChildRun, out: Path, key: str) -> str:
    """The one line of a refusal on *key*, checked: exit 2, one line naming the design file
    and the key, nothing written, within seconds."""
    assert run.code == 2, run.describe()
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1, run.describe()
    assert re.match(rf"design\.yaml:\d+: {re.escape(key)}: ", lines[0]), lines[0]
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr
    assert not out.exists() or not any(out.iterdir()), "a refused build wrote files"
    assert run.cpu_s < REFUSAL_CPU_S, run.describe()
    return lines[0]


def finest(line: str) -> float:
    """The tolerance (mm) a refusal says the cam can be built to."""
    match = re.search(r"can be built to ([0-9.e+-]+) mm or coarser", line)
    assert match, line
    return float(match.group(1))


def built(run: ChildRun, out: Path) -> None:
    """A build that ended within its bounds: exit 0 or 1, nothing on stderr, files written."""
    assert run.code in (0, 1), run.describe()
    assert not run.stderr.strip(), run.describe()
    assert any(out.glob("*.stl")) or any(out.glob("*.dxf")), run.describe()
    assert run.cpu_s < BUILD_CPU_S, run.describe()
    assert run.peak_mb < BUILD_MEMORY_MB, run.describe()


# ---- the reproducers --------------------------------------------------------------------------

@linux_only
def test_a_drum_of_a_thousand_segments_is_refused_with_the_size_it_would_take(
        tmp_path: Path) -> None:
    """It ran out of memory (5.6 GB) after 27 s: its groove folds on every bump, a mesh of
    71,000 stations, and the roller run through it held every angle's window at once."""
    run, out = build(tmp_path, many_segments(starter("cylindrical")))
    line = refusal(run, out, "manufacturing.tolerance")
    assert "a drum's groove" in line and "million facets" in line
    assert f"at most {MAX_TUBE_FACETS:,} facets" in line
    assert 0.001 < finest(line) <= 1.0


@linux_only
@pytest.mark.parametrize("tolerance", [0.0001, 0.001], ids=["finest", "plate default"])
def test_a_globoid_at_a_fine_tolerance_is_refused_with_the_size_it_would_take(
        tmp_path: Path, tolerance: float) -> None:
    """At 0.0001 mm (the finest the design file takes) it crashed (SIGSEGV at 4.7 GB) or ran
    out of memory (11.6 GB); at 0.001 mm it took 39 s and 3.2 GB."""
    run, out = build(tmp_path, with_tolerance(starter("globoidal"), tolerance))
    line = refusal(run, out, "manufacturing.tolerance")
    assert f"at {tolerance:g} mm would take" in line and "million facets" in line
    assert "GB to build" in line
    assert 0.001 < finest(line) < 0.01  # the starter's default, 0.01 mm, builds


@linux_only
def test_a_globoid_of_a_thousand_segments_is_refused_with_the_size_it_would_take(
        tmp_path: Path) -> None:
    """It built in 51 s at 1.3 GB."""
    run, out = build(tmp_path, many_segments(starter("globoidal")))
    line = refusal(run, out, "manufacturing.tolerance")
    assert "a globoid's groove" in line and "million facets" in line
    assert 0.01 < finest(line) <= 1.0


@linux_only
def test_the_tolerance_a_refusal_names_builds_in_seconds(tmp_path: Path) -> None:
    """The globoidal starter of a thousand segments at the finest tolerance its refusal names:
    a mesh near the most camfab builds, within the bounds of a build. (At its own motion the
    starter's finest, some 0.005 mm, builds the same way in some 13 s of CPU.)"""
    refused, out = build(tmp_path, many_segments(starter("globoidal")))
    tolerance = finest(refusal(refused, out, "manufacturing.tolerance"))
    run, out = build(tmp_path, with_tolerance(many_segments(starter("globoidal")), tolerance))
    built(run, out)


@linux_only
def test_a_linear_cam_of_a_thousand_segments_builds_in_seconds(tmp_path: Path) -> None:
    """It took 107 s: every bump undercut, each of its faces measured against the whole pitch
    curve."""
    run, out = build(tmp_path, many_segments(starter("linear")))
    built(run, out)


def test_a_motion_too_tight_at_any_tolerance_is_refused_on_the_motion() -> None:
    """When even the coarsest tolerance leaves the mesh too large, the motion is named."""
    from camfab.design.rules import RuleViolation
    from camfab.geometry.tube_budget import check_tube

    with pytest.raises(RuleViolation) as refused:
        check_tube(lambda tolerance, most: 10 * MAX_TUBE_FACETS, 0.001, "a drum's groove",
                   1000)
    assert refused.value.path == ("motion",)
    assert "1,000 segments" in str(refused.value) and "1 mm" in str(refused.value)


# ---- the bounds, against what they replace ----------------------------------------------------

def _design(data: dict[str, Any]):  # type: ignore[no-untyped-def]
    from camfab.pipeline import design_from_text

    return design_from_text(yaml.safe_dump(data, sort_keys=False))


@pytest.mark.parametrize("tolerance", [0.001, 0.0003])
def test_a_drums_mesh_is_counted_as_built(tolerance: float) -> None:
    from camfab.curves.sampling import SAMPLING_SHARE
    from camfab.geometry.drum import drum
    from camfab.geometry.drum_mesh import groove_tube, tube_facets

    design = _design(starter("cylindrical"))
    d, share = drum(design), SAMPLING_SHARE * tolerance
    faces = len(groove_tube(d, design.program, share).faces)
    assert tube_facets(d, design.program, share, 10**9) == faces
    # counted no further than the most: more than it, from the stations alone
    assert faces > tube_facets(d, design.program, share, 1000) > 1000


@pytest.mark.parametrize("tolerance", [0.02, 0.01])
def test_a_globoids_mesh_is_counted_as_built(tolerance: float) -> None:
    from camfab.geometry.globoid_cam import globoid_cam, tube, tube_plan

    design = _design(starter("globoidal"))
    blank, program = globoid_cam(design), design.program
    made = tube(blank, program, tolerance)
    plan = tube_plan(blank, program, tolerance)
    assert plan.facets == len(made.faces)
    assert plan.stations is not None and np.array_equal(plan.stations, made.stations)
    assert np.array_equal(plan.rows, made.rows)
    given_up = tube_plan(blank, program, tolerance, most=1000)
    assert given_up.stations is None and given_up.facets > 1000


def test_stations_are_counted_as_spread() -> None:
    from camfab.curves.sampling import spread, spread_count

    program = _design(many_segments(starter("disc-roller"), 300)).program
    segment, theta, m = program.segment_grid(math.radians(0.05))
    for density in (np.full(theta.size, 50.0), 40.0 + 3000.0 * np.abs(m[2]) / np.abs(m[2]).max()):
        count = spread_count(segment, theta, density, len(program.segments))
        assert abs(count - spread(segment, theta, density, len(program.segments)).size) <= 3


def test_the_roller_run_through_a_drum_in_blocks_is_the_run_at_once(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from camfab.arrays import edge_groups
    from camfab.geometry import drum_mesh
    from camfab.geometry.drum import drum
    from camfab.motion.program import cycle_angles

    design = _design(starter("cylindrical"))
    d, program = drum(design), design.program
    tube = drum_mesh.groove_tube(d, program, 0.0005)
    theta = cycle_angles(math.radians(0.5))
    centre = d.start + program.evaluate(theta)[0]
    edges = edge_groups(tube.faces, len(tube.vertices))[0]
    whole = drum_mesh.groove_lift(d, tube.vertices, edges, theta, centre)
    monkeypatch.setattr(drum_mesh, "LIFT_BLOCK_ELEMENTS", 5000)
    blocks = drum_mesh.groove_lift(d, tube.vertices, edges, theta, centre)
    for a, b in zip(whole, blocks, strict=True):
        assert np.array_equal(a, b)


def test_distances_in_blocks_are_the_distances_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    from camfab.curves import nearest
    from camfab.curves.profile import Profile

    rng = np.random.default_rng(4)
    angle = np.sort(rng.uniform(0.0, 2 * math.pi, 3000))
    radius = 40.0 + 3.0 * np.sin(7 * angle)
    profile = Profile.from_points(np.stack((radius * np.cos(angle), radius * np.sin(angle)), -1))
    points = rng.uniform(-50.0, 50.0, (20_000, 2))
    whole = profile.distance(points)
    monkeypatch.setattr(nearest, "SEARCH_BLOCK", 700)
    assert np.array_equal(profile.distance(points), whole)


def _every_line(normals: np.ndarray, heights: np.ndarray, slack: float,
                points: np.ndarray) -> np.ndarray:
    return np.all(points @ normals.T <= heights[None, :] + slack, axis=1)


@pytest.mark.parametrize("seed", range(6))
def test_the_face_test_near_each_point_is_the_test_of_every_line(seed: int) -> None:
    """Points below every face line or not, judged against the lines near each: the same
    answer as every line's, away from ties (a point on a line, within rounding)."""
    from camfab.geometry.undercut import below_face_lines

    rng = np.random.default_rng(seed)
    count = int(rng.integers(1, 4000))
    beta = rng.uniform(-4.0, 4.0, count) if seed % 2 else np.linspace(0, 2 * math.pi, count)
    normals = np.stack((np.cos(beta), np.sin(beta)), -1)
    heights = 40.0 + rng.uniform(0.0, 0.3 * seed, count) - (30.0 if seed == 5 else 0.0)
    slack = 1e-6
    r, a = rng.uniform(0.0, 80.0, 10_000), rng.uniform(-math.pi, math.pi, 10_000)
    points = np.stack((r * np.cos(a), r * np.sin(a)), -1)
    excess = np.max(points @ normals.T - heights - slack, axis=1)
    clear = np.abs(excess) > 1e-9
    kept = below_face_lines(normals, heights, slack)(points)
    assert np.array_equal(kept[clear], _every_line(normals, heights, slack, points)[clear])
    assert kept.any() and not kept.all()
