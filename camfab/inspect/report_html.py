"""``STEM-inspection.html``: the inspection of a made or scanned cam, for people.

One self-contained page in the build report's style (a Jinja2 template, inline SVG figures):
the verdict, the checks, the outline with the design over it and where the deviation exceeds the
tolerance, the key numbers, the runs over the tolerance, the diagrams and how the numbers were
obtained.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.findings import Finding, count
from camfab.export.report_html import num, page_template, where
from camfab.inspect.record import Inspection

if TYPE_CHECKING:
    from camfab.inspect.options import Prepared


def _numbers(data: dict[str, Any]) -> list[tuple[str, str]]:
    """The scalar values of the JSON report's sections, as labelled rows."""
    rows = []
    for section in ("deviation", "motion", "profile", "follower"):
        values = data.get(section) or {}
        for key, value in values.items():
            if value is None or isinstance(value, (dict, bool)) or key in ("file", "read",
                                                                             "units"):
                continue
            if isinstance(value, list):
                if not value or not all(isinstance(v, (int, float)) for v in value):
                    continue
                text = ", ".join(num(v) for v in value)
            else:
                text = num(value) if isinstance(value, float) else str(value)
            rows.append((f"{section}: {key.replace('_', ' ')}", text))
    return rows


def render_inspection_html(ins: Inspection, prepared: Prepared) -> bytes:
    """The report page as UTF-8 bytes."""
    from camfab.inspect import figures
    from camfab.inspect.report_json import inspection_dict

    data = inspection_dict(ins, prepared)
    fol = ins.setup.follower
    follower = (f"{'oscillating' if fol.oscillating else 'translating'} {fol.contact} follower"
                + (f" (radius {fol.radius:.4g} mm)" if fol.radius > 0 else ""))
    rotation = "ccw" if ins.setup.sigma > 0 else "cw"
    errors, warnings = count(ins.findings, "error"), count(ins.findings, "warning")
    name = prepared.options.profile.name
    if ins.reference is None:
        verdict, state = "MEASURED", "ok"
        summary = (f"{rotation}, {follower}; no design to compare with; {warnings} warning(s)")
    else:
        verdict = "PASS" if ins.exit_code == 0 else "FAIL"
        state = "ok" if ins.exit_code == 0 else "fail"
        summary = (f"against {ins.reference.name}, {rotation}, {follower}; {errors} error(s), "
                   f"{warnings} warning(s)")
    dev = data["deviation"]
    excursions = [] if dev is None else [
        {"start": num(e["start_deg"]), "end": num(e["end_deg"]), "peak": num(e["peak_mm"]),
         "at": num(e["peak_at_deg"]),
         "xy": ", ".join(num(v) for v in e["peak_at_xy_mm"] if v is not None)}
        for e in dev["excursions"]]
    title = f"{name} at θ = 0 ({rotation})"
    if ins.align is not None:
        title += f", turned {math.degrees(ins.align):.4g}° into phase with the design"
    method = [("read", data["profile"]["read"]), ("units", data["profile"]["units"]),
              ("kerf taken off", f"{num(prepared.kerf_mm)} mm ({prepared.kerf_source})"),
              ("cam centre in the file", ", ".join(num(c) for c in prepared.centre_mm) + " mm"),
              ("follower run every", f"{num(data['method']['grid_step_deg'])}° of cam angle"),
              ("lift measured from", data["method"]["lift_from"]),
              ("derivatives", data["method"]["derivatives"])]
    if ins.reference is not None:
        method.append(("design motion", ins.reference.source))
    page = page_template("inspection.html.j2").render(
        version=__version__, name=name, description=f"inspection of {name}: {follower}",
        verdict=verdict, state=state, summary=summary,
        findings=finding_rows(ins.findings),
        drawing=figures.outline_drawing(ins, title),
        numbers=_numbers(data), excursions=excursions,
        more=(len(ins.excursions()) if dev else 0),
        diagrams=figures.diagrams(ins), method=method, with_design=ins.reference is not None,
        json_name=f"{prepared.options.profile.stem}-inspection.json")
    return page.encode("utf-8")


def finding_rows(findings: list[Finding]) -> list[dict[str, Any]]:
    """The findings as table rows, failed ones first, as the build report shows them."""
    rows = []
    for f in sorted(findings, key=lambda f: (f.ok, f.severity != "error")):
        row = "" if f.ok else ("fail" if f.severity == "error" else "warn")
        rows.append({"id": f.id, "severity": f.severity, "row": row,
                     "mark": f.mark,
                     "value": "" if f.value is None else f"{num(f.value)} {f.unit or ''}",
                     "limit": "" if f.limit is None else f"{num(f.limit)} {f.unit or ''}",
                     "where": where(f.ranges_deg[:12]) + (" …" if len(f.ranges_deg) > 12
                                                            else ""),
                     "message": f.message})
    return rows
