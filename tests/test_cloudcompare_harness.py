"""The CloudCompare harness (:mod:`tests.cloudcompare`) gives the exact signed distance from
points to meshes whose distances are known: a unit cube (the sign convention), a box off the
origin (any point, edges and corners too, against the box's distance function), a many-sided
prism like a cam's flank, and the cube with a face on the middle of CloudCompare's octree box,
where 2.11.3 alone gets it wrong."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from .cloudcompare import c2m_distances, faces_on_grid_planes, need_cloudcompare

trimesh = pytest.importorskip("trimesh")

#: How close CloudCompare's distance must be to the exact one (mm).
TOLERANCE = 1e-4
#: CPU seconds a run of CloudCompare may take here (each takes well under one).
CPU_S = 60.0


def write_stl(mesh: trimesh.Trimesh, path: Path) -> Path:
    """*mesh* as a binary STL file at *path*, its triangles wound outward (checked)."""
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    path.write_bytes(mesh.export(file_type="stl"))
    return path


def box_mesh(low: np.ndarray, high: np.ndarray, subdivisions: int = 0) -> trimesh.Trimesh:
    """The box *low*–*high*, each triangle split in four *subdivisions* times (still flat)."""
    mesh = trimesh.creation.box(bounds=np.array([low, high], dtype=float))
    for _ in range(subdivisions):
        mesh = mesh.subdivide()
    return mesh


def box_signed_distance(points: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """The exact signed distance from *points* (N, 3) to the surface of the box *low*–*high*:
    + outside, − inside."""
    centre, half = (low + high) / 2, (high - low) / 2
    q = np.abs(points - centre) - half
    return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)


def box_sign_ties(points: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Which *points* (N, 3) outside the box *low*–*high* are as far, in float32, from a face
    whose plane they are on the inner side of as from the box: CloudCompare may give them
    either sign (see :mod:`tests.cloudcompare`)."""
    centre, half = (low + high) / 2, (high - low) / 2
    q = np.abs(points - centre) - half
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    to_face = np.sqrt(outside[:, None] ** 2 + np.minimum(q, 0.0) ** 2)
    step = np.spacing(outside.astype(np.float32)).astype(float)
    tie = (q < 0) & (to_face - outside[:, None] <= 2 * step[:, None])
    return (outside > 0) & tie.any(axis=1)


def test_a_point_outside_a_face_is_positive_inside_negative(tmp_path: Path) -> None:
    need_cloudcompare()
    stl = write_stl(box_mesh(np.zeros(3), np.ones(3)), tmp_path / "cube.stl")
    centres, normals = [], []
    for axis in range(3):
        for side in (0.0, 1.0):
            centre = np.full(3, 0.5)
            centre[axis] = side
            normal = np.zeros(3)
            normal[axis] = 1.0 if side else -1.0
            centres.append(centre)
            normals.append(normal)
    centres_, normals_ = np.array(centres), np.array(normals)
    points = np.vstack([centres_ + 0.1 * normals_, centres_ - 0.1 * normals_])
    distances = c2m_distances(points, stl, tmp_path / "work", cpu_s=CPU_S)
    expected = np.r_[np.full(6, 0.1), np.full(6, -0.1)]
    np.testing.assert_allclose(distances, expected, rtol=0, atol=TOLERANCE)


def test_distances_to_a_box_are_exact_anywhere_around_it(tmp_path: Path) -> None:
    need_cloudcompare()
    low, high = np.array([-0.43, -3.7, 0.0]), np.array([6.87, 0.41, 2.9])
    stl = write_stl(box_mesh(low, high, subdivisions=3), tmp_path / "box.stl")
    # the box as the STL file holds it (float32)
    low, high = low.astype(np.float32).astype(float), high.astype(np.float32).astype(float)
    rng = np.random.default_rng(7)
    points = rng.uniform(low - 1.5, high + 1.5, size=(3000, 3))
    distances = c2m_distances(points, stl, tmp_path / "work", cpu_s=CPU_S)
    expected = box_signed_distance(points, low, high)
    assert (expected > 0).sum() > 500 and (expected < 0).sum() > 500
    np.testing.assert_allclose(np.abs(distances), np.abs(expected), rtol=0, atol=TOLERANCE)
    # the sign too, but where another face is as close in float32 (a handful of points)
    sure = ~box_sign_ties(points, low, high)
    assert sure.sum() > 0.99 * len(points)
    np.testing.assert_allclose(distances[sure], expected[sure], rtol=0, atol=TOLERANCE)


