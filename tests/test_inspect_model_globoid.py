"""A globoidal cam's scan model: its walls lie on the STL camfab builds with their normals into
the groove, the gauge roller run over a perfect part gives the design's swing, and over a wall
moved into the groove by h a swing tighter by h / (ℓ cos α) (by hand)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from camfab.errors import InspectionError
from camfab.inspect.models.globoid import GloboidScan, scan_model
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGNS

GLOBOIDS = sorted(DESIGNS.glob("demo-globoidal-*.yaml"))
#: The rows' step here (rad): coarser than an inspection's, for quick tests.
STEP = math.radians(0.5)


@pytest.fixture(scope="module", params=GLOBOIDS, ids=[p.stem for p in GLOBOIDS])
def built(request: pytest.FixtureRequest) -> tuple[GloboidScan, bytes]:
    """The scan model of a demo globoid, and the bytes of the STL its build writes."""
    path: Path = request.param
    artifacts = render(analyse(load_design(path)))
    assert artifacts.analysis is not None
    return scan_model(artifacts.analysis, STEP), artifacts.files[f"{path.stem}.stl"]


def test_the_walls_are_sampled_as_the_scan_contract_asks(built: tuple[GloboidScan, bytes]) -> None:
    model, _ = built
    blank = model.blank
    assert np.allclose(model.theta, STEP * np.arange(720), rtol=0, atol=1e-15)
    assert np.allclose(model.map_u, np.degrees(model.theta))
    assert (model.q_unit, model.map_u_label) == ("rad", "cam angle (°)")
    assert [f.side for f in model.flanks] == [-1, 1]
    for flank in model.flanks:
        rows, columns, _ = flank.points.shape
        assert rows == model.theta.size and columns >= 9
        assert flank.normals.shape == flank.points.shape
        # columns from the floor outward, at most 0.25 mm apart along the roller
        assert np.all(np.diff(flank.across) > 0) and np.max(np.diff(flank.across)) <= 0.25
        assert flank.across[0] == pytest.approx(abs(blank.floor - blank.roller_inner))
        # each column's distance from the pivot: from the roller's inner end to the blank
        ell = blank.floor - blank.inward * flank.across
        assert ell[0] == pytest.approx(blank.roller_inner)
        assert abs(ell[-1] - blank.surface) < 1.0  # (where the walls leave the blank)
        # mm per radian: the middle of the roller's stretch, its middle column, from the pivot
        assert model.q_scale == pytest.approx(ell[columns // 2])


#: Facets of a mesh whose corners lie within this of their centre (mm) are found by their centre.
SMALL_FACET_MM = 2.0


def _closest(triangles: np.ndarray, points: np.ndarray, reach: float) -> tuple[np.ndarray,
                                                                            np.ndarray]:
    """Each point's distance (mm) from the nearest of the *triangles* within *reach* (mm) of it
    (inf where none is), and that facet's unit normal by its winding: every facet that can be
    that near (a small one by its centre, a large one by its box), measured exactly (trimesh's
    closest point)."""
    centres = triangles.mean(axis=1)
    size = np.linalg.norm(triangles - centres[:, None], axis=2).max(axis=1)
    small, large = np.flatnonzero(size <= SMALL_FACET_MM), np.flatnonzero(size > SMALL_FACET_MM)
    tree = cKDTree(centres[small])
    low, high = triangles[large].min(axis=1) - reach, triangles[large].max(axis=1) + reach
    distance, normal = np.full(len(points), np.inf), np.zeros((len(points), 3))
    for i, p in enumerate(points):
        near = np.concatenate((small[tree.query_ball_point(p, SMALL_FACET_MM + reach)],
                               large[np.all((low <= p) & (p <= high), axis=1)])).astype(np.intp)
        if near.size == 0:
            continue
        closest = trimesh.triangles.closest_point(triangles[near], np.tile(p, (near.size, 1)))
        gaps = np.linalg.norm(closest - p, axis=1)
        best = triangles[near[np.argmin(gaps)]]
        distance[i] = float(gaps.min())
        normal[i] = np.cross(best[1] - best[0], best[2] - best[0])
    return distance, normal / np.linalg.norm(normal, axis=1)[:, None]


def test_the_walls_lie_on_the_built_stl_with_their_normals_into_the_groove(
        built: tuple[GloboidScan, bytes]) -> None:
    """Nodes of each wall stand within the tolerance of the STL the build writes (read by
    trimesh), and away from the blank's surface their normals are the nearest facet's outward
    normal: out of the material, into the groove."""
    model, stl = built
    mesh = trimesh.load(trimesh.util.wrap_as_stream(stl), file_type="stl")
    triangles = np.asarray(mesh.triangles, dtype=np.float64)
    tolerance = model.analysis.design.manufacturing.tolerance
    rng = np.random.default_rng(3)
    for flank in model.flanks:
        rows = rng.integers(0, model.theta.size, 1000)
        columns = rng.integers(0, flank.across.size, 1000)
        distance, facet = _closest(triangles, flank.points[rows, columns], tolerance)
        assert float(np.max(distance)) <= tolerance
        inside = columns < flank.across.size - 3  # (the last columns meet the blank's surface)
        normals = flank.normals[rows, columns]
        assert np.allclose(np.linalg.norm(normals, axis=-1), 1.0, rtol=0, atol=1e-12)
        assert float(np.min(np.einsum("ij,ij->i", normals, facet)[inside])) > 0.99


def test_the_normals_are_the_walls_surface_normals(built: tuple[GloboidScan, bytes]) -> None:
    """Each normal is square to the wall's tangents along the roller and along the cam angle
    (central differences over the grid)."""
    model, _ = built
    for flank in model.flanks:
        p, n = flank.points, flank.normals
        along = p[:, 2:] - p[:, :-2]
        turning = np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)
        for tangent, normal in ((along, n[:, 1:-1]), (turning, n)):
            unit = tangent / np.linalg.norm(tangent, axis=-1)[..., None]
            assert float(np.max(np.abs(np.einsum("...i,...i->...", unit, normal)))) < 1e-4


def test_a_perfect_part_runs_the_design_with_the_designs_play(
        built: tuple[GloboidScan, bytes]) -> None:
    """Over the walls as designed each run is the design's swing (to 1e-6 mm at q_scale),
    unbounded only where the roller reaches no scanned row, and the play left the roller is
    the groove's clearance, 0.05 mm at q_scale."""
    model, _ = built
    design = model.design()
    lower, upper = (model.run(f, f.points) for f in model.flanks)
    for run in (lower, upper):
        assert np.isfinite(run).all()
        assert float(np.max(np.abs(run - design))) * model.q_scale <= 1e-6
    # rows with nothing scanned: no bound where the roller reaches none but them, and near
    # them only the neighbours' looser bounds (the lower wall's: below the design's)
    w = model.window
    holed = model.flanks[0].points.copy()
    holed[300:310 + 2 * w] = np.nan
    run = model.run(model.flanks[0], holed)
    assert np.isnan(run[300 + w:310 + w]).all()
    apart = np.r_[0:300 - w, 310 + 3 * w:model.theta.size]
    assert np.allclose(run[apart], design[apart], rtol=0, atol=1e-12)
    assert np.all(np.isnan(run) | (run <= design + 1e-12))
    assert model.clearance == pytest.approx(0.05 / model.q_scale)
    backlash = model.clearance + upper - lower
    assert np.allclose(backlash * model.q_scale, 0.05, rtol=0, atol=1e-6)


