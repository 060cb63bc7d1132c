"""Reading back, shared by the kinds: every build checks the files it writes, reading them back
as their users would and running the follower over what it finds.

A disc cam's CUT outline is read back from the DXF (the kerf taken back off) and the follower run
over it; the outline's distance from the exact curve is measured; the STL is read back and
checked closed, outward and of the part's volume. A drum cam's STL is read back and the roller
run through the groove between the wall vertices it finds; the developed groove in the DXF is
measured against the exact walls.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.findings import Finding
from camfab.analysis.verification import Verification
from camfab.geometry.disc_geometry import LiftCheck

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.analysis.verification import StlCheck
    from camfab.arrays import Array, Index
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.export.serialise import PartFiles
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.linear import LinearGeometry
    from camfab.geometry.plate import Contours, Plate
    from camfab.motion.program import MotionProgram

def against_cut(written: LiftCheck, cut: LiftCheck, tolerance: float) -> LiftCheck:
    """The lift over the files *written* against the motion of the *cut* cam as computed (its
    loops trimmed), at the same cam angles: what the files add to an undercut cam's departure
    from the design.

    Where the cut cam follows the design (its lift within the sampling share of *tolerance*,
    mm, of the design's), the design's motion is the reference, as for any cam; where the
    undercut takes it further, the cut cam's motion is."""
    from camfab.curves.sampling import SAMPLING_SHARE

    departs = np.abs(cut.error_mm) > SAMPLING_SHARE * tolerance
    return LiftCheck(written.theta, written.error - np.where(departs, cut.error, 0.0),
                     written.error_mm - np.where(departs, cut.error_mm, 0.0))


def beam_cut(design: Design, geom: DiscGeometry | LinearGeometry, program: MotionProgram,
             kerf: float) -> LiftCheck | None:
    """The follower's lift over the cam as a laser's beam *kerf* wide (mm) cuts it: the cam
    computed with its hollows narrower than the beam filled (a knife's velocity step makes a
    sharp one), which no file can cut sharper; None without a kerf, or where the beam leaves
    nowhere under the follower more than the sampling share of the tolerance (the ``kerf``
    check says what it leaves). Its error is the beam's, the run over the filled outline less
    the run over the outline itself (whose fit to the exact curve the read-back is not held
    to), added to the outline's own where that departs from the design (an undercut's trim)."""
    if kerf <= 0.0:
        return None
    from camfab.analysis.cam_checks import tool_cut
    from camfab.curves.sampling import SAMPLING_SHARE

    cut = tool_cut(design, geom, kerf / 2.0, program,
                   leave=SAMPLING_SHARE * design.manufacturing.tolerance)
    if cut is None:
        return None
    made, own = cut.made, geom.lift
    departs = np.abs(own.error_mm) > SAMPLING_SHARE * design.manufacturing.tolerance
    return LiftCheck(made.theta, made.error - np.where(departs, 0.0, own.error),
                     made.error_mm - np.where(departs, 0.0, own.error_mm))


#: The words of a verification that holds a plate's files to the cam as a beam cuts it.
BEAM_DEPARTS = {"departs_because": "the beam rounds the profile's hollows narrower than it",
                "departs_check": "kerf", "departs_cam": "the beam-cut cam",
                "departs_by": "the beam cuts it as designed"}


def verify_plate(analysis: Analysis, contours: Plate,
                 files: PartFiles) -> tuple[Verification, ReadBack]:
    """A plate cam's files read back: the follower run over the CUT outline of ``NAME.dxf``,
    the STL (when made) checked against the plate's exact volume; what was found, and the
    outline read back."""
    design, geom = analysis.design, analysis.geometry
    assert geom is not None
    stl_check = None
    if files.stl is not None:
        from camfab.export.stl import check_stl

        stl_check = check_stl(files.stl.data, *expected_volume(analysis, contours))
    dxf = files.files["dxf"][f"{design.name}.dxf"]
    back = read_back(design, geom, analysis.program, dxf, contours.kerf, f"{design.name}.dxf",
                     holes=contours.holes)
    tolerance = design.manufacturing.tolerance
    beam = beam_cut(design, geom, analysis.program, contours.kerf)
    if beam is not None:
        return Verification(back.lift, back.source, back.entities, back.deviation, stl_check,
                            exempt=True, cut_error=against_cut(back.lift, beam, tolerance),
                            **BEAM_DEPARTS), back
    return Verification(back.lift, back.source, back.entities, back.deviation, stl_check,
                        exempt=geom.undercut,
                        cut_error=against_cut(back.lift, geom.lift, tolerance)
                        if geom.undercut else None
                        ), back


def groove_mesh(part: Part, files: PartFiles, tolerance: float,
                folded: bool) -> tuple[Array, Index, StlCheck | None, Index]:
    """The mesh a drum's or a globoid's roller is run through (mm): the STL read back,
    checked closed, outward and of the solid's volume (within *tolerance*, mm, over its
    surface), or, when the groove folds (or no STL was made), the tube as computed, unchecked:
    (V, 3) vertices, (F, 3) faces, the STL's check, and the mesh's edges, each once (E, 2)."""
    from camfab.arrays import edge_groups

    if folded or files.stl is None:
        made = part.made
        return made.vertices, made.faces, None, edge_groups(made.faces, len(made.vertices))[0]
    from camfab.export.stl import check_stl, read_stl

    mesh = read_stl(files.stl.data)
    check = check_stl(files.stl.data, files.stl.volume_mm3, tolerance * files.stl.area_mm2,
                      mesh)
    return (np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces), check,
            mesh.edge_groups[0])


