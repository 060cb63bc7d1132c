"""How long a sizing takes in process: the least base radius of a disc cam (goal: under 0.2 s),
with the best offset, an oscillating follower with and without its pivot distance, a groove
cam, a conjugate pair and a drum.

    python benchmarks/sizing_speed.py [--runs N]

Each time is ``camfab.pipeline.size_design`` on a design loaded without its radius (as
``camfab size`` loads it), the median of N runs after one untimed run (imports); each run
computes its grids of cam angles anew, as the one sizing of ``camfab size`` does (the sizing
keeps the last few, so the runs would otherwise share the first's).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from functools import partial
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from timing import ROOT, median_seconds, use_checkout

if TYPE_CHECKING:
    from camfab.analysis.sizing import Sizing
    from camfab.design import Design

#: (label, design file or starter, keys beyond the radius, size the pivot too)
CASES = (("disc (seed-10-4)", ROOT / "designs" / "seed-10-4.yaml", (), False),
         ("disc, best offset", ROOT / "designs" / "seed-10-4.yaml", ("follower.offset",), False),
         ("oscillating roller", "oscillating", (), False),
         ("oscillating, best pivot", "oscillating", (), True),
         ("groove", "groove", (), False),
         ("conjugate", "conjugate", (), False),
         ("drum", "cylindrical", (), False))

#: The goal for the first case (seconds).
GOAL = 0.2


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    options = parser.parse_args()
    use_checkout()
    from camfab.analysis.sizing import grids
    from camfab.design.loader import unsized_design
    from camfab.pipeline import size_design

    def sizing_alone(design: Design, left: frozenset[str], pivot: bool) -> Sizing:
        grids.cache_clear()
        return size_design(design, left, pivot)

    first = None
    with tempfile.TemporaryDirectory() as folder:
        for label, source, keys, pivot in CASES:
            path = source
            if isinstance(source, str):
                text = (resources.files("camfab") / "starters" / f"{source}.yaml").read_text()
                path = Path(folder) / f"{source}.yaml"
                path.write_text(text, encoding="utf-8")
            design, left = unsized_design(path, frozenset({"cam.base_radius", "cam.radius",
                                                            *keys}))
            sizing = size_design(design, left, pivot)
            time = median_seconds(partial(sizing_alone, design, left, pivot), options.runs)
            first = time if first is None else first
            print(f"{label}: {time * 1e3:.0f} ms (median of {options.runs}); size "
                  f"{sizing.size:.4f} mm" + (f", offset {sizing.offset:.4f} mm"
                                             if sizing.offset is not None else "")
                  + (f", pivot distance {sizing.pivot_distance:.4f} mm"
                     if sizing.pivot_distance is not None else ""))
    assert first is not None
    met = first < GOAL
    print(f"goal: a disc cam's sizing under {GOAL} s: {'met' if met else 'NOT met'}")
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
