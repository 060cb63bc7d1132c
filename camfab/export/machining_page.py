"""The report page's setup sheets (its "Machining" section), one per machining program written:
the stock, the work zero in words and in a sketch, the machine's axes, the tools, the operations
in order with their estimated times, the estimated cycle time, the notes and the toolpath.

Lengths and feeds are shown in the program's units (the design's: mm or in); the JSON report
holds the same in millimetres (:func:`camfab.export.report_json.machining_list`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.analysis.setup_sheet import Setup

#: What each machine axis letter is, for the setup sheet's list of axes.
AXIS_WORDS = {"X": "X", "Y": "Y", "Z": "Z", "A": "A (turns about X)", "B": "B (turns about Y)",
              "C": "C (turns about Z)"}


def minutes_words(minutes: float) -> str:
    """An estimated time (*minutes*) as a person reads it: "0.45 min", "12.3 min",
    "2 h 05 min"."""
    if minutes < 59.5:
        return f"{minutes:.3g} min"
    whole = round(minutes)
    return f"{whole // 60} h {whole % 60:02d} min"


def num(value: float) -> str:
    """A length or a feed in a table: five significant digits, whole numbers in full."""
    return f"{value:.5g}" if abs(value) < 1e5 else f"{value:.0f}"


def minutes_number(minutes: float) -> str:
    """An estimated time (min) in a table: three significant digits, whole minutes from
    100 up."""
    return f"{minutes:.3g}" if minutes < 99.95 else f"{minutes:.0f}"


def cycle_time_line(setup: Setup) -> str:
    """The program's estimated cycle time in a line (the terminal's, after a build)."""
    count = len(setup.operations)
    return (f"{setup.file}: estimated cycle time {minutes_words(setup.minutes)} "
            f"({count} operation{'s' if count != 1 else ''}, at the feeds; rapid moves not "
            "counted)")


def axes_words(axes: str) -> str:
    """The machine's axes (``XZA``) in words: "X, Z, A (turns about X)"."""
    return ", ".join(AXIS_WORDS.get(letter, letter) for letter in axes.upper())


def machining_section(analysis: Analysis, geometry: dict[str, Any]) -> list[dict[str, Any]]:
    """Each program's setup sheet as the page shows it (*geometry*: the JSON report's, mm):
    its rows (the stock, the work zero, the axes, the estimated cycle time), notes, tool table,
    operations table, total time and pictures (SVG)."""
    from camfab.export.machining_figures import toolpath_figure, work_zero_sketch

    design = analysis.design
    unit = design.units
    scale = 1.0 / design.mm_per_unit
    sheets = []
    for k, setup in enumerate(analysis.machining):
        tools = [[str(t.number), t.what, num(t.diameter_mm * scale),
                  "—" if t.flutes is None else str(t.flutes),
                  "—" if t.cut_length_mm is None else num(t.cut_length_mm * scale)]
                 for t in setup.tools]
        operations = [[str(i), op.name, f"T{op.tool}", str(op.passes),
                       num(op.feed_mm_min * scale), minutes_number(op.minutes)]
                      for i, op in enumerate(setup.operations, start=1)]
        sheets.append({
            "file": setup.file,
            "rows": [("stock", setup.stock), ("work zero", setup.work_zero),
                     ("axes", axes_words(setup.axes)),
                     ("estimated cycle time", minutes_words(setup.minutes))],
            "notes": list(setup.notes), "unit": unit, "tools": tools, "operations": operations,
            "total": minutes_number(setup.minutes),
            "sketch": work_zero_sketch(setup, analysis, geometry, f"workzero{k}"),
            "toolpath": toolpath_figure(setup, f"toolpath{k}"),
        })
    return sheets
