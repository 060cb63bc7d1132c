"""The synthetic scans of :mod:`tests.scan_synth`: their points lie on the exact flanks (well
under a micrometre, by the scan model's own tangent planes) and on the part's mesh, spread by
area; each error is put where it is asked, by the amount asked; the rigid motion, the files and
the seed do what they say."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camfab.inspect.scan import read_scan
from camfab.inspect.scan_deviation import Others, flank_nodes, point_deviations

from .conftest import DESIGNS
from .scan_synth import cell_areas, part_of, synthetic_scan
from .test_inspect_model_plates import mesh_distance

#: One design of each kind of scan model: two drums (the second's groove folds: camfab makes no
#: solid of it), two globoids, a groove plate, a conjugate pair, a disc cam.
KINDS = ["demo-cylindrical", "demo-drum-steep", "demo-globoidal-convex",
         "demo-globoidal-concave", "demo-groove-roller", "demo-conjugate", "seed-poly-345"]

#: Points of the quick scans here.
POINTS = 50_000

#: How far (mm) a point of the synthetic flanks may lie from the exact flank: bilinear in a
#: cell 0.1° by 0.25 mm, a micrometre (the grids' own bound and the tangent planes' measure
#: are some 0.05 µm and 0.13 µm).
ON_EXACT_MM = 1e-3

#: The gate (mm) of the deviations taken here.
GATE_MM = 1.0


def path(name: str) -> str:
    return str(DESIGNS / f"{name}.yaml")


def deviations(scan, points=None):  # type: ignore[no-untyped-def]
    """camfab's deviations of *scan*'s points (its cam-frame points by default)."""
    nodes = flank_nodes(scan.model)
    return point_deviations(scan.cam_points if points is None else points, nodes,
                            Others(scan.model, nodes), GATE_MM)


@pytest.mark.parametrize("name", KINDS)
def test_a_clean_scan_lies_on_the_exact_flanks_and_the_mesh(name: str) -> None:
    """Without errors: the flanks' points are where the truth says, within a micrometre of the
    exact flank by the scan model's own tangent planes (camfab's deviation) and by the grid's
    bound on bilinear interpolation (its second differences over 8); the other points lie on
    the part's mesh and on no flank; the flank points lie on the mesh within the STL's
    deviation from the exact flanks (a few micrometres: see the CloudCompare test)."""
    scan = synthetic_scan(path(name), points=POINTS, seed=1)
    part = part_of(path(name))
    on = scan.flank >= 0
    assert np.array_equal(scan.points, scan.design_points)  # no error, no motion
    assert np.all(scan.deviation[on] == 0.0) and np.isnan(scan.deviation[~on]).all()
    for f in scan.model.flanks:
        p, n = f.points, f.normals
        rows = np.einsum("...i,...i->...", np.roll(p, -1, 0) - 2 * p + np.roll(p, 1, 0), n)
        cols = np.einsum("...i,...i->...", p[:, 2:] - 2 * p[:, 1:-1] + p[:, :-2], n[:, 1:-1])
        assert (np.abs(rows).max() + np.abs(cols).max()) / 8 < ON_EXACT_MM
    if not len(part.faces):  # (a folded groove: no solid, every point on a flank)
        assert on.all()
        return
    assert np.count_nonzero(on) == round(0.6 * POINTS)
    dev = deviations(scan)
    kept = on & (dev.flank >= 0)  # (a globoid's engine sets a few aside: see the CloudCompare test)
    assert np.count_nonzero(kept) >= 0.999 * np.count_nonzero(on)
    assert np.array_equal(dev.flank[kept], scan.flank[kept])
    assert float(np.abs(dev.deviation[kept]).max()) < ON_EXACT_MM
    tolerance = scan.analysis.design.manufacturing.tolerance
    picked = np.flatnonzero(on)[:150]
    reach = 5 * tolerance
    assert mesh_distance(scan.points[picked], part.vertices, part.faces, reach).max() \
        <= 3 * tolerance
    picked = np.flatnonzero(~on)[:150]
    assert mesh_distance(scan.points[picked], part.vertices, part.faces, reach).max() < 1e-9
    assert (dev.flank[~on] < 0).mean() > 0.95  # (some beside a flank's edge are kept)


def test_points_are_spread_over_the_flanks_by_area() -> None:
    """Each flank gets its share of the points by its area, and along the turn each tenth of a
    turn its share (within four standard deviations of the count)."""
    scan = synthetic_scan(path("demo-groove-roller"), points=POINTS, seed=2)
    areas = [cell_areas(f) for f in scan.model.flanks]
    total = sum(float(a.sum()) for a in areas)
    on = np.count_nonzero(scan.flank >= 0)
    for index, area in enumerate(areas):
        count = np.count_nonzero(scan.flank == index)
        assert abs(count - on * float(area.sum()) / total) <= 1
        mine = scan.flank == index
        counts, _ = np.histogram(scan.cam_angle[mine], bins=10, range=(0, 2 * math.pi))
        per_row = area.sum(axis=1)
        expected = np.add.reduceat(per_row, np.arange(0, per_row.size, per_row.size // 10))
        expected = count * expected / expected.sum()
        assert np.all(np.abs(counts - expected) <= 4 * np.sqrt(expected))


@pytest.mark.parametrize("name", ["demo-cylindrical", "demo-globoidal-concave",
                                  "demo-conjugate"])
def test_a_bump_is_where_and_as_high_as_asked(name: str) -> None:
    """A bump of 0.05 mm and radius 2 mm on flank 1 at 200°, at its column a third of the way
    across: each point of that flank stands out of it by the bump's height at its distance from
    the flank's node there, the highest at that cam angle and across; the other flank is
    untouched; and camfab measures it (within a micrometre of the truth on every point it
    keeps)."""
    model = part_of(path(name)).model
    flank = model.flanks[1]
    row, column = 2000, flank.across.size // 3
    centre = flank.points[row, column]
    scan = synthetic_scan(path(name), points=POINTS, seed=3,
                          bump=(200.0, float(flank.across[column]), 0.05, 2.0, 1))
    on = scan.flank == 1
    d = np.linalg.norm(scan.design_points[on] - centre, axis=1)
    expected = np.where(d < 2.0, 0.025 * (1.0 + np.cos(np.pi * d / 2.0)), 0.0)
    assert np.allclose(scan.surface[on], expected, rtol=0, atol=1e-8)
    assert np.count_nonzero(expected > 0.0) >= 10
    top = int(np.argmax(np.where(on, scan.surface, -np.inf)))
    assert math.degrees(scan.cam_angle[top]) == pytest.approx(200.0, abs=1.0)
    assert scan.across[top] == pytest.approx(flank.across[column], abs=1.0)
    assert np.abs(scan.surface[scan.flank == 0]).max() < 1e-9
    dev = deviations(scan)
    kept = (dev.flank >= 0) & (scan.flank >= 0)
    assert np.abs(dev.deviation[kept] - scan.deviation[kept]).max() < 1e-3


def test_oversize_and_taper_move_the_flanks_into_the_material() -> None:
    """Oversize: −oversize/2 on every flank point; taper: −taper times the share across the
    flank (0 at its first column, −taper at its last); both on top of each other."""
    name = "demo-groove-roller"
    scan = synthetic_scan(path(name), points=POINTS, oversize_mm=0.04, taper_mm=0.03, seed=4)
    on = scan.flank >= 0
    first = np.array([f.across[0] for f in scan.model.flanks])[scan.flank[on]]
    width = np.array([f.across[-1] - f.across[0] for f in scan.model.flanks])[scan.flank[on]]
    share = (scan.across[on] - first) / width
    assert np.allclose(scan.surface[on], -0.02 - 0.03 * share, rtol=0, atol=1e-7)
    assert np.allclose(scan.deviation[on], scan.surface[on], rtol=0, atol=0)
    assert np.array_equal(scan.points[~on], scan.design_points[~on])


def test_a_phase_error_turns_only_the_flanks() -> None:
    """A phase error of 0.2° turns the flanks' points about Z (the rest stays), and the truth is
    each turned point's distance from the design's flank: to first order the turn's
    displacement along the normal, δ (ẑ × p)·n."""
    name = "demo-cylindrical"
    delta = math.radians(0.2)
    scan = synthetic_scan(path(name), points=POINTS, phase_deg=0.2, with_normals=True, seed=5)
    on = scan.flank >= 0
    p, q = scan.design_points[on], scan.points[on]
    c, s = math.cos(delta), math.sin(delta)
    turned = np.column_stack((c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]))
    assert np.allclose(q, turned, rtol=0, atol=1e-9)
    assert np.array_equal(scan.points[~on], scan.design_points[~on])
    # the design normal turned with the point: its displacement along it, to first order
    n = scan.normals[on]
    first_order = delta * np.einsum("ij,ij->i", np.cross([0.0, 0.0, 1.0], p), n)
    inside = np.isfinite(scan.surface[on])
    assert inside.mean() > 0.99  # (past the flank's edge: no foot)
    # the second order: (δr)²/2ρ with ρ the flank's radius of curvature along the turn (at
    # least 10 mm here; the error found is some 0.14 µm)
    shift = delta * float(np.hypot(p[:, 0], p[:, 1]).max())
    assert np.allclose(scan.surface[on][inside], first_order[inside], rtol=0,
                       atol=shift**2 / (2 * 10.0))
    assert np.abs(first_order).max() > 0.05
    dev = deviations(scan)
    kept = (dev.flank >= 0) & on & np.isfinite(scan.deviation)
    assert np.abs(dev.deviation[kept] - scan.deviation[kept]).max() < 1e-3


def test_noise_is_along_the_normals_with_the_deviation_asked() -> None:
    """Noise of 0.01 mm: every point moves along its normal, the flank points' deviation less
    their surface's has mean 0 and standard deviation 0.01 mm (within 3 %)."""
    scan = synthetic_scan(path("seed-poly-345"), points=POINTS, noise_mm=0.01, with_normals=True,
                          seed=6)
    moved = scan.points - scan.design_points
    along = np.einsum("ij,ij->i", moved, scan.normals)
    assert np.allclose(moved, along[:, None] * scan.normals, rtol=0, atol=1e-12)
    assert np.std(along) == pytest.approx(0.01, rel=0.03)
    on = scan.flank >= 0
    noise = scan.deviation[on] - scan.surface[on]
    assert abs(float(noise.mean())) < 3 * 0.01 / math.sqrt(noise.size)
    assert np.std(noise) == pytest.approx(0.01, rel=0.03)
    assert np.allclose(noise, along[on], rtol=0, atol=1e-9)


