"""Inspecting a 3-D scan of a million points: time per phase and peak memory.

    python benchmarks/scan_inspection.py [--points N] [--designs D.yaml ...] [--keep DIR]
        [--fits free fixtured] [--formats csv ply] [--shift X,Y,Z] [--profile [N]] [--markdown]

For each design (by default the drum ``demo-cylindrical`` and the globoid
``demo-globoidal-convex``) a scan is made here from camfab's own mesh of the part (the kind's
``reference_mesh()``, the triangles of its STL): N points (default 1,000,000) spread evenly by
area over the triangles, those on a flank (the groove's walls) drawn more often so that some 60 %
of the points lie on the flanks; each moved along its face's normal by Gaussian noise of
0.01 mm (σ), with that normal (out of the material) as its normal. The scan is then misplaced
as a scanner would hold it:

- for a **free** fit, turned 2° about an axis tilted from the cam's, (1, 2, 2)/3, and shifted
  3 mm along (2, −1, 2)/3 (``--shift X,Y,Z`` gives another shift, mm);
- for a **fixtured** fit (``--fixtured``: only the phase is fitted), turned 2° about the cam
  axis, as a fixture holds the part at an unknown phase.

Each scan is written as a CSV with normals (``x,y,z,nx,ny,nz``, 5 and 6 decimals) and as a
binary PLY (float32). Each case (design × fit × format) is then ``camfab inspect SCAN --design
DESIGN.yaml [--fixtured] -o DIR`` run in a fresh process with a timer around each phase (the
functions the inspection calls, wrapped: a phase's time is its own, less any other phase's
called within it):

- **read**: the scan file read (``read_scan``);
- **model**: the design analysed, the kind's scan model (its flank grids) and the part's mesh
  (``reference_mesh``: the kind's solid by manifold3d, as the STL is made);
- **align**: the scan placed on the part (``align_scan``: the target sampled, the phase
  searched, the ICP iterations);
- **deviations**: each point matched to its flank node and its deviation (``flank_nodes``,
  ``Others``, ``point_deviations``, ``flank_stats``);
- **fit + run**: the fitted surface and the gauge roller run over it (``fitted_deviation``,
  ``fitted_surface``, the model's ``run``, the lift, play and pressure angle);
- **reports**: the lift CSV, the JSON and HTML reports rendered and written;
- **rest**: the rest of the inspection (the setup, the scan moved, the findings).

Wall and processor seconds of each (the processor's counts every thread: a k-d tree query uses
both cores), the process's wall and processor seconds from its start (the imports included),
and its peak resident memory (``ru_maxrss`` of the child, from ``wait4``) beside the peak after
the imports alone. The last columns say the inspection found what was made: the placement's
residual, the share of points on the flanks and the largest lift error (the noise is averaged
over the fit's box, so it is some micrometres).

``--profile`` runs the first design's free CSV case under cProfile instead and prints the N
costliest functions (own time and cumulative).
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = [ROOT / "designs" / "demo-cylindrical.yaml",
           ROOT / "designs" / "demo-globoidal-convex.yaml"]

#: The scan: points, share on the flanks, noise along the normals (mm, σ), misplacement.
POINTS = 1_000_000
FLANK_SHARE = 0.6
NOISE_MM = 0.01
TURN_DEG = 2.0
SHIFT_MM = 3.0
#: The free scan's turn axis (tilted from the cam axis) and shift direction (unit vectors).
TURN_AXIS = np.array([1.0, 2.0, 2.0]) / 3.0
SHIFT_AXIS = np.array([2.0, -1.0, 2.0]) / 3.0
#: A triangle of the part's mesh is on a flank when its centre lies within this (mm) of the
#: flank's tangent plane at its nearest node, and within the node's spacing along it.
ON_FLANK_MM = 0.02

PHASES = ("read", "model", "align", "deviations", "fit + run", "reports", "rest")


# ---------------------------------------------------------------------------- the scan made

def _model(design_path: Path) -> Any:
    sys.path.insert(0, str(ROOT))
    from camfab.inspect.scan_run import scan_model_of
    from camfab.pipeline import analyse, load_design

    return scan_model_of(analyse(load_design(design_path)), str(design_path))


def _on_flanks(model: Any, centres: np.ndarray) -> np.ndarray:
    """Which triangle *centres* (mm, cam frame) lie on one of *model*'s flanks."""
    from camfab.inspect.scan_deviation import flank_nodes

    nodes = flank_nodes(model)
    distance, k = nodes.tree.query(centres, distance_upper_bound=float(nodes.spacing.max()) + 1.0)
    found = np.isfinite(distance)
    k = np.where(found, k, 0)
    offset = centres - nodes.points[k]
    normal = np.einsum("ij,ij->i", offset, nodes.normals[k])
    sideways = np.linalg.norm(offset - normal[:, None] * nodes.normals[k], axis=1)
    return found & (np.abs(normal) <= ON_FLANK_MM) & (sideways <= nodes.spacing[k])


