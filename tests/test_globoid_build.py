"""Globoidal cams built (camfab/kinds/globoid.py): the groove's tube against the exact flanks,
the STL read back by trimesh against the exact blank less a brute-force estimate of the groove's
volume, the roller put at its poses in the STL and found clear of material by winding numbers,
the design file's rules, and the type's default tolerance."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from camfab.errors import DesignError
from camfab.geometry.globoid import to_cam
from camfab.geometry.globoid_cam import GloboidCam
from camfab.motion.program import MotionProgram
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS, run_cli

GLOBOIDS = sorted(DESIGNS.glob("demo-globoidal-*.yaml"))
IDS = [p.stem for p in GLOBOIDS]


def built(path: Path):  # type: ignore[no-untyped-def]
    """The analysis after the build's read-back, and the STL's bytes."""
    artifacts = render(analyse(load_design(path)))
    assert artifacts.analysis is not None
    return artifacts.analysis, artifacts.files[f"{path.stem}.stl"]


@pytest.fixture(scope="module", params=GLOBOIDS, ids=IDS)
def globoid(request: pytest.FixtureRequest):  # type: ignore[no-untyped-def]
    return built(request.param)


def test_the_build_passes_and_its_verification_holds_the_tolerance(globoid) -> None:  # type: ignore[no-untyped-def]
    analysis, _ = globoid
    tolerance = analysis.design.manufacturing.tolerance
    assert tolerance == pytest.approx(0.01)  # the type's default
    checks = {f.id: f for f in analysis.findings}
    for name in ("pressure_angle", "undercut", "groove", "verification"):
        assert checks[name].ok, checks[name].message
    assert analysis.verification.lift.max_mm <= 0.5 * tolerance
    assert analysis.verification.stl.ok
    assert analysis.verification.deviation_mm <= 1e-9


def test_the_roller_run_measuring_the_near_edges_first_is_the_run_over_them_all(
        globoid, monkeypatch: pytest.MonkeyPatch) -> None:  # type: ignore[no-untyped-def]
    """The read-back's roller run measures, at each pose, the edges its search finds near the
    roller's axis, and every edge of its window only where a side has no wall that near: the
    same numbers, bit for bit, as measuring them all at every pose (``NEAR_TOLERANCES``
    infinite), as measuring them all after the near ones at every pose (minus infinity: a
    side never near enough), and as a search within a thousandth of the tolerance (some poses
    measure all, some not), whatever the size of the blocks of poses that share a pass."""
    from camfab.arrays import edge_groups
    from camfab.geometry import globoid_run
    from camfab.geometry.globoid_cam import VERIFY_STEP
    from camfab.motion.program import cycle_angles

    analysis, stl = globoid
    blank = analysis.globoid.blank
    tolerance = analysis.design.manufacturing.tolerance
    mesh = trimesh.load(trimesh.util.wrap_as_stream(stl), file_type="stl")
    vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    pairs = edge_groups(faces, len(vertices))[0]
    edges = globoid_run.mesh_edges(vertices, pairs, globoid_run.near_roller(blank, vertices))
    theta = cycle_angles(VERIFY_STEP)[::3]
    motion = analysis.program.evaluate(theta)
    runs, fell_back = [], []
    measure_all = globoid_run._nearest

    def counted(*args):  # type: ignore[no-untyped-def]
        fell_back.append(len(args[0]))
        return measure_all(*args)

    for near, block in ((globoid_run.NEAR_TOLERANCES, globoid_run.BLOCK), (math.inf, 3),
                        (-math.inf, 5), (1e-3, 1)):
        monkeypatch.setattr(globoid_run, "NEAR_TOLERANCES", near)
        monkeypatch.setattr(globoid_run, "BLOCK", block)
        fell_back.clear()
        monkeypatch.setattr(globoid_run, "_nearest", counted)
        run = globoid_run.roller_run(blank, edges, theta, motion, tolerance)
        monkeypatch.setattr(globoid_run, "_nearest", measure_all)
        runs.append(np.stack((run.cut_mm, run.gap_plus_mm, run.gap_minus_mm)))
        if near == 1e-3:  # a call per pose, and one more at each pose that measured them all
            assert theta.size < len(fell_back) < 2 * theta.size
    assert np.isfinite(runs[0]).all()
    for other in runs[1:]:
        assert np.array_equal(runs[0], other)


def test_the_tube_stays_within_the_tolerance_of_the_exact_flanks(globoid) -> None:  # type: ignore[no-untyped-def]
    """At points of the flanks between the tube's stations and rows, the exact flank's distance
    from the plane of the tube's facet there."""
    from camfab.curves.sampling import SAMPLING_SHARE
    from camfab.geometry.globoid_cam import tube

    analysis, _ = globoid
    blank, program = analysis.globoid.blank, analysis.program
    tolerance = SAMPLING_SHARE * analysis.design.manufacturing.tolerance
    made = tube(blank, program, tolerance)
    g = blank.follower
    theta, rows = made.stations, made.rows
    rng = np.random.default_rng(7)
    k = rng.integers(0, theta.size, 4000)
    j = rng.integers(0, rows.size - 1, 4000)
    s, t = rng.random(4000), rng.random(4000)
    ahead = np.where(k + 1 < theta.size, theta[(k + 1) % theta.size], theta[0] + 2 * math.pi)
    th = theta[k] + s * (ahead - theta[k])
    ell = rows[j] + t * (rows[j + 1] - rows[j])
    worst = 0.0
    for side in (1, -1):
        corner = {(dk, dj): g.flank(np.where(dk, ahead, theta[k]), rows[j + dj],
                                    program.evaluate(np.where(dk, ahead, theta[k])), side)
                  for dk in (0, 1) for dj in (0, 1)}
        exact = g.flank(th, ell, program.evaluate(th), side)
        # the two facets of each quad: (a, c, b) below the diagonal b–c, (b, c, d) above
        a, b, c, d = corner[0, 0], corner[0, 1], corner[1, 0], corner[1, 1]
        lower = s + t <= 1.0
        p0 = np.where(lower[:, None], a, d)
        normal = np.cross(c - p0, b - p0)
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        worst = max(worst, float(np.max(np.abs(np.einsum("ij,ij->i", exact - p0, normal)))))
    assert worst <= tolerance * 1.05


