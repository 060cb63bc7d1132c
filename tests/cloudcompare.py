"""CloudCompare as an independent consumer of camfab's meshes: its cloud-to-mesh distance (C2M),
signed, from each point of a cloud to a triangle mesh (an STL file read by CloudCompare itself),
in the cloud's units (millimetres here).

Debian's ``cloudcompare`` package (2.11.3 in bookworm; ``.ci/run`` installs it) runs without a
display on Qt's ``offscreen`` platform. :func:`c2m_distances` writes the cloud to
``WORKDIR/cloud.xyz`` (x y z a line) and runs, in *workdir*::

    QT_QPA_PLATFORM=offscreen CloudCompare -SILENT -NO_TIMESTAMP -AUTO_SAVE OFF \\
        -O cloud.xyz -O MESH.stl -C2M_DIST \\
        -C_EXPORT_FMT ASC -PREC 12 -ADD_HEADER -SAVE_CLOUDS

then reads ``WORKDIR/cloud_C2M_DIST.asc``: a header ``//X Y Z C2M_signed_distances`` and one
line per point, in the cloud's order, with the point as CloudCompare holds it (float32) and its
distance. HOME, XDG_CONFIG_HOME and XDG_RUNTIME_DIR point into *workdir*, so neither the user's
saved settings nor a GUI session's change what it computes, and it writes nothing outside.

What 2.11.3 does, and how this harness deals with it:

- The distance is signed by default (there is no ``-UNSIGNED`` flag before 2.12;
  ``-FLIP_NORMS`` would flip it): its sign is the side of the closest triangle's plane,
  ``(P - A)·(AB × AC)``, from the order of the triangle's vertices (the facet normal an STL file
  stores is not read), so with triangles wound counter-clockwise seen from outside (as camfab
  writes them) a point outside the solid is +, inside −. A closer triangle replaces the one
  found only when it is closer in float32, so where two are equally close within float32 the
  first found decides the sign. Outside a face, beside its edge with another face and within
  about ``sqrt(d · ulp32(d))`` (~3.5e-4·d) of that face's plane on its inner side, a point's
  distance ``d`` to both is the same in float32, and that other plane may give it −: its
  magnitude is right, its sign is not. For a deviation of 0.1 mm that slab is some 3.5e-5 mm
  thick; at 0.7 mm some 2e-4 mm (the box test meets it).
- ``-SPLIT_XYZ`` is C2C-only (C2M warns and ignores it). Without ``-OCTREE_LEVEL`` the level is
  chosen from approximate distances computed first, and printed (``Octree level (auto): N``),
  which this harness reads; a level given by hand can be much slower.
- Points and distances are float32: a coordinate of 100 mm is held to ~8e-6 mm.
- A flat triangle lying exactly on a plane of the octree grid with its normal pointing along
  the axis is left out of every cell, and points near it get the distance to some other
  triangle (fixed upstream in CCCoreLib in October 2021, after 2.11.3). The grid is the cube,
  1 % larger than and centred on the box holding the cloud and the mesh, cut in 2^N cells per
  side: a face of an axis-aligned mesh at the middle of that box falls on it. So the cloud is
  sent with two guard points of its own (:func:`_guard_points`: outside the cloud's and the
  mesh's boxes, by odd fractions of their size, which make the box CloudCompare sees a generic
  one), their distances dropped; and after the run, the flat faces of the mesh are checked
  against the grid at the level CloudCompare used, a new pair of guards being tried when one
  lies on it.
- Coordinates past 1e4 make CloudCompare shift the cloud (its global shift): refused here.
- Points are neither reordered nor dropped; the harness checks that the coordinates it reads
  back are the ones it sent, in order.

The run is bounded in CPU time (``RLIMIT_CPU``, through :func:`tests.limited_child.run_limited`)
with a wall-clock backstop many times longer.
"""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np

from .conftest import tool
from .limited_child import run_limited

#: CloudCompare's program, as Debian installs it.
PROGRAM = "CloudCompare"
#: Past this absolute coordinate CloudCompare 2.11.3 shifts the cloud (its global shift).
MAX_COORDINATE = 1.0e4
#: The guard points: below the minimum and above the maximum of the box holding the cloud and
#: the mesh by these fractions of its largest side, per axis (x, y, z), times an attempt's scale.
GUARD_BELOW = np.array([0.0371, 0.0437, 0.0529])
GUARD_ABOVE = np.array([0.0613, 0.0283, 0.0719])
ATTEMPT_SCALES = (1.0, 1.37, 1.71)
#: CloudCompare 2.11.3 makes the box cubic and 1 % larger before building its octree.
CUBE_ENLARGE = 1.01
#: The address space CloudCompare may map (bytes): Qt, its plugins and a thread pool.
ADDRESS_SPACE = 16 * 1024**3

