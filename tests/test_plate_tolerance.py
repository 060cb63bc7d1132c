"""A plate cam's files hold its exact curve within ``manufacturing.tolerance``: designs whose
DXF outline strayed further (arcs fitted across a velocity corner of a knife's profile or a jump
of curvature, bowing off the curve between the points they were checked at; a mushroom's
follower run that found no contact on a dwell) build with the ``verification`` check passing,
and, measured independently, every point of the CUT contour (read with ezdxf, its arcs
flattened by ezdxf) lies within the tolerance of the exact working curve (camfab's closed-form
evaluator on a grid far finer than the tolerance needs), and every point of that curve within
the tolerance of the contour."""

from __future__ import annotations

import io
import math

import ezdxf
import numpy as np
import pytest
import shapely

from camfab.geometry.arcfit import fit_arcs
from camfab.geometry.disc_geometry import disc_cam
from camfab.pipeline import analyse, design_from_text, verify_exports

from .dxf_loops import loops

#: Cam-angle step of the exact reference curve: its chords stray under 1e-6 mm from the curve
#: on these plates (c²/8ρ with c ≈ 0.02 mm).
REFERENCE_STEP = math.radians(0.02)

KNIFE_UNIFORM_VELOCITY = """\
name: knife-velocity-corner
cam: {type: disc, rotation: cw, base_radius: 47.463, thickness: 8, bore: 10}
follower: {type: knife, motion: translating}
motion:
  - rise:   {angle: 103, lift: 22.85, law: uniform-velocity}
  - dwell:  {angle: 66}
  - return: {angle: 81, law: uniform-velocity}
  - dwell:  {angle: 110}
manufacturing: {tolerance: 0.0046831}
"""

SWINGING_KNIFE_UNIFORM_VELOCITY = """\
name: swinging-knife-corner
units: in
cam: {type: disc, base_radius: 1.5021, thickness: 0.31496, bore: 0.3937}
follower: {type: knife, motion: oscillating, pivot_distance: 4.9842, arm_length: 4.0282,
           pivot_side: left}
motion:
  - rise:   {angle: 87, lift: 13.051, law: uniform-velocity}
  - dwell:  {angle: 167}
  - return: {angle: 92, law: uniform-velocity}
  - dwell:  {angle: 14}
manufacturing: {tolerance: 0.00028776}
"""

MUSHROOM_ACCELERATION_STEPS = """\
name: mushroom-acceleration-steps
cam: {type: disc, base_radius: 47.508, thickness: 8, bore: 10}
follower: {type: mushroom, motion: oscillating, pivot_distance: 117.66, arm_length: 93.748,
           face_radius: 59.093}
motion:
  - rise:   {angle: 66, lift: 16.218, law: polynomial-23}
  - dwell:  {angle: 12}
  - return: {angle: 94, law: polynomial-23}
  - dwell:  {angle: 188}
manufacturing: {tolerance: 0.00050015}
"""

FLAT_ACCELERATION_STEPS = """\
name: flat-acceleration-steps
units: in
cam: {type: disc, rotation: cw, base_radius: 1.3254, thickness: 0.31496, bore: 0.3937}
follower: {type: flat, motion: translating, face_width: 5.3016}
motion:
  - rise:   {angle: 114, lift: 0.51297, law: uniform-acceleration}
  - dwell:  {angle: 117}
  - return: {angle: 72, law: uniform-acceleration}
  - dwell:  {angle: 57}
manufacturing: {tolerance: 0.0010553}
"""

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


def build(text: str, drawing: str = ""):  # type: ignore[no-untyped-def]
    """The design of *text*, its DXF (of the plate *drawing*: ``-a`` for a conjugate pair's cam
    a) as a reader opens it, and its ``verification`` check: the build's own reading back of
    the files it writes."""
    design = design_from_text(text)
    analysis, exports = verify_exports(analyse(design, advice=False), ("dxf",))
    dxf = exports.files["dxf"][f"{design.name}{drawing}.dxf"]
    check = next(f for f in analysis.findings if f.id == "verification")
    return design, ezdxf.read(io.StringIO(dxf.decode())), check


