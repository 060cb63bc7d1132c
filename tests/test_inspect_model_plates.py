"""The scan models of plate cams (disc, shaped, groove, conjugate pair): their flanks lie on the
STL camfab builds, their normals point out of it, the follower run over the exact grid is the
design's motion, a patch of a flank moved out by h moves the follower by h / cos φ there (φ from
the textbook's closed form), and a part as designed has the design's play.

The STL is measured with this file's own geometry: the distance of a point from the nearest
facet, and the winding number of the closed surface about a point (1 inside, 0 outside)."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest

from camfab.errors import InspectionError
from camfab.inspect.models import groove, pair, plate
from camfab.inspect.surface import FlankGrid
from camfab.pipeline import analyse, design_from_mapping, load_design
from tests.conftest import DESIGNS

#: The rows' step in these tests (rad): coarser than the 0.1° the inspection uses, the same
#: geometry.
STEP = math.radians(0.5)

#: kind's module, design: a translating roller, an oscillating roller, an oscillating flat face,
#: a translating knife (disc cams), a tangent cam (shaped), a groove for each follower motion,
#: a conjugate pair for each.
CASES = {"demo-table": plate, "seed-10-3-oscillating": plate, "demo-oscillating-flat": plate,
         "demo-cnc-cutter": plate, "demo-tangent-roller": plate, "demo-groove-roller": groove,
         "demo-groove-oscillating": groove, "demo-conjugate": pair,
         "demo-conjugate-oscillating": pair}


@cache
def built(name: str, step: float = STEP) -> tuple[object, plate.PlateScan]:
    """The example design *name*'s analysis and scan model."""
    analysis = analyse(load_design(DESIGNS / f"{name}.yaml"))
    return analysis, CASES[name].scan_model(analysis, step)


