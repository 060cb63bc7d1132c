"""The report's drawings and diagrams as inline SVG, drawn by :mod:`camfab.export.chart`.

Every figure is a function of the analysis returning SVG text (no XML header), ready to paste
into the HTML page. Lengths are millimetres and angles degrees.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camfab.export.chart import Axes, Figure
from camfab.motion.program import cycle_angles

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.disc_geometry import DiscGeometry
    from camfab.geometry.linear import LinearGeometry

#: Cam-angle step of the diagrams: 0.5° draws every feature a reader can see.
DIAGRAM_STEP = math.radians(0.5)

#: Colours: cut outline, pitch curve, references, violations, follower.
CUT, PITCH, REFERENCE, BAD, FOLLOWER, WARN = ("#c0392b", "#2c5aa0", "#999999", "#e67e22",
                                              "#2d7d46", "#d4ac0d")
#: A groove cam's pocket walls, and its wall-change marks.
POCKET, CHANGE = "#8e44ad", "#0e6e8c"


def _thin(*arrays: np.ndarray) -> list[np.ndarray]:
    """Every n-th value of dense arrays (0.05° apart) so lines are drawn every 0.5°: finer than a
    reader can see, and ten times fewer points to write."""
    return [a[..., ::10] for a in arrays]


def angle_axis(*axes: Axes) -> None:
    """Cam angle from 0 to 360° with a tick every 60° on the bottom panel (the segment lines
    run through all), and at most four intervals on the values."""
    for ax in axes:
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 60) if ax is axes[-1] else [])
        ax.set_bins(y=4)


def _segment_marks(ax: Axes, analysis: Analysis, labels: bool) -> None:
    """Segment boundaries as vertical lines, with the laws written above the top plot."""
    for seg in analysis.program.segments:
        ax.axvline(math.degrees(seg.start), color=REFERENCE, linewidth=0.6, linestyle=":")
        if labels:
            name = seg.kind if seg.kind == "dwell" else f"{seg.kind}: {seg.law_name}"
            ax.text(math.degrees(seg.start + seg.span / 2), 1.02, name, ha="center",
                    va="bottom", fontsize=7, y_in_axes=True)


def panel_stack(rows: int) -> tuple[Figure, list[Axes]]:
    """The diagrams' figure: *rows* panels 1.45 in high, one under the other on a shared
    cam-angle axis, 9 in wide."""
    height = 1.45 * rows + 0.6
    fig = Figure(9.0, height, "diagrams", left=0.11, top=1 - 0.3 / height, bottom=0.45 / height)
    return fig, fig.subplots(rows, sharex=True)


def diagrams(analysis: Analysis) -> str:
    """One figure of the cycle, panel under panel on a shared cam-angle axis: s, v, a and j (per
    radian of cam angle without a speed), the pressure angle against its limit, the radii of
    curvature against the follower's, and with dynamics the contact force and camshaft torque.
    """
    rows = 8 if has_dynamics(analysis) else 6
    fig, axes = panel_stack(rows)
    _motion_panels(analysis, axes[:4])
    _pressure_panels(analysis, axes[4], axes[5])
    if rows == 8:
        _dynamics_panels(analysis, axes[6], axes[7])
    for ax in axes:
        _segment_marks(ax, analysis, labels=ax is axes[0])
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    return fig.svg()


def has_dynamics(analysis: Analysis) -> bool:
    dyn = analysis.dynamics
    return dyn is not None and dyn.force_N is not None and dyn.torque_N_m is not None


def _motion_panels(analysis: Analysis, axes: list[Axes]) -> None:
    theta = cycle_angles(DIAGRAM_STEP)
    units = analysis.units
    omega = analysis.design.cam.omega
    motion = analysis.program.evaluate(theta)
    names = ("displacement", "velocity", "acceleration", "jerk")
    degrees = np.degrees(theta)
    for order, ax in enumerate(axes):
        values = motion[order]
        if order == 0:
            values = np.degrees(values) if units.oscillating else values
            unit = "deg" if units.oscillating else "mm"
        elif omega is not None:
            values = units.to_si(order, values, omega)
            unit = units.unit(order, True)
        else:
            unit = units.unit(order, False)
        ax.plot(degrees, values, color=PITCH, linewidth=1.0)
        ax.set_ylabel(f"{names[order]}\n({unit})", fontsize=8)
        ax.axhline(0.0, color=REFERENCE, linewidth=0.5)


def _pressure_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    limit = math.degrees(analysis.design.pressure_angle_limit)
    geom, dense = analysis.geometry, analysis.drum
    if analysis.linear is not None:
        from camfab.export.linear_figures import linear_pressure_panels

        linear_pressure_panels(analysis, top, bottom)
    elif geom is not None:
        theta, phi, pitch, profile = _thin(np.degrees(geom.dense.theta),
                                           np.degrees(geom.dense.pressure_angle),
                                           geom.dense.pitch.radius, geom.dense.working.radius)
        top.plot(theta, phi, color=PITCH, linewidth=1.0, label="pressure angle φ")
        bottom.plot(theta, clip_radii(pitch), color=PITCH, linewidth=1.0, label="pitch curve ρ")
        bottom.plot(theta, clip_radii(profile), color=CUT, linewidth=1.0, label="profile ρ")
        radius = geom.cam.follower.radius
        if radius > 0:
            bottom.axhline(radius, color=BAD, linewidth=0.8, linestyle="--",
                           label=f"follower radius {radius:.4g} mm")
        if analysis.groove is not None:  # the outer wall folds where a concave ρ_p > −R
            bottom.axhline(-radius, color=BAD, linewidth=0.8, linestyle="--")
    elif dense is not None:
        theta, phi, rho = _thin(np.degrees(dense.theta), np.degrees(dense.pressure_angle),
                                dense.developed_radius)
        for row, name in ((0, "floor"), (-1, "surface")):
            top.plot(theta, phi[row], linewidth=1.0,
                     label=f"φ at the {name} (r = {dense.radii[row]:.4g} mm)")
            bottom.plot(theta, clip_radii(rho[row]), linewidth=1.0,
                        label=f"developed ρ at the {name}")
        bottom.axhline(dense.drum.roller, color=BAD, linewidth=0.8, linestyle="--",
                       label=f"roller {dense.drum.roller:.4g} mm")
        bottom.axhline(-dense.drum.roller, color=BAD, linewidth=0.8, linestyle="--")
    for sign in (1, -1):
        top.axhline(sign * limit, color=BAD, linewidth=0.8, linestyle="--")
    top.set_ylabel("pressure angle\n(deg)", fontsize=8)
    bottom.set_ylabel("radius of\ncurvature (mm)", fontsize=8)
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="upper right")


def clip_radii(radius: np.ndarray) -> np.ndarray:
    """Radii for plotting: straight stretches (±∞) and the huge values next to them hidden."""
    finite = np.abs(radius[np.isfinite(radius)])
    cap = 4.0 * float(np.median(finite)) if finite.size else 1.0
    return np.where(np.abs(radius) <= cap, radius, np.nan)


def _dynamics_panels(analysis: Analysis, top: Axes, bottom: Axes) -> None:
    dyn = analysis.dynamics
    assert dyn is not None and dyn.force_N is not None and dyn.torque_N_m is not None
    theta, force, static, torque = _thin(np.degrees(dyn.theta), dyn.force_N, dyn.static_N,
                                         dyn.torque_N_m)
    top.plot(theta, force, color=PITCH, linewidth=1.0, label="contact force")
    top.plot(theta, static, color=REFERENCE, linewidth=0.8, label="spring and loads")
    top.axhline(0.0, color=BAD, linewidth=0.8, linestyle="--")
    if (force < 0).any():
        top.fill_between(theta, force, 0, where=force < 0, color=BAD, alpha=0.4,
                         label="contact lost")
    bottom.plot(theta, torque, color=FOLLOWER, linewidth=1.0, label="camshaft torque")
    top.set_ylabel("contact\nforce (N)", fontsize=8)
    bottom.set_ylabel("torque (N·m)", fontsize=8)
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="upper right")


def cam_drawing(analysis: Analysis) -> str | None:
    """The cam at θ = 0 with its follower, or a drum's groove developed at its surface."""
    if analysis.geometry is not None:
        return _disc_drawing(analysis)
    if analysis.drum is not None:
        return _drum_drawing(analysis)
    if analysis.linear is not None:
        return _linear_drawing(analysis)
    return None