def _rotation(axis: np.ndarray, degrees: float) -> np.ndarray:
    """The rotation by *degrees* about the unit *axis* (Rodrigues)."""
    angle = math.radians(degrees)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def make_scan(design_path: Path, count: int, seed: int = 1
              ) -> tuple[np.ndarray, np.ndarray, float]:
    """*count* points (mm, cam frame) and their unit normals spread over the part's mesh (see
    the module), and the share of them that lie on a flank."""
    model = _model(design_path)
    vertices, faces = model.reference_mesh()
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    keep = area > 0.0
    tri, cross, area = tri[keep], cross[keep], area[keep]
    flank = _on_flanks(model, tri.mean(axis=1))
    flank_area, other_area = float(area[flank].sum()), float(area[~flank].sum())
    weight = max(1.0, FLANK_SHARE / (1.0 - FLANK_SHARE) * other_area / flank_area)
    chance = area * np.where(flank, weight, 1.0)
    rng = np.random.default_rng(seed)
    face = rng.choice(len(area), size=count, p=chance / chance.sum())
    u = rng.random((count, 2))
    flip = u.sum(axis=1) > 1.0
    u[flip] = 1.0 - u[flip]
    corner = tri[face]
    normals = cross[face] / (2.0 * area[face, None])
    points = (corner[:, 0] + u[:, :1] * (corner[:, 1] - corner[:, 0])
              + u[:, 1:] * (corner[:, 2] - corner[:, 0])
              + rng.normal(0.0, NOISE_MM, count)[:, None] * normals)
    return points, normals, float(np.count_nonzero(flank[face])) / count


def misplace(points: np.ndarray, normals: np.ndarray, fixtured: bool,
             shift: np.ndarray = SHIFT_MM * SHIFT_AXIS) -> tuple[np.ndarray, np.ndarray]:
    """The scan as the scanner holds it (see the module): a free scan shifted by *shift* (mm)."""
    if fixtured:
        turn = _rotation(np.array([0.0, 0.0, 1.0]), TURN_DEG)
        return points @ turn.T, normals @ turn.T
    turn = _rotation(TURN_AXIS, TURN_DEG)
    return points @ turn.T + shift, normals @ turn.T


def write_csv(path: Path, points: np.ndarray, normals: np.ndarray) -> None:
    """A CSV of x, y, z (mm, 5 decimals) and nx, ny, nz (6 decimals) under a header."""
    with path.open("w") as out:
        out.write("x,y,z,nx,ny,nz\n")
        np.savetxt(out, np.hstack((points, normals)),
                   fmt=["%.5f"] * 3 + ["%.6f"] * 3, delimiter=",")


def write_ply(path: Path, points: np.ndarray, normals: np.ndarray) -> None:
    """A binary little-endian PLY of float32 x, y, z, nx, ny, nz."""
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(points)}\n"
              + "".join(f"property float {c}\n" for c in ("x", "y", "z", "nx", "ny", "nz"))
              + "end_header\n")
    with path.open("wb") as out:
        out.write(header.encode("ascii"))
        out.write(np.hstack((points, normals)).astype("<f4").tobytes())


# ------------------------------------------------------------------ the child: timed phases

