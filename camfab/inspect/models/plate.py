"""Plate cams' scan models (:class:`~camfab.inspect.surface.ScanModel`): a disc cam's or a
shaped cam's profile (:func:`scan_model`), and what a groove's walls (:mod:`.groove`) and a
conjugate pair's plates (:mod:`.pair`) share with it (:class:`PlateScan`).

The follower's coordinate q is what the follower simulation
(:func:`camfab.geometry.simulate.simulate`) gives for it: a translating follower's trace-point
height (mm; a flat face's height), an oscillating one's arm angle Ψ from the line pivot → cam
centre (rad): ``q = rest + s(θ)`` on the design. Row *i* of a flank is the follower's contact
with the plate's exact working curve at cam angle θᵢ (:class:`~camfab.geometry.disc.DiscCam`,
the curve the build samples), in the frame of camfab's STL (the plate drawn at cam angle 0,
from z = 0 up); its columns run through the plate's thickness (a plate is a straight
extrusion: every column is the same outline). The normals are the outline's, horizontal, out of
the material. The run: :mod:`camfab.inspect.models.plate_run`. The deviation map's u is the cam
angle (°).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from camfab.curves.plane import perp
from camfab.errors import InspectionError
from camfab.inspect.models.plate_run import WINDOW_MARGIN_MM, Rider, fit_window
from camfab.inspect.surface import ACROSS_STEP_MM, MIN_COLUMNS, FlankGrid
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array, Index
    from camfab.geometry.disc import DiscCam



#: The deviation maps' horizontal axis.
CAM_ANGLE_LABEL = "cam angle (°)"

#: The pressure angle (rad) of the motion q(θ), q′ (per rad) at the model's rows.
Pressure = Callable[["Array", "Array"], "Array"]


@dataclass(frozen=True, eq=False)
class PlateScan:
    """A plate cam's scan model (``ScanModel``).

    Attributes
    ----------
    theta
        (R,) the rows' cam angles (rad), evenly spaced over the turn.
    flanks
        The functional surfaces, in the STL's frame.
    q_scale
        mm per unit of q at the trace point: 1, or the arm's length.
    q_unit
        "mm" (translating) or "rad" (oscillating).
    clearance
        The play the design gives the follower between the flanks (q's unit; 0 for one side).
    map_u
        (R,) the rows' cam angles (°).
    q
        (R,) the design's q at ``theta``.
    riders
        The follower on each flank, by the flank's name.
    pressure
        The pressure angle of a motion q(θ) at ``theta``.
    analysis
        The design's analysis, for the part's mesh.
    """

    theta: Array
    flanks: tuple[FlankGrid, ...]
    q_scale: float
    q_unit: str
    clearance: float
    map_u: Array
    q: Array
    riders: dict[str, Rider]
    pressure: Pressure
    analysis: Analysis
    map_u_label: str = CAM_ANGLE_LABEL

    def design(self) -> Array:
        """The design's q at ``theta`` (mm or rad)."""
        return self.q

    def run(self, flank: FlankGrid, points: Array) -> Array:
        """The follower (a groove's gauge roller) run over *points* ((R, C, 3) mm, *flank*'s
        grid moved as the scan says, NaN where unscanned): the bound of q at each row."""
        return self.riders[flank.name].run(points, self.theta)

    def pressure_angle(self, q: Array, dq: Array) -> Array:
        """The pressure angle (rad) of the motion *q* (q's unit) with q′ *dq* (per rad) at
        ``theta``."""
        return self.pressure(q, dq)

    def reference_mesh(self) -> tuple[Array, Index]:
        """The part as camfab builds it (mm, the STL's frame): (V, 3) vertices and (F, 3)
        faces of the solid the STL writer makes, read back as the STL file is."""
        return self._mesh

    @cached_property
    def _mesh(self) -> tuple[Array, Index]:
        from camfab.inspect.models.part_mesh import part_mesh

        return part_mesh(self.analysis)


def plate_thickness(analysis: Analysis) -> float:
    """The plate's thickness (mm); a design without one has no solid to hold a scan to."""
    design = analysis.design
    thickness = design.cam.thickness
    if thickness is None:
        raise InspectionError(design.source or design.name, "cam.thickness is not given: a "
                              "scan is held to the plate's solid, which needs it")
    return thickness


def motion_of(s: Array, ds: Array) -> Array:
    """(4, R) the motion (s, s′, 0, 0) the pressure angle needs of *s* and *ds* (its s″ and s‴
    enter no pressure angle)."""
    zero = np.zeros_like(s)
    return np.stack((s, ds, zero, zero))


def outward(cam: DiscCam, theta: Array, m: Array) -> Array:
    """(R, 2) the pitch curve's unit normals out of the plate at *theta* (rad), motion *m*."""
    return cam.sigma * perp(cam.pitch(theta, m).tangent)


def working(cam: DiscCam, theta: Array, m: Array) -> tuple[Array, Array]:
    """The working curve's points (R, 2) mm at *theta* (rad), motion *m*, and its unit normals
    out of the plate: the pitch curve's (a roller's centre lies along them), a flat face's."""
    if cam.follower.flat:
        lines = cam.face_lines(theta, m)
        return cam.working(theta, m, lines).xy, lines.normal
    return cam.working(theta, m).xy, outward(cam, theta, m)


def flank_grid(name: str, side: int, xy: Array, normal: Array, low: float,
               high: float) -> FlankGrid:
    """A flank of (R, 2) outline points *xy* (mm) and normals *normal* through z = *low* to
    *high* (mm): at least :data:`MIN_COLUMNS` columns at most :data:`ACROSS_STEP_MM` apart,
    ``across`` measured from *low*."""
    count = max(MIN_COLUMNS, math.ceil((high - low) / ACROSS_STEP_MM - 1e-9) + 1)
    z = np.linspace(low, high, count)
    rows = len(xy)
    points = np.empty((rows, count, 3))
    points[..., :2] = xy[:, None, :]
    points[..., 2] = z
    normals = np.zeros((rows, count, 3))
    normals[..., :2] = normal[:, None, :]
    return FlankGrid(name, side, points, normals, z - low)


def plate_scan(analysis: Analysis, theta: Array, sides: list[tuple[FlankGrid, Rider]],
               q: Array, pressure: Pressure, clearance: float = 0.0) -> PlateScan:
    """A plate cam's scan model of *sides* (each flank with its follower, the window fitted
    here), the design's *q* at the rows' angles *theta* (rad), its *pressure* angle, the
    *clearance* in q's unit."""
    fol = analysis.geometry.cam.follower
    scale = fol.arm_length if fol.oscillating else 1.0
    margin = WINDOW_MARGIN_MM / scale
    riders = {}
    for flank, rider in sides:
        own = q if rider.spacing is None else rider.spacing - q
        window = fit_window(rider, flank.points[:, 0], theta, own, margin)
        riders[flank.name] = replace(rider, window=window)
    return PlateScan(theta, tuple(flank for flank, _ in sides), scale,
                     "rad" if fol.oscillating else "mm", clearance, np.degrees(theta), q,
                     riders, pressure, analysis)


def scan_model(analysis: Analysis, step: float) -> PlateScan:
    """The scan model of a disc cam or a shaped cam (``disc``, ``circular-arc``,
    ``tangent``): its profile ("profile", side −1: it pushes the follower toward +q) through
    the plate's thickness, rows *step* rad of cam angle apart over the turn."""
    thickness = plate_thickness(analysis)
    cam, program = analysis.geometry.cam, analysis.program
    theta = cycle_angles(step)
    m = program.evaluate(theta)
    flank = flank_grid("profile", -1, *working(cam, theta, m), 0.0, thickness)

    def pressure(q: Array, dq: Array) -> Array:
        return cam.pressure_angle(theta, motion_of(q - cam.rest, dq))

    return plate_scan(analysis, theta, [(flank, Rider(cam, -1))], cam.rest + m[0], pressure)
