"""Numbers with units in design files, converted once to camfab's internal units.

A design value is a bare number in its default unit or a string with a unit (``"1.5 in"``,
``"24 N/mm"``, ``"600 rpm"``). Internally camfab works in millimetres and radians; the other
quantities keep the unit their name states (``speed_rpm`` in rpm, spring ``rate`` in N/mm, a
material's ``E`` and ``limits.contact_stress`` in MPa, ``limits.roller_life`` in hours).

pint is imported only when a value carries a unit, so designs written in bare numbers load without
paying for its import.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from camfab.errors import DesignError

MM_PER_UNIT = {"mm": 1.0, "in": 25.4}


@dataclass(frozen=True)
class Kind:
    """A kind of quantity: its pint dimensionality, internal unit and default design unit."""

    name: str  # how messages call it: "a length"
    internal: str  # pint unit of the internal value
    default: str | None  # pint unit of a bare number (None: the design's length unit)
    dimensionality: str | None  # pint dimensionality to check (None: an angle, checked by name)
    examples: str
    #: Largest magnitude accepted, in the internal unit, and how messages say it. Far beyond any
    #: real cam, these bounds keep ω³·s‴ and similar products inside floating point.
    maximum: float | None = None
    maximum_text: str = ""
    #: True for a lift's derivative per radian^n of cam angle: its unit may or may not name
    #: the radians (``"5 mm/rad"`` or ``"5 mm"``; ``"0.5 rad/rad"`` cancels to a number).
    angle_rate: bool = False


LENGTH = Kind("a length", "mm", None, "[length]", "mm, in, cm, m", 1e6, "1 km")
ANGLE = Kind("an angle", "radian", "degree", None, "deg, rad, turn", 1e4, "10,000 rad")
SPEED = Kind("a rotational speed", "rpm", "rpm", "1/[time]", "rpm, rev/s, rad/s, deg/s", 1e6,
             "1,000,000 rpm")
MASS = Kind("a mass", "kg", "kg", "[mass]", "kg, g, lb", 1e6, "1,000 t")
FORCE = Kind("a force", "N", "N", "[force]", "N, kN, lbf", 1e9, "1 GN")
RATE = Kind("a spring rate", "N/mm", "N/mm", "[force]/[length]", "N/mm, N/m, lbf/in", 1e9,
            "1e9 N/mm")
DAMPING = Kind("a damping coefficient", "N*s/m", "N*s/m", "[force]*[time]/[length]", "N*s/m",
               1e9, "1e9 N·s/m")
STRESS = Kind("a stress", "MPa", "MPa", "[force]/[length]**2", "MPa, GPa, N/mm**2, psi, ksi",
              1e9, "1e9 MPa")
FEED = Kind("a feed rate", "mm/minute", None, "[length]/[time]", "mm/min, in/min, m/s", 1e9,
            "1,000 km/min")
DURATION = Kind("a duration", "hour", "hour", "[time]", "h, hour, s, day, year", 1e12,
                "1e12 h")

#: A value with a unit: a plain decimal number, then the unit (``"1.5 in"``, ``"24 N/mm"``).
_NUMBER_UNIT = re.compile(
    r"\s*[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?(?![0-9.])\s*(?P<unit>.*)", re.S)
#: A unit's one-digit power (``mm**2``, ``s^-2``) that is not itself raised to a power.
_POWER = re.compile(r"(?:\*\*|\^)\s*\(?\s*[-+]?[0-9]\s*\)?(?!\s*\)?\s*(?:\*\*|\^))")
#: What else a unit may be written with: names, products, quotients and brackets.
_UNIT_PUNCTUATION = set(" */()_·°")

_ANGLE_UNITS = ("degree", "radian", "revolution", "turn", "arcminute", "arcsecond", "gradian")


def angle_rate(order: int, lift_kind: Kind) -> Kind:
    """The kind of the *order*-th derivative of a lift of *lift_kind* per radian of cam angle."""
    per = "/radian" if order == 1 else f"/radian**{order}"
    if lift_kind is ANGLE:
        return Kind(
            f"an angle per radian{'' if order == 1 else f'^{order}'}",
            f"radian{per}", f"radian{per}", None, f"rad{per.replace('radian', 'rad')}",
            angle_rate=True,
        )
    return Kind(
        f"a length per radian{'' if order == 1 else f'^{order}'}",
        f"mm{per}", None, "[length]", f"mm{per.replace('radian', 'rad')}", angle_rate=True,
    )


@lru_cache(maxsize=1)
def registry() -> Any:
    """The shared pint registry, created on first use (it costs a few tenths of a second)."""
    import pint

    return pint.UnitRegistry()


def convert(raw: object, kind: Kind, design_units: str = "mm") -> float:
    """Convert a design value to *kind*'s internal unit.

    Parameters
    ----------
    raw
        What the design file holds: a number, or a string such as ``"1.5 in"``.
    kind
        The quantity expected (``LENGTH``, ``ANGLE``, ...).
    design_units
        The design's ``units`` (``mm`` or ``in``): the default unit of bare lengths.

    Raises
    ------
    DesignError
        Not a number, an unknown unit, or a unit of the wrong kind.
    """
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        raise DesignError(f"must be {kind.name}", got=raw, allowed=_allowed(kind),
                          kind="shape")
    if isinstance(raw, str):
        text = raw.strip()
        try:
            number = float(text)
        except ValueError:
            return _in_range(_convert_text(text, raw, kind, design_units), raw, kind)
    else:
        try:
            number = float(raw)
        except OverflowError:  # an integer too large for a float
            number = math.inf
    _check_finite(number, raw, kind)
    return _in_range(number * _default_factor(kind, design_units), raw, kind)


def _in_range(value: float, raw: object, kind: Kind) -> float:
    if kind.maximum is not None and abs(value) > kind.maximum:
        raise DesignError(f"is out of range for {kind.name} (at most {kind.maximum_text})", got=raw)
    return value


def _convert_text(text: str, raw: str, kind: Kind, design_units: str) -> float:
    if not any(ch.isdigit() for ch in text):  # empty, or words: not a quantity
        raise DesignError(f"must be {kind.name}", got=raw, allowed=_allowed(kind),
                          kind="shape")
    if not _number_and_unit(text):
        raise DesignError(
            f"must be {kind.name} (a number, optionally with a unit)", got=raw,
            allowed=_allowed(kind),
        )
    ureg = registry()
    try:
        quantity = ureg.Quantity(text)
    except Exception as exc:  # pint's parser raises many types on free text; all mean "bad value"
        unknown = getattr(exc, "unit_names", None)
        if unknown:
            name = unknown if isinstance(unknown, str) else ", ".join(map(str, unknown))
            raise DesignError(
                f"unknown unit '{name}'", got=raw, allowed=_allowed(kind)
            ) from None
        raise DesignError(
            f"must be {kind.name} (a number, optionally with a unit)", got=raw,
            allowed=_allowed(kind),
        ) from None
    if not hasattr(quantity, "magnitude"):  # a plain number came back
        return convert(float(quantity), kind, design_units)
    try:
        magnitude = float(quantity.magnitude)
    except OverflowError:  # an integer too large for a float
        magnitude = math.inf
    except (TypeError, ValueError):
        raise DesignError(f"must be {kind.name}", got=raw, allowed=_allowed(kind),
                          kind="shape") from None
    _check_finite(magnitude, raw, kind)
    _check_unit_names(quantity, raw, kind)
    if not _has_kind(quantity, kind):
        raise DesignError(
            f"must be {kind.name}, not {_describe(quantity)}", got=raw, allowed=_allowed(kind)
        )
    return float(quantity.to(kind.internal).magnitude)


def _number_and_unit(text: str) -> bool:
    """True when *text* is a plain number followed by a unit built of names, products, quotients
    and one-digit powers. pint evaluates whatever it is given as arithmetic: ``"10**10**10 mm"``
    would never finish and ``"[1,2] mm"`` would read as 12 mm."""
    match = _NUMBER_UNIT.fullmatch(text)
    if match is None:
        return False
    unit = _POWER.sub(" ", match["unit"])
    return all(ch.isalpha() or ch in _UNIT_PUNCTUATION for ch in unit)


#: Units of turning, and how many angles each holds (rpm is one angle per time).
_TURNING = {**dict.fromkeys(_ANGLE_UNITS, 1), "revolutions_per_minute": 1,
            "revolutions_per_second": 1}


def _check_unit_names(quantity: Any, raw: str, kind: Kind) -> None:
    """Refuse a unit that says nothing (``"5 mm**0"``, ``"5 turn/revolution"``: pint cancels
    them to a bare number) and dimensionless names that are not angles (``percent``, ``ppm``,
    ``pi``, ``count``): pint would take ``"5 percent"`` as 0.05 of nothing and ``"5 pi*mm"`` as
    15.7 mm, arithmetic that a design's numbers do not do."""
    items = list(quantity.unit_items())
    if not items and not kind.angle_rate:
        raise DesignError(f"must be {kind.name}; the unit cancels out to a bare number",
                          got=raw, allowed=_allowed(kind))
    ureg = registry()
    for name, _power in items:
        if name not in _TURNING and not ureg.get_dimensionality(name):
            raise DesignError(f"must be {kind.name}; '{name}' is a pure number, not a unit",
                              got=raw, allowed=_allowed(kind))


