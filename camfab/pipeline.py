"""The pipeline: design -> analysis -> artifacts (bytes) -> files, written atomically.

Exporters only serialise; this module decides which files a design gets and writes them through
temporary files renamed into place, so an interrupted or failed build leaves earlier outputs intact.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from camfab.analysis.findings import Finding, exit_status
from camfab.analysis.kinematics import MotionUnits, SegmentStats, continuity_findings, segment_stats
from camfab.design import Design, load_design
from camfab.errors import OutputError
from camfab.motion.program import MotionProgram

if TYPE_CHECKING:
    from camfab.analysis.cam_checks import CamNumbers
    from camfab.export.stl import StlCheck
    from camfab.geometry.disc_geometry import DiscGeometry, LiftCheck

#: Every output a design may ask for, in the order files are listed.
ALL_OUTPUTS = ("dxf", "svg", "stl", "report", "csv")


@dataclass(frozen=True)
class Verification:
    """The follower run over the CUT outline read back from the written DXF, and the STL read
    back (when one is made).

    ``deviation_mm`` is the largest distance of the exact working curve (offset kerf/2 outward
    with a kerf) from that outline (None for an undercut cam, whose outline is the trimmed one
    on purpose).
    """

    lift: LiftCheck
    source: str
    entities: int
    deviation_mm: float | None
    stl: StlCheck | None = None


@dataclass(frozen=True)
class Analysis:
    """Everything computed about a design, before any file is made."""

    design: Design
    program: MotionProgram
    units: MotionUnits
    segments: list[SegmentStats]
    findings: list[Finding]
    geometry: DiscGeometry | None = None
    numbers: CamNumbers | None = None
    verification: Verification | None = None

    @property
    def exit_code(self) -> int:
        """0 when every error-severity check passed, 1 otherwise."""
        return exit_status(self.findings)


def analyse(design: Design) -> Analysis:
    """Compute the motion, its kinematics and the checks of *design*."""
    program = design.program
    units = MotionUnits(design.follower.oscillating)
    omega = design.cam.omega
    findings, steps = continuity_findings(program, units, omega)
    stats = segment_stats(program, steps, units, omega)
    if design.cam.type != "disc":
        return Analysis(design, program, units, stats, findings)
    from camfab.analysis.cam_checks import cam_findings, cam_numbers
    from camfab.geometry.disc_geometry import disc_geometry

    geometry = disc_geometry(design)
    numbers = cam_numbers(geometry, len(program.segments))
    findings = [*cam_findings(design, geometry, numbers), *findings]
    return Analysis(design, program, units, stats, findings, geometry, numbers)


def verify_exports(analysis: Analysis,
                   requested: tuple[str, ...] = ALL_OUTPUTS) -> tuple[Analysis, dict[str, bytes]]:
    """Write the DXF in memory, read its CUT outline back and run the follower over it.

    Returns the analysis with its :class:`Verification` and the *requested* plate files by output
    name (``dxf``, ``svg``, ``stl``; none for cam types without a plate outline). The DXF is
    made whether requested or not: the verification reads it. With a kerf, the part is the
    outline as written less the kerf/2 the beam takes off, and the deviation is measured from
    the exact working curve offset by kerf/2.
    """
    geom = analysis.geometry
    if geom is None:
        return analysis, {}
    from dataclasses import replace

    from camfab.export.dxf import read_cut_outline, render_dxf
    from camfab.geometry.curves import offset_inward
    from camfab.geometry.disc_geometry import lift_check
    from camfab.geometry.plate import inside_kerf, plate

    design = analysis.design
    contours = plate(design, geom)
    dxf = render_dxf(analysis, contours)
    written = read_cut_outline(dxf, design.mm_per_unit)
    part = written
    source = f"CUT outline read back from {design.name}.dxf"
    if contours.kerf > 0.0:
        part = inside_kerf(written, contours.kerf, geom.tolerance)
        source += f", less the kerf/2 of {contours.kerf / 2:.6g} mm the beam removes"
    lift = lift_check(geom.cam, analysis.program, part)
    deviation = None
    if not geom.undercut:
        exact = offset_inward(geom.dense.working, geom.cam.sigma, -contours.kerf / 2.0)
        deviation = float(written.distance(exact.xy).max())
    plates = {"dxf": dxf}
    if "svg" in requested:
        from camfab.export.svg import render_svg

        plates["svg"] = render_svg(analysis, contours)
    stl_check = None
    if "stl" in requested:
        from camfab.export.stl import check_stl, expected_volume, render_stl

        stl = render_stl(analysis, contours)
        if stl is not None:
            plates["stl"] = stl
            stl_check = check_stl(stl, *expected_volume(analysis, contours))
    check = Verification(lift, source, len(written.vertices), deviation, stl_check)
    findings = [*analysis.findings, verification_finding(analysis, check)]
    return replace(analysis, verification=check, findings=findings), plates


def verification_finding(analysis: Analysis, check: Verification) -> Finding:
    """Do the files hold the design? The follower's lift over the written outline within the
    tolerance (an undercut cam's error is the undercut finding's), and the STL closed, outward
    and of the part's volume."""
    tolerance = analysis.design.manufacturing.tolerance
    geom = analysis.geometry
    assert geom is not None
    lift_ok = geom.undercut or check.lift.max_mm <= tolerance
    parts = [f"the follower run over the CUT outline as written moves "
             f"{check.lift.max_mm:.3g} mm at most from the design motion (at "
             f"{check.lift.at_deg:.4g}°, tolerance {tolerance:.3g} mm)"]
    stl = check.stl
    if stl is not None:
        shape = ("closed, outward, no degenerate face" if stl.watertight and
                 stl.consistent_winding and stl.degenerate_faces == 0 else
                 f"NOT a closed outward solid (watertight: {stl.watertight}, consistent "
                 f"winding: {stl.consistent_winding}, degenerate faces: {stl.degenerate_faces})")
        parts.append(f"the STL reads back {shape}, {stl.faces} faces, "
                     f"{stl.volume_mm3:.6g} mm³ against the part's {stl.expected_volume_mm3:.6g}")
    ok = lift_ok and (stl is None or stl.ok)
    return Finding("verification", ok, "error", "; ".join(parts), check.lift.max_mm,
                   tolerance, "mm")


