"""RS274NGC text: a program's blocks, numbers formatted once for the whole program.

camfab writes G-code as LinuxCNC's interpreter reads it (``dialect: linuxcnc``) or as Grbl
does (``grbl``: no cutter compensation, no canned cycles, no tool table; arcs only in the XY
plane). A :class:`Program` collects blocks; moves along arrays of points are formatted by one
``%`` over the whole array (:func:`moves`), not a call per point.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from camfab.arrays import Array

#: Decimals written per unit: 0.1 µm in millimetres, 0.01 thou in inches; 0.0001° for angles.
DECIMALS = {"mm": 4, "in": 5}
ANGLE_DECIMALS = 4
#: The rotary axes: their words are degrees whatever the program's length unit.
ROTARY = frozenset("ABC")


class Program:
    """A G-code program in *units* (``mm``: G21, ``in``: G20) for *dialect*; lengths given to
    it are millimetres and are scaled to the program's unit as they are written."""

    def __init__(self, units: str, dialect: str) -> None:
        self.units = units
        self.dialect = dialect
        self.scale = 1.0 if units == "mm" else 1 / 25.4
        self.decimals = DECIMALS[units]
        self.lines: list[str] = []

    def comment(self, text: str) -> None:
        """A comment block (parentheses inside *text* become brackets: a comment cannot hold
        them)."""
        self.lines.append(f"({text.replace('(', '[').replace(')', ']')})")

    def block(self, *words: str) -> None:
        """One block of *words* (already formatted, e.g. ``"G0"``, ``self.word("X", 1.0)``)."""
        self.lines.append(" ".join(w for w in words if w))

    def opening(self, header: Iterable[str], rpm: float, modes: tuple[str, ...] = ()) -> None:
        """The program's opening: *header* as comment blocks, the length unit (G21 or G20),
        the modal state (G17 G90 G94, and for LinuxCNC G40 G49 G80 too), then *modes* (each a
        block), tool 1 loaded with its length offset (LinuxCNC: Grbl has no tool table), and
        the spindle turning clockwise at *rpm* (to 0.1 rpm)."""
        grbl = self.dialect == "grbl"
        for line in header:
            self.comment(line)
        self.block("G21" if self.units == "mm" else "G20")
        self.block("G17 G90 G94" if grbl else "G17 G90 G40 G49 G80 G94")
        for mode in modes:
            self.block(mode)
        if not grbl:
            self.block("T1 M6")
            self.block("G43 H1")
        self.block(f"S{_number(rpm, 1)} M3")

    def closing(self) -> None:
        """The program's end: the spindle stopped, the program ended (M30: rewound)."""
        self.block("M5")
        self.block("M30")

    def word(self, axis: str, value: float) -> str:
        """*axis*'s word for *value* (mm, or degrees for A/B/C; a feed in mm/min for ``F``)."""
        if axis in ROTARY:
            return f"{axis}{_number(value, ANGLE_DECIMALS)}"
        return f"{axis}{_number(value * self.scale, self.decimals)}"

    def moves(self, code: str, axes: str, points: Array, feeds: Array | None = None) -> None:
        """One *code* block (``G0``, ``G1``) per row of *points* ((N, len(axes)); mm, degrees
        for rotary axes), with its ``F`` word from *feeds* ((N,), mm/min, or inverse time under
        G93: taken as is) when given."""
        points = np.asarray(points, dtype=float).reshape(len(points), len(axes))
        if len(points) == 0:
            return
        columns = [_column(points[:, k] if a in ROTARY else points[:, k] * self.scale,
                           ANGLE_DECIMALS if a in ROTARY else self.decimals)
                   for k, a in enumerate(axes)]
        template = code + "".join(f" {a}%s" for a in axes)
        if feeds is not None:
            columns.append(_column(np.asarray(feeds, dtype=float), 4))
            template += " F%s"
        rows = np.stack(columns, axis=1)
        self.lines.extend(((template + "\n") * len(rows) % tuple(rows.ravel())).splitlines())

    def text(self) -> bytes:
        """The program as a file's bytes: ``%`` first and last (the tape marks every control
        accepts), one block per line."""
        return ("%\n" + "\n".join(self.lines) + "\n%\n").encode("ascii")


def _number(value: float, decimals: int) -> str:
    text = f"{round(value, decimals) + 0.0:.{decimals}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def _column(values: Array, decimals: int) -> Array:
    """*values* as words' numbers: rounded to *decimals*, no negative zero, trailing zeros off
    (vectorised)."""
    rounded = np.round(values, decimals) + 0.0
    text = np.char.mod(f"%.{decimals}f", rounded)
    stripped = np.char.rstrip(np.char.rstrip(text, "0"), ".")
    return np.where(stripped == "-0", "0", stripped)
