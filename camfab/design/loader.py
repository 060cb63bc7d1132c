"""Load a design: YAML with lines -> structural checks -> models -> rules.

Every problem becomes one :class:`~camfab.errors.DesignError` naming the file, the line, the field
and what is wrong. When a file has several problems, the one nearest the top is reported.
"""

from __future__ import annotations

import errno
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

from pydantic import ValidationError

from camfab.design.cam_types import CAM_TYPES, CamTypeSpec
from camfab.design.model import NAME_RULE, UNION_TAGS, Design, Sized
from camfab.design.rules import RuleViolation
from camfab.design.source import Path_, SourceDocument, dotted, parse_yaml, read_design_file
from camfab.design.units import MM_PER_UNIT
from camfab.errors import DesignError, Location, did_you_mean

SEGMENT_KINDS = {"rise": "rise", "return": "return", "fall": "return", "dwell": "dwell"}

_TOP = ("name", "description", "units", "cam", "follower", "motion", "motion_target", "spring",
        "limits", "materials", "manufacturing", "inspection", "machining", "sizing", "outputs",
        "table_step")
_SECTIONS: dict[str, tuple[str, ...]] = {
    "spring": ("rate", "preload", "initial_compression", "gravity", "damping", "external_load"),
    "limits": ("pressure_angle", "min_radius_of_curvature", "contact_stress", "roller_life"),
    "materials": ("cam", "follower"),
    "manufacturing": ("tolerance", "kerf", "cutter_radius"),
    "inspection": ("tolerance",),
    "machining": ("tool_diameter", "flutes", "cut_length", "spindle_rpm", "feed", "plunge_feed",
                  "step_down", "finish_allowance", "safe_z", "direction", "compensation",
                  "dialect", "machine",
                  "wheel_diameter"),
    "sizing": ("round_to",),
}
#: The keys a design may leave to camfab with ``auto`` (``section.key``), each where its cam
#: type sizes it (:attr:`~camfab.design.cam_types.CamTypeSpec.auto_keys`).
AUTO_KEYS = ("cam.base_radius", "cam.radius", "follower.offset")
#: Largest table law CSV file (bytes) and most rows it may hold: a lift measured every 0.1° is
#: 3,600 rows; the quintic spline through the points costs time in proportion to their count.
MAX_TABLE_BYTES = 1_000_000
MAX_TABLE_ROWS = 20_000

_KEYWAY = ("width", "depth")
_MACHINE = ("b_axis_x", "b_axis_z")
_ELASTIC = ("E", "poisson")
_CONDITIONS = ("velocity", "acceleration", "jerk", "snap")
_LAW_KEYS = {
    "modified-uniform-velocity": ("blend",),
    "polynomial": ("start", "end", "points"),
    "table": ("start", "end", "points", "csv"),
    "spline": ("order", "controls", "start", "end"),
}


#: Checks a higher layer runs on a design the file's own rules accept (the rules of its cam kind
#: that need the kind's geometry), raising :class:`~camfab.design.rules.RuleViolation` as the
#: rules do: reported on the line of the key they name like any other.
Checks = Callable[[Design], None]

#: A higher layer's sizing of a design that leaves keys to camfab (``auto``): given the design
#: checked without them (see :func:`~camfab.design.rules.check_rules`) and those keys
#: (``section.key``), the values it chose and why, in millimetres; it raises
#: :class:`~camfab.design.rules.RuleViolation` on a key no value of which meets the limits
#: (:func:`camfab.pipeline.load_design` passes camfab's).
Sizer = Callable[[Design, frozenset[str]], Sized]


def load_design(path: str | Path, checks: Checks | None = None,
                sizer: Sizer | None = None) -> Design:
    """Read, check and return the design in file *path* (raises DesignError/DesignFileError):
    the design file's rules, then *checks* (:func:`camfab.pipeline.load_design` passes the cam
    kind's); the keys it gives as ``auto`` sized by *sizer* first."""
    return _validate(read_design_file(path), checks, sizer)


def design_from_text(text: str, file: str = "<design>", folder: Path = Path("."),
                     checks: Checks | None = None, sizer: Sizer | None = None) -> Design:
    """The design in YAML *text* (for tests and tools; *file* names it in messages)."""
    return _validate(parse_yaml(text, file, folder), checks, sizer)


