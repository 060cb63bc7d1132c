"""Build N random but ordinary valid designs of every cam type and follower and print, per kind,
how the builds ended: exit 0/1/2, internal errors, refusals not on one located line, and the
``verification`` check failed (the files do not hold the design), with its deviation over the
tolerance. Each failing design's YAML is saved, to hand on as a reproducer.

    python scripts/random_builds.py                       # 1000 designs, seed 0, one at a time
    python scripts/random_builds.py -n 200 --seed 7 --jobs 2 --out /tmp/failing
    python scripts/random_builds.py --kinds cylindrical,disc/roller -n 50
    python scripts/random_builds.py --replay /tmp/failing/r7-0042.yaml   # one file again

The designs come from ``tests/valid_designs.py`` (the property test's definition of a valid
design), design *i* of a run from ``random.Random(f"{seed}-{i}")`` and the kinds taken in turn,
so a run is reproducible from its seed and count. Each build runs in a child forked from this
process, under ``--cpu`` seconds of CPU time (past it the build counts as an internal error).
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time
from collections import Counter, defaultdict
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.valid_designs import KINDS, design  # noqa: E402
from tests.whole_builds import BUILD_CPU_S, BuildOutcome, build_design, dump  # noqa: E402

#: The deviation/tolerance ratios a failed verification is classed by.
RATIO_BANDS = ((1.2, "1-1.2x"), (2.0, "1.2-2x"), (10.0, "2-10x"), (float("inf"), ">=10x"))


def band(ratio: float | None) -> str:
    """The band of a deviation/tolerance *ratio* (None: the lift is not compared)."""
    if ratio is None:
        return "lift not compared"
    if ratio <= 1.0:
        return "lift within tolerance"
    return next(name for top, name in RATIO_BANDS if ratio < top)


def chosen_kinds(spec: str | None) -> list[str]:
    """The kinds whose name starts with one of the comma-separated *spec* (all when None)."""
    if not spec:
        return list(KINDS)
    wanted = [s.strip() for s in spec.split(",") if s.strip()]
    kinds = [k for k in KINDS if any(k.startswith(w) for w in wanted)]
    if not kinds:
        sys.exit(f"--kinds {spec}: no kind matches; the kinds are {', '.join(KINDS)}")
    return kinds


def one(task: tuple[str, str, str, float]) -> dict[str, Any]:
    """Build one design (``name``, ``kind``, YAML text, CPU limit): its row of results."""
    name, kind, text, cpu_s = task
    outcome = build_design(text, cpu_s)
    return row(name, kind, text, outcome)


def row(name: str, kind: str, text: str, outcome: BuildOutcome) -> dict[str, Any]:
    check = outcome.verification or {}
    return {
        "name": name, "kind": kind, "code": outcome.code, "cpu_s": round(outcome.cpu_s, 2),
        "internal": outcome.internal_error,
        "unlocated": outcome.unlocated_refusal("design.yaml"),
        "refusal": outcome.stderr.strip()[:300] if outcome.code == 2 else None,
        "verification_failed": outcome.verification_failed,
        "ratio": outcome.ratio, "stl_unclean": outcome.stl_unclean,
        "verification": check.get("message"), "other_failed": outcome.failed_checks,
        "steps": outcome.steps,
        "verification_na": bool(check) and check.get("ok") is None,
        "text": text,
    }


def failing(result: dict[str, Any]) -> bool:
    return bool(result["internal"] or result["unlocated"] or result["verification_failed"])


def describe(result: dict[str, Any]) -> str:
    if result["internal"]:
        return f"INTERNAL ERROR: {result['internal'][:300]}"
    if result["unlocated"]:
        return f"UNLOCATED REFUSAL: {result['unlocated']}"
    other = ", ".join(result["other_failed"]) or "none"
    ratio = result["ratio"]
    return (f"VERIFICATION {ratio:.3g}x" if ratio is not None else "VERIFICATION") + (
        " (STL not clean)" if result["stl_unclean"] else "") + (
        f"; other failed checks: {other}; {result['verification']}")


def save(result: dict[str, Any], out: Path) -> Path:
    """The failing design's YAML, with what failed in comments at its head."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{result['name']}.yaml"
    head = [f"# {result['kind']}: exit {result['code']}, {result['cpu_s']} s CPU",
            *(f"# {line}" for line in _wrapped(describe(result)))]
    path.write_text("\n".join(head) + "\n" + result["text"], encoding="utf-8")
    return path


def _wrapped(text: str, width: int = 98) -> list[str]:
    words, lines, line = text.split(), [], ""
    for word in words:
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return [*lines, line] if line else lines


def table(results: list[dict[str, Any]]) -> list[str]:
    """The table per kind (markdown)."""
    head = ("| kind | designs | exit 0 | exit 1 | exit 2 | internal errors | unlocated exit 2 "
            "| verification failed | …with no other check failed | worst ratio | CPU s (max) |")
    lines = [head, "| --- | " + " | ".join(["---:"] * 10) + " |"]
    by_kind: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for result in results:
        by_kind[result["kind"]].append(result)
    total: Counter[str] = Counter()
    for kind in [*KINDS, *sorted(set(by_kind) - set(KINDS))]:
        rows = by_kind.get(kind)
        if not rows:
            continue
        counts = Counter({
            "n": len(rows), "0": sum(r["code"] == 0 and not r["internal"] for r in rows),
            "1": sum(r["code"] == 1 and not r["internal"] for r in rows),
            "2": sum(r["code"] == 2 and not r["internal"] for r in rows),
            "internal": sum(bool(r["internal"]) for r in rows),
            "unlocated": sum(bool(r["unlocated"]) for r in rows),
            "verif": sum(r["verification_failed"] for r in rows),
            "clean": sum(r["verification_failed"] and not r["other_failed"] for r in rows)})
        total.update(counts)
        ratios = [r["ratio"] for r in rows if r["verification_failed"] and r["ratio"]]
        worst = f"{max(ratios):.3g}" if ratios else ""
        cpu = max(r["cpu_s"] for r in rows)
        lines.append(f"| {kind} | {counts['n']} | {counts['0']} | {counts['1']} | {counts['2']} "
                     f"| {counts['internal']} | {counts['unlocated']} | {counts['verif']} "
                     f"| {counts['clean']} | {worst} | {cpu:.1f} |")
    lines.append(f"| **all** | {total['n']} | {total['0']} | {total['1']} | {total['2']} "
                 f"| {total['internal']} | {total['unlocated']} | {total['verif']} "
                 f"| {total['clean']} | | |")
    return lines


