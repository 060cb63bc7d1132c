"""The scan inspection report's figures as inline SVG (:mod:`camfab.export.chart`): each flank's
deviation map, its colour scale with the tolerance marked, and the motion through the scanned
flanks (lift, lift error per flank against the tolerance, play, pressure angle)."""

from __future__ import annotations

import math

import numpy as np

from camfab.export.chart import Figure
from camfab.export.figures import (
    BAD,
    CUT,
    FIGURE_WIDTH,
    PITCH,
    REFERENCE,
    WARN,
    angle_axis,
    panel_stack,
    side_margins,
)
from camfab.export.png import png_bytes
from camfab.inspect.scan_record import ScanInspection

#: Most columns of a map's raster: rows of the flank grid are averaged in groups to keep to it.
MAP_COLUMNS = 720

#: The colour scale spans ±this many tolerances (beyond: the end colours).
SCALE_TOLERANCES = 2.0

#: Colours: material left on (+), under (−), none (not scanned).
OVER_RGB = np.array([192, 57, 43])
UNDER_RGB = np.array([41, 98, 182])
MIDDLE_RGB = np.array([255, 255, 255])
MISSING_RGB = np.array([205, 205, 205])

#: Colours of the flanks' curves, in order.
FLANK_COLOURS = (CUT, WARN, PITCH, BAD)


def colours(deviation: np.ndarray, span: float) -> np.ndarray:
    """(…, 3) uint8 colours of *deviation* (mm) on a scale of ±*span* mm: white at 0, red for
    material left on, blue for material under, grey where NaN."""
    t = np.clip(np.nan_to_num(deviation) / span, -1.0, 1.0)[..., None]
    rgb = np.where(t > 0, MIDDLE_RGB + t * (OVER_RGB - MIDDLE_RGB),
                   MIDDLE_RGB + (-t) * (UNDER_RGB - MIDDLE_RGB))
    rgb = np.where(np.isnan(deviation)[..., None], MISSING_RGB, rgb)
    return np.round(rgb).astype(np.uint8)


def _columns(values: np.ndarray) -> np.ndarray:
    """(R, C) values averaged over groups of rows to at most :data:`MAP_COLUMNS` rows."""
    rows = values.shape[0]
    group = max(1, math.ceil(rows / MAP_COLUMNS))
    pad = (-rows) % group
    padded = np.concatenate((values, np.full((pad, values.shape[1]), np.nan)))
    blocks = padded.reshape(-1, group, values.shape[1])
    with np.errstate(invalid="ignore"):
        counts = np.sum(np.isfinite(blocks), axis=1)
        sums = np.nansum(blocks, axis=1)
        return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def deviation_maps(ins: ScanInspection) -> str:
    """Each flank's fitted deviation over the flank unrolled (across: the model's u per cam
    angle; up: the position across the flank), then the colour scale."""
    span = SCALE_TOLERANCES * ins.setup.tolerance
    model = ins.model
    count = len(ins.flanks)
    height = 1.9 * count + 0.7
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, height, "maps", left=left, right=right, top=1 - 0.3 / height,
                 bottom=0.5 / height, hspace=0.3)
    axes = fig.subplots(count, sharex=True)
    u = model.map_u
    for ax, flank, grid in zip(axes, ins.flanks, model.flanks, strict=True):
        values = _columns(flank.fitted)
        pixels = colours(values.T[::-1], span)
        ax.image(png_bytes(pixels), (float(u[0]), float(u[-1])),
                 (float(grid.across[0]), float(grid.across[-1])))
        ax.set_ylabel(f"{flank.name}\nacross (mm)", fontsize=8)
        ax.set_xlim(float(u[0]), float(u[-1]))
        ax.set_bins(x=8, y=3)
    axes[-1].set_xlabel(model.map_u_label)
    return fig.svg() + colour_scale(ins.setup.tolerance)


def colour_scale(tolerance: float) -> str:
    """The maps' colour scale from −2 to +2 tolerances, the tolerance marked."""
    span = SCALE_TOLERANCES * tolerance
    height = 1.0
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, height, "scale", left=left, right=right, top=0.8, bottom=0.45)
    [ax] = fig.subplots(1)
    values = np.linspace(-span, span, 256)
    ax.image(png_bytes(colours(values[None, :], span)), (-span, span), (0.0, 1.0))
    for sign in (-1, 1):
        ax.axvline(sign * tolerance, color="#222222", linewidth=1.0, linestyle="--")
    ax.set_xlim(-span, span)
    ax.set_ylim(0.0, 1.0)
    ax.set_bins(x=8)
    ax.set_yticks([])
    ax.set_xlabel("deviation (mm): red, material left on; blue, under; grey, not scanned; "
                  "dashed, ± tolerance", fontsize=8)
    return fig.svg()


def scan_diagrams(ins: ScanInspection) -> str:
    """Panel under panel on a shared cam-angle axis: the lift as made and the design's, each
    flank's lift error against the tolerance, the play between two flanks, and the pressure
    angle as made and the design's against its limit."""
    two = ins.backlash_mm is not None
    fig, axes = panel_stack(4 if two else 3, name="scandiagrams")
    degrees = np.degrees(ins.theta)
    swing = ins.model.q_unit == "rad"
    scale = math.degrees(1.0) if swing else 1.0
    ax = axes[0]
    ax.plot(degrees, ins.lift_q * scale, color=CUT, linewidth=1.0, label="as made")
    ax.plot(degrees, ins.design_q * scale, color=PITCH, linewidth=0.8, linestyle="--",
            label="design")
    ax.set_ylabel(f"{'swing' if swing else 'lift'}\n({'deg' if swing else 'mm'})", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    ax = axes[1]
    tolerance = ins.setup.tolerance
    for colour, flank in zip(FLANK_COLOURS, ins.flanks, strict=False):
        ax.plot(degrees, flank.error_mm, color=colour, linewidth=0.9, label=flank.name)
    for sign in (-1, 1):
        ax.axhline(sign * tolerance, color=BAD, linewidth=0.8, linestyle="--")
    ax.axhline(0.0, color=REFERENCE, linewidth=0.5)
    ax.set_ylabel("lift error\n(mm)", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    if two:
        assert ins.backlash_mm is not None
        ax = axes[2]
        ax.plot(degrees, ins.backlash_mm, color=CUT, linewidth=1.0, label="play as made")
        ax.axhline(ins.model.clearance * ins.model.q_scale, color=PITCH, linewidth=0.8,
                   linestyle="--")
        ax.axhline(0.0, color=BAD, linewidth=0.8)
        ax.set_ylabel("play\n(mm)", fontsize=8)
    ax = axes[-1]
    limit = math.degrees(ins.setup.pressure_angle_limit)
    ax.plot(degrees, np.degrees(ins.pressure_angle), color=CUT, linewidth=1.0, label="as made")
    ax.plot(degrees, np.degrees(ins.design_pressure_angle), color=PITCH, linewidth=0.8,
            linestyle="--", label="design")
    for sign in (1, -1):
        ax.axhline(sign * limit, color=BAD, linewidth=0.8, linestyle="--")
    ax.set_ylabel("pressure angle\n(deg)", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    return fig.svg()
