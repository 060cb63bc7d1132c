"""Built disc cams: sampled profiles within tolerance, the follower never penetrating the cam,
the round trip design → profile → lift, undercut trimming, and the follower simulation checked
against closed-form answers on profiles that are not made by camfab's synthesis."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from camfab.curves.follower import FollowerGeometry
from camfab.curves.profile import Profile
from camfab.geometry.disc_geometry import disc_geometry
from camfab.geometry.simulate import simulate
from camfab.pipeline import analyse, design_from_text, load_design, render

from .conftest import DESIGN_FILES, DESIGNS

DISC_DESIGNS = [p for p in DESIGN_FILES if load_design(p).cam.type == "disc"]
CLEAN = [p for p in DISC_DESIGNS if p.stem != "demo-undercut"]


@pytest.mark.parametrize("path", CLEAN, ids=[p.stem for p in CLEAN])
def test_round_trip_lift_error_is_within_the_tolerance(path) -> None:  # type: ignore[no-untyped-def]
    design = load_design(path)
    geom = disc_geometry(design)
    tolerance = design.manufacturing.tolerance
    assert not geom.undercut
    assert geom.lift.max_mm <= tolerance
    # the sampled profile stays within the tolerance of the exact curve (dense, independent θ)
    ring = shapely.LinearRing(geom.profile.vertices)
    exact = geom.dense.working.xy
    assert float(np.max(shapely.distance(ring, shapely.points(exact)))) <= tolerance
    assert ring.is_simple


@pytest.mark.parametrize("path", CLEAN, ids=[p.stem for p in CLEAN])
def test_the_follower_never_penetrates_the_cam(path) -> None:  # type: ignore[no-untyped-def]
    design = load_design(path)
    geom = disc_geometry(design)
    fol = design.follower
    cam_polygon = shapely.Polygon(geom.profile.vertices)
    tolerance = design.manufacturing.tolerance
    if fol.type == "flat":
        # every point of the cam lies on the cam side of the face line at every angle
        lines = geom.cam.face_lines(geom.dense.theta, geom.dense.motion)
        normals = np.stack((np.cos(lines.beta), np.sin(lines.beta)), -1)
        reach = geom.profile.vertices @ normals.T - lines.h[None, :]
        assert float(reach.max()) <= 1e-9
        return
    centres = shapely.points(geom.dense.pitch.xy)
    inside = shapely.contains(cam_polygon, centres)
    gap = np.where(inside, -1.0, 1.0) * shapely.distance(cam_polygon.exterior, centres)
    assert float(gap.min()) >= fol.trace_radius - tolerance
    # every working-curve point is one roller radius from the pitch curve
    pitch_ring = shapely.LinearRing(geom.pitch.xy)
    spacing = shapely.distance(pitch_ring, shapely.points(geom.working.xy))
    assert np.allclose(spacing, fol.trace_radius, atol=tolerance)


def test_points_are_placed_by_chord_error() -> None:
    text = (DESIGNS / "seed-poly-345.yaml").read_text()
    counts = {}
    for tol in (0.01, 0.0001):
        design = design_from_text(text + f"manufacturing: {{tolerance: {tol}}}\n")
        geom = disc_geometry(design)
        counts[tol] = len(geom.profile.vertices)
        ring = shapely.LinearRing(geom.profile.vertices)
        dev = shapely.distance(ring, shapely.points(geom.dense.working.xy))
        assert float(dev.max()) <= tol
        assert geom.lift.max_mm <= tol
    # chord error ∝ chord², so 100× finer needs about 10× the points, not 100×
    assert 6 < counts[0.0001] / counts[0.01] < 14


def test_undercut_roller_is_trimmed_and_its_motion_error_measured() -> None:
    design = load_design(DESIGNS / "demo-undercut.yaml")
    analysis = analyse(design)
    geom = analysis.geometry
    assert geom is not None and geom.undercut and geom.self_intersecting
    finding = next(f for f in analysis.findings if f.id == "undercut")
    assert not finding.ok and finding.severity == "error"
    assert finding.limit == 12.0 and finding.value == pytest.approx(10.94, abs=0.01)
    (start, end), = finding.ranges_deg
    assert start < 45.0 < end and end - start < 20.0  # the nose, at the top of the lift
    # the cut cam: simple, and the roller never enters it
    ring = shapely.LinearRing(geom.profile.vertices)
    assert ring.is_simple
    polygon = shapely.Polygon(geom.profile.vertices)
    centres = shapely.points(geom.dense.pitch.xy)
    assert float(shapely.distance(polygon.exterior, centres).min()) >= 12.0 - 1e-3
    assert not shapely.contains(polygon, centres).any()
    # the follower cannot reach the full lift at the nose: the error is real, and where it is
    assert 0.05 < geom.lift.max_mm < 1.0 and abs(geom.lift.at_deg - 45.0) < 3.0
    assert float(geom.lift.error.max()) <= 1e-3  # never pushed above the design motion
    assert f"{geom.lift.max_mm:.4g} mm off the design" in finding.message
    assert "roller radius below 10.94 mm" in finding.message


def test_where_the_envelope_folds_and_where_the_cut_cam_departs_are_said_apart() -> None:
    """Two ranges with their own words, in the message and in the JSON: where the pitch
    curve's convex radius is under the roller's (scanned here on a grid of its own), and the
    wider one where the cam as cut (the loops trimmed) departs from the design."""
    analysis = analyse(load_design(DESIGNS / "demo-undercut.yaml"))
    geom = analysis.geometry
    theta = np.radians(np.arange(0.0, 360.0, 0.01))
    radius = geom.cam.pitch(theta, analysis.program.evaluate(theta)).radius
    folds = np.degrees(theta[(radius > 0) & (radius < 12.0)])
    report = json.loads(render(analysis).files["demo-undercut-report.json"])["geometry"]
    [(fold_start, fold_end)] = report["undercut_fold_ranges_deg"]
    [(cut_start, cut_end)] = report["undercut_cut_ranges_deg"]
    assert fold_start == pytest.approx(folds.min(), abs=0.06)
    assert fold_end == pytest.approx(folds.max(), abs=0.06)
    assert cut_start < fold_start - 1.0 and cut_end > fold_end + 1.0
    finding = next(f for f in analysis.findings if f.id == "undercut")
    fold_words = f"at {fold_start:.4g}°–{fold_end:.4g}°: the envelope folds over there"
    cut_words = f"departs from the design at {cut_start:.4g}°–{cut_end:.4g}°"
    assert fold_words in finding.message and cut_words in finding.message


def test_an_undercut_cams_files_are_held_to_the_cut_cam_not_passed_unchecked() -> None:
    """The verification of an undercut cam compares the follower over the DXF read back with
    the design's motion wherever the cut cam follows it, and with the cut cam's inside the
    undercut: a check that can fail, with its value within its limit when it passes."""
    design = load_design(DESIGNS / "demo-undercut.yaml")
    analysis = render(analyse(design)).analysis
    assert analysis is not None and analysis.verification is not None
    check = next(f for f in analysis.findings if f.id == "verification")
    tolerance = design.manufacturing.tolerance
    assert check.applicable and check.ok and check.limit == tolerance
    assert check.value is not None and check.value <= tolerance
    assert "the cam is undercut" in check.message and "see the undercut check" in check.message
    # independently: the lift read back from the DXF, against the design away from the nose
    # and against the trimmed cam's own motion at the nose (undercut at 38°-52°)
    written = analysis.verification.lift
    cut = analysis.geometry.lift
    theta = np.degrees(written.theta)
    away = (theta < 30.0) | (theta > 60.0)
    assert np.abs(written.error_mm[away]).max() <= tolerance
    nose = ~away
    assert np.abs(written.error_mm[nose] - cut.error_mm[nose]).max() <= tolerance
    assert np.abs(written.error_mm[nose]).max() > 50 * tolerance  # the undercut's own error
    # a cut cam off by more than the tolerance fails the check
    from camfab.kinds.readback import verification_finding

    shifted = replace(analysis.verification, cut_error=replace(
        analysis.verification.cut_error, error_mm=analysis.verification.cut_error.error_mm
        + 2 * tolerance))
    failed = verification_finding(analysis, shifted)
    assert not failed.ok and failed.applicable and failed.value > tolerance


def test_a_folded_groove_has_no_verification_to_pass() -> None:
    """A drum whose groove folds over has no STL and no cam whose motion files could hold: its
    verification is not applicable (null in the JSON, "–" on the page), not passed."""
    artifacts = render(analyse(load_design(DESIGNS / "demo-drum-steep.yaml")))
    check = next(c for c in json.loads(artifacts.files["demo-drum-steep-report.json"])["checks"]
                 if c["id"] == "verification")
    assert check["ok"] is None and check["applicable"] is False and check["value"] is None
    assert check["message"].startswith("not applicable: the groove folds over itself")
    page = artifacts.files["demo-drum-steep-report.html"].decode()
    assert '<td class="mark na">–</td>' in page


@pytest.mark.parametrize(("path", "part"), [("seed-poly-345.yaml", "plate"),
                                            ("demo-oscillating-knife.yaml", "plate")])
def test_a_plate_without_a_bore_is_a_warning(path: str, part: str) -> None:
    findings = analyse(load_design(DESIGNS / path)).findings
    bore = next(f for f in findings if f.id == "bore")
    assert not bore.ok and bore.severity == "warning"
    assert bore.message.startswith(f"no bore: the {part} has no shaft hole")
    with_bore = analyse(load_design(DESIGNS / "seed-10-4.yaml")).findings
    assert next(f for f in with_bore if f.id == "bore").ok


FLAT_CUSP = """
name: flat-cusp
cam: {type: disc, base_radius: 10, thickness: 8}
follower: {type: flat}
motion:
  - rise: {angle: 90, lift: 30, law: cycloidal}
  - dwell: {angle: 10}
  - return: {angle: 90, law: cycloidal}
  - dwell: {angle: 170}