def design_from_mapping(data: dict[str, Any], file: str = "<design>",
                        checks: Checks | None = None, sizer: Sizer | None = None,
                        folder: Path = Path(".")) -> Design:
    """A design from already-parsed data (no line numbers in messages), the files it names
    (a table law's) found from *folder*."""
    if not isinstance(data, dict):
        raise DesignError("a design must be a mapping of keys", location=Location(file, None, ""),
                          got=data)
    return _validate(SourceDocument(file=file, data=_text_keys(data), folder=folder), checks,
                     sizer)


def design_from_document(doc: SourceDocument, checks: Checks | None = None,
                         sizer: Sizer | None = None) -> Design:
    """The design of the parsed document *doc* (a file's, or one with a shop's machining
    settings merged in: :func:`camfab.design.shop.with_shop`), checked as :func:`load_design`
    checks a file's."""
    return _validate(doc, checks, sizer)


def unsized_design(path: str | Path, keys: frozenset[str],
                   text: str | None = None) -> tuple[Design, frozenset[str]]:
    """The design in file *path* (or in its *text*, when given: an edit not saved yet) checked
    without the keys it gives as ``auto`` and without *keys* (those of them its cam type sizes,
    whatever the file gives), for a sizing: the design and the keys left out (raises
    DesignError/DesignFileError)."""
    path = Path(path)
    doc = read_design_file(path) if text is None else parse_yaml(text, str(path), path.parent)
    shaped = Shaper(doc)
    data = shaped.run()
    spec = CAM_TYPES.get(_text(_get(data, "cam", "type")) or "")
    if spec is not None and not spec.auto_keys:
        _not_sizable(shaped, spec)
    asked = frozenset(k for k in keys if spec is not None and k in spec.auto_keys)
    auto = _auto_keys(data, shaped) | asked
    try:
        return _model(_without(data, auto), doc, shaped, auto), auto
    except RuleViolation as exc:
        raise _rule_error(exc, doc, shaped) from None


def _text_keys(value: Any, depth: int = 0) -> Any:
    """*value* with every mapping key as text, as the YAML loader gives them."""
    if depth > 50:
        raise DesignError("nested too deeply (or a structure that contains itself)")
    if isinstance(value, dict):
        return {str(k): _text_keys(v, depth + 1) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_text_keys(v, depth + 1) for v in value]
    return value


def _validate(doc: SourceDocument, checks: Checks | None = None,
              sizer: Sizer | None = None) -> Design:
    shaped = Shaper(doc)
    data = shaped.run()
    auto = _auto_keys(data, shaped)
    try:
        sized = None
        if auto:
            if sizer is None:
                key = sorted(auto)[0]
                shaped.fail(tuple(key.split(".")), "auto asks camfab to size it, which camfab "
                            "build, check and size do")
            sized = sizer(_model(_without(data, auto), doc, shaped, auto), auto)
            data = _with_sizes(data, sized)
        design = _model(data, doc, shaped, sized=sized)
        if checks is not None:
            checks(design)
    except RuleViolation as exc:
        raise _rule_error(exc, doc, shaped) from None
    return design


def _model(data: dict[str, Any], doc: SourceDocument, shaped: Shaper,
           sizing: frozenset[str] = frozenset(), sized: Sized | None = None) -> Design:
    """The design model of the shaped *data*, its rules checked (those that need the keys in
    *sizing* left for the sized design); pydantic's errors as camfab's."""
    oscillating = _text(_get(data, "follower", "motion")) == "oscillating"
    units = _text(data.get("units"))
    units = units if units in ("mm", "in") else "mm"
    context = {"units": units, "oscillating": oscillating, "sizing": sizing}
    data = _with_type_tolerance(data, units)
    try:
        return Design.model_validate({**data, "source": doc.file, "sized": sized},
                                     context=context)
    except ValidationError as exc:
        raise first_error(exc, doc, shaped) from None


