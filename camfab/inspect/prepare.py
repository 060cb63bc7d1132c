"""Reading the design, the follower file and the outline, and resolving the setup (``prepare``).

The follower, the cam's turning, speed and tolerance come from the design (``--design``), then a
small follower file (``--follower``), then the command line, each overriding the one before.
Lengths on the command line and in the follower file are in ``--units`` (default: the design's
units, else mm) unless they carry a unit (``"5 mm"``); ``--centre`` is in the outline file's
coordinates. Nothing is written unless everything was read and computed.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from camfab.errors import InspectionError
from camfab.inspect.follower import inspection_follower, read_follower_file
from camfab.inspect.measure import SMOOTH_DRAWING, SMOOTH_POINTS
from camfab.inspect.options import InspectOptions, Prepared
from camfab.inspect.part import centred, part_outline
from camfab.inspect.record import InspectionSetup
from camfab.inspect.values import (
    SMOOTH_RANGE_DEG,
    angle,
    cam_centre,
    cam_speed,
    length,
    optional_length,
    row_step,
)

if TYPE_CHECKING:
    from camfab.design import Design


def read_design(options: InspectOptions) -> Design | None:
    """The design of ``--design``, None without one."""
    from camfab.design.source import MAX_DESIGN_BYTES
    from camfab.files import check_bounded
    from camfab.pipeline import load_design

    if options.design is None:
        return None
    check_bounded(options.design, MAX_DESIGN_BYTES, "a design file")
    return load_design(options.design)


def prepare(options: InspectOptions, design: Design | None) -> Prepared:
    """Read the follower file and the outline, and resolve the setup against *design* (read
    from ``--design``)."""
    from camfab.export.outline import read_outline

    analysis = None
    if design is not None:
        from camfab.kinds import kind_of
        from camfab.pipeline import analyse

        refusal = kind_of(design.cam.type).inspect_refusal
        if refusal is not None:
            raise InspectionError(str(options.design), refusal)
        analysis = analyse(design)
    extra = read_follower_file(options.follower_file) if options.follower_file else {}
    file_units = extra.get("units")
    units = options.units or file_units or (design.units if design else "mm")
    follower = inspection_follower(options, extra, design, units)
    outline = read_outline(options.profile, units=options.units,
                           default_units=units, layer=options.layer)
    tolerance = optional_length("--tolerance", options.tolerance, units, positive=True)
    if tolerance is None and "tolerance" in extra:
        tolerance = length("tolerance", extra["tolerance"], units, str(options.follower_file),
                           positive=True)
    if tolerance is None and design is not None:
        tolerance = design.inspection_tolerance
    rotation = options.rotation or extra.get("rotation") or (
        design.cam.rotation if design else "ccw")
    if rotation not in ("ccw", "cw"):
        raise InspectionError(str(options.follower_file), f"rotation: must be ccw or cw (got "
                              f"{rotation!r})")
    speed_rpm = cam_speed(options, extra, design)
    step = row_step(options, design)
    smooth = (angle("--smooth", options.smooth, SMOOTH_RANGE_DEG)
              if options.smooth is not None
              else SMOOTH_POINTS if outline.points_only else SMOOTH_DRAWING)
    limit = (design.pressure_angle_limit if design is not None
             else math.radians(35.0 if follower.oscillating else 30.0))
    setup = InspectionSetup(follower, 1 if rotation == "ccw" else -1,
                            None if speed_rpm is None else speed_rpm * math.pi / 30.0,
                            tolerance, step, smooth, limit)
    centre = cam_centre(options.centre, outline.mm_per_unit)
    profile, kerf, kerf_source = part_outline(options, outline, units)
    profile = centred(profile, centre, options.profile)
    reference = None
    if analysis is not None:
        from camfab.inspect.reference import design_reference

        reference = design_reference(analysis, follower)
    elif options.align:
        raise InspectionError("--align", "needs --design (the motion to align the outline to)")
    return Prepared(options, outline, profile, setup, reference, units, speed_rpm, centre, kerf,
                    kerf_source, design)
