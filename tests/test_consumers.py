"""Real consumers of the files: OpenSCAD imports the DXF's CUT layer and extrudes it, and imports
the STL into a boolean; admesh checks the STL for open, degenerate or flipped facets. Both come
from Debian (``.ci/run`` installs them); the DXF is also rendered to PNG with ezdxf's drawing
add-on and checked to show the cam."""

from __future__ import annotations

import math
import re
import subprocess
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely
import trimesh

from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGN_FILES, tool
from .dxf_loops import loops

PLATES = [p for p in DESIGN_FILES if load_design(p).cam.type == "disc"
          and load_design(p).cam.thickness is not None]
DRUMS = [p for p in DESIGN_FILES if load_design(p).cam.type == "cylindrical"
         and render(analyse(load_design(p))).files.get(f"{p.stem}.stl") is not None]
#: Face-groove cams: plates whose groove is a pocket (their CUT layer is the plate's circle).
GROOVES = [p for p in DESIGN_FILES if load_design(p).cam.type == "groove"]
GLOBOIDS = [p for p in DESIGN_FILES if load_design(p).cam.type == "globoidal"]
SOLIDS = PLATES + DRUMS + GROOVES + GLOBOIDS


def written(path: Path, folder: Path):  # type: ignore[no-untyped-def]
    """Build *path* in memory and write its files into *folder*; the design and its report."""
    design = load_design(path)
    artifacts = render(analyse(design))
    for name, data in artifacts.files.items():
        (folder / name).write_bytes(data)
    assert artifacts.analysis is not None
    return design, artifacts.analysis


def openscad(folder: Path, source: str) -> tuple[trimesh.Trimesh, str]:
    """Run OpenSCAD on *source*, export an STL and read it back; with OpenSCAD's messages."""
    scad, out = folder / "model.scad", folder / "openscad.stl"
    scad.write_text(source)
    run = subprocess.run([tool("openscad"), "-o", str(out), str(scad)], capture_output=True,
                         text=True, timeout=300, check=False)
    assert run.returncode == 0, run.stderr
    mesh = trimesh.load(out, file_type="stl")
    return mesh, run.stderr


@pytest.mark.parametrize("path", PLATES, ids=[p.stem for p in PLATES])
def test_openscad_extrudes_the_cut_layer_to_our_volume(path: Path, tmp_path: Path) -> None:
    design, analysis = written(path, tmp_path)
    thickness = design.cam.thickness
    unit = design.mm_per_unit
    # OpenSCAD reads DXF coordinates as they are; its arcs are cut fine enough to hold 1e-4 mm
    mesh, messages = openscad(tmp_path, (
        f'scale([{unit!r}, {unit!r}, 1]) linear_extrude(height={thickness!r}) '
        f'import(file="{design.name}.dxf", layer="CUT", $fa=0.2, $fs=0.01);\n'))
    assert "WARNING" not in messages and "ERROR" not in messages, messages
    assert mesh.is_watertight
    ours = trimesh.load(tmp_path / f"{design.name}.stl", file_type="stl")
    stl = analysis.verification.stl
    allowance = stl.volume_allowance_mm3
    if design.manufacturing.kerf == 0.0:
        assert abs(mesh.volume - ours.volume) <= allowance
    else:  # the beam's path, not the part: ezdxf's reading of the same contours
        outline, *holes = loops(ezdxf.readfile(tmp_path / f"{design.name}.dxf"), "CUT")
        area = shapely.Polygon(outline * unit, [h * unit for h in holes]).area
        assert abs(mesh.volume - area * thickness) <= allowance


def less_prism(tmp_path: Path, name: str, y: float, r: float, height: float,
               sides: int, z: float = -1.0) -> tuple[float, float]:
    """OpenSCAD imports our STL and takes an upright prism of *sides* (radius *r*, centred at
    (0, *y*), from *z* up *height*) out of it; the result must be a clean closed solid.
    Returns its volume and our STL's (mm³)."""
    mesh, messages = openscad(tmp_path, (
        f'difference() {{ import("{name}.stl"); '
        f'translate([0, {y!r}, {z!r}]) cylinder(r={r!r}, h={height!r}, $fn={sides}); }}\n'))
    assert "WARNING" not in messages and "ERROR" not in messages, messages
    assert mesh.is_watertight and mesh.is_winding_consistent
    ours = trimesh.load(tmp_path / f"{name}.stl", file_type="stl")
    return mesh.volume, ours.volume


@pytest.mark.parametrize("path", PLATES + GROOVES, ids=[p.stem for p in PLATES + GROOVES])
def test_openscad_takes_the_stl_into_a_boolean(path: Path, tmp_path: Path) -> None:
    design, _ = written(path, tmp_path)
    base = design.cam.base_radius
    bore = (design.cam.bore or 0.0) / 2
    # a 48-sided prism through the plate, wholly inside the base circle's material on −Y
    r, y = (base - bore) / 4, -(base + bore) / 2
    thickness = design.cam.thickness
    volume, ours = less_prism(tmp_path, design.name, y, r, thickness + 2, 48)
    prism = 24 * r * r * math.sin(2 * math.pi / 48) * thickness
    assert volume == pytest.approx(ours - prism, rel=1e-6)