def _with_type_tolerance(data: dict[str, Any], units: str) -> dict[str, Any]:
    """*data* with its cam type's own export tolerance where the design gives none
    (:attr:`~camfab.design.cam_types.CamTypeSpec.default_tolerance`), in the design's
    *units*."""
    spec = CAM_TYPES.get(_text(_get(data, "cam", "type")) or "")
    made = data.get("manufacturing", {})
    if spec is None or spec.default_tolerance is None or not isinstance(made, dict) \
            or "tolerance" in made:
        return data
    tolerance = spec.default_tolerance / MM_PER_UNIT[units]
    return {**data, "manufacturing": {**made, "tolerance": tolerance}}


def _rule_error(exc: RuleViolation, doc: SourceDocument, shaped: Shaper) -> DesignError:
    """A broken rule as camfab's message on the line of the key it names."""
    yaml_path = shaped.yaml_path(exc.path)
    got = doc.value_at(yaml_path) if exc.show_got else None
    return DesignError(
        exc.error.problem,
        location=doc.locate(yaml_path, dotted(exc.path)),
        got=got,
        allowed=exc.error.allowed,
        hint=exc.error.hint,
        show_got=exc.show_got and got is not None,
    )


def _auto_keys(data: dict[str, Any], shaped: Shaper) -> frozenset[str]:
    """The keys the design gives as ``auto`` (``section.key``); one its cam type does not size
    is reported on its line."""
    spec = CAM_TYPES.get(_text(_get(data, "cam", "type")) or "")
    found = set()
    for key in AUTO_KEYS:
        path = tuple(key.split("."))
        value = _get(data, *path)
        if not (isinstance(value, str) and value.strip().lower() == "auto"):
            continue
        if spec is None:
            continue  # the cam type itself is reported
        if key not in spec.auto_keys:
            _not_sized(shaped, path, spec)
        found.add(key)
    return frozenset(found)


def _not_sizable(shaped: Shaper, spec: CamTypeSpec) -> NoReturn:
    """Refuse to size a cam of a type camfab does not size, on its ``cam.type`` line."""
    sized = {key: [name for name, row in CAM_TYPES.items() if key in row.auto_keys]
             for key in ("cam.base_radius", "cam.radius")}
    reason = ": its shape sets its motion" if spec.shaped else ""
    shaped.fail(("cam", "type"), f"a {spec.name} cam is not sized{reason}; camfab sizes the "
                f"base radius of {', '.join(sized['cam.base_radius'])} cams and the radius of "
                f"{', '.join(sized['cam.radius'])} (drum) cams", show_got=False)


def _not_sized(shaped: Shaper, path: tuple[str, ...], spec: CamTypeSpec) -> NoReturn:
    key = f"{path[0]}.{path[1]}"
    sizable = [name for name, row in CAM_TYPES.items() if key in row.auto_keys]
    reason = ("its shape sets its motion; " if spec.shaped else
              "it is not a radius camfab sizes; " if spec.auto_keys else "")
    shaped.fail(path, f"a {spec.name} cam's {path[1]} cannot be sized: {reason}camfab sizes "
                f"{key} of {', '.join(sizable) or 'no'} cams", show_got=False)


def _without(data: dict[str, Any], keys: frozenset[str]) -> dict[str, Any]:
    """*data* without *keys* (``section.key``)."""
    out = dict(data)
    for key in keys:
        section, name = key.split(".")
        if isinstance(out.get(section), dict):
            out[section] = {k: v for k, v in out[section].items() if k != name}
    return out


def _with_sizes(data: dict[str, Any], sized: Sized) -> dict[str, Any]:
    """*data* with the values of *sized* (mm) in the design's units."""
    per_unit = MM_PER_UNIT.get(_text(data.get("units")) or "mm", 1.0)
    out = dict(data)
    for key, value in (("cam.base_radius", sized.base_radius), ("cam.radius", sized.radius),
                       ("follower.offset", sized.offset)):
        if value is None:
            continue
        section, name = key.split(".")
        out[section] = {**out.get(section, {}), name: value / per_unit}
    return out


def _get(data: Any, *keys: str) -> Any:
    for key in keys:
        if not isinstance(data, dict):
            return None
        data = data.get(key)
    return data


def _text(value: Any) -> str | None:
    """*value* when it is text (a type name to look up), else None: other values are reported by
    the model's own validation."""
    return value if isinstance(value, str) else None


