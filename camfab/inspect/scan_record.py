"""The record of a scan's inspection (``ScanInspection``): how the scan was placed on the part,
its points' deviations from the exact flanks, and the follower's motion through the flanks as
the scan shows them, judged against the design."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from camfab.analysis.findings import Finding, exit_status
from camfab.arrays import Array

if TYPE_CHECKING:
    from camfab.inspect.scan import Scan
    from camfab.inspect.scan_align import Alignment
    from camfab.inspect.scan_deviation import FlankStats, PointDeviations
    from camfab.inspect.surface import ScanModel


@dataclass(frozen=True)
class ScanSetup:
    """How to inspect a scan: lengths in mm, angles in rad.

    Attributes
    ----------
    tolerance
        Largest |lift error| (mm at the trace point) accepted.
    fixtured
        The scan is in the cam's frame up to its phase (a CMM's fixture); else a free fit.
    fit
        Size of the box the scan's deviation is averaged over into the fitted surface (mm).
    gate
        Largest |deviation| (mm) of a point counted on a flank; farther points are set aside.
    smooth
        Half-width of the window the measured motion's derivative is fitted over (rad).
    pressure_angle_limit
        The limit the pressure angle as made is reported against.
    """

    tolerance: float
    fixtured: bool
    fit: float
    gate: float
    smooth: float
    pressure_angle_limit: float


@dataclass(frozen=True)
class FlankMotion:
    """The follower run over one flank as the scan shows it.

    ``run`` is the bound of the follower's coordinate q the flank gives at each cam angle (mm
    or rad, NaN where the scan does not reach), ``error_mm`` its departure from the design's
    (mm at the trace point; + the follower is pushed toward +q), ``fitted`` the flank's fitted
    deviation (mm, (R, C), NaN where unscanned).
    """

    name: str
    side: int
    run: Array
    error_mm: Array
    fitted: Array

    @property
    def measured(self) -> Array:
        return np.isfinite(self.run)

    def worst(self) -> tuple[float, int] | None:
        """The largest |error| (mm) and its row, None where nothing was measured."""
        if not self.measured.any():
            return None
        k = int(np.nanargmax(np.abs(self.error_mm)))
        return float(abs(self.error_mm[k])), k


@dataclass(frozen=True)
class ScanInspection:
    """A scan inspected against its design (all on the model's rows of cam angle ``theta``)."""

    setup: ScanSetup
    model: ScanModel
    scan: Scan
    alignment: Alignment
    deviations: PointDeviations
    stats: list[FlankStats]
    flanks: list[FlankMotion]
    design_q: Array
    lift_q: Array
    backlash_mm: Array | None
    pressure_angle: Array
    design_pressure_angle: Array
    findings: list[Finding] = field(default_factory=list)

    @property
    def theta(self) -> Array:
        return self.model.theta

    @property
    def exit_code(self) -> int:
        return exit_status(self.findings)

    @property
    def lift_error_mm(self) -> Array:
        """The lift as made (the middle of the play between two flanks) less the design's
        (mm at the trace point)."""
        return (self.lift_q - self.design_q) * self.model.q_scale

    def worst(self) -> tuple[float, str, float] | None:
        """The largest |lift error| of any flank (mm), the flank, the cam angle (deg)."""
        best = None
        for f in self.flanks:
            found = f.worst()
            if found is not None and (best is None or found[0] > best[0]):
                best = (found[0], f.name, math.degrees(float(self.theta[found[1]])))
        return best
