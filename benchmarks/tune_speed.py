"""``camfab tune`` on a few designs: the time a tuning takes and what it gains, in one run.

    python benchmarks/tune_speed.py [--markdown] [--quick]

Each case is one tuning in a fresh process (a tuning is deterministic: one run tells its
result; its time carries the machine's load): the wall and processor time, the candidates
measured and analysed in full, the objective before and after, and for the residual vibration
of the valve train over its band (1350–1650 rpm) the tuned objective over the best the standard
laws reach there (the valve train of ``demo-valve-at-speed`` with its rise and return tuned
among the standard laws alone). The designs are ``demo-valve-at-speed`` and variants of it
written into a temporary folder: its rise as a polynomial through two free points, as a spline
of four free control values, both segments as modified uniform velocity; and a plate cam whose
rise is a polynomial through two free points (the peak acceleration, a linear programme).
``--quick`` runs one start each (the default is the command's, four).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from timing import ROOT

VALVE = ROOT / "designs" / "demo-valve-at-speed.yaml"
RISE = "  - rise:   {angle: 110, lift: 9, law: polynomial-4567}"
#: The variants of the valve train's rise (and return), by file name.
VARIANTS = {
    "valve-poly.yaml": (RISE, "  - rise:\n      angle: 110\n      lift: 9\n"
                              "      law: polynomial\n"
                              "      start: {velocity: 0, acceleration: 0, jerk: 0}\n"
                              "      end: {velocity: 0, acceleration: 0, jerk: 0}\n"
                              "      points: [[36.6667, 3], [73.3333, 6]]"),
    "valve-spline.yaml": (RISE, "  - rise:   {angle: 110, lift: 9, law: spline, "
                                "controls: [0.1, 0.4, 0.6, 0.9]}"),
    "valve-muv.yaml": ("law: polynomial-4567}", "law: modified-uniform-velocity, blend: 0.2}"),
}
PLATE = """\
name: plate-poly
cam: {type: disc, speed_rpm: 300, base_radius: 40, thickness: 8}
follower: {type: roller, roller_radius: 8}
motion:
  - rise: {angle: 120, lift: 10, law: polynomial, start: {velocity: 0, acceleration: 0},
           end: {velocity: 0, acceleration: 0}, points: [[40, 2], [80, 8]]}
  - dwell: {angle: 60}
  - return: {angle: 120, law: cycloidal}
  - dwell: {angle: 60}
"""
#: (label, design file, extra options); the first is the standard laws' best.
CASES = (
    ("standard laws, residual over the band", "demo-valve-at-speed.yaml", []),
    ("polynomial points, residual over the band", "valve-poly.yaml", []),
    ("polynomial points, residual at 1500 rpm", "valve-poly.yaml", ["--speeds", "1500"]),
    ("spline controls, residual over the band", "valve-spline.yaml", []),
    ("blends, residual over the band", "valve-muv.yaml", []),
    ("blends, peak contact stress", "valve-muv.yaml", ["--objective", "stress"]),
    ("polynomial points, peak acceleration (LP)", "plate-poly.yaml",
     ["--objective", "acceleration"]),
)

_CHILD = """
import json, resource, sys, time
sys.path.insert(0, {root!r})
from pathlib import Path
from camfab.tune.plan import TuneOptions, plan
from camfab.tune.search import Search
args = {args!r}
speeds = args[args.index("--speeds") + 1] if "--speeds" in args else None
objective = args[args.index("--objective") + 1] if "--objective" in args else None
wall, cpu = time.perf_counter(), time.process_time()
tuning = plan(TuneOptions(Path({design!r}), objective=objective, speeds=speeds,
                          starts={starts}))
search = Search(tuning.evaluator, tuning.start, {starts})
search.run()
print(json.dumps({{"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu,
    "measured": tuning.evaluator.measured, "analysed": tuning.evaluator.analysed,
    "before": search.before.objective, "after": search.best.objective if search.best else None,
    "unit": tuning.objective.unit, "global": search.global_optimum}}))
"""


def run(design: Path, args: list[str], starts: int) -> dict:
    code = _CHILD.format(root=str(ROOT), design=str(design), args=args, starts=starts)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--quick", action="store_true", help="one start a case")
    options = parser.parse_args()
    starts = 1 if options.quick else 4
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        text = VALVE.read_text(encoding="utf-8")
        (work / "demo-valve-at-speed.yaml").write_text(text)
        for name, (old, new) in VARIANTS.items():
            assert old in text, old
            (work / name).write_text(text.replace(old, new))
        (work / "plate-poly.yaml").write_text(PLATE)
        rows = []
        standard = None
        for label, name, args in CASES:
            found = run(work / name, args, starts)
            if standard is None:
                standard = found["after"]
            band = "--speeds" not in args and "--objective" not in args
            ratio = (f"{found['after'] / standard:.3f}" if band and found["after"] else "")
            rows.append((label, f"{found['wall']:.1f}", f"{found['cpu']:.1f}",
                         str(found["measured"]), str(found["analysed"]),
                         f"{found['before']:.4g}", f"{found['after']:.4g}"
                         + (" (global)" if found["global"] else ""), found["unit"], ratio))
            if not options.markdown:
                print(" | ".join(rows[-1]), flush=True)
    if options.markdown:
        print("| case | wall (s) | processor (s) | candidates | analysed | before | after "
              "| unit | after / standard laws' best |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |")
        for row in rows:
            print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
