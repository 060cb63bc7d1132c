"""The studio's 3-D scene (``camfab.serve.scene``, the kinds' ``scene``): for one design of every
cam kind and follower, the STL camfab writes is read with trimesh and placed by the scene's part
transform, and the follower placed by its own: at several frames a roller (or a mushroom's face)
lies one radius (with half a groove's clearance) from the walls of the placed mesh, neither
floating nor sunk; a flat face's plane touches the mesh and nothing of it crosses the face; a
knife's edge lies on it. The transforms are rigid, the frames are the report animation's, and
the JSON stays small and quick to make. Then ``static/view3d.js`` is driven in Debian's
Chromium: it loads a disc's scene and STL, shows frames without a script error, and draws the
cam (or, without WebGL, says so)."""

from __future__ import annotations

import functools
import http.server
import io
import json
import re
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from camfab.export.figures import frame_angles
from camfab.kinds import kind_of
from camfab.pipeline import analyse, load_design, render, verify_exports
from camfab.serve.scene import scene_json

from .conftest import DESIGNS, chromium, page_wait

trimesh = pytest.importorskip("trimesh")

#: One design of every cam kind and of every follower of a plate cam.
KINDS = ["seed-10-4", "seed-10-3-oscillating", "demo-oscillating-flat", "demo-inch-flat",
         "demo-mushroom-cw", "demo-oscillating-knife", "demo-cylindrical",
         "demo-globoidal-convex", "demo-groove-roller", "demo-conjugate",
         "demo-conjugate-oscillating", "demo-linear-roller", "seed-7-10-circular-arc",
         "demo-tangent-roller", "demo-constant-breadth"]

#: The frames at which the follower is held to the mesh (of 360).
FRAMES = (0, 47, 100, 181, 233, 300)

#: How far (in the design's manufacturing tolerance) a contact may stray from the mesh: the
#: mesh's chords lie within the tolerance of the exact surface, and the JSON's rounding adds
#: some 0.1 µm.
SLACK = 4.0

#: Facets whose normal is within this cosine of square to a roller's axis are its walls (a
#: plate's faces, a groove's floor, a blank's surface stand square to it).
WALL_COSINE = 0.5


@dataclass(frozen=True)
class Built:
    """A design built in process: its verified analysis, its STL files, their meshes (mm) and
    its scene."""

    analysis: Any
    stl: dict[str, bytes]
    meshes: list[Any]
    scene: dict[str, Any]


@functools.cache
def built(name: str) -> Built:
    analysis, exports = verify_exports(analyse(load_design(DESIGNS / f"{name}.yaml")), ("stl",))
    stl = exports.files["stl"]
    meshes = [trimesh.load(io.BytesIO(data), file_type="stl") for data in stl.values()]
    return Built(analysis, stl, meshes, scene_json(analysis, list(stl)))


def _matrix(numbers: list[float]) -> np.ndarray:
    return np.asarray(numbers, dtype=np.float64).reshape(4, 4)


def _inverse(matrix: np.ndarray) -> np.ndarray:
    """The inverse of a rigid transform."""
    out = np.eye(4)
    out[:3, :3] = matrix[:3, :3].T
    out[:3, 3] = -matrix[:3, :3].T @ matrix[:3, 3]
    return out


def _placed(scene: dict[str, Any], shape: dict[str, Any], frame: int) -> np.ndarray:
    """The shape's frame in the part's own frame (the STL's coordinates) at *frame*."""
    part = _matrix(scene["parts"][0]["matrices"][frame])
    follower = _matrix(scene["follower"]["matrices"][frame])
    return _inverse(part) @ follower @ _matrix(shape["matrix"])


