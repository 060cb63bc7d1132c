"""The tuning's comparison report (``NAME-tuning.html``): the objective before and after, the
values changed, the laws tried on each segment, every limit's margin before and after, and two
figures drawn by the report's chart code (:mod:`camfab.export.chart`): the motion before and
after (s, s′, s″, s‴ per radian of cam angle over the cycle), and the objective against the
cam's speed over the band, before and after.

The page holds no time or date: the same design and options give the same bytes.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.tune.plan import Plan
    from camfab.tune.search import Search

#: Speeds of the objective's curve over the band: the program's objectives (cheap) ...
CURVE_SPEEDS = 61
#: ... and those that need an analysis at each speed.
ANALYSED_SPEEDS = 9
#: The curve's band around a single speed tuned at: ± this share.
AROUND = 0.10
#: The motion's figure's cam-angle step (rad): every feature a reader can see.
MOTION_STEP = math.radians(0.5)


def render_report(tuning: Plan, search: Search, stopped: bool) -> bytes:
    """The report's bytes (see the module)."""
    import jinja2

    from camfab.pipeline import design_from_mapping
    from camfab.tune.plan import changed
    from camfab.tune.summary import (
        margin_rows,
        number,
        objective_line,
        shown,
        trial_verdict,
        why_none,
    )

    best = search.best
    after = None if best is None else design_from_mapping(best.data, tuning.evaluator.file,
                                                           tuning.evaluator.folder)
    families = tuning.evaluator.families
    tried = [(f"motion[{families[t.family].index}]", t.option,
              number(t.trial.objective, tuning.objective.unit), trial_verdict(t.trial, best))
             for t in search.tried]
    before_margins = search.before.margins if search.before is not None else []
    env = jinja2.Environment(loader=jinja2.PackageLoader("camfab", "templates"),
                             autoescape=True, trim_blocks=True, lstrip_blocks=True)
    markup = jinja2.utils.markupsafe.Markup
    text = env.get_template("tune.html.j2").render(
        title=f"{tuning.options.design.stem} — tuned",
        design=str(tuning.options.design),
        tuned=tuning.tuned_path.name if best is not None else None,
        state="OK" if best is not None else "FAIL",
        stopped=stopped,
        objective=objective_line(tuning, search),
        why=None if best is not None else why_none(search),
        changes=[] if best is None else [(p, shown(o), shown(n))
                                         for p, o, n in changed(tuning, best.written)],
        tuned_families=[(f.where, f.label) for f in families],
        untuned=[(f"motion[{u.index}]", u.why) for u in tuning.untuned],
        tried=tried,
        margins=margin_rows(before_margins, best.margins if best is not None else None),
        global_note=search.convex_note if search.global_optimum else None,
        convex_note=None if search.global_optimum else search.convex_note,
        starts=tuning.options.starts,
        measured=search.evaluator.measured,
        analysed=search.evaluator.analysed,
        motion=markup(motion_figure(tuning.design, after)),
        # a stopped search writes at once: no analyses for the curve of the stress or torque
        speed=markup("" if stopped and tuning.objective.needs_analysis else
                     speed_figure(tuning, after, None if best is None else best.data) or ""),
    )
    return text.encode("utf-8")


def motion_figure(before: Design, after: Design | None) -> str:
    """s, s′, s″, s‴ (per radian of cam angle) over the cycle, before and after."""
    from camfab.export.figures import LEGEND_FONT, PITCH, REFERENCE, angle_axis, panel_stack

    fig, axes = panel_stack(4, "tunedmotion")
    lift = "rad" if before.follower.oscillating else "mm"
    names = (f"s ({lift})", f"s′ ({lift}/rad)", f"s″ ({lift}/rad²)", f"s‴ ({lift}/rad³)")
    for design, color, style, label in ((before, REFERENCE, "--", "before"),
                                        (after, PITCH, "-", "after")):
        if design is None:
            continue
        _, theta, motion = design.program.segment_grid(MOTION_STEP)
        for k, ax in enumerate(axes):
            ax.plot(np.degrees(theta), motion[k], color=color, linewidth=1.0, linestyle=style,
                    label=label)
    for ax, name in zip(axes, names, strict=True):
        ax.set_ylabel(name, fontsize=LEGEND_FONT)
        ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    for seg in before.program.segments[1:]:
        for ax in axes:
            ax.axvline(math.degrees(seg.start), color=REFERENCE, linewidth=0.6, linestyle=":")
    axes[-1].set_xlabel("cam angle θ (deg)")
    angle_axis(*axes)
    return fig.svg()