def expected_volume(analysis: Analysis, plate: Plate) -> tuple[float, float]:
    """The plate's volume (mm³) from its exact hole areas and its outline's area, and the
    allowance for the tolerance along every contour (mm³)."""
    from camfab.export.stl import chain_length, hole_points, holes_area

    geom, cam = analysis.geometry, analysis.design.cam
    assert geom is not None and cam.thickness is not None
    area = geom.profile.area - holes_area(plate.holes)
    chains = [geom.outline_points(), *hole_points(plate.holes, geom.tolerance)]
    length = sum(chain_length(c) for c in chains)
    tolerance = analysis.design.manufacturing.tolerance
    return area * cam.thickness, tolerance * length * cam.thickness


@dataclass(frozen=True)
class ReadBack:
    """A plate's CUT outline read back from its DXF: the part it makes (the kerf taken off, mm),
    the follower run over it, its entity count and its largest distance from the exact curve
    (None for an undercut cam)."""

    part: Profile
    lift: LiftCheck
    source: str
    entities: int
    deviation: float


def read_part(dxf: bytes, mm_per_unit: float, kerf: float, tolerance: float, file_name: str,
              move: Callable[[Profile], Profile] | None = None) -> tuple[Profile, Profile, str]:
    """The CUT outline of *dxf* read back as a reader would (mm; moved by *move* into the frame
    it was computed in), the part it makes (the laser's *kerf* taken back off, its offset within
    *tolerance*), and a sentence saying so."""
    from camfab.export.dxf import read_cut_outline
    from camfab.geometry.plate import inside_kerf

    written = read_cut_outline(dxf, mm_per_unit)
    if move is not None:
        written = move(written)
    part = written
    source = f"CUT outline read back from {file_name}"
    if kerf > 0.0:
        part = inside_kerf(written, kerf, tolerance)
        source += f", less the kerf/2 of {kerf / 2:.6g} mm the beam removes"
    return written, part, source


def read_back(design: Design, geom: DiscGeometry, program: MotionProgram, dxf: bytes, kerf: float,
              file_name: str, move: Callable[[Profile], Profile] | None = None,
              holes: Contours | None = None) -> ReadBack:
    """Read a plate cam's CUT outline back from *dxf* (see :func:`read_part`) and run the
    follower of *geom* through *program* over it; *move* takes the outline from the frame the
    file draws it in to the frame of *geom* (a conjugate pair's cam b). Every CUT contour is
    measured against the exact one (:func:`cut_deviation`; the part's *holes*, in the file's
    frame)."""
    from camfab.geometry.disc_geometry import lift_check

    written, part, source = read_part(dxf, design.mm_per_unit, kerf, geom.tolerance, file_name,
                                      move)
    deviation = max(outline_deviation(written, exact_outline(geom, program), kerf,
                                      design.manufacturing.tolerance),
                    holes_deviation(dxf, design.mm_per_unit, holes, kerf,
                                    design.manufacturing.tolerance))
    return ReadBack(part, lift_check(geom.cam, program, part), source, len(written.vertices),
                    deviation)


