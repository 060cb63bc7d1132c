"""Fuzzing the command line with generated and mutated design files (hypothesis).

Every run must end with exit status 0, 1 or 2 — never a traceback or an "internal error" — and
within a few seconds; a refusal (2) is one line naming the file and writes nothing, and a build
(0 or 1) leaves no temporary files behind. Most cases run as ``camfab check`` does (load, rules,
analysis and summary) in this process; a smaller share as a full ``camfab build`` of every
output; whole files that might crash or exhaust a process (binary, huge, deeply nested, alias
bombs) also run as real ``camfab`` processes.

The designs come from :mod:`tests.fuzz_designs`; the cases are the same on every run
(``derandomize``), and ``test_zz_case_count`` reports how many ran.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import signal
import tempfile
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from camfab.cli import _check_one, main

from .fuzz_designs import (
    BASE_TEXTS,
    TABLE_CSV,
    alias_bomb,
    buildable_data,
    csv_texts,
    dump,
    mutated_data,
    nested,
    text_mutations,
    variant,
    whole_files,
)
from .limited_child import run_camfab

#: Generated cases per test (the counts CI runs; ``test_zz_case_count`` checks their sum).
CHECK_CASES = 1800
TEXT_CASES = 700
WHOLE_FILE_CASES = 300
BUILD_CASES = 120

#: Most CPU time a run may use before it counts as a runaway (s): loading and analysing a design
#: takes well under a second, a full build of an absurd one a few seconds. CPU time, not the
#: clock's, so that a busy machine slows the runs without failing them.
CHECK_LIMIT = 5.0
BUILD_LIMIT = 30.0

FUZZ = settings(deadline=None, derandomize=True, database=None, print_blob=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.filter_too_much,
                                       HealthCheck.large_base_example])

CASES: Counter[str] = Counter()
#: Exit statuses of the generated cases, by test (reported with the count).
STATUSES: Counter[tuple[str, int]] = Counter()


class Hang(BaseException):
    """A run over its CPU limit (a BaseException, so camfab's own handlers cannot hide it)."""


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Stop the block when it has used *seconds* of this process's CPU time (SIGPROF counts
    CPU time, user and system, not the clock's)."""
    def expire(signum: int, frame: object) -> None:
        raise Hang(f"no result after {seconds:g} s of CPU time")

    previous = signal.signal(signal.SIGPROF, expire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


@pytest.fixture(scope="module", autouse=True)
def _debug_tracebacks() -> Iterator[None]:
    """With CAMFAB_DEBUG the command line lets an unexpected exception through instead of
    printing its "internal error" line, so hypothesis shows (and shrinks) the real traceback."""
    old = os.environ.get("CAMFAB_DEBUG")
    os.environ["CAMFAB_DEBUG"] = "1"
    yield
    if old is None:
        del os.environ["CAMFAB_DEBUG"]
    else:
        os.environ["CAMFAB_DEBUG"] = old


def _files(folder: Path) -> set[Path]:
    return {p.relative_to(folder) for p in folder.rglob("*")}


def _assert_one_clean_line(err: str, design: Path) -> None:
    message = err.strip()
    assert message, "exit 2 without a message"
    assert "\n" not in message, f"more than one line:\n{err}"
    assert "Traceback" not in message and "internal error" not in message, message
    assert message.startswith(f"{design}:"), f"does not name the file: {message}"


def check_file(data: bytes, csv: bytes | None = None) -> int:
    """``camfab check`` on a file holding *data*, in this process: the status, after the
    contract's assertions (one clean line on a refusal, nothing written, no hang)."""
    with tempfile.TemporaryDirectory(prefix="camfab-fuzz-") as tmp:
        folder = Path(tmp)
        design = folder / "design.yaml"
        design.write_bytes(data)
        if csv is not None:
            (folder / TABLE_CSV).write_bytes(csv)
        before = _files(folder)
        with time_limit(CHECK_LIMIT), contextlib.redirect_stdout(io.StringIO()):
            outcome = _check_one(str(design))
        assert outcome.code in (0, 1, 2), outcome
        err = "\n".join(outcome.err)
        assert "Traceback" not in err and "internal error" not in err, err
        if outcome.code == 2:
            _assert_one_clean_line(err, design)
        assert _files(folder) == before, "camfab check wrote a file"
    return outcome.code


def build_file(text: str, csv: bytes | None = None) -> int:
    """``camfab build FILE -o DIR`` of *text*, in this process, with the same assertions; a
    build that succeeds (0 or 1) must leave its files and no temporary ones."""
    runner = CliRunner()
    with tempfile.TemporaryDirectory(prefix="camfab-fuzz-") as tmp:
        folder = Path(tmp)
        design = folder / "design.yaml"
        design.write_text(text, encoding="utf-8")
        if csv is not None:
            (folder / TABLE_CSV).write_bytes(csv)
        before = _files(folder)
        with time_limit(BUILD_LIMIT):
            result = runner.invoke(main, ["build", str(design), "-o", str(folder / "out")],
                                   catch_exceptions=False)
        assert result.exit_code in (0, 1, 2), result.output
        assert "Traceback" not in result.output and "internal error" not in result.output
        out = folder / "out"
        if result.exit_code == 2:
            _assert_one_clean_line(result.stderr, design)
            assert _files(folder) == before, "a refused build wrote files"
        else:
            written = sorted(p.name for p in out.iterdir())
            assert written, "a build wrote nothing"
            assert not [n for n in written if n.startswith(".") or n.endswith(".tmp")], written
            assert f"wrote {len(written)} file(s)" in result.stdout, result.stdout
    return result.exit_code


def _encode(text: str) -> bytes:
    return text.encode("utf-8", "surrogatepass")


# ---- most cases: mutated designs through the loader, the rules and the analysis --------------

@settings(FUZZ, max_examples=CHECK_CASES)
@given(st.one_of(mutated_data(), buildable_data(max_mutations=3, most_segments=100)),
       st.one_of(st.none(), csv_texts.map(_encode), st.binary(max_size=40)))
def test_mutated_designs_check_or_refuse_cleanly(case: tuple[str, object], csv: bytes | None):
    CASES["check"] += 1
    _, data = case
    STATUSES["check", check_file(_encode(dump(data)), csv)] += 1


@settings(FUZZ, max_examples=TEXT_CASES)
@given(text_mutations())
def test_mutated_yaml_text_checks_or_refuses_cleanly(text: str) -> None:
    CASES["text"] += 1
    STATUSES["text", check_file(_encode(text))] += 1


@settings(FUZZ, max_examples=WHOLE_FILE_CASES)
@given(whole_files())
def test_files_that_are_not_designs_are_refused_cleanly(data: bytes) -> None:
    CASES["whole"] += 1
    STATUSES["whole", check_file(data)] += 1


# ---- a smaller share: full builds of every output --------------------------------------------

@settings(FUZZ, max_examples=BUILD_CASES)
@given(buildable_data(),
       st.one_of(st.none(), csv_texts.map(_encode)))
def test_mutated_designs_build_or_refuse_cleanly(case: tuple[str, object],
                                                  csv: bytes | None) -> None:
    CASES["build"] += 1
    _, data = case
    STATUSES["build", build_file(dump(data), csv)] += 1


# ---- the bugs the fuzzing found, kept as explicit cases --------------------------------------

SEGMENT = "  - dwell: {angle: %s}\n"
DISC = "name: x\ncam: {type: disc, base_radius: %s}\nfollower: {type: knife}\nmotion:\n"
POLY = "designs/seed-poly-345.yaml"

#: (id, file text, status, words of the message): each was a traceback, a hang, a runaway of
#: memory or a wrong value before the fix named.
REGRESSIONS = [
    # source.py: aliases of aliases expanded without bound (a billion laughs)
    ("alias-bomb", alias_bomb(9, 9), 2, "aliases (*name) expand to more than 100,000 values"),
    ("alias-bomb-in-cam", alias_bomb(9, 9, key="cam"), 2, "expand to more than"),
    # source.py: libyaml's composer recursed through 100,000 brackets and overflowed the C stack
    ("deep-flow-nesting", nested(100_000, flow=True), 2, "nested too deeply"),
    ("deep-block-nesting", nested(1000, flow=False), 2, "nested too deeply"),
    # source.py: a few MB of tiny values took many seconds to compose
    ("many-values", "name: x\ndescription: [" + "1, " * 100_001 + "]\n", 2,
     "more than 100,000 values"),
    # source.py: a tag its text does not fit raised a KeyError
    ("bool-tag", DISC.replace("name: x", "name: !!bool x") % 20 + SEGMENT % 360, 0, ""),
    # units.py: pint evaluated the text as arithmetic
    ("pint-power-tower", DISC % "'10**10**10 mm'" + SEGMENT % 360, 2,
     "cam.base_radius: must be a length"),
    ("pint-big-integer", DISC % "'10**400 mm'" + SEGMENT % 360, 2,
     "cam.base_radius: must be a length"),
    ("pint-integer-overflow", DISC % f"'1{'0' * 400} mm'" + SEGMENT % 360, 2, "finite"),
    ("pint-list-as-number", DISC % "'[1,2] mm'" + SEGMENT % 360, 2,
     "cam.base_radius: must be a length"),
    # rules.py: programs of 100,000 segments took minutes
    ("too-many-segments", DISC % 20 + SEGMENT % 0.18 * 2000, 2,
     "motion: has 2,000 segments; camfab builds at most 1,000"),
    # program.py: "the segment angles sum to 360°; they must sum to 360°"
    ("angles-just-short-of-360", DISC % 20 + SEGMENT % 359.9999999, 2, "sum to 359.9999999°"),
    # rules.py: an export tolerance of 1e-15 mm sampled curves without end
    ("tolerance-1e-15", variant(POLY, manufacturing={"tolerance": 1e-15}), 2,
     "manufacturing.tolerance: must be at least 0.0001 mm"),
    # rules.py: boundary conditions that swing the motion below zero (or far above its top)
    # were accepted, and sampling the curve asked for a terabyte
    ("polynomial-below-zero",
     variant(POLY, motion__0__rise__end={"velocity": 0, "acceleration": -1e4}), 2,
     "motion[0]: goes below zero lift inside the segment, by more than a tenth of the top lift "
     "25 mm (s = -509.401 mm at θ = 59.6°)"),
    ("polynomial-overshoot",
     variant(POLY, motion__0__rise__end={"velocity": 0, "acceleration": 1e17}), 2,
     "motion[0]: overshoots the program's top lift 25 mm inside the segment"),
    # rules.py: a cam a few nanometres across left no outline to export
    ("nanometre-cam", variant(POLY, cam__base_radius=4e-8, motion__0__rise__lift=3e-8), 2,
     "cam.base_radius: must be larger than the export tolerance"),
    # rules.py: a circular-arc nose of radius 3e-18 mm has no direction left after rounding
    # (its centre and its ends are the same floats): the follower's joints came out NaN
    ("nose-radius-3e-18", variant("designs/seed-7-12-exhaust-valve.yaml", cam__nose_radius=3e-18),
     2, "cam.nose_radius: gives a nose of radius 3e-18 mm: it must be at least 1e-08 of the "
        "cam's radius (37 mm)"),
    # rules.py: a groove 1e-12 mm deep left the read-back check no wall to run over
    ("groove-depth-1e-12", variant("designs/demo-cylindrical.yaml", cam__groove_depth=1e-12), 2,
     "cam.groove_depth: must be larger than the export tolerance"),
    # rules.py: a rise of 40 mm over 0.001° took minutes to sample
    ("rise-over-a-thousandth-degree",
     variant("designs/seed-c11-shm-ua.yaml", motion__0__rise__angle=0.001,
             motion__1__dwell__angle=125.999), 2, "motion[0]: is too steep to build"),
    # rules.py: a 30 m cam at 0.001 mm took minutes and gigabytes
    ("huge-cam-fine-tolerance", variant("designs/demo-conjugate.yaml", cam__base_radius=30_000,
                                        follower__roller_spacing=100_000), 2,
     "manufacturing.tolerance: must be at least"),
    # drum_mesh.py: a drum of 72 velocity steps sought each step's crease at 33 radii one at a
    # time, 128 × 128 pieces of track each (11 s)
    ("drum-72-velocity-steps",
     "name: d\ncam: {type: cylindrical, radius: 50, length: 70, groove_depth: 8}\n"
     "follower: {type: roller, roller_radius: 6}\nmotion:\n"
     + "  - rise: {angle: 5, lift: 1, law: uniform-velocity}\n"
       "  - return: {angle: 5, law: uniform-velocity}\n" * 36, 1, ""),
]


@pytest.mark.parametrize(("text", "status", "words"), [c[1:] for c in REGRESSIONS],
                         ids=[c[0] for c in REGRESSIONS])
def test_regressions(text: str, status: int, words: str) -> None:
    CASES["regression"] += 1
    with tempfile.TemporaryDirectory() as tmp:
        design = Path(tmp) / "design.yaml"
        design.write_text(text, encoding="utf-8")
        with time_limit(CHECK_LIMIT), contextlib.redirect_stdout(io.StringIO()):
            outcome = _check_one(str(design))
    assert outcome.code == status, outcome
    assert words in "\n".join(outcome.err), outcome


#: (id, file text, status): designs whose full build raised or took minutes before the fix.
BUILD_REGRESSIONS = [
    # drum_mesh.py: a drum cam's groove of under 1 mm lift had no wall row between floor and
    # surface, and the read-back check indexed an empty array
    ("drum-small-lift", variant("designs/demo-cylindrical.yaml", motion__0__rise__lift=0.01), 0),
    # arcfit.py: on a drum 60 m in radius, nearly straight arcs of radius 10¹¹ mm were written
    # whose ends a DXF reader recomputes 10⁻⁵ mm off, and the outline did not close
    ("drum-60-m", variant("designs/demo-cylindrical.yaml", cam__radius=60_000,
                          manufacturing={"tolerance": 0.1}), 1),
    # shaped.py: a tangent cam's lift of 1e-17 mm, where cos(lift_angle) rounds to 1, divided
    # by zero (its STL, open at the nose's slivers until mesh_quality.py, now reads back closed)
    ("tangent-lift-1e-17", variant("starters/tangent.yaml", cam__lift=1.2e-17,
                                   cam__lift_angle=6e-8), 0),
    # plate.py: a tangent cam's lift of 1e-12 mm left a corner of rounding in its exact
    # outline, whose exact offset for the laser's kerf then raised
    ("tangent-picometre-lift-with-kerf",
     variant("designs/demo-tangent-roller.yaml", cam__lift=1e-12), 0),
    # dxf.py: a nose of 1 nm was written as arcs a DXF reader drops as too short, and the
    # outline read back did not close
    ("nose-of-a-nanometre", "name: n\ncam: {type: circular-arc, base_radius: 30, lift: 20, "
     "lift_angle: 75, nose_radius: 1e-6}\nfollower: {type: roller, roller_radius: 5}\n", 1),
    # undercut.py: a steep linear cam measured 30,000 points against a 30,000-point outline
    # one pair at a time (8 s)
    ("linear-steep-lift", variant("designs/demo-linear-roller.yaml", motion__0__rise__lift=2000),
     1),
]


@pytest.mark.parametrize(("text", "status"), [c[1:] for c in BUILD_REGRESSIONS],
                         ids=[c[0] for c in BUILD_REGRESSIONS])
def test_build_regressions(text: str, status: int) -> None:
    CASES["regression"] += 1
    assert build_file(text) == status


# ---- whole files as real processes: a crash or a runaway here would take pytest with it ------

def _huge_design() -> bytes:
    text = BASE_TEXTS["starters/disc-roller.yaml"]
    return (text + ("# " + "x" * 98 + "\n") * 45_000).encode()  # 4.5 MB of comments: builds


PROCESS_CASES = [
    ("binary", bytes((i * 7919 + 13) % 256 for i in range(16_384)), 2, r"not a text file"),
    ("empty", b"", 2, r"the design file is empty"),
    ("blank", b" \n\n   \n", 2, r"the design file is empty"),
    ("invalid-utf8", b"name: caf\xc3\n", 2, r"not a text file"),
    ("too-large", b"#" * 5_000_001, 2, r"a design file is at most"),
    ("huge-but-allowed", _huge_design(), 0, r""),
    ("many-values", b"name: x\ndescription: [" + b"1, " * 1_500_000 + b"]\n", 2,
     r"more than 100,000 values"),
    ("alias-bomb", alias_bomb(9, 9).encode(), 2, r"expand to more than"),
    ("deeply-nested", nested(100_000, flow=True).encode(), 2, r"nested too deeply"),
]


@pytest.mark.parametrize("command", ["check", "build"])
@pytest.mark.parametrize(("data", "status", "pattern"), [c[1:] for c in PROCESS_CASES],
                         ids=[c[0] for c in PROCESS_CASES])
def test_whole_files_as_real_processes(tmp_path: Path, command: str, data: bytes, status: int,
                                       pattern: str) -> None:
    CASES["process"] += 1
    (tmp_path / "d.yaml").write_bytes(data)
    # a runaway ends by CPU time and memory; the clock only catches a hang
    run = run_camfab([command, "d.yaml"], cpu_s=60, wall_s=900, cwd=tmp_path)
    assert run.code == status, run.stderr
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr, run.stderr
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*"))
    if status == 2:
        assert re.fullmatch(rf"d\.yaml(:\d+)?: .*{pattern}.*\n", run.stderr), run.stderr
        assert written == ["d.yaml"]
    elif command == "check":
        assert written == ["d.yaml"]
    else:
        assert not [p for p in written if p.endswith(".tmp")], written


def test_zz_case_count(request: pytest.FixtureRequest) -> None:
    """How many generated cases ran (the module's tests run in file order, this one last); not
    counted when an earlier test failed, which stops its cases short."""
    if request.session.testsfailed:
        pytest.skip("an earlier test failed: its cases stopped short")
    total = sum(CASES.values())
    print(f"\nfuzz cases: {total} ({dict(CASES)}); exit statuses: {dict(sorted(STATUSES.items()))}")
    if {"check", "text", "whole", "build"} <= set(CASES):
        assert CASES["check"] + CASES["text"] + CASES["whole"] + CASES["build"] >= 2000
        assert total >= 2000
