"""The records of a build's read-back: what reading its files back found (the follower run over
the geometry as written, the STL as a reader sees it). Made by the kinds and the format readers,
carried by the analysis to the report."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.geometry.conjugate import Hold
    from camfab.geometry.disc_geometry import LiftCheck


@dataclass(frozen=True)
class Verification:
    """What reading the files back found.

    ``lift`` is the follower run over the geometry as written; ``source`` says which; ``entities``
    counts the lines and arcs of the CUT contour read back; ``deviation_mm`` is the largest
    distance of the CUT contours read back from the exact ones, measured both ways (a plate's
    working curve grown by kerf/2 with a kerf, an undercut plate's cut cam as computed, its holes
    shrunk by kerf/2; a drum's walls developed at its surface; None where there is no exact
    curve to measure against: a folded groove); the verification fails when it exceeds the
    tolerance; ``stl`` is the STL read back (when one is made).
    """

    lift: LiftCheck
    source: str
    entities: int
    deviation_mm: float | None
    stl: StlCheck | None = None
    exempt: bool = False
    #: Why an exempt build's files hold no cam, and the check that says more.
    exempt_because: str = "the groove folds over itself"
    exempt_check: str = "groove"
    hold: Hold | None = None
    #: An undercut cam's files held to the cam camfab computed, whose motion departs from the
    #: design on purpose: the follower's lift over the geometry as written less its lift over
    #: the cut cam (None when there is no such reference: a folded groove).
    cut_error: LiftCheck | None = None
    #: Why the motion of the cam camfab computed departs from the design (``cut_error``), the
    #: check that says by how much, that cam, and where it follows the design.
    departs_because: str = "the cam is undercut"
    departs_check: str = "undercut"
    departs_cam: str = "the cut cam"
    departs_by: str = "the undercut leaves it"
    #: The STEP read back (when one is made).
    step: StepCheck | None = None
    #: The outputs asked for that this part could not have, each with why.
    withheld: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class StlCheck:
    """The STL as a reader sees it: read back from its bytes (coincident corners merged).
    ``short_edges`` and ``sliver_faces`` count what breaks the rule of
    :mod:`camfab.export.mesh_quality` (an edge shared by two faces counts twice).

    ``volume_allowance_mm3`` is how far the volume may differ from the part's area × thickness:
    the tolerance along every contour, through the thickness.
    """

    faces: int
    watertight: bool
    consistent_winding: bool
    degenerate_faces: int
    short_edges: int
    sliver_faces: int
    volume_mm3: float
    expected_volume_mm3: float
    volume_allowance_mm3: float

    @property
    def ok(self) -> bool:
        """Closed, consistently wound with outward normals (positive volume), no degenerate
        face, short edge or sliver, and the volume of the part."""
        return (self.watertight and self.consistent_winding and self.degenerate_faces == 0
                and self.short_edges == 0 and self.sliver_faces == 0
                and abs(self.volume_mm3 - self.expected_volume_mm3) <= self.volume_allowance_mm3)


@dataclass(frozen=True)
class StepCheck:
    """The STEP read back with OpenCASCADE: its solids (and how many the part has), whether
    ``BRepCheck_Analyzer`` finds the shape valid, its volume against the part's exact one
    (mm³, the allowance: the tolerance over the part's surface), how far points sampled on its
    faces lie from the part's contours of lines and arcs (mm, across; and how far its flat faces
    lie off their planes) against the tolerance, and its entities: circles, cylinders and
    B-splines."""

    solids: int
    expected_solids: int
    valid: bool
    volume_mm3: float
    expected_volume_mm3: float
    volume_allowance_mm3: float
    deviation_mm: float
    tolerance_mm: float
    circles: int
    cylinders: int
    b_splines: int
    #: The part has surfaces fitted through exact points (B-splines: a drum's or a globoid's
    #: groove), its volume held to the STL's.
    fitted: bool = False

    @property
    def as_made(self) -> bool:
        """Valid, one solid per part, and B-splines only where the part's surfaces were fitted."""
        return (self.valid and self.solids == self.expected_solids
                and (self.fitted or self.b_splines == 0))

    @property
    def ok(self) -> bool:
        """One valid closed solid per part, of the part's volume, its faces on the contours."""
        return (self.as_made
                and abs(self.volume_mm3 - self.expected_volume_mm3) <= self.volume_allowance_mm3
                and self.deviation_mm <= self.tolerance_mm)