def exact_working(design, outward: float = 0.0) -> np.ndarray:  # type: ignore[no-untyped-def]
    """The exact working curve (mm) at every :data:`REFERENCE_STEP` of each segment, both
    ends of each included (a corner at a joint is a point of it), moved *outward* (mm) along
    its normal: the path of a beam's centre kerf/2 outside it."""
    cam = disc_cam(design)
    _, theta, motion = design.program.segment_grid(REFERENCE_STEP)
    curve = cam.working(theta, motion)
    # the normal: the unit tangent turned a right angle, to the side away from the cam centre
    normal = np.column_stack((curve.tangent[:, 1], -curve.tangent[:, 0]))
    normal *= np.sign(np.sum(normal * curve.xy))
    return curve.xy + outward * normal


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


@pytest.mark.parametrize("text", [KNIFE_UNIFORM_VELOCITY, SWINGING_KNIFE_UNIFORM_VELOCITY,
                                  MUSHROOM_ACCELERATION_STEPS, FLAT_ACCELERATION_STEPS,
                                  MUSHROOM_SWINGING_OVER_A_DWELL],
                         ids=["knife-corner", "swinging-knife-corner",
                              "mushroom-acceleration-steps", "flat-acceleration-steps",
                              "mushroom-dwell"])
def test_the_cut_outline_holds_the_exact_curve(text: str) -> None:
    design, doc, check = build(text)
    tolerance = design.manufacturing.tolerance
    assert check.ok and check.value is not None and check.value <= tolerance
    mm = design.mm_per_unit
    outline = mm * loops(doc, "CUT", sagitta=1e-2 * tolerance / mm)[0]
    out, back = distances(outline, exact_working(design))
    assert out <= tolerance and back <= tolerance


CONJUGATE_ACCELERATION_STEPS_KERF = """\
name: conjugate-kerf
cam: {type: conjugate, rotation: cw, base_radius: 22.401, thickness: 8, bore: 10}
follower: {type: roller, motion: translating, roller_radius: 6.1818, roller_spacing: 96.989}
motion:
  - rise:   {angle: 117, lift: 16.19, law: uniform-acceleration}
  - dwell:  {angle: 88}
  - return: {angle: 70, law: uniform-acceleration}
  - dwell:  {angle: 85}
manufacturing: {tolerance: 0.00067254, kerf: 0.25074}
"""


def test_a_kerf_path_holds_the_exact_offset() -> None:
    """A conjugate pair's cam a cut by a laser (uniform acceleration: jumps of curvature at
    every joint and halfway up each rise): the beam's path on CUT lies within the tolerance of
    the exact working curve moved kerf/2 outward, and the part it leaves passes its check."""
    design, doc, check = build(CONJUGATE_ACCELERATION_STEPS_KERF, "-a")
    tolerance = design.manufacturing.tolerance
    assert check.ok and check.value is not None and check.value <= tolerance
    outline = loops(doc, "CUT", sagitta=1e-2 * tolerance)[0]
    out, back = distances(outline, exact_working(design, design.manufacturing.kerf / 2.0))
    assert out <= tolerance and back <= tolerance


def test_arcs_hold_the_chords_when_asked() -> None:
    """Twelve points on a circle of radius 10 (30° apart, the chords sagging 10(1 − cos 15°) =
    0.34 inside it): arcs through them meet every point, and stray 0.34 from the chain between
    them; with the chords held, no point of the fitted contour strays further from the chain
    than the tolerance."""
    angle = np.radians(np.arange(0.0, 360.0, 30.0))
    chain = 10.0 * np.column_stack((np.cos(angle), np.sin(angle)))
    polygon = shapely.LinearRing(chain)
    sagitta = 10.0 * (1.0 - math.cos(math.radians(15.0)))
    for chords in (False, True):
        flat = fit_arcs(chain, 0.1, chords=chords).points(1e-6)
        stray = float(shapely.distance(polygon, shapely.points(flat)).max())
        assert stray <= 0.1 if chords else stray == pytest.approx(sagitta, rel=1e-3)