class Shaper:
    """Structural pass: unknown keys (with suggestions), motion segments flattened, CSV read."""

    def __init__(self, doc: SourceDocument) -> None:
        self.doc = doc
        self.segment_keys: dict[int, str] = {}
        self.span = "angle"  # what a segment gives its length in: its cam type's

    def yaml_path(self, model_path: Path_) -> Path_:
        """Where a model path is in the file: ``motion[i].x`` lives under the segment's key."""
        path = tuple(model_path)
        if len(path) >= 2 and path[0] == "motion" and isinstance(path[1], int):
            key = self.segment_keys.get(path[1])
            if key is not None:
                return (path[0], path[1], key, *path[2:])
        return path

    def fail(self, path: Path_, problem: str, **kwargs: Any) -> NoReturn:
        """Refuse the file's shape at *path*: a key, a type, a unit, a name (``kind`` shape)."""
        yaml_path = self.yaml_path(path)
        kwargs.setdefault("kind", "shape")
        raise DesignError(problem, location=self.doc.locate(yaml_path, dotted(path)), **kwargs)

    def keys(self, mapping: Any, allowed: tuple[str, ...], path: Path_, what: str) -> None:
        if not isinstance(mapping, dict):
            return
        for key in mapping:
            if key not in allowed:
                self.fail((*path, key), f"unknown key in {what}",
                          hint=did_you_mean(key, allowed), allowed=", ".join(allowed))

    def run(self) -> dict[str, Any]:
        data = dict(self.doc.data)
        self.keys(data, _TOP, (), "the design")
        cam_type = _text(_get(data, "cam", "type"))
        spec = CAM_TYPES.get(cam_type) if cam_type is not None else None
        if spec is not None:
            self.keys(data["cam"], spec.cam_keys, ("cam",), f"a {cam_type} cam")
            self.keys(_get(data, "cam", "keyway"), _KEYWAY, ("cam", "keyway"), "keyway")
        self.keys(_get(data, "machining", "machine"), _MACHINE, ("machining", "machine"),
                  "a globoid's machine")
        follower = data.get("follower")
        if isinstance(follower, dict):
            self.keys(follower, follower_keys(spec, follower), ("follower",),
                      _follower_label(follower))
        for section, allowed in _SECTIONS.items():
            self.keys(data.get(section), allowed, (section,), section)
        for part in ("cam", "follower"):
            self.keys(_get(data, "materials", part), _ELASTIC, ("materials", part),
                      "a material's constants")
        if "motion" in data:
            self.span = spec.span if spec is not None else "angle"
            data["motion"] = self._motion(data["motion"])
        return data

    def _motion(self, motion: Any) -> Any:
        if not isinstance(motion, list):
            self.fail(("motion",), "must be a list of segments (rise, dwell, return)",
                      got=motion)
        out = []
        for i, item in enumerate(motion):
            if not isinstance(item, dict) or len(item) != 1:
                self.fail(("motion", i), "each segment is a one-key map such as "
                          "'- rise: {angle: 120, lift: 40, law: harmonic}'", got=item)
            (key, body), = item.items()
            if key not in SEGMENT_KINDS:
                self.fail(("motion", i), f"unknown segment kind '{key}'",
                          hint=did_you_mean(key, list(SEGMENT_KINDS), cutoff=0.5),
                          allowed="rise, return (fall), dwell")
            kind = SEGMENT_KINDS[key]
            self.segment_keys[i] = key
            if not isinstance(body, dict):
                self.fail(("motion", i), f"a {key} needs its data as a mapping "
                          "(angle, lift, law)", got=body)
            self._segment_params(i, kind, body)
            self.keys(body, segment_keys(kind, body.get("law"), self.span), ("motion", i),
                      f"a {kind}")
            for end in ("start", "end"):
                self.keys(body.get(end), _CONDITIONS, ("motion", i, end), "boundary conditions")
            body = dict(body)
            if "csv" in body:
                body["points"] = self._csv(i, body["csv"])
            out.append({"kind": kind, **body})
        return out

    def _segment_params(self, i: int, kind: str, body: dict[str, Any]) -> None:
        """Parameters that belong to other laws, named as such rather than as unknown keys."""
        allowed = segment_keys(kind, body.get("law"), self.span)
        for key in body:
            if key in allowed:
                continue
            if key in ("angle", "travel"):
                self.fail(("motion", i, key), "a linear cam's segments give their travel (a "
                          "length along the cam), not an angle" if self.span == "travel" else
                          "only a linear cam's segments give a travel; this cam's give an angle")
            if kind == "dwell" and key in ("lift", "law"):
                self.fail(("motion", i, key), "a dwell has only an angle (no lift or law)")
            if any(key in params for params in _LAW_KEYS.values()):
                from camfab.motion.laws import laws_taking

                self.fail(("motion", i, key), f"only {laws_taking(key)} '{key}'",
                          got=body.get("law"))

    def _csv(self, index: int, name: Any) -> list[list[str]]:
        path = ("motion", index, "csv")
        if not isinstance(name, str) or not name.strip():
            self.fail(path, "must be the path of a CSV file of angle, displacement rows", got=name)
        if "points" in self.doc.value_at(self.yaml_path(("motion", index))):
            self.fail(path, "give either points or csv, not both")
        text = self._table_text(path, name)
        rows: list[list[str]] = []
        for number, line in enumerate(text.splitlines(), start=1):
            cells = [c.strip() for c in line.replace(";", ",").split(",")]
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            if len(cells) < 2:
                self.fail(path, f"row {number} of {name} needs two columns: angle, displacement")
            try:
                float(cells[0].split()[0])
            except (ValueError, IndexError):
                if not rows:
                    continue  # a header row
                self.fail(path, f"row {number} of {name} is not a number: {line.strip()[:40]!r}")
            rows.append(cells[:2])
            if len(rows) > MAX_TABLE_ROWS:
                self.fail(path, f"{name} has more than {MAX_TABLE_ROWS:,} rows; a table law "
                          "takes at most that many points")
        return rows

    def _table_text(self, path: Path_, name: str) -> str:
        """The text of a table law's CSV file *name*: a regular file of at most
        :data:`MAX_TABLE_BYTES` in the design file's folder or below it."""
        from camfab.errors import InputFileError
        from camfab.files import read_bounded

        if "\0" in name:  # no file system takes one; Python refuses it before asking
            self.fail(path, "must be the path of a CSV file, and a path holds no NUL character",
                      got=name)
        shown = name if name.isprintable() else repr(name)
        try:
            folder = self.doc.folder.resolve()
            file = (folder / name).resolve()
        except (OSError, RuntimeError) as exc:  # a symbolic link loop: RuntimeError before 3.13
            problem = (os.strerror(errno.ELOOP) if isinstance(exc, RuntimeError)
                       else exc.strerror or str(exc))
            self.fail(path, f"cannot read the table: {shown} cannot be read ({problem})")
        if Path(name).is_absolute() or not file.is_relative_to(folder):
            self.fail(path, "must name a file in the design file's folder or below it (a "
                      "relative path such as 'lift.csv' or 'data/lift.csv')", got=name)
        try:
            return read_bounded(file, MAX_TABLE_BYTES, "a table").decode("utf-8-sig")
        except InputFileError as exc:
            self.fail(path, f"cannot read the table: {shown} {exc.problem}")
        except UnicodeDecodeError:
            self.fail(path, f"cannot read the table: {shown} is not a UTF-8 text file")


