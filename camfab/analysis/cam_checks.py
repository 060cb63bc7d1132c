"""Checks of a disc cam's geometry: pressure angle, undercut, curvature margin, face width.

Each check yields a :class:`~camfab.analysis.findings.Finding`; lengths are in millimetres and
angles in degrees whatever the design's units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.findings import Finding, listed
from camfab.angles import Extreme, Range, extreme, merge, ranges_deg
from camfab.arrays import Array, Index, Mask
from camfab.design import Design
from camfab.geometry.disc_geometry import DiscGeometry, LiftCheck
from camfab.motion.program import MotionProgram

if TYPE_CHECKING:
    from collections.abc import Callable

    from camfab.geometry.linear import LinearGeometry


@dataclass(frozen=True)
class CurveNumbers:
    """The key numbers every plate cam has (mm, deg): the smallest convex and concave radii of
    the pitch and working curves, the largest pressure angle over the cycle and per segment
    (:func:`curve_extremes`), and where the envelope is undercut: where it folds over
    (``fold_ranges``: the curvature says so), where the cam as cut departs from the design
    (``cut_ranges``: the envelope's points its trimmed outline has lost), and both together."""

    pitch_min_convex: Extreme
    pitch_min_concave: Extreme
    profile_min_convex: Extreme
    profile_min_concave: Extreme
    pressure_angle: Extreme
    segment_pressure: list[Extreme]
    undercut_ranges: tuple[Range, ...]
    fold_ranges: tuple[Range, ...]
    cut_ranges: tuple[Range, ...]


@dataclass(frozen=True)
class CamNumbers(CurveNumbers):
    """The key numbers of a disc cam (mm, deg): a plate cam's, its largest radius and where a
    flat face touches it."""

    max_radius_mm: float
    face_contact_mm: tuple[float, float] | None


def curve_extremes(theta: Array, pitch_radius: Array, working_radius: Array, folds: Mask,
                   pressure_angle: Array, segment: Index, segment_count: int) -> dict[str, Any]:
    """The extremes every plate cam reports, on a dense grid of *theta*, by their field names
    in :class:`CurveNumbers`: the smallest convex and concave radii
    (mm) of the pitch and working curves, the largest |pressure angle| (deg) over the cycle
    and in each segment."""
    rp, rw = pitch_radius, working_radius
    phi = np.degrees(np.abs(pressure_angle))
    return {
        "pitch_min_convex": extreme(theta, rp, rp > 0, largest=False),
        "pitch_min_concave": extreme(theta, -rp, rp < 0, largest=False),
        "profile_min_convex": extreme(theta, rw, rw > 0, largest=False),
        # the raw envelope's loops run backwards (ρ < 0) but are cut away: not concave parts
        "profile_min_concave": extreme(theta, -rw, (rw < 0) & ~folds, largest=False),
        "pressure_angle": extreme(theta, phi, largest=True),
        "segment_pressure": [extreme(theta, phi, segment == i, largest=True)
                             for i in range(segment_count)],
    }


def cam_numbers(geom: DiscGeometry, segment_count: int) -> CamNumbers:
    """Extremes of curvature and pressure angle, radii, face contact and undercut ranges."""
    dense = geom.dense
    theta = dense.theta
    contact = None
    if dense.face_contact is not None:
        contact = (float(dense.face_contact.min()), float(dense.face_contact.max()))
    folds = ranges_deg(theta, geom.folds)
    cut = ranges_deg(geom.working.theta, geom.cut)
    return CamNumbers(
        max_radius_mm=float(np.max(geom.profile.radii())),
        face_contact_mm=contact,
        undercut_ranges=merge([*folds, *cut]),
        fold_ranges=merge(list(folds)),
        cut_ranges=merge(list(cut)),
        **curve_extremes(theta, dense.pitch.radius, dense.working.radius, geom.folds,
                         dense.pressure_angle, dense.segment, segment_count),
    )


def offset_side(design: Design) -> str | None:
    """Which side of the cam centre an offset of a translating follower lowers the rise pressure
    angle on: ``+X`` for a counter-clockwise cam, ``-X`` for a clockwise one (SPEC §2)."""
    fol = design.follower
    if fol.oscillating or fol.type == "flat":
        return None
    return "+X" if design.cam.sigma > 0 else "-X"


def fmt(value: float) -> str:
    """A number in a finding's message: four significant digits."""
    return f"{value:.4g}"


def where(ranges: tuple[Range, ...]) -> str:
    if not ranges:
        return "a point too small to resolve"
    return listed([f"{fmt(a)}°" if fmt(a) == fmt(b) else f"{fmt(a)}°–{fmt(b)}°"
                   for a, b in ranges])


def pressure_angle_finding(design: Design, geom: DiscGeometry, numbers: CamNumbers) -> Finding:
    """|φ| against ``limits.pressure_angle`` over the whole cycle."""
    limit = math.degrees(design.pressure_angle_limit)
    worst = numbers.pressure_angle
    value = worst.value or 0.0
    dense = geom.dense
    over = ranges_deg(dense.theta, np.degrees(np.abs(dense.pressure_angle)) > limit)
    if not over:
        message = f"largest pressure angle {fmt(value)}° at {fmt(worst.at_deg or 0.0)}°"
        if value == 0.0 and design.follower.type == "flat" and not design.follower.oscillating:
            message = "a flat face perpendicular to its motion has no pressure angle"
        return Finding("pressure_angle", True, "error",
                       f"{message}, within the limit {fmt(limit)}°", value, limit, "deg",
                       at_deg=worst.at_deg)
    k = int(np.argmax(np.abs(dense.pressure_angle)))
    kind = design.program.segments[int(dense.segment[k])].kind
    advice = f"a larger base radius or a longer {kind} lowers it"
    side = offset_side(design)
    if side is not None and kind != "dwell":
        other = {"rise": "return", "return": "rise"}[kind]
        toward = side if kind == "rise" else {"+X": "-X", "-X": "+X"}[side]
        advice = (f"on the {kind} an offset toward {toward} lowers it (and raises it on the "
                  f"{other}); " + advice)
    return Finding(
        "pressure_angle", False, "error",
        f"pressure angle reaches {fmt(value)}° at {fmt(worst.at_deg or 0.0)}°, over the limit "
        f"{fmt(limit)}° at {where(over)}: {advice}",
        value, limit, "deg", over, at_deg=worst.at_deg)


def departure_words(numbers: CurveNumbers, what: str = "cam") -> str:
    """Where the cam as cut (its envelope's loops trimmed) departs from the design, in words:
    a range of its own, apart from where the envelope folds."""
    if not numbers.cut_ranges:
        return ""
    return (f"; the {what} as cut, its loops trimmed away, departs from the design at "
            f"{where(numbers.cut_ranges)}")


def undercut_finding(design: Design, geom: DiscGeometry, numbers: CamNumbers) -> Finding:
    """Does the follower's envelope fold over (or cross itself)? With the motion error it causes:
    where the envelope folds and where the cam as cut departs from the design are two ranges
    (the second wider: the trimmed outline bridges the fold), said apart."""
    fol = design.follower
    ranges = numbers.undercut_ranges
    folds = numbers.fold_ranges or ranges
    departs = departure_words(numbers)
    motion = (f"the cam that is really cut moves the follower up to "
              f"{fmt(geom.lift.max_mm)} mm off the design at {fmt(geom.lift.at_deg)}°")
    if fol.type == "flat":
        worst = numbers.profile_min_convex if not geom.folds.any() else extreme(
            geom.dense.theta, geom.dense.working.radius, largest=False)
        value = worst.value
        if not geom.undercut:
            return Finding("undercut", True, "error",
                           f"the profile's radius of curvature stays positive (smallest "
                           f"{fmt(value or 0.0)} mm at {fmt(worst.at_deg or 0.0)}°)",
                           value, 0.0, "mm", at_deg=worst.at_deg)
        need = ""
        if not fol.oscillating and value is not None:
            base = design.cam.base_radius or 0.0
            need = f"; a base radius above {fmt(base - value)} mm removes the cusp"
        rho = "ρ" if fol.oscillating else "ρ = Rb + s + s″"
        return Finding("undercut", False, "error",
                       f"the flat face's envelope has a cusp (its radius of curvature {rho} falls "
                       f"to {fmt(value or 0.0)} mm) at {where(folds)}{departs}: {motion}{need}",
                       value, 0.0, "mm", ranges)
    radius = fol.trace_radius
    smallest = numbers.pitch_min_convex
    value = smallest.value
    if not geom.undercut:
        at = f" at {fmt(smallest.at_deg or 0.0)}°" if value is not None else ""
        shape = {"knife": "knife edge", "roller": "roller", "mushroom": "mushroom face"}[fol.type]
        return Finding("undercut", True, "error",
                       f"the pitch curve's smallest convex radius {fmt(value or 0.0)} mm{at} "
                       f"is larger than the {shape} radius {fmt(radius)} mm", value, radius,
                       "mm", at_deg=smallest.at_deg)
    what = "roller" if fol.type == "roller" else "mushroom face"
    if geom.folds.any() and value is not None:
        cause = (f"the {what} radius {fmt(radius)} mm exceeds the pitch curve's convex radius "
                 f"of curvature (down to {fmt(value)} mm) at {where(numbers.fold_ranges)}: the "
                 f"envelope folds over there{departs}")
        need = (f"a {what} radius below {fmt(value)} mm, a larger base radius or a longer rise "
                f"or return avoids it")
    else:
        cause = (f"the {what}'s envelope crosses itself: the {what} cannot reach into a sharp "
                 f"hollow of the pitch curve (a velocity step makes one){departs}")
        need = "a motion law without a velocity step or a smaller radius avoids it"
    return Finding("undercut", False, "error", f"{cause}; {motion}; {need}",
                   value, radius, "mm", ranges)


def curvature_finding(design: Design, geom: DiscGeometry, numbers: CamNumbers) -> Finding | None:
    """The convex working curve against its least radius (``limits.min_radius_of_curvature``,
    or a flat or mushroom face's default: :attr:`~camfab.design.Design.min_profile_radius`)."""
    margin = design.min_profile_radius
    if margin <= 0.0:
        return None
    smallest = numbers.profile_min_convex
    value = smallest.value
    dense = geom.dense
    low = ranges_deg(dense.theta, (dense.working.radius > 0) & (dense.working.radius < margin))
    ok = not low and not geom.undercut
    message = (f"smallest convex radius of the profile {fmt(value or 0.0)} mm at "
               f"{fmt(smallest.at_deg or 0.0)}°, "
               + (f"at least {fmt(margin)} mm" if ok else
                  f"below the required {fmt(margin)} mm at {where(low)}"))
    return Finding("curvature", ok, "error", message, value, margin, "mm", low,
                   at_deg=smallest.at_deg)


def face_width_finding(design: Design, numbers: CamNumbers) -> Finding | None:
    """The face width a flat follower needs, against ``face_width`` when given.

    A translating face is centred on its stem, so it must reach the farther contact point on
    each side; an oscillating face must cover the span of contact along it.
    """
    fol = design.follower
    if fol.type != "flat" or numbers.face_contact_mm is None:
        return None
    low, high = numbers.face_contact_mm
    if fol.oscillating:
        needed = high - low
        span = f"from {fmt(low)} to {fmt(high)} mm along the face from the pivot's foot"
    else:
        needed = 2.0 * max(abs(low), abs(high))
        span = f"from {fmt(low)} to {fmt(high)} mm of the stem axis"
    if fol.face_width is None:
        return Finding("face_width", True, "error",
                       f"contact runs {span}: the face must be at least {fmt(needed)} mm wide",
                       needed, None, "mm")
    ok = fol.face_width >= needed
    verdict = "covers it" if ok else "is too narrow: the cam edge would dig into the face"
    return Finding("face_width", ok, "error",
                   f"contact runs {span}, needing a face {fmt(needed)} mm wide; the face of "
                   f"{fmt(fol.face_width)} mm {verdict}", needed, fol.face_width, "mm")


@dataclass(frozen=True)
class ToolCut:
    """Where a tool of ``radius`` (mm) running around the outside of a plate's outline cannot
    follow it, and the cam it makes: ``closed`` the outline it leaves (mm), ``spots`` the cam
    angles (deg) where it leaves material under the follower's contact, ``depth`` the most it
    leaves there (mm), ``tightest`` the smallest concave radius under its own there (mm; None
    where only a sharp hollow stops it) and ``made`` the follower run over the cam it makes."""

    radius: float
    closed: Array
    spots: tuple[Range, ...]
    depth: float
    tightest: float | None
    made: LiftCheck


def fine_outline(geom: DiscGeometry | LinearGeometry) -> Array:
    """The plate's outline of *geom* as a closed chain of points (mm), its arcs cut into chords
    within a quarter of its sampling tolerance (a sampled profile's own points)."""
    if isinstance(geom, DiscGeometry) and not geom.exact:
        return geom.profile.vertices
    outline = geom.profile if isinstance(geom, DiscGeometry) else geom.outline
    return outline.points(0.25 * geom.tolerance)


def tool_cut(design: Design, geom: DiscGeometry | LinearGeometry, radius: float,
             program: MotionProgram | None = None, leave: float | None = None) -> ToolCut | None:
    """What a tool of *radius* (mm: a milling cutter's, or half a laser's kerf) running around
    the outside of the outline of *geom* (a disc's or a linear cam's plate) leaves under the
    follower, driven through *program* (by default the design's); None where it follows the
    whole profile, leaving nowhere more than *leave* (mm; by default
    ``manufacturing.tolerance``).

    It cannot follow a concave part of smaller radius, nor reach into a sharp hollow; what it
    leaves there is measured (the outline closed by the tool), and where it lies under the
    follower's contact, the follower is run over the cam as made."""
    from camfab.curves.profile import Profile
    from camfab.geometry.offset import closing, on_outline, uncut_depth

    if isinstance(geom, DiscGeometry):
        from camfab.geometry.disc_geometry import lift_check
    else:
        from camfab.geometry.linear import lift_check

    dense, tol = geom.dense, geom.tolerance
    # the outline's arcs in chords finer than it was sampled: the follower run over the cam
    # as made then differs from the run over the outline only where the tool changes it
    part = fine_outline(geom)
    closed = closing(part, radius, 0.25 * tol)
    depth = uncut_depth(part, closed, dense.working.xy, 2.0 * tol)
    rw = dense.working.radius
    tight = (rw < 0) & ~geom.folds & (-rw < radius)
    deep = depth > (design.manufacturing.tolerance if leave is None else leave)
    # only where the profile is (the raw envelope's points the part has lost do not count)
    index = np.flatnonzero(tight | deep)
    on_part = np.zeros(len(rw), dtype=bool)
    on_part[index] = on_outline(part, dense.working.xy[index], 2.0 * tol)
    tight &= on_part
    deep &= on_part
    spots = ranges_deg(dense.theta, tight | deep)
    if not spots:
        return None
    made = lift_check(geom.cam, program or design.program,  # type: ignore[arg-type]
                      Profile.from_points(closed))
    return ToolCut(radius, closed, spots, float(depth.max()),
                   float(np.min(-rw[tight])) if tight.any() else None, made)


def cutter_finding(design: Design, geom: DiscGeometry, numbers: CamNumbers,
                   program: MotionProgram | None = None) -> Finding | None:
    """Can a milling cutter of ``cutter_radius`` (running outside the outline) make the profile?
    (see :func:`tool_cut`)."""
    radius = design.manufacturing.cutter_radius
    if radius <= 0.0:
        return None
    return tool_finding("cutter", f"a cutter of radius {fmt(radius)} mm", radius,
                         tool_cut(design, geom, radius, program), numbers)


def kerf_finding(design: Design, geom: DiscGeometry, numbers: CamNumbers,
                 program: MotionProgram | None = None) -> Finding | None:
    """Can a laser's beam, ``kerf`` wide (running outside the outline, its radius half the
    kerf), cut the profile? A sharp hollow (a knife's velocity step makes one) or a concave
    radius under the beam's is rounded to the beam's radius; the follower run over the cam as
    cut says how far it moves off the design there (see :func:`tool_cut`)."""
    kerf = design.manufacturing.kerf
    if kerf <= 0.0:
        return None
    return tool_finding("kerf", f"a beam of kerf {fmt(kerf)} mm (radius {fmt(kerf / 2.0)} mm)",
                         kerf / 2.0, tool_cut(design, geom, kerf / 2.0, program), numbers,
                         scale=2.0, what="kerf", made="cut")


def tool_finding(check: str, tool: str, radius: float, cut: ToolCut | None,
                 numbers: CurveNumbers, scale: float = 1.0, what: str = "cutter radius",
                 made: str = "milled", spots: Callable[[tuple[Range, ...]], str] | None = None,
                 at: Callable[[float], str] | None = None) -> Finding:
    """The finding *check* of a *tool* of *radius* (mm) and what it leaves, *cut*: the tool's
    size a profile needs is *scale* times its radius (a kerf is twice the beam's radius), and
    *what* names it, *made* how the cam is made; *spots* and *at* word the cam angles (deg)
    where it fails and one cam angle (by default as degrees)."""
    spots = spots or where
    at = at or (lambda deg: f"{fmt(deg)}°")
    smallest = numbers.profile_min_concave
    if cut is None:
        shape = (f"smallest concave radius {fmt(smallest.value)} mm at "
                 f"{at(smallest.at_deg or 0.0)}" if smallest.value is not None
                 else "the profile has no concave part")
        return Finding(check, True, "error", f"{tool} follows the whole profile ({shape})",
                       smallest.value, radius, "mm")
    if cut.tightest is not None:
        value = cut.tightest
        cause = f"its concave radius falls to {fmt(value)} mm"
        advice = f"a {what} below {fmt(scale * value)} mm cuts it"
    else:
        value = 0.0
        cause = "it has a sharp hollow (a velocity step of the motion makes one)"
        advice = "a motion law without a velocity step, or finishing the hollow by hand, cuts it"
    return Finding(
        check, False, "error",
        f"{tool} cannot follow the profile at {spots(cut.spots)}: {cause}; it leaves up to "
        f"{fmt(cut.depth)} mm of material there, and the cam as {made} moves the follower up "
        f"to {fmt(cut.made.max_mm)} mm off the design at {at(cut.made.at_deg)}; {advice}",
        value, radius, "mm", cut.spots)


def bore_finding(design: Design, part: str | None) -> Finding | None:
    """A cam that turns on a shaft (the *part*: "plate" or "drum") with no ``bore``: a warning,
    since the part as made has no hole to mount it by (None for a cam on no shaft, *part*
    None: a linear cam slides)."""
    if part is None:
        return None
    if design.cam.bore is not None:
        return Finding("bore", True, "warning",
                       f"the shaft hole is {fmt(design.cam.bore)} mm across", design.cam.bore,
                       None, "mm")
    return Finding("bore", False, "warning",
                   f"no bore: the {part} has no shaft hole (give cam.bore, its diameter, to cut "
                   "one)")


def cam_findings(design: Design, geom: DiscGeometry, numbers: CamNumbers,
                 program: MotionProgram | None = None) -> list[Finding]:
    """Every geometric check of a disc cam (driving its follower through *program*, by default
    the design's)."""
    found = [pressure_angle_finding(design, geom, numbers),
             undercut_finding(design, geom, numbers),
             curvature_finding(design, geom, numbers),
             face_width_finding(design, numbers),
             cutter_finding(design, geom, numbers, program),
             kerf_finding(design, geom, numbers, program)]
    return [f for f in found if f is not None]
