"""Reading a 3-D scan (:mod:`camfab.inspect.scan`): each format written by numpy or trimesh
reads back the same points, normals and faces; a million-point CSV reads within a few CPU
seconds; each bad file is refused in one line naming it."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh

from camfab.errors import CamfabError, InputFileError, ScanError
from camfab.inspect.scan import MAX_BYTES, MIN_POINTS, read_scan

#: CPU seconds a million points with normals may take to read (some 3 on a slow core).
MILLION_CPU_S = 12.0


@pytest.fixture(scope="module")
def sphere() -> trimesh.Trimesh:
    return trimesh.creation.icosphere(subdivisions=2, radius=20.0)  # 162 vertices


def _cloud(count: int = 500) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(7)
    points = rng.normal(size=(count, 3)) * 30.0
    return points, points / np.linalg.norm(points, axis=1)[:, None]


def _refused(path: Path, *said: str, line: int | None = None) -> str:
    with pytest.raises(CamfabError) as caught:
        read_scan(path)
    text = str(caught.value)
    assert "\n" not in text and text.startswith(str(path)), text
    if line is not None:
        assert text.startswith(f"{path}:{line}:"), text
    for phrase in said:
        assert phrase in text, text
    return text


# -- round trips --------------------------------------------------------------------------------

@pytest.mark.parametrize("separator", [",", ";", " ", "\t"])
def test_csv_round_trip_with_header_and_normals(tmp_path: Path, separator: str) -> None:
    points, normals = _cloud()
    path = tmp_path / "scan.csv"
    np.savetxt(path, np.hstack((normals, points)), fmt="%.9f", delimiter=separator,
               header=separator.join(("nx", "ny", "nz", "X", "Y", "Z")), comments="")
    scan = read_scan(path)
    np.testing.assert_allclose(scan.points, points, atol=1e-8)
    assert scan.normals is not None
    np.testing.assert_allclose(scan.normals, normals, atol=1e-8)
    assert scan.faces is None
    assert scan.source == "500 points with normals from a CSV"
    assert scan.units.startswith("mm")


def test_csv_without_header_in_inches(tmp_path: Path) -> None:
    points, _ = _cloud()
    path = tmp_path / "scan.txt"
    np.savetxt(path, points, fmt="%.9f", header="a comment line")  # '# a comment line'
    path.write_text(path.read_text() + "\n\n# the end\n")
    scan = read_scan(path, units="in")
    np.testing.assert_allclose(scan.points, points * 25.4, atol=1e-6)
    assert scan.normals is None and scan.units == "in (--units)"


def test_csv_decimal_comma_with_semicolons(tmp_path: Path) -> None:
    points, _ = _cloud()
    path = tmp_path / "scan.csv"
    rows = [";".join(f"{v:.6f}".replace(".", ",") for v in row) for row in points]
    path.write_text("\n".join(rows) + "\n")
    np.testing.assert_allclose(read_scan(path).points, points, atol=1e-6)


@pytest.mark.parametrize("encoding", ["ascii", "binary"])
def test_ply_mesh_round_trip(tmp_path: Path, sphere: trimesh.Trimesh, encoding: str) -> None:
    path = tmp_path / "scan.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(sphere, encoding=encoding))
    scan = read_scan(path)
    np.testing.assert_allclose(scan.points, sphere.vertices, atol=1e-5)
    assert scan.faces is not None
    np.testing.assert_array_equal(scan.faces, sphere.faces)
    assert "320 triangles" in scan.source


@pytest.mark.parametrize("order", ["<", ">"])
def test_binary_ply_cloud_with_normals(tmp_path: Path, order: str) -> None:
    points, normals = _cloud()
    body = np.empty(len(points), dtype=[(n, order + "f8") for n in ("x", "y", "z")]
                    + [("intensity", order + "u2")] + [(n, order + "f4")
                                                       for n in ("nx", "ny", "nz")])
    for k, n in enumerate(("x", "y", "z")):
        body[n] = points[:, k]
    for k, n in enumerate(("nx", "ny", "nz")):
        body[n] = normals[:, k]
    body["intensity"] = 7
    kind = "binary_little_endian" if order == "<" else "binary_big_endian"
    header = (f"ply\nformat {kind} 1.0\ncomment made by a test\nelement vertex {len(points)}\n"
              "property double x\nproperty double y\nproperty double z\nproperty ushort "
              "intensity\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n")
    path = tmp_path / "cloud.ply"
    path.write_bytes(header.encode() + body.tobytes())
    scan = read_scan(path)
    np.testing.assert_array_equal(scan.points, points)
    assert scan.normals is not None and scan.faces is None
    np.testing.assert_allclose(scan.normals, normals, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(scan.normals, axis=1), 1.0, atol=1e-12)
    assert scan.source == "500 points with normals from a binary PLY"


@pytest.mark.parametrize("ascii_stl", [False, True])
def test_stl_round_trip(tmp_path: Path, sphere: trimesh.Trimesh, ascii_stl: bool) -> None:
    path = tmp_path / "scan.stl"
    if ascii_stl:
        path.write_text(trimesh.exchange.stl.export_stl_ascii(sphere))
    else:
        path.write_bytes(trimesh.exchange.stl.export_stl(sphere))
    scan = read_scan(path)
    assert scan.faces is not None and len(scan.faces) == len(sphere.faces)
    assert len(scan.points) == len(sphere.vertices)
    np.testing.assert_allclose(scan.points[scan.faces], sphere.triangles, atol=1e-5)


def test_million_point_csv_within_cpu_budget(tmp_path: Path) -> None:
    points, normals = _cloud(1000)
    block = "".join(f"{p[0]:.6f},{p[1]:.6f},{p[2]:.6f},{n[0]:.6f},{n[1]:.6f},{n[2]:.6f}\n"
                    for p, n in zip(points, normals, strict=True))
    path = tmp_path / "million.csv"
    path.write_text("x,y,z,nx,ny,nz\n" + block * 1000)
    started = time.process_time()
    scan = read_scan(path)
    spent = time.process_time() - started
    assert spent < MILLION_CPU_S, f"{spent:.1f} s CPU for a million points"
    assert scan.points.shape == (1_000_000, 3)
    np.testing.assert_allclose(scan.points[-1000:], points, atol=1e-6)


# -- refusals -----------------------------------------------------------------------------------

def test_fifo_refused(tmp_path: Path) -> None:
    path = tmp_path / "pipe.csv"
    os.mkfifo(path)
    with pytest.raises(InputFileError, match="FIFO"):
        read_scan(path)


def test_too_large_refused(tmp_path: Path) -> None:
    path = tmp_path / "huge.csv"
    with open(path, "wb") as stream:
        stream.truncate(MAX_BYTES + 1)  # sparse: no disk used
    _refused(path, f"{MAX_BYTES:,}")


def _csv(tmp_path: Path, rows: np.ndarray, edit: dict[int, str] | None = None) -> Path:
    lines = [",".join(f"{v:.6f}" for v in row) for row in rows]
    for index, text in (edit or {}).items():
        lines[index] = text
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_csv_refusals(tmp_path: Path) -> None:
    points, normals = _cloud()
    both = np.hstack((points, normals))
    _refused(_csv(tmp_path, points, {9: "1,2"}), "2 values", "have 3", line=10)
    _refused(_csv(tmp_path, points, {4: "1,nan,3"}), "not a finite number", line=5)
    _refused(_csv(tmp_path, points, {6: "1,2,abc"}), "'abc' is not a number", line=7)
    _refused(_csv(tmp_path, points[: MIN_POINTS - 1]), f"at least {MIN_POINTS}")
    _refused(_csv(tmp_path, points[:, :2]), "2 values", line=1)
    _refused(_csv(tmp_path, both, {11: "1,2,3,0,0,0"}), "is zero", "unit vector", line=12)
    _refused(_csv(tmp_path, both, {2: "1,2,3,0,0,0.9"}), "0.9 long", line=3)
    path = tmp_path / "bad.csv"
    path.write_text("x,y,q\n1,2,3\n")
    _refused(path, "header", line=1)
    path.write_bytes(b"x,y,z\n1,2,\xff\n")
    _refused(path, "not a text file", line=2)


def test_normals_nearly_unit_are_made_unit(tmp_path: Path) -> None:
    points, normals = _cloud()
    scan = read_scan(_csv(tmp_path, np.hstack((points, normals * (1 + 5e-4)))))
    assert scan.normals is not None
    np.testing.assert_allclose(np.linalg.norm(scan.normals, axis=1), 1.0, atol=1e-12)


def test_ply_refusals(tmp_path: Path, sphere: trimesh.Trimesh) -> None:
    path = tmp_path / "bad.ply"
    data = trimesh.exchange.ply.export_ply(sphere, encoding="binary")
    path.write_bytes(data[:-5])
    _refused(path, "PLY header says")
    path.write_bytes(data + b"\0" * 8)
    _refused(path, "PLY header says")
    path.write_bytes(data.replace(b"element vertex 162", b"element vertex 9000000"))
    _refused(path, "PLY header says")
    path.write_bytes(data.replace(b"element vertex 162", b"element vertex 90000000"))
    _refused(path, "at most 20,000,000")
    path.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 1\nend_header\n")
    _refused(path, "no x, y and z")
    path.write_bytes(b"solid x\n")
    _refused(path, "not a PLY file")
    text = trimesh.exchange.ply.export_ply(sphere, encoding="ascii")
    header, _, _ = text.partition(b"end_header\n")
    lines = header.count(b"\n") + 2  # the body's first line
    face = f"\n3 {' '.join(map(str, sphere.faces[0]))}\n".encode()
    path.write_bytes(text.replace(face, b"\n3 0 11 999\n", 1))
    _refused(path, "face 1 names vertex 0, 11, 999", "0 to 161")
    path.write_bytes(text.replace(face, b"\n4 0 11 5 6\n", 1))
    _refused(path, "5 values in a row", line=lines + 162)
    vertex = text.split(b"end_header\n")[1].split(b"\n")[3]
    vertex = b"\n" + vertex + b"\n"  # the whole line (one vertex's text ends another's)
    path.write_bytes(text.replace(vertex, b"\n1 2 inf\n", 1))
    _refused(path, "finite")
    path.write_bytes(text.replace(vertex, b"\n1 2\n", 1))
    _refused(path, "2 values", line=lines + 3)
    path.write_bytes(text + b"1 2 3\n")
    _refused(path, "more lines than its header says")


def test_stl_refusals(tmp_path: Path, sphere: trimesh.Trimesh) -> None:
    path = tmp_path / "bad.stl"
    data = trimesh.exchange.stl.export_stl(sphere)
    path.write_bytes(data[:-1])
    _refused(path, "not an STL file")
    corners = np.frombuffer(data, dtype=np.float32, count=3, offset=84 + 12).copy()
    path.write_bytes(data.replace(corners.tobytes(), np.array([np.nan, 0, 0], "<f4").tobytes()))
    _refused(path, "not a finite number")
    text = trimesh.exchange.stl.export_stl_ascii(sphere)
    path.write_text(text.replace("vertex", "vertex abc", 1))
    _refused(path, "not three numbers")
    tiny = trimesh.creation.box()
    path.write_bytes(trimesh.exchange.stl.export_stl(tiny))
    _refused(path, f"at least {MIN_POINTS}")


def test_far_points_and_unknown_unit(tmp_path: Path) -> None:
    points, _ = _cloud()
    path = _csv(tmp_path, points, {0: "1e9,0,0"})
    _refused(path, "from the origin")
    with pytest.raises(ScanError, match="unknown unit"):
        read_scan(path, units="furlong")
