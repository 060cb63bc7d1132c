"""A plate cam's files hold its exact curve within ``manufacturing.tolerance``: designs whose
check failed (a mushroom's follower run that found no contact on a dwell) build with the
``verification`` check passing, and, measured independently, every point of the CUT contour
(read with ezdxf, its arcs flattened by ezdxf) lies within the tolerance of the exact working
curve (camfab's closed-form evaluator on a grid far finer than the tolerance needs), and every
point of that curve within the tolerance of the contour."""

from __future__ import annotations

import io
import math

import ezdxf
import numpy as np
import pytest
import shapely

from camfab.geometry.disc_geometry import disc_cam
from camfab.pipeline import analyse, design_from_text, verify_exports

from .dxf_loops import loops

#: Cam-angle step of the exact reference curve: its chords stray under 1e-6 mm from the curve
#: on these plates (c²/8ρ with c ≈ 0.02 mm).
REFERENCE_STEP = math.radians(0.02)

MUSHROOM_SWINGING_OVER_A_DWELL = """\
name: mushroom-dwell
cam: {type: disc, rotation: cw, base_radius: 49.97, thickness: 8, bore: 10}
follower: {type: mushroom, motion: oscillating, pivot_distance: 94.455, arm_length: 72.998,
           face_radius: 98.092}
motion:
  - rise:   {angle: 130, lift: 19.935, law: cycloidal}
  - dwell:  {angle: 102}
  - return: {angle: 118, law: cycloidal}
  - dwell:  {angle: 10}
manufacturing: {tolerance: 0.025105}
"""


def build(text: str):  # type: ignore[no-untyped-def]
    """The design of *text*, its DXF as a reader opens it, and its ``verification`` check: the
    build's own reading back of the files it writes."""
    design = design_from_text(text)
    analysis, exports = verify_exports(analyse(design, advice=False), ("dxf",))
    dxf = exports.files["dxf"][f"{design.name}.dxf"]
    check = next(f for f in analysis.findings if f.id == "verification")
    return design, ezdxf.read(io.StringIO(dxf.decode())), check


def exact_working(design) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The exact working curve (mm) at every :data:`REFERENCE_STEP` of each segment, both
    ends of each included (a corner at a joint is a point of it)."""
    cam = disc_cam(design)
    _, theta, motion = design.program.segment_grid(REFERENCE_STEP)
    return cam.working(theta, motion).xy


def polyline_distance(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Distance (mm) of each of *points* from the closed polyline through *ring*: the nearest
    of its segments, found through shapely's tree of them."""
    segments = shapely.linestrings(np.stack((ring, np.roll(ring, -1, axis=0)), axis=1))
    _, distance = shapely.STRtree(segments).query_nearest(shapely.points(points),
                                                          return_distance=True, all_matches=False)
    return distance


def distances(contour: np.ndarray, exact: np.ndarray) -> tuple[float, float]:
    """The largest distance (mm) of the contour's points from the exact curve, and of the exact
    curve's points from the contour (both as closed polylines)."""
    return (float(polyline_distance(contour, exact).max()),
            float(polyline_distance(exact, contour).max()))


@pytest.mark.parametrize("text", [MUSHROOM_SWINGING_OVER_A_DWELL], ids=["mushroom-dwell"])
def test_the_cut_outline_holds_the_exact_curve(text: str) -> None:
    design, doc, check = build(text)
    tolerance = design.manufacturing.tolerance
    assert check.ok and check.value is not None and check.value <= tolerance
    mm = design.mm_per_unit
    outline = mm * loops(doc, "CUT", sagitta=1e-2 * tolerance / mm)[0]
    out, back = distances(outline, exact_working(design))
    assert out <= tolerance and back <= tolerance
