"""FreeCAD (from Debian, ``freecadcmd``) on camfab's STEP files, as a user would meet them: its full
check (``shape.check(True)``, OpenCASCADE's BOP argument check, curves on their surfaces included)
finds nothing in the STEP of any example plate (tests/test_step.py checks the drum's and the
globoids'), and its Import module (File > Open) makes of a conjugate pair an assembly named for
the design holding its two plates by name. One FreeCAD start per test, run in a scratch HOME so
that neither the user's preferences nor the test's touch each other."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

from camfab.pipeline import analyse, load_design

from .conftest import DESIGN_FILES, ROOT, need_step_extra, tool

need_step_extra()  # CI installs the extra: there, its absence fails


def freecad(files: list[Path], home: Path, **flags: str) -> dict[str, dict]:
    """What tests/freecad_step.py prints of *files* in one ``freecadcmd`` run, by file name."""
    program = tool("freecadcmd", "freecad-python3")
    home.mkdir(exist_ok=True)
    run = subprocess.run([program, str(ROOT / "tests" / "freecad_step.py")],
                         env={**os.environ, "HOME": str(home), **flags,
                              "CAMFAB_STEP": os.pathsep.join(str(f) for f in files)},
                         capture_output=True, text=True, timeout=600, check=False)
    found = {}
    for line in run.stdout.splitlines():
        if "CAMFAB {" in line:  # (FreeCAD's progress bar may share the line)
            record = json.loads(line[line.index("CAMFAB {") + len("CAMFAB "):])
            found[record["file"]] = record
    assert len(found) == len(files), run.stdout[-3000:] + run.stderr[-3000:]
    return found


def step_of(path: Path) -> tuple[str, bytes] | None:
    """The design's name and its STEP bytes as a build writes them, or None for a design whose
    part has no exact solid."""
    from camfab.export.step import NotExact, render_step
    from camfab.kinds import kind_of

    design = load_design(path)
    part = kind_of(design.cam.type).part(analyse(design))
    if part.solid is None or "step" in part.withheld:
        return None
    try:
        return design.name, render_step(part.solid, design.name).data
    except NotExact:
        return None


def test_freecads_full_check_passes_on_every_plates_step(tmp_path: Path) -> None:
    # (the drum's and the globoids' are checked by tests/test_step.py, which builds them anyway)
    files, kinds = [], set()
    for path in DESIGN_FILES:
        kind = load_design(path).cam.type
        if kind in ("cylindrical", "globoidal"):
            continue
        made = step_of(path)
        assert made is not None, path
        files.append(tmp_path / f"{made[0]}.step")
        files[-1].write_bytes(made[1])
        kinds.add(kind)
    assert {"conjugate", "constant-breadth", "disc", "groove", "linear"} <= kinds, kinds
    found = freecad(files, tmp_path / "home", CAMFAB_FULL_CHECK="1")
    # each solid on its own: a pair's plates touch face to face, which the check of the two as
    # one shape reports as the shape crossing itself
    failed = {name: [m for m in record["full_check"] if m is not None]
              for name, record in found.items()
              if any(m is not None for m in record["full_check"]) or not record["valid"]}
    assert not failed, failed


def test_freecad_opens_a_pair_as_its_two_plates_named_in_an_assembly(tmp_path: Path) -> None:
    names = []
    for path in (ROOT / "designs" / "demo-conjugate.yaml", ROOT / "designs" / "seed-10-4.yaml"):
        made = step_of(path)
        assert made is not None
        (tmp_path / f"{made[0]}.step").write_bytes(made[1])
        names.append(made[0])
    pair, plate = names
    found = freecad([tmp_path / f"{n}.step" for n in names], tmp_path / "home",
                    CAMFAB_IMPORT="1")
    objects = {label: (kind, solids) for label, kind, solids in found[f"{pair}.step"]["objects"]}
    assert objects == {f"{pair}-a": ("Part::Feature", 1), f"{pair}-b": ("Part::Feature", 1),
                       pair: ("App::Part", 2)}, objects
    assert found[f"{plate}.step"]["objects"] == [[plate, "Part::Feature", 1]]
