"""Fuzzing ``camfab sweep`` as the build's inputs are fuzzed (:mod:`tests.test_fuzz_limits`):
generated ``--vary`` ranges, lists and paths, variants files (broken CSV, long fields, bytes
that are not text, repeated keys), design names, objectives, formats, scheduler addresses and
output folders.

Each case is a full ``camfab sweep`` in a child forked from this process under limits of CPU
time and memory (:func:`tests.limited_child.run_forked`), and must end with exit status 0, 1 or
2: a refusal (2) is one line on stderr and writes nothing; no case writes outside its ``-o``
folder or leaves a temporary file. The sweeps that run are kept to a few variants, so the cases
cost their refusals and their start, and some hundreds run in well under a minute. The cases
are the same on every run (``derandomize``).
"""

from __future__ import annotations

import math
import os
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from camfab.sweep.vary import SweepError, parse_spec

from .conftest import DESIGNS
from .limited_child import run_forked

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="forks children and reads /proc")

CASES = 520
#: Most CPU seconds a case may use: a refusal takes a few hundredths, a sweep of a dozen
#: variants well under a second.
CPU_LIMIT = 20.0
#: Most variants a generated sweep that runs may have (count).
MOST_VARIANTS = 6
#: Most growth of resident memory a case may show (MB).
MEMORY_LIMIT_MB = 600.0

SEED_TEXT = (DESIGNS / "seed-10-4.yaml").read_text()
PATHS = ["cam.base_radius", "follower.offset", "follower.roller_radius", "cam.speed_rpm",
         "motion[0].law", "motion[0].angle", "motion[2].law", "motion[9].law", "name",
         "cam.type", "limits.pressure_angle", "cam", "motion[0]", "follower.offset.x",
         "Cam.Base", "cam..x", "../x", "", "a" * 300, "motion[99999999999999999999].law"]
NAMES = [None, "ok-name", "../../escaped", "/tmp/camfab-fuzz-abs", ".hidden", "a/b",
         "x" * 120, "ünï", ""]
COLUMNS = ["cam.base_radius", "variant", "status", "pressure_angle_max_deg", "undercut",
           "roller_life_h", "nonsense", ""]
SCHEDULERS = ["", " ", "ucx://h:1", "tls://h:1", "http://h:8787", "nonsense", "tcp://",
              "tcp://:0", "tcp://h:99999", "[::1:8786", "tcp://h:port"]
FUZZ = settings(max_examples=CASES, deadline=None, derandomize=True, database=None,
                print_blob=True, phases=[Phase.explicit, Phase.generate],
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])
STATUSES: Counter[int] = Counter()


@dataclass(frozen=True)
class Case:
    """A sweep's arguments, its design's text, and its variants file's bytes (or None)."""

    label: str
    args: tuple[str, ...]
    design: str
    variants: bytes | None

    def __repr__(self) -> str:
        return f"Case({self.label!r}, {self.args!r})"


_NUMBER = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**30, 10**30).map(str),
    st.sampled_from(["1e-320", "1e308", "-1e308", "5e-324", "nan", "inf", "-0", "1_0", "0x10",
                     "20", "40", "0.5", "", " ", "2 mm", "1e400"]))
_TEXT = st.text(st.characters(codec="utf-8", exclude_categories=["Cs"]), max_size=12)


@st.composite
def specs(draw: Any) -> str:
    """A --vary SPEC: a range, a log range, a list, or anything."""
    kind = draw(st.sampled_from(["range", "range", "log", "list", "list", "text"]))
    if kind == "range":
        return ":".join(draw(st.lists(_NUMBER, min_size=2, max_size=4)))
    if kind == "log":
        return "log:" + ":".join(draw(st.lists(_NUMBER, min_size=1, max_size=4)))
    if kind == "list":
        items = draw(st.lists(st.one_of(_NUMBER, _TEXT,
                                        st.sampled_from(["cycloidal", "harmonic", "1 in"])),
                              min_size=1, max_size=4))
        return ",".join(items)
    return draw(_TEXT)


def _count(spec: str) -> int | None:
    """How many values *spec* gives, or None when camfab refuses it."""
    try:
        return len(parse_spec(spec.strip(), "--vary x"))
    except SweepError:
        return None


@st.composite
def variants_files(draw: Any) -> bytes:
    """A --variants file: a header of paths and a few rows, often broken."""
    header = draw(st.lists(st.sampled_from(PATHS), min_size=0, max_size=4))
    rows = draw(st.lists(st.lists(st.one_of(_NUMBER, _TEXT), min_size=0, max_size=5),
                         min_size=0, max_size=MOST_VARIANTS))
    text = "\n".join([",".join(header), *(",".join(r) for r in rows)]) + "\n"
    damage = draw(st.sampled_from(["none", "none", "none", "quote", "long", "nul", "bytes",
                                   "crlf", "bom"]))
    data = text.encode("utf-8")
    if damage == "quote":
        data = data.replace(b",", b',"', 1)
    elif damage == "long":
        data += b"9" * draw(st.sampled_from([200, 140_000])) + b"\n"
    elif damage == "nul":
        data = data.replace(b",", b"\x00", 1)
    elif damage == "bytes":
        data += b"\xff\xfe\x80\n"
    elif damage == "crlf":
        data = data.replace(b"\n", b"\r\n")
    elif damage == "bom":
        data = b"\xef\xbb\xbf" + data
    return data


