"""The inspection follower: the design's, then a follower file's keys, then the command line's,
each over the one before."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab.errors import InspectionError
from camfab.inspect.values import length

if TYPE_CHECKING:
    from camfab.curves.follower import FollowerGeometry
    from camfab.design import Design
    from camfab.inspect.options import InspectOptions

#: Follower keys of a design's ``follower:`` section that the inspection follower takes.
FOLLOWER_KEYS = ("type", "motion", "offset", "roller_radius", "face_radius", "pivot_distance",
                 "arm_length", "pivot_side", "face_offset")
_LENGTH_KEYS = ("offset", "roller_radius", "face_radius", "pivot_distance", "arm_length",
                "face_offset")
#: Other keys a follower file may hold.
SETUP_KEYS = ("units", "rotation", "speed_rpm", "tolerance", "follower")
FOLLOWER_TYPES = ("knife", "roller", "flat", "mushroom")


def read_follower_file(path: Path) -> dict[str, Any]:
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


def inspection_follower(options: InspectOptions, extra: dict[str, Any],
                        design: Design | None, units: str) -> FollowerGeometry:
    """The inspection follower: the design's, then the follower file's keys, then the command
    line's, each over the one before. A refusal names where the value at fault came from: the
    follower file (and its key), the option, or the outline file when no follower is given."""
    from camfab.curves.follower import FollowerGeometry

    fields: dict[str, Any] = {}
    origin: dict[str, str] = {}  # key -> the file it came from; "" for the command line
    if design is not None:
        fol = design.follower
        fields = {"type": fol.type, "motion": fol.motion, "offset": fol.offset,
                  "roller_radius": fol.roller_radius, "face_radius": fol.face_radius,
                  "pivot_distance": fol.pivot_distance, "arm_length": fol.arm_length,
                  "pivot_side": fol.pivot_side, "face_offset": fol.face_offset}
        origin = dict.fromkeys(fields, design.source or design.name)
    file = extra.get("_file", "")
    for source, given in ((file, extra), ("", options.follower)):
        swinging = "pivot_distance" in given or "arm_length" in given
        for key in FOLLOWER_KEYS:
            if key not in given or given[key] is None:
                continue
            what = _option(key) if not source else f"{source}: {key}"
            value = given[key]
            fields[key] = (length(what, value, units, "", positive=key not in
                                  ("offset", "face_offset")) if key in _LENGTH_KEYS
                           else str(value))
            origin[key] = source
        if swinging and "motion" not in given:
            fields["motion"] = "oscillating"
            origin["motion"] = source

    def where(key: str) -> str:
        """The follower file and *key*, or the option, that gave *key*'s value."""
        return f"{origin[key]}: {key}" if origin.get(key) else _option(key)

    kind = fields.get("type")
    if kind == "spherical":
        kind = "mushroom"
    if kind is None:
        if file:
            raise InspectionError(file, "type: not given (knife, roller, flat or mushroom; or "
                                  "give --type)")
        raise InspectionError(str(options.profile), "no follower to run over the outline: use "
                              "--design, --follower FILE.yaml or --type with its dimensions "
                              "(e.g. --type roller --roller-radius 8)")
    if kind not in FOLLOWER_TYPES:
        raise InspectionError(where("type"), f"unknown follower type {kind!r} (allowed: "
                              f"{', '.join(FOLLOWER_TYPES)})")
    motion = fields.get("motion", "translating")
    if motion not in ("translating", "oscillating"):
        raise InspectionError(where("motion"), f"must be translating or oscillating (got "
                              f"{motion!r})")
    radius = 0.0
    if kind in ("roller", "mushroom"):
        key = "roller_radius" if kind == "roller" else "face_radius"
        radius = fields.get(key) or 0.0
        if radius <= 0.0:
            raise _missing(origin.get("type", ""), f"a {kind} follower", (key,), (key,))
    oscillating = motion == "oscillating"
    if oscillating and not (fields.get("pivot_distance") and fields.get("arm_length")):
        needed = ("pivot_distance", "arm_length")
        raise _missing(origin.get("motion", ""), "an oscillating follower", needed,
                       tuple(k for k in needed if not fields.get(k)))
    side = fields.get("pivot_side", "right")
    if side not in ("right", "left"):
        raise InspectionError(where("pivot_side"), f"must be right or left (got {side!r})")
    return FollowerGeometry(
        contact=kind, oscillating=oscillating, radius=radius,
        offset=0.0 if oscillating else float(fields.get("offset") or 0.0),
        pivot_distance=float(fields.get("pivot_distance") or 0.0) if oscillating else 0.0,
        arm_length=float(fields.get("arm_length") or 0.0) if oscillating else 0.0,
        pivot_sign=1 if side == "right" else -1,
        face_offset=float(fields.get("face_offset") or 0.0) if oscillating else 0.0)


def _option(key: str) -> str:
    """The command-line option of a follower key: ``roller_radius`` -> ``--roller-radius``."""
    return f"--{key.replace('_', '-')}"


def _missing(source: str, follower: str, needed: tuple[str, ...], lacking: tuple[str, ...]
             ) -> InspectionError:
    """The refusal of a *follower*, which needs the keys *needed*, lacking some (*lacking*):
    naming *source*, the file that made it such a follower (its type or motion), or the first
    missing option when the command line did."""
    if source:
        return InspectionError(source, f"{follower} needs {' and '.join(needed)} (in this "
                               f"file, or {' and '.join(_option(k) for k in needed)})")
    it = "it" if len(needed) == 1 else " and ".join(_option(k) for k in needed)
    return InspectionError(_option(lacking[0]), f"not given; {follower} needs {it}")