def test_distances_along_the_normals_of_a_many_sided_prism(tmp_path: Path) -> None:
    """A 360-sided prism, like a cam's flank: points on the normal of a side triangle through
    its centroid, and above or below a cap, at known signed offsets."""
    need_cloudcompare()
    mesh = trimesh.creation.cylinder(radius=25.0, height=8.0, sections=360)
    stl = write_stl(mesh, tmp_path / "prism.stl")
    rng = np.random.default_rng(11)
    side = np.flatnonzero(np.abs(mesh.face_normals[:, 2]) < 1e-9)
    faces = rng.choice(side, 1500)
    offsets = rng.uniform(-1.0, 1.0, len(faces) + 500)
    flank = (mesh.triangles_center[faces]
             + offsets[:len(faces), None] * mesh.face_normals[faces])
    angle, radius = rng.uniform(0, 2 * np.pi, 500), rng.uniform(0, 20.0, 500)
    cap = np.sign(rng.uniform(-1, 1, 500)) * 4.0
    caps = np.c_[radius * np.cos(angle), radius * np.sin(angle),
                 cap + np.sign(cap) * offsets[len(faces):]]
    distances = c2m_distances(np.vstack([flank, caps]), stl, tmp_path / "work", cpu_s=CPU_S)
    np.testing.assert_allclose(distances, offsets, rtol=0, atol=TOLERANCE)


def test_a_face_on_the_middle_of_the_octree_box_is_not_lost(tmp_path: Path) -> None:
    """With a cloud reaching from the cube to (2, 2, 2), the box CloudCompare builds its octree
    in is centred on the plane x = 1 of the cube's +x face; 2.11.3 leaves that face out and
    gives the point 0.1 outside it -0.51 (the distance to another face's edge)."""
    need_cloudcompare()
    stl = write_stl(box_mesh(np.zeros(3), np.ones(3)), tmp_path / "cube.stl")
    points = np.array([[1.1, 0.5, 0.5], [2.0, 2.0, 2.0], [0.5, 1.1, 0.5], [0.5, 0.5, 1.1],
                       [0.9, 0.5, 0.5]])
    distances = c2m_distances(points, stl, tmp_path / "work", cpu_s=CPU_S)
    expected = [0.1, np.sqrt(3.0), 0.1, 0.1, -0.1]
    np.testing.assert_allclose(distances, expected, rtol=0, atol=TOLERANCE)


def test_flat_faces_on_the_octree_grid_are_found() -> None:
    """The check behind the guard points: the unit cube's faces at 1 lie on the middle of the
    octree box of the cube and (2, 2, 2), at every level; moved off, none does."""
    triangles = box_mesh(np.zeros(3), np.ones(3)).triangles
    for level in (1, 6, 10):
        assert faces_on_grid_planes(triangles, np.zeros(3), np.full(3, 2.0), level) == [
            "x = 1", "y = 1", "z = 1"]
        assert faces_on_grid_planes(triangles, np.full(3, -0.0371),
                                    np.array([2.0613, 2.0283, 2.0719]), level) == []


def test_bad_points_are_refused(tmp_path: Path) -> None:
    stl = write_stl(box_mesh(np.zeros(3), np.ones(3)), tmp_path / "cube.stl")
    for points in (np.zeros((4, 2)), np.zeros((0, 3)), np.array([[0.0, np.nan, 0.0]])):
        with pytest.raises(ValueError):
            c2m_distances(points, stl, tmp_path / "work")
    with pytest.raises(ValueError, match="below"):
        c2m_distances(np.array([[2e4, 0.0, 0.0]]), stl, tmp_path / "work")
