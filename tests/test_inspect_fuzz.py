"""Fuzzing ``camfab inspect`` with generated and mutated DXF and CSV files and option values.

Every run must end with exit status 0, 1 or 2 — never an "internal error", a traceback or an
exception escaping the command line — within :data:`CASE_CPU_S` CPU seconds and
:data:`PEAK_MB` of resident memory; a refusal (2) is one line naming the file, the option or the
follower, and writes nothing.

The cases are made here, the same on every run (a fixed seed): DXF drawings of random entities
(lines, arcs, circles, polylines with bulges, 2-D polylines, splines, ellipses, notes) whose
numbers are sometimes NaN, infinite, huge, tiny or not numbers at all, in random units and on
random layers, and files then truncated, cut up or salted with random bytes; camfab's own DXF
mutated the same way; CSV scans in every layout, with bad rows; random bytes; pipes, devices and
folders; a drawing of 10⁵ tiny lines; and options (``--step``, ``--smooth``, ``--tolerance``,
``--kerf``, ``--centre``, ``--roller-radius`` and the follower's other lengths, ``--speed``,
``--layer``) of 0, negative, NaN, 1e-300, 1e300 and sensible values.

They run in child processes (:mod:`tests.inspect_fuzz_child`), many to a process, each under a
CPU-time limit and all under a memory limit (``RLIMIT_AS``); only CPU time is limited per case,
so a busy machine cannot fail the test, and the wall-clock guard is ten times the time the
whole batch takes on an idle machine.
"""

from __future__ import annotations

import io
import json
import math
import os
import random
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from .conftest import DESIGNS, run_cli
from .limited_child import run_limited

#: Cases generated (the seed makes them the same on every run).
CASE_COUNT = 800
SEED = 20_240_517

#: CPU seconds one case may take (an inspection of a few thousand points takes well under
#: one), and the CPU time after which the child is killed (SIGXCPU): a runaway case.
CASE_CPU_S = 10.0
KILL_CPU_S = 30.0

#: Peak resident memory of a child (MB): the libraries take some 200 MB, a case a few tens.
PEAK_MB = 1500.0

#: Wall-clock guard of one child (s): ten times what its whole batch takes on an idle machine
#: (some 25 s).
BATCH_WALL_S = 300.0

#: Children the cases are shared between (run side by side: one per core of a small machine).
BATCHES = 2

SEED_DESIGN = DESIGNS / "seed-10-4.yaml"
ECCENTRIC = DESIGNS / "seed-jump-eccentric.yaml"
OSCILLATING = DESIGNS / "seed-10-3-oscillating.yaml"

#: Numbers that break things, as they would be written in a file or on the command line.
WEIRD = ["nan", "NaN", "inf", "-inf", "1e300", "-1e300", "1e-300", "5e-324", "-0.0", "0",
         "1e308", "-1e308", "1e20", "1e-20", "abc", "", "1,5", "0x1p3", "1_000", "٣٤", "1e",
         "--1", "+", "."]

#: $INSUNITS codes: every real one, unitless, and some that are not codes.
UNIT_CODES = [*range(0, 25), -1, 25, 99, 2**31, "abc", "4.5", ""]

LAYERS = ["CUT", "cut", "0", "PART", 'PA"RT', "X']i", "日本", "a b", "[CUT]", "CUT]i", "*", "NOTE"]


@dataclass
class Case:
    """One run: its kind (for the report) and the command line after ``inspect``."""

    id: int
    kind: str
    args: list[str]
    profile: str


# -- numbers and shapes -------------------------------------------------------------------------

def _number(rng: random.Random, value: float, weird: float) -> str:
    """*value* as a DXF or CSV would write it, or (with probability *weird*) a weird number."""
    if rng.random() < weird:
        return rng.choice(WEIRD)
    return repr(float(value))