def _cos_alpha(model: GloboidScan, ell: np.ndarray) -> np.ndarray:
    """cos α along the roller at *ell* (mm from the pivot; (C,)) at each row ((R, C)), by hand:
    the contact normal (C − ℓ cos ψ, ψ′ℓ, ...) against the swing, tan α = |ψ′|ℓ / |C − ℓ cos ψ|."""
    g = model.blank.follower
    psi, dpsi = model.design()[:, None], model.motion[1][:, None]
    reach = g.centre - ell[None, :] * np.cos(psi)
    return np.abs(reach) / np.hypot(reach, dpsi * ell[None, :])


@pytest.mark.parametrize("width", ["middle column", "whole width"])
def test_a_wall_moved_into_the_groove_tightens_its_bound_by_h_over_cos_alpha(
        built: tuple[GloboidScan, bytes], width: str) -> None:
    """A patch of a wall moved h along its normals, over the rows of the rise: at rows whose
    window lies in the patch, the swing bound moves toward the other wall by h / (ℓ cos α)
    (the arm must turn that much further for the roller to stand h further off); far from the
    patch it is the design's. Its middle column is q_scale from the pivot, so there it is
    h / cos(φ) / q_scale with φ the model's pressure angle."""
    model, _ = built
    h = 0.02
    first, last = 60, 240  # rows: 30° to 120°, in the rise
    g = model.blank.follower
    for flank in model.flanks:
        columns = flank.across.size
        middle = columns // 2
        # (the whole width but its end columns: the first is at the roller's end, off which a
        # point moved to its side may fall as the arm turns)
        patch = slice(middle, middle + 1) if width == "middle column" else slice(1, columns - 1)
        moved = flank.points.copy()
        moved[first:last, patch] += h * flank.normals[first:last, patch]
        error = model.run(flank, moved) - model.design()
        # the columns' distances from the pivot along the roller
        ell = model.blank.floor - model.blank.inward * flank.across
        # in the roller's section: the point R − h from its axis at α from the swing's
        # direction is back at R once the axis has moved x = √(R² − (R − h)² sin²α) −
        # (R − h) cos α (= h / cos α to first order), the arm x / ℓ
        c = _cos_alpha(model, ell[patch])
        r = g.radius
        moves = (np.sqrt(r * r - (r - h) ** 2 * (1 - c * c)) - (r - h) * c) / ell[None, patch]
        expected = moves.max(axis=1)
        inside = np.arange(first + model.window, last - model.window)
        assert np.allclose(-flank.side * error[inside], expected[inside], rtol=1e-4, atol=0)
        far = np.r_[0:first - model.window - 1, last + model.window + 1:model.theta.size]
        assert float(np.max(np.abs(error[far]))) <= 1e-12
        if width == "middle column":
            phi = model.pressure_angle(model.design(), model.motion[1])
            # to first order: the next term is h·tan²α / 2R of it, under h / R
            first_order = h / np.cos(phi[inside]) / model.q_scale
            assert np.allclose(-flank.side * error[inside], first_order, rtol=h / g.radius,
                               atol=0)