KNIFE_VELOCITY_STEP_KERF = """\
name: knife-kerf-hollow
cam: {type: disc, rotation: cw, base_radius: 28.781, thickness: 8, bore: 10}
follower: {type: knife, motion: translating, offset: 3.0833}
motion:
  - rise:   {angle: 157, lift: 17.539, law: uniform-velocity}
  - dwell:  {angle: 42}
  - return: {angle: 75, law: uniform-velocity}
  - dwell:  {angle: 86}
manufacturing: {tolerance: 0.00064004, kerf: 0.26452}
"""


def knife_lift_over(design, ring: np.ndarray, theta: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    """A translating knife's lift (mm) over the plate inside *ring* (mm) at each cam angle
    *theta* (rad), by brute force: the plate turned to the angle (a point of the cam appears
    in the frame at Rot(σθ)·P), cut by the knife's line x = offset, the highest point of the
    cut less the base circle's on that line."""
    sigma = design.cam.sigma
    offset = design.follower.offset
    base = design.cam.base_radius
    lift = np.empty(len(theta))
    for i, angle in enumerate(theta):
        c, s = math.cos(sigma * angle), math.sin(sigma * angle)
        turned = ring @ np.array([[c, s], [-s, c]])
        line = shapely.LineString([(offset, -1e3), (offset, 1e3)])
        hit = shapely.Polygon(turned).intersection(line)
        lift[i] = max(y for _, y in hit.coords) if hit.geom_type == "LineString" else max(
            y for part in hit.geoms for _, y in part.coords)
    return lift - math.sqrt(base * base - offset * offset)


def test_a_beam_rounds_a_knifes_sharp_hollow() -> None:
    """A knife whose return ends at a velocity step has a sharp hollow there (its rise
    starts at another), which a laser's
    beam (radius kerf/2) cannot cut: the ``kerf`` check fails and says how far the cam as cut
    moves the follower, as a brute-force run of the knife over the exact profile closed by the
    beam finds it (shapely's buffer out and back, far finer than the tolerance); the files are
    held to that cam, and hold it. With laws of no velocity step the beam cuts the design:
    the check passes and the verification is the plain one."""
    from camfab.analysis.cam_checks import tool_cut

    design = design_from_text(KNIFE_VELOCITY_STEP_KERF)
    analysis, _ = verify_exports(analyse(design, advice=False), ("dxf",))
    tolerance = design.manufacturing.tolerance
    found = {f.id: f for f in analysis.findings}
    assert found["verification"].ok and found["verification"].value <= tolerance
    assert not found["kerf"].ok and found["kerf"].value == 0.0
    assert "cam as cut" in found["kerf"].message
    beam = design.manufacturing.kerf / 2.0
    cut = tool_cut(design, analysis.geometry, beam)
    assert cut is not None and cut.made.max_mm > 2.0 * tolerance
    exact = shapely.Polygon(exact_working(design))
    closed = exact.buffer(beam, quad_segs=256).buffer(-beam, quad_segs=256)
    at = math.radians(cut.made.at_deg)
    theta = at + np.radians(np.linspace(-1.0, 1.0, 201))
    brute = knife_lift_over(design, np.asarray(closed.exterior.coords), theta)
    off = np.abs(brute - design.program.evaluate(theta)[0]).max()
    assert off == pytest.approx(cut.made.max_mm, abs=0.1 * tolerance)

    smooth = design_from_text(KNIFE_VELOCITY_STEP_KERF.replace("uniform-velocity", "cycloidal"))
    analysis, _ = verify_exports(analyse(smooth, advice=False), ("dxf",))
    found = {f.id: f for f in analysis.findings}
    assert found["kerf"].ok and "follows the whole profile" in found["kerf"].message
    assert found["verification"].ok and "design motion" in found["verification"].message