def mesh_distance(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray,
                  reach: float) -> np.ndarray:
    """The distance (mm) of each of (N, 3) *points* from the nearest facet of a mesh, for
    points within *reach* (mm) of it (inf beyond): the facets whose box, grown by *reach*,
    holds the point, each measured exactly (to its plane where the foot falls inside it, else
    to its nearest edge)."""
    tri = vertices[faces]
    low, high = tri.min(axis=1) - reach, tri.max(axis=1) + reach
    inside = np.all((points[:, None, :] >= low[None]) & (points[:, None, :] <= high[None]),
                    axis=2)
    which, facet = np.nonzero(inside)
    p, (a, b, c) = points[which], (tri[facet, k] for k in range(3))
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    height = np.einsum("ij,ij->i", p - a, normal)
    foot = p - height[:, None] * normal
    signs = [np.einsum("ij,ij->i", np.cross(v - u, foot - u), normal)
             for u, v in ((a, b), (b, c), (c, a))]
    within = np.all(np.stack(signs) >= 0.0, axis=0)
    edge = np.full(len(p), np.inf)
    for u, v in ((a, b), (b, c), (c, a)):
        d = v - u
        t = np.clip(np.einsum("ij,ij->i", p - u, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
        edge = np.minimum(edge, np.linalg.norm(p - (u + t[:, None] * d), axis=1))
    each = np.where(within, np.abs(height), edge)
    best = np.full(len(points), np.inf)
    np.minimum.at(best, which, each)
    return best


def winding(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The winding number of a closed, outward mesh about each of (N, 3) *points*: the solid
    angles of its facets seen from the point, summed, over 4π (van Oosterom and Strackee)."""
    out = []
    for p in points:
        a, b, c = (vertices[faces[:, k]] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        div = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc
               + np.einsum("ij,ij->i", b, c) * la + np.einsum("ij,ij->i", c, a) * lb)
        out.append(2.0 * np.arctan2(det, div).sum() / (4.0 * math.pi))
    return np.array(out)


@pytest.mark.parametrize("name", CASES)
def test_flank_points_lie_on_the_built_stl(name: str) -> None:
    """Every 9th row of each flank, at its first, middle and last column, lies on the STL's
    surface within the design's tolerance."""
    analysis, model = built(name)
    vertices, faces = model.reference_mesh()
    tolerance = analysis.design.manufacturing.tolerance
    for flank in model.flanks:
        columns = [0, flank.points.shape[1] // 2, -1]
        points = flank.points[::9][:, columns].reshape(-1, 3)
        distance = mesh_distance(points, vertices, faces, 4 * tolerance)
        assert distance.max() <= tolerance, (flank.name, distance.max())


@pytest.mark.parametrize("name", CASES)
def test_normals_are_unit_and_point_out_of_the_part(name: str) -> None:
    """A flank's normals are unit and horizontal; 0.05 mm along one from a point of the middle
    column is outside the STL's solid, 0.05 mm against it inside."""
    _, model = built(name)
    vertices, faces = model.reference_mesh()
    for flank in model.flanks:
        assert np.allclose(np.linalg.norm(flank.normals, axis=2), 1.0, atol=1e-12)
        assert np.all(flank.normals[..., 2] == 0.0)
        middle = flank.points.shape[1] // 2
        points, normals = flank.points[::24, middle], flank.normals[::24, middle]
        assert np.allclose(winding(points + 0.05 * normals, vertices, faces), 0.0, atol=1e-6)
        assert np.allclose(winding(points - 0.05 * normals, vertices, faces), 1.0, atol=1e-6)


@pytest.mark.parametrize("name", CASES)
def test_the_grid_is_the_contracts(name: str) -> None:
    """Rows evenly over the turn, the maps' u their cam angles in degrees, at least 9 columns
    at most 0.25 mm apart through the plate (a groove's depth), q in mm or rad."""
    analysis, model = built(name)
    rows = round(2 * math.pi / STEP)
    assert np.allclose(model.theta, np.arange(rows) * (2 * math.pi / rows), atol=1e-12)
    assert np.allclose(model.map_u, np.degrees(model.theta))
    assert model.map_u_label == "cam angle (°)"
    fol = analysis.design.follower
    assert model.q_unit == ("rad" if fol.oscillating else "mm")
    assert model.q_scale == (fol.arm_length if fol.oscillating else 1.0)
    for flank in model.flanks:
        assert flank.points.shape[0] == rows
        assert flank.points.shape[1] >= 9 and np.diff(flank.across).max() <= 0.25 + 1e-12
        assert flank.across[0] == 0.0
    sides = {flank.name: flank.side for flank in model.flanks}
    assert sides in ({"profile": -1}, {"inner wall": -1, "outer wall": 1},
                     {"plate a": -1, "plate b": 1})


@pytest.mark.parametrize("name", CASES)
def test_the_run_over_the_exact_grid_is_the_design(name: str) -> None:
    """Every flank's run over its own exact grid is the design's q (what the follower
    simulation gives: the rest position plus the lift) to 1e-6 mm at the trace point."""
    analysis, model = built(name)
    cam = analysis.geometry.cam
    q = model.design()
    assert np.allclose(q, cam.rest + analysis.program.evaluate(model.theta)[0], atol=1e-12)
    for flank in model.flanks:
        run = model.run(flank, flank.points)
        assert np.abs(run - q).max() * model.q_scale < 1e-6, flank.name


def test_the_design_is_what_the_follower_simulation_gives() -> None:
    """q is the simulation's coordinate: the follower run over the disc cam's outline as
    built (within its tolerance) is the model's design."""
    from camfab.geometry.simulate import simulate

    for name in ("demo-table", "seed-10-3-oscillating", "demo-oscillating-flat"):
        analysis, model = built(name)
        geom = analysis.geometry
        ran = simulate(geom.profile, geom.cam.follower, model.theta, geom.cam.sigma)
        tolerance = analysis.design.manufacturing.tolerance
        assert np.abs(ran - model.design()).max() * model.q_scale < tolerance


def test_both_plates_of_a_pair_give_the_same_q() -> None:
    """Cam b's own follower coordinate at the design, subtracted from the spacing, is cam a's:
    the pair holds the follower exactly, and its play on the exact grid is 0."""
    for name in ("demo-conjugate", "demo-conjugate-oscillating"):
        analysis, model = built(name)
        partner = analysis.partner
        own_b = partner.geometry.cam.rest + partner.program.evaluate(model.theta)[0]
        assert np.abs(partner.spacing - own_b - model.design()).max() * model.q_scale < 1e-9
        a, b = (model.run(flank, flank.points) for flank in model.flanks)
        assert model.clearance == 0.0
        assert np.abs(model.clearance + b - a).max() * model.q_scale < 1e-6


def test_a_perfect_groove_has_the_design_clearance() -> None:
    """The gauge roller fills the groove: on the exact walls the play is the design's groove
    clearance (mm, or over the arm's length in rad)."""
    for name, clearance in (("demo-groove-roller", 0.1), ("demo-groove-oscillating", 0.05 / 60)):
        _, model = built(name)
        inner, outer = (model.run(flank, flank.points) for flank in model.flanks)
        assert model.clearance == pytest.approx(clearance, rel=1e-12)
        backlash = model.clearance + outer - inner
        assert np.abs(backlash - clearance).max() * model.q_scale < 1e-6


def translating_pressure_angle(analysis: object, theta: np.ndarray) -> np.ndarray:
    """The textbook's pressure angle of a translating roller, atan((σs′ − e)/(d + s)) with
    d = √(Rp² − e²) (rad)."""
    design = analysis.design
    e, rp = design.follower.offset, design.cam.base_radius + design.follower.roller_radius
    s, ds = analysis.program.evaluate(theta)[:2]
    return np.arctan((design.cam.sigma * ds - e) / (math.sqrt(rp * rp - e * e) + s))


def moved_patch(model: plate.PlateScan, flank: FlankGrid, low_deg: float, high_deg: float,
                h: float) -> tuple[np.ndarray, np.ndarray]:
    """The run over *flank* with the rows from *low_deg* to *high_deg* moved *h* mm out along
    their normals (every column), less the design (mm at the trace point), and the rows of the
    patch further than the run's window from its ends."""
    rows = np.flatnonzero((model.map_u >= low_deg) & (model.map_u <= high_deg))
    points = flank.points.copy()
    points[rows] += h * flank.normals[rows]
    error = (model.run(flank, points) - model.design()) * model.q_scale
    window = model.riders[flank.name].window
    return error, rows[window:-window]


@pytest.mark.parametrize("name, flank_index", [("demo-table", 0), ("demo-groove-roller", 0),
                                                ("demo-groove-roller", 1),
                                                ("demo-conjugate", 1)])
def test_a_patch_moved_out_lifts_a_translating_roller_by_h_over_cos_phi(
        name: str, flank_index: int) -> None:
    """h = 0.01 mm of material left on a flank over 20°–80° moves the follower h / cos φ
    (toward −q on a flank of side +1) at the rows the roller meets only the patch on, φ the
    pressure angle of the flank's own roller (cam b's for plate b), from the closed form; the
    run outside the patch's reach stays the design."""
    analysis, model = built(name)
    flank = model.flanks[flank_index]
    h = 0.01
    error, inside = moved_patch(model, flank, 20.0, 80.0, h)
    if flank.name == "plate b":  # roller b, on the line x = −e: its own cam's angle
        partner = analysis.partner
        motion = partner.program.evaluate(model.theta)
        phi = partner.geometry.cam.pressure_angle(model.theta, motion)
    else:
        phi = translating_pressure_angle(analysis, model.theta)
    assert np.degrees(np.abs(phi[inside])).max() > 10.0  # the patch is on a rise
    expected = -flank.side * h / np.cos(phi[inside])
    assert np.abs(error[inside] - expected).max() < 2e-3 * h
    window = model.riders[flank.name].window
    far = (model.map_u < 20.0 - 3 * window * math.degrees(STEP)) | (model.map_u > 100.0)
    assert np.abs(error[far]).max() < 1e-9


def test_a_patch_moved_out_swings_an_oscillating_roller_by_h_over_cos_phi() -> None:
    """The same on an oscillating roller: the arm turns (h / cos φ) / L, φ the pressure angle
    of the cam (its formula checked by the build's tests)."""
    analysis, model = built("seed-10-3-oscillating")
    h = 0.01
    error, inside = moved_patch(model, model.flanks[0], 10.0, 70.0, h)
    cam = analysis.geometry.cam
    phi = cam.pressure_angle(model.theta, analysis.program.evaluate(model.theta))
    assert np.degrees(np.abs(phi[inside])).max() > 30.0
    assert np.abs(error[inside] - h / np.cos(phi[inside])).max() < 1e-3 * h


def test_the_pressure_angle_is_the_motions() -> None:
    """pressure_angle(q, q′) is the textbook's for a translating roller, and for a pair the
    larger of the two rollers' in size."""
    analysis, model = built("demo-table")
    ds = analysis.program.evaluate(model.theta)[1]
    assert np.allclose(model.pressure_angle(model.design(), ds),
                       translating_pressure_angle(analysis, model.theta), atol=1e-12)
    analysis, model = built("demo-conjugate")
    motion = analysis.program.evaluate(model.theta)
    phi = model.pressure_angle(model.design(), motion[1])
    partner = analysis.partner
    phi_b = partner.geometry.cam.pressure_angle(model.theta,
                                                partner.program.evaluate(model.theta))
    worst = np.maximum(np.abs(translating_pressure_angle(analysis, model.theta)), np.abs(phi_b))
    assert np.allclose(np.abs(phi), worst, atol=1e-12)


def test_unscanned_nodes_are_skipped() -> None:
    """Nodes without points (NaN) bound nothing: with half the columns missing the run is still
    the design; where every node of a stretch of rows longer than the window is missing, the
    run is NaN in its middle, below the design (the roller sinks onto the nodes beside the
    stretch) at its ends, and the design at every row with its own nodes."""
    _, model = built("demo-table")
    flank = model.flanks[0]
    points = flank.points.copy()
    points[:, ::2] = np.nan
    assert np.abs(model.run(flank, points) - model.design()).max() < 1e-6
    window = model.riders["profile"].window
    gap = np.zeros(len(model.theta), dtype=bool)
    gap[100:100 + 4 * window] = True
    points[gap] = np.nan
    error = model.run(flank, points) - model.design()
    assert np.isnan(error[100 + window + 1:100 + 3 * window - 1]).all()
    assert np.abs(error[~gap]).max() < 1e-6
    assert np.nanmax(error[gap]) < 1e-6


def test_a_knife_runs_over_the_chords_between_nodes() -> None:
    """A knife has no width: it touches the chords between a column's nodes, so a patch moved
    out by h lifts it h / cos φ as well (φ of a translating knife, atan((σs′ − e)/(Rb + s)))."""
    analysis, model = built("demo-cnc-cutter")
    h = 0.01
    error, inside = moved_patch(model, model.flanks[0], 20.0, 80.0, h)
    design = analysis.design
    s, ds = analysis.program.evaluate(model.theta)[:2]
    e, rb = design.follower.offset, design.cam.base_radius
    phi = np.arctan((design.cam.sigma * ds - e) / (math.sqrt(rb * rb - e * e) + s))
    assert np.degrees(np.abs(phi[inside])).max() > 10.0
    assert np.abs(error[inside] - h / np.cos(phi[inside])).max() < 5e-3 * h


def test_a_plate_without_thickness_is_refused() -> None:
    """A scan is held to the plate's solid: a design without ``cam.thickness`` has none."""
    import yaml

    data = yaml.safe_load((DESIGNS / "demo-table.yaml").read_text(encoding="utf-8"))
    del data["cam"]["thickness"]
    analysis = analyse(design_from_mapping(data, "table.yaml"))
    with pytest.raises(InspectionError, match="thickness"):
        plate.scan_model(analysis, STEP)