def _report_json(analysis: Analysis) -> bytes:
    from camfab.export.report_json import render_report_json

    return render_report_json(analysis)


def _motion_csv(analysis: Analysis) -> bytes:
    from camfab.export.motion_csv import render_motion_csv

    return render_motion_csv(analysis)


#: output name -> [(file suffix, renderer)]; outputs without an entry are not produced yet.
RENDERERS: dict[str, list[tuple[str, Callable[[Analysis], bytes]]]] = {
    "report": [("-report.json", _report_json)],
    "csv": [("-motion.csv", _motion_csv)],
}


@dataclass(frozen=True)
class Artifacts:
    """The files of one build, as bytes by file name, and the requested outputs not produced."""

    files: dict[str, bytes]
    not_produced: tuple[str, ...] = field(default_factory=tuple)
    analysis: Analysis | None = None


def render(analysis: Analysis) -> Artifacts:
    """The bytes of every file the design asks for (all that apply by default), after the
    verification of the exported outline (which the report carries)."""
    requested = analysis.design.outputs or ALL_OUTPUTS
    analysis, plates = verify_exports(analysis, requested)
    files: dict[str, bytes] = {}
    missing = []
    for output in ALL_OUTPUTS:
        if output not in requested:
            continue
        if output in plates:
            files[f"{analysis.design.name}.{output}"] = plates[output]
            continue
        if output not in RENDERERS:
            missing.append(output)
            continue
        for suffix, renderer in RENDERERS[output]:
            files[analysis.design.name + suffix] = renderer(analysis)
    return Artifacts(files, tuple(missing), analysis)


def write_files(folder: Path, files: Mapping[str, bytes]) -> list[Path]:
    """Write *files* into *folder* atomically: all to temporary files first, then renamed.

    Raises
    ------
    OutputError
        The folder or a file cannot be written; no file of *files* is changed then.
    """
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{folder}: cannot create the output folder ({exc.strerror})") from None
    temps: list[tuple[Path, Path]] = []
    try:
        for name, data in files.items():
            handle, temp_name = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
            temps.append((Path(temp_name), folder / name))
            with os.fdopen(handle, "wb") as stream:
                stream.write(data)
        for temp, final in temps:
            os.replace(temp, final)
    except OSError as exc:
        for temp, _ in temps:
            temp.unlink(missing_ok=True)
        raise OutputError(f"{folder}: cannot write the outputs ({exc.strerror or exc})") from None
    return [final for _, final in temps]


@dataclass(frozen=True)
class BuildResult:
    """What one build did."""

    analysis: Analysis
    folder: Path
    written: list[Path]
    not_produced: tuple[str, ...]

    @property
    def exit_code(self) -> int:
        return self.analysis.exit_code


def output_folder(design: Design, out_dir: Path | None) -> Path:
    """``exports/<name>/`` under the working directory, or *out_dir* when given."""
    return out_dir if out_dir is not None else Path("exports") / design.name


def build(path: str | Path, out_dir: Path | None = None) -> BuildResult:
    """Load, analyse, render and write one design file."""
    design = load_design(path)
    analysis = analyse(design)
    artifacts = render(analysis)
    folder = output_folder(design, out_dir)
    written = write_files(folder, artifacts.files)
    return BuildResult(artifacts.analysis or analysis, folder, written, artifacts.not_produced)
