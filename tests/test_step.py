"""STEP solids (camfab/export/step.py), read back with OpenCASCADE directly: one valid solid per
plate, its volume against the exact contours' areas (sampled finely and measured by shapely),
true circles and cylinders for the arcs and no B-spline; the same bytes every build; a clear
line without the extra; no OpenCASCADE in a build that does not ask for STEP."""

from __future__ import annotations

import functools
import io
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGN_FILES, DESIGNS, ROOT, need_step_extra, run_cli, tool

need_step_extra()  # CI installs the extra: there, its absence fails

#: One design of each plate kind with a thickness.
PLATE_KINDS = {load_design(p).cam.type: p for p in DESIGN_FILES
               if load_design(p).cam.thickness is not None}


@functools.cache
def stepped(path: Path):  # type: ignore[no-untyped-def]
    """The design and its artifacts built with a STEP (kept: the tests of a file share one
    build)."""
    design = load_design(path)
    design = design.model_copy(update={"outputs": ("dxf", "stl", "step")})
    artifacts = render(analyse(design))
    assert artifacts.analysis is not None
    return design, artifacts


def read(data: bytes):  # type: ignore[no-untyped-def]
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    assert reader.ReadStream("x.step", io.BytesIO(data)) == IFSelect_ReturnStatus.IFSelect_RetDone
    reader.TransferRoots()
    return reader.OneShape()


def solids(shape) -> list:  # type: ignore[no-untyped-def]
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    found, explorer = [], TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        found.append(explorer.Current())
        explorer.Next()
    return found


def volume(shape) -> float:  # type: ignore[no-untyped-def]
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    return float(props.Mass())


@pytest.mark.parametrize("kind", sorted(PLATE_KINDS), ids=sorted(PLATE_KINDS))
def test_a_plate_reads_back_as_exact_valid_solids(kind: str) -> None:
    from OCP.BRepCheck import BRepCheck_Analyzer

    design, artifacts = stepped(PLATE_KINDS[kind])
    data = artifacts.files[f"{design.name}.step"]
    text = data.decode("ascii")
    assert text.startswith("ISO-10303-21;") and "AUTOMOTIVE_DESIGN" in text  # AP214
    assert "SI_UNIT(.MILLI.,.METRE.)" in text
    shape = read(data)
    assert BRepCheck_Analyzer(shape).IsValid()
    parts = solids(shape)
    assert len(parts) == (2 if kind == "conjugate" else 1)
    # the arcs are circles and cylinders, never B-splines or facets
    assert len(re.findall(r"=\s*CIRCLE\(", text)) >= 2
    assert len(re.findall(r"=\s*CYLINDRICAL_SURFACE\(", text)) >= 1
    assert "B_SPLINE" not in text and "FACETED" not in text
    # the volume against the part's contours sampled finely, their areas by shapely
    analysis = artifacts.analysis
    check = analysis.verification.step
    assert check is not None and check.ok, check
    part = kind_of_part(analysis)
    expected = sum(region_volume(piece) for piece in part)
    assert volume(shape) == pytest.approx(expected, rel=1e-6)


def kind_of_part(analysis):  # type: ignore[no-untyped-def]
    """The part's extrusions (pieces of the solid tree), with a sign: +1 added, −1 cut."""
    from camfab.export.part import Difference, Extrusion, Union
    from camfab.kinds import kind_of

    solid = kind_of(analysis.design.cam.type).part(analysis).solid
    pieces = []

    def walk(node, sign: int) -> None:  # type: ignore[no-untyped-def]
        if isinstance(node, Extrusion):
            pieces.append((sign, node))
        elif isinstance(node, Union):
            for child in node.parts:
                walk(child, sign)
        else:
            assert isinstance(node, Difference)
            walk(node.body, sign)
            walk(node.cut, -sign)

    walk(solid, 1)
    top = max(n.height + (n.z or 0.0) for s, n in pieces if s > 0)
    return [(s, n, top) for s, n in pieces]


def region_volume(piece) -> float:  # type: ignore[no-untyped-def]
    sign, node, top = piece
    polygons = []
    for contour in node.exact:
        if isinstance(contour, float):
            angle = np.linspace(0.0, 2 * math.pi, 20001)[:-1]
            polygons.append(shapely.Polygon(np.column_stack((contour * np.cos(angle),
                                                             contour * np.sin(angle)))))
        else:
            polygons.append(shapely.Polygon(contour.points(1e-6)))
    region = polygons[0]
    for hole in polygons[1:]:
        region = region.difference(hole)
    z = node.z or 0.0
    height = min(node.height, top - z)  # a pocket's overshoot above the face cuts nothing
    return sign * region.area * height