#: The exact contours the CUT contours are measured against are sampled within this share of
#: the tolerance, and the contours read back cut into points within it: the distances found are
#: within twice this share of the true ones.
REFERENCE_SHARE = 1.0 / 32.0


def exact_outline(geom: DiscGeometry, program: MotionProgram) -> Array:
    """The part's outline as camfab computed it, as a closed chain of points (mm) within
    :data:`REFERENCE_SHARE` of the tolerance of the exact curve: a cam drawn from its shape,
    its lines and arcs; any other, the working curve sampled anew, and an undercut cam's with
    its loops trimmed as camfab trims them (the cut cam: the design cannot be made, the undercut
    check says so, and the files are held to the cam camfab computes)."""
    from camfab.geometry.disc_geometry import cut_cam, sample_closed

    share = REFERENCE_SHARE * geom.tolerance
    if geom.exact:
        return geom.profile.points(share)
    working = sample_closed(geom.cam, program, "working", share)
    if not geom.undercut:
        return working.xy
    pitch = sample_closed(geom.cam, program, "pitch", share)
    return cut_cam(geom.cam, program, geom.dense, pitch, working, share)


def outline_deviation(written: Profile, exact: Array, kerf: float, tolerance: float) -> float:
    """The largest distance (mm) between the CUT outline *written* (read back, mm) and the
    exact one: the outline through the points *exact* (mm) grown by kerf/2 as a beam runs
    round it (round joins), each way: from points along the written lines and arcs to the
    exact chain, and from the exact points to the written lines and arcs."""
    from camfab.curves.profile import Profile
    from camfab.geometry.offset import grow

    share = REFERENCE_SHARE * tolerance
    if kerf > 0.0:
        exact = max(grow(exact, kerf / 2.0, share), key=len)
    there = Profile.from_points(exact).distance(written.points(share))
    back = written.distance(exact)
    return float(max(there.max(initial=0.0), back.max(initial=0.0)))


def holes_deviation(dxf: bytes, mm_per_unit: float, holes: Contours | None, kerf: float,
                    tolerance: float) -> float:
    """The largest distance (mm) between the CUT contours inside the outline of *dxf* (read
    back, mm) and the part's *holes* shrunk by kerf/2 (a beam runs inside them): each circle's
    radius against the hole's, each closed contour against the nearest hole each way; inf when
    the file has another number of holes than the part."""
    from camfab.curves.profile import Profile
    from camfab.export.dxf import read_dxf
    from camfab.geometry.offset import grow

    drawing = read_dxf(dxf, mm_per_unit)
    share = REFERENCE_SHARE * tolerance
    circles = sorted((r - kerf / 2.0 for r in (holes.circles if holes else ())
                      if r - kerf / 2.0 > 0.0), reverse=True)
    rings = [ring for hole in (holes.profiles if holes else ())
             for ring in grow(hole.points(share), -kerf / 2.0, share)]
    written = drawing.cut_profiles[1:]
    if len(drawing.cut_circles) != len(circles) or len(written) != len(rings):
        return np.inf
    worst = max((abs(a - b) for a, b in zip(drawing.cut_circles, circles, strict=True)),
                default=0.0)
    exact = [Profile.from_points(ring) for ring in rings]
    for contour in written:
        there = np.min([e.distance(contour.points(share)) for e in exact], axis=0)
        worst = max(worst, float(there.max(initial=0.0)))
    for ring in rings:
        back = np.min([contour.distance(ring) for contour in written], axis=0)
        worst = max(worst, float(back.max(initial=0.0)))
    return worst


