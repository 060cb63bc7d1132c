"""The files of every example and starter handed to the programs a workshop opens them with
(Debian packages; ``.ci/run`` installs them):

- ``rsvg-convert`` (librsvg, as Inkscape and browsers draw SVG) renders every SVG: the whole
  outline is on the page, with a margin on every side;
- PrusaSlicer (``prusa-slicer --info``) reads every STL as one manifold part that needs no
  repair;
- LibreCAD (``librecad dxf2pdf``) prints every DXF on its own paper: a page of the drawing's size
  in the drawing's units, with the drawing on it at true size.

Each program runs once over all the files of a kind, with a limit on its processor time rather
than a tight limit on the clock (a loaded machine runs it slowly, not wrongly).
"""

from __future__ import annotations

import os
import re
import resource
import subprocess
import zlib
from collections.abc import Callable
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from ezdxf import bbox as ezdxf_bbox
from PIL import Image

from .conftest import EVERY_DESIGN, Built, tool

#: Processor seconds a consumer may spend on one run over all files (each takes well under a
#: tenth of this on an idle machine).
CPU_LIMIT_S = 120
#: Wall-clock seconds before a run is abandoned: far beyond its processor time, for loaded
#: machines.
WALL_LIMIT_S = 1200

POINTS_PER_MM = 72 / 25.4


def cpu_limit(seconds: int) -> Callable[[], None]:
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds))

    return limit


def run(args: list[str], folder: Path) -> subprocess.CompletedProcess[str]:
    """Run a consumer in *folder* without a display, its settings kept in *folder*."""
    env = {**os.environ, "HOME": str(folder), "XDG_CONFIG_HOME": str(folder / ".config"),
           "XDG_RUNTIME_DIR": str(folder / ".runtime"), "QT_QPA_PLATFORM": "offscreen"}
    (folder / ".runtime").mkdir(mode=0o700, exist_ok=True)
    result = subprocess.run(args, cwd=folder, env=env, capture_output=True, text=True,
                            preexec_fn=cpu_limit(CPU_LIMIT_S), timeout=WALL_LIMIT_S,
                            check=False)
    assert result.returncode == 0, f"{args[0]} failed: {result.stderr[-2000:]}"
    return result


def gathered(every_build: dict[str, Built], suffix: str, folder: Path) -> dict[str, Path]:
    """Every built file with *suffix*, linked into *folder* (their names are unique)."""
    folder.mkdir(parents=True, exist_ok=True)
    found = {}
    for built in every_build.values():
        for path in built.files(suffix):
            link = folder / path.name
            link.symlink_to(path)
            found[path.name] = link
    return found


# ---- SVG: rsvg-convert -----------------------------------------------------------------------

#: Pixels across the longer side of the rendered page.
RENDER_PX = 1000


@pytest.fixture(scope="module")
def svg_margins(every_build: dict[str, Built],
                tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[int, ...]]:
    """Every SVG rendered by rsvg-convert on white: the blank pixels between the drawing and the
    page's left, top, right and bottom edges, by file name."""
    program = tool("rsvg-convert", "librsvg2-bin")
    folder = tmp_path_factory.mktemp("rsvg")
    margins = {}
    for name, svg in gathered(every_build, ".svg", folder / "in").items():
        png = folder / f"{name}.png"
        run([program, "--background-color", "white", "--keep-aspect-ratio", "--width",
             str(RENDER_PX), "--height", str(RENDER_PX), "-o", str(png), str(svg)], folder)
        image = np.asarray(Image.open(png).convert("L"))
        rows, cols = np.nonzero(image < 250)
        assert rows.size > 0, f"{name}: nothing drawn"
        height, width = image.shape
        margins[name] = (int(cols.min()), int(rows.min()), int(width - 1 - cols.max()),
                         int(height - 1 - rows.max()))
    return margins


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_rsvg_draws_the_whole_outline_on_the_page(every_build: dict[str, Built],
                                                  svg_margins: dict[str, tuple[int, ...]],
                                                  name: str) -> None:
    svgs = every_build[name].files(".svg")
    assert svgs
    for svg in svgs:
        left, top, right, bottom = svg_margins[svg.name]
        assert min(left, top, right, bottom) > 0, (
            f"{svg.name}: the drawing touches the page's edge (margins left {left}, top {top}, "
            f"right {right}, bottom {bottom} px)")


# ---- STL: prusa-slicer --info ----------------------------------------------------------------

#: What PrusaSlicer 2.5's ``--info`` prints only when it had to repair the mesh.
REPAIRS = ("open_edges", "degenerate_facets", "edges_fixed", "facets_removed",
           "facets_reversed", "backwards_edges")


