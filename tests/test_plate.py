"""Laser kerf and milling cutter: the CUT contours offset by kerf/2 away from the material, the
cutter-centre path on TOOLPATH, and the ``cutter`` finding where the cutter cannot follow the
profile — each checked against the definition of an offset (points at a fixed distance) and an
independent curvature of the pitch curve."""

from __future__ import annotations

import io
import json
import math

import ezdxf
import numpy as np
import pytest
import shapely

from camfab.pipeline import analyse, design_from_text, render

from .conftest import DESIGNS
from .dxf_loops import loops

TOLERANCE = 0.001  # mm, the designs' default


def seed_10_4(extra: str, keyway: bool = True) -> str:
    """Seed example 10.4 (offset roller, SHM rise, uniform-acceleration return) with a keyway
    and the given lines added."""
    text = (DESIGNS / "seed-10-4.yaml").read_text()
    if keyway:
        text = text.replace("  bore: 10", "  bore: 10\n  keyway: {width: 3, depth: 1.4}")
    return text + extra


def build(text: str):  # type: ignore[no-untyped-def]
    design = design_from_text(text)
    analysis = analyse(design)
    artifacts = render(analysis)
    doc = ezdxf.read(io.StringIO(artifacts.files[f"{design.name}.dxf"].decode()))
    report = json.loads(artifacts.files[f"{design.name}-report.json"])
    return design, artifacts.analysis, doc, report


def hole_outline() -> shapely.LinearRing:
    """The part's bore (r = 5) with its keyway (3 wide, 1.4 above the bore's top), from its
    definition, the arc flattened to 1e-7 mm."""
    r, half, top = 5.0, 1.5, 6.4
    foot = math.sqrt(r * r - half * half)
    # up the keyway's right side, across, down its left side, round the bottom of the bore
    left, right = math.atan2(foot, -half), math.atan2(foot, half) + 2 * math.pi
    angle = np.linspace(left, right, 200_001)[1:-1]
    arc = np.stack((r * np.cos(angle), r * np.sin(angle)), -1)
    return shapely.LinearRing(np.vstack(([[half, foot], [half, top], [-half, top],
                                          [-half, foot]], arc)))


def test_kerf_moves_the_outline_out_and_the_holes_in() -> None:
    kerf = 0.4
    _, analysis, doc, report = build(seed_10_4(f"manufacturing: {{kerf: {kerf}}}\n"))
    geom = analysis.geometry
    assert geom is not None and not geom.undercut
    cut = loops(doc, "CUT")
    assert len(cut) == 2
    outline, hole = cut
    # the outline: every point kerf/2 outside the exact working curve, and back
    exact = shapely.LinearRing(geom.dense.working.xy)
    distance = shapely.distance(shapely.points(outline), exact)
    assert np.max(np.abs(distance - kerf / 2)) <= TOLERANCE
    assert not shapely.Polygon(outline).within(shapely.Polygon(geom.dense.working.xy))
    assert shapely.Polygon(geom.dense.working.xy).within(shapely.Polygon(outline))
    normal = geom.cam.sigma * np.stack((-geom.dense.working.tangent[:, 1],
                                        geom.dense.working.tangent[:, 0]), -1)
    shifted = shapely.points(geom.dense.working.xy + kerf / 2 * normal)
    assert float(np.max(shapely.distance(shifted, shapely.LinearRing(outline)))) <= TOLERANCE
    # the keyed bore: every point kerf/2 inside the part's hole, and its area that of the hole
    # shrunk by kerf/2 (the hole less a band kerf/2 wide along its outline)
    ring = hole_outline()
    distance = shapely.distance(shapely.points(hole), ring)
    assert np.max(np.abs(distance - kerf / 2)) <= TOLERANCE
    assert shapely.Polygon(hole).within(shapely.Polygon(ring))
    # the part is unchanged: the STL holds the part, not the beam's path
    assert report["verification"]["max_lift_error_mm"] <= TOLERANCE
    assert "kerf" in report["verification"]["checked_on"]
    assert report["verification"]["cut_outline_max_deviation_mm"] <= TOLERANCE
    assert len(doc.modelspace().query('*[layer=="TOOLPATH"]')) == 0


def test_kerf_on_a_round_bore_is_a_smaller_circle() -> None:
    _, _, doc, _ = build(seed_10_4("manufacturing: {kerf: 0.3}\n", keyway=False))
    circles = doc.modelspace().query('CIRCLE[layer=="CUT"]')
    assert [c.dxf.radius for c in circles] == [pytest.approx(5.0 - 0.15, abs=1e-12)]