"""


def test_flat_face_cusp_is_an_undercut() -> None:
    analysis = analyse(design_from_text(FLAT_CUSP))
    geom = analysis.geometry
    assert geom is not None and geom.undercut
    finding = next(f for f in analysis.findings if f.id == "undercut")
    assert not finding.ok and finding.value is not None and finding.value < 0.0
    # Rb + s + s″ ≥ 0 needs Rb ≥ −min(s + s″); the message names that radius
    s = geom.dense.motion
    needed = -float(np.min(s[0] + s[2]))
    assert f"base radius above {needed:.4g} mm" in finding.message
    # the trimmed cam is the intersection of the half-planes below every face line
    lines = geom.cam.face_lines(geom.dense.theta, geom.dense.motion)
    normals = np.stack((np.cos(lines.beta), np.sin(lines.beta)), -1)
    assert float((geom.profile.vertices @ normals.T - lines.h).max()) <= 1e-3
    assert geom.lift.max_mm > 1.0


# ---- an undercut cam's files hold the cam cut at its corners -----------------------------------

#: A 14 mm roller on an 8 mm base circle: both ends of the rise and the return's start fold over,
#: and the cut cam has sharp corners where the loops were trimmed.
ROLLER_CORNERS = """
name: roller-corners
cam: {type: disc, base_radius: 8, thickness: 8}
follower: {type: roller, roller_radius: 14}
motion:
  - rise: {angle: 40, lift: 10, law: modified-trapezoid}
  - dwell: {angle: 20}
  - return: {angle: 60, law: polynomial-23}
  - dwell: {angle: 240}
