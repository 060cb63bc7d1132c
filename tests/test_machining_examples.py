"""Every example design writes its machining programs — or a refusal that says where the tool
cannot cut it — and LinuxCNC's rs274 runs every program written without an error.

The tool each example is given is what a shop would pick for its kind: a 6 mm end mill for a
plate (a groove plate: one three quarters of the roller's diameter, narrower than the groove),
a cutter of the groove's width for a drum or a globoid (2 × roller radius + clearance); the
length of cut the part's depth (a plate's thickness: its outline is cut through) and a margin.
The geometry each program cuts is proven per kind (tests/test_machining_plates.py, _drum.py,
_globoid.py, _grinding.py); here, that none is left without a program or a reason."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from camfab.design.cam_types import CAM_TYPES
from camfab.pipeline import analyse, design_from_mapping, render

from .conftest import DESIGNS
from .rs274 import interpret, need_rs274

EXAMPLES = sorted(p.name for p in DESIGNS.glob("*.yaml"))
#: Margin of the length of cut over the part's depth (mm).
MARGIN_MM = 5.0


def settings(data: dict) -> dict:
    """The ``machining:`` section a shop would give the design *data* (lengths in mm)."""
    cam, follower = data["cam"], data["follower"]
    per_unit = 25.4 if data.get("units") == "in" else 1.0
    family = CAM_TYPES[cam["type"]].machining
    if family == "plate":
        depth = float(cam.get("thickness", 10)) * per_unit
        tool = 6.0
        if cam["type"] == "groove":
            tool = 1.5 * float(follower["roller_radius"]) * per_unit
    else:
        tool = (2 * float(follower["roller_radius"])
                + float(follower.get("groove_clearance", 0))) * per_unit
        depth = float(cam["groove_depth"]) * per_unit
    return {"tool_diameter": f"{tool:.6f} mm", "feed": "500 mm/min",
            "cut_length": f"{depth + MARGIN_MM:.6f} mm", "spindle_rpm": 12000}


#: A plate's program in LinuxCNC's form (the control's cutter compensation) and in Grbl's (the
#: tool centre's path); a drum's and a globoid's in LinuxCNC's alone (Grbl has no rotary axes).
FORMS = {"linuxcnc": {}, "grbl": {"dialect": "grbl"}}




def _cases() -> list[tuple[str, str]]:
    cases = []
    for name in EXAMPLES:
        cam_type = yaml.safe_load((DESIGNS / name).read_text())["cam"]["type"]
        plate = CAM_TYPES[cam_type].machining == "plate"
        cases += [(name, dialect) for dialect in FORMS if plate or dialect == "linuxcnc"]
    return cases


@pytest.mark.parametrize(("name", "dialect"), _cases())
def test_every_example_writes_a_program_rs274_runs_or_says_why_not(name: str, dialect: str,
                                                                    tmp_path: Path) -> None:
    need_rs274()
    path = DESIGNS / name
    data = yaml.safe_load(path.read_text())
    data = {**data, "machining": {**settings(data), **FORMS[dialect]}, "outputs": ["gcode"]}
    design = design_from_mapping(data, str(path), path.parent)
    artifacts = render(analyse(design, advice=False))
    assert artifacts.analysis is not None
    programs = {n: b for n, b in artifacts.files.items() if n.endswith(".ngc")}
    if not programs:
        (reason,) = [r for r in artifacts.not_produced if r.startswith("gcode")]
        check = re.search(r"see the (\S+) check", reason)
        if check is None:
            assert any(ch.isdigit() for ch in reason), f"a refusal says where: {reason}"
        else:  # where is the failed check's
            (finding,) = [f for f in artifacts.analysis.findings if f.id == check[1]]
            assert not finding.ok and finding.ranges_deg, reason
        return
    setups = {s.file: s for s in artifacts.analysis.machining}
    per_unit = 25.4 if design.units == "in" else 1.0
    for file, program in programs.items():
        tools = {t.number: t.diameter_mm / per_unit for t in setups[file].tools}
        moves = interpret(program, tools, tmp_path / file, design.units)
        assert (moves.kind != "traverse").any(), f"{file} cuts nothing"