def test_svg_holds_the_kerf_compensated_contours() -> None:
    import xml.etree.ElementTree as ET

    from svgelements import Path as SvgPath

    design = design_from_text(seed_10_4("manufacturing: {kerf: 0.4}\n"))
    files = render(analyse(design)).files
    root = ET.fromstring(files["seed-10-4.svg"])
    paths = root.findall(".//{http://www.w3.org/2000/svg}path")
    assert len(paths) == 2  # the outline and the keyed bore
    doc = ezdxf.read(io.StringIO(files["seed-10-4.dxf"].decode()))
    for path, contour in zip(paths, loops(doc, "CUT"), strict=True):
        points = np.array(SvgPath(path.get("d", "")).npoint(np.linspace(0.0, 1.0, 4001)))
        xy = np.stack((points[:, 0], -points[:, 1]), -1)  # SVG's y axis points down
        gap = shapely.distance(shapely.points(xy), shapely.LinearRing(contour))
        assert float(gap.max()) <= 1e-4


def pitch_concave_radius(design, theta: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Independent profile radius of curvature of a translating offset roller follower's cam
    (convex positive): the pitch curve C(θ) = Rot(−σθ)(e, √(Rp² − e²) + s) differentiated
    numerically, less the roller radius."""
    fol, cam = design.follower, design.cam
    rp = cam.base_radius + fol.roller_radius
    h = 1e-5

    def at(t: np.ndarray) -> np.ndarray:
        s = design.program.evaluate(t)[0]
        frame = np.stack((np.full_like(s, fol.offset), math.sqrt(rp**2 - fol.offset**2) + s), -1)
        a = -cam.sigma * t
        c, si = np.cos(a), np.sin(a)
        return np.stack((c * frame[:, 0] - si * frame[:, 1], si * frame[:, 0] + c * frame[:, 1]),
                        -1)

    d1 = (at(theta + h) - at(theta - h)) / (2 * h)
    d2 = (at(theta + h) - 2 * at(theta) + at(theta - h)) / h**2
    rho = -cam.sigma * np.hypot(*d1.T) ** 3 / (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    return rho - fol.roller_radius


def test_cutter_larger_than_a_concave_radius_is_a_finding_where_it_is() -> None:
    cutter = 30.0
    extra = f"manufacturing: {{cutter_radius: {cutter}}}\n"
    design, analysis, doc, report = build(seed_10_4(extra))
    # independent: where the profile is concave with a radius under the cutter's
    # a grid that comes within 0.001° of each joint from both sides, where one-sided values hold
    joints = np.array([0.0, 120.0, 180.0, 260.0, 360.0])
    theta = np.radians(np.concatenate((np.arange(0.05, 360, 0.1), joints[1:] - 1e-3,
                                       joints[:-1] + 1e-3)))
    rho = pitch_concave_radius(design, theta)
    tight = (rho < 0) & (-rho < cutter)
    assert tight.any()
    finding = next(c for c in report["checks"] if c["id"] == "cutter")
    assert not finding["ok"] and finding["severity"] == "error"
    assert finding["value"] == pytest.approx(float(np.min(-rho[tight])), rel=1e-3)
    assert finding["limit"] == cutter
    ranges = finding["ranges_deg"]

    def covered(angle: float) -> bool:
        return any((a <= angle <= b) if a <= b else (angle >= a or angle <= b) for a, b in ranges)

    assert all(covered(a) for a in np.degrees(theta[tight]))
    assert "mm off the design" in finding["message"]
    assert analysis.exit_code == 1
    # the toolpath keeps the cutter clear of the part, touching it wherever it fits
    path = loops(doc, "TOOLPATH")[0]
    part = shapely.LinearRing(geom_points(analysis))
    gap = shapely.distance(shapely.points(path), part)
    assert float(gap.min()) >= cutter - TOLERANCE
    assert float(np.median(gap)) == pytest.approx(cutter, abs=TOLERANCE)


def geom_points(analysis) -> np.ndarray:  # type: ignore[no-untyped-def]
    assert analysis.geometry is not None
    return analysis.geometry.dense.working.xy


def test_cutter_that_fits_passes_and_its_path_is_one_radius_off() -> None:
    cutter = 3.0
    _, analysis, doc, report = build(seed_10_4(f"manufacturing: {{cutter_radius: {cutter}}}\n"))
    finding = next(c for c in report["checks"] if c["id"] == "cutter")
    assert finding["ok"], finding["message"]
    outline, hole = loops(doc, "TOOLPATH")
    gap = shapely.distance(shapely.points(outline), shapely.LinearRing(geom_points(analysis)))
    assert np.max(np.abs(gap - cutter)) <= TOLERANCE
    # inside the keyed bore the centre runs 3 mm in from the hole; the keyway, 3 wide, is too
    # narrow for the cutter to enter
    gap = shapely.distance(shapely.points(hole), hole_outline())
    assert np.max(np.abs(gap - cutter)) <= TOLERANCE
    # its top: the cutter against both corners of the keyway's mouth, (±1.5, √(5² − 1.5²))
    top = math.sqrt(25 - 1.5**2) - math.sqrt(cutter**2 - 1.5**2)
    assert float(hole[:, 1].max()) == pytest.approx(top, abs=TOLERANCE)


def test_a_sharp_hollow_stops_any_cutter() -> None:
    """A knife follower with uniform velocity: the pitch curve has sharp hollows where the rise
    starts and the return ends; no cutter reaches into them, and the finding says where."""
    text = """\
name: knife-hollow
cam: {type: disc, base_radius: 40, rotation: ccw}
follower: {type: knife}
motion:
  - rise: {angle: 120, lift: 20, law: uniform-velocity}
  - dwell: {angle: 60}
  - return: {angle: 120, law: uniform-velocity}
  - dwell: {angle: 60}
manufacturing: {cutter_radius: 4}
"""
    analysis = analyse(design_from_text(text))
    finding = next(f for f in analysis.findings if f.id == "cutter")
    assert not finding.ok and finding.value == 0.0
    assert "sharp hollow" in finding.message
    where = [a for r in finding.ranges_deg for a in r]
    # the hollows are the joints at 0° and 300° (rise start, return end)
    assert any(abs(a - 0.0) < 1 or abs(a - 360.0) < 1 for a in where)
    assert any(abs(a - 300.0) < 1 for a in where)


# ---- the verification measures every CUT contour against the exact one ----------------------

def shifted_cut(monkeypatch: pytest.MonkeyPatch, contour: int, vertex: int,
                by: np.ndarray) -> None:
    """Make the plate's writer draw CUT contour *contour* (0: the outline, then the holes) with
    its vertex *vertex* moved by *by* (mm), the rest of the part (the STL's) as computed."""
    from dataclasses import replace

    import camfab.geometry.plate as plate_module
    from camfab.curves.profile import Profile

    computed = plate_module.plate

    def plate(design, geom):  # type: ignore[no-untyped-def]
        made = computed(design, geom)
        profiles = list(made.cut.profiles)
        moved = profiles[contour].vertices.copy()
        moved[vertex] += by
        profiles[contour] = Profile(moved, profiles[contour].bulges)
        return replace(made, cut=replace(made.cut, profiles=tuple(profiles)))

    monkeypatch.setattr(plate_module, "plate", plate)


def test_a_keyway_drawn_off_by_twice_the_tolerance_fails_the_verification(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The follower never touches the bore, so its lift cannot tell a hole drawn off the part:
    the CUT contours read back are measured against the exact ones, and a keyway corner moved
    twice the tolerance fails the verification (exit 1), saying by how much."""
    shifted_cut(monkeypatch, 1, 1, np.array([2 * TOLERANCE, 0.0]))  # the keyway's top right
    _, analysis, _, report = build(seed_10_4(""))
    check = next(f for f in analysis.findings if f.id == "verification")
    assert analysis.verification.lift.max_mm <= TOLERANCE  # the follower sees nothing
    assert not check.ok and check.value == pytest.approx(2 * TOLERANCE, rel=0.01)
    assert "over the tolerance" in check.message and analysis.exit_code == 1
    assert report["verification"]["cut_outline_max_deviation_mm"] == pytest.approx(
        2 * TOLERANCE, rel=0.01)


@pytest.mark.parametrize("kerf", [0.0, 0.3])
def test_an_outline_point_drawn_off_by_twice_the_tolerance_fails_the_verification(
        monkeypatch: pytest.MonkeyPatch, kerf: float) -> None:
    """An outline vertex moved twice the tolerance toward the cam centre (with a kerf: the
    beam's path moved) fails the verification, whatever the follower's run makes of it."""
    design = design_from_text(seed_10_4(f"manufacturing: {{kerf: {kerf}}}\n"))
    made = __import__("camfab.geometry.plate", fromlist=["plate"]).plate(
        design, analyse(design).geometry)
    outline = made.cut.profiles[0].vertices
    k = int(np.argmin(outline[:, 1]))  # on the dwell, at the base circle
    inward = -outline[k] / np.hypot(*outline[k])
    shifted_cut(monkeypatch, 0, k, 2 * TOLERANCE * inward)
    _, analysis, _, _ = build(seed_10_4(f"manufacturing: {{kerf: {kerf}}}\n"))
    check = next(f for f in analysis.findings if f.id == "verification")
    assert not check.ok and check.value >= 1.9 * TOLERANCE
    assert analysis.verification.deviation_mm >= 1.9 * TOLERANCE