_LEVEL = re.compile(r"Octree level \(auto\): (\d+)")


class CloudCompareError(RuntimeError):
    """CloudCompare did not give a distance for every point."""


def cloudcompare_available() -> bool:
    """Whether CloudCompare is installed (``apt-get install cloudcompare``)."""
    return shutil.which(PROGRAM) is not None


def need_cloudcompare() -> None:
    """Skip the test without CloudCompare (fail it when CI requires the consumers)."""
    if not cloudcompare_available():
        tool(PROGRAM, "cloudcompare")


def c2m_distances(points: np.ndarray, mesh_stl: Path, workdir: Path,
                  cpu_s: float = 600.0, wall_s: float | None = None) -> np.ndarray:
    """CloudCompare's signed distance (mm) from each of *points* (N, 3; mm) to the mesh of
    *mesh_stl*, in the points' order: + outside the solid, − inside (triangles wound outward).
    Files go in *workdir* (created when missing). At most *cpu_s* CPU seconds a run, killed
    after *wall_s* wall-clock seconds (default ten times *cpu_s*). The command line and what is
    done about 2.11.3's quirks are in this module's docstring."""
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0:
        raise ValueError(f"points must be an (N, 3) array with N >= 1, not {points.shape}")
    if not np.isfinite(points).all():
        raise ValueError("points must be finite")
    mesh_stl = Path(mesh_stl).resolve()
    triangles = _triangles(mesh_stl)
    # the farthest guard points bound every coordinate sent
    if np.abs(_guard_points(points, triangles, max(ATTEMPT_SCALES))).max() >= MAX_COORDINATE:
        raise ValueError(f"coordinates must stay below {MAX_COORDINATE:g} mm with room around "
                         "(CloudCompare shifts larger ones)")
    path = shutil.which(PROGRAM)
    if path is None:
        raise CloudCompareError(f"{PROGRAM} is not installed (apt-get install cloudcompare)")
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    for scale in ATTEMPT_SCALES:
        cloud = np.vstack([points, _guard_points(points, triangles, scale)])
        distances, level = _run(path, cloud, mesh_stl, workdir, cpu_s,
                                10.0 * cpu_s if wall_s is None else wall_s)
        low = np.minimum(cloud.min(axis=0), triangles.reshape(-1, 3).min(axis=0))
        high = np.maximum(cloud.max(axis=0), triangles.reshape(-1, 3).max(axis=0))
        if not faces_on_grid_planes(triangles, low, high, level):
            return distances[:len(points)]
    on_grid = faces_on_grid_planes(triangles, low, high, level)
    raise CloudCompareError(f"flat faces of {mesh_stl.name} lie on CloudCompare's octree grid "
                            f"whatever the guard points: {on_grid}")


def _triangles(mesh_stl: Path) -> np.ndarray:
    """The triangles (F, 3, 3) of the STL file as stored (float32 values), read by trimesh."""
    import trimesh

    mesh = trimesh.load_mesh(mesh_stl, file_type="stl", process=False)
    triangles = np.asarray(mesh.triangles, dtype=np.float32).astype(float)
    if len(triangles) == 0:
        raise CloudCompareError(f"{mesh_stl.name} holds no triangle")
    return triangles


def _guard_points(points: np.ndarray, triangles: np.ndarray, scale: float) -> np.ndarray:
    """Two points (2, 3) outside the box holding *points* and *triangles*, below its minimum
    and above its maximum by :data:`GUARD_BELOW` and :data:`GUARD_ABOVE` (times *scale*) of its
    largest side: the box CloudCompare builds its octree in is then theirs."""
    corners = np.vstack([points, triangles.reshape(-1, 3)])
    low, high = corners.min(axis=0), corners.max(axis=0)
    size = max(float(np.max(high - low)), 1.0)
    return np.array([low - scale * GUARD_BELOW * size, high + scale * GUARD_ABOVE * size])