def _distance(mesh: Any, point: np.ndarray, axis: np.ndarray, half: float) -> float:
    """The distance (mm) from *point* to the mesh's walls along a roller of *axis* (unit) at
    *point* — the facets square to the axis within *half* (mm) of it along the axis —
    negative when the point lies inside the material (behind the nearest facet)."""
    centres = mesh.triangles_center
    along = (centres - point) @ axis
    walls = (np.abs(mesh.face_normals @ axis) < WALL_COSINE) & (np.abs(along) <= half)
    triangles = mesh.triangles[walls]
    closest = trimesh.triangles.closest_point(triangles, np.tile(point, (len(triangles), 1)))
    distances = np.linalg.norm(closest - point, axis=1)
    nearest = int(np.argmin(distances))
    outside = float(np.dot(point - closest[nearest], mesh.face_normals[walls][nearest])) >= 0.0
    return float(distances[nearest]) * (1.0 if outside else -1.0)


def _shapes(scene: dict[str, Any], role: str) -> list[dict[str, Any]]:
    return [s for s in scene["follower"]["shapes"] if s["role"] == role]


@pytest.mark.parametrize("name", KINDS)
def test_follower_touches_the_part(name: str) -> None:
    """At every frame tried each contact of the follower touches the part as the STL holds it:
    a roller's axis (or a mushroom's centre) one radius (plus half a groove's clearance) from
    the walls, a flat face's plane on the mesh with none of it beyond, a knife's edge on it."""
    b = built(name)
    design = b.analysis.design
    fol = design.follower
    slack = SLACK * design.manufacturing.tolerance
    mesh = b.meshes[0]
    rollers, faces, knives = (_shapes(b.scene, role) for role in ("roller", "face", "knife"))
    assert len(rollers) + len(faces) + len(knives) == (2 if design.cam.type in (
        "conjugate", "constant-breadth") else 1)
    for frame in FRAMES:
        for shape in rollers:
            placed = _placed(b.scene, shape, frame)
            expected = fol.roller_radius + fol.groove_clearance / 2.0
            assert shape["radius"] == pytest.approx(fol.roller_radius, abs=1e-4)
            gap = _distance(mesh, placed[:3, 3], placed[:3, 2], shape["length"] / 2.0)
            assert gap == pytest.approx(expected, abs=slack), (name, frame)
        for shape in faces:
            placed = _placed(b.scene, shape, frame)
            if shape["type"] == "cap":  # a mushroom: a sphere of face_radius about its centre
                gap = _distance(mesh, placed[:3, 3], np.array([0.0, 0.0, 1.0]), np.inf)
                assert gap == pytest.approx(fol.face_radius, abs=slack), (name, frame)
                continue
            # a flat face: the box's side toward the cam (its −Y) is the face
            normal, along = placed[:3, 1], placed[:3, 0]
            origin = placed[:3, 3] - normal * shape["y"] / 2.0
            offset = mesh.vertices - origin
            under = np.abs(offset @ along) <= shape["x"] / 2.0
            depth = -(offset[under] @ normal)  # how far each vertex lies on the cam's side
            assert depth.min() == pytest.approx(0.0, abs=slack), (name, frame)
        for shape in knives:
            placed = _placed(b.scene, shape, frame)
            edge, direction = placed[:3, 3], placed[:3, 2]
            gap = _distance(mesh, edge, direction, shape["length"] / 2.0)
            assert gap == pytest.approx(0.0, abs=slack), (name, frame)


