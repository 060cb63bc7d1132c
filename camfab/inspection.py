"""``camfab inspect``: a made or scanned cam's outline -> its motion and deviation -> files.

The follower, the cam's turning, speed and tolerance come from the design (``--design``), then a
small follower file (``--follower``), then the command line, each overriding the one before.
Lengths on the command line and in the follower file are in ``--units`` (default: the design's
units, else mm) unless they carry a unit (``"5 mm"``); ``--centre`` is in the outline file's
coordinates. Nothing is written unless everything was read and computed.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab.analysis.inspection import (
    SMOOTH_DRAWING,
    SMOOTH_POINTS,
    Inspection,
    InspectionSetup,
    Reference,
)
from camfab.design.rules import MIN_TABLE_STEP_DEG
from camfab.errors import InspectionError

if TYPE_CHECKING:
    from camfab.curves.follower import FollowerGeometry
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.export.outline import Outline

#: Follower keys of a design's ``follower:`` section that the inspection follower takes.
FOLLOWER_KEYS = ("type", "motion", "offset", "roller_radius", "face_radius", "pivot_distance",
                 "arm_length", "pivot_side", "face_offset")
_LENGTH_KEYS = ("offset", "roller_radius", "face_radius", "pivot_distance", "arm_length",
                "face_offset")
#: Other keys a follower file may hold.
SETUP_KEYS = ("units", "rotation", "speed_rpm", "tolerance", "follower")
FOLLOWER_TYPES = ("knife", "roller", "flat", "mushroom")

#: Tolerance of the shapely offset that takes a laser's kerf off a beam path (mm): a micrometre.
KERF_OFFSET_TOLERANCE_MM = 1e-3

#: The lift table's row step when neither the command line nor a design gives one: 1°, like the
#: design's motion table.
DEFAULT_STEP = math.radians(1.0)

#: ``--step`` (deg): the range of a design's ``table_step``, from 0.01° (36,000 rows, the
#: follower run at each) to 30°. The angles the follower is run at grow as 1/step.
STEP_RANGE_DEG = (MIN_TABLE_STEP_DEG, 30.0)

#: ``--smooth`` (deg): from 0.1°, the step the follower is run at (a window of less is that of
#: two steps), to 30°; the fit over the window costs its width in steps at every angle.
SMOOTH_RANGE_DEG = (0.1, 30.0)

#: Largest kerf (mm): a laser's is a few tenths of a millimetre, a plasma cutter's a few.
MAX_KERF_MM = 10.0

#: Most pairs of an outline's edges whose bounding boxes overlap (estimated from a sample of
#: its edges) for it to be checked for crossing itself: GEOS's test takes some 30 ns a pair. A
#: smooth outline's edges overlap only their neighbours' (200,000 points: some 600,000 pairs);
#: a star of long spikes, or points out of order, overlap thousands each.
MAX_OVERLAPS = 50_000_000

#: Edges sampled for that estimate.
OVERLAP_SAMPLES = 256

#: Most the direction of an outline may turn, in all (rad: 300 turns), for a kerf to be taken
#: off it. A beam's path is smooth (one turn, and a little more where it is concave); a jagged
#: one (the noise of a dense scan, random points) makes the offset's round joins cross each
#: other so often that it could take minutes.
MAX_KERF_TURNING = 600.0 * math.pi


@dataclass(frozen=True)
class InspectOptions:
    """The command line, as given (None: not given). Lengths are text, optionally with a unit."""

    profile: Path
    design: Path | None = None
    follower_file: Path | None = None
    follower: dict[str, str] = field(default_factory=dict)
    rotation: str | None = None
    speed: str | None = None
    units: str | None = None
    layer: str | None = None
    centre: str | None = None
    step: str | None = None
    smooth: str | None = None
    tolerance: str | None = None
    kerf: str | None = None
    align: bool = False
    out_dir: Path | None = None


@dataclass(frozen=True)
class Prepared:
    """Everything read and resolved, before the follower is run."""

    options: InspectOptions
    outline: Outline
    profile: Profile
    setup: InspectionSetup
    reference: Reference | None
    units: str
    speed_rpm: float | None
    centre_mm: tuple[float, float]
    kerf_mm: float
    kerf_source: str
    design: Design | None


@dataclass(frozen=True)
class InspectResult:
    """What one inspection did."""

    inspection: Inspection
    prepared: Prepared
    folder: Path
    written: list[Path]

    @property
    def exit_code(self) -> int:
        return self.inspection.exit_code


def inspect(options: InspectOptions) -> InspectResult:
    """Read, inspect, render and write (atomically); raises a ``CamfabError`` on bad input,
    before anything is written."""
    from camfab.analysis.inspection import inspect_profile
    from camfab.export.inspection_csv import render_lift_csv
    from camfab.export.inspection_html import render_inspection_html
    from camfab.export.inspection_json import render_inspection_json
    from camfab.geometry.simulate import SimulationTooLarge
    from camfab.pipeline import write_files

    with warnings.catch_warnings():
        # numpy's warnings on degenerate numbers are not messages for the user: what they
        # warn of is refused with one line, or does not matter to the result
        warnings.simplefilter("ignore", RuntimeWarning)
        prepared = prepare(options)
        try:
            inspection = inspect_profile(prepared.profile, prepared.setup, prepared.reference,
                                         options.align)
        except SimulationTooLarge as exc:
            raise InspectionError(str(options.profile), f"the outline is too jagged to run the "
                                  f"follower over ({exc}): are its points in order along it? "
                                  "(a smooth outline of any number of points needs far fewer)"
                                  ) from None
        stem = options.profile.stem
        files = {f"{stem}-lift.csv": render_lift_csv(inspection),
                 f"{stem}-inspection.json": render_inspection_json(inspection, prepared),
                 f"{stem}-inspection.html": render_inspection_html(inspection, prepared)}
    folder = options.out_dir or Path("exports") / f"{stem}-inspection"
    return InspectResult(inspection, prepared, folder, write_files(folder, files))


def prepare(options: InspectOptions) -> Prepared:
    """Read the design, the follower file and the outline, and resolve the setup."""
    from camfab.pipeline import load_design
    from camfab.design.source import MAX_DESIGN_BYTES
    from camfab.export.outline import read_outline
    from camfab.files import check_bounded

    design = None
    if options.design is not None:
        check_bounded(options.design, MAX_DESIGN_BYTES, "a design file")
        design = load_design(options.design)
    analysis = None
    if design is not None:
        from camfab.pipeline import analyse

        if design.cam.type == "cylindrical":
            raise InspectionError(str(options.design), "is a drum (cylindrical) cam; inspection "
                                  "checks the outline of a disc cam")
        if design.cam.type == "groove":
            raise InspectionError(str(options.design), "is a groove cam; inspection checks the "
                                  "outline of a disc cam, not a groove's two walls")
        analysis = analyse(design)
        if analysis.geometry is None:
            raise InspectionError(str(options.design), f"a {design.cam.type} cam has no disc "
                                  "geometry in this version of camfab to inspect against")
    extra = _follower_file(options.follower_file) if options.follower_file else {}
    file_units = extra.get("units")
    units = options.units or file_units or (design.units if design else "mm")
    follower = _follower(options, extra, design, units)
    outline = read_outline(options.profile, units=options.units,
                           default_units=units, layer=options.layer)
    tolerance = _length_or_none("--tolerance", options.tolerance, units, positive=True)
    if tolerance is None and "tolerance" in extra:
        tolerance = _length("tolerance", extra["tolerance"], units, str(options.follower_file),
                            positive=True)
    if tolerance is None and design is not None:
        tolerance = design.manufacturing.tolerance
    rotation = options.rotation or extra.get("rotation") or (
        design.cam.rotation if design else "ccw")
    if rotation not in ("ccw", "cw"):
        raise InspectionError(str(options.follower_file), f"rotation: must be ccw or cw (got "
                              f"{rotation!r})")
    speed_rpm = _speed(options, extra, design)
    step = _step(options, design)
    smooth = (_angle("--smooth", options.smooth, SMOOTH_RANGE_DEG)
              if options.smooth is not None
              else SMOOTH_POINTS if outline.points_only else SMOOTH_DRAWING)
    limit = (design.pressure_angle_limit if design is not None
             else math.radians(35.0 if follower.oscillating else 30.0))
    setup = InspectionSetup(follower, 1 if rotation == "ccw" else -1,
                            None if speed_rpm is None else speed_rpm * math.pi / 30.0,
                            tolerance, step, smooth, limit)
    centre = _centre(options.centre, outline.mm_per_unit)
    profile, kerf, kerf_source = _part(options, outline, units)
    profile = _centred(profile, centre, options.profile)
    reference = None
    if analysis is not None:
        from camfab.analysis.inspection import design_reference

        reference = design_reference(analysis, follower)
    elif options.align:
        raise InspectionError("--align", "needs --design (the motion to align the outline to)")
    return Prepared(options, outline, profile, setup, reference, units, speed_rpm, centre, kerf,
                    kerf_source, design)


# -- the follower -------------------------------------------------------------------------------

def _follower_file(path: Path) -> dict[str, Any]:
    """A follower file: the keys of a design's ``follower:`` section, at the top or under
    ``follower:``, and optionally ``units``, ``rotation``, ``speed_rpm``, ``tolerance``."""
    from camfab.design.source import MAX_DESIGN_BYTES, compose_yaml
    from camfab.errors import DesignError, did_you_mean
    from camfab.files import read_bounded

    name = str(path)
    raw = read_bounded(path, MAX_DESIGN_BYTES, "a follower file")
    try:
        # read as a design is, within the same limits of size, depth and aliases
        _, data, _ = compose_yaml(raw.decode("utf-8-sig"), name)
    except UnicodeDecodeError:
        raise InspectionError(name, "is not a text file (a follower file is YAML in UTF-8)"
                              ) from None
    except DesignError as exc:
        line = exc.location.line if exc.location is not None else None
        raise InspectionError(f"{name}:{line}" if line else name, exc.problem) from None
    if not isinstance(data, dict):
        raise InspectionError(name, "must be a mapping of follower keys (type, roller_radius, "
                              "offset, ...)")
    nested = data.get("follower")
    if nested is not None and not isinstance(nested, dict):
        raise InspectionError(name, "follower: must be a mapping")
    out = {k: v for k, v in data.items() if k != "follower"}
    out.update(nested or {})
    allowed = (*FOLLOWER_KEYS, *SETUP_KEYS)
    for key in out:
        if key not in allowed:
            hint = did_you_mean(key, allowed)
            raise InspectionError(name, f"unknown key '{key}' ({hint + '; ' if hint else ''}"
                                  f"allowed: {', '.join(allowed)})")
    if "units" in out and out["units"] not in ("mm", "in"):
        raise InspectionError(name, f"units: must be mm or in (got {out['units']!r})")
    out["_file"] = name
    return out


def _follower(options: InspectOptions, extra: dict[str, Any], design: Design | None,
              units: str) -> FollowerGeometry:
    """The inspection follower: the design's, then the follower file's keys, then the command
    line's, each over the one before."""
    from camfab.curves.follower import FollowerGeometry

    fields: dict[str, Any] = {}
    if design is not None:
        fol = design.follower
        fields = {"type": fol.type, "motion": fol.motion, "offset": fol.offset,
                  "roller_radius": fol.roller_radius, "face_radius": fol.face_radius,
                  "pivot_distance": fol.pivot_distance, "arm_length": fol.arm_length,
                  "pivot_side": fol.pivot_side, "face_offset": fol.face_offset}
    for source, given in ((extra.get("_file", ""), extra), ("", options.follower)):
        swinging = "pivot_distance" in given or "arm_length" in given
        for key in FOLLOWER_KEYS:
            if key not in given or given[key] is None:
                continue
            what = f"--{key.replace('_', '-')}" if not source else f"{source}: {key}"
            value = given[key]
            fields[key] = (_length(what, value, units, "", positive=key not in
                                   ("offset", "face_offset")) if key in _LENGTH_KEYS
                           else str(value))
        if swinging and "motion" not in given:
            fields["motion"] = "oscillating"
    kind = fields.get("type")
    if kind == "spherical":
        kind = "mushroom"
    if kind is None:
        raise InspectionError("follower", "not given: use --design, --follower FILE.yaml or "
                              "--type with its dimensions (e.g. --type roller --roller-radius 8)")
    if kind not in FOLLOWER_TYPES:
        raise InspectionError("--type", f"unknown follower type {kind!r} (allowed: "
                              f"{', '.join(FOLLOWER_TYPES)})")
    motion = fields.get("motion", "translating")
    if motion not in ("translating", "oscillating"):
        raise InspectionError("follower", f"motion: must be translating or oscillating (got "
                              f"{motion!r})")
    radius = 0.0
    if kind in ("roller", "mushroom"):
        key = "roller_radius" if kind == "roller" else "face_radius"
        radius = fields.get(key) or 0.0
        if radius <= 0.0:
            raise InspectionError("follower", f"a {kind} follower needs --"
                                  f"{key.replace('_', '-')}")
    oscillating = motion == "oscillating"
    if oscillating and not (fields.get("pivot_distance") and fields.get("arm_length")):
        raise InspectionError("follower", "an oscillating follower needs --pivot-distance and "
                              "--arm-length")
    side = fields.get("pivot_side", "right")
    if side not in ("right", "left"):
        raise InspectionError("follower", f"pivot_side: must be right or left (got {side!r})")
    return FollowerGeometry(
        contact=kind, oscillating=oscillating, radius=radius,
        offset=0.0 if oscillating else float(fields.get("offset") or 0.0),
        pivot_distance=float(fields.get("pivot_distance") or 0.0) if oscillating else 0.0,
        arm_length=float(fields.get("arm_length") or 0.0) if oscillating else 0.0,
        pivot_sign=1 if side == "right" else -1,
        face_offset=float(fields.get("face_offset") or 0.0) if oscillating else 0.0)


