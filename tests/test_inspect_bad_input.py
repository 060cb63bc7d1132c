"""``camfab inspect`` on bad input: one line on stderr naming the file (and the line, entity or
option at fault), exit status 2, nothing written, within a few CPU seconds — never an "internal
error", a traceback, a hang or unbounded memory.

Inputs that could hang or exhaust a process (pipes, devices, files of a million entities) run as
real ``camfab`` processes under limits of CPU time and memory (:mod:`tests.limited_child`);
the others in this process.
"""

from __future__ import annotations

import itertools
import json
import math
import os
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from .conftest import DESIGNS, run_cli
from .limited_child import ChildRun, run_camfab

SEED = DESIGNS / "seed-10-4.yaml"
ECCENTRIC = DESIGNS / "seed-jump-eccentric.yaml"
LASER = DESIGNS / "demo-laser-kerf.yaml"

#: CPU seconds a refusal may take in a child process: the imports take one or two.
REFUSAL_CPU_S = 8.0

_RUNS = itertools.count()


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """seed-10-4 and demo-laser-kerf built once (their DXFs), into one folder."""
    folder = tmp_path_factory.mktemp("built")
    for design in (SEED, LASER):
        result = run_cli("build", str(design), "-o", str(folder))
        assert result.exit_code in (0, 1), result.output + result.stderr
    return folder


def _inspect(tmp_path: Path, profile: Path, *args: str) -> tuple[int, str, Path]:
    """``camfab inspect PROFILE ARGS -o OUT`` in this process (OUT a new folder's name for each
    run): exit status, stderr, OUT."""
    out = tmp_path / f"out-{next(_RUNS)}"
    result = run_cli("inspect", str(profile), *args, "-o", str(out))
    return result.exit_code, result.stderr, out


def _assert_refused(code: int, err: str, out: Path, named: str, *said: str) -> None:
    """Exit 2, one line naming *named* and saying each of *said*, nothing written."""
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "internal error" not in err and "Traceback" not in err, err
    assert lines[0].startswith(named), err
    for phrase in said:
        assert phrase in err, err
    assert not out.exists()


def _refused(tmp_path: Path, profile: Path, *args: str, said: tuple[str, ...] = (),
             named: str | None = None) -> str:
    code, err, out = _inspect(tmp_path, profile, *args)
    _assert_refused(code, err, out, str(profile) if named is None else named, *said)
    return err


def _eccentric(count: int = 2000) -> np.ndarray:
    """seed-jump-eccentric's cam at θ = 0: a circle of radius 60 mm about (0, −37.5)."""
    angle = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    return np.column_stack((60.0 * np.cos(angle), -37.5 + 60.0 * np.sin(angle)))


def _dxf(path: Path, units: int = 4) -> tuple[ezdxf.document.Drawing, Path]:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = units
    return doc, path


