"""Every input of a design, as the report records it: each key of the design model (defaults
included) that the design file takes for its cam type and follower — its ``cam:`` section's
keys and its follower's (type, motion and cam type), as the loader lists them, so a drum shows
no ``pivot_side`` and a translating follower no arm — in the design's units: lengths in its
``units``, angles and oscillating lifts in degrees, the other quantities in the units their
keys state (rpm, kg, N, N/mm, N·s/m); and a follower block of every follower dimension in
millimetres and degrees."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel

from camfab.design import units as U
from camfab.design.fields import field_kind as _kind  # the unit kind of a model's field

if TYPE_CHECKING:
    from camfab.design import Design

#: Keys of the model that are not inputs of the design file.
_NOT_INPUTS = ("source", "sized")

#: The boundary conditions' keys: derivatives of the lift per radian^n of cam angle.
_RATES = {"velocity": 1, "acceleration": 2, "jerk": 3}


def _value(value: Any, kind: Any, design: Design) -> Any:
    """An internal value of *kind* in the design's units."""
    if value is None or kind is None or isinstance(value, str):
        return value
    if kind == "lift":
        kind = U.ANGLE if design.follower.oscillating else U.LENGTH
    if kind is U.LENGTH:
        return value / design.mm_per_unit
    if kind is U.ANGLE:
        return math.degrees(value)
    return value


def accepted_keys(design: Design) -> dict[str, tuple[str, ...]]:
    """The keys the design file takes in its ``cam`` and ``follower`` sections for the cam
    type and follower of *design*: the loader's lists (the cam type's row, the follower's type
    and motion)."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import follower_keys

    spec = CAM_TYPES[design.cam.type]
    fol = design.follower
    return {"cam": spec.cam_keys,
            "follower": follower_keys(spec, {"type": fol.type, "motion": fol.motion})}


def _model(model: BaseModel, design: Design,
           keys: dict[str, tuple[str, ...]] | None = None) -> dict[str, Any]:
    """The fields of *model* in the design's units; of a section named in *keys*, only the
    fields the design file takes there."""
    out: dict[str, Any] = {}
    for name in type(model).model_fields:
        if name in _NOT_INPUTS:
            continue
        value = getattr(model, name)
        if isinstance(value, BaseModel):
            section = _model(value, design)
            if keys is not None and name in keys:
                section = {k: v for k, v in section.items() if k in keys[name]}
            out[name] = section
        elif isinstance(value, tuple) and value and isinstance(value[0], BaseModel):
            out[name] = [_model(item, design) for item in value]
        elif name == "points" and value is not None:
            lift = U.ANGLE if design.follower.oscillating else U.LENGTH
            out[name] = [[math.degrees(a), _value(s, lift, design)] for a, s in value]
        elif name in _RATES and isinstance(value, float):
            # per radian^n of cam angle: a length in the design's units, or an angle in rad
            out[name] = value if design.follower.oscillating else value / design.mm_per_unit
        elif isinstance(value, tuple):
            out[name] = list(value)
        else:
            out[name] = _value(value, _kind(type(model), name), design)
    return out


def _label(kind: Any, design: Design) -> str | None:
    """The unit of a value of *kind* in :func:`design_record` (None: a pure number or text)."""
    if kind == "lift":
        kind = U.ANGLE if design.follower.oscillating else U.LENGTH
    if kind is U.LENGTH:
        return design.units
    return {U.ANGLE: "deg", U.SPEED: "rpm", U.MASS: "kg", U.FORCE: "N", U.RATE: "N/mm",
            U.DAMPING: "N·s/m", U.STRESS: "MPa", U.DURATION: "h"}.get(kind)


def record_units(design: Design) -> dict[str, str]:
    """The unit of every input of :func:`design_record` that has one, by its dotted key
    (``follower.mass``, ``motion[0].lift``, ``materials.cam.E``): the design's length unit,
    degrees, or the unit its key states."""
    units = _units(design, design, "")
    return {key: units[key] for key in _keys(design_record(design)) if key in units}


def _keys(record: dict[str, Any], prefix: str = "") -> list[str]:
    """The dotted keys of *record*'s values, nested sections ``a.b``, lists of them ``a[0].b``."""
    out: list[str] = []
    for key, value in record.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out += _keys(value, f"{name}.")
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for i, item in enumerate(value):
                out += _keys(item, f"{name}[{i}].")
        else:
            out.append(name)
    return out


def _units(model: BaseModel, design: Design, prefix: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for name in type(model).model_fields:
        if name in _NOT_INPUTS:
            continue
        value, key = getattr(model, name), f"{prefix}{name}"
        if isinstance(value, BaseModel):
            out.update(_units(value, design, f"{key}."))
        elif isinstance(value, tuple) and value and isinstance(value[0], BaseModel):
            for i, item in enumerate(value):
                out.update(_units(item, design, f"{key}[{i}]."))
        elif name in _RATES:
            base = "rad" if design.follower.oscillating else design.units
            out[key] = f"{base}/rad{('', '', '²', '³')[_RATES[name]]}"
        else:
            unit = _label(_kind(type(model), name), design)
            if unit is not None:
                out[key] = unit
    return out


def design_record(design: Design) -> dict[str, Any]:
    """Every key of *design* that the design file takes for its cam type and follower
    (:func:`accepted_keys`), in the design's units."""
    return _model(design, design, accepted_keys(design))


def follower_record(design: Design) -> dict[str, Any]:
    """The follower: its type and motion, and every dimension (``_mm``, ``_deg``, ``_kg``,
    ``_N_per_mm``, ``_N``)."""
    fol = design.follower
    out: dict[str, Any] = {"type": fol.type, "motion": fol.motion}
    for name in type(fol).model_fields:
        if name in ("type", "motion"):
            continue
        value = getattr(fol, name)
        kind = _kind(type(fol), name)
        suffix = {U.LENGTH: "_mm", U.ANGLE: "_deg", U.MASS: "_kg", U.RATE: "_N_per_mm",
                  U.FORCE: "_N"}.get(kind, "")
        if kind is U.ANGLE and value is not None:
            value = math.degrees(value)
        out[f"{name}{suffix}"] = value
    out["trace_radius_mm"] = fol.trace_radius
    return out