def _angle_power(quantity: Any) -> float:
    """How many angles the unit of *quantity* holds: 1 for deg or rpm, 2 for deg², 0 for mm."""
    return sum(power * _TURNING.get(name, 0) for name, power in quantity.unit_items())


def _has_kind(quantity: Any, kind: Kind) -> bool:
    if kind.angle_rate:  # per radian^n: the radians may be written or not
        if kind.dimensionality is None:
            return bool(quantity.dimensionless)
        return bool(quantity.check(kind.dimensionality))
    if kind.dimensionality is None:  # an angle: dimensionless in pint, one power of an angle
        return bool(quantity.dimensionless) and _angle_power(quantity) == 1
    if kind is SPEED:
        # rpm is revolution/minute; a bare frequency (Hz, 1/s) does not say what turns.
        return bool(quantity.check(kind.dimensionality)) and _angle_power(quantity) == 1
    return bool(quantity.check(kind.dimensionality)) and _angle_power(quantity) == 0


def _describe(quantity: Any) -> str:
    dims = str(quantity.dimensionality)
    return f"'{quantity.units:~}' ({dims})" if dims != "dimensionless" else f"'{quantity.units:~}'"


def _default_factor(kind: Kind, design_units: str) -> float:
    if kind.default is None:  # a length or a length rate: the design's length unit
        return MM_PER_UNIT[design_units]
    if kind is ANGLE:
        return math.pi / 180.0
    return 1.0


def _check_finite(value: float, raw: object, kind: Kind) -> None:
    if not math.isfinite(value):
        raise DesignError(f"must be a finite number ({kind.name})", got=raw)


def _allowed(kind: Kind) -> str:
    return f"a number or a string with a unit such as {kind.examples}"