@pytest.mark.parametrize("kind", ["disc", "conjugate"])
def test_the_same_design_gives_the_same_step_bytes(kind: str) -> None:
    # written twice in one process: OpenCASCADE's counters (of products, of a pair's assembly
    # occurrences) run on between the two
    from camfab.export.step import render_step
    from camfab.kinds import kind_of

    design = load_design(PLATE_KINDS[kind])
    solid = kind_of(design.cam.type).part(analyse(design)).solid
    first, second = (render_step(solid, design.name).data for _ in range(2))
    assert first == second


def test_cli_step_writes_the_file(tmp_path: Path) -> None:
    result = run_cli("build", "--step", str(DESIGNS / "seed-10-4.yaml"), "-o", "out",
                     cwd=tmp_path)
    assert result.exit_code == 1  # the seed's pressure angle, not the STEP
    assert (tmp_path / "out" / "seed-10-4.step").is_file()


def test_a_drum_with_a_velocity_step_withholds_its_step_and_says_so(tmp_path: Path) -> None:
    """A cornered groove (uniform velocity) has no smooth surfaces to fit: the STEP is not
    written, for the corner, and the verification (of the files written) still passes."""
    import json

    text = (DESIGNS / "demo-cylindrical.yaml").read_text().replace(
        "law: cycloidal", "law: uniform-velocity")
    (tmp_path / "corner.yaml").write_text(text)
    result = run_cli("build", "--step", "corner.yaml", "-o", "out", cwd=tmp_path)
    assert result.exit_code == 1, result.output  # the corner and the velocity step
    assert "not produced: step (the groove has a corner at each velocity step" in result.output
    assert not (tmp_path / "out" / "demo-cylindrical.step").exists()
    report = json.loads((tmp_path / "out" / "demo-cylindrical-report.json").read_text())
    failed = {c["id"] for c in report["checks"] if c["ok"] is False}
    assert failed == {"corner", "continuity"}


