"""Fuzzing what sets camfab's amount of work: every number that sets how finely it samples
(``table_step``, ``blend``, ``manufacturing.tolerance``, the count and size of motion segments,
a table's points, a nose radius, the part's size against its tolerance) and every file a design
names (a table law's ``csv``: devices, FIFOs, folders, huge files, paths out of the design's
folder).

Each case is a full ``camfab build`` in a child process limited by CPU time and memory
(:func:`tests.limited_child.run_forked`), and must end in seconds of CPU, within a bounded growth
of memory, with exit status 0, 1 or 2; a refusal (2) is one line on stderr naming the design
file, and writes nothing. The cases are the same on every run (``derandomize``).
"""

from __future__ import annotations

import copy
import math
import os
import shutil
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from .fuzz_designs import BASES, dump
from .limited_child import ChildRun, run_forked

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="forks children and reads /proc")

#: Most CPU seconds a case may use. The heaviest designs inside camfab's limits (a groove mesh
#: near its 500,000 facets, a plate cam of a thousand segments, a table of 20,000 points) build
#: in 5-13 s of CPU on the machines camfab is tested on, a flat face undercut on each of a
#: thousand tiny bumps some 40 s (its verification trims the envelope's loops again, eight times
#: as finely as the cam, for the exact outline it measures the files against); a case that hits
#: this limit is a runaway.
CPU_LIMIT = 60.0
#: Most growth of resident memory a case may show (MB). Ordinary builds peak under 300 MB; the
#: worst inside camfab's limits, a flat face folding on each of a thousand tiny bumps (some
#: 380,000 faces of envelope to trim), about 1.2 GB.
MEMORY_LIMIT_MB = 2000.0

NUMBER_CASES = 70
FILE_CASES = 40

#: No shrinking: a runaway case costs its CPU limit on every try, and the case as drawn says
#: enough (its label names what was pushed).
FUZZ = settings(deadline=None, derandomize=True, database=None, print_blob=True,
                phases=[Phase.explicit, Phase.generate],
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])


@dataclass(frozen=True)
class Case:
    """A design file's text and what was done to it (shown instead of the long text)."""

    label: str
    text: str

    def __repr__(self) -> str:
        return f"Case({self.label!r}, {len(self.text):,} characters)"

#: Bases with a motion list, one of each kind of cam (the shaped ones have a shape instead).
MOTION_BASES = ["designs/seed-10-4.yaml", "designs/demo-cylindrical.yaml",
                "designs/demo-linear-roller.yaml", "starters/groove.yaml",
                "starters/conjugate.yaml", "designs/seed-10-3-oscillating.yaml",
                "starters/disc-flat.yaml"]
SHAPED_BASES = ["starters/tangent.yaml", "designs/seed-7-12-exhaust-valve.yaml"]

STATUSES: Counter[tuple[str, int | None]] = Counter()
#: CPU seconds and the largest growth of memory (MB) by case kind.
CPU: Counter[str] = Counter()
PEAK: dict[str, float] = {}