# -- numbers ------------------------------------------------------------------------------------

def _length(what: str, raw: object, units: str, file: str = "", positive: bool = False) -> float:
    """A length (mm) from a number in *units* or a string with a unit."""
    from camfab.design.units import LENGTH, convert
    from camfab.errors import DesignError

    try:
        value = convert(raw, LENGTH, units)
    except DesignError as exc:
        raise InspectionError(f"{file}: {what}" if file else what, str(exc)) from None
    if positive and value <= 0.0:
        raise InspectionError(what, f"must be > 0 (got {raw})")
    return value


def _length_or_none(what: str, raw: str | None, units: str, positive: bool = False
                    ) -> float | None:
    return None if raw is None else _length(what, raw, units, positive=positive)


def _angle(what: str, raw: str, range_deg: tuple[float, float]) -> float:
    """An angle (rad) from a number of degrees or a string with a unit, within *range_deg*
    (deg, both ends included)."""
    from camfab.design.units import ANGLE, convert
    from camfab.errors import DesignError

    try:
        value = convert(raw, ANGLE)
    except DesignError as exc:
        raise InspectionError(what, str(exc)) from None
    low, high = range_deg
    if not math.radians(low) * (1 - 1e-12) <= value <= math.radians(high) * (1 + 1e-12):
        raise InspectionError(what, f"must be from {low:g}° to {high:g}° (got {raw})")
    return value


