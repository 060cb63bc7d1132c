"""``STEM-inspection.html`` of a scan's inspection, for people: one self-contained page in the
build report's style — the verdict and checks, each flank's deviation map with its colour
scale, the surface's statistics, the follower's motion through the scanned flanks, how the scan
was placed on the part, the key numbers and how they were measured."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.findings import count
from camfab.export.report_html import num, page_template
from camfab.inspect.report_html import finding_rows
from camfab.inspect.scan_record import ScanInspection

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.inspect.options import InspectOptions

#: How the motion through the scan is found, for the report.
METHOD = ("each point's deviation is its distance from the exact flank's tangent plane at the "
          "nearest node of the flank's grid (a k-d tree); the flank as scanned is that grid, "
          "each node moved along its normal by the mean deviation of the points within a "
          "{fit:g} mm box about it; the follower of the design (a groove's roller grown by half "
          "the clearance, so that it fills the groove) is pressed onto each flank so fitted at "
          "every {step:g}° of cam angle; the lift error is where it then stands less where the "
          "design puts it; the play is the design's clearance plus the upper flank's run less "
          "the lower's; the pressure angle as made follows from the lift's derivative, fitted by "
          "least squares over ±{smooth:g}°")


def render_scan_html(ins: ScanInspection, options: InspectOptions, design: Design) -> bytes:
    """The report page as UTF-8 bytes."""
    import math

    from camfab.inspect.scan_figures import deviation_maps, scan_diagrams
    from camfab.inspect.scan_json import scan_dict

    data = scan_dict(ins, options, design)
    errors, warnings = count(ins.findings, "error"), count(ins.findings, "warning")
    name = options.profile.name
    verdict = "PASS" if ins.exit_code == 0 else "FAIL"
    worst = ins.worst()
    most = num(worst[0]) if worst else "–"
    summary = (f"against {design.name} ({design.cam.type}); lift error {most} mm at most, "
               f"tolerance {num(ins.setup.tolerance)} mm; {errors} error(s), "
               f"{warnings} warning(s)")
    scan, al = data["scan"], data["alignment"]
    alignment = [("mode", "fixtured (the scan's frame is the cam's; only the phase was fitted)"
                  if al["mode"] == "fixtured" else "free (a rigid best fit)"),
                 ("start", al["start"]),
                 ("turn about the cam axis", f"{num(al['phase_deg'])}°"),
                 ("tilt of the scanner's Z from the cam axis", f"{num(al['tilt_deg'])}°"),
                 ("translation", ", ".join(num(v) for v in al["translation_mm"]) + " mm"),
                 ("rotation matrix R (p_cam = R·p_scan + t)",
                  "; ".join(", ".join(num(v) for v in row) for row in al["rotation"])),
                 ("residual (RMS)", f"{num(al['residual_rms_mm'])} mm over {al['points_used']:,}"
                  f" points, {al['iterations']} iterations")]
    numbers = [("points read (a mesh: its vertices)", f"{scan['points']:,}"),
               ("points judged (a mesh: its triangles sampled)", f"{scan['judged']:,}"),
               ("points on the flanks", f"{scan['on_flanks']:,}"),
               ("set aside: on no flank (ends, bore, floor, fixture)",
                f"{scan['set_aside']['off_every_flank']:,}"),
               ("set aside: farther than the gate", f"{scan['set_aside']['beyond_gate']:,}")]
    motion = data["motion"]
    for f in motion["flanks"]:
        numbers.append((f"{f['flank']}: largest lift error", "–" if f["max_error_mm"] is None
                        else f"{num(f['max_error_mm'])} mm at {num(f['max_error_at_deg'])}°"))
        numbers.append((f"{f['flank']}: share of the turn measured",
                        f"{num(100.0 * f['measured_share'])} %"))
    if motion["backlash"]:
        b = motion["backlash"]
        numbers.append(("play", f"{num(b['min_mm'])} to {num(b['max_mm'])} mm (design "
                                f"{num(b['design_mm'])} mm)"))
    step = math.degrees(float(ins.theta[1] - ins.theta[0]))
    method = [("read", scan["read"]), ("units", scan["units"]),
              ("gate", f"points farther than {num(ins.setup.gate)} mm from their flank are set "
                       "aside"),
              ("motion", METHOD.format(fit=ins.setup.fit, step=step,
                                       smooth=math.degrees(ins.setup.smooth)))]
    page = page_template("scan_inspection.html.j2").render(
        version=__version__, name=name,
        description=f"inspection of a scan of {design.name} ({design.cam.type})",
        verdict=verdict, state="ok" if ins.exit_code == 0 else "fail", summary=summary,
        findings=finding_rows(ins.findings), map_u_label=ins.model.map_u_label,
        fit=num(ins.setup.fit), maps=deviation_maps(ins),
        surface=[_stats_row(s) for s in data["surface"]], diagrams=scan_diagrams(ins),
        alignment=alignment, numbers=numbers, method=method,
        json_name=f"{options.profile.stem}-inspection.json")
    return page.encode("utf-8")


def _stats_row(s: dict[str, Any]) -> dict[str, str]:
    return {k: (num(v) if isinstance(v, float) else str(v)) for k, v in
            (("flank", s["flank"]), ("points", s["points"]), ("mean", s["mean_mm"]),
             ("std", s["std_mm"]), ("rms", s["rms_mm"]), ("min", s["min_mm"]),
             ("max", s["max_mm"]), ("p01", s["p01_mm"]), ("p99", s["p99_mm"]),
             ("over", s["over_tolerance"]))}