manufacturing: {tolerance: 0.001, kerf: KERF}
"""

#: A flat face whose envelope has cusps on both flanks (Rb + s + s″ < 0), cut by a laser.
FLAT_CORNERS = """
name: flat-corners
cam: {type: disc, base_radius: 25, thickness: 8}
follower: {type: flat, face_width: 300}
motion:
  - rise: {angle: 40, lift: 20, law: harmonic}
  - dwell: {angle: 20}
  - return: {angle: 80, law: polynomial-345}
  - dwell: {angle: 220}
manufacturing: {tolerance: 0.001, kerf: 0.2}
"""


def cut_contour(text: str) -> tuple[object, np.ndarray]:
    """The design in *text* built: its analysis and the DXF's CUT outline read back by ezdxf
    (its arcs flattened within 1e-6 mm)."""
    import io

    import ezdxf

    from .dxf_loops import loops

    design = design_from_text(text)
    artifacts = render(analyse(design))
    doc = ezdxf.read(io.StringIO(artifacts.files[f"{design.name}.dxf"].decode()))
    return artifacts.analysis, loops(doc, "CUT", 1e-6)[0]


def verification_of(analysis) -> object:  # type: ignore[no-untyped-def]
    return next(f for f in analysis.findings if f.id == "verification")


def part_of(outline: np.ndarray, kerf: float, step: float) -> np.ndarray:
    """The part a laser following *outline* (mm) leaves, by shapely (the outline shrunk by
    kerf/2, its joins true to 1e-6 mm), as points no more than *step* (mm) apart."""
    part = shapely.Polygon(outline).buffer(-kerf / 2, quad_segs=512) if kerf else (
        shapely.Polygon(outline))
    return np.asarray(part.exterior.segmentize(step).coords)


@pytest.mark.parametrize("kerf", [0.0, 0.2])
def test_an_undercut_rollers_files_keep_the_corners_of_the_cut_cam(kerf: float) -> None:
    """Where the loops are trimmed the cut cam has sharp corners, on which the roller rides:
    its outline is fitted with lines and arcs between them, never an arc across one (which
    bowed 0.025 mm off the cut cam, 25 times the tolerance), and the laser's path round them
    neither. The cut cam is where the roller never enters: every point of the part the CUT
    outline makes lies the roller radius from the pitch curve, which the test computes from the
    motion law (ccw: the cam frame turns the follower's (0, Rb + r + s) by −θ)."""
    analysis, outline = cut_contour(ROLLER_CORNERS.replace("KERF", str(kerf)))
    tolerance, rr = 0.001, 14.0
    points = part_of(outline, kerf, 0.05)
    # the pitch curve's points 0.005° apart: its chords within 2e-7 mm of it
    theta = np.linspace(0.0, 2 * np.pi, 72_001)[:-1]
    y = 8.0 + rr + analysis.design.program.evaluate(theta)[0]
    pitch = np.stack((y * np.sin(theta), y * np.cos(theta)), -1)
    chords = shapely.STRtree(shapely.linestrings(np.stack((pitch, np.roll(pitch, -1, 0)), 1)))
    _, away = chords.query_nearest(shapely.points(points), return_distance=True,
                                   all_matches=False)
    assert np.abs(away - rr).max() <= tolerance
    # the cut cam's corners are where the exact branches of the envelope cross, not where two
    # of their chords do (3e-4 mm off): on the exact curve, the roller radius from the pitch
    corners = analysis.geometry.profile.vertices[analysis.geometry.corners]
    _, reach = chords.query_nearest(shapely.points(corners), return_distance=True,
                                    all_matches=False)
    assert len(corners) == 2 and np.abs(reach - rr).max() <= 1e-6
    check = verification_of(analysis)
    assert analysis.geometry.undercut and check.ok and check.value <= tolerance


def test_an_undercut_flat_faces_laser_path_keeps_the_corners_of_the_cut_cam() -> None:
    """A flat face's cut cam is the region below every face line, with corners where the cusps
    were trimmed; the laser's path rounds them with arcs of radius kerf/2, which its fit keeps
    (an arc across a round join and the long chords beside it bowed 2.6 times the tolerance
    off). The part the path leaves (the path shrunk by kerf/2) lies on the boundary of that
    region: below every face line h = Rb + s along the normal at 90° − θ, and on one."""
    analysis, outline = cut_contour(FLAT_CORNERS)
    tolerance = 0.001
    points = part_of(outline, 0.2, 0.05)
    # face lines 0.05° apart: the tangent one missed by at most 0.025°, 1e-5 mm on this cam
    theta = np.linspace(0.0, 2 * np.pi, 7201)[:-1]
    h = 25.0 + analysis.design.program.evaluate(theta)[0]
    normal = np.stack((np.sin(theta), np.cos(theta)), -1)
    above = np.max(points @ normal.T - h, axis=1)
    assert np.abs(above).max() <= tolerance
    check = verification_of(analysis)
    assert analysis.geometry.undercut and check.ok and check.value <= tolerance


# ---- the simulation on profiles camfab did not make -----------------------------------------

R, C = 30.0, 12.0  # an eccentric disc: radius R, centre C from the cam centre along +X


def eccentric(as_arcs: bool) -> Profile:
    if as_arcs:  # two half circles as bulged edges
        return Profile(np.array([[C + R, 0.0], [C - R, 0.0]]), np.array([1.0, 1.0]))
    angle = np.linspace(0, 2 * math.pi, 20000, endpoint=False)
    return Profile.from_points(np.stack((C + R * np.cos(angle), R * np.sin(angle)), -1))


THETA = np.linspace(0, 2 * math.pi, 720, endpoint=False)


def test_profile_arcs_area_and_order() -> None:
    prof = eccentric(as_arcs=True)
    assert prof.signed_area == pytest.approx(math.pi * R**2, rel=1e-12)
    arcs = prof.arcs()
    assert np.allclose(arcs.centre, [[C, 0.0], [C, 0.0]]) and np.allclose(arcs.radius, R)
    # the same contour clockwise: reversed, bulges negated, and ccw() restores it
    clockwise = Profile(prof.vertices[::-1].copy(), -np.roll(prof.bulges[::-1], -1))
    assert clockwise.signed_area == pytest.approx(-math.pi * R**2, rel=1e-12)
    assert clockwise.ccw().signed_area == pytest.approx(math.pi * R**2, rel=1e-12)
    fol = FollowerGeometry("roller", radius=6.0, offset=3.0)
    assert np.allclose(simulate(clockwise, fol, THETA, 1), simulate(prof, fol, THETA, 1))


def centre_in_frame(sigma: int) -> np.ndarray:
    return np.stack((C * np.cos(sigma * THETA), C * np.sin(sigma * THETA)), -1)


@pytest.mark.parametrize("as_arcs", [True, False], ids=["arcs", "points"])
@pytest.mark.parametrize("sigma", [1, -1])
def test_simulated_translating_followers_on_an_eccentric(as_arcs: bool, sigma: int) -> None:
    prof = eccentric(as_arcs)
    tol = 1e-9 if as_arcs else 2e-5
    c = centre_in_frame(sigma)
    for e, rr in ((0.0, 0.0), (7.0, 10.0), (-5.0, 4.0)):
        fol = FollowerGeometry("roller" if rr else "knife", radius=rr, offset=e)
        expected = c[:, 1] + np.sqrt((R + rr) ** 2 - (e - c[:, 0]) ** 2)
        assert np.max(np.abs(simulate(prof, fol, THETA, sigma) - expected)) < tol
    flat = simulate(prof, FollowerGeometry("flat"), THETA, sigma)
    assert np.max(np.abs(flat - (c[:, 1] + R))) < tol


@pytest.mark.parametrize("as_arcs", [True, False], ids=["arcs", "points"])
@pytest.mark.parametrize(("sigma", "side"), [(1, 1), (-1, 1), (1, -1)])
def test_simulated_oscillating_followers_on_an_eccentric(as_arcs: bool, sigma: int,
                                                        side: int) -> None:
    prof = eccentric(as_arcs)
    tol = 1e-9 if as_arcs else 1e-6
    a, arm, rr, f = 80.0, 60.0, 8.0, 5.0
    pivot = np.array([side * a, 0.0])
    c = centre_in_frame(sigma)
    roller = simulate(prof, FollowerGeometry("roller", True, rr, pivot_distance=a, arm_length=arm,
                                             pivot_sign=side), THETA, sigma)
    face = simulate(prof, FollowerGeometry("flat", True, pivot_distance=a, arm_length=arm,
                                           pivot_sign=side, face_offset=f), THETA, sigma)
    for k in range(0, len(THETA), 7):
        def gap(psi: float, k: int = k) -> float:  # roller centre to disc centre, minus R + rr
            b = pivot + arm * np.array([-side * math.cos(psi), math.sin(psi)])
            return float(np.hypot(*(b - c[k]))) - (R + rr)

        def clearance(psi: float, k: int = k) -> float:  # face line to disc centre, minus R + f
            n = np.array([-side * math.sin(psi), -math.cos(psi)])
            return float((c[k] - pivot) @ n) - (f + R)

        assert roller[k] == pytest.approx(brentq(gap, 0.0, math.pi / 2), abs=tol)
        assert face[k] == pytest.approx(brentq(clearance, 0.0, math.pi / 2), abs=tol)


def test_velocity_steps_give_a_rolled_corner_and_a_trimmed_hollow() -> None:
    """Uniform velocity steps the velocity at both ends of the rise: at 0° the pitch curve has a
    convex corner, which the roller rolls over (an arc of the roller radius on the cam, no lift
    error); at 120° a hollow the roller cannot reach into, which is trimmed and reported."""
    text = (DESIGNS / "seed-10-4.yaml").read_text().replace("law: harmonic", "law: linear")
    analysis = analyse(design_from_text(text))
    geom = analysis.geometry
    assert geom is not None
    finding = next(f for f in analysis.findings if f.id == "undercut")
    assert not finding.ok and "velocity step" in finding.message
    (start, end), = finding.ranges_deg
    assert start < 120.0 < end
    error = np.abs(geom.lift.error_mm)
    near = lambda deg: np.abs(np.degrees(geom.lift.theta) - deg) < 5  # noqa: E731
    assert error[near(0.0) | near(360.0)].max() <= 1e-3
    assert error[near(120.0)].max() > 0.01
    # the corner arc: profile points within the roller radius of the pitch corner at 0°
    corner = geom.cam.pitch(np.zeros(1), analysis.program.evaluate(np.zeros(1))).xy[0]
    on_arc = np.abs(np.hypot(*(geom.profile.vertices - corner).T) - 7.0) < 1e-9
    assert on_arc.sum() >= 5


def test_ranges_through_zero_are_joined() -> None:
    from camfab.angles import merge, ranges_deg

    theta = np.radians(np.arange(360.0))
    mask = (theta < np.radians(10)) | (theta > np.radians(350)) | (np.abs(theta - 2) < 0.05)
    assert ranges_deg(theta, mask) == ((112.0, 117.0), (351.0, 9.0))
    assert merge([(350.0, 10.0), (5.0, 20.0), (100.0, 120.0), (119.0, 130.0)]) == (
        (100.0, 130.0), (350.0, 20.0))


# ---- property: any buildable disc design gets a verified profile or a reported undercut ------

LAWS = ["uniform-acceleration", "harmonic", "cycloidal", "polynomial-345", "polynomial-4567",
        "modified-trapezoid", "modified-sine", "modified-uniform-velocity", "polynomial-23"]


@st.composite
def disc_designs(draw):  # type: ignore[no-untyped-def]
    contact = draw(st.sampled_from(["knife", "roller", "flat", "mushroom"]))
    oscillating = draw(st.booleans())
    rb = draw(st.floats(5.0, 80.0))
    fol: dict = {"type": contact, "motion": "oscillating" if oscillating else "translating"}
    radius = draw(st.floats(1.0, 30.0))
    if contact == "roller":
        fol["roller_radius"] = radius
    if contact == "mushroom":
        fol["face_radius"] = radius
    rp = rb + (radius if contact in ("roller", "mushroom") else 0.0)
    if oscillating:
        a = draw(st.floats(rp * 1.1 + 1.0, rp * 4.0 + 10.0))
        fol["pivot_distance"] = a
        fol["pivot_side"] = draw(st.sampled_from(["left", "right"]))
        if contact == "flat":
            fol["arm_length"] = draw(st.floats(10.0, 100.0))
            fol["face_offset"] = draw(st.floats(-0.4 * rb, 0.4 * (a - rb)))
        else:
            fol["arm_length"] = draw(st.floats(max(a - rp + 0.5, 1.0), a + rp - 0.5))
        lift = draw(st.floats(2.0, 25.0))
    else:
        if contact != "flat":
            fol["offset"] = draw(st.floats(-0.8 * rb, 0.8 * rb))
        lift = draw(st.floats(1.0, 1.5 * rb))
    angles = draw(st.lists(st.floats(20.0, 200.0), min_size=4, max_size=4))
    angles = [x * 360.0 / sum(angles) for x in angles]
    motion = [{"rise": {"angle": angles[0], "lift": lift, "law": draw(st.sampled_from(LAWS))}},
              {"dwell": {"angle": angles[1]}},
              {"return": {"angle": angles[2], "law": draw(st.sampled_from(LAWS))}},
              {"dwell": {"angle": angles[3]}}]
    return {"name": "random", "follower": fol, "motion": motion,
            "cam": {"type": "disc", "base_radius": rb,
                    "rotation": draw(st.sampled_from(["ccw", "cw"]))}}


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(disc_designs())
def test_random_disc_designs_are_verified_or_report_their_undercut(data: dict) -> None:
    from camfab.errors import CamfabError
    from camfab.pipeline import design_from_mapping

    try:
        design = design_from_mapping(data)
    except CamfabError:
        return  # a design the rules refuse (a clear message, tested elsewhere)
    analysis = analyse(design)
    geom = analysis.geometry
    assert geom is not None
    assert shapely.LinearRing(geom.profile.vertices).is_simple
    undercut = next(f for f in analysis.findings if f.id == "undercut")
    assert undercut.ok == (not geom.undercut)
    if not geom.undercut:
        assert geom.lift.max_mm <= design.manufacturing.tolerance
