"""Machining programs: the G-code (RS274NGC) that cuts a cam, and its setup sheet.

How a cam is cut is its type's row in the registry of cam types
(:attr:`~camfab.design.cam_types.CamTypeSpec.machining`): a ``plate`` is milled round the
contours of its drawing on three axes (:mod:`camfab.machining.plates`), a ``drum``'s groove on a
rotary A axis (:mod:`camfab.machining.drum`), a ``globoid``'s on A and a swinging B
(:mod:`camfab.machining.globoid`). Each module's ``machine`` takes the analysis, the part and
the design's ``machining:`` settings and returns a :class:`Machined`. This package writes
text; the pipeline writes the files.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import import_module
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.record import Analysis
    from camfab.analysis.setup_sheet import Setup
    from camfab.export.part import Part


@dataclass(frozen=True)
class Machined:
    """The programs of a part by file name (bytes) with their setup sheets, the findings their
    making measured (the wall a smaller tool leaves, ...), and, when the part cannot be cut as
    asked, why (then no program)."""

    files: dict[str, bytes] = field(default_factory=dict)
    setups: tuple[Setup, ...] = ()
    findings: tuple[Finding, ...] = ()
    withheld: str | None = None


#: ``CamTypeSpec.machining`` -> the module that cuts it.
MODULES = {"plate": "camfab.machining.plates", "drum": "camfab.machining.drum",
           "globoid": "camfab.machining.globoid"}


def machine(analysis: Analysis, part: Part) -> Machined:
    """The machining programs of *part* (the design has a ``machining:`` section)."""
    design = analysis.design
    assert design.machining is not None, "the design file's rules ask for the section"
    module = import_module(MODULES[design.cam.spec.machining])
    made: Machined = module.machine(analysis, part, design.machining)
    return made