def _linear_drawing(analysis: Analysis) -> str:
    """A linear cam's plate at travel 0 with its follower (camfab.export.linear_figures)."""
    from camfab.export.linear_figures import linear_drawing

    return linear_drawing(analysis)


def _disc_drawing(analysis: Analysis) -> str:
    geom = analysis.geometry
    assert geom is not None
    fol = geom.cam.follower
    fig = Figure(6.4, 6.4, "drawing", left=0.12, bottom=0.08)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    if analysis.groove is not None:
        _draw_groove(ax, analysis)
    else:
        outline = geom.outline_points()
        ring = np.vstack((outline, outline[:1]))
        ax.fill(ring[:, 0], ring[:, 1], color="#f4d6d2", zorder=0)
        ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.2, label="cam profile")
    pitch = np.vstack((geom.pitch.xy, geom.pitch.xy[:1]))
    if fol.radius > 0:
        ax.plot(pitch[:, 0], pitch[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
                label="pitch curve")
    angle = np.linspace(0, 2 * math.pi, 361)
    for radius, style, name in ((geom.cam.base_radius, ":", "base circle"),
                                (geom.cam.prime_radius, "-.", "prime circle")):
        ax.plot(radius * np.cos(angle), radius * np.sin(angle), color=REFERENCE,
                linewidth=0.7, linestyle=style, label=name)
    # where the checks fail, on the profile
    mark_failures(ax, analysis, geom)
    _draw_follower(ax, analysis)
    _draw_partner(ax, analysis)
    ax.plot([0], [0], "+", color="black", markersize=10)
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title(f"{analysis.design.name} at θ = 0 ({analysis.design.cam.rotation})",
                 fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return fig.svg()


def _draw_groove(ax: Axes, analysis: Analysis) -> None:
    """A groove cam's plate: its outer circle, the groove shaded between its walls, where a
    wall folds, and a tick across the groove wherever contact passes to the other wall."""
    from camfab.geometry.curves import perp
    from camfab.geometry.groove import WALL_NAMES

    geom, walls = analysis.geometry, analysis.groove
    assert geom is not None and walls is not None
    angle = np.linspace(0, 2 * math.pi, 361)
    rim = walls.outer_radius * np.stack((np.cos(angle), np.sin(angle)), axis=-1)
    ax.fill(rim[:, 0], rim[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(rim[:, 0], rim[:, 1], color=CUT, linewidth=1.2, label="plate outline (cut)")
    outer, inner = (np.vstack((p, p[:1])) for p in (walls.outer_points, walls.inner_points))
    ax.fill(outer[:, 0], outer[:, 1], color="#d9d9d9", zorder=0)
    ax.fill(inner[:, 0], inner[:, 1], color="#f4d6d2", zorder=0)
    ax.plot(outer[:, 0], outer[:, 1], color=POCKET, linewidth=1.0,
            label=f"groove walls ({walls.depth:.4g} mm deep)")
    ax.plot(inner[:, 0], inner[:, 1], color=POCKET, linewidth=1.0)
    if walls.outer_folds.any():
        xy = walls.outer_dense.xy[walls.outer_folds]
        ax.plot(xy[:, 0], xy[:, 1], ".", color=BAD, markersize=2, label="outer wall folds")
    changes = walls.contact.changes
    if not changes.size:
        return
    pitch = geom.cam.pitch(changes, analysis.program.evaluate(changes))
    across = 1.4 * walls.radius * perp(pitch.tangent)
    for k, (centre, step) in enumerate(zip(pitch.xy, across, strict=True)):
        ends = np.array([centre - step, centre + step])
        ax.plot(ends[:, 0], ends[:, 1], color=CHANGE, linewidth=1.6,
                label="contact changes walls" if k == 0 else None)
        label = (f"{walls.contact.changes_deg[k]:.4g}°: onto the "
                 f"{WALL_NAMES[int(walls.contact.onto[k])]} wall")
        tip = centre - 2.0 * step * np.sign(float(np.dot(step, centre)) or 1.0)  # toward the centre
        ax.text(float(tip[0]), float(tip[1]), label, fontsize=7, color=CHANGE)


def mark_failures(ax: Axes, analysis: Analysis, geom: DiscGeometry | LinearGeometry) -> None:
    """Dots on the profile of *geom* (a disc or linear cam's geometry) where the pressure angle
    is over the limit and where the envelope is undercut."""
    dense = geom.dense
    steep = np.abs(dense.pressure_angle) > analysis.design.pressure_angle_limit
    if steep.any():
        xy = dense.working.xy[steep]
        ax.plot(xy[:, 0], xy[:, 1], ".", color=WARN, markersize=2,
                label="pressure angle over the limit")
    if geom.undercut:
        cut = geom.working.xy[geom.cut] if geom.cut.any() else dense.working.xy[geom.folds]
        ax.plot(cut[:, 0], cut[:, 1], ".", color=BAD, markersize=2, label="undercut")


def _draw_follower(ax: Axes, analysis: Analysis) -> None:
    """The follower at θ = 0 (the cam frame and the fixed frame coincide there)."""
    geom = analysis.geometry
    assert geom is not None
    cam = geom.cam
    fol = cam.follower
    m = analysis.program.evaluate(np.zeros(1))
    trace = cam.trace(m)[0][0]
    angle = np.linspace(0, 2 * math.pi, 181)
    if fol.flat:
        lines = cam.face_lines(np.zeros(1), m)
        normal = lines.normal[0]
        foot = normal * lines.h[0]
        along = np.array([-normal[1], normal[0]])
        half = 0.6 * geom.cam.base_radius
        ends = np.array([foot - half * along, foot + half * along])
        ax.plot(ends[:, 0], ends[:, 1], color=FOLLOWER, linewidth=2.0, label="follower face")
    elif fol.radius > 0:
        ax.plot(trace[0] + fol.radius * np.cos(angle), trace[1] + fol.radius * np.sin(angle),
                color=FOLLOWER, linewidth=1.5, label="follower")
    if fol.oscillating:
        pivot = cam.pivot
        ax.plot([pivot[0], trace[0]], [pivot[1], trace[1]], color=FOLLOWER, linewidth=1.0)
        ax.plot([pivot[0]], [pivot[1]], "o", color=FOLLOWER, markersize=4)
    elif not fol.flat:
        ax.plot([trace[0], trace[0]], [trace[1], trace[1] + 1.5 * geom.cam.base_radius * 0.5],
                color=FOLLOWER, linewidth=1.5)
    ax.plot([trace[0]], [trace[1]], ".", color=FOLLOWER)


def _draw_partner(ax: Axes, analysis: Analysis) -> None:
    """What holds the follower on the other side, at θ = 0: a conjugate pair's cam b (turned
    into the frame it is made in) with its roller, or a yoke's other face or roller."""
    partner, geom = analysis.partner, analysis.geometry
    if partner is None or geom is None:
        return
    cam = geom.cam
    fol = cam.follower
    trace = cam.trace(analysis.program.evaluate(np.zeros(1)))[0][0]
    other = trace - np.array([0.0, partner.spacing])
    if partner.geometry is not None and partner.program is not None:
        from camfab.geometry.conjugate import half_turned, mirrored

        cam_b = partner.geometry.cam
        other = cam_b.trace(partner.program.evaluate(np.zeros(1)))[0][0]
        move = mirrored if partner.mirror else half_turned
        other = move(other)
        ring = move(partner.geometry.outline_points())
        ring = np.vstack((ring, ring[:1]))
        ax.plot(ring[:, 0], ring[:, 1], color=CUT, linewidth=1.0, linestyle="--",
                label="cam b (behind cam a)")
    if fol.flat:
        half = 0.6 * cam.base_radius
        ax.plot([other[0] - half, other[0] + half], [other[1], other[1]], color=FOLLOWER,
                linewidth=2.0, label="the yoke's other face")
        return
    angle = np.linspace(0, 2 * math.pi, 181)
    ax.plot(other[0] + fol.radius * np.cos(angle), other[1] + fol.radius * np.sin(angle),
            color=FOLLOWER, linewidth=1.5, linestyle="--", label="second roller")
    joint = cam.pivot if fol.oscillating else trace
    ax.plot([other[0], joint[0]], [other[1], joint[1]], color=FOLLOWER, linewidth=0.8,
            linestyle=":")


def _drum_drawing(analysis: Analysis) -> str:
    from camfab.geometry.drum_mesh import development

    dense = analysis.drum
    assert dense is not None
    d = dense.drum
    dev = development(d, analysis.program, 0.01)
    fig = Figure(9.0, 3.6, "drawing", bottom=0.14)
    [ax] = fig.subplots()
    ax.set_aspect("equal")
    ax.plot([0, dev.width, dev.width, 0, 0], [0, 0, dev.height, dev.height, 0],
            color=REFERENCE, linewidth=0.7)
    ax.plot(dev.lower[:, 0], dev.lower[:, 1], color=CUT, linewidth=1.2, label="groove walls")
    ax.plot(dev.upper[:, 0], dev.upper[:, 1], color=CUT, linewidth=1.2)
    ax.plot(dev.centre[:, 0], dev.centre[:, 1], color=PITCH, linewidth=0.8, linestyle="--",
            label="roller axis")
    ax.set_title(f"{analysis.design.name}: groove developed at the surface (r = {d.radius:.4g}"
                 " mm), seen from outside", fontsize=9)
    ax.set_xlabel("around the drum (mm)")
    ax.set_ylabel("z (mm)")
    ax.legend(fontsize=7, loc="upper right")
    return fig.svg()