class Phases:
    """Wall and processor seconds spent in each phase: a wrapped call's own time, less that of
    any wrapped call within it."""

    def __init__(self) -> None:
        self.wall = dict.fromkeys(PHASES, 0.0)
        self.cpu = dict.fromkeys(PHASES, 0.0)
        self._inner: list[list[float]] = []

    def wrap(self, phase: str, func: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(func)
        def timed(*args: Any, **kwargs: Any) -> Any:
            self._inner.append([0.0, 0.0])
            wall, cpu = time.perf_counter(), time.process_time()
            try:
                return func(*args, **kwargs)
            finally:
                wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
                inner_wall, inner_cpu = self._inner.pop()
                self.wall[phase] += wall - inner_wall
                self.cpu[phase] += cpu - inner_cpu
                if self._inner:
                    self._inner[-1][0] += wall
                    self._inner[-1][1] += cpu
        return timed


def _install(phases: Phases) -> None:
    """Wrap the functions the scan's inspection calls (each looked up as it is called)."""
    import camfab.inspect.scan as scan
    import camfab.inspect.scan_align as scan_align
    import camfab.inspect.scan_deviation as scan_deviation
    import camfab.inspect.scan_html as scan_html
    import camfab.inspect.scan_json as scan_json
    import camfab.inspect.scan_lift_csv as scan_lift_csv
    import camfab.inspect.scan_measure as scan_measure
    import camfab.inspect.scan_run as scan_run
    import camfab.pipeline as pipeline
    from camfab.inspect.models.drum import DrumScan
    from camfab.inspect.models.globoid import GloboidScan

    where: list[tuple[Any, str, str]] = [
        (scan_run, "inspect_scan_file", "rest"),
        (scan, "read_scan", "read"),
        (pipeline, "analyse", "model"), (scan_run, "scan_model_of", "model"),
        (DrumScan, "reference_mesh", "model"), (GloboidScan, "reference_mesh", "model"),
        (scan_align, "align_scan", "align"),
        *((scan_deviation, name, "deviations") for name in
          ("flank_nodes", "Others", "point_deviations", "flank_stats")),
        (scan_deviation, "fitted_deviation", "fit + run"),
        (scan_deviation, "fitted_surface", "fit + run"),
        (DrumScan, "run", "fit + run"), (GloboidScan, "run", "fit + run"),
        (scan_measure, "_lift_and_play", "fit + run"), (scan_measure, "_slope", "fit + run"),
        (scan_lift_csv, "render_scan_lift_csv", "reports"),
        (scan_json, "render_scan_json", "reports"), (scan_html, "render_scan_html", "reports"),
        (pipeline, "write_files", "reports")]
    for owner, name, phase in where:
        setattr(owner, name, phases.wrap(phase, getattr(owner, name)))


def child(report: Path, command: list[str]) -> None:
    """Run ``camfab inspect`` with *command*'s arguments, its phases timed; write them, with the
    peak memory after the imports and the inspection's findings, to *report* (JSON)."""
    sys.path.insert(0, str(ROOT))
    import camfab.cli
    import camfab.inspect.scan_run as scan_run
    from camfab import terminal

    terminal.install()  # (as the program does: its output in any encoding)
    phases = Phases()
    _install(phases)
    imported = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    results: list[Any] = []
    inspect_file = scan_run.inspect_scan_file

    def keep(*args: Any, **kwargs: Any) -> Any:
        results.append(inspect_file(*args, **kwargs))
        return results[-1]

    scan_run.inspect_scan_file = keep
    try:
        camfab.cli.main.main(["inspect", *command], prog_name="camfab", standalone_mode=False)
    except SystemExit:
        pass
    ins = results[0].inspection
    worst = ins.worst()
    report.write_text(json.dumps({
        "wall": phases.wall, "cpu": phases.cpu, "imported_kib": imported,
        "residual_mm": ins.alignment.residual_mm, "iterations": ins.alignment.iterations,
        "on_flanks": 1.0 - ins.deviations.aside / len(ins.scan.points),
        "worst_mm": worst[0] if worst else math.nan}))


# ----------------------------------------------------------------------------- the parent

def run_case(scan: Path, design: Path, fixtured: bool, out: Path) -> dict[str, Any]:
    """One case in a fresh process: its phases, its wall and processor seconds and its peak
    resident memory (KiB)."""
    report = out / "report.json"
    command = [sys.executable, __file__, "--child", str(report), str(scan), "--design",
               str(design), "-o", str(out / "inspection"), *(["--fixtured"] if fixtured else [])]
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, cwd=ROOT)
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - start
    if process.returncode != 0 or not report.exists():
        raise RuntimeError(f"{' '.join(command)} failed ({process.returncode})")
    result: dict[str, Any] = json.loads(report.read_text())
    result.update(process_wall=wall, process_cpu=usage.ru_utime + usage.ru_stime,
                  peak_kib=usage.ru_maxrss)
    return result


def profile(scan: Path, design: Path, top: int, out: Path) -> str:
    """cProfile's N costliest functions of one inspection, by own time and by cumulative."""
    import cProfile
    import io
    import pstats

    sys.path.insert(0, str(ROOT))
    import camfab.cli
    from camfab import terminal

    terminal.install()
    profiler = cProfile.Profile()
    profiler.enable()
    try:
        camfab.cli.main.main(["inspect", str(scan), "--design", str(design), "-o", str(out)],
                             prog_name="camfab", standalone_mode=False)
    except SystemExit:
        pass
    profiler.disable()
    text = io.StringIO()
    stats = pstats.Stats(profiler, stream=text)
    stats.sort_stats("tottime").print_stats(top)
    stats.sort_stats("cumulative").print_stats(top)
    return text.getvalue()