def verification_finding(analysis: Analysis, check: Verification) -> Finding:
    """Do the files hold the design? The follower's lift over the geometry as written within
    the tolerance, the CUT contours read back within it of the exact ones, and the STL closed,
    outward and of the part's volume.

    An undercut cam's motion departs from the design on purpose (the undercut check says by how
    much): its files are held to the cam camfab computed instead. Where there is no such cam to
    compare with (a groove that folds over), the lift is not compared, and without an STL to
    check the finding is not applicable rather than passed."""
    tolerance = analysis.design.manufacturing.tolerance
    lift = check.lift
    value: float | None = lift.max_mm
    if not check.exempt:
        lift_ok = lift.max_mm <= tolerance
        parts = [f"the follower run over the geometry as written ({check.source}) moves "
                 f"{lift.max_mm:.3g} mm at most from the design motion (at {lift.at_deg:.4g}°, "
                 f"tolerance {tolerance:.3g} mm)"]
    elif check.cut_error is not None:
        cut = check.cut_error
        value = cut.max_mm
        lift_ok = cut.max_mm <= tolerance
        parts = [f"{check.departs_because} and moves the follower up to {lift.max_mm:.3g} mm "
                 f"off the design (see the {check.departs_check} check); the follower run over "
                 f"the geometry as written ({check.source}) moves {cut.max_mm:.3g} mm at most "
                 f"from the motion of {check.departs_cam} camfab computed, the design's wherever "
                 f"{check.departs_by} (at {cut.at_deg:.4g}°, tolerance "
                 f"{tolerance:.3g} mm)"]
    else:
        value = None
        lift_ok = True
        parts = [f"not applicable: {check.exempt_because}, so there is no cam whose "
                 f"motion the files could hold (see the {check.exempt_check} check); run over "
                 f"{check.source}, the roller moves up to {lift.max_mm:.3g} mm off the design"]
    # (a groove that folds over has no exact walls to measure against)
    deviation = check.deviation_mm if value is not None else None
    deviation_ok = deviation is None or deviation <= tolerance
    if deviation is not None:
        parts.append(f"the CUT contours read back lie {deviation:.3g} mm at most from the "
                     f"exact ones" + ("" if deviation_ok else f", over the tolerance "
                                      f"{tolerance:.3g} mm: the files do not hold the design"))
        if not deviation_ok:
            value = deviation if value is None else max(value, deviation)
    stl = check.stl
    if stl is not None:
        shape = ("closed, outward, no degenerate face, short edge or sliver" if stl.watertight
                 and stl.consistent_winding and stl.degenerate_faces == 0
                 and stl.short_edges == 0 and stl.sliver_faces == 0 else
                 f"NOT a clean closed outward solid (watertight: {stl.watertight}, consistent "
                 f"winding: {stl.consistent_winding}, degenerate faces: {stl.degenerate_faces}, "
                 f"short edges: {stl.short_edges}, sliver faces: {stl.sliver_faces})")
        parts.append(f"the STL reads back {shape}, {stl.faces} faces, "
                     f"{stl.volume_mm3:.6g} mm³ against the part's {stl.expected_volume_mm3:.6g}")
    step = check.step
    if step is not None:
        shape = ("valid" if step.as_made else
                 f"NOT as made (valid: {step.valid}, solids: {step.solids} of "
                 f"{step.expected_solids}, B-splines: {step.b_splines})")
        against = ("the STL's" if step.fitted else "the part's exact")
        off = ("the exact surfaces" if step.fitted else "the part's contours")
        parts.append(f"the STEP reads back {shape}, {step.solids} solid(s), {step.circles} "
                     f"circles and {step.cylinders} cylinders, {step.volume_mm3:.6g} mm³ against "
                     f"{against} {step.expected_volume_mm3:.6g}, its faces "
                     f"{step.deviation_mm:.3g} mm at most off {off}")
    ok = lift_ok and deviation_ok and (stl is None or stl.ok) and (step is None or step.ok)
    applicable = value is not None or not deviation_ok or (stl is not None and not stl.ok) or (
        step is not None and not step.ok)
    return Finding("verification", ok, "error", "; ".join(parts), value, tolerance, "mm",
                   applicable=applicable)