def _step(options: InspectOptions, design: Design | None) -> float:
    """The lift table's row step (rad): ``--step``, else the design's ``table_step`` (which the
    design rules hold to the same range), else 1°."""
    if options.step is not None:
        return _angle("--step", options.step, STEP_RANGE_DEG)
    return DEFAULT_STEP if design is None else design.table_step


def _speed(options: InspectOptions, extra: dict[str, Any], design: Design | None
           ) -> float | None:
    from camfab.design.units import SPEED, convert
    from camfab.errors import DesignError

    raw = options.speed if options.speed is not None else extra.get("speed_rpm")
    if raw is None:
        return design.cam.speed_rpm if design is not None else None
    what = "--speed" if options.speed is not None else f"{extra['_file']}: speed_rpm"
    try:
        value = convert(raw, SPEED)
    except DesignError as exc:
        raise InspectionError(what, str(exc)) from None
    if value <= 0.0:
        raise InspectionError(what, f"must be > 0 (got {raw})")
    return value


def _centre(raw: str | None, mm_per_unit: float) -> tuple[float, float]:
    if raw is None:
        return (0.0, 0.0)
    parts = raw.replace(";", ",").split(",")
    try:
        x, y = (float(p) for p in parts)
    except ValueError:
        raise InspectionError("--centre", f"must be X,Y in the outline's coordinates (got "
                              f"{raw!r})") from None
    from camfab.export.outline import MAX_COORDINATE_MM

    if not (math.isfinite(x) and math.isfinite(y)):
        raise InspectionError("--centre", f"must be finite (got {raw!r})")
    if not max(abs(x), abs(y)) * mm_per_unit <= MAX_COORDINATE_MM:
        raise InspectionError("--centre", f"must lie within {MAX_COORDINATE_MM:,.0f} mm of the "
                              f"origin (got {raw!r})")
    return (x * mm_per_unit, y * mm_per_unit)


