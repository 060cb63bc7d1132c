"""The report's figures of the cam at its speed, as inline SVG: the contact stress around the
cycle against its limit, the elastic follower train's lift, error and contact force against the
rigid model's, and the acceleration's harmonics beside the train's natural frequency.

The figures over the cam angle carry the page's cursor (:func:`camfab.export.figures.add_cursor`),
so they follow the animation. Stresses in MPa, forces in N, lengths in mm (an oscillating arm's
at its trace point), angles in degrees.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.export.figures import (
    BAD,
    FIGURE_WIDTH,
    FOLLOWER,
    LEGEND_FONT,
    PITCH,
    REFERENCE,
    WARN,
    add_cursor,
    angle_axis,
    panel_stack,
    segment_marks,
    side_margins,
    thin,
)

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.speed.model import AtSpeed


def stress_figure(analysis: Analysis) -> str | None:
    """The contact stress around the cycle (with ``limits.contact_stress`` and where it is
    exceeded) over the normal force at the contact, or None without a stress."""
    speed = analysis.at_speed
    if speed is None or speed.stress is None or speed.force_N is None:
        return None
    stress = speed.stress
    fig, (top, bottom) = panel_stack(2, "stress")
    theta, value = thin(np.degrees(stress.theta), stress.stress)
    top.plot(theta, value, color=PITCH, linewidth=1.0, label="contact stress")
    limit = analysis.design.limits.contact_stress
    if limit is not None:
        top.axhline(limit, color=BAD, linewidth=0.8, linestyle="--",
                    label=f"allowed {limit:.4g} MPa")
        if (value > limit).any():
            top.fill_between(theta, value, limit, where=value > limit, color=BAD, alpha=0.4,
                             label="over the limit")
    k = stress.index
    top.plot([math.degrees(float(stress.theta[k]))], [stress.max_MPa], ".", color=BAD,
             markersize=7, label=f"largest {stress.max_MPa:.4g} MPa")
    normal = _normal_force(speed)
    _, load = thin(stress.theta, normal)
    bottom.plot(theta, load, color=FOLLOWER, linewidth=1.0, label="normal force")
    top.set_ylabel("contact\nstress (MPa)", fontsize=LEGEND_FONT)
    bottom.set_ylabel("normal\nforce (N)", fontsize=LEGEND_FONT)
    return _finish(fig, [top, bottom], analysis)


def _normal_force(speed: AtSpeed) -> np.ndarray:
    """The normal force at the carrying side's contact (N; 0 where none carries)."""
    stress = speed.stress
    assert stress is not None and speed.force_N is not None
    out = np.zeros(stress.theta.size)
    for k, side in enumerate(stress.contact.sides):
        here = stress.side == k
        out[here] = np.abs(speed.force_N[here]) * side.normal[here]
    return out


def vibration_figure(analysis: Analysis) -> str | None:
    """The elastic follower train over the cycle: the lift as the cam gives it and as the mass
    follows it, their difference (the dynamic error, with each dwell's residual vibration), and
    the contact force against the rigid model's, or None without a stiffness."""
    speed = analysis.at_speed
    shaken = None if speed is None else speed.vibration
    if shaken is None:
        return None
    fig, (lift_ax, error_ax, force_ax) = panel_stack(3, "vibration")
    scale = 1000.0  # mm at the trace point
    s = analysis.program.evaluate(shaken.theta)[0] * shaken.trace_m * scale
    theta, kinematic, error, static, force, rigid = thin(
        np.degrees(shaken.theta), s, shaken.error_m * scale, shaken.static_m * scale,
        shaken.force_N, shaken.rigid_N)
    lift_ax.plot(theta, kinematic, color=REFERENCE, linewidth=1.0, label="the cam's lift")
    lift_ax.plot(theta, kinematic + error, color=PITCH, linewidth=1.0, label="the mass's")
    error_ax.plot(theta, static, color=REFERENCE, linewidth=0.8, linestyle="--",
                  label="the train's compression")
    error_ax.plot(theta, error, color=PITCH, linewidth=1.0, label="x − s")
    error_ax.axhline(0.0, color=REFERENCE, linewidth=0.5)
    for dwell in shaken.dwells:
        error_ax.axvspan(dwell.start_deg, dwell.end_deg, color=WARN, alpha=0.15,
                         label="dwells" if dwell is shaken.dwells[0] else None)
    force_ax.plot(theta, rigid, color=REFERENCE, linewidth=0.8, label="rigid")
    force_ax.plot(theta, force, color=FOLLOWER, linewidth=1.0, label="elastic")
    force_ax.axhline(0.0, color=BAD, linewidth=0.8, linestyle="--")
    if shaken.one_sided and (force < 0).any():
        force_ax.fill_between(theta, force, 0, where=force < 0, color=BAD, alpha=0.4,
                              label="contact lost")
    where = "at the trace point" if analysis.design.follower.oscillating else ""
    lift_ax.set_ylabel(f"lift (mm)\n{where}".strip(), fontsize=LEGEND_FONT)
    error_ax.set_ylabel("dynamic\nerror (mm)", fontsize=LEGEND_FONT)
    force_ax.set_ylabel("contact\nforce (N)", fontsize=LEGEND_FONT)
    return _finish(fig, [lift_ax, error_ax, force_ax], analysis)


