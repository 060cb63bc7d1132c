"""``camfab inspect SCAN --design DESIGN.yaml`` for a 3-D scan (or CMM points) of a made cam:
which inputs are scans (``is_scan``), the kind's scan model (``scan_model_of``), and the
inspection read, run, rendered and written (``inspect_scan_file``).

A file is a scan when it is a PLY or STL file, when ``--scan`` says so, or when the design's cam
is of a kind whose functional surfaces are not one outline (a drum, a globoid, a groove plate, a
conjugate pair): its CSV is then x, y, z points. A disc cam's CSV stays an outline of x, y
points unless ``--scan`` is given. A groove plate's DXF is read as its two walls, a conjugate
pair's as plate a with plate b's drawing given by ``--plate-b`` (without it, plate a's drawing
is inspected as an outline against cam a, as before)
(:mod:`camfab.inspect.scan_drawing`), and judged like a scan.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from importlib import import_module
from pathlib import Path
from typing import TYPE_CHECKING

from camfab.errors import InspectionError
from camfab.inspect.options import InspectOptions
from camfab.inspect.scan_record import ScanInspection, ScanSetup

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.inspect.scan import Scan
    from camfab.inspect.surface import ScanModel

#: Cam-angle step (rad) of the flank grids' rows and of the motion as made: 0.1°, like the
#: inspection of an outline.
SCAN_STEP = math.radians(0.1)

#: The kind's module (``camfab.kinds.<name>``, the registry's row) -> the module of its scan
#: model under ``camfab.inspect.models``.
SCAN_MODELS = {"camfab.kinds.drum": "drum", "camfab.kinds.globoid": "globoid",
               "camfab.kinds.groove": "groove", "camfab.kinds.pair:CONJUGATE": "pair",
               "camfab.kinds.disc": "plate", "camfab.kinds.shaped": "plate",
               # the yoke's lower face: it touches every point of the profile once a turn
               "camfab.kinds.pair:CONSTANT_BREADTH": "plate", "camfab.kinds.linear": "linear"}

#: Kinds whose CSV is a scan (x, y, z) without ``--scan``: no one outline holds their surfaces.
SCAN_ONLY = ("drum", "globoid", "groove", "pair", "linear")

#: Default size (mm) of the box the scan's deviation is averaged over (``--fit``).
DEFAULT_FIT_MM = 1.0

#: ``--fit`` range (mm): from a twentieth of a millimetre to 20 mm.
FIT_RANGE_MM = (0.05, 20.0)

#: Default gate (mm) on a point's distance from its flank (``--gate``).
DEFAULT_GATE_MM = 1.0

#: ``--gate`` range (mm).
GATE_RANGE_MM = (0.01, 20.0)

#: Half-width (rad) of the window the motion's derivative is fitted over: 3°, as for points.
SCAN_SMOOTH = math.radians(3.0)


def model_name(design: Design) -> str | None:
    """The scan model's module name of *design*'s kind, None when camfab has none."""
    from camfab.kinds import REGISTRY

    return SCAN_MODELS.get(REGISTRY[design.cam.type])


def is_scan(path: Path, design: Design | None, forced: bool, plate_b: bool = False) -> bool:
    """True when *path* is to be read as a 3-D scan (see the module), or a groove plate's
    drawing with its design (its two walls measured as a scan's), or a conjugate pair's plate
    a's drawing with plate b's (*plate_b*; plate a's alone is inspected as an outline, against
    cam a)."""
    if forced or path.suffix.lower() in (".ply", ".stl"):
        return True
    if design is None:
        return False
    if path.suffix.lower() == ".dxf":
        return model_name(design) == "groove" or (plate_b and model_name(design) == "pair")
    return model_name(design) in SCAN_ONLY


def scan_model_of(analysis: Analysis, file: str) -> ScanModel:
    """The scan model of *analysis*'s kind (a refusal names the design *file*)."""
    name = model_name(analysis.design)
    if name is None:
        raise InspectionError(file, f"cam.type {analysis.design.cam.type!r}: camfab cannot "
                              "inspect a scan of this kind of cam yet")
    module = import_module(f"camfab.inspect.models.{name}")
    model: ScanModel = module.scan_model(analysis, SCAN_STEP)
    return model


@dataclass(frozen=True)
class ScanResult:
    """What one scan inspection did."""

    inspection: ScanInspection
    design: Design
    folder: Path
    written: list[Path]

    @property
    def exit_code(self) -> int:
        return self.inspection.exit_code


def _bounded(what: str, raw: str | None, default: float, units: str,
             limits: tuple[float, float]) -> float:
    from camfab.inspect.values import length

    if raw is None:
        return default
    value = length(what, raw, units)
    if not limits[0] <= value <= limits[1]:
        raise InspectionError(what, f"must be from {limits[0]:g} to {limits[1]:g} mm (got "
                              f"{value:g} mm)")
    return value


def scan_setup(options: InspectOptions, design: Design, units: str) -> ScanSetup:
    """The setup from the command line and the design."""
    from camfab.inspect.values import SMOOTH_RANGE_DEG, angle, optional_length

    tolerance = optional_length("--tolerance", options.tolerance, units, positive=True)
    smooth = (angle("--smooth", options.smooth, SMOOTH_RANGE_DEG)
              if options.smooth is not None else SCAN_SMOOTH)
    return ScanSetup(design.inspection_tolerance if tolerance is None else tolerance,
                     options.fixtured,
                     _bounded("--fit", options.fit, DEFAULT_FIT_MM, units, FIT_RANGE_MM),
                     _bounded("--gate", options.gate, DEFAULT_GATE_MM, units, GATE_RANGE_MM),
                     smooth, design.pressure_angle_limit)


def _refuse_outline_options(options: InspectOptions) -> None:
    """Options of an outline's inspection that a scan's does not take, refused by name."""
    given = [name for name, value in (
        ("--follower", options.follower_file), ("--layer", options.layer),
        ("--centre", options.centre), ("--kerf", options.kerf), ("--step", options.step),
        ("--speed", options.speed), ("--rotation", options.rotation)) if value]
    given += [f"--{key.replace('_', '-')}" for key in options.follower]
    if options.align:
        given.append("--align")
    if given:
        raise InspectionError(given[0], "applies to an outline, not to a 3-D scan (a scan is "
                              "placed on the part by itself; the follower and the cam's turning "
                              "are the design's)")


def _drawing_points(options: InspectOptions, design: Design, units: str) -> Scan:
    """A groove plate's drawing, or a conjugate pair's two (``--plate-b``), as scan points."""
    from camfab.inspect.scan_drawing import drawing_scan, pair_scan

    thickness = design.cam.thickness
    if thickness is None:
        raise InspectionError(str(options.design), "cam.thickness is not given: camfab makes "
                              "no plate of this design to hold a drawing to")
    if model_name(design) == "pair":
        assert options.plate_b is not None, "is_scan: a pair's drawing is a scan with plate b's"
        return pair_scan(options.profile, options.plate_b, thickness, units)
    if options.plate_b is not None:
        raise InspectionError("--plate-b", "applies to a conjugate pair's drawings")
    return drawing_scan(options.profile, thickness, units)


def inspect_scan_file(options: InspectOptions, design: Design) -> ScanResult:
    """Read the scan and inspect it against *design*; render and write the files (atomically).
    Raises a ``CamfabError`` on bad input, before anything is written."""
    from camfab.inspect.scan import read_scan
    from camfab.inspect.scan_html import render_scan_html
    from camfab.inspect.scan_json import render_scan_json
    from camfab.inspect.scan_lift_csv import render_scan_lift_csv
    from camfab.inspect.scan_measure import inspect_scan
    from camfab.pipeline import analyse, write_files

    _refuse_outline_options(options)
    assert options.design is not None
    units = options.units or design.units
    setup = scan_setup(options, design, units)
    if options.profile.suffix.lower() == ".dxf":
        scan = _drawing_points(options, design, units)
        setup = replace(setup, fixtured=True)
    else:
        if options.plate_b is not None:
            raise InspectionError("--plate-b", "applies to a conjugate pair's drawings (PROFILE "
                                  "then plate a's DXF); a scan holds both plates")
        scan = read_scan(options.profile, units=options.units, default_units=design.units)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        model = scan_model_of(analyse(design), str(options.design))
        inspection = inspect_scan(scan, model, setup, file=str(options.profile))
        stem = options.profile.stem
        files = {f"{stem}-lift.csv": render_scan_lift_csv(inspection, design.table_step),
                 f"{stem}-inspection.json": render_scan_json(inspection, options, design),
                 f"{stem}-inspection.html": render_scan_html(inspection, options, design)}
    folder = options.out_dir or Path("exports") / f"{stem}-inspection"
    return ScanResult(inspection, design, folder, write_files(folder, files))