@pytest.mark.parametrize("name", KINDS)
def test_transforms_are_rigid(name: str) -> None:
    """Every part's and the follower's transform is a rotation (orthonormal, det 1) and a
    translation, at every one of the report animation's frames; the JSON holds the kind's scene
    to its rounding."""
    b = built(name)
    design = b.analysis.design
    theta = frame_angles(design.table_step)
    assert b.scene["frames"] == theta.size
    np.testing.assert_allclose(b.scene["angles_deg"], np.degrees(theta), atol=1e-4)
    assert [p["file"] for p in b.scene["parts"]] == [f"{design.name}.stl"]
    exact = kind_of(design.cam.type).scene(b.analysis, theta)
    tracks = [p["matrices"] for p in b.scene["parts"]] + [b.scene["follower"]["matrices"]]
    for track, matrices in zip(tracks, [*exact.part_matrices, exact.follower_matrices],
                               strict=True):
        m = np.asarray(track, dtype=np.float64).reshape(-1, 4, 4)
        assert m.shape[0] == theta.size
        rotation = m[:, :3, :3]
        np.testing.assert_allclose(rotation @ rotation.transpose(0, 2, 1),
                                   np.broadcast_to(np.eye(3), rotation.shape), atol=3e-6)
        np.testing.assert_allclose(np.linalg.det(rotation), 1.0, atol=1e-5)
        np.testing.assert_array_equal(m[:, 3], np.broadcast_to([0, 0, 0, 1], (theta.size, 4)))
        np.testing.assert_allclose(m, matrices, atol=1e-4)
    for shape in b.scene["follower"]["shapes"]:
        rotation = _matrix(shape["matrix"])[:3, :3]
        np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=3e-6)
        assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-5)
    low, high = (np.array(b.scene["bounds"][k]) for k in ("min", "max"))
    mesh_low, mesh_high = b.meshes[0].bounds
    assert (low <= mesh_low + 1e-3).all() and (high >= mesh_high - 1e-3).all()


def test_a_disc_turns_as_the_report_draws_it() -> None:
    """A disc's scene has the report's animation frames (its drawing's ``data-frames``), and
    its plate turns by σθ about Z: a clockwise cam the other way."""
    name = "seed-10-4"
    artifacts = render(analyse(load_design(DESIGNS / f"{name}.yaml")))
    page = artifacts.files[f"{name}-report.html"].decode()
    frames = json.loads(re.search(r"data-frames='([^']*)'", page).group(1))
    stl = [n for n in artifacts.files if n.endswith(".stl")]
    scene = scene_json(artifacts.analysis, stl)
    assert scene["frames"] == len(frames) == 360
    theta = np.radians(scene["angles_deg"])
    for other, sigma in ((name, 1.0), ("demo-mushroom-cw", -1.0)):
        m = np.asarray(built(other).scene["parts"][0]["matrices"]).reshape(-1, 4, 4)
        turned = np.arctan2(m[:, 1, 0], m[:, 0, 0])
        np.testing.assert_allclose(np.unwrap(turned), sigma * theta, atol=1e-5)


def test_scene_is_small_and_quick() -> None:
    """A 360-frame scene's JSON stays well under 300 kB, and is made in a few milliseconds
    (for a disc, a drum and a globoid)."""
    for name in ("seed-10-4", "demo-cylindrical", "demo-globoidal-convex"):
        b = built(name)
        names = [p["file"] for p in b.scene["parts"]]
        scene_json(b.analysis, names)
        start = time.process_time()  # CPU time: the other tests' load on the machine not counted
        for _ in range(5):
            text = json.dumps(scene_json(b.analysis, names))
        spent = (time.process_time() - start) / 5
        assert len(text) < 150_000, name
        assert spent < 0.05, (name, spent)  # some 3–10 ms of CPU


# -- the view in Chromium -------------------------------------------------------------------------

STATIC = Path(__file__).resolve().parent.parent / "camfab" / "serve" / "static"

