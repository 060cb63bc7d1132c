"""The machining programs: their size, the time to write them and the time to check them, for
one design of each way of cutting a cam (in process).

    python benchmarks/machining.py [--runs N] [--markdown]

Each design is read with a ``machining:`` section added, analysed and its part made once
(untimed); then, medians of N runs (milliseconds):

- ``write``: :func:`camfab.machining.machine` — the tool paths and the program's text (and the
  setup sheet, the grinding table or the cutter locations where the kind writes them);
- ``check``: LinuxCNC's ``rs274`` running the program and its canonical output read back
  (``tests/rs274.py``), what the tests do with every program; a fresh process each time;
- the program's size: bytes and blocks (lines).

Needs rs274 unpacked as ``.ci/run`` does (``$CAMFAB_RS274_ROOT``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from timing import ROOT, median_seconds

sys.path.insert(0, str(ROOT))

#: (label, design file, machining section added to it).
CASES = (
    ("disc, translating roller", "seed-10-4.yaml",
     {"tool_diameter": 6, "feed": 600, "cut_length": 20}),
    ("disc, flat face (inch)", "demo-inch-flat.yaml",
     {"tool_diameter": 0.25, "feed": 24, "cut_length": 1}),
    ("groove plate", "demo-groove-roller.yaml",
     {"tool_diameter": 6, "feed": 600, "cut_length": 20}),
    ("conjugate pair", "demo-conjugate.yaml",
     {"tool_diameter": 6, "feed": 600, "cut_length": 20}),
    ("linear", "demo-linear-roller.yaml",
     {"tool_diameter": 6, "feed": 600, "cut_length": 20}),
    ("drum, tool of the groove's width", "demo-cylindrical.yaml", "groove"),
    ("drum, 6 mm tool", "demo-cylindrical.yaml",
     {"tool_diameter": 6, "feed": 300, "cut_length": 30}),
    ("globoid (concave)", "demo-globoidal-concave.yaml", "groove"),
    ("globoid (convex)", "demo-globoidal-convex.yaml", "groove"),
)


def _design(name: str, section: dict | str):  # type: ignore[no-untyped-def]
    """The design *name* with the machining *section* (``"groove"``: a tool of the groove's
    width, the roller's diameter and the clearance) and ``outputs: [gcode]``."""
    import yaml

    from camfab.pipeline import design_from_mapping

    path = ROOT / "designs" / name
    data = yaml.safe_load(path.read_text())
    if section == "groove":
        follower = data["follower"]
        scale = 25.4 if data.get("units") == "in" else 1.0
        width = (2 * float(follower["roller_radius"])
                 + float(follower.get("groove_clearance", 0))) * scale
        depth = float(data["cam"]["groove_depth"]) * scale
        section = {"tool_diameter": f"{width} mm", "feed": "300 mm/min",
                   "cut_length": f"{depth + 10} mm"}
    data = {**data, "machining": section, "outputs": ["gcode"]}
    return design_from_mapping(data, str(path), path.parent)


def _row(label, design, machine, analyse, kind_of, interpret, runs):  # type: ignore[no-untyped-def]
    """The table's row of one case."""
    analysis = analyse(design, advice=False)
    part = kind_of(design.cam.type).part(analysis)
    made = machine(analysis, part)
    if made.withheld is not None:
        return (label, f"withheld: {made.withheld}", "", "", "", "")
    program_name = next(n for n in made.files if n.endswith(".ngc"))
    program = made.files[program_name]
    per_unit = 25.4 if design.units == "in" else 1.0
    tools = {t.number: t.diameter_mm / per_unit for s in made.setups for t in s.tools}
    write = median_seconds(lambda: machine(analysis, part), runs)
    with tempfile.TemporaryDirectory() as tmp:
        check = median_seconds(lambda: interpret(program, tools, Path(tmp), design.units), runs)
    blocks = program.count(b"\n")
    return (label, program_name, f"{len(program) / 1024:.1f}", f"{blocks:,}",
            f"{write * 1e3:.0f}", f"{check * 1e3:.0f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()

    from camfab.kinds import kind_of
    from camfab.machining import machine
    from camfab.pipeline import analyse
    from tests.rs274 import interpret

    rows = []
    for label, name, section in CASES:
        rows.append(_row(label, _design(name, section), machine, analyse, kind_of, interpret,
                         args.runs))
    header = ("case", "program", "KiB", "blocks", "write ms", "check ms")
    if args.markdown:
        print("| " + " | ".join(header) + " |")
        print("| --- | --- | ---: | ---: | ---: | ---: |")
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        for row in (header, *rows):
            print("  ".join(f"{c:>12}" if i > 1 else f"{c:<34}" for i, c in enumerate(row)))


if __name__ == "__main__":
    main()