def _log_uniform(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(math.log10(low), math.log10(high)).map(lambda e: float(f"{10 ** e:.3g}"))


def _set(data: dict[str, Any], path: tuple[Any, ...], value: Any) -> None:
    node = data
    for key in path[:-1]:
        node = node.setdefault(key, {}) if isinstance(key, str) else node[key]
    node[path[-1]] = value


def _first_rise(data: dict[str, Any]) -> dict[str, Any] | None:
    for item in data.get("motion") or []:
        if "rise" in item:
            return item["rise"]
    return None


@st.composite
def sampling_cases(draw: Any) -> Case:
    """A design with one or two of the numbers that set its sampling pushed to an extreme."""
    base = draw(st.sampled_from(MOTION_BASES + SHAPED_BASES))
    data = copy.deepcopy(BASES[base])
    data["name"] = "limits"
    shaped = base in SHAPED_BASES
    linear = data["cam"]["type"] == "linear"
    knobs = ["tolerance", "table_step", "size", "size"] + (
        ["nose"] if shaped else ["blend", "segments", "segments", "tiny_segment", "table"])
    done = []
    for knob in draw(st.lists(st.sampled_from(knobs), min_size=1, max_size=2, unique=True)):
        done.append(knob)
        if knob == "tolerance":
            _set(data, ("manufacturing", "tolerance"), draw(st.one_of(
                _log_uniform(1e-16, 100.0), st.sampled_from(["1e-6 mm", "0.0001 in", "1 um"]))))
        elif knob == "table_step":
            data["table_step"] = draw(st.one_of(
                _log_uniform(1e-12, 40.0),
                st.sampled_from([0.01, 0.012, 0.015, 0.02, "1e-9 rad", "0.0001 turn"])))
        elif knob == "size":
            factor = draw(_log_uniform(1e-9, 1e5))
            for key in ("base_radius", "radius", "stroke", "base_height", "length"):
                if isinstance(data["cam"].get(key), (int, float)):
                    data["cam"][key] = float(f"{data['cam'][key] * factor:.6g}")
        elif knob == "nose":
            data["cam"].pop("lift_angle" if data["cam"]["type"] == "tangent" else "flank_angle",
                            None)
            data["cam"]["nose_radius"] = draw(_log_uniform(1e-20, 5.0))
        elif knob == "blend":
            rise = _first_rise(data)
            if rise is not None and not linear:
                rise.update(law="modified-uniform-velocity", blend=draw(st.one_of(
                    _log_uniform(1e-16, 0.5), st.sampled_from([0.001, 0.0011, 0.5]))))
        elif knob == "segments":
            count = draw(st.sampled_from([2, 10, 100, 999, 1000, 1001, 3000]))
            data["motion"] = _many_segments(data, count, draw(st.booleans()))
        elif knob == "tiny_segment":
            motion = data["motion"]
            span = "travel" if linear else "angle"
            first = next(iter(motion[0].values()))
            tiny = draw(_log_uniform(1e-12, 1e-3))
            first[span] = float(first[span]) - tiny
            motion.insert(1, {"dwell": {span: tiny}})
        elif knob == "table" and not linear:
            rise = _first_rise(data)
            if rise is not None:
                count = draw(st.sampled_from([2, 3, 50, 2000, 20_000]))
                angle = float(rise["angle"])
                lift = float(rise.get("lift", 10.0))
                rise.clear()
                rise.update(angle=angle, law="table", points=[
                    [round(angle * i / (count - 1), 9),
                     round(lift * (i / (count - 1)) ** 2 * (3 - 2 * i / (count - 1)), 9)]
                    for i in range(count)])
    return Case(f"{base} {'+'.join(done)}", dump(data))


def _many_segments(data: dict[str, Any], count: int, rising: bool) -> list[dict[str, Any]]:
    """*count* segments sharing the cycle: rises and returns of a small lift, or dwells."""
    linear = data["cam"]["type"] == "linear"
    span = "travel" if linear else "angle"
    total = float(data["cam"]["stroke"]) if linear else 360.0
    step = total / count
    oscillating = (data.get("follower") or {}).get("motion") == "oscillating"
    lift = 0.05 if oscillating else 0.2
    if not rising or count % 2:
        return [{"dwell": {span: step}} for _ in range(count)]
    out: list[dict[str, Any]] = []
    for i in range(count):
        kind = "rise" if i % 2 == 0 else "return"
        body: dict[str, Any] = {span: step, "law": "cycloidal"}
        if kind == "rise":
            body["lift"] = lift
        out.append({kind: body})
    return out


#: What a table law's ``csv`` may name, and how to make it in the case's folder.
FILE_KINDS = ["dev-zero", "dev-urandom", "dev-null", "fifo", "folder", "absolute", "parent",
              "symlink-device", "symlink-outside", "symlink-loop", "huge", "many-rows", "binary",
              "empty", "good", "missing", "nested-good"]


@st.composite
def file_cases(draw: Any) -> Case:
    base = draw(st.sampled_from(["designs/demo-table.yaml", "designs/seed-10-4.yaml",
                                 "designs/seed-10-3-oscillating.yaml"]))
    data = copy.deepcopy(BASES[base])
    data["name"] = "limits"
    kind = draw(st.sampled_from(FILE_KINDS))
    rise = _first_rise(data)
    assert rise is not None
    rise.clear()
    rise.update(angle=90, law="table", csv=_csv_name(kind))  # the rows span 90°
    data["motion"] = _fit_first(rise, 90.0)
    return Case(kind, dump(data))


def _fit_first(rise: dict[str, Any], angle: float) -> list[dict[str, Any]]:
    """A program of the *rise*, *angle* long, then a dwell, a return and a dwell sharing the
    rest of the cycle, so a good table builds."""
    rest = 360.0 - angle
    return [{"rise": rise}, {"dwell": {"angle": rest / 3}},
            {"return": {"angle": rest / 3, "law": "cycloidal"}}, {"dwell": {"angle": rest / 3}}]


def _csv_name(kind: str) -> str:
    return {"dev-zero": "/dev/zero", "dev-urandom": "/dev/urandom", "dev-null": "/dev/null",
            "absolute": "ABSOLUTE", "parent": "../outside.csv", "nested-good": "data/lift.csv",
            "missing": "nope.csv"}.get(kind, f"{kind}.csv")


def _lift_rows(count: int) -> str:
    return "".join(f"{90 * i / (count - 1):.6f},{10 * (i / (count - 1)) ** 2:.6f}\n"
                   for i in range(count))


def _make_files(kind: str, folder: Path, design_text: str) -> str:
    """Make the file *kind* names in *folder*; the design text with its path filled in."""
    outside = folder.parent / "outside.csv"
    outside.write_text(_lift_rows(10))
    if kind == "fifo":
        os.mkfifo(folder / "fifo.csv")
    elif kind == "folder":
        (folder / "folder.csv").mkdir()
    elif kind == "symlink-device":
        (folder / "symlink-device.csv").symlink_to("/dev/zero")
    elif kind == "symlink-outside":
        (folder / "symlink-outside.csv").symlink_to(outside)
    elif kind == "symlink-loop":
        (folder / "symlink-loop.csv").symlink_to("loop.csv")
        (folder / "loop.csv").symlink_to("symlink-loop.csv")
    elif kind == "huge":
        with open(folder / "huge.csv", "w") as stream:
            stream.write(_lift_rows(10))
            stream.write("# " + "x" * 1_100_000 + "\n")
    elif kind == "many-rows":
        (folder / "many-rows.csv").write_text(_lift_rows(25_000))
    elif kind == "binary":
        (folder / "binary.csv").write_bytes(bytes(range(256)) * 64)
    elif kind == "empty":
        (folder / "empty.csv").write_text("")
    elif kind == "good":
        (folder / "good.csv").write_text("angle,lift\n" + _lift_rows(50))
    elif kind == "nested-good":
        (folder / "data").mkdir()
        (folder / "data" / "lift.csv").write_text(_lift_rows(50))
    return design_text.replace("ABSOLUTE", str(outside))


def _check(run: ChildRun, folder: Path, before: set[str]) -> None:
    assert run.code in (0, 1, 2), run.describe()
    assert run.cpu_s < CPU_LIMIT, run.describe()
    assert run.peak_mb < MEMORY_LIMIT_MB, run.describe()
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr, run.describe()
    files = {str(p.relative_to(folder)) for p in folder.rglob("*")}
    if run.code == 2:
        lines = run.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("design.yaml:"), run.describe()
        assert files == before, f"a refused build wrote {sorted(files - before)}"
    else:
        assert not run.stderr.strip(), run.describe()
        assert not [f for f in files if f.endswith(".tmp")], sorted(files)


def _build(tmp_path_factory: pytest.TempPathFactory, text: str, kind: str = "") -> ChildRun:
    root = tmp_path_factory.mktemp("limits")
    folder = root / "case"
    folder.mkdir()
    text = _make_files(kind, folder, text) if kind else text
    (folder / "design.yaml").write_text(text, encoding="utf-8")
    before = {str(p.relative_to(folder)) for p in folder.rglob("*")}
    run = run_forked(["build", "design.yaml", "-o", "out"], folder, CPU_LIMIT + 5)
    _check(run, folder, before)
    shutil.rmtree(root, ignore_errors=True)
    key = kind or "sampling"
    CPU[key] += run.cpu_s
    PEAK[key] = max(PEAK.get(key, 0.0), run.peak_mb)
    return run


@settings(FUZZ, max_examples=NUMBER_CASES)
@given(sampling_cases())
def test_sampling_numbers_end_in_bounded_work(tmp_path_factory: pytest.TempPathFactory,
                                              case: Case) -> None:
    label, text = case.label, case.text
    run = _build(tmp_path_factory, text)
    STATUSES[label.split()[-1], run.code] += 1
    CPU[label] += run.cpu_s


@settings(FUZZ, max_examples=FILE_CASES)
@given(file_cases())
def test_file_references_end_in_bounded_work(tmp_path_factory: pytest.TempPathFactory,
                                             case: Case) -> None:
    kind, text = case.label, case.text
    run = _build(tmp_path_factory, text, kind)
    STATUSES[kind, run.code] += 1
    if kind in ("good", "nested-good"):
        assert run.code in (0, 1), run.describe()
    else:
        assert run.code == 2, run.describe()


#: (kind, words of the message) for every kind of file reference, each run once.
FILE_MESSAGES = [
    ("dev-zero", "must name a file in the design file's folder"),
    ("absolute", "must name a file in the design file's folder"),
    ("parent", "must name a file in the design file's folder"),
    ("symlink-outside", "must name a file in the design file's folder"),
    ("symlink-device", "must name a file in the design file's folder"),
    ("fifo", "fifo.csv is not a regular file but a FIFO (a pipe); a table must be a file"),
    ("folder", "folder.csv is a folder, not a table"),
    ("huge", "huge.csv is 1,100,"),
    ("many-rows", "more than 20,000 rows"),
    ("binary", "not a UTF-8 text file"),
    ("missing", "nope.csv no such file"),
]


@pytest.mark.parametrize(("kind", "words"), FILE_MESSAGES, ids=[k for k, _ in FILE_MESSAGES])
def test_each_bad_file_reference_is_named_on_its_line(tmp_path_factory: pytest.TempPathFactory,
                                                      kind: str, words: str) -> None:
    data = copy.deepcopy(BASES["designs/demo-table.yaml"])
    data["name"] = "limits"
    rise = _first_rise(data)
    assert rise is not None
    rise.clear()
    rise.update(angle=90, law="table", csv=_csv_name(kind))
    data["motion"] = _fit_first(rise, 90.0)
    text = dump(data)
    line = next(i for i, t in enumerate(text.splitlines(), 1) if "csv:" in t)
    run = _build(tmp_path_factory, text, kind)
    assert run.code == 2
    assert run.stderr.startswith(f"design.yaml:{line}: motion[0].csv: "), run.stderr
    assert words in run.stderr, run.stderr


def test_a_fifo_as_the_design_file_is_refused_at_once(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "design.yaml")
    for device in ("design.yaml", "/dev/zero", "/dev/urandom"):
        run = run_forked(["build", device], tmp_path, 10)
        assert run.code == 2, run.describe()
        assert run.stderr.strip().startswith(f"{device}: is not a regular file but "), run.stderr
        assert run.cpu_s < 5, run.describe()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["design.yaml"]


def test_zz_statuses() -> None:
    """What the fuzzing did, by case kind and exit status (printed with -s)."""
    print(f"\nlimit fuzz statuses: {dict(sorted(STATUSES.items(), key=str))}")
    print(f"CPU seconds: {dict(CPU)}; peak growth of memory (MB): {PEAK}")
    assert yaml is not None
