"""The inspection's record: its setup, the design's motion it is compared with, and what the
follower measured (motion, deviation, findings, the runs over the tolerance)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from camfab.analysis.findings import Finding, exit_status
from camfab.angles import Range, ranges_deg
from camfab.arrays import Array, Index, Mask
from camfab.curves.follower import FollowerGeometry
from camfab.curves.profile import Profile

#: Peaks of |deviation| listed per excursion over the tolerance in the reports.
MAX_EXCURSIONS = 50


@dataclass(frozen=True)
class InspectionSetup:
    """How to inspect: the follower and the cam's turning, all lengths in mm, angles in rad.

    Attributes
    ----------
    follower
        The inspection follower (it may differ from the design's, e.g. a dial indicator's roller).
    sigma
        +1 for a counter-clockwise cam, −1 for clockwise.
    omega
        Speed (rad/s) for velocities and accelerations; None: per radian of cam angle only.
    tolerance
        Largest |deviation| (mm at the trace point) accepted; None without a design.
    step
        Cam-angle step of the lift table's rows.
    smooth
        Half-width of the window the derivatives are fitted over.
    pressure_angle_limit
        The limit the pressure angle is reported against.
    """

    follower: FollowerGeometry
    sigma: int
    omega: float | None
    tolerance: float | None
    step: float
    smooth: float
    pressure_angle_limit: float


@dataclass(frozen=True)
class Reference:
    """The design's motion for the inspection follower.

    ``position(theta)`` is the trace point's height (mm) or arm angle (rad) at cam angles θ;
    ``base_radius`` the design's base circle (mm); ``source`` says how the position is found;
    ``file`` is the design file, which a refusal about the design names.
    """

    position: Callable[[Array], Array]
    base_radius: float
    source: str
    name: str
    profile: Profile
    file: str


@dataclass(frozen=True)
class Excursion:
    """A run of cam angles where |deviation| exceeds the tolerance, and its worst point."""

    start_deg: float
    end_deg: float
    peak_mm: float
    peak_at_deg: float


@dataclass(frozen=True)
class Inspection:
    """The follower run over an outline, on a fine grid of cam angles ``theta`` (rad).

    Motion arrays are in mm (translating) or rad of swing (oscillating), derivatives per radian
    of cam angle: ``motion`` is (4, N) s, s′, s″ and zeros (s‴ is not estimated).
    ``deviation`` is measured minus design (positive: the follower rides higher than the design
    would lift it, material left on), ``deviation_mm`` the same at the trace point.
    """

    setup: InspectionSetup
    profile: Profile
    theta: Array
    rows: Index
    position: Array
    rest: float
    base_radius: float
    measured_base_radius: float
    motion: Array
    pressure_angle: Array
    pitch_radius: Array
    contact: Array
    reference: Reference | None = None
    design_lift: Array | None = None
    deviation: Array | None = None
    deviation_mm: Array | None = None
    align: float | None = None
    findings: list[Finding] = field(default_factory=list)
    lift_from: str = "the outline's smallest radius (its base circle)"

    @property
    def oscillating(self) -> bool:
        return self.setup.follower.oscillating

    @property
    def lift(self) -> Array:
        return self.motion[0]

    @property
    def exit_code(self) -> int:
        return exit_status(self.findings)

    def max_deviation(self) -> tuple[float, float] | None:
        """Largest |deviation| (mm at the trace point) and the cam angle (deg) where it is."""
        if self.deviation_mm is None:
            return None
        k = int(np.argmax(np.abs(self.deviation_mm)))
        return float(abs(self.deviation_mm[k])), float(np.degrees(self.theta[k]))

    def rms_deviation(self) -> float | None:
        """Root mean square of the deviation over the turn (mm at the trace point)."""
        if self.deviation_mm is None:
            return None
        return float(np.sqrt(np.mean(self.deviation_mm**2)))

    def on_outline(self, theta_deg: float) -> tuple[float, float]:
        """Where the follower touches the cam at cam angle *theta_deg*: the contact point (mm) in
        the outline's frame as read (centred, before any alignment turn) — where to look on the
        part."""
        k = int(np.argmin(np.abs(np.degrees(self.theta) - theta_deg)))
        x, y = self.contact[k]
        if self.align:
            c, s = math.cos(self.setup.sigma * self.align), math.sin(self.setup.sigma * self.align)
            x, y = c * x + s * y, -s * x + c * y
        return float(x), float(y)

    def excursions(self) -> list[Excursion]:
        """Where |deviation| exceeds the tolerance, each run with its peak (largest first)."""
        if self.deviation_mm is None or self.setup.tolerance is None:
            return []
        over = np.abs(self.deviation_mm) > self.setup.tolerance
        out = []
        for start, end in ranges_deg(self.theta, over):
            inside = _in_range(np.degrees(self.theta), (start, end))
            k = int(np.flatnonzero(inside)[np.argmax(np.abs(self.deviation_mm[inside]))])
            out.append(Excursion(start, end, float(self.deviation_mm[k]),
                                 float(np.degrees(self.theta[k]))))
        return sorted(out, key=lambda e: -abs(e.peak_mm))[:MAX_EXCURSIONS]


def _in_range(deg: Array, r: Range) -> Mask:
    start, end = r
    if start <= end:
        return (deg >= start - 1e-9) & (deg <= end + 1e-9)
    return (deg >= start - 1e-9) | (deg <= end + 1e-9)