def curve_speeds(band: Array, count: int) -> Array:
    """*count* speeds (rpm) over the *band* (± :data:`AROUND` round a single speed)."""
    low, high = float(band[0]), float(band[-1])
    if high <= low:
        low, high = low * (1 - AROUND), low * (1 + AROUND)
    return np.linspace(low, high, count)


def speed_figure(tuning: Plan, after: Design | None,
                 after_data: dict[str, Any] | None) -> str | None:
    """The objective against the cam's speed over the band, before and after (None without a
    speed); *after_data* is the tuned design's data."""
    from camfab.export.chart import Figure
    from camfab.export.figures import BAD, FIGURE_WIDTH, LEGEND_FONT, PITCH, REFERENCE, side_margins

    band = tuning.band
    if band.size == 0:
        return None
    objective = tuning.objective
    analysed = objective.needs_analysis
    speeds = curve_speeds(band, ANALYSED_SPEEDS if analysed else CURVE_SPEEDS)
    height = 2.6
    left, right = side_margins()
    fig = Figure(FIGURE_WIDTH, height, "tunedspeed", left=left, right=right,
                 top=1 - 0.3 / height, bottom=0.55 / height)
    [ax] = fig.subplots()
    unit = objective.unit
    for design, data, color, style, label in (
            (tuning.design, tuning.doc.data, REFERENCE, "--", "before"),
            (after, after_data, PITCH, "-", "after")):
        if design is None or data is None:
            continue
        values, unit = _against_speed(tuning, design, data, speeds)
        ax.plot(speeds, values, color=color, linewidth=1.2, linestyle=style, label=label)
    if band.size > 1 and band[-1] > band[0]:
        ax.axvspan(float(band[0]), float(band[-1]), color=BAD, alpha=0.08,
                   label="the band tuned")
    else:
        ax.axvline(float(band[0]), color=BAD, linewidth=0.8, linestyle="--")
    ax.set_xlabel("cam speed (rpm)")
    ax.set_ylabel(f"{objective.name}\n({unit})", fontsize=LEGEND_FONT)
    ax.legend(fontsize=LEGEND_FONT, outside_right=True)
    return fig.svg()


def _against_speed(tuning: Plan, design: Design, data: dict[str, Any],
                   speeds: Array) -> tuple[Array, str]:
    """The objective of *design* (whose data is *data*) at each of *speeds* (rpm), and its
    unit: the residual from the train's model, a peak of the motion in SI at each speed, the
    stress or torque from an analysis at each speed."""
    from camfab.analysis.dynamics import trace_scale
    from camfab.sweep.rows import checked
    from camfab.sweep.vary import with_values
    from camfab.tune.objectives import Peak, Residual, residuals

    objective = tuning.objective
    if isinstance(objective, Residual):
        return residuals(design, speeds), objective.unit
    if isinstance(objective, Peak):
        omega = speeds * (math.pi / 30.0)
        peak = max(objective.peaks(design))
        oscillating = design.follower.oscillating
        scale = 1.0 if oscillating else trace_scale(design)
        unit = ("rad/s" if oscillating else "m/s") + ("²" if objective.order == 2 else "³")
        return peak * scale * omega**objective.order, unit
    ev = tuning.evaluator
    values = []
    for speed in speeds:
        _, _, analysis = checked(with_values(data, [("cam", "speed_rpm")], [float(speed)]),
                                 ev.file, ev.folder)
        values.append(math.nan if analysis is None else objective.measure_analysis(analysis)[0])
    return np.array(values), objective.unit