def _eccentric_dxf(path: Path, units: int = 4, layer: str = "CUT") -> Path:
    doc, _ = _dxf(path, units)
    doc.modelspace().add_lwpolyline(_eccentric(720), close=True, dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


# -- DXF ----------------------------------------------------------------------------------------

def test_a_layer_name_with_quotes_is_matched_without_a_query(tmp_path: Path) -> None:
    path = _eccentric_dxf(tmp_path / "quoted.dxf", layer="PARTQ")
    path.write_bytes(path.read_bytes().replace(b"PARTQ", b'PA"RT'))
    code, err, _ = _inspect(tmp_path, path, "--layer", 'PA"RT', "--design", str(ECCENTRIC))
    assert code == 0, err
    _refused(tmp_path, path, "--layer", 'X"]i', "--design", str(ECCENTRIC),
             said=("has no entities on layer 'X\"]i'", "PA\"RT"))


def test_a_drawing_in_micro_inches_is_refused_with_its_size(built: Path, tmp_path: Path) -> None:
    doc = ezdxf.readfile(built / "seed-10-4.dxf")
    doc.header["$INSUNITS"] = 8
    path = tmp_path / "micro.dxf"
    doc.saveas(path)
    _refused(tmp_path, path, "--design", str(SEED), said=("mm across", "µin", "--units"))
    code, err, _ = _inspect(tmp_path, path, "--design", str(SEED), "--units", "mm")
    assert code == 0, err


@pytest.mark.parametrize(("code", "said"), [
    (99, "$INSUNITS is 99"), (19, "mm from the origin")])  # 19: light years
def test_an_unknown_or_absurd_unit_code_is_refused(tmp_path: Path, code: int, said: str) -> None:
    path = _eccentric_dxf(tmp_path / "units.dxf", units=code)
    _refused(tmp_path, path, "--design", str(ECCENTRIC), said=(said,))


@pytest.mark.parametrize(("note", "said"), [
    ("CUT offset for a kerf of 1..2 mm", "gives no kerf"),
    ("CUT offset for a kerf of 0e mm", "gives no kerf"),
    ("CUT offset for a kerf of . mm", "gives no kerf"),
    ("CUT offset for a kerf of 0.2 furlongs", "gives no kerf"),
    ("CUT offset for a kerf of", "gives no kerf"),
    ("CUT offset for a kerf of nan mm", "gives no kerf"),
    ("CUT offset for a kerf of 1e300 mm", "must be from 0 to 10 mm"),
    ("CUT offset for a kerf of -.5 mm", "must be from 0 to 10 mm"),
    ("CUT offset for a kerf of 50 mm", "must be from 0 to 10 mm"),
])
def test_a_damaged_kerf_note_is_refused_naming_its_entity(built: Path, tmp_path: Path,
                                                          note: str, said: str) -> None:
    doc = ezdxf.readfile(built / "demo-laser-kerf.dxf")
    (text,) = [t for t in doc.modelspace().query("TEXT") if "CUT offset" in t.dxf.text]
    text.dxf.text = note
    path = tmp_path / "laser.dxf"
    doc.saveas(path)
    _refused(tmp_path, path, "--design", str(LASER), said=(f"TEXT #{text.dxf.handle}", said))
    # --kerf overrides the note, damaged or not
    code, err, _ = _inspect(tmp_path, path, "--design", str(LASER), "--kerf", "0.2")
    assert code == 0, err


def test_a_kerf_wider_than_the_part_is_refused(tmp_path: Path) -> None:
    doc, path = _dxf(tmp_path / "small.dxf")
    msp = doc.modelspace()
    msp.add_text("CUT offset for a kerf of 8 mm", dxfattribs={"layer": "NOTE"})
    msp.add_circle((0, 0), 2.0, dxfattribs={"layer": "PART"})
    doc.saveas(path)
    _refused(tmp_path, path, "--type", "knife", said=("leaves nothing of the outline",))


def _write_points(path: Path, xy: np.ndarray) -> Path:
    np.savetxt(path, xy, fmt="%.6f", delimiter=",")
    return path


def test_a_kerf_is_not_taken_off_a_jagged_outline(tmp_path: Path) -> None:
    """A dense scan with micrometres of noise: the offset's round joins cross each other at
    every point (GEOS took over two minutes)."""
    angle = np.linspace(0.0, 2.0 * math.pi, 150_000, endpoint=False)
    radius = 40.0 + 10.0 * np.sin(angle) ** 2 + np.random.default_rng(0).normal(0, 0.002,
                                                                               angle.size)
    path = _write_points(tmp_path / "noisy.csv", np.column_stack((radius * np.cos(angle),
                                                                  radius * np.sin(angle))))
    run = run_camfab(["inspect", str(path), "--type", "knife", "--kerf", "0.2", "-o",
                      str(tmp_path / "out")])
    _assert_refused_child(run, "--kerf", "cannot be taken off an outline this jagged")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("count", "said"), [
    (150_000, "the outline is too jagged to check"),
    (12_000, "the outline is too jagged to run the follower over")])
def test_a_jagged_outline_is_refused_before_it_is_worked_on(tmp_path: Path, count: int,
                                                            said: str) -> None:
    """A star of spikes about the centre: testing it for crossings compares every spike with
    thousands of others, and every spike may touch the follower over tens of degrees (150,000
    points took minutes and gigabytes)."""
    angle = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    radius = 40.0 * np.where(np.arange(angle.size) % 2 == 0, 1.0, 0.3)
    path = _write_points(tmp_path / "star.csv", np.column_stack((radius * np.cos(angle),
                                                                 radius * np.sin(angle))))
    run = run_camfab(["inspect", str(path), "--type", "roller", "--roller-radius", "5", "-o",
                      str(tmp_path / "out")])
    _assert_refused_child(run, str(path), said)
    assert run.peak_mb < 1000.0, run.peak_mb