# -- the part -----------------------------------------------------------------------------------

def _part(options: InspectOptions, outline: Outline, units: str) -> tuple[Profile, float, str]:
    """The part's outline: a laser's beam path less kerf/2 (``--kerf``, or the kerf a camfab
    drawing's note declares)."""
    from camfab.geometry.plate import inside_kerf

    name = str(options.profile)
    if options.kerf is not None:
        kerf, what = _length("--kerf", options.kerf, units), "--kerf"
        source = "--kerf"
    elif outline.kerf_note is not None:
        kerf = outline.kerf_note.kerf_mm(name)
        what = f"{name}: {outline.kerf_note.entity}: the note's kerf"
        source = "the drawing's note (CUT offset for a kerf)"
    else:
        return outline.profile, 0.0, "none"
    if not 0.0 <= kerf <= MAX_KERF_MM:
        raise InspectionError(what, f"must be from 0 to {MAX_KERF_MM:g} mm (got {kerf:g} mm)")
    if kerf == 0.0:
        return outline.profile, 0.0, source
    turning = _turning(outline.profile)
    if turning > MAX_KERF_TURNING:
        raise InspectionError(what, f"cannot be taken off an outline this jagged: its direction "
                              f"turns {turning / (2 * math.pi):,.0f} times round in all (at most "
                              f"{MAX_KERF_TURNING / (2 * math.pi):,.0f}); a beam's path is smooth")
    try:
        part = inside_kerf(outline.profile, kerf, KERF_OFFSET_TOLERANCE_MM, split_lines=False)
    except ValueError as exc:
        raise InspectionError(what, f"{exc} (kerf/2 is wider than the part)") from None
    return part.ccw(), kerf, source