@pytest.fixture(scope="module")
def slicer_info(every_build: dict[str, Built],
                tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, str]]:
    """``prusa-slicer --info`` over every STL at once: each file's ``key = value`` lines."""
    program = tool("prusa-slicer")
    folder = tmp_path_factory.mktemp("prusa")
    files = gathered(every_build, ".stl", folder / "in")
    output = run([program, "--info", *map(str, files.values())], folder).stdout
    info: dict[str, dict[str, str]] = {}
    current = None
    for line in output.splitlines():
        header = re.fullmatch(r"\[(.+\.stl)\]", line.strip())
        if header:
            current = info.setdefault(header.group(1), {})
        elif current is not None and " = " in line:
            key, value = line.split(" = ", 1)
            current[key.strip()] = value.strip()
    assert set(info) == set(files), f"--info reported on {sorted(info)}"
    return info


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_prusa_slicer_reads_every_stl_as_one_manifold_part(
        every_build: dict[str, Built], slicer_info: dict[str, dict[str, str]],
        name: str) -> None:
    built = every_build[name]
    stls = built.files(".stl")
    if not stls:
        pytest.skip(f"{name} writes no STL: {built.not_produced}")
    for stl in stls:
        info = slicer_info[stl.name]
        assert info.get("manifold") == "yes", info
        assert not set(REPAIRS) & set(info), info
        assert info.get("number_of_parts") == "1", info
        expected = built.report["verification"]["stl"]
        assert float(info["volume"]) == pytest.approx(
            expected["expected_volume_mm3"], abs=expected["volume_allowance_mm3"], rel=1e-6)


# ---- DXF: librecad dxf2pdf -------------------------------------------------------------------

def pdf_page_and_ink(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """A one-page PDF as Qt writes it: the page's width and height, and every point of its
    drawing's paths (both in points, y up)."""
    box = re.search(rb"/MediaBox\s*\[([^\]]+)\]", data)
    assert box is not None
    x0, y0, x1, y1 = (float(v) for v in box.group(1).split())
    for start in re.finditer(rb"stream\r?\n", data):
        try:
            content = zlib.decompressobj().decompress(data[start.end():]).decode("latin-1")
        except zlib.error:
            continue
        matrix = re.search(r"([-\d.]+) 0 0 ([-\d.]+) ([-\d.]+) ([-\d.]+) cm", content)
        if matrix is None:
            continue
        sx, sy, tx, ty = (float(v) for v in matrix.groups())
        # after the clipping rectangle, the coordinates before each m, l and c operator
        body = content.split("W* n", 1)[-1]
        number = r"(-?[\d.]+)"
        ends = re.findall(rf"(?<![\d.]){number} {number} [ml]\s", body)
        curves = re.findall(rf"(?<![\d.]){' '.join([number] * 6)} c\s", body)
        points = [*ends, *(pair for curve in curves for pair in
                           (curve[0:2], curve[2:4], curve[4:6]))]
        xy = np.array(points, dtype=np.float64)
        return (np.array([x1 - x0, y1 - y0]),
                np.column_stack((sx * xy[:, 0] + tx, sy * xy[:, 1] + ty)))
    raise AssertionError("no page content in the PDF")


@pytest.fixture(scope="module")
def librecad_pdfs(every_build: dict[str, Built],
                  tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Every DXF printed by ``librecad dxf2pdf`` (one run, no display): the PDF by DXF name."""
    program = tool("librecad")
    folder = tmp_path_factory.mktemp("librecad")
    files = gathered(every_build, ".dxf", folder / "in")
    out = folder / "out"
    out.mkdir()
    run([program, "dxf2pdf", "-t", str(out), *map(str, files.values())], folder)
    return {name: out / f"{Path(name).stem}.pdf" for name in files}


@pytest.mark.parametrize("name", EVERY_DESIGN)
def test_librecad_prints_the_drawing_at_true_size_on_a_page_of_its_size(
        every_build: dict[str, Built], librecad_pdfs: dict[str, Path], name: str) -> None:
    built = every_build[name]
    dxfs = built.files(".dxf")
    assert dxfs
    points_per_unit = built.design.mm_per_unit * POINTS_PER_MM
    for dxf in dxfs:
        pdf = librecad_pdfs[dxf.name]
        assert pdf.exists(), f"LibreCAD wrote no {pdf.name}"
        page, ink = pdf_page_and_ink(pdf.read_bytes())
        doc = ezdxf.readfile(dxf)
        # the page: the drawing's paper in its units (Qt rounds a page to whole points)
        paper = np.array(doc.header["$PLIMMAX"]) - np.array(doc.header["$PLIMMIN"])
        assert np.allclose(page, paper * points_per_unit, atol=0.51), (page, paper)
        # ... which holds the drawing's extents: its size in the drawing's units, a margin round
        extents = (np.array(doc.header["$EXTMAX"][:2])
                   - np.array(doc.header["$EXTMIN"][:2])) * points_per_unit
        assert np.all(page > extents) and np.all(page < 1.2 * extents.max() + extents)
        # everything drawn is on the page, and at true size: at least as large as the cut
        # (LibreCAD scales by the page's device pixels per whole millimetre: off by up to half
        # a millimetre in the page's smaller side)
        assert ink.size, f"{pdf.name}: nothing drawn"
        assert np.all(ink >= -0.5) and np.all(ink <= page + 0.5), (ink.min(0), ink.max(0), page)
        cut = ezdxf_bbox.extents(doc.modelspace().query('*[layer=="CUT"]'))
        size = np.array([cut.size.x, cut.size.y]) * points_per_unit
        scale_error = 0.5 / float(page.min() / POINTS_PER_MM)
        drawn = np.ptp(ink, axis=0)
        assert np.all(drawn >= size * (1 - scale_error) - 0.5), (drawn, size)