def test_a_step_that_reads_back_wrong_is_not_written_and_the_report_says_why(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import json

    import camfab.export.step_surfaces as surfaces

    fitted_solid = surfaces.fitted_solid

    def moved(*shifts: float):  # type: ignore[no-untyped-def]
        """The groove's grids moved up by *shifts* (mm; one a grid) before they are fitted."""
        return lambda grids: fitted_solid(tuple(
            g + np.array([0.0, 0.0, shift]) for g, shift in zip(grids, shifts, strict=True)))

    # the whole groove fitted 0.05 mm off its exact walls
    monkeypatch.setattr(surfaces, "fitted_solid", moved(0.05, 0.05, 0.05, 0.05))
    result = run_cli("build", "--step", str(DESIGNS / "demo-cylindrical.yaml"), "-o", "out",
                     cwd=tmp_path)
    assert result.exit_code == 1, result.output
    assert "not produced: step (the solid OpenCASCADE made of the part did not read back" \
        in result.output
    assert not (tmp_path / "out" / "demo-cylindrical.step").exists()
    assert (tmp_path / "out" / "demo-cylindrical.stl").is_file()
    report = json.loads((tmp_path / "out" / "demo-cylindrical-report.json").read_text())
    check = report["verification"]["step"]
    assert not check["ok"] and check["max_deviation_mm"] > 0.001
    assert "step" in report["verification"]["not_produced"]
    # one wall's surface 0.01 mm from its neighbours' edges: no solid to check
    monkeypatch.setattr(surfaces, "fitted_solid", moved(0.01, 0.0, 0.0, 0.0))
    unsewn = run_cli("build", "--step", str(DESIGNS / "demo-cylindrical.yaml"), "-o", "unsewn",
                     cwd=tmp_path)
    assert unsewn.exit_code == 0, unsewn.output
    assert "not produced: step (no exact solid of a cylindrical cam in camfab" in unsewn.output
    assert "do not sew into one closed shell" in unsewn.output
    assert not (tmp_path / "unsewn" / "demo-cylindrical.step").exists()


def exact_drum_volume(analysis) -> float:  # type: ignore[no-untyped-def]
    """A drum's volume (mm³) less its bore and groove, the groove's by the area of the band
    between the exact walls developed at each radius, integrated over the depth."""
    d, program = analysis.drum.drum, analysis.program
    theta = np.linspace(0.0, 2 * math.pi, 100001)
    m = program.evaluate(theta)
    radii = np.linspace(d.root, d.radius, 201)
    band = []
    for r in radii:
        walls = d.walls(theta, m[0], m[1], r)
        area = [r * float(np.sum(0.5 * (z[1:] + z[:-1]) * np.diff(np.unwrap(phi))))
                for phi, z in ((walls.phi_upper, walls.z_upper),
                               (walls.phi_lower, walls.z_lower))]
        band.append(abs(area[0] - area[1]))
    groove = float(np.sum(0.5 * (np.array(band[1:]) + np.array(band[:-1])) * np.diff(radii)))
    return math.pi * (d.radius**2 - d.bore**2) * d.length - groove


DRUMS = [p for p in DESIGN_FILES if p.stem != "demo-drum-steep"
         and load_design(p).cam.type == "cylindrical"]


def one_fitted_solid(path: Path):  # type: ignore[no-untyped-def]
    """The design, its artifacts, its STEP's text and shape as read back, after checking that
    the shape is one valid solid with fitted (B-spline) and cylindrical faces, and that the
    build's own check passed."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    design, artifacts = stepped(path)
    data = artifacts.files[f"{design.name}.step"]
    text = data.decode("ascii")
    shape = read(data)
    assert BRepCheck_Analyzer(shape).IsValid()
    assert len(solids(shape)) == 1
    assert "B_SPLINE_SURFACE" in text and "CYLINDRICAL_SURFACE" in text
    check = artifacts.analysis.verification.step
    assert check is not None and check.ok, check
    return design, artifacts, text, shape


@pytest.mark.parametrize("path", DRUMS, ids=[p.stem for p in DRUMS])
def test_a_drum_reads_back_as_one_valid_solid_of_the_exact_volume(path: Path) -> None:
    # the walls fitted surfaces, the drum and its bore true cylinders
    design, artifacts, _, shape = one_fitted_solid(path)
    check = artifacts.analysis.verification.step
    assert check.deviation_mm <= 0.1 * design.manufacturing.tolerance
    exact = exact_drum_volume(artifacts.analysis)
    assert volume(shape) == pytest.approx(exact, abs=design.manufacturing.tolerance * 1e3)


def test_the_checks_deviation_projects_only_the_probes_that_can_be_farthest(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The STEP check's distance of the exact surface's probes from the fitted faces: the
    same number, bit for bit, as projecting every probe (each probe's bound, from a point of
    the surface found near it, never below its projection's distance), from a few of them."""
    from camfab.export import step
    from camfab.kinds import kind_of

    design, artifacts = stepped(DESIGNS / "demo-cylindrical.yaml")
    solid = kind_of(design.cam.type).part(artifacts.analysis).solid
    shape = read(artifacts.files[f"{design.name}.step"])
    probes = len(step._probes(solid))
    projected: list[float] = []
    project = step._projected

    def counted(*args):  # type: ignore[no-untyped-def]
        projected.append(project(*args))
        return projected[-1]

    monkeypatch.setattr(step, "_projected", counted)
    bounded = step._deviation(shape, solid)
    few = len(projected)
    monkeypatch.setattr(step, "PROBE_SLACK_MM", math.inf)
    projected.clear()
    every = step._deviation(shape, solid)
    assert len(projected) == probes > 100 * few
    assert bounded == every == max(projected) == artifacts.analysis.verification.step.deviation_mm
    assert 0.0 < bounded <= 0.1 * design.manufacturing.tolerance


def test_without_the_extra_asking_for_step_is_one_clear_line(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import camfab.design.rules as rules

    monkeypatch.setattr(rules, "step_available", lambda: False)
    text = (DESIGNS / "seed-10-4.yaml").read_text() + "outputs: [dxf, step]\n"
    path = tmp_path / "d.yaml"
    path.write_text(text)
    result = run_cli("build", str(path), "-o", "out", cwd=tmp_path)
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "outputs" in lines[0] and "camfab[step]" in lines[0], lines
    assert not (tmp_path / "out").exists()
    flag = run_cli("build", "--step", str(DESIGNS / "seed-10-4.yaml"), "-o", "out",
                   cwd=tmp_path)
    assert flag.exit_code == 2 and "camfab[step]" in flag.output
    with pytest.raises(Exception, match="camfab\\[step\\]"):
        design_from_text(text)


def test_a_build_without_step_imports_no_opencascade(tmp_path: Path) -> None:
    code = ("import sys\nfrom camfab.pipeline import build\n"
            f"build({str(DESIGNS / 'seed-10-4.yaml')!r}, __import__('pathlib').Path("
            f"{str(tmp_path)!r}))\nprint('OCP' in sys.modules)\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120)
    assert run.stdout.strip() == "False"


GLOBOIDS = sorted(DESIGNS.glob("demo-globoidal-*.yaml"))


@pytest.mark.parametrize("path", GLOBOIDS, ids=[p.stem for p in GLOBOIDS])
def test_a_globoid_reads_back_as_one_valid_solid_on_the_exact_flanks(path: Path) -> None:
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt

    # the blank's surface its exact arc revolved, the bore a cylinder, the groove fitted
    design, artifacts, text, shape = one_fitted_solid(path)
    assert "TOROIDAL_SURFACE" in text or "SURFACE_OF_REVOLUTION" in text
    analysis = artifacts.analysis
    check = analysis.verification.step
    tolerance = design.manufacturing.tolerance
    assert check.deviation_mm <= 0.1 * tolerance
    # points of the exact flanks at random cam angles and depths inside the blank
    blank, g = analysis.globoid.blank, analysis.globoid.blank.follower
    rng = np.random.default_rng(7)
    theta = rng.uniform(0.0, 2 * math.pi, 60)
    low, high = sorted((blank.surface, blank.floor))
    ell = rng.uniform(low + 0.2, high - 0.2, 60)
    m = analysis.program.evaluate(theta)
    points = np.concatenate([g.flank(theta, ell, m, side) for side in (1, -1)])
    worst = 0.0
    for x, y, z in points:
        vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(float(x), float(y), float(z))).Vertex()
        distance = BRepExtrema_DistShapeShape(vertex, shape)
        assert distance.IsDone()
        worst = max(worst, distance.Value())
    assert worst <= 0.1 * tolerance, worst


def test_a_globoids_step_volume_is_the_limit_the_finer_stls_approach() -> None:
    """The STL's volume converges on the exact one linearly in the tolerance (its chords'
    sag): the STEP's volume lies at the limit extrapolated from the STLs at the tolerance and
    at half of it, not at the STL's."""
    import trimesh

    path = DESIGNS / "demo-globoidal-convex.yaml"
    design, artifacts = stepped(path)
    step_volume = volume(read(artifacts.files[f"{design.name}.step"]))
    coarse = trimesh.load(io.BytesIO(artifacts.files[f"{design.name}.stl"]), file_type="stl")
    finer = design.model_copy(update={
        "outputs": ("stl",), "manufacturing": design.manufacturing.model_copy(
            update={"tolerance": design.manufacturing.tolerance / 2})})
    fine = trimesh.load(io.BytesIO(render(analyse(finer)).files[f"{design.name}.stl"]),
                        file_type="stl")
    step = fine.volume - coarse.volume
    assert step > 0.0  # the coarse mesh cuts the groove a little wide
    limit = fine.volume + step
    assert step_volume == pytest.approx(limit, abs=0.25 * step)


#: One design of each kind with a solid, and both globoids (a torus and an arc revolved).
SOLID_KINDS = {**PLATE_KINDS, "cylindrical": DESIGNS / "demo-cylindrical.yaml",
               "globoidal": DESIGNS / "demo-globoidal-convex.yaml",
               "globoidal-concave": DESIGNS / "demo-globoidal-concave.yaml"}


@pytest.mark.parametrize("kind", sorted(SOLID_KINDS), ids=sorted(SOLID_KINDS))
def test_freecad_reads_the_step_as_valid_solids_of_our_volume(kind: str, tmp_path: Path) -> None:
    """FreeCAD reads the STEP as our solids, and its full check (``shape.check(True)``: the BOP
    argument check, each edge's curve against its faces everywhere along it) passes on each
    (tests/test_step_freecad.py runs it on every example plate)."""
    import json
    import os

    program = tool("freecadcmd", "freecad-python3")
    design, artifacts = stepped(SOLID_KINDS[kind])
    path = tmp_path / f"{design.name}.step"
    path.write_bytes(artifacts.files[path.name])
    (tmp_path / "home").mkdir()  # FreeCAD's preferences in a scratch HOME, not the user's
    run = subprocess.run([program, str(ROOT / "tests" / "freecad_step.py")],
                         env={**os.environ, "CAMFAB_STEP": str(path), "CAMFAB_FULL_CHECK": "1",
                              "HOME": str(tmp_path / "home")},
                         capture_output=True, text=True, timeout=300, check=False)
    line = next((x for x in run.stdout.splitlines() if "CAMFAB {" in x), None)
    assert line is not None, run.stdout + run.stderr
    found = json.loads(line[line.index("CAMFAB {") + len("CAMFAB "):])
    check = artifacts.analysis.verification.step
    assert found["valid"] and found["closed"], found
    assert found["solids"] == check.expected_solids
    # each solid on its own (a pair's plates touch face to face, which the check of the two as
    # one shape reports as the shape crossing itself)
    assert found["full_check"] == [None] * check.expected_solids, found["full_check"]
    # as OpenCASCADE reads it (FreeCAD integrates to the same fixed order)
    assert found["volume"] == pytest.approx(volume(read(path.read_bytes())), rel=1e-9)
    assert found["volume"] == pytest.approx(check.volume_mm3, rel=1e-5)
    assert found["circles"] >= 2
    # (a drum's and a globoid's grooves are fitted)
    assert found["bsplines"] == 0 or kind.startswith(("cylindrical", "globoidal"))