def _blank_volume(blank: GloboidCam) -> float:
    """The blank's volume (mm³) from its surface r(z) about the pivot, integrated in z."""
    c, s, half = blank.follower.centre, blank.surface, blank.width / 2.0
    z = np.linspace(-half, half, 200001)
    root = np.sqrt(s * s - z * z)
    r = c - root if blank.inward > 0 else root - c
    area = math.pi * (r * r - blank.bore * blank.bore)
    return float(np.sum(0.5 * (area[1:] + area[:-1]) * np.diff(z)))


def _groove_volume(blank: GloboidCam, program: MotionProgram, step: float = 0.6,
                   turns: int = 90) -> float:
    """The groove's volume inside the blank (mm³) by brute force: points on a grid of the planes
    through the cam axis; a point is in the groove when, as the cam turns past it, it crosses
    the plane of the roller's axis and the contact normal within the wall's radius of the axis
    and between the tube's top and floor along it (the strip the groove sweeps)."""
    g = blank.follower
    top, floor = blank.tube_span()
    near, far = sorted((top, floor))
    # the meridian grid: (r, z) cells inside the blank and near the groove's band
    r_grid = np.arange(blank.bore + step / 2, g.centre + blank.surface, step)
    half = blank.width / 2.0
    z_grid = np.arange(-half + step / 2, half, step)
    rr, zz = (v.ravel() for v in np.meshgrid(r_grid, z_grid))
    root = np.sqrt(np.maximum(blank.surface ** 2 - zz * zz, 0.0))
    surface_r = g.centre - root if blank.inward > 0 else root - g.centre
    x = g.centre - rr if blank.inward > 0 else g.centre + rr
    d = np.hypot(x, zz)
    keep = (rr <= surface_r) & (d >= near - g.radius - 1.0) & (d <= far + g.radius + 1.0)
    rr, zz = rr[keep], zz[keep]
    window = np.radians(np.arange(-20.0, 20.0001, 0.5))
    total = 0.0
    for phi in np.linspace(0.0, 2 * math.pi, turns, endpoint=False):
        point = np.stack((rr * math.cos(phi), rr * math.sin(phi), zz), axis=-1)
        # the pose whose roller lies in this point's plane, and those around it
        centre = -phi if blank.inward > 0 else math.pi - phi
        theta = g.sigma * centre + window[:, None] + np.zeros(rr.size)
        m = program.evaluate(theta.ravel()).reshape(4, *theta.shape)
        psi = g.rest + m[0]
        frame = to_cam(np.broadcast_to(point, (*theta.shape, 3)), -g.sigma * theta)
        axis = np.stack((-np.cos(psi), np.zeros_like(psi), np.sin(psi)), axis=-1)
        rel = frame - np.array([g.centre, 0.0, 0.0])
        along = np.einsum("...i,...i->...", rel, axis)
        normal = g.normal(along, psi, m[1])
        off = np.einsum("...i,...i->...", rel, np.cross(axis, normal))
        across = np.einsum("...i,...i->...", rel, normal)
        cross = np.signbit(off[:-1]) != np.signbit(off[1:])
        f = np.where(cross, off[:-1] / np.where(cross, off[:-1] - off[1:], 1.0), 0.0)
        u = across[:-1] + f * (across[1:] - across[:-1])
        ell = along[:-1] + f * (along[1:] - along[:-1])
        inside = cross & (np.abs(u) <= g.radius) & (ell >= near) & (ell <= far)
        total += float(np.sum(rr[inside.any(axis=0)])) * step * step
    return total * 2 * math.pi / turns


