"""Cam kinds: each kind of cam is one module implementing :class:`CamKind`, found through
:data:`REGISTRY` by the design's ``cam.type``.

A kind analyses a design (its geometry, key numbers and findings), describes the part it makes
as data the format writers serialise, and reads the files back, running the follower over
them. The pipeline knows no kind: it asks :func:`kind_of` for the design's and calls it.
Adding a kind means adding one module here and its row to the design file's registry of cam
types, :data:`camfab.design.cam_types.CAM_TYPES`, which names the module
(``docs/architecture.md``).
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Protocol

from camfab.design.cam_types import CAM_TYPES

if TYPE_CHECKING:
    from camfab.analysis.findings import Finding
    from camfab.analysis.kinematics import MotionUnits, SegmentStats
    from camfab.analysis.record import Analysis
    from camfab.analysis.sizing import ProblemOf
    from camfab.analysis.verification import Verification
    from camfab.arrays import Array
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.export.serialise import PartFiles
    from camfab.kinds.scene3d import Scene3D
    from camfab.motion.program import MotionProgram


class CamKind(Protocol):
    """What a kind of cam does for the pipeline."""

    #: True when the cam drives its follower both ways (a groove, a conjugate pair, a yoke): no
    #: spring to size, and the forces on either side are the kind's own.
    drives_both_ways: bool

    #: What turns on the shaft and needs a bore ("plate", "drum", "globoid"), or None for a cam
    #: on no shaft (a linear cam slides).
    mounted: str | None

    #: Why ``camfab inspect`` cannot hold a made part of this kind to its design (None: it can).
    inspect_refusal: str | None

    def check(self, design: Design) -> None:
        """The rules of the design file that need the kind's geometry (raising
        :class:`~camfab.design.rules.RuleViolation` like the design's own rules)."""

    def analyse(self, design: Design, program: MotionProgram, units: MotionUnits,
                stats: list[SegmentStats], findings: list[Finding]) -> Analysis:
        """The analysis of *design*: the kind's geometry, numbers and checks, before the
        *findings* every cam has (continuity, bore)."""

    def part(self, analysis: Analysis) -> Part:
        """What the cam is made of, as data the format writers serialise: its drawings (DXF),
        views (SVG) and solid (STL), which of them its read-back needs, and why an output the
        cam cannot have is withheld."""

    def verify(self, analysis: Analysis, part: Part, files: PartFiles) -> tuple[
            Analysis, Verification]:
        """The *files* made of *part* read back as their users would, the follower run over
        them: the analysis (with what reading them back changes) and what was found."""

    def scene(self, analysis: Analysis, theta: Array) -> Scene3D:
        """The part and its follower in three dimensions at the cam angles *theta* (rad, the
        report's animation frames): where each STL file's part and the follower stand at each,
        and the follower's solids, from the kind's exact geometry (mm, in the STL files'
        coordinates: :mod:`camfab.kinds.scene3d`)."""


def sizing_of(cam_type: str) -> ProblemOf | None:
    """The sizing of a ``cam.type``'s radius (:mod:`camfab.analysis.sizing`): its kind's
    ``size_problem``, or None for a kind camfab does not size (its shape sets its motion, or it
    has no radius to size)."""
    problem: ProblemOf | None = getattr(kind_of(cam_type), "size_problem", None)
    return problem


#: ``cam.type`` -> the module holding its kind (imported when a design of that type is built),
#: as ``module`` (its ``KIND``) or ``module:NAME`` for a module holding more than one: the
#: ``kind`` of each row of the design file's registry of cam types
#: (:data:`camfab.design.cam_types.CAM_TYPES`).
REGISTRY: dict[str, str] = {name: spec.kind for name, spec in CAM_TYPES.items()}


def kind_of(cam_type: str) -> CamKind:
    """The kind of a ``cam.type`` (the design has been validated: the type is registered)."""
    module, _, name = REGISTRY[cam_type].partition(":")
    kind: CamKind = getattr(import_module(module), name or "KIND")
    return kind


def check_design(design: Design) -> None:
    """The rules of *design*'s kind that need its geometry (see :meth:`CamKind.check`)."""
    kind_of(design.cam.type).check(design)