def _outline_points(rng: random.Random) -> np.ndarray:
    """A closed outline about the origin (mm): a circle, an eccentric, a cam-like radial
    function, a notched circle, a star or random points (which may cross)."""
    count = rng.choice([3, 4, 7, 60, 360, 1000, 3000])
    angle = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    size = rng.choice([40.0, 40.0, 40.0, 0.01, 2.0, 4000.0, 1e6])
    shape = rng.choice(["circle", "eccentric", "cam", "notch", "star", "random"])
    if shape == "circle":
        radius = np.full(count, size)
    elif shape == "eccentric":
        return np.column_stack((size * np.cos(angle), -0.6 * size + size * np.sin(angle)))
    elif shape == "cam":
        radius = size * (1.0 + 0.4 * np.clip(np.sin(angle), 0.0, None) ** 2)
    elif shape == "notch":
        radius = np.where(np.abs(angle - 1.5) < 0.03, 0.5 * size, size)
    elif shape == "star":
        radius = size * np.where(np.arange(count) % 2 == 0, 1.0, 0.3)
    else:
        radius = size * np.array([rng.uniform(0.2, 1.0) for _ in range(count)])
    return np.column_stack((radius * np.cos(angle), radius * np.sin(angle)))


# -- DXF ----------------------------------------------------------------------------------------

def _template() -> tuple[str, str]:
    """An empty R2010 drawing written by ezdxf, split where entities go (the header's
    ``$INSUNITS`` value replaced by a placeholder)."""
    import ezdxf

    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    stream = io.StringIO()
    doc.write(stream)
    text = stream.getvalue().replace("$INSUNITS\n 70\n4\n", "$INSUNITS\n 70\n{units}\n", 1)
    at = text.index("ENTITIES\n") + len("ENTITIES\n")
    return text[:at], text[at:]


def _tags(*pairs: tuple[int, object]) -> str:
    return "".join(f"{code:>3}\n{value}\n" for code, value in pairs)


def _head(kind: str, layer: str, subclass: str) -> list[tuple[int, object]]:
    return [(0, kind), (100, "AcDbEntity"), (8, layer), (100, subclass)]