def follower_keys(spec: CamTypeSpec | None, follower: dict[str, Any]) -> tuple[str, ...]:
    """The keys the *follower* section takes: its type's and motion's, and its cam type's."""
    ftype = _text(follower.get("type"))
    ftype = "mushroom" if ftype == "spherical" else ftype
    motion = _text(follower.get("motion", "translating"))
    keys = ["type", "motion", "mass", "stiffness", "damping_ratio"]
    if motion == "oscillating":
        keys += ["pivot_distance", "arm_length", "pivot_side"]
        if ftype == "flat":
            keys.append("face_offset")
    else:
        keys.append("offset")
    keys += {"roller": ["roller_radius", "roller_length", "roller_load_rating",
                        "roller_bearing"],
             "mushroom": ["face_radius"], "flat": ["face_width"]}.get(ftype or "", [])
    if spec is not None:
        keys += spec.follower_keys(motion == "oscillating")
    if ftype not in ("knife", "roller", "flat", "mushroom") or motion not in (
            "translating", "oscillating"):
        # the type itself is wrong: accept every follower key and let the type error speak
        keys = ["type", "motion", "mass", "stiffness", "damping_ratio", "offset",
                "roller_radius", "roller_length", "roller_load_rating", "roller_bearing",
                "face_radius", "face_width", "pivot_distance", "arm_length", "pivot_side",
                "face_offset", "groove_clearance", "roller_spacing", "arm_angle", "rest_angle"]
    return tuple(dict.fromkeys(keys))


