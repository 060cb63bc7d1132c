"""The design models' field types: numbers with units converted as they are validated, the
immutable base model, and the errors a field's validator carries through pydantic to the loader
(which rebuilds them with the file's line)."""

from __future__ import annotations

import typing
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationInfo
from pydantic_core import PydanticCustomError

from camfab.design import units as U
from camfab.errors import DesignError


def context(info: ValidationInfo) -> dict[str, Any]:
    return info.context or {}


def converted(value: Any, kind: U.Kind, info: ValidationInfo) -> float:
    """*value* in *kind*'s internal unit in this design's units; errors carried through pydantic."""
    try:
        return U.convert(value, kind, context(info).get("units", "mm"))
    except DesignError as exc:
        raise carried(exc) from None


def lift_kind(info: ValidationInfo) -> U.Kind:
    """A lift is a length for translating followers and an angle of swing for oscillating ones."""
    return U.ANGLE if context(info).get("oscillating") else U.LENGTH


def as_kind(kind: U.Kind) -> Any:
    """A before-validator converting a design value of *kind* to internal units."""

    def convert(value: Any, info: ValidationInfo) -> Any:
        return None if value is None else converted(value, kind, info)

    convert.kind = kind  # type: ignore[attr-defined]  # what the report converts back
    return BeforeValidator(convert)


def _lift(value: Any, info: ValidationInfo) -> Any:
    """A lift, converted as its follower needs (see :func:`lift_kind`)."""
    return None if value is None else converted(value, lift_kind(info), info)


_lift.kind = "lift"  # type: ignore[attr-defined]  # a length or an angle, by the follower


def field_kind(model: type[BaseModel], name: str) -> Any:
    """The unit kind of *model*'s field *name* (a :class:`~camfab.design.units.Kind`, or
    ``"lift"``) from its converter (:func:`as_kind`), or None for a field without a unit."""
    field = model.model_fields[name]
    found: list[Any] = list(field.metadata)
    pending = [field.annotation]
    while pending:
        annotation = pending.pop()
        if typing.get_origin(annotation) is Annotated:
            found += list(annotation.__metadata__)
        pending += list(typing.get_args(annotation))
    for item in found:
        if isinstance(item, BeforeValidator):
            kind = getattr(item.func, "kind", None)
            if kind is not None:
                return kind
    return None


def problem(problem: str, allowed: Any = None, hint: str | None = None,
             kind: str = "") -> PydanticCustomError:
    """Carry a camfab message through pydantic so the loader can rebuild it with a location
    (*kind* as :class:`~camfab.errors.DesignError` has it)."""
    return PydanticCustomError(
        "camfab", "{problem}", {"problem": problem, "allowed": allowed, "hint": hint,
                                "kind": kind}
    )


def carried(exc: DesignError) -> PydanticCustomError:
    return problem(exc.problem, exc.allowed, exc.hint, exc.kind)


Length = Annotated[float, as_kind(U.LENGTH)]
PositiveLength = Annotated[float, as_kind(U.LENGTH), Field(gt=0)]
NonNegativeLength = Annotated[float, as_kind(U.LENGTH), Field(ge=0)]
PositiveAngle = Annotated[float, as_kind(U.ANGLE), Field(gt=0)]
NonNegativeAngle = Annotated[float, as_kind(U.ANGLE), Field(ge=0)]
Angle = Annotated[float, as_kind(U.ANGLE)]
Lift = Annotated[float, BeforeValidator(_lift), Field(gt=0)]


class Frozen(BaseModel):
    """Base of the design models: immutable, unknown keys rejected, no silent coercion of text."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=False, validate_default=False)
