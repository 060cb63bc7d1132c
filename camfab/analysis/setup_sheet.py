"""The setup sheet of a machining program, as data the report shows: the stock, the work zero,
each tool and each operation with its estimated time (:mod:`camfab.machining` makes it)."""

from __future__ import annotations

from dataclasses import dataclass, field

from camfab.arrays import Array


@dataclass(frozen=True)
class Tool:
    """A tool of the program: its number in the program and the tool table, and its size (mm)."""

    number: int
    what: str  # "flat end mill", "grinding wheel"
    diameter_mm: float
    flutes: int | None = None
    cut_length_mm: float | None = None


@dataclass(frozen=True)
class Operation:
    """One operation: what it cuts, with which tool, at which feeds, and its estimated time
    (min) from the lengths of its moves at their feeds (rapid moves not counted)."""

    name: str
    tool: int
    feed_mm_min: float
    minutes: float
    passes: int = 1


@dataclass(frozen=True)
class Toolpath:
    """What the toolpath's picture draws: (N, 2) points of the tool's centre in the picture's
    plane (``x_label``, ``y_label``; mm, or degrees for an angle), cutting and rapid moves apart;
    each an array of points whose rows ``NaN`` split into pieces."""

    x_label: str
    y_label: str
    cutting: Array
    rapid: Array


@dataclass(frozen=True)
class Setup:
    """A program's setup sheet: its file, the stock and the work zero in words, the machine's
    axes (``XYZ``, ``XZA``, ``XZAB``, ``XC``), the tools, the operations in order and the
    toolpath's picture; *notes* say what else the operator must know (the wall error a smaller
    tool leaves, ...)."""

    file: str
    stock: str
    work_zero: str
    axes: str
    tools: tuple[Tool, ...]
    operations: tuple[Operation, ...]
    toolpath: Toolpath | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def minutes(self) -> float:
        """The estimated cycle time (min): the operations' times summed."""
        return sum(op.minutes for op in self.operations)
