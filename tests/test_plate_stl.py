"""Plates whose STL once failed the build's own read-back with sliver facets: an outline
sampled within a fine tolerance has every three neighbouring points within a few tenths of a
micrometre of a line, and the caps manifold3d triangulated by clipping ears held needles. Each
test writes a small plate's STL and reads it back with trimesh (an independent reader): closed,
outward, of the volume the shoelace formula gives, and no facet thinner than the rule allows."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from camfab.export.mesh_quality import MIN_ALTITUDE_MM, MIN_EDGE_MM
from camfab.export.part import Extrusion, Union
from camfab.export.stl import render_stl
from camfab.pipeline import build


def dense_outline(count: int, bump: float = 6.0) -> np.ndarray:
    """A cam-like outline (mm) about the origin, r = 45 + bump·(1 − cos θ)/2 at *count* points:
    at 4000 points its chords are some 0.07 mm and three neighbours lie within 5e-5 mm of a
    line, as the outline of a plate at a tolerance of 1e-4 mm."""
    theta = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    r = 45.0 + bump * (1.0 - np.cos(theta)) / 2.0
    return np.column_stack((r * np.cos(theta), r * np.sin(theta)))


def shoelace(chain: np.ndarray) -> float:
    """The area (mm²) of a closed chain, counter-clockwise positive."""
    x, y = chain[:, 0], chain[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def assert_clean(data: bytes, volume: float) -> None:
    """The STL read back by trimesh: closed, wound alike, of *volume* (mm³) to 1e-6, no edge
    shorter than the rule's and no facet thinner than its (brute force over every facet)."""
    import io

    import trimesh

    mesh = trimesh.load(io.BytesIO(data), file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(volume, rel=1e-6)
    corners = mesh.vertices[mesh.faces]
    edges = np.linalg.norm(np.roll(corners, -1, axis=1) - corners, axis=2)
    twice_area = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                         corners[:, 2] - corners[:, 0]), axis=1)
    assert edges.min() >= MIN_EDGE_MM
    assert (twice_area / edges.max(axis=1)).min() >= MIN_ALTITUDE_MM


def test_every_three_neighbours_of_the_dense_outline_lie_near_a_line() -> None:
    """The premise of the tests below: an ear of the outline would be a needle."""
    ring = dense_outline(4000)
    before, after = np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0)
    chord = after - before
    height = np.abs(np.cross(np.column_stack((chord, np.zeros(len(ring)))),
                             np.column_stack((ring - before, np.zeros(len(ring)))))[:, 2])
    assert (height / np.hypot(*chord.T)).max() < MIN_ALTITUDE_MM


@pytest.mark.parametrize("bore", [0.0, 12.0])
def test_a_finely_sampled_plate_has_no_needle_on_its_caps(bore: float) -> None:
    """Without a bore (the caps fanned from the centre) and with one (zipped to it)."""
    outline = dense_outline(4000)
    chains = (outline,)
    area = shoelace(outline)
    if bore:
        hole = dense_outline(700, 0.0)[::-1] * (bore / 45.0)
        chains = (outline, hole)
        area += shoelace(hole)
    stl = render_stl(Extrusion(chains, 7.0))
    assert_clean(stl.data, area * 7.0)


def test_a_conjugate_stack_of_two_finely_sampled_plates_is_clean() -> None:
    """Two plates face to face (a conjugate pair printed as one part), outlines crossing."""
    a, b = dense_outline(4000), dense_outline(4000)[:, ::-1] * [1.0, -1.0]
    b = np.column_stack((-b[:, 1], b[:, 0]))  # turned a quarter
    stl = render_stl(Union((Extrusion((a,), 7.0, 0.0), Extrusion((b,), 7.0, 7.0))))
    assert_clean(stl.data, (shoelace(a) + abs(shoelace(b))) * 7.0)


REPRODUCERS = {
    # a conjugate pair on an oscillating arm at a tolerance of 2e-4 mm: three needle facets on
    # plate a's cap (at 1e-4 mm, two)
    "conjugate": {
        "name": "fine-pair",
        "cam": {"type": "conjugate", "speed_rpm": 90, "base_radius": 45.0, "thickness": 7},
        "follower": {"type": "roller", "motion": "oscillating", "roller_radius": 4.5,
                     "pivot_distance": 118, "arm_length": 124, "pivot_side": "left",
                     "arm_angle": 57},
        "motion": [{"rise": {"angle": 115.0, "lift": 10.0, "law": "modified-trapezoid"}},
                   {"return": {"angle": 100.0, "law": "harmonic"}},
                   {"dwell": {"angle": 145.0}}],
        "manufacturing": {"tolerance": 0.0002},
    },
    # a groove that folds over itself (not buildable): its STL must still be clean
    "groove": {
        "name": "folding-groove", "units": "mm",
        "cam": {"type": "groove", "speed_rpm": 70, "base_radius": 35.0, "thickness": 18,
                "groove_depth": 16.0},
        "follower": {"type": "roller", "motion": "translating", "roller_radius": 8.5,
                     "groove_clearance": 0.02, "offset": -2.5},
        "motion": [{"rise": {"angle": 60.0, "lift": 4.0, "law": "double-harmonic"}},
                   {"rise": {"angle": 65.0, "lift": 8.5, "law": "uniform-velocity"}},
                   {"return": {"angle": 135.0, "law": "double-harmonic"}},
                   {"dwell": {"angle": 100.0}}],
        "manufacturing": {"kerf": 0.25},
    },
}


@pytest.mark.parametrize("kind", sorted(REPRODUCERS))
def test_the_build_reads_its_plate_stl_back_clean(tmp_path: Path, kind: str) -> None:
    design = REPRODUCERS[kind]
    source = tmp_path / "design.yaml"
    source.write_text(yaml.safe_dump(design))
    build(source, tmp_path / "out")
    report = json.loads((tmp_path / "out" / f"{design['name']}-report.json").read_text())
    check = next(c for c in report["checks"] if c["id"] == "verification")
    assert "the STL reads back closed, outward, no degenerate face, short edge or sliver" in (
        check["message"]), check["message"]
    assert check["ok"] is (None if kind == "groove" else True), check["message"]


def test_a_region_a_ray_from_the_centre_meets_twice_is_extruded_as_before() -> None:
    """A C-shaped outline whose opening holds the centre (a ray from it meets the outline
    twice, or not at all): no fan or strip of it, and manifold3d's extrusion of it is closed
    and of its shoelace volume."""
    from camfab.export.plate_mesh import extruded_mesh

    c_shape = np.array([[10.0, -10.0], [10.0, -6.0], [-6.0, -6.0], [-6.0, 6.0], [10.0, 6.0],
                        [10.0, 10.0], [-10.0, 10.0], [-10.0, -10.0]])
    assert extruded_mesh((c_shape,), 5.0, 1e-4) is None
    stl = render_stl(Extrusion((c_shape,), 5.0))
    assert_clean(stl.data, abs(shoelace(c_shape)) * 5.0)