def _turning(profile: Profile) -> float:
    """How far (rad) the direction of *profile* turns in all, one way or the other: 2π for a
    convex outline."""
    import numpy as np

    start, end = profile.normal_angles()
    corners = np.mod(start - np.roll(end, 1) + math.pi, 2.0 * math.pi) - math.pi
    return float(np.sum(np.abs(corners)) + np.sum(np.abs(profile.arcs().sweep)))


def _centred(profile: Profile, centre: tuple[float, float], path: Path) -> Profile:
    """*profile* moved so *centre* is the origin; the centre must lie inside it."""
    import numpy as np

    from camfab.curves.profile import Profile as P
    from camfab.geometry.undercut import is_simple

    moved = P(profile.vertices - np.array(centre), profile.bulges)
    chain = moved.points(KERF_OFFSET_TOLERANCE_MM, split_lines=False)
    if len(np.unique(chain, axis=0)) < 3:
        raise InspectionError(str(path), "the outline encloses no area (fewer than three "
                              "distinct points)")
    overlaps = _overlapping_edges(chain)
    if overlaps > MAX_OVERLAPS:
        raise InspectionError(str(path), f"the outline is too jagged to check: its edges' boxes "
                              f"overlap in some {overlaps:.2g} pairs (at most {MAX_OVERLAPS:.2g}"
                              "); are the points in order along the outline?")
    if not is_simple(chain):
        raise InspectionError(str(path), "the outline crosses itself (are the points in order "
                              "along the outline?)")
    if not _inside(chain):
        raise InspectionError(str(path), f"the cam centre ({centre[0]:.6g}, {centre[1]:.6g}) mm "
                              "lies outside the outline; give it with --centre X,Y")
    return moved


def _overlapping_edges(chain: Any) -> float:
    """About how many pairs of the closed polyline *chain*'s edges have overlapping bounding
    boxes (the work of a test for self-crossing): counted for every so many edges
    (:data:`OVERLAP_SAMPLES` of them), scaled to all."""
    import numpy as np

    following = np.roll(chain, -1, axis=0)
    (x0, y0), (x1, y1) = np.minimum(chain, following).T, np.maximum(chain, following).T
    picked = np.arange(0, len(chain), max(1, len(chain) // OVERLAP_SAMPLES))
    count = 0
    for k in picked.tolist():
        count += int(np.count_nonzero((x0 <= x1[k]) & (x1 >= x0[k]) & (y0 <= y1[k])
                                      & (y1 >= y0[k])))
    return count / len(picked) * len(chain)


def _inside(chain: Any) -> bool:
    """True when the origin lies inside the closed polyline *chain* (even-odd rule)."""
    import numpy as np

    a, b = chain, np.roll(chain, -1, axis=0)
    straddles = (a[:, 1] > 0.0) != (b[:, 1] > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (0.0 - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(straddles & (x > 0.0)) % 2)
