"""camfab writes, reads back and checks its STL files with numpy alone; trimesh, an independent
mesh library, is the reference here: it reads every STL camfab writes to the same faces, closure,
winding and volume, and writes the same bytes for the same mesh. A build that needs neither
imports neither trimesh nor scipy."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from camfab.arrays import clusters
from camfab.export.stl import binary_stl, check_stl, equal_rows, read_stl, stl_bytes

from .conftest import DESIGNS, EVERY_DESIGN, Built


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_trimesh_reads_every_stl_as_camfab_does(every_build: dict[str, Built],
                                                name: str) -> None:
    built = every_build[name]
    for path in built.files(".stl"):
        data = path.read_bytes()
        theirs = trimesh.load(io.BytesIO(data), file_type="stl")
        ours = read_stl(data)
        check = check_stl(data, float(theirs.volume), 1e-9 * abs(float(theirs.volume)))
        assert len(ours.faces) == len(theirs.faces) == check.faces
        assert np.array_equal(ours.vertices, theirs.vertices)
        assert np.array_equal(ours.faces, theirs.faces)
        assert check.watertight == theirs.is_watertight
        assert check.consistent_winding == theirs.is_winding_consistent
        assert check.volume_mm3 == pytest.approx(float(theirs.volume), rel=1e-12)
        assert check.degenerate_faces == int(np.count_nonzero(theirs.area_faces <= 1e-10))


def _trimesh_stl(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """What trimesh writes of a mesh of float32 corners: merged, faces without area dropped."""
    mesh = trimesh.Trimesh(vertices.astype(np.float32), faces, process=False)
    mesh.merge_vertices()
    mesh.update_faces(mesh.nondegenerate_faces(height=0.0))
    mesh.remove_unreferenced_vertices()
    data = mesh.export(file_type="stl")
    assert isinstance(data, bytes)
    return data


def test_the_writer_writes_what_trimesh_writes_of_the_same_solid() -> None:
    """A plate with a bore and a keyway-like notch, as manifold3d builds it: camfab's bytes are
    trimesh's, header, normals, corners and all."""
    import manifold3d

    plate = manifold3d.Manifold.cylinder(6.0, 40.0, circular_segments=400)
    bore = manifold3d.Manifold.cylinder(8.0, 6.0, circular_segments=64).translate((0, 0, -1))
    notch = manifold3d.Manifold.cube((2.0, 3.0, 8.0)).translate((-1.0, 5.0, -1.0))
    solid = plate - bore - notch
    mesh = solid.to_mesh()
    theirs = _trimesh_stl(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts))
    assert binary_stl(solid) == theirs


def test_the_reader_finds_a_hole_and_a_flipped_facet() -> None:
    corners = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    closed = stl_bytes(corners[faces])
    check = check_stl(closed, 1000.0 / 6.0, 1e-9)
    assert check.watertight and check.consistent_winding and check.ok
    assert check.volume_mm3 == pytest.approx(1000.0 / 6.0, rel=1e-12)
    holed = check_stl(stl_bytes(corners[faces[:3]]), 1000.0 / 6.0, 1e-9)
    assert not holed.watertight and not holed.ok
    flipped = faces.copy()
    flipped[3] = flipped[3, ::-1]
    turned = check_stl(stl_bytes(corners[flipped]), 1000.0 / 6.0, 1e-9)
    assert turned.watertight and not turned.consistent_winding and not turned.ok
    for mine, theirs in ((check, faces), (turned, flipped)):
        mesh = trimesh.Trimesh(corners, theirs, process=False)
        assert (mine.watertight, mine.consistent_winding) == (mesh.is_watertight,
                                                              mesh.is_winding_consistent)


def test_the_reader_refuses_a_file_of_the_wrong_length() -> None:
    data = stl_bytes(np.zeros((2, 3, 3)))
    with pytest.raises(ValueError, match="binary STL"):
        read_stl(data[:-1])
    with pytest.raises(ValueError, match="binary STL"):
        read_stl(data[:40])


def test_equal_rows_are_the_groups_numpy_finds() -> None:
    """The groups of equal rows (the STL's corners merged, its edges paired), against numpy's
    unique of rows: narrow and wide integers, one to three columns, repeated rows."""
    def expected(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        order = np.argsort(first)
        rank = np.empty(len(first), dtype=np.intp)
        rank[order] = np.arange(len(first))
        return first[order], rank[inverse.ravel()]

    rng = np.random.default_rng(5)
    cases = []
    for reach in (3, 1000, 10**12, 2**62):
        for columns in (1, 2, 3):
            keys = rng.integers(-reach, reach, size=(500, columns), dtype=np.int64)
            cases.append(keys[rng.integers(0, 500, size=700)])  # each row some twice
    cases.append(np.array([[0, 5], [2**61, -(2**61)], [1, 5], [0, 5], [-(2**61), 3], [1, 5]],
                          dtype=np.int64))
    for keys in cases:
        first, group = equal_rows(keys)
        want_first, want_group = expected(keys)
        assert np.array_equal(first, want_first) and np.array_equal(group, want_group)


def test_clusters_are_the_connected_components() -> None:
    """Against scipy's connected components, on random graphs sparse and dense (the STL's
    sliver repair and the chaining of a DXF's loose pieces use them)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    rng = np.random.default_rng(7)
    for count, edges in ((1, 0), (10, 3), (200, 150), (500, 2000), (1000, 20)):
        pairs = rng.integers(0, count, size=(edges, 2))
        groups, label = clusters(pairs, count)
        graph = coo_matrix((np.ones(edges), (pairs[:, 0], pairs[:, 1])), shape=(count, count))
        expected_groups, expected = connected_components(graph, directed=False)
        assert groups == expected_groups
        # the same partition: a one-to-one map between the two labellings
        assert len(set(zip(label.tolist(), expected.tolist(), strict=True))) == groups
        # numbered alike too (by each cluster's lowest point), as the chaining of loose
        # pieces relies on
        assert np.array_equal(label, expected)


@pytest.mark.parametrize("design", ["seed-10-4", "demo-cylindrical", "demo-groove-roller"])
def test_a_build_imports_neither_trimesh_nor_scipy(tmp_path, design: str) -> None:
    """Both are heavy imports (trimesh through scipy.spatial, half a second); a build of a disc,
    a drum or a groove cam with every output needs neither."""
    code = ("import sys\nfrom camfab.cli import main\ntry:\n    main(sys.argv[1:])\n"
            "except SystemExit:\n    pass\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('trimesh', 'scipy')))")
    run = subprocess.run([sys.executable, "-c", code, "build", str(DESIGNS / f"{design}.yaml"),
                          "-o", str(tmp_path)], capture_output=True, text=True, check=True)
    assert run.stdout.strip().splitlines()[-1] == "[]"
    assert any(tmp_path.glob("*.stl"))
