"""``inspect``: prepare, run the follower over the outline, render the three files and write
them (atomically), and what that did (``InspectResult``)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from camfab.errors import InspectionError
from camfab.inspect.options import InspectOptions, Prepared
from camfab.inspect.prepare import prepare
from camfab.inspect.record import Inspection

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.inspect.scan_run import ScanResult


@dataclass(frozen=True)
class InspectResult:
    """What one inspection did."""

    inspection: Inspection
    prepared: Prepared
    folder: Path
    written: list[Path]

    @property
    def exit_code(self) -> int:
        return self.inspection.exit_code


def inspect(options: InspectOptions) -> InspectResult | ScanResult:
    """Read, inspect, render and write (atomically); raises a ``CamfabError`` on bad input,
    before anything is written. A 3-D scan (:func:`~camfab.inspect.scan_run.is_scan`) is
    inspected by :func:`~camfab.inspect.scan_run.inspect_scan_file`."""
    from camfab.inspect.prepare import read_design
    from camfab.inspect.scan_run import inspect_scan_file, is_scan

    design = read_design(options)
    if is_scan(options.profile, design, options.scan, options.plate_b is not None):
        if design is None:
            raise InspectionError(str(options.profile), "a 3-D scan is inspected against its "
                                  "design: give --design DESIGN.yaml")
        return inspect_scan_file(options, design)
    if options.plate_b is not None:
        raise InspectionError("--plate-b", "applies to a conjugate pair's drawings, with "
                              "--design")
    return _inspect_outline(options, design)


def _inspect_outline(options: InspectOptions, design: Design | None) -> InspectResult:
    """An outline's inspection (see :func:`inspect`)."""
    from camfab.geometry.simulate import SimulationTooLarge
    from camfab.inspect.lift_csv import render_lift_csv
    from camfab.inspect.measure import inspect_profile
    from camfab.inspect.report_html import render_inspection_html
    from camfab.inspect.report_json import render_inspection_json
    from camfab.pipeline import write_files

    with warnings.catch_warnings():
        # numpy's warnings on degenerate numbers are not messages for the user: what they
        # warn of is refused with one line, or does not matter to the result
        warnings.simplefilter("ignore", RuntimeWarning)
        prepared = prepare(options, design)
        try:
            inspection = inspect_profile(prepared.profile, prepared.setup, prepared.reference,
                                         options.align, file=str(options.profile))
        except SimulationTooLarge as exc:
            raise InspectionError(str(options.profile), f"the outline is too jagged to run the "
                                  f"follower over ({exc}): are its points in order along it? "
                                  "(a smooth outline of any number of points needs far fewer)"
                                  ) from None
        stem = options.profile.stem
        files = {f"{stem}-lift.csv": render_lift_csv(inspection),
                 f"{stem}-inspection.json": render_inspection_json(inspection, prepared),
                 f"{stem}-inspection.html": render_inspection_html(inspection, prepared)}
    folder = options.out_dir or Path("exports") / f"{stem}-inspection"
    return InspectResult(inspection, prepared, folder, write_files(folder, files))