def _vector(text: str) -> np.ndarray:
    values = [float(v) for v in text.split(",")]
    if len(values) != 3:
        raise argparse.ArgumentTypeError("three lengths, X,Y,Z (mm)")
    return np.array(values)


def _row(cells: list[str], markdown: bool) -> str:
    if markdown:
        return "| " + " | ".join(cells) + " |"
    return "  ".join(f"{c:>11}" if i else f"{c:<34}" for i, c in enumerate(cells))


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--designs", nargs="+", type=Path, default=DESIGNS)
    parser.add_argument("--points", type=int, default=POINTS)
    parser.add_argument("--keep", type=Path, help="write the scans and reports here (kept)")
    parser.add_argument("--profile", type=int, nargs="?", const=30, default=0, metavar="N")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--fits", nargs="+", choices=("free", "fixtured"),
                        default=["free", "fixtured"])
    parser.add_argument("--formats", nargs="+", choices=("csv", "ply"), default=["csv", "ply"])
    parser.add_argument("--shift", type=_vector, default=SHIFT_MM * SHIFT_AXIS, metavar="X,Y,Z",
                        help="the free scan's shift (mm; default 3 mm along (2, -1, 2))")
    return parser


def _scans(options: argparse.Namespace, folder: Path) -> list[tuple[Path, str, Path]]:
    """The cases: (design, fit, scan file) of each design, fit and format, in *folder*."""
    return [(design, fit, folder / f"{design.stem}-{fit}.{suffix}")
            for design in options.designs for fit in options.fits for suffix in options.formats]


def make_files(options: argparse.Namespace, folder: Path) -> None:
    """Make and write every case's scan into *folder* (run in a process of its own, so that
    the cases' processes start from a small one: a child's peak memory counts its parent's at
    the fork)."""
    for design in options.designs:
        made = time.perf_counter()
        points, normals, share = make_scan(design, options.points)
        made = time.perf_counter() - made
        for fit in options.fits:
            p, n = misplace(points, normals, fit == "fixtured", options.shift)
            if "csv" in options.formats:
                write_csv(folder / f"{design.stem}-{fit}.csv", p, n)
            if "ply" in options.formats:
                write_ply(folder / f"{design.stem}-{fit}.ply", p, n)
        print(f"{design.stem}: {options.points:,} points made in {made:.1f} s, "
              f"{share:.0%} on the flanks", flush=True)


def main() -> int:
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        child(Path(sys.argv[2]), sys.argv[3:])
        return 0
    if len(sys.argv) > 2 and sys.argv[1] == "--make":
        make_files(_parser().parse_args(sys.argv[3:]), Path(sys.argv[2]))
        return 0
    options = _parser().parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = options.keep or Path(temporary)
        folder.mkdir(parents=True, exist_ok=True)
        subprocess.run([sys.executable, __file__, "--make", str(folder), *sys.argv[1:]],
                       check=True, cwd=ROOT)
        if options.profile:
            design, _, scan = _scans(options, folder)[0]
            print(profile(scan, design, options.profile, folder / "profile"))
            return 0
        return _run(options, folder)


def _run(options: argparse.Namespace, folder: Path) -> int:
    load = os.getloadavg()[0]
    header = ["case", *PHASES, "inspection", "process", "peak memory", "after imports",
              "residual", "on flanks", "lift error"]
    if options.markdown:
        print(_row(header, True))
        print("| --- |" + " ---: |" * (len(header) - 1))
    else:
        print(_row(header, False))
    for design, fit, path in _scans(options, folder):
        out = folder / path.stem / path.suffix[1:]
        out.mkdir(parents=True, exist_ok=True)
        r = run_case(path, design, fit == "fixtured", out)
        total_wall, total_cpu = sum(r["wall"].values()), sum(r["cpu"].values())
        size = path.stat().st_size / 1e6
        cells = [f"{design.stem}, {fit}, {path.suffix[1:].upper()} ({size:.0f} MB)"]
        cells += [f"{r['wall'][p]:.2f} / {r['cpu'][p]:.2f}" for p in PHASES]
        cells += [f"{total_wall:.2f} / {total_cpu:.2f}",
                  f"{r['process_wall']:.2f} / {r['process_cpu']:.2f}",
                  f"{r['peak_kib'] / 1024:.0f} MiB", f"{r['imported_kib'] / 1024:.0f} MiB",
                  f"{r['residual_mm']:.4f} mm", f"{r['on_flanks']:.1%}",
                  f"{r['worst_mm'] * 1000:.1f} µm"]
        print(_row(cells, options.markdown), flush=True)
    print(f"seconds: wall / processor (both cores); load {load:.1f} → {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