def _dxf_entities(rng: random.Random, weird: float) -> list[str]:
    """Entities of one or two outlines and some loose ones."""
    out: list[str] = []

    def num(value: float) -> str:
        return _number(rng, value, weird)

    for _ in range(rng.choice([1, 1, 2, 3])):
        layer = rng.choice(LAYERS) if rng.random() < 0.3 else "CUT"
        points = _outline_points(rng)
        style = rng.choice(["lines", "lwpolyline", "polyline", "arcs", "circle", "ellipse",
                            "spline", "open-lwpolyline"])
        if style == "lines" or (style == "lwpolyline" and len(points) < 3):
            following = np.roll(points, -1, axis=0)
            order = list(range(len(points)))
            if rng.random() < 0.3:
                rng.shuffle(order)
            for k in order:
                a, b = (points[k], following[k]) if rng.random() < 0.7 else (following[k],
                                                                              points[k])
                out.append(_tags(*_head("LINE", layer, "AcDbLine"), (10, num(a[0])),
                                 (20, num(a[1])), (30, 0.0), (11, num(b[0])), (21, num(b[1])),
                                 (31, 0.0)))
        elif style in ("lwpolyline", "open-lwpolyline"):
            closed = style == "lwpolyline"
            chain = points if closed else np.vstack((points, points[:1]))
            vertices: list[tuple[int, object]] = []
            for x, y in chain:
                vertices += [(10, num(x)), (20, num(y))]
                if rng.random() < 0.2:
                    vertices.append((42, num(rng.uniform(-1.5, 1.5))))
            out.append(_tags(*_head("LWPOLYLINE", layer, "AcDbPolyline"), (90, len(chain)),
                             (70, 1 if closed else 0), *vertices))
        elif style == "polyline":
            text = _tags(*_head("POLYLINE", layer, "AcDb2dPolyline"), (66, 1), (10, 0.0),
                         (20, 0.0), (30, 0.0), (70, 1))
            for x, y in points:
                text += _tags((0, "VERTEX"), (100, "AcDbEntity"), (8, layer),
                              (100, "AcDbVertex"), (100, "AcDb2dVertex"), (10, num(x)),
                              (20, num(y)), (30, 0.0), (42, num(0.0)))
            out.append(text + _tags((0, "SEQEND"), (100, "AcDbEntity"), (8, layer)))
        elif style == "arcs":
            radius = float(np.max(np.hypot(points[:, 0], points[:, 1])))
            cuts = sorted(rng.uniform(0.0, 360.0) for _ in range(rng.randint(1, 12)))
            for start, end in zip(cuts, cuts[1:] + cuts[:1], strict=True):
                out.append(_tags(*_head("ARC", layer, "AcDbCircle"), (10, num(0.0)),
                                 (20, num(0.0)), (30, 0.0), (40, num(radius)),
                                 (100, "AcDbArc"), (50, num(start)), (51, num(end))))
        elif style == "circle":
            radius = float(np.max(np.hypot(points[:, 0], points[:, 1])))
            sign = -1.0 if rng.random() < 0.1 else 1.0
            out.append(_tags(*_head("CIRCLE", layer, "AcDbCircle"), (10, num(0.0)),
                             (20, num(-0.3 * radius)), (30, 0.0), (40, num(sign * radius))))
        elif style == "ellipse":
            radius = float(np.max(np.hypot(points[:, 0], points[:, 1])))
            out.append(_tags(*_head("ELLIPSE", layer, "AcDbEllipse"), (10, num(0.0)),
                             (20, num(0.0)), (30, 0.0), (11, num(radius)), (21, num(0.0)),
                             (31, 0.0), (40, num(rng.choice([0.5, 1.0, 1e-9, 2.0, 0.0]))),
                             (41, num(0.0)), (42, num(2 * math.pi))))
        else:
            control = points[:: max(1, len(points) // 40)]
            degree = rng.choice([1, 2, 3, 3, 3, 5, 30])
            count = len(control) + degree
            knots = [(40, num(k)) for k in range(count + degree + 1)]
            ctrl = [pair for x, y in control for pair in ((10, num(x)), (20, num(y)),
                                                          (30, 0.0))]
            ctrl += [pair for x, y in control[:degree] for pair in ((10, num(x)), (20, num(y)),
                                                                    (30, 0.0))]
            out.append(_tags(*_head("SPLINE", layer, "AcDbSpline"), (70, 8), (71, degree),
                             (72, len(knots)), (73, count), (74, 0), *knots, *ctrl))
    for _ in range(rng.choice([0, 0, 1, 3])):  # loose junk
        kind = rng.choice(["LINE", "CIRCLE", "ARC"])
        values = [num(rng.uniform(-100, 100)) for _ in range(5)]
        if kind == "LINE":
            out.append(_tags(*_head("LINE", rng.choice(LAYERS), "AcDbLine"),
                             (10, values[0]), (20, values[1]), (11, values[2]), (21, values[3])))
        else:
            extra = [(100, "AcDbArc"), (50, values[3]), (51, values[4])] if kind == "ARC" else []
            out.append(_tags(*_head(kind, rng.choice(LAYERS), "AcDbCircle"), (10, values[0]),
                             (20, values[1]), (40, values[2]), *extra))
    if rng.random() < 0.3:  # a kerf note, sound or damaged
        kerf = rng.choice(["0.2", "0.2", "1..2", "nan", "-1", "1e300", "50", "", "0.2mm",
                           "3 furlongs", "0"])
        unit = rng.choice(["mm", "mm", "in", "", "µm"])
        out.append(_tags(*_head("TEXT", "NOTE", "AcDbText"), (10, 0.0), (20, 0.0), (30, 0.0),
                         (40, 2.5), (1, f"CUT offset for a kerf of {kerf} {unit}"),
                         (100, "AcDbText")))
    return out


def _mutated(rng: random.Random, data: bytes) -> bytes:
    """*data* truncated, cut up, or salted with random bytes (or left alone)."""
    choice = rng.random()
    if choice < 0.75 or not data:
        return data
    if choice < 0.8:
        return data[:rng.randrange(len(data))]
    lines = data.split(b"\n")
    if choice < 0.87:
        for _ in range(rng.randint(1, 5)):
            if lines:
                del lines[rng.randrange(len(lines))]
        return b"\n".join(lines)
    if choice < 0.94:
        for _ in range(rng.randint(1, 5)):
            at = rng.randrange(len(lines))
            lines[at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        return b"\n".join(lines)
    at = rng.randrange(len(lines))
    return b"\n".join(lines[:at] + lines[at:at + rng.randint(1, 50)] * 2 + lines[at:])


def _dxf_case(rng: random.Random, template: tuple[str, str]) -> bytes:
    head, tail = template
    code = rng.choice(UNIT_CODES) if rng.random() < 0.4 else 4
    weird = rng.choice([0.0, 0.0, 0.0, 0.0, 0.001, 0.01, 0.1])
    text = head.replace("{units}", str(code), 1) + "".join(_dxf_entities(rng, weird)) + tail
    return _mutated(rng, text.encode("utf-8"))


def _own_dxf_case(rng: random.Random, own: list[bytes]) -> bytes:
    """camfab's own drawing with some numbers replaced by weird ones, then mutated."""
    lines = rng.choice(own).split(b"\n")
    numeric = [k for k, line in enumerate(lines) if line[:1].isdigit() or line[:1] == b"-"]
    for _ in range(rng.choice([0, 1, 3, 10])):
        k = rng.choice(numeric)
        if k % 2 == 1:  # a value, not a group code (ezdxf writes code, value, code, value...)
            lines[k] = rng.choice(WEIRD).encode()
    return _mutated(rng, b"\n".join(lines))


def _tiny_lines(count: int) -> bytes:
    """A minimal drawing of *count* lines of a micrometre, chained round a circle."""
    angle = np.linspace(0.0, 2.0 * math.pi, count + 1)
    x, y = 0.0002 * count * np.cos(angle) / math.pi, 0.0002 * count * np.sin(angle) / math.pi
    body = "".join(f"  0\nLINE\n  8\nCUT\n 10\n{x[k]:.9f}\n 20\n{y[k]:.9f}\n 11\n{x[k + 1]:.9f}\n"
                   f" 21\n{y[k + 1]:.9f}\n" for k in range(count))
    return f"  0\nSECTION\n  2\nENTITIES\n{body}  0\nENDSEC\n  0\nEOF\n".encode()


# -- CSV ----------------------------------------------------------------------------------------

def _csv_case(rng: random.Random) -> bytes:
    points = _outline_points(rng)
    weird = rng.choice([0.0, 0.0, 0.0, 0.0, 0.001, 0.01, 0.2])
    layout = rng.choice(["commas", "semicolons", "decimal-commas", "tabs", "spaces",
                         "three-columns", "header-yx", "arabic-indic"])
    rows = [(_number(rng, x, weird), _number(rng, y, weird)) for x, y in points]
    lines = [f"# scan of {len(rows)} points"]
    if layout == "commas":
        lines += ["x,y", *(f"{x},{y}" for x, y in rows)]
    elif layout == "semicolons":
        lines += [f"{x};{y}" for x, y in rows]
    elif layout == "decimal-commas":
        lines += [f"{x};{y}".replace(".", ",") for x, y in rows]
    elif layout == "tabs":
        lines += [f"{x}\t{y}" for x, y in rows]
    elif layout == "spaces":
        lines += [f"  {x}   {y}  " for x, y in rows]
    elif layout == "three-columns":
        lines += ["X_mm,Y_mm,Z_mm", *(f"{x},{y},1.5" for x, y in rows)]
    elif layout == "header-yx":
        lines += ["n,y (mm),x (mm)", *(f"{k},{y},{x}" for k, (x, y) in enumerate(rows))]
    else:
        digits = str.maketrans("0123456789", "٠١٢٣٤٥٦٧٨٩")
        lines += [f"{x},{y}".translate(digits) for x, y in rows]
    if rng.random() < 0.1:
        lines.insert(rng.randrange(len(lines)), rng.choice([",", ";", "\t", "x", "1", "1,2,3,4",
                                                            '"1","2"', "#", "\ufeff1,2"]))
    text = "\n".join(lines) + rng.choice(["\n", "", "\r\n"])
    data = text.encode("utf-8") if rng.random() < 0.95 else text.encode("utf-16")
    return _mutated(rng, data)


# -- options ------------------------------------------------------------------------------------

#: Sensible values of the options that take numbers (and layer names).
_SANE: dict[str, list[str]] = {
    "--step": ["1", "0.5", "0.01", "30", "2 deg", "0.01 rad", "7"],
    "--smooth": ["1", "3", "0.1", "30", "1 deg"],
    "--tolerance": ["0.01", "0.1", "1", "1 um", "0.0001"],
    "--kerf": ["0", "0.2", "5", "9.9"],
    "--centre": ["0,0", "1,1", "0.5;-0.5", "-3,2"],
    "--offset": ["0", "5", "-5", "20", "30", "45"],
    "--speed": ["100", "1000", "10 rev/s", "0.001"],
    "--layer": LAYERS,
}
#: Values that are not sensible: the weird numbers, and for --centre broken pairs.
_WEIRD: dict[str, list[str]] = {**{option: WEIRD for option in _SANE},
                                "--centre": ["1e300,0", "nan,0", "1", "1,2,3", "", ",", "abc",
                                             "1e6,1e6", "0x1,2"]}
_LENGTHS = ["5", "0.5", "10", "2 mm", "0.2 in", "1e-6", "500"]
_CHOICES = {"--rotation": ["ccw", "cw"], "--units": ["mm", "in"], "--pivot-side": ["right", "left"]}


def _options(rng: random.Random, csv: bool) -> list[str]:
    """A command line: a design or a follower, and some options, sensible or (in some cases)
    weird."""
    weird = rng.random() < 0.4
    args: list[str] = []
    design = rng.choice([SEED_DESIGN, ECCENTRIC, OSCILLATING, None, None])
    if design is not None:
        args += ["--design", str(design)]
    if design is None or rng.random() < 0.2:
        kind = rng.choice(["knife", "roller", "flat", "mushroom"])
        args += ["--type", kind]
        lengths = _LENGTHS + (WEIRD if weird else [])
        if kind == "roller":
            args += ["--roller-radius", rng.choice(lengths)]
        if kind == "mushroom":
            args += ["--face-radius", rng.choice(lengths)]
        if rng.random() < 0.2:
            args += ["--pivot-distance", rng.choice(["80", "60", *lengths]),
                     "--arm-length", rng.choice(["60", "40", *lengths])]
            if kind == "flat":
                args += ["--face-offset", rng.choice(["0", "5", *lengths])]
    for option, values in _SANE.items():
        if option == "--layer" and csv:
            continue
        if rng.random() < 0.12:
            args += [option, rng.choice(_WEIRD[option] if weird and rng.random() < 0.5
                                        else values)]
    for option, values in _CHOICES.items():
        if rng.random() < 0.1:
            args += [option, rng.choice(values)]
    if design is not None and rng.random() < 0.1:
        args.append("--align")
    return args


# -- the cases ----------------------------------------------------------------------------------

def make_cases(folder: Path, own: list[bytes]) -> list[Case]:
    """:data:`CASE_COUNT` cases, their files written into *folder*."""
    rng = random.Random(SEED)
    template = _template()
    cases: list[Case] = []

    def add(kind: str, profile: Path, args: list[str]) -> None:
        number = len(cases)
        cases.append(Case(number, kind, [str(profile), *args, "-o",
                                         str(folder / f"out-{number}")], str(profile)))

    special = _special_files(folder)
    for kind, path in special:
        add(kind, path, ["--type", "knife"])
    tiny = folder / "tiny-lines.dxf"
    tiny.write_bytes(_tiny_lines(100_000))
    add("dxf-100k-tiny-lines", tiny, ["--type", "knife"])
    while len(cases) < CASE_COUNT:
        number = len(cases)
        pick = rng.random()
        if pick < 0.4:
            kind, suffix, data = "dxf-generated", ".dxf", _dxf_case(rng, template)
        elif pick < 0.55:
            kind, suffix, data = "dxf-camfab-mutated", ".dxf", _own_dxf_case(rng, own)
        elif pick < 0.9:
            kind, suffix, data = "csv", ".csv", _csv_case(rng)
        else:
            kind, suffix = "random-bytes", rng.choice([".dxf", ".csv"])
            data = bytes(rng.randrange(256) for _ in range(rng.choice([0, 1, 10, 1000, 20000])))
        path = folder / f"case-{number}{suffix}"
        path.write_bytes(data)
        add(kind, path, _options(rng, suffix == ".csv"))
    return cases


def _special_files(folder: Path) -> list[tuple[str, Path]]:
    """Paths that are not regular files of a sensible size."""
    fifo = folder / "pipe.csv"
    os.mkfifo(fifo)
    folder_dxf = folder / "a-folder.dxf"
    folder_dxf.mkdir()
    huge = folder / "huge.csv"
    with huge.open("wb") as stream:
        stream.truncate(2**31)  # sparse: no disk used
    found = [("fifo", fifo), ("folder", folder_dxf), ("huge", huge),
             ("missing", folder / "missing.dxf")]
    found += [(f"device-{p.name}", p) for p in (Path("/dev/zero"), Path("/dev/urandom"),
                                                Path("/dev/null")) if p.exists()]
    return found


# -- running and checking -----------------------------------------------------------------------

def run_cases(cases: list[Case], folder: Path) -> tuple[dict[int, dict], list[str]]:
    """Run *cases* in :data:`BATCHES` child processes side by side: the outcome of each case
    that finished, and what went wrong with the ones that did not (a child killed at its CPU
    limit or by the wall-clock guard)."""
    from concurrent.futures import ThreadPoolExecutor

    batches = [(number, cases[number::BATCHES]) for number in range(BATCHES)]
    with ThreadPoolExecutor(BATCHES) as pool:
        done = list(pool.map(lambda batch: _run_batch(*batch, folder), batches))
    outcomes = {k: v for found, _ in done for k, v in found.items()}
    return outcomes, [crash for _, crashes in done for crash in crashes]


def _run_batch(number: int, batch: list[Case], folder: Path) -> tuple[dict[int, dict],
                                                                       list[str]]:
    """One child's cases; after a crash the remaining ones run in a new child."""
    outcomes: dict[int, dict] = {}
    crashes: list[str] = []
    pending = batch
    for restart in range(10):
        if not pending:
            break
        cases_file = folder / f"batch-{number}-{restart}.json"
        results = folder / f"batch-{number}-{restart}.jsonl"
        cases_file.write_text(json.dumps([{"id": c.id, "args": c.args} for c in pending]))
        run = run_limited([sys.executable, "-m", "tests.inspect_fuzz_child", str(cases_file),
                           str(results), str(KILL_CPU_S)],
                          cpu_s=KILL_CPU_S * (len(pending) + 1), wall_s=BATCH_WALL_S,
                          cwd=Path(__file__).resolve().parents[1])
        started = None
        for line in results.read_text().splitlines() if results.exists() else []:
            record = json.loads(line)
            if "start" in record:
                started = record["start"]
            else:
                outcomes[record["id"]] = record
                started = None
        if run.code == 0:
            break
        culprit = next((c for c in pending if c.id == started), None)
        crashes.append(f"child ended with {run.code} (CPU {run.cpu_s:.1f} s) during "
                       f"{_describe(culprit) if culprit else 'start-up'}: {run.stderr[-500:]}")
        pending = [c for c in pending if c.id not in outcomes and c is not culprit]
    return outcomes, crashes


def _describe(case: Case) -> str:
    return f"case {case.id} ({case.kind}): inspect {' '.join(case.args)}"


def problems(case: Case, outcome: dict) -> list[str]:
    """What is wrong with one case's outcome under the contract."""
    found = []
    code, err = outcome["code"], outcome["stderr"]
    if outcome["escaped"]:
        found.append(f"an exception escaped: {outcome['escaped']}")
    if code not in (0, 1, 2):
        found.append(f"exit status {code}")
    if "Traceback" in err or "internal error" in err:
        found.append(f"stderr: {err.strip()[-300:]}")
    if code == 2:
        lines = err.strip().splitlines()
        if len(lines) != 1:
            found.append(f"{len(lines)} lines on stderr: {err[-300:]!r}")
        elif not _names_the_culprit(lines[0], case):
            found.append(f"names neither file nor option: {lines[0]}")
        if Path(case.args[case.args.index("-o") + 1]).exists():
            found.append("a refused run wrote files")
    if outcome["cpu_s"] > CASE_CPU_S:
        found.append(f"took {outcome['cpu_s']:.1f} CPU s")
    return found


def _names_the_culprit(line: str, case: Case) -> bool:
    """True when the refusal begins with the outline file (and a line), the design or an
    option."""
    heads = [case.profile, "--", *(str(p) for p in (SEED_DESIGN, ECCENTRIC, OSCILLATING))]
    return any(line.startswith(head) for head in heads)


@pytest.fixture(scope="module")
def own_drawings(tmp_path_factory: pytest.TempPathFactory) -> list[bytes]:
    """camfab's own drawings (a plain and a laser-kerf one), built once (a batch: each in
    a folder of its own)."""
    folder = tmp_path_factory.mktemp("own")
    designs = [SEED_DESIGN, DESIGNS / "demo-laser-kerf.yaml"]
    result = run_cli("build", *(str(d) for d in designs), "-o", str(folder))
    assert result.exit_code in (0, 1), result.output + result.stderr
    return [(folder / d.stem / f"{d.stem}.dxf").read_bytes() for d in designs]


def test_inspect_survives_generated_and_mutated_files(tmp_path: Path,
                                                      own_drawings: list[bytes]) -> None:
    cases = make_cases(tmp_path, own_drawings)
    outcomes, crashes = run_cases(cases, tmp_path)
    failures = list(crashes)
    for case in cases:
        outcome = outcomes.get(case.id)
        if outcome is None:
            if not any(f"case {case.id} " in c for c in crashes):
                failures.append(f"{_describe(case)}: no outcome")
            continue
        failures += [f"{_describe(case)}: {p}" for p in problems(case, outcome)]
    peak_mb = max((o["maxrss_kb"] for o in outcomes.values()), default=0) / (
        1024.0 * 1024.0 if sys.platform == "darwin" else 1024.0)
    if peak_mb > PEAK_MB:
        failures.append(f"a child's resident memory reached {peak_mb:.0f} MB")
    statuses = Counter((case.kind, outcomes[case.id]["code"]) for case in cases
                       if case.id in outcomes)
    cpu = sum(o["cpu_s"] for o in outcomes.values())
    print(f"\n{len(cases)} inspect cases, {cpu:.1f} CPU s in the cases, peak {peak_mb:.0f} MB; "
          f"statuses: {dict(sorted(statuses.items()))}")
    assert not failures, f"{len(failures)} failure(s):\n" + "\n".join(failures[:30])
    assert len(outcomes) == len(cases) == CASE_COUNT
