"""What the cam at its speed costs a plate cam's analysis, in process: before (camfab at an
earlier commit, the design without the keys it does not know) and after (this checkout, with
the elastic follower train, the contact stress, the roller's life and their limits), and this
checkout without the new keys (the rigid dynamics alone). Goal: at most 20 ms more.

    python benchmarks/at_speed.py [--base REV] [--rounds N] [--runs N]

Each time is ``camfab.pipeline.analyse`` (without the sizing's advice, which a passing design
does not run) of ``designs/demo-valve-at-speed.yaml``, the median of N runs after one untimed
run, in a fresh process per checkout and round; the rounds alternate the checkouts, so a
machine's load falls on all of them alike. The base checkout is a temporary git worktree.
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from timing import ROOT

#: The commit before the cam at its speed.
BASE = "9a3ee29"

DESIGN = ROOT / "designs" / "demo-valve-at-speed.yaml"

#: The design's keys that camfab before them did not know, and the keys of the elastic train.
NEW_KEYS = re.compile(r"^(\s*(stiffness|damping_ratio|roller_length|roller_load_rating|"
                      r"roller_bearing|contact_stress|roller_life):.*|materials:.*)\n", re.M)

#: The goal (seconds more than before).
GOAL = 0.020

_CHILD = """
import statistics, sys, time
sys.path.insert(0, {root!r})
from camfab.pipeline import analyse, design_from_text
design = design_from_text(open({design!r}).read())
analyse(design, advice=False)
times = []
for _ in range({runs}):
    start = time.perf_counter()
    analyse(design, advice=False)
    times.append(time.perf_counter() - start)
print(statistics.median(times))
"""


def _time(root: Path, design: Path, runs: int) -> float:
    code = _CHILD.format(root=str(root), design=str(design), runs=runs)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=root)
    return float(out.stdout.strip())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", default=BASE)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--runs", type=int, default=15)
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        base = work / "base"
        subprocess.run(["git", "worktree", "add", "--detach", str(base), options.base],
                       cwd=ROOT, check=True, capture_output=True)
        try:
            plain = work / "plain.yaml"
            # without the new keys, and without a section they leave empty
            plain.write_text(re.sub(r"^limits:\n(?=\S|\Z)", "",
                                    NEW_KEYS.sub("", DESIGN.read_text()), flags=re.M))
            cases = {"before (base, no new keys)": (base, plain),
                     "after, no new keys": (ROOT, plain),
                     "after, at speed": (ROOT, DESIGN)}
            times: dict[str, list[float]] = {label: [] for label in cases}
            for _ in range(options.rounds):
                for label, (root, design) in cases.items():
                    times[label].append(_time(root, design, options.runs))
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(base)], cwd=ROOT,
                           check=False, capture_output=True)
    medians = {label: statistics.median(values) for label, values in times.items()}
    for label, value in medians.items():
        print(f"{label}: {value * 1e3:.1f} ms (median of {options.rounds} rounds)")
    extra = medians["after, at speed"] - medians["before (base, no new keys)"]
    print(f"the cam at its speed adds {extra * 1e3:.1f} ms "
          f"({medians['after, at speed'] / medians['before (base, no new keys)']:.2f}x)")
    print(json.dumps({k: round(v * 1e3, 2) for k, v in medians.items()}))
    met = extra <= GOAL
    print(f"goal: at most {GOAL * 1e3:.0f} ms more: {'met' if met else 'NOT met'}")
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