def test_the_stl_is_the_blank_less_the_groove(globoid) -> None:  # type: ignore[no-untyped-def]
    analysis, data = globoid
    mesh = trimesh.load(trimesh.util.wrap_as_stream(data), file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    assert len(mesh.split(only_watertight=False)) == 1
    blank = analysis.globoid.blank
    removed = _blank_volume(blank) - float(mesh.volume)
    estimate = _groove_volume(blank, analysis.program)
    assert removed == pytest.approx(estimate, rel=0.01)


def _winding(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """The generalised winding number of each point (1 inside a closed outward mesh, 0
    outside): the solid angles of every facet seen from it, summed, over 4π."""
    tri = np.asarray(mesh.triangles)
    out = np.zeros(len(points))
    for i, p in enumerate(points):
        a, b, c = (tri[:, k] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        div = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc
               + np.einsum("ij,ij->i", b, c) * la + np.einsum("ij,ij->i", c, a) * lb)
        out[i] = float(np.sum(np.arctan2(det, div))) * 2.0 / (4.0 * math.pi)
    return out


def test_the_roller_at_its_poses_is_clear_of_the_stl_and_touches_its_flanks(globoid) -> None:  # type: ignore[no-untyped-def]
    """Points on the roller's surface (its own radius, inside the groove's clearance) lie
    outside the solid read back; points 0.05 mm beyond the wall radius along the contact
    normal, where the flank is inside the blank, lie in the material."""
    analysis, data = globoid
    mesh = trimesh.load(trimesh.util.wrap_as_stream(data), file_type="stl")
    blank, program = analysis.globoid.blank, analysis.program
    g = blank.follower
    roller = analysis.design.follower.roller_radius
    clear, solid = [], []
    for theta in np.radians(np.arange(7.0, 360.0, 30.0)):
        m = program.evaluate(np.array([theta]))[:, 0]
        psi = g.rest + m[0]
        axis = np.array([-math.cos(psi), 0.0, math.sin(psi)])
        for ell in blank.contact(5)[1:4]:
            q = g.axis_point(np.asarray(ell), np.asarray(psi))
            n = g.normal(np.asarray(ell), np.asarray(psi), np.asarray(m[1]))
            b = np.cross(axis, n)
            for beta in np.linspace(0.0, 2 * math.pi, 8, endpoint=False):
                clear.append(to_cam(q + roller * (math.cos(beta) * n + math.sin(beta) * b),
                                    g.sigma * theta))
            for side in (1.0, -1.0):
                solid.append(to_cam(q + side * (g.radius + 0.05) * n, g.sigma * theta))
    assert float(np.max(_winding(mesh, np.array(clear)))) < 0.5
    assert float(np.min(_winding(mesh, np.array(solid)))) > 0.5


CONCAVE = (DESIGNS / "demo-globoidal-concave.yaml").read_text()


@pytest.mark.parametrize(("old", "new", "field", "words"), [
    ("  globoid: concave\n", "", "cam.globoid", "required for a globoidal cam"),
    ("  motion: oscillating\n  pivot_distance: 130\n  arm_length: 60\n", "", "follower.motion",
     "drives an oscillating follower"),
    ("  roller_length: 20\n", "", "follower.roller_length", "required for a globoidal"),
    ("globoid: concave", "globoid: convex", "follower.arm_length", "a convex globoid's roller"),
    ("arm_length: 60", "arm_length: 125", "follower.arm_length", "passes the cam axis"),
    ("groove_depth: 14", "groove_depth: 20", "cam.groove_depth", "less than the roller's"),
    ("  bore: 30\n", "  bore: 30\n  width: 60\n", "cam.width", "the groove reaches"),
    ("  bore: 30\n", "  bore: 30\n  outer_radius: 73.6\n", "cam.groove_depth", "sweeps"),
    ("  bore: 30\n", "  bore: 30\n  outer_radius: 131\n", "cam.outer_radius",
     "less than pivot_distance"),
    ("bore: 30", "bore: 120", "cam.bore", "reaches the groove's floor"),
    ("  bore: 30\n", "  bore: 30\n  outer_radius: 10\n", "cam.outer_radius",
     "takes the groove's floor to within"),
    ("  arm_length: 60\n", "  arm_length: 60\n  rest_angle: 50\n", "follower.rest_angle",
     "must stay within"),
])
def test_a_bad_globoid_is_one_located_line(tmp_path: Path, old: str, new: str, field: str,
                                           words: str) -> None:
    assert old in CONCAVE
    path = tmp_path / "bad.yaml"
    path.write_text(CONCAVE.replace(old, new, 1))
    result = run_cli("build", str(path), "-o", "out", cwd=tmp_path)
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output
    assert "bad.yaml:" in lines[0] and field in lines[0] and words in lines[0], lines[0]
    assert not (tmp_path / "out").exists()


def test_the_default_tolerance_is_the_globoids_in_any_unit() -> None:
    design = design_from_text(CONCAVE)
    assert design.manufacturing.tolerance == pytest.approx(0.01)
    given = design_from_text(CONCAVE + "manufacturing: {tolerance: 0.02}\n")
    assert given.manufacturing.tolerance == pytest.approx(0.02)
    inch = CONCAVE.replace("name: demo", "units: in\nname: demo")
    for key in ("groove_depth: 14", "bore: 30", "pivot_distance: 130", "arm_length: 60",
                "roller_radius: 8", "roller_length: 20", "groove_clearance: 0.05"):
        name, value = key.split(": ")
        inch = inch.replace(key, f"{name}: {float(value) / 25.4!r}")
    design = design_from_text(inch)
    assert design.units == "in"
    assert design.manufacturing.tolerance == pytest.approx(0.01)  # mm, inside camfab


def test_a_disc_cam_keeps_the_design_files_default_tolerance() -> None:
    from camfab.design.model import DEFAULT_TOLERANCE_MM

    disc = load_design(DESIGNS / "seed-10-4.yaml")
    assert disc.manufacturing.tolerance == DEFAULT_TOLERANCE_MM


def test_an_undercut_globoid_fails_and_writes_no_stl_nor_step() -> None:
    text = (CONCAVE.replace("pivot_distance: 130", "pivot_distance: 90")
            .replace("arm_length: 60", "arm_length: 50")
            .replace("roller_radius: 8", "roller_radius: 14")
            .replace("roller_length: 20", "roller_length: 30")
            .replace("groove_depth: 14", "groove_depth: 16")
            .replace("rise:   {angle: 150, lift: 40", "rise:   {angle: 60, lift: 60")
            .replace("dwell:  {angle: 30}", "dwell:  {angle: 120}", 1)
            .replace("pressure_angle: 40", "pressure_angle: 85"))
    design = design_from_text(text)
    design = design.model_copy(update={"outputs": ("dxf", "stl", "step")})
    analysis = analyse(design)
    undercut = next(f for f in analysis.findings if f.id == "undercut")
    assert not undercut.ok and undercut.ranges_deg, undercut.message
    artifacts = render(analysis)
    assert f"{design.name}.stl" not in artifacts.files
    assert f"{design.name}.step" not in artifacts.files
    for output in ("stl", "step"):
        assert any(line.startswith(f"{output} (a flank of the groove folds")
                   for line in artifacts.not_produced), artifacts.not_produced
    with pytest.raises(DesignError):
        design_from_text(text.replace("type: roller", "type: flat"))


#: Globoids whose groove meets the blank's surface at grazing angles, where the boolean leaves
#: needles and slivers the ordinary repair did not clear (found by building random designs).
GRAZING = {
    "concave-cw": """name: grazing-concave
cam: {type: globoidal, globoid: concave, rotation: cw, groove_depth: 11.616, bore: 10}
follower: {type: roller, motion: oscillating, pivot_distance: 155.099, arm_length: 57.914,
           roller_radius: 9.363, roller_length: 28.409, groove_clearance: 0.05}
motion:
  - rise: {angle: 144.08, lift: 12.42, law: polynomial-345}
  - dwell: {angle: 35.92}
  - return: {angle: 144.08, law: polynomial-345}
  - dwell: {angle: 35.92}
limits: {pressure_angle: 60}
manufacturing: {tolerance: 0.02}
""",
    "convex-cw": """name: grazing-convex
cam: {type: globoidal, globoid: convex, rotation: cw, groove_depth: 7.313, bore: 10}
follower: {type: roller, motion: oscillating, pivot_distance: 130.740, arm_length: 208.465,
           roller_radius: 3.311, roller_length: 10.172, groove_clearance: 0.05}
motion:
  - rise: {angle: 103.84, lift: 26.57, law: modified-trapezoid}
  - dwell: {angle: 76.16}
  - return: {angle: 103.84, law: modified-trapezoid}
  - dwell: {angle: 76.16}
limits: {pressure_angle: 60}
""",
}


@pytest.mark.parametrize("text", GRAZING.values(), ids=GRAZING.keys())
def test_a_groove_grazing_the_blank_still_makes_a_clean_stl(text: str) -> None:
    analysis = render(analyse(design_from_text(text))).analysis
    assert analysis is not None
    stl = analysis.verification.stl
    assert stl.ok and stl.short_edges == 0 and stl.sliver_faces == 0, stl
    assert analysis.verification.lift.max_mm <= analysis.design.manufacturing.tolerance