def faces_on_grid_planes(triangles: np.ndarray, low: np.ndarray, high: np.ndarray,
                         level: int) -> list[str]:
    """The planes (``"x = 1"``) of the axis-aligned flat triangles among *triangles* (F, 3, 3)
    that lie, within a few float32 steps, on a plane of the octree grid CloudCompare 2.11.3
    builds at *level* over the box *low*–*high* (the cloud's and the mesh's): the triangles its
    C2M may leave out. The grid is computed as CloudCompare does, in float32."""
    low32, high32 = np.asarray(low, np.float32), np.asarray(high, np.float32)
    side = np.float32(float(np.max(high32 - low32)) * CUBE_ENLARGE)
    cube_min = ((high32 + low32) - side) * np.float32(0.5)
    cell = float(side) / 2**level
    reach = float(np.max(np.abs(np.concatenate([cube_min, cube_min + side]))))
    tolerance = 8.0 * float(np.spacing(np.float32(reach)))
    found = []
    for k, axis in enumerate("xyz"):
        values = triangles[:, :, k]
        planes = np.unique(values[np.ptp(values, axis=1) <= tolerance])
        offset = (planes - float(cube_min[k])) / cell
        on_grid = np.abs(offset - np.round(offset)) * cell <= tolerance
        found += [f"{axis} = {plane:.9g}" for plane in planes[on_grid]]
    return found


def _run(program: str, cloud: np.ndarray, mesh_stl: Path, workdir: Path, cpu_s: float,
         wall_s: float) -> tuple[np.ndarray, int]:
    """One CloudCompare run: the signed distance of each point of *cloud* (N, 3) to the mesh,
    and the octree level it used."""
    cloud_path = workdir / "cloud.xyz"
    result_path = workdir / "cloud_C2M_DIST.asc"
    result_path.unlink(missing_ok=True)
    np.savetxt(cloud_path, cloud, fmt="%.17g")
    command = [program, "-SILENT", "-NO_TIMESTAMP", "-AUTO_SAVE", "OFF",
               "-O", cloud_path.name, "-O", str(mesh_stl), "-C2M_DIST",
               "-C_EXPORT_FMT", "ASC", "-PREC", "12", "-ADD_HEADER", "-SAVE_CLOUDS"]
    run = run_limited(command, cpu_s=cpu_s, wall_s=wall_s, address_space=ADDRESS_SPACE,
                      cwd=workdir, env=_environment(workdir))
    said = (run.stdout + run.stderr).strip()
    if run.code != 0 or not result_path.is_file():
        raise CloudCompareError(f"{' '.join(command)} failed ({run.describe()}); it said: "
                                f"{said[-2000:]}")
    level = _LEVEL.search(run.stdout)
    if level is None:
        raise CloudCompareError(f"CloudCompare did not say its octree level: {said[-2000:]}")
    return _read_result(result_path, cloud), int(level.group(1))


def _environment(workdir: Path) -> dict[str, str]:
    """CloudCompare's environment: Qt's offscreen platform (no display needed) and a home of
    its own in *workdir* for the settings it reads and writes."""
    home = workdir / "cloudcompare-home"
    home.mkdir(mode=0o700, exist_ok=True)
    env = dict(os.environ)
    env.update(QT_QPA_PLATFORM="offscreen", HOME=str(home),
               XDG_CONFIG_HOME=str(home / ".config"), XDG_DATA_HOME=str(home / ".local/share"),
               XDG_RUNTIME_DIR=str(home))
    return env


def _read_result(path: Path, cloud: np.ndarray) -> np.ndarray:
    """The distances of CloudCompare's ASCII cloud *path*, checked to hold *cloud*'s points in
    order (as float32) and one finite signed distance each."""
    with path.open() as stream:
        header = stream.readline().split()
    if header != ["//X", "Y", "Z", "C2M_signed_distances"]:
        raise CloudCompareError(f"{path.name}: unexpected columns {header}")
    table = np.loadtxt(path, comments="//", ndmin=2)
    if table.shape != (len(cloud), 4):
        raise CloudCompareError(f"{path.name}: {table.shape[0]} rows of {table.shape[1]} "
                                f"columns for {len(cloud)} points")
    sent = cloud.astype(np.float32).astype(float)
    moved = np.abs(table[:, :3] - sent).max()
    if moved > 1e-9 * max(1.0, float(np.abs(sent).max())):
        raise CloudCompareError(f"{path.name}: points not read back as sent (off by {moved:g})")
    distances = table[:, 3]
    if not np.isfinite(distances).all():
        raise CloudCompareError(f"{path.name}: {int((~np.isfinite(distances)).sum())} points "
                                "without a distance")
    return distances
