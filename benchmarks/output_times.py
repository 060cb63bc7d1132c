"""Time of the analysis and of each output, for one design of every cam type (in process).

    python benchmarks/output_times.py [--runs N] [--markdown]

Everything runs in one process after every library is imported (one untimed build of each
design first), so the numbers are camfab's computation and serialisation alone, without the
import cost a fresh ``camfab build`` pays (``build_speed.py`` measures that). Each number is the
median of N runs, in milliseconds.

- ``analyse``: ``analyse(load_design(path))``: reading the YAML, the motion, the geometry and
  every check.
- ``dxf``, ``svg``, ``stl``, ``stl check``, ``verify``: one ``verify_exports(analysis, ("dxf",
  "svg", "stl"))`` call, the manufacturing files and their verification, split by timing the
  format writers it calls directly: each writer function of ``camfab.export`` is wrapped, for
  that call only, in a timer (the outermost wrapped call counts, so nothing is counted twice).
  ``dxf`` is writing the DXF (``render_dxf``), ``svg`` is ``render_svg``, ``stl`` is making the
  solid and its bytes (``render_stl``), ``stl check`` is reading the STL back and checking it
  closed, outward and of the part's volume (``read_stl``, ``check_stl``), and ``verify`` is the
  rest of the call: the kind's part (the plate's contours, drawings and solid described),
  reading the DXF back and running the follower over the CUT outline (a drum: the roller
  through the groove of the STL read back, and the development measured), which every build
  makes whatever outputs are asked for.
- ``html``, ``json``, ``csv``: the renderers of ``camfab.pipeline.RENDERERS`` (report page,
  report JSON, motion table) called on the verified analysis.
- ``render``: ``render(analysis)``: every output at once, what a build does after the analysis.
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from timing import ROOT, median_seconds, use_checkout

if TYPE_CHECKING:
    from camfab.pipeline import Analysis

#: One design of each cam type: (label, file in designs/).
CASES = (
    ("disc, translating roller", "seed-10-4.yaml"),
    ("disc, flat face (inch)", "demo-inch-flat.yaml"),
    ("disc, oscillating roller", "seed-10-3-oscillating.yaml"),
    ("cylindrical (drum)", "demo-cylindrical.yaml"),
    ("circular-arc", "seed-7-10-circular-arc.yaml"),
    ("tangent", "demo-tangent-roller.yaml"),
    ("groove", "demo-groove-roller.yaml"),
    ("conjugate", "demo-conjugate.yaml"),
    ("constant-breadth", "demo-constant-breadth.yaml"),
    ("linear", "demo-linear-roller.yaml"),
)

#: Part of verify_exports -> the exporter functions timed as that part, by module.
PARTS: dict[str, dict[str, tuple[str, ...]]] = {
    "dxf": {"camfab.export.dxf": ("render_dxf",)},
    "svg": {"camfab.export.svg": ("render_svg",)},
    "stl": {"camfab.export.stl": ("render_stl",)},
    "stl check": {"camfab.export.stl": ("read_stl", "check_stl")},
}

COLUMNS = ("analyse", "dxf", "svg", "stl", "stl check", "verify", "html", "json", "csv",
           "render")


class PartTimer:
    """Seconds spent in each part's exporters, the outermost wrapped call counting."""

    def __init__(self) -> None:
        self.spent = dict.fromkeys(PARTS, 0.0)
        self._depth = 0

    def wrap(self, part: str, function: Callable[..., Any]) -> Callable[..., Any]:
        def timed(*args: Any, **kwargs: Any) -> Any:
            self._depth += 1
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                self._depth -= 1
                if self._depth == 0:
                    self.spent[part] += time.perf_counter() - start
        return timed

    @contextmanager
    def installed(self) -> Iterator[PartTimer]:
        """The exporters wrapped while inside (camfab imports them when it calls them, so the
        module attributes are what it finds), restored after."""
        saved = []
        for part, modules in PARTS.items():
            for module_name, names in modules.items():
                module = importlib.import_module(module_name)
                for name in names:
                    original = getattr(module, name)
                    saved.append((module, name, original))
                    setattr(module, name, self.wrap(part, original))
        try:
            yield self
        finally:
            for module, name, original in reversed(saved):
                setattr(module, name, original)


def all_outputs(analysis: Analysis) -> Analysis:
    """The analysis of the same design asking for every output (the default)."""
    if analysis.design.outputs is None:
        return analysis
    return replace(analysis, design=analysis.design.model_copy(update={"outputs": None}))


def export_parts(analysis: Analysis, runs: int) -> dict[str, float]:
    """Median milliseconds of each part of ``verify_exports`` with every file asked for."""
    from camfab.pipeline import verify_exports

    samples: dict[str, list[float]] = {part: [] for part in (*PARTS, "verify")}
    for _ in range(runs):
        with PartTimer().installed() as timer:
            start = time.perf_counter()
            verify_exports(analysis, ("dxf", "svg", "stl"))
            total = time.perf_counter() - start
        for part, spent in timer.spent.items():
            samples[part].append(spent)
        samples["verify"].append(total - sum(timer.spent.values()))
    return {part: 1e3 * statistics.median(values) for part, values in samples.items()}


def time_design(path: Path, runs: int) -> dict[str, float]:
    """Milliseconds of each step for the design in *path*."""
    from camfab.pipeline import RENDERERS, analyse, load_design, render, verify_exports

    analysis = all_outputs(analyse(load_design(path)))
    render(analysis)  # warm every import the outputs need
    verified, _ = verify_exports(analysis, ("dxf", "svg", "stl"))
    times = {"analyse": 1e3 * median_seconds(lambda: analyse(load_design(path)), runs, warm=0)}
    times.update(export_parts(analysis, runs))
    for column, (output, index) in (("html", ("report", 0)), ("json", ("report", 1)),
                                    ("csv", ("csv", 0))):
        renderer = RENDERERS[output][index][1]
        times[column] = 1e3 * median_seconds(lambda r=renderer: r(verified), runs, warm=0)
    times["render"] = 1e3 * median_seconds(lambda: render(analysis), runs, warm=0)
    return times


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=7, help="runs per median (default 7)")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    options = parser.parse_args()
    use_checkout()
    width = max(len(c) for c in COLUMNS) + 1
    if options.markdown:
        print("| cam type | design | " + " | ".join(COLUMNS) + " |")
        print("| --- | --- | " + " | ".join("---:" for _ in COLUMNS) + " |")
    else:
        print(f"{'cam type':25s} {'design':28s}" + "".join(f"{c:>{width}s}" for c in COLUMNS)
              + f"   (ms, median of {options.runs})")
    for label, file in CASES:
        times = time_design(ROOT / "designs" / file, options.runs)
        if options.markdown:
            print(f"| {label} | {Path(file).stem} | "
                  + " | ".join(f"{times[c]:.1f}" for c in COLUMNS) + " |", flush=True)
        else:
            print(f"{label:25s} {file:28s}" + "".join(f"{times[c]:{width}.1f}" for c in COLUMNS),
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