#: The harness page: the import map the studio page gives, the view on a disc's scene.
HARNESS = """<!doctype html>
<html><head><meta charset="utf-8">
<script type="importmap">{"imports": {"three": "./static/three/three.module.js"}}</script>
</head><body data-errors="0">
<div id="view" style="width: 480px; height: 360px"></div>
<script>
window.addEventListener("error", () => {
  document.body.dataset.errors = String(Number(document.body.dataset.errors) + 1); });
window.addEventListener("unhandledrejection", () => {
  document.body.dataset.errors = String(Number(document.body.dataset.errors) + 1); });
</script>
<script type="module">
import { View3D } from "./static/view3d.js";
const scene = await (await fetch("scene.json")).json();
const buffers = await Promise.all(scene.parts.map(
  async (p) => (await fetch(p.file)).arrayBuffer()));
const view = new View3D(document.getElementById("view"));
view.setScene(scene, buffers);
window.view = view;
window.scene = scene;
window.buffers = buffers;
</script></body></html>
"""


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: Any) -> None:
        pass


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Any:
    """The harness, a disc's scene and STL, and the static folder served on 127.0.0.1."""
    root = tmp_path_factory.mktemp("view3d")
    b = built("seed-10-4")
    (root / "static").symlink_to(STATIC, target_is_directory=True)
    (root / "index.html").write_text(HARNESS, encoding="utf-8")
    (root / "scene.json").write_text(json.dumps(b.scene), encoding="utf-8")
    for file, data in b.stl.items():
        (root / file).write_bytes(data)
    handler = functools.partial(_Quiet, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}/index.html"
    server.shutdown()
    server.server_close()


def _browser(flags: tuple[str, ...]) -> Any:
    return chromium("--window-size=800,600", *flags)


#: The share of the view's pixels not of its background (its corner's colour), and a digest of
#: the picture.
DRAWN = """
var source = document.querySelector('#view canvas');
var copy = document.createElement('canvas');
copy.width = source.width; copy.height = source.height;
var context = copy.getContext('2d');
context.drawImage(source, 0, 0);
var data = context.getImageData(0, 0, copy.width, copy.height).data;
var drawn = 0, digest = 0;
for (var i = 0; i < data.length; i += 4) {
  if (Math.abs(data[i] - data[0]) + Math.abs(data[i + 1] - data[1])
      + Math.abs(data[i + 2] - data[2]) > 24) { drawn += 1; digest = (digest * 31 + i) % 1000003; }
}
return [drawn / (data.length / 4), digest];
"""

#: Chromium's software WebGL (SwiftShader through ANGLE), and none at all.
WEBGL = ("--use-angle=swiftshader", "--enable-unsafe-swiftshader")
NO_WEBGL = ("--disable-gpu", "--disable-webgl", "--disable-3d-apis")


@pytest.mark.parametrize("flags", [WEBGL, NO_WEBGL], ids=["webgl", "no-webgl"])
def test_view_in_chromium(served: str, flags: tuple[str, ...]) -> None:
    """The view loads a disc's scene and STL and shows the frames asked for, without a script
    error: with WebGL it draws the cam (its canvas is not blank, and changes as the cam turns);
    without, it says it needs WebGL."""
    browser = _browser(flags)
    try:
        browser.get(served)
        page_wait(browser, "return document.getElementById('view').dataset.ready === 'yes'",
                  seconds=30.0)
        webgl = browser.execute_script(
            "return !!document.querySelector('#view canvas')")
        pictures = []
        for frame in (0, 90, 181, 359):
            browser.execute_script("window.view.show(arguments[0])", frame)
            assert browser.execute_script(
                "return document.getElementById('view').dataset.frame") == str(frame)
            if webgl:
                pictures.append(browser.execute_script(DRAWN))
        # a new scene for the same design keeps the view; dispose leaves nothing behind
        browser.execute_script("window.view.setScene(window.scene, window.buffers);"
                               "window.view.show(12)")
        assert browser.execute_script(
            "return document.getElementById('view').dataset.frame") == "12"
        assert browser.execute_script("return document.body.dataset.errors") == "0"
        if webgl:
            # the cam covers a good share of the view, and turns
            assert all(share > 0.02 for share, _ in pictures), pictures
            assert len({digest for _, digest in pictures}) > 1
        else:
            text = browser.execute_script("return document.getElementById('view').textContent")
            assert "needs WebGL" in text
        browser.execute_script("window.view.dispose()")
        assert browser.execute_script(
            "return document.querySelectorAll('#view canvas').length") == 0
        assert browser.execute_script("return document.body.dataset.errors") == "0"
    finally:
        browser.quit()
