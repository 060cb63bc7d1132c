"""Stop ``camfab build`` with a signal at random moments and tally what each stop left.

Each trial restores an earlier set of files in the output folder, starts a build of the same
design changed (so that every file of the new set differs from the old), and sends SIGINT or
SIGTERM: at a random delay from the start (``--when start``), or a random few milliseconds after
the first temporary file appears in the folder (``--when writing``: the stop lands while the
files are written and renamed). It then tallies the folder (the old set whole, the new set
whole, a mix, temporary files left) and how camfab ended (status, the lines on stderr)::

    python scripts/stop_trials.py --trials 40 --signal INT --when writing

A good result: every trial "old" or "new", no temporary file, and every trial's status the
build's own (0, 1) with nothing on stderr or 128 + the signal with its one line.
"""

from __future__ import annotations

import argparse
import collections
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "designs" / "seed-10-4.yaml"
LINES = {signal.SIGINT: "camfab: interrupted", signal.SIGTERM: "camfab: stopped by signal 15"}


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    return env


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir()} if folder.exists() else {}


def _build(design: Path, out: Path) -> None:
    subprocess.run([sys.executable, "-m", "camfab", "build", str(design), "-o", str(out)],
                   env=_env(), stdout=subprocess.DEVNULL, check=False)


def _stops_not_ignored() -> None:
    """In the child: Ctrl-C and SIGTERM as a terminal's program has them (a shell's background
    job starts with Ctrl-C ignored, which camfab keeps)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=40)
    parser.add_argument("--signal", choices=("INT", "TERM"), default="INT")
    parser.add_argument("--when", choices=("start", "writing"), default="writing")
    parser.add_argument("--most", type=float, default=0.03,
                        help="the largest random delay, seconds (after the first temporary "
                             "file; from the start with --when start)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    signum = getattr(signal, f"SIG{args.signal}")
    rng = random.Random(args.seed)
    tally: collections.Counter[str] = collections.Counter()
    with tempfile.TemporaryDirectory(prefix="camfab-stops-") as tmp:
        work = Path(tmp)
        old_design, new_design = work / "old.yaml", DESIGN
        old_design.write_text(DESIGN.read_text().replace("base_radius: 20", "base_radius: 21"))
        assert old_design.read_text() != DESIGN.read_text()
        reference_old, reference_new = work / "ref-old", work / "ref-new"
        _build(old_design, reference_old)
        _build(new_design, reference_new)
        old, new = _snapshot(reference_old), _snapshot(reference_new)
        assert old.keys() == new.keys() and all(old[k] != new[k] for k in old), "sets alike"
        for trial in range(args.trials):
            out = work / "out"
            shutil.rmtree(out, ignore_errors=True)
            shutil.copytree(reference_old, out)
            child = subprocess.Popen([sys.executable, "-m", "camfab", "build", str(new_design),
                                      "-o", str(out)], env=_env(), stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True,
                                     preexec_fn=_stops_not_ignored)
            delay = rng.uniform(0.0, args.most)
            if args.when == "writing":
                while child.poll() is None and not any(
                        n.endswith(".tmp") for n in os.listdir(out)):
                    pass
            time.sleep(delay)
            child.send_signal(signum)
            _, err = child.communicate(timeout=600)
            files = _snapshot(out)
            temps = [n for n in files if n.endswith(".tmp")]
            final = {k: v for k, v in files.items() if not k.endswith(".tmp")}
            state = "old" if final == old else "new" if final == new else "mixed"
            lines = err.strip().splitlines()
            if child.returncode == 128 + signum and lines == [LINES[signum]]:
                ending = "stopped, one line"
            elif child.returncode in (0, 1) and not lines:
                ending = "done before the stop"
            else:
                ending = f"status {child.returncode}, {len(lines)} line(s)"
            tally[state] += 1
            tally[ending] += 1
            tally["temporary file left"] += bool(temps)
            if state == "mixed" or temps or ending.startswith("status"):
                print(f"trial {trial}: delay {delay * 1000:.1f} ms: {state}, temps {temps}, "
                      f"{ending}: {lines[-3:]}", flush=True)
    print(f"{args.trials} trials, SIG{args.signal}, --when {args.when}, "
          f"delay up to {args.most * 1000:.0f} ms:")
    for key, count in sorted(tally.items()):
        print(f"  {key}: {count}")


if __name__ == "__main__":
    main()