@pytest.mark.parametrize("path", DRUMS, ids=[p.stem for p in DRUMS])
def test_openscad_takes_the_drum_into_a_boolean(path: Path, tmp_path: Path) -> None:
    design, _ = written(path, tmp_path)
    cam = design.cam
    assert cam.radius is not None and cam.groove_depth is not None and cam.length is not None
    inner = (cam.bore or 0.0) / 2
    r = (inner + cam.radius - cam.groove_depth) / 2  # between the bore and the groove's floor
    volume, ours = less_prism(tmp_path, design.name, 0.0, r, cam.length + 2, 96)
    # the 96-gon's area less the bore's polygon (both within 1e-6 of their circles here)
    removed = (48 * r * r * math.sin(2 * math.pi / 96) - math.pi * inner * inner) * cam.length
    assert volume == pytest.approx(ours - removed, rel=1e-4)


@pytest.mark.parametrize("path", GLOBOIDS, ids=[p.stem for p in GLOBOIDS])
def test_openscad_takes_the_globoid_into_a_boolean(path: Path, tmp_path: Path) -> None:
    design, analysis = written(path, tmp_path)
    blank = analysis.globoid.blank
    numbers = analysis.numbers
    inner = blank.bore
    # a 96-gon through the blank's whole width, between the bore and the groove's floor
    solid_to = min(numbers.floor_radius, numbers.flank_radius, blank.ends_radius())
    r = (inner + solid_to) / 2
    volume, ours = less_prism(tmp_path, design.name, 0.0, r, blank.width + 2.0, 96,
                              -blank.width / 2.0 - 1.0)
    removed = (48 * r * r * math.sin(2 * math.pi / 96) - math.pi * inner * inner) * blank.width
    assert volume == pytest.approx(ours - removed, rel=1e-4)


#: What admesh must not have had to repair. ("Normals fixed" is left out: admesh recomputes the
#: normal of every facet in float32, and for the few sliver facets where a boolean meets the
#: drum's surface its own rounding disagrees with the stored normal; the test checks the stored
#: normals against the winding in double precision instead.)
ADMESH_CLEAN = ("Degenerate facets", "Edges fixed", "Facets removed", "Facets added",
                "Facets reversed", "Backwards edges", "Total disconnected facets")


@pytest.mark.parametrize("path", SOLIDS, ids=[p.stem for p in SOLIDS])
def test_admesh_finds_nothing_to_repair(path: Path, tmp_path: Path) -> None:
    design, analysis = written(path, tmp_path)
    run = subprocess.run([tool("admesh"), str(tmp_path / f"{design.name}.stl")],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr
    report = run.stdout

    def value(label: str) -> int:
        # "Label : original final" or "Label : value"; the last number is the final state
        found = re.search(re.escape(label) + r"\s*:\s*(\d+)(?:[ \t]+(\d+))?", report)
        assert found is not None, f"{label} not in {report}"
        return int(found.group(2) or found.group(1))

    assert value("Number of parts") == 1
    for label in ADMESH_CLEAN:
        assert value(label) == 0, f"{label}: {report}"
    # every stored normal is the unit normal of its facet's winding (computed in double)
    data = (tmp_path / f"{design.name}.stl").read_bytes()
    count = int.from_bytes(data[80:84], "little")
    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    facets = np.frombuffer(data, dtype=record, count=count, offset=84)
    corners = facets["corners"].astype(np.float64)
    winding = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    winding /= np.linalg.norm(winding, axis=1)[:, None]
    assert float(np.max(np.linalg.norm(winding - facets["normal"], axis=1))) < 1e-5
    volume = float(re.search(r"Volume\s*:\s*([\d.]+)", report).group(1))  # type: ignore[union-attr]
    stl = analysis.verification.stl
    assert abs(volume - stl.expected_volume_mm3) <= stl.volume_allowance_mm3


@pytest.mark.parametrize("path", PLATES[:3], ids=[p.stem for p in PLATES[:3]])
def test_dxf_renders_to_a_picture_of_the_cam(path: Path, tmp_path: Path) -> None:
    from ezdxf.addons.drawing import matplotlib as drawing
    from PIL import Image

    design, _ = written(path, tmp_path)
    doc = ezdxf.readfile(tmp_path / f"{design.name}.dxf")
    png = tmp_path / f"{design.name}.png"
    drawing.qsave(doc.modelspace(), png, bg="#FFFFFF", dpi=100, size_inches=(6, 6))
    image = np.asarray(Image.open(png).convert("RGB")).astype(int)
    # the CUT layer is red (ACI 1): a good share of the picture's pixels, spread over the cam
    red = (image[..., 0] > 200) & (image[..., 1] < 80) & (image[..., 2] < 80)
    assert red.sum() > 500
    rows, cols = np.nonzero(red)
    assert np.ptp(rows) > image.shape[0] / 4 and np.ptp(cols) > image.shape[1] / 4
