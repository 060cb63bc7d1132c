"""camfab's deviation of a scan's points from the exact flanks, checked against an independent
consumer: CloudCompare's signed cloud-to-mesh distance (:mod:`tests.cloudcompare`) from the STL
camfab builds of the part.

For a drum, a globoid and a groove plate, a synthetic scan (:mod:`tests.scan_synth`) of
100,000 points in the cam frame, 60 % on the flanks, with a bump of 0.05 mm (radius 2 mm) and
noise of 0.01 mm, is matched to the scan model's flanks (``point_deviations`` with the part's
other surfaces and a gate of 1 mm). Both signs are the same: + out of the material (camfab:
material left on, the point in the air beside the flank; CloudCompare: outside the solid).

The STL stands off the exact flanks by its own sampling error: CloudCompare's distance of each
flank point's place on the design's surface (``design_points``) measures it there. So on every
point camfab keeps on a flank, away from the flank's edges (where another face of the part may
be nearer than the flank: within the point's own deviation and 0.02 mm of the edge, some
0.7 % of the flank points), the two agree within the largest of those (0.25 to 6.7 µm here)
and 0.2 µm, and camfab's deviation is CloudCompare's less the STL's own error at that place
within 0.2 µm (on the three scans here 0.1 µm at most).

A point is set aside when it lies nearer another face of the part than its flank, that face's
normal more than 20° from the flank's (not the flank's own continuation past its grid, as a
globoid's wall below the roller's inner end), the faces sampled evenly by area (a regression:
samples 4–16 mm apart on large faces left points of the drum's outer surface and the groove
plate's face on the flank with deviations up to the gate, and a globoid's wall continued set
aside 2.4 % of its flank points).

Known departure, a test marked as an expected failure (strict: it fails once fixed): the
drum's STL stands up to some 2 µm off its walls where the groove is steepest (60–90°,
240–270°), over the design's tolerance of 1 µm (its groove is sampled to half of it).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from camfab.arrays import Array
from camfab.inspect.scan_deviation import (
    Others,
    PointDeviations,
    flank_nodes,
    point_deviations,
)

from .cloudcompare import c2m_distances, need_cloudcompare
from .conftest import DESIGNS
from .scan_synth import Synthetic, part_of, synthetic_scan

#: The scans' points, noise (mm) and bump's height and radius (mm); camfab's gate (mm).
POINTS = 100_000
NOISE_MM = 0.01
BUMP_MM, BUMP_RADIUS_MM = 0.05, 2.0
GATE_MM = 1.0

#: CloudCompare's float32 arithmetic on coordinates up to some 100 mm (mm).
FLOAT32_MM = 2e-5

#: How near (mm) camfab's deviation is to CloudCompare's less the STL's own error there: the
#: scan model's tangent planes (well under 0.2 µm) and float32.
SHARP_MM = 2e-4

#: A flank point is compared when it lies farther than its deviation and this (mm) from the
#: flank's edges: nearer, CloudCompare may measure it (or its place on the design) from
#: another face of the part, the STL's edge a little off the exact one.
EDGE_MARGIN_MM = 0.02

#: Most of a scan's flank points left out of the comparison for lying by an edge (share).
MOST_AT_EDGES = 0.01

#: Most of the flank points camfab may set aside (share), each within this (mm) of an edge.
MOST_SET_ASIDE = 0.005
SET_ASIDE_NEAR_EDGE_MM = 0.1

#: Most of the other surfaces' points camfab may keep (share), each at a flank's edge column.
MOST_OTHERS_KEPT = 0.015

#: CPU seconds one CloudCompare run may take (one takes about one).
CPU_S = 120.0

STL_OVER = pytest.mark.xfail(strict=True, reason=(
    "the drum's STL stands up to ~2 µm off its walls where the groove is steep, over the "
    "design's 1 µm tolerance"))
@dataclass(frozen=True)
class Measured:
    """A scan and its distances: camfab's deviations, CloudCompare's of each point (mm), of
    each flank point's place on the design (mm, NaN for the other points), and the design's
    manufacturing tolerance (mm)."""

    name: str
    scan: Synthetic
    dev: PointDeviations
    cc: Array
    cc_design: Array
    tolerance: float

    @property
    def on(self) -> np.ndarray:
        return self.scan.flank >= 0

    @property
    def kept(self) -> np.ndarray:
        return self.dev.flank >= 0

    def edge_mm(self) -> Array:
        """Each flank point's distance (mm) across its flank from the nearer of its first and
        last columns (NaN off the flanks)."""
        flanks = self.scan.model.flanks
        first = np.array([f.across[0] for f in flanks])
        last = np.array([f.across[-1] for f in flanks])
        index = np.maximum(self.scan.flank, 0)
        return np.minimum(self.scan.across - first[index], last[index] - self.scan.across)

    def compared(self) -> np.ndarray:
        """The points both measure from the flank: kept by camfab, on a flank, farther from
        its edges than their deviation and :data:`EDGE_MARGIN_MM`."""
        with np.errstate(invalid="ignore"):
            return self.kept & self.on & (
                self.edge_mm() > np.abs(self.scan.deviation) + EDGE_MARGIN_MM)


@pytest.fixture(scope="module")
def measured(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
             ) -> Measured:
    """The scan of the design *request.param*, camfab's deviations and CloudCompare's."""
    from camfab.export.stl import render_stl
    from camfab.kinds import kind_of

    need_cloudcompare()
    name: str = request.param
    path = DESIGNS / f"{name}.yaml"
    flank = part_of(str(path)).model.flanks[0]
    middle = float(0.5 * (flank.across[0] + flank.across[-1]))
    scan = synthetic_scan(path, points=POINTS, noise_mm=NOISE_MM, seed=11,
                          bump=(90.0, middle, BUMP_MM, BUMP_RADIUS_MM, 0))
    nodes = flank_nodes(scan.model)
    dev = point_deviations(scan.points, nodes, Others(scan.model, nodes), GATE_MM)
    work = tmp_path_factory.mktemp(name)
    part = kind_of(scan.analysis.design.cam.type).part(scan.analysis)
    stl = work / f"{name}.stl"
    stl.write_bytes(render_stl(part.solid).data)
    on = scan.flank >= 0
    cloud = np.vstack((scan.points, scan.design_points[on]))
    distances = c2m_distances(cloud, stl, Path(work) / "cloudcompare", cpu_s=CPU_S)
    cc_design = np.full(POINTS, np.nan)
    cc_design[on] = distances[POINTS:]
    return Measured(name, scan, dev, distances[:POINTS], cc_design,
                    scan.analysis.design.manufacturing.tolerance)


def cases(**marks: pytest.MarkDecorator) -> list:  # type: ignore[type-arg]
    """The three designs, as the *measured* fixture's parameters, with *marks* by name."""
    names = ["demo-cylindrical", "demo-globoidal-convex", "demo-groove-roller"]
    return [pytest.param(n, marks=[marks[n]] if n in marks else [], id=n) for n in names]


