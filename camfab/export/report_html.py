"""``NAME-report.html``: the inspection report for people (SPEC §5), one self-contained page.

A Jinja2 template inside the package lays out the verdict, every check with where it fails, the
drawing of the cam (a disc at θ = 0 with its follower, or a drum's developed groove), the key
numbers, the motion diagrams, pressure angle and curvature, the dynamics and the verification.
The figures are inline SVG (``figures``), so the page works offline.
"""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.findings import count

if TYPE_CHECKING:
    import jinja2

    from camfab.analysis.record import Analysis


def num(value: float | None, digits: int = 5) -> str:
    if value is None:
        return "—"
    if 1e4 <= abs(value) < 1e9:  # large values in full, not as 4.9907e+05
        return f"{value:.1f}"
    return f"{value:.{digits}g}"


def where(ranges: tuple[tuple[float, float], ...]) -> str:
    return ", ".join(f"{a:.4g}–{b:.4g}" for a, b in ranges)


def _findings(analysis: Analysis) -> list[dict[str, Any]]:
    rows = []
    for f in sorted(analysis.findings, key=lambda f: (f.ok, f.severity != "error")):
        row = "na" if not f.applicable else (
            "" if f.ok else ("fail" if f.severity == "error" else "warn"))
        rows.append({"id": f.id, "severity": f.severity, "row": row, "mark": f.mark,
                     "value": "" if f.value is None else f"{num(f.value)} {f.unit or ''}",
                     "limit": "" if f.limit is None else f"{num(f.limit)} {f.unit or ''}",
                     "where": where(f.ranges_deg), "message": f.message})
    return rows


def _numbers(report: dict[str, Any]) -> list[tuple[str, str]]:
    """The geometry and dynamics keys of the JSON report, as labelled rows."""
    rows = []
    for section in ("geometry", "dynamics"):
        for key, value in report[section].items():
            if value is None or isinstance(value, (list, dict)) or key == "note":
                continue
            label = key.replace("_", " ")
            rows.append((label, num(value) if isinstance(value, float) else str(value)))
    return rows


def _segments(report: dict[str, Any]) -> tuple[list[str], list[list[str]]]:
    keys = [k for k in report["segments"][0] if k not in ("law_coefficients",)]
    rows = [[num(seg[k]) if isinstance(seg[k], float) else str(seg[k]) for k in keys]
            for seg in report["segments"]]
    return [k.replace("_", " ") for k in keys], rows


def _key_points(report: dict[str, Any]) -> tuple[list[str], list[list[str]]]:
    """A shaped cam's key points of the rise (none for other cams)."""
    points = report["motion"].get("key_points") or []
    if not points:
        return [], []
    keys = list(points[0])
    rows = [[num(p[k]) if isinstance(p[k], float) else str(p[k]) for k in keys]
            for p in points]
    return [k.replace("_", " ") for k in keys], rows


def _verification(report: dict[str, Any]) -> list[tuple[str, str]]:
    rows = []
    for key, value in report["verification"].items():
        if isinstance(value, dict):
            rows += [(f"STL {k.replace('_', ' ')}", num(v) if isinstance(v, float) else str(v))
                     for k, v in value.items()]
        elif value is not None:
            rows.append((key.replace("_", " "), num(value) if isinstance(value, float)
                         else str(value)))
    return rows


#: The package's template of the report page.
REPORT_TEMPLATE = "report.html.j2"


@cache
def page_template(name: str) -> jinja2.Template:
    """The page template *name* of the package, compiled once per process (compiling costs a
    build more than filling it in)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.PackageLoader("camfab", "templates"),
                             autoescape=True, trim_blocks=True, lstrip_blocks=True)
    return env.get_template(name)


def render_report_html(analysis: Analysis) -> bytes:
    """The report page as UTF-8 bytes."""
    from camfab.analysis.sizing_words import sized_words
    from camfab.export import figures
    from camfab.export.report_json import report_data

    report = report_data(analysis)
    errors, warnings = count(analysis.findings, "error"), count(analysis.findings, "warning")
    design = analysis.design
    head, rows = _segments(report)
    key_head, key_rows = _key_points(report)
    follower = f"{design.follower.motion} {design.follower.type} follower"
    result = analysis.result
    kind = result.kind_name(design)
    page = page_template(REPORT_TEMPLATE).render(
        version=__version__, name=design.name,
        description=design.description or f"{kind}, {follower}",
        exit_code=analysis.exit_code,
        verdict="PASS" if analysis.exit_code == 0 else "FAIL",
        summary=f"{kind}, {result.motion_words(design)}, {follower}; {errors} error(s), "
                f"{warnings} warning(s)",
        findings=_findings(analysis),
        sized=sized_words(design),
        drawing=figures.cam_drawing(analysis),
        drawing_title=result.drawing_title,
        numbers=_numbers(report), segment_head=head, segment_rows=rows,
        key_head=key_head, key_rows=key_rows,
        changes=result.contact_changes(report),
        diagrams=figures.diagrams(analysis),
        dynamics=figures.has_dynamics(analysis),
        verification=_verification(report))
    return page.encode("utf-8")
