"""A scan inspected against its design (``inspect_scan``): placed on the part, each point's
deviation from its flank, the flanks as the scan shows them, and the follower run over them.

The follower's motion as made is the gauge follower (one that fills the design's play) pressed
onto each flank as fitted to the scan (:mod:`camfab.inspect.scan_deviation`): per flank, the
lift error against the design at each cam angle; between two flanks, the play the real follower
has (the backlash) and the lift as the middle of it. Its pressure angle follows from the
lift's derivative, fitted like a measured outline's (:func:`camfab.inspect.measure.derivatives`)
where the scan reaches all round; where it does not, the design's motion stands in across the
gap for the fit, and the gap is not reported.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from camfab.arrays import Array
from camfab.errors import InspectionError
from camfab.inspect.scan import Scan
from camfab.inspect.scan_record import FlankMotion, ScanInspection, ScanSetup
from camfab.inspect.surface import ScanModel


def inspect_scan(scan: Scan, model: ScanModel, setup: ScanSetup, *, file: str) -> ScanInspection:
    """Inspect *scan* (read from *file*, which a refusal names) against *model*.

    Raises
    ------
    InspectionError
        No point of the scan lies on the cam's flanks once placed.
    """
    from camfab.inspect.models.part_mesh import part_samples
    from camfab.inspect.scan_align import align_scan
    from camfab.inspect.scan_checks import scan_findings
    from camfab.inspect.scan_deviation import (
        Others,
        fitted_deviation,
        fitted_surface,
        flank_nodes,
        flank_stats,
        point_deviations,
    )

    raw, normals = scan_points(scan)
    samples = part_samples(model)  # the part's faces, sampled once for both
    alignment = align_scan(raw, normals, model, fixtured=setup.fixtured, samples=samples)
    points = alignment.apply(raw)
    nodes = flank_nodes(model)
    deviations = point_deviations(points, nodes, Others(model, nodes, samples), setup.gate)
    if not np.any(deviations.flank >= 0):
        raise InspectionError(file, f"no point of the scan lies on the cam's "
                              f"{' or '.join(f.name for f in model.flanks)} once placed (within "
                              f"{setup.gate:g} mm): is it a scan of this design's part?")
    design = model.design()
    flanks = []
    for flank, fitted in zip(model.flanks, fitted_deviation(model, deviations, setup.fit),
                             strict=True):
        run = model.run(flank, fitted_surface(flank.points, flank.normals, fitted))
        # judged only where the scan reaches the line the follower touches: elsewhere it would
        # fall into what was not scanned, as if there were no material
        run = np.where(np.isfinite(fitted).any(axis=1), run, np.nan)
        flanks.append(FlankMotion(flank.name, flank.side, run,
                                  (run - design) * model.q_scale, fitted))
    if not any(f.measured.any() for f in flanks):
        raise InspectionError(file, "the scan reaches no line the follower touches on the "
                              f"{' or '.join(f.name for f in model.flanks)} (too few points "
                              f"within {setup.fit:g} mm of any: is --fit too small for its "
                              "density?)")
    lift, backlash = _lift_and_play(flanks, design, model)
    step = float(model.theta[1] - model.theta[0])
    pressure = model.pressure_angle(lift, _slope(lift, design, step, setup.smooth))
    design_pressure = model.pressure_angle(design, _slope(design, design, step, setup.smooth))
    inspection = ScanInspection(setup, model, scan, alignment, deviations,
                                flank_stats(model, deviations, setup.tolerance), flanks, design,
                                lift, backlash, np.where(np.isfinite(lift), pressure, np.nan),
                                design_pressure)
    return replace(inspection, findings=scan_findings(inspection))


#: Spacing (mm) of the points a scanned mesh's triangles are sampled at (the mesh's vertices
#: alone are too few where its triangles are long, as on a flank), and the most of them.
MESH_SPACING_MM = 0.2
MESH_SAMPLES = 2_000_000


def scan_points(scan: Scan) -> tuple[Array, Array | None]:
    """The points (mm) to judge and their normals (or None): a point cloud's own; for a mesh,
    its triangles sampled every :data:`MESH_SPACING_MM` or so (at most
    :data:`MESH_SAMPLES`), with their faces' normals."""
    if scan.faces is None:
        return scan.points, scan.normals
    from camfab.inspect.models.part_mesh import surface_samples

    points, normals, _ = surface_samples(scan.points, scan.faces, MESH_SPACING_MM,
                                         MESH_SAMPLES)
    return points, normals


def _lift_and_play(flanks: list[FlankMotion], design: Array, model: ScanModel
                   ) -> tuple[Array, Array | None]:
    """The lift as made (q: the middle of the play between a lower and an upper flank, the one
    flank's run where only it is measured) and the real follower's play (mm at the trace point)
    where both are; None for a cam of one side."""
    lower = [f.run for f in flanks if f.side < 0]
    upper = [f.run for f in flanks if f.side > 0]
    low = np.fmax.reduce(lower) if lower else None
    high = np.fmin.reduce(upper) if upper else None
    if low is None or high is None:
        only = low if low is not None else high
        assert only is not None
        return only, None
    both = np.isfinite(low) & np.isfinite(high)
    lift = np.where(both, 0.5 * (low + high), np.fmax(low, high))
    play = np.where(both, (model.clearance + high - low) * model.q_scale, np.nan)
    return lift, play


def _slope(q: Array, design: Array, step: float, smooth: float) -> Array:
    """q′ (per rad) of the periodic *q* sampled every *step* rad, fitted over ±*smooth* rad;
    across gaps (NaN) the design's motion, moved to meet the measured ends, stands in."""
    from camfab.inspect.measure import derivatives

    known = np.isfinite(q)
    if not known.any():
        return np.full_like(q, np.nan)
    if not known.all():
        error = q - design
        index = np.arange(q.size)
        filled = np.interp(index, index[known], error[known], period=q.size)
        q = design + filled
    return derivatives(q, step, smooth)[0]