@st.composite
def plain_cases(draw: Any) -> Case:
    """A sweep that runs: one or two keys of the design, two or three values between them."""
    first = draw(st.sampled_from(["cam.base_radius=20,30", "cam.base_radius=15:25:10",
                                  "follower.offset=0,5", "motion[0].law=cycloidal,harmonic",
                                  "cam.speed_rpm=log:500:2000:2", "follower.roller_radius=0,5"]))
    args = ["--vary", first]
    if draw(st.booleans()):
        args += ["--vary", draw(st.sampled_from(["motion[2].law=cycloidal",
                                                 "limits.pressure_angle=20"]))]
    args += draw(st.sampled_from([[], ["--format", "csv"], ["--format", "parquet"],
                                  ["--minimize", "pressure_angle_max_deg"],
                                  ["--maximize", "roller_life_h"]]))
    out = draw(st.sampled_from(["out", "out/deep/er"]))
    return Case("plain " + " ".join(args), ("sweep", "design.yaml", *args, "-o", out, "-j", "1"),
                SEED_TEXT, None)


@st.composite
def cases(draw: Any) -> Case:
    """A sweep's options, design and variants (see the module): a quarter of them sweeps that
    should run (keys of the design, a few values each), the rest anything."""
    if draw(st.integers(0, 3)) == 0:
        return draw(plain_cases())
    args: list[str] = []
    labels = []
    variants = None
    if draw(st.integers(0, 9)) < 3:
        variants = draw(variants_files())
        args += ["--variants", "variants.csv"]
        labels.append("variants")
    varies = draw(st.lists(st.tuples(st.sampled_from(PATHS), specs()),
                           max_size=3 if variants is None else 1))
    product = 1
    for path, spec in varies:
        count = _count(spec)
        if count is not None:
            if product * count > MOST_VARIANTS:  # a sweep that runs stays small
                spec = "20,30"
                count = 2
            product *= count
        args += ["--vary", f"{path}={spec}"]
        labels.append(f"vary {path}")
    name = draw(st.sampled_from(NAMES))
    design = SEED_TEXT
    if name is not None:
        design = design.replace("name: seed-10-4", f"name: {name!r}" if name else "name:", 1)
        labels.append(f"name {name!r}")
    for option in draw(st.lists(st.sampled_from(["format", "minimize", "maximize", "jobs",
                                                 "scheduler", "size", "build-best", "out",
                                                 "progress"]), max_size=3, unique=True)):
        labels.append(option)
        if option == "format":
            args += ["--format", draw(st.sampled_from(["csv", "parquet", "xlsx"]))]
        elif option in ("minimize", "maximize"):
            args += [f"--{option}", draw(st.sampled_from(COLUMNS))]
        elif option == "jobs":
            args += ["-j", draw(st.sampled_from(["0", "2", "-1", "x", "257"]))]
        elif option == "scheduler":
            args += ["--scheduler", draw(st.sampled_from(SCHEDULERS))]
        elif option == "size":
            args.append("--size")
        elif option == "build-best":
            args += ["--build-best", draw(st.sampled_from(["0", "1", "-1", "1001"]))]
        elif option == "out":
            args += ["-o", draw(st.sampled_from(["out/deep/er", "/proc/self", "design.yaml",
                                                 "out/../out2"]))]
        elif option == "progress":
            args.append("--progress")
    if "-o" not in args:
        args += ["-o", "out"]
    if "-j" not in args:
        args += ["-j", "1"]
    return Case(", ".join(labels) or "bare", ("sweep", "design.yaml", *args), design, variants)


def _within(path: str, folder: str) -> bool:
    """True when *path* is *folder*, inside it, or a folder above it (made to hold it)."""
    return path == folder or path.startswith(folder + "/") or folder.startswith(path + "/")


def _files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


@given(case=cases())
@FUZZ
def test_every_sweep_ends_in_one_line_or_its_files(tmp_path_factory: pytest.TempPathFactory,
                                                   case: Case) -> None:
    folder = tmp_path_factory.mktemp("sweep-fuzz")
    (folder / "design.yaml").write_text(case.design)
    if case.variants is not None:
        (folder / "variants.csv").write_bytes(case.variants)
    before = _files(folder)
    outside = Path("/tmp/camfab-fuzz-abs-sweep")
    run = run_forked(list(case.args), folder, cpu_s=CPU_LIMIT, wall_s=300.0)
    STATUSES[run.code] += 1
    assert run.code in (0, 1, 2), run.describe()
    assert run.cpu_s < CPU_LIMIT and run.peak_mb < MEMORY_LIMIT_MB, run.describe()
    after = _files(folder)
    out = case.args[case.args.index("-o") + 1]
    if run.code == 2:
        assert len(run.stderr.strip().split("\n")) == 1, run.describe()
        assert after == before, sorted(after - before)
    else:
        inside = os.path.normpath(out)
        assert all(_within(os.path.normpath(p), inside) for p in after - before), \
            sorted(after - before)
    assert not any(p.endswith(".tmp") for p in after), sorted(after)
    assert not outside.exists() and not any(Path("/tmp").glob("camfab-fuzz-abs*"))
    assert math.isfinite(run.wall_s)


def test_the_fuzz_cases_reach_every_outcome() -> None:
    """(After the fuzz test, in the same process.) Refusals, sweeps that run, and enough of
    both: the generator is not stuck on one kind of case."""
    if not STATUSES:
        pytest.skip("the fuzz test did not run in this process")
    assert sum(STATUSES.values()) >= CASES, STATUSES
    assert STATUSES[2] >= 100 and STATUSES[0] + STATUSES[1] >= 40, STATUSES