def test_the_rigid_motion_moves_the_whole_cloud_last() -> None:
    """A whole-part phase and a misplacement: the points are R·p + t of the scan without them
    (the same seed draws the same cloud), R the turn about Z then rx, ry, rz about X, Y, Z; the
    normals turn with them; the truth does not change."""
    name = "demo-globoidal-convex"
    misplace = (2.0, -3.0, 10.0, 5.0, -4.0, 1.5)
    still = synthetic_scan(path(name), points=POINTS, noise_mm=0.005, with_normals=True, seed=7)
    moved = synthetic_scan(path(name), points=POINTS, noise_mm=0.005, with_normals=True, seed=7,
                           whole_phase_deg=30.0, misplace=misplace)

    def turn(axis: int, degrees: float) -> np.ndarray:
        c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
        return r

    rotation = turn(2, 10.0) @ turn(1, -3.0) @ turn(0, 2.0) @ turn(2, 30.0)
    assert np.allclose(moved.rotation, rotation, rtol=0, atol=1e-15)
    assert np.allclose(moved.translation, [5.0, -4.0, 1.5], rtol=0, atol=0)
    assert np.allclose(moved.points, still.points @ rotation.T + moved.translation, rtol=0,
                       atol=1e-12)
    assert np.allclose(moved.normals, still.normals @ rotation.T, rtol=0, atol=1e-12)
    assert np.allclose(moved.cam_points, still.points, rtol=0, atol=1e-12)
    assert np.array_equal(moved.deviation, still.deviation, equal_nan=True)