def _follower_label(follower: dict[str, Any]) -> str:
    motion = _text(follower.get("motion", "translating")) or "translating"
    article = "an" if motion[:1] in "aeiou" else "a"
    return f"{article} {motion} {_text(follower.get('type')) or ''} follower"


def segment_keys(kind: str, law: Any, span: str = "angle") -> tuple[str, ...]:
    """The keys a segment takes: its *span* (an angle, or a sliding cam's travel), and its
    law's."""
    if kind == "dwell":
        return (span,)
    from camfab.motion.laws import canonical_law_name

    name = canonical_law_name(law) if isinstance(law, str) else None
    if name is None:  # an unknown law is reported on its own; accept every law's parameters
        return (span, "lift", "law", "blend", "start", "end", "points", "csv", "order",
                "controls")
    return (span, "lift", "law", *_LAW_KEYS.get(name, ()))


_PYDANTIC_PROBLEMS = {
    "missing": "required",
    "extra_forbidden": "unknown key",
    "string_type": "must be text",
    "model_type": "must be a mapping of keys",
    "model_attributes_type": "must be a mapping of keys",
    "dict_type": "must be a mapping of keys",
    "tuple_type": "must be a list",
    "list_type": "must be a list",
    "float_type": "must be a number",
    "float_parsing": "must be a number",
    "bool_type": "must be true or false",
    "bool_parsing": "must be true or false",
    "string_too_short": "must not be empty",
    "string_too_long": "is too long",
    "too_short": "must not be empty",
}


def first_error(exc: ValidationError, doc: SourceDocument, shaped: Shaper) -> DesignError:
    """The pydantic error nearest the top of the file, as a camfab message."""
    best: tuple[int, DesignError] | None = None
    for err in exc.errors(include_url=False):
        loc = tuple(p for p in err["loc"] if isinstance(p, int) or (
            "[" not in str(p) and p not in UNION_TAGS))
        if loc and loc[-1] in ("float", "str", "function-before", "tagged-union"):
            loc = loc[:-1]
        yaml_path = shaped.yaml_path(loc)
        location = doc.locate(yaml_path, dotted(loc))
        line = location.line
        problem, allowed, hint = _describe(err)
        got = doc.value_at(yaml_path)
        error = DesignError(
            problem,
            location=location,
            got=got,
            allowed=allowed,
            hint=hint,
            show_got=err["type"] != "missing" and got is not None,
            kind=(err.get("ctx") or {}).get("kind", "") if err["type"] == "camfab"
            else err["type"],
        )
        key = line if line is not None else 10**9
        if best is None or key < best[0]:
            best = (key, error)
    assert best is not None
    return best[1]


def _describe(err: Any) -> tuple[str, Any, str | None]:
    kind = err["type"]
    ctx = err.get("ctx") or {}
    if kind == "camfab":
        return ctx.get("problem", err["msg"]), ctx.get("allowed"), ctx.get("hint")
    if kind == "literal_error":
        expected = str(ctx.get("expected", ""))
        choices = [c.strip(" '\"") for c in expected.replace(" or ", ", ").split(",") if c.strip()]
        return ("unknown value", ", ".join(choices),
                did_you_mean(str(err.get("input")), choices, cutoff=0.5))
    if kind == "greater_than":
        return f"must be > {ctx.get('gt')}", None, None
    if kind == "greater_than_equal":
        return f"must be ≥ {ctx.get('ge')}", None, None
    if kind == "less_than_equal":
        return f"must be ≤ {ctx.get('le')}", None, None
    if kind == "string_pattern_mismatch":
        return NAME_RULE, None, None  # (the name's is the one pattern of the design file)
    if kind in _PYDANTIC_PROBLEMS:
        return _PYDANTIC_PROBLEMS[kind], None, None
    msg = str(err.get("msg", "is invalid"))
    return msg[:1].lower() + msg[1:], None, None