def test_a_drawing_without_a_usable_contour_is_refused(tmp_path: Path) -> None:
    doc, path = _dxf(tmp_path / "nothing.dxf")
    msp = doc.modelspace()
    msp.add_line((1, 1), (1, 1), dxfattribs={"layer": "A"})
    msp.add_circle((0, 0), 0.0, dxfattribs={"layer": "A"})
    msp.add_arc((0, 0), 0.0, 0, 90, dxfattribs={"layer": "B"})
    msp.add_lwpolyline([], dxfattribs={"layer": "B"})
    msp.add_text("hello", dxfattribs={"layer": "C"})
    doc.saveas(path)
    _refused(tmp_path, path, "--type", "knife", said=("has no closed contour on every layer",))


@pytest.mark.parametrize("entity", ["nan-vertex", "inf-line", "nan-radius", "nan-bulge"])
def test_a_number_that_is_not_finite_is_refused_naming_its_entity(tmp_path: Path,
                                                                  entity: str) -> None:
    doc, path = _dxf(tmp_path / "nan.dxf")
    msp = doc.modelspace()
    msp.add_lwpolyline(_eccentric(360), close=True, dxfattribs={"layer": "CUT"})
    marker = 12345.678
    if entity == "nan-vertex":
        bad = msp.add_lwpolyline([(0, 0), (100, 0), (marker, 50), (0, 50)], close=True,
                                 dxfattribs={"layer": "CUT"})
    elif entity == "inf-line":
        bad = msp.add_line((0, 0), (marker, 0), dxfattribs={"layer": "CUT"})
    elif entity == "nan-radius":
        bad = msp.add_circle((0, 0), marker, dxfattribs={"layer": "CUT"})
    else:
        bad = msp.add_lwpolyline([(0, 0, 0, 0, marker), (100, 0)], close=True,
                                 dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    value = b"inf" if entity == "inf-line" else b"nan"
    path.write_bytes(path.read_bytes().replace(b"12345.678", value))
    _refused(tmp_path, path, "--design", str(ECCENTRIC),
             said=(f"{bad.dxftype()} #{bad.dxf.handle} on layer CUT", "not finite"))


@pytest.mark.parametrize("kind", ["CIRCLE", "ARC"])
def test_a_negative_radius_is_refused(tmp_path: Path, kind: str) -> None:
    doc, path = _dxf(tmp_path / "negative.dxf")
    msp = doc.modelspace()
    if kind == "CIRCLE":
        bad = msp.add_circle((0, -37.5), 60.0, dxfattribs={"layer": "CUT"})
    else:
        msp.add_arc((0, -37.5), 60.0, 180, 0, dxfattribs={"layer": "CUT"})
        bad = msp.add_arc((0, -37.5), 60.0, 0, 180, dxfattribs={"layer": "CUT"})
    bad.dxf.radius = -60.0
    doc.saveas(path)
    _refused(tmp_path, path, "--design", str(ECCENTRIC),
             said=(f"{kind} #{bad.dxf.handle} on layer CUT: radius -60 is negative",))


def _r12_lines(points: np.ndarray) -> bytes:
    """A minimal R12 DXF: a LINE on layer CUT from each point to the next (a closed chain)."""
    following = np.roll(points, -1, axis=0)
    body = "".join(f"  0\nLINE\n  8\nCUT\n 10\n{a[0]:.9f}\n 20\n{a[1]:.9f}\n 11\n{b[0]:.9f}\n"
                   f" 21\n{b[1]:.9f}\n" for a, b in zip(points, following, strict=True))
    return (f"  0\nSECTION\n  2\nHEADER\n  9\n$INSUNITS\n 70\n4\n  0\nENDSEC\n  0\nSECTION\n"
            f"  2\nENTITIES\n{body}  0\nENDSEC\n  0\nEOF\n").encode()


def _assert_refused_child(run: ChildRun, named: str, *said: str) -> None:
    assert run.code == 2, (run.code, run.cpu_s, run.stderr[-2000:])
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(named), run.stderr[-2000:]
    assert "internal error" not in run.stderr and "Traceback" not in run.stderr
    for phrase in said:
        assert phrase in run.stderr, run.stderr
    assert run.cpu_s < REFUSAL_CPU_S, run.cpu_s


def test_a_drawing_of_a_hundred_thousand_tiny_lines_is_refused_at_once(tmp_path: Path) -> None:
    angle = np.linspace(0.0, 2.0 * math.pi, 100_000, endpoint=False)
    path = tmp_path / "tiny.dxf"
    path.write_bytes(_r12_lines(np.column_stack((np.cos(angle), np.sin(angle)))))
    run = run_camfab(["inspect", str(path), "--type", "knife", "-o", str(tmp_path / "out")])
    _assert_refused_child(run, str(path), "inspect reads a DXF of at most")
    assert not (tmp_path / "out").exists()


def test_a_drawing_of_a_million_tiny_lines_is_refused_at_once(tmp_path: Path) -> None:
    line = b"  0\nLINE\n  8\nCUT\n 10\n0.0\n 20\n0.0\n 11\n0.000001\n 21\n0.0\n"
    path = tmp_path / "million.dxf"
    path.write_bytes(b"  0\nSECTION\n  2\nENTITIES\n" + line * 1_000_000 + b"  0\nENDSEC\n"
                     b"  0\nEOF\n")
    run = run_camfab(["inspect", str(path), "--type", "knife", "-o", str(tmp_path / "out")])
    _assert_refused_child(run, str(path), "bytes; a DXF or CSV outline is at most")
    assert not (tmp_path / "out").exists()


def test_a_drawing_of_many_lines_under_the_limit_is_read_in_seconds(tmp_path: Path) -> None:
    """19,000 lines (just under the limit of entities) chain into one outline in a few CPU
    seconds; ezdxf's edge miner took some 5 s for 20,000 (and minutes for more)."""
    angle = np.linspace(0.0, 2.0 * math.pi, 19_000, endpoint=False)
    path = tmp_path / "many.dxf"
    path.write_bytes(_r12_lines(np.column_stack((60.0 * np.cos(angle),
                                                 -37.5 + 60.0 * np.sin(angle)))))
    out = tmp_path / "out"
    run = run_camfab(["inspect", str(path), "--design", str(ECCENTRIC), "-o", str(out)],
                     cpu_s=60.0)
    assert run.code == 0, run.stderr
    assert run.cpu_s < 20.0, run.cpu_s
    report = json.loads((out / "many-inspection.json").read_text())
    assert report["deviation"]["max_mm"] < 1e-4


def test_lines_meeting_many_at_a_point_are_refused_within_seconds(tmp_path: Path) -> None:
    """A grid of lines: every crossing joins four, and the loops through them are a search
    without end (ezdxf's edge miner ran out its 20 s and its time-out escaped)."""
    doc, path = _dxf(tmp_path / "grid.dxf")
    msp = doc.modelspace()
    for i in range(31):
        for j in range(30):
            msp.add_line((j, i), (j + 1, i), dxfattribs={"layer": "CUT"})
            msp.add_line((i, j), (i, j + 1), dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    run = run_camfab(["inspect", str(path), "--type", "knife", "--centre", "15.5,15.5", "-o",
                      str(tmp_path / "out")])
    _assert_refused_child(run, str(path), "meet three or more at a point")


def test_a_mark_drawn_to_the_outline_is_peeled_off(tmp_path: Path) -> None:
    """Lines hanging off the outline (a mark, a construction line) are not part of it."""
    doc, path = _dxf(tmp_path / "marked.dxf")
    msp = doc.modelspace()
    points = _eccentric(720)
    for a, b in zip(points, np.roll(points, -1, axis=0), strict=True):
        msp.add_line(a, b, dxfattribs={"layer": "CUT"})
    msp.add_line(points[0], points[0] + (20.0, 0.0), dxfattribs={"layer": "CUT"})
    msp.add_line(points[0] + (20.0, 0.0), points[0] + (20.0, 5.0), dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    code, err, out = _inspect(tmp_path, path, "--design", str(ECCENTRIC))
    assert code == 0, err
    report = json.loads((out / "marked-inspection.json").read_text())
    assert report["deviation"]["max_mm"] < 1e-3


def test_an_open_polyline_whose_ends_meet_is_an_outline(tmp_path: Path) -> None:
    doc, path = _dxf(tmp_path / "open.dxf")
    points = _eccentric(720)
    doc.modelspace().add_lwpolyline(np.vstack((points, points[:1])), close=False,
                                    dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    code, err, _ = _inspect(tmp_path, path, "--design", str(ECCENTRIC))
    assert code == 0, err


@pytest.mark.parametrize(("change", "said"), [
    ("degree", "degree 40"), ("points", "control and fit points"),
    ("knots", "ezdxf's audit of the damaged file")])
def test_splines_are_read_within_limits(tmp_path: Path, change: str, said: str) -> None:
    """A spline of a degree or with more points than inspect flattens in a second is refused,
    naming it; one whose knots do not fit its degree (a damaged file) ezdxf's audit removes,
    and the refusal says so."""
    doc, path = _dxf(tmp_path / "spline.dxf")
    msp = doc.modelspace()
    points = _eccentric(3000 if change == "points" else 60)
    if change == "points":
        msp.add_spline(fit_points=[(x, y) for x, y in points], dxfattribs={"layer": "CUT"})
    else:
        spline = msp.add_open_spline([(x, y) for x, y in points],
                                     degree=40 if change == "degree" else 3,
                                     dxfattribs={"layer": "CUT"})
        if change == "knots":
            spline.dxf.degree = 40
    doc.saveas(path)
    _refused(tmp_path, path, "--design", str(ECCENTRIC), said=(said,))


def test_long_lines_with_only_tiny_arcs_are_not_cut_into_millions_of_points(
        tmp_path: Path) -> None:
    """A square of 5 m with one arc of a micrometre's chord: the lines used to be cut as finely
    as the arc's chords of a few micrometres, into millions of points (and a drawing of them)."""
    doc, path = _dxf(tmp_path / "square.dxf")
    half = 2500.0
    doc.modelspace().add_lwpolyline(
        [(-half, -half, 0, 0, 0), (half, -half, 0, 0, 0), (half, half, 0, 0, 14.0),
         (half - 1e-3, half, 0, 0, 0), (-half, half, 0, 0, 0)], close=True,
        dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    run = run_camfab(["inspect", str(path), "--type", "roller", "--roller-radius", "5", "-o",
                      str(tmp_path / "out")])
    assert run.code == 0, run.stderr[-2000:]
    assert run.cpu_s < 20.0 and run.peak_mb < 1000.0, (run.cpu_s, run.peak_mb)
    assert (tmp_path / "out" / "square-inspection.html").stat().st_size < 1_000_000


# -- damaged DXF: read through ezdxf's recover path ----------------------------------------------

def _damaged(dxf: Path, damage: str, path: Path) -> Path:
    """*dxf* (camfab's) written to *path* with *damage*: ``huge-code`` the group code of the
    VIEW table's TABLE tag replaced by a huge number; ``swapped-code`` the handle's group code
    (5) of the first entity on layer PITCH replaced by 0, so that its handle reads as the type
    of an entity; ``duplicated-lines`` the 24 lines after that group code duplicated."""
    lines = dxf.read_text().splitlines()
    if damage == "huge-code":
        k = next(i for i in range(len(lines) - 2) if lines[i] == "TABLE" and
                 lines[i + 2] == "VIEW")
        lines[k - 1] = "1000000"
    else:
        codes = range(lines.index("ENTITIES") + 1, len(lines) - 1, 2)  # the group codes
        layer = next(i for i in codes if lines[i].strip() == "8" and lines[i + 1] == "PITCH")
        handle = max(i for i in codes if i < layer and lines[i].strip() == "0") + 2
        assert lines[handle].strip() == "5"
        if damage == "swapped-code":
            lines[handle] = "  0"
        else:
            lines[handle + 1:handle + 1] = lines[handle + 1:handle + 25]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("damage", ["huge-code", "swapped-code", "duplicated-lines"])
def test_a_damaged_dxf_whose_outline_is_whole_is_inspected(built: Path, tmp_path: Path,
                                                           damage: str) -> None:
    """Group codes out of step with their values stopped the plain reader (StopIteration) or
    left an entity without a layer (an internal error); ezdxf's recover path reads what is
    there, and the outline, untouched, inspects as the intact drawing does."""
    intact = built / "seed-10-4.dxf"
    path = _damaged(intact, damage, tmp_path / f"{damage}.dxf")
    assert path.read_bytes() != intact.read_bytes()
    deviations = []
    for profile in (intact, path):
        code, err, out = _inspect(tmp_path, profile, "--design", str(SEED))
        assert code == 0, err
        report = json.loads((out / f"{profile.stem}-inspection.json").read_text())
        deviations.append(report["deviation"]["max_mm"])
    assert deviations[1] == pytest.approx(deviations[0], abs=1e-12)


@pytest.mark.parametrize(("content", "said"), [
    (b"", "is not a readable DXF file"),
    (b"x,y\n0,0\n1,0\n0,1\n", "is not a readable DXF file"),
    (b"  0\nEOF\n", "is not a readable DXF file"),
    (b"  0\nSECTION\n  2\nENTITIES\nLINE\n  0\nENDSEC\n  0\nEOF\n",
     "is not a readable DXF file"),
])
def test_a_file_that_is_no_dxf_is_refused_as_not_readable(tmp_path: Path, content: bytes,
                                                          said: str) -> None:
    path = tmp_path / "drawing.dxf"
    path.write_bytes(content)
    _refused(tmp_path, path, "--design", str(ECCENTRIC), said=(said,))


# -- options ------------------------------------------------------------------------------------

@pytest.mark.parametrize(("option", "value", "said"), [
    ("--step", "1e-9", "must be from 0.01° to 30°"),
    ("--step", "0", "must be from 0.01° to 30°"),
    ("--step", "-1", "must be from 0.01° to 30°"),
    ("--step", "45", "must be from 0.01° to 30°"),
    ("--step", "nan", "finite"),
    ("--step", "", "must be an angle"),
    ("--smooth", "1e-9", "must be from 0.1° to 30°"),
    ("--smooth", "1e-300", "must be from 0.1° to 30°"),
    ("--smooth", "60", "must be from 0.1° to 30°"),
    ("--smooth", "1e300", "out of range"),
    ("--kerf", "11", "must be from 0 to 10 mm"),
    ("--kerf", "-0.1", "must be from 0 to 10 mm"),
    ("--centre", "1e308,0", "must lie within"),
    ("--roller-radius", "nan", "finite"),
    ("--roller-radius", "1e300", "out of range"),
])
def test_options_are_bounded(built: Path, tmp_path: Path, option: str, value: str,
                             said: str) -> None:
    _refused(tmp_path, built / "seed-10-4.dxf", "--design", str(SEED), option, value,
             said=(said,), named=option)


def test_a_designs_table_step_finer_than_any_table_is_refused(built: Path,
                                                              tmp_path: Path) -> None:
    """A design tabulating every 10⁻⁹° would have had inspect run its follower at 3.6·10¹¹
    angles (an array of 2.6 TiB): the design is refused on its line, --step or not."""
    design = tmp_path / "fine.yaml"
    design.write_text(SEED.read_text().replace("name: seed-10-4", "name: seed-10-4\n"
                                               "table_step: 0.000000001", 1))
    for extra in ((), ("--step", "1")):
        err = _refused(tmp_path, built / "seed-10-4.dxf", "--design", str(design), *extra,
                       said=("table_step: must be at least 0.01°",), named=f"{design}:")
        assert "(got 1e-09)" in err


#: A follower file's content (None: none given), the command line, where the refusal names
#: (``FILE``: the follower file, ``PROFILE``: the outline, else that option) and what it says.
FOLLOWER_REFUSALS = [
    ("type: rollr\nroller_radius: 5\n", [], "FILE: type", "unknown follower type 'rollr'"),
    ("type: 5\n", [], "FILE: type", "unknown follower type '5'"),
    ("roller_radius: 5\n", [], "FILE: type", "not given"),
    ("type: knife\nmotion: swinging\n", [], "FILE: motion",
     "must be translating or oscillating"),
    ("type: roller\n", [], "FILE", "a roller follower needs roller_radius"),
    ("type: knife\npivot_distance: 80\n", [], "FILE",
     "an oscillating follower needs pivot_distance and arm_length"),
    ("type: knife\npivot_distance: 80\narm_length: 60\npivot_side: up\n", [],
     "FILE: pivot_side", "must be right or left"),
    ("type: knife\ntolerance: -1\n", [], "FILE: tolerance", "must be > 0"),
    ("type: knife\noffset: 1000\n", [], "PROFILE", "the follower does not touch the outline"),
    (None, [], "PROFILE", "no follower to run over the outline"),
    (None, ["--type", "roller"], "--roller-radius", "not given"),
    (None, ["--type", "mushroom"], "--face-radius", "not given"),
    (None, ["--type", "knife", "--arm-length", "40"], "--pivot-distance", "not given"),
    (None, ["--type", "knife", "--offset", "1000"], "PROFILE",
     "the follower does not touch the outline"),
]


@pytest.mark.parametrize(("follower", "args", "named", "said"), FOLLOWER_REFUSALS)
def test_a_follower_refusal_names_its_file_or_option(built: Path, tmp_path: Path,
                                                     follower: str | None, args: list[str],
                                                     named: str, said: str) -> None:
    """Each refusal of the follower names where the value at fault was given: the follower
    file (and its key), the option, or the outline when nothing gives a follower or the
    follower misses it — never a bare "follower"."""
    profile = built / "seed-10-4.dxf"
    named = named.replace("PROFILE", str(profile))
    if follower is not None:
        file = tmp_path / "follower.yaml"
        file.write_text(follower)
        args = ["--follower", str(file), *args]
        named = named.replace("FILE", str(file))
    _refused(tmp_path, profile, *args, said=(said,), named=f"{named}: ")


# -- CSV ----------------------------------------------------------------------------------------

def _notched(count: int = 3600) -> np.ndarray:
    """A circle of radius 40 mm with a notch 20 mm deep and 2° wide at +Y: no roller enters it."""
    angle = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    radius = np.where(np.abs(angle - math.pi / 2) < math.radians(1.0), 20.0, 40.0)
    return np.column_stack((radius * np.cos(angle), radius * np.sin(angle)))


def _csv(path: Path, layout: str, points: np.ndarray) -> Path:
    """*points* written in one of the layouts a CSV may have."""
    rows = [(f"{x:.9f}", f"{y:.9f}") for x, y in points]
    if layout == "commas":
        lines = ["x,y", *(f"{x},{y}" for x, y in rows)]
    elif layout == "three-columns":
        lines = [f"{x},{y},7" for x, y in rows]
    elif layout == "semicolons":
        lines = [f"{x}; {y}" for x, y in rows]
    elif layout == "decimal-commas":
        lines = [f"{x};{y}".replace(".", ",") for x, y in rows]
    elif layout == "tabs":
        lines = [f"{x}\t{y}" for x, y in rows]
    else:
        digits = str.maketrans("0123456789", "٠١٢٣٤٥٦٧٨٩")
        lines = [f"{x},{y}".translate(digits) for x, y in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _notched_motion(tmp_path: Path, layout: str) -> dict:
    """The motion a roller of 5 mm at an offset of 30 mm measures on the notched outline."""
    path = _csv(tmp_path / f"{layout}.csv", layout, _notched())
    code, err, out = _inspect(tmp_path, path, "--type", "roller", "--roller-radius", "5",
                              "--offset", "30")
    assert code == 0, err
    report = json.loads((out / f"{layout}-inspection.json").read_text())
    return {"lift_from": report["method"]["lift_from"], **report["motion"]}


def test_a_notched_outline_with_an_offset_roller(tmp_path: Path) -> None:
    """The notch (to 20 mm) is the outline's smallest radius, but the roller cannot enter it,
    nor, at an offset of 30 mm, rest on a circle of 20 mm: lift is measured from its lowest
    position."""
    motion = _notched_motion(tmp_path, "commas")
    assert "lowest position" in motion["lift_from"]
    # riding the 40 mm circle its centre is at √(45² − 30²); over the notch it dips
    assert motion["rest_position_mm"] <= math.sqrt(45.0**2 - 30.0**2) + 1e-9
    assert 0.0 < motion["max_lift_mm"] < 1.0


@pytest.mark.parametrize("layout", ["three-columns", "semicolons", "decimal-commas", "tabs",
                                    "arabic-indic"])
def test_csv_layouts_read_the_same_points(tmp_path: Path, layout: str) -> None:
    assert _notched_motion(tmp_path, layout) == _notched_motion(tmp_path, "commas")


def test_a_follower_off_the_designs_base_circle_is_refused(tmp_path: Path) -> None:
    """seed-10-4's roller (7 mm) at an offset of 30 mm cannot reach its base circle (20 mm)."""
    path = _csv(tmp_path / "notched.csv", "commas", _notched())
    _refused(tmp_path, path, "--design", str(SEED), "--offset", "30", named=f"{SEED}: ",
             said=("the follower ",))


def test_a_csv_whose_first_line_is_a_comma_is_refused_on_that_line(tmp_path: Path) -> None:
    path = tmp_path / "comma.csv"
    path.write_text(",\n1,2\n3,4\n5,7\n")
    _refused(tmp_path, path, "--type", "knife", said=("comma.csv:1: not a pair of numbers",),
             named=f"{path}:1")


@pytest.mark.parametrize(("text", "line", "said"), [
    ("x,y\n1,2\n3,nan\n5,7\n", 3, "not a pair of finite numbers"),
    ("1,2\n3,1e308\n5,7\n", 2, "not a pair of finite numbers"),  # inf in mm
    ("1,2\n3,1e7\n5,7\n", None, "2.54e+08 mm from the origin"),
    ("1,2\n3;\n5,7\n", 2, "expected 2 values"),
    ("x\n1\n2\n3\n", 1, "not a pair of numbers"),
])
def test_bad_csv_rows_are_refused(tmp_path: Path, text: str, line: int | None,
                                  said: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    _refused(tmp_path, path, "--type", "knife", "--units", "in", said=(said,),
             named=str(path) if line is None else f"{path}:{line}")


# -- files that are not regular files -----------------------------------------------------------

@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "dev-urandom", "folder", "huge",
                                  "design-fifo", "follower-fifo"])
def test_files_that_are_not_regular_or_too_large_are_refused_at_once(tmp_path: Path,
                                                                     kind: str) -> None:
    profile = tmp_path / "scan.csv"
    profile.write_text("".join(f"{x:.6f},{y:.6f}\n" for x, y in _eccentric(360)))
    args = ["--type", "knife"]
    if kind in ("fifo", "design-fifo", "follower-fifo"):
        fifo = tmp_path / "pipe.csv"
        os.mkfifo(fifo)
        if kind == "fifo":
            profile = fifo
        else:
            args = ["--design" if kind == "design-fifo" else "--follower", str(fifo)]
        named, said = str(fifo), "is not a regular file"
    elif kind.startswith("dev-"):
        profile = Path("/dev") / kind[4:]
        if not profile.exists():
            pytest.skip(f"no {profile}")
        named, said = str(profile), "is not a regular file"
    elif kind == "folder":
        profile = tmp_path / "folder.dxf"
        profile.mkdir()
        named, said = str(profile), "is a folder"
    else:
        profile = tmp_path / "huge.dxf"
        with profile.open("wb") as stream:
            stream.truncate(100_000_000)  # sparse: no disk used
        named, said = str(profile), "is 100,000,000 bytes"
    run = run_camfab(["inspect", str(profile), *args, "-o", str(tmp_path / "out")],
                     wall_s=120.0)
    _assert_refused_child(run, named, said)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("which", ["profile", "design", "follower"])
def test_a_nul_in_a_path_is_refused_naming_it(built: Path, tmp_path: Path, which: str) -> None:
    """A path holding a NUL character (which no file system takes, and Python refuses with a
    ValueError before asking one) is refused as a file that cannot be read. The command line
    cannot pass one (a process's arguments cannot hold it), so the library is called."""
    from camfab.errors import CamfabError
    from camfab.inspect import InspectOptions, inspect

    bad = tmp_path / "a\0b"
    given = {"profile": built / "seed-10-4.dxf", "design": SEED, "out_dir": tmp_path / "out"}
    given["follower_file" if which == "follower" else which] = bad
    with pytest.raises(CamfabError) as refusal:
        inspect(InspectOptions(**given))
    assert str(refusal.value).startswith(f"{bad}: "), refusal.value
    assert "\n" not in str(refusal.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == []


@pytest.mark.parametrize("layer", [(), ("--layer", "pocket")])
def test_a_groove_cams_drawing_is_never_read_as_its_blank(tmp_path: Path,
                                                          layer: tuple[str, ...]) -> None:
    """A groove cam's DXF holds the plate's blank on CUT (a circle about the cam's centre) and
    the groove's two walls on POCKET. Read without a design, its largest CUT contour is that
    circle, which gave "lift 0 mm" and exit 0: a verdict about the wrong contour. It is refused
    in one line saying where the cam is, whichever of the two layers is asked for."""
    result = run_cli("build", str(DESIGNS / "demo-groove-roller.yaml"), "-o", str(tmp_path))
    assert result.exit_code in (0, 1), result.output + result.stderr
    drawing = tmp_path / "demo-groove-roller.dxf"
    code, err, out = _inspect(tmp_path, drawing, "--type", "roller", "--roller-radius", "8",
                              *layer)
    _assert_refused(code, err, out, str(drawing), "groove", "POCKET", "blank")