def test_the_same_seed_gives_the_same_scan() -> None:
    a, b, c = (synthetic_scan(path("demo-conjugate"), points=5_000, noise_mm=0.01, seed=seed)
               for seed in (8, 8, 9))
    assert np.array_equal(a.points, b.points) and np.array_equal(a.flank, b.flank)
    assert not np.array_equal(a.points, c.points)


@pytest.mark.parametrize("suffix", [".csv", ".ply"])
@pytest.mark.parametrize("normals", [False, True])
def test_the_files_read_back_as_the_scan(tmp_path, suffix: str, normals: bool) -> None:  # type: ignore[no-untyped-def]
    """camfab reads the written CSV (to its 1e-7 mm) and binary PLY (exactly) back: the points,
    and the normals when written."""
    scan = synthetic_scan(path("seed-poly-345"), points=2_000, noise_mm=0.01,
                          with_normals=normals, misplace=(1.0, 2.0, 3.0, 4.0, 5.0, 6.0), seed=10)
    read = read_scan(scan.write(tmp_path / f"scan{suffix}"))
    exact = suffix == ".ply"
    assert np.allclose(read.points, scan.points, rtol=0, atol=0 if exact else 6e-8)
    if normals:
        assert read.normals is not None
        assert np.allclose(read.normals, scan.normals, rtol=0, atol=1e-12 if exact else 1e-8)
    else:
        assert read.normals is None
    assert [p.name for p in tmp_path.iterdir()] == [f"scan{suffix}"]