#: The band's figure is scaled to the vibration within this share of the design speed.
BAND_SHOWN = 0.1


def polydyne_figure(analysis: Analysis) -> str | None:
    """A polydyne cam's two motions over the cycle: the motion asked of the follower's mass and
    the cam's lift that gives it at the design speed, and their difference; None for another
    cam."""
    speed = analysis.at_speed
    if speed is None or speed.band is None or speed.vibration is None:
        return None
    shaken = speed.vibration
    fig, (lift_ax, apart_ax) = panel_stack(2, "polydyne")
    scale = shaken.trace_m * 1000.0  # mm at the trace point
    cam = analysis.program.evaluate(shaken.theta)[0] * scale
    output = analysis.design.output_program.evaluate(shaken.theta)[0] * scale
    theta, cam, output = thin(np.degrees(shaken.theta), cam, output)
    lift_ax.plot(theta, output, color=REFERENCE, linewidth=1.0, label="asked of the mass, x")
    lift_ax.plot(theta, cam, color=PITCH, linewidth=1.0, label="the cam's lift, s")
    apart_ax.plot(theta, cam - output, color=PITCH, linewidth=1.0, label="s − x")
    apart_ax.axhline(0.0, color=REFERENCE, linewidth=0.5)
    where = "at the trace point" if analysis.design.follower.oscillating else ""
    lift_ax.set_ylabel(f"lift (mm)\n{where}".strip(), fontsize=LEGEND_FONT)
    apart_ax.set_ylabel("s − x (mm)", fontsize=LEGEND_FONT)
    return _finish(fig, [lift_ax, apart_ax], analysis)


def band_figure(analysis: Analysis) -> str | None:
    """A polydyne cam's largest dwell vibration against speed beside its motion list cut
    directly, the design speed and the band over which the polydyne cam rings less marked;
    None for another cam."""
    speed = analysis.at_speed
    band = None if speed is None else speed.band
    if band is None:
        return None
    fig, ax = _one_panel("band")
    ax.axvspan(band.low_rpm, band.high_rpm, color=WARN, alpha=0.15,
               label="the polydyne cam rings less")
    ax.plot(band.speeds_rpm, band.direct_m * 1000.0, color=REFERENCE, linewidth=1.0,
            label="the motion cut directly")
    ax.plot(band.speeds_rpm, band.polydyne_m * 1000.0, color=PITCH, linewidth=1.2,
            label="the polydyne cam")
    design = analysis.design.cam.speed_rpm
    assert design is not None
    ax.axvline(design, color=BAD, linewidth=0.8, linestyle="--",
               label=f"cut for {design:.6g} rpm")
    ax.set_xlim(float(band.speeds_rpm[0]), float(band.speeds_rpm[-1]))
    # the scale of the speeds about the design speed: far from it both cams ring far more
    near = np.abs(band.speeds_rpm / design - 1.0) <= BAND_SHOWN
    top = float(np.nanmax(np.concatenate([band.direct_m[near], band.polydyne_m[near]])))
    if top > 0.0:
        ax.set_ylim(0.0, 1.25 * 1000.0 * top)
    ax.set_ylabel("residual\nvibration (mm)", fontsize=LEGEND_FONT)
    ax.set_xlabel("cam speed (rpm)")
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


def spectrum_figure(analysis: Analysis) -> str | None:
    """The follower's acceleration at the design speed as harmonics of the cam's turning
    frequency, with the follower train's natural frequency marked, or None without a
    stiffness."""
    speed = analysis.at_speed
    shaken = None if speed is None else speed.vibration
    if shaken is None:
        return None
    fig, ax = _one_panel("spectrum")
    n, amplitude = shaken.harmonics, shaken.amplitudes
    x = np.repeat(n.astype(float), 3)
    y = np.column_stack((np.zeros(n.size), amplitude, np.full(n.size, np.nan))).ravel()
    ax.plot(x, y, color=PITCH, linewidth=1.6, label="harmonic amplitude")
    ratio = shaken.frequency_ratio
    top = float(amplitude.max()) * 1.1 or 1.0
    ax.plot([ratio, ratio], [0.0, top], color=BAD, linewidth=1.0, linestyle="--",
            label=f"f_n {shaken.natural_Hz:.4g} Hz ({ratio:.3g}×)")
    ax.set_xlim(0.0, float(n[-1]) + 1.0)
    ax.set_ylim(0.0, top)
    where = "\nat the trace point" if analysis.design.follower.oscillating else ""
    ax.set_ylabel(f"acceleration\n(m/s²){where}", fontsize=LEGEND_FONT)
    ax.set_xlabel(f"harmonic of the cam's turning ({shaken.speed_rpm / 60.0:.4g} Hz)")
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


def _one_panel(name: str) -> tuple[Figure, Axes]:
    """A figure of one panel, 2.6 in high, named *name*, its margins as the others'."""
    height = 2.6
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, height, name, left=left, right=right,
                 top=1 - 0.3 / height, bottom=0.55 / height)
    [ax] = fig.subplots()
    return fig, ax


def _finish(fig: Figure, axes: list[Axes], analysis: Analysis) -> str:
    """Segment marks, legends, the cam-angle axis and the page's cursor on *axes*."""
    for ax in axes:
        segment_marks(ax, analysis, labels=ax is axes[0])
        ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    add_cursor(fig, axes)
    return fig.svg()