def cause(result: dict[str, Any]) -> str:
    """What about the design a failed verification goes with: an undercut, a step in the
    velocity or the acceleration, or none (smooth motion, every other check passed or not)."""
    if any(c.startswith("undercut") for c in result["other_failed"]):
        return "undercut"
    steps = result.get("steps") or []
    if "velocity" in steps:
        return "velocity step"
    if "acceleration" in steps:
        return "acceleration step"
    return "smooth motion" + ("" if result["other_failed"] else ", every other check passed")


def classes(results: list[dict[str, Any]]) -> list[str]:
    """The failures by class: what failed, the kind's cam type, the cause (:func:`cause`), the
    ratio's band; each with its count and its designs (the smallest file first)."""
    groups: dict[tuple[str, ...], list[dict[str, Any]]] = defaultdict(list)
    for r in results:
        if r["internal"]:
            groups[("internal error", r["kind"].split("/")[0], "")].append(r)
        elif r["unlocated"]:
            groups[("unlocated exit 2", r["kind"].split("/")[0], "")].append(r)
        elif r["verification_failed"]:
            what = "verification, STL not clean" if r["stl_unclean"] else "verification"
            groups[(what, r["kind"].split("/")[0], cause(r), band(r["ratio"]))].append(r)
    lines = []
    for key in sorted(groups, key=lambda k: (-len(groups[k]), k)):
        rows = sorted(groups[key], key=lambda r: len(r["text"]))
        names = ", ".join(f"{r['name']}.yaml" for r in rows[:6])
        more = f" and {len(rows) - 6} more" if len(rows) > 6 else ""
        lines.append(f"- {' / '.join(k for k in key if k)}: {len(rows)} — {names}{more}")
    return lines


def replayed(text: str) -> tuple[str, str]:
    """The kind and the design of a saved design file (its kind from the comment at its head,
    which is left out), or ``replay`` and the whole text for another file."""
    lines = text.splitlines(keepends=True)
    head = 0
    while head < len(lines) and lines[head].startswith("#"):
        head += 1
    kind = lines[0][2:].split(":")[0] if head and lines[0][2:].split(":")[0] in KINDS else None
    return (kind, "".join(lines[head:])) if kind else ("replay", text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-n", "--count", type=int, default=1000, help="designs (default 1000)")
    parser.add_argument("--seed", default="0", help="the run's seed (default 0)")
    parser.add_argument("--jobs", type=int, default=1, help="builds at once (default 1)")
    parser.add_argument("--kinds", help="only the kinds starting with one of these "
                        "(comma-separated, e.g. cylindrical,disc/roller)")
    parser.add_argument("--out", type=Path, default=Path("random-builds"),
                        help="folder for the failing designs' YAML and results.jsonl "
                        "(default ./random-builds)")
    parser.add_argument("--cpu", type=float, default=BUILD_CPU_S,
                        help=f"CPU seconds a build may take (default {BUILD_CPU_S:g})")
    parser.add_argument("--replay", nargs="+", type=Path,
                        help="build these design files instead (each judged the same way)")
    args = parser.parse_args()

    if args.replay:
        tasks = [(p.stem, *replayed(p.read_text(encoding="utf-8")), args.cpu)
                 for p in args.replay]
    else:
        kinds = chosen_kinds(args.kinds)
        tasks = []
        for i in range(args.count):
            name = f"r{args.seed}-{i:04d}"
            kind, data = design(random.Random(f"{args.seed}-{i}"), kinds[i % len(kinds)], name)
            tasks.append((name, kind, dump(data), args.cpu))
    args.out.mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    results: list[dict[str, Any]] = []
    with open(args.out / "results.jsonl", "w", encoding="utf-8") as log:
        if args.jobs > 1:
            with ProcessPoolExecutor(args.jobs) as pool:
                outcomes = pool.map(one, tasks)
                for result in outcomes:
                    _record(result, results, log, args.out, len(tasks))
        else:
            for task in tasks:
                _record(one(task), results, log, args.out, len(tasks))
    print()
    print(f"{len(results)} designs" + ("" if args.replay else f" (seed {args.seed})")
          + f" in {time.monotonic() - started:.0f} s")
    print()
    print("\n".join(table(results)))
    failures = classes(results)
    if failures:
        print()
        print(f"failure classes (designs in {args.out}/):")
        print("\n".join(failures))


def _record(result: dict[str, Any], results: list[dict[str, Any]], log: Any, out: Path,
            count: int) -> None:
    results.append(result)
    log.write(json.dumps({k: v for k, v in result.items() if k != "text"}) + "\n")
    log.flush()
    if failing(result):
        path = save(result, out)
        print(f"[{len(results)}/{count}] {result['name']} {result['kind']}: "
              f"{describe(result)[:300]} -> {path}", flush=True)
    elif len(results) % 25 == 0:
        print(f"[{len(results)}/{count}] ...", flush=True)


if __name__ == "__main__":
    main()