def test_the_reference_mesh_is_the_built_stl(built: tuple[GloboidScan, bytes]) -> None:
    """The reference mesh is the solid the build writes as its STL, facet for facet."""
    model, stl = built
    vertices, faces = model.reference_mesh()
    mesh = trimesh.load(trimesh.util.wrap_as_stream(stl), file_type="stl")
    ours = vertices[faces].reshape(-1, 9)
    theirs = np.asarray(mesh.triangles, dtype=np.float64).reshape(-1, 9)
    ours, theirs = (rows[np.lexsort(rows.T[::-1])] for rows in (ours, theirs))
    assert ours.shape == theirs.shape
    assert np.allclose(ours, theirs, rtol=0, atol=1e-6)


def test_a_folded_groove_has_no_reference_mesh() -> None:
    """A groove whose flanks fold has no solid (the build withholds its STL): its model says so
    in one line instead of giving a mesh."""
    text = ((DESIGNS / "demo-globoidal-concave.yaml").read_text()  # 60° of swing in 30°
            .replace("rise:   {angle: 150, lift: 40", "rise:   {angle: 30, lift: 60")
            .replace("dwell:  {angle: 30}", "dwell:  {angle: 150}", 1)
            .replace("pressure_angle: 40", "pressure_angle: 89"))
    model = scan_model(analyse(design_from_text(text, file="folded.yaml")), STEP)
    with pytest.raises(InspectionError, match=r"^folded\.yaml: .*folds") as caught:
        model.reference_mesh()
    assert "\n" not in str(caught.value)