@pytest.mark.parametrize("measured", cases(**{"demo-cylindrical": STL_OVER}), indirect=True)
def test_the_stl_holds_the_flanks_within_the_designs_tolerance(measured: Measured) -> None:
    """CloudCompare's distance of the exact flanks' points from camfab's STL: within the
    design's manufacturing tolerance (the globoid's 6.7 µm of 10; the groove plate's 0.25 µm
    of 1; the drum's 2.0 µm of 1)."""
    stl_error = float(np.nanmax(np.abs(measured.cc_design)))
    assert stl_error <= measured.tolerance + FLOAT32_MM, stl_error


@pytest.mark.parametrize("measured", cases(), indirect=True)
def test_camfab_deviation_agrees_with_cloudcompare(measured: Measured) -> None:
    """On the points camfab keeps on a flank, away from its edges: camfab's deviation is
    CloudCompare's less the STL's own error at the point's place within 0.2 µm, so
    CloudCompare's within the largest of those errors and 0.2 µm; the bump stands out on both,
    with the same sign."""
    m = measured
    use = m.compared()
    assert np.count_nonzero(m.on & m.kept & ~use) <= MOST_AT_EDGES * np.count_nonzero(m.on)
    camfab, cc = m.dev.deviation[use], m.cc[use]
    bound = float(np.nanmax(np.abs(m.cc_design))) + SHARP_MM
    assert float(np.abs(camfab - cc).max()) <= bound, bound
    sharp = np.abs(camfab - (cc - m.cc_design[use]))
    assert float(sharp.max()) <= SHARP_MM
    clear = np.abs(cc) > bound
    assert np.array_equal(np.sign(camfab[clear]), np.sign(cc[clear]))
    top = use & (m.scan.surface > 0.8 * BUMP_MM)
    assert np.count_nonzero(top) >= 5
    assert np.all(m.dev.deviation[top] > 0.0) and np.all(m.cc[top] > 0.0)
    lifted = m.dev.deviation[top] - m.scan.surface[top]  # the noise alone
    assert abs(float(lifted.mean())) <= 4 * NOISE_MM / np.sqrt(lifted.size)


@pytest.mark.parametrize("measured", cases(), indirect=True)
def test_the_flank_points_are_kept(measured: Measured) -> None:
    """Of the points on a flank camfab sets aside at most 0.5 %, each within 0.1 mm of the
    flank's edge: points within the scanner's noise of an edge may lie nearer the face beyond
    it (a groove's floor), and are set aside with it."""
    m = measured
    aside = m.on & ~m.kept
    assert np.count_nonzero(aside) <= MOST_SET_ASIDE * np.count_nonzero(m.on)
    assert np.all(m.edge_mm()[aside] <= SET_ASIDE_NEAR_EDGE_MM)


@pytest.mark.parametrize("measured", cases(), indirect=True)
def test_the_other_surfaces_points_are_set_aside_but_at_the_flanks_edges(
        measured: Measured) -> None:
    """Of the points on the part's other surfaces camfab keeps at most 1.5 %, each matched to
    a node of a flank's first or last column: they lie beside its edge."""
    m = measured
    others_kept = ~m.on & m.kept
    assert np.count_nonzero(others_kept) <= MOST_OTHERS_KEPT * np.count_nonzero(~m.on)
    last = np.array([f.across.size - 1 for f in m.scan.model.flanks])
    columns, flanks = m.dev.col[others_kept], m.dev.flank[others_kept]
    assert np.all((columns == 0) | (columns == last[flanks]))


@pytest.mark.parametrize("measured", cases(), indirect=True)
def test_the_other_surfaces_points_kept_carry_no_false_deviation(measured: Measured) -> None:
    """The points of the other surfaces camfab keeps at a flank's edge lie on the part: their
    deviation is within the noise (4 σ) and the STL's error of CloudCompare's (a point nearer
    another face of the part than its flank, that face not the flank's own continuation, is
    set aside)."""
    m = measured
    others_kept = ~m.on & m.kept
    if not others_kept.any():
        return
    bound = 4 * NOISE_MM + float(np.nanmax(np.abs(m.cc_design)))
    assert float(np.abs(m.dev.deviation[others_kept] - m.cc[others_kept]).max()) <= bound
