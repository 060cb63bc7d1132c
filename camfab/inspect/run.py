"""``inspect``: prepare, run the follower over the outline, render the three files and write
them (atomically), and what that did (``InspectResult``)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

from camfab.errors import InspectionError
from camfab.inspect.options import InspectOptions, Prepared
from camfab.inspect.prepare import prepare
from camfab.inspect.record import Inspection


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


def inspect(options: InspectOptions) -> InspectResult:
    """Read, inspect, render and write (atomically); raises a ``CamfabError`` on bad input,
    before anything is written."""
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
        prepared = prepare(options)
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
