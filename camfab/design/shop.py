"""A shop's machining settings in a file of their own (``camfab build --machining shop.yaml``),
merged into a design's ``machining:`` section key by key: the design's own keys win, the shop's
fill in the rest.

The file holds a ``machining:`` section as a design file does, with the same keys, and may
give its ``units`` (``mm``, the default, or ``in``) as a design file does: its bare lengths are
in them, and its feeds in them per minute, whatever the design's units. So a section copies
between a design and a shop file unchanged, and a shop's file means the same tool for a
design in inches as for one in millimetres::

    units: mm
    machining:
      tool_diameter: 6
      feed: 800
      spindle_rpm: 12000

Every problem is one line naming the file it is in, its line and the key: the shop file's own
keys and values as it is read (:func:`read_shop`), and a rule of the design file that a setting
from the shop file breaks for one design (a tool wider than that design's groove) on the shop
file's line, naming the design (:class:`ShopDocument`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from pydantic import ValidationError

from camfab.design import units as U
from camfab.design.fields import Frozen, PositiveLength, field_kind
from camfab.design.loader import Shaper, first_error  # the design file's own reading
from camfab.design.machining import Machining, PositiveFeed
from camfab.design.source import (
    MAX_DESIGN_BYTES,
    Path_,
    SourceDocument,
    compose_yaml,
    dotted,
)
from camfab.errors import DesignError, DesignFileError, InputFileError, Location, did_you_mean

#: The keys of a shop's settings file.
SHOP_KEYS = ("units", "machining")
#: The keys of its ``machining:`` section: the design file's.
MACHINING_KEYS = tuple(Machining.model_fields)


class ShopMachining(Machining):
    """A shop file's ``machining:`` section: a design's, every key optional (the design may
    give the tool and the feed itself)."""

    tool_diameter: PositiveLength | None = None  # type: ignore[assignment]
    feed: PositiveFeed | None = None  # type: ignore[assignment]


class ShopSettings(Frozen):
    """A shop's settings file: its ``units`` and its ``machining:`` section."""

    units: Literal["mm", "in"] = "mm"
    machining: ShopMachining


@dataclass(frozen=True)
class Shop:
    """A shop's settings file, read and checked: its document (the values as written, with
    their lines) and the units of its bare lengths and feeds."""

    doc: SourceDocument
    units: str

    @property
    def section(self) -> dict[str, Any]:
        """Its ``machining:`` section as written."""
        section: dict[str, Any] = self.doc.data["machining"]
        return section


def read_shop(path: str | Path) -> Shop:
    """Read and check the shop's settings file *path* (raises DesignError/DesignFileError
    naming it, and the line)."""
    path = Path(path)
    name = str(path)
    from camfab.files import read_bounded

    try:
        raw = read_bounded(path, MAX_DESIGN_BYTES, "a machining settings file")
    except InputFileError as exc:
        raise DesignFileError(name, exc.problem) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DesignError("not a text file (machining settings are YAML in UTF-8)",
                          location=Location(name, raw[: exc.start].count(b"\n") + 1, "")
                          ) from None
    return shop_from_text(text, name)


def shop_from_text(text: str, file: str = "<shop>") -> Shop:
    """The shop's settings in YAML *text* (*file* names it in messages), checked: its keys,
    and each value as a design's ``machining:`` section takes it."""
    root, data, lines = compose_yaml(text, file)
    if root is None:
        raise DesignError("the machining settings file is empty", location=Location(file, 1, ""))
    if not isinstance(data, dict):
        raise DesignError("machining settings must be a mapping with a machining: section",
                          location=Location(file, root.start_mark.line + 1, ""), got=data)
    doc = SourceDocument(file=file, data=data, lines=lines, folder=Path(file).parent)
    shaped = Shaper(doc)
    for key in data:
        if key not in SHOP_KEYS:
            hint = ("give it under machining:" if key in MACHINING_KEYS
                    else did_you_mean(key, SHOP_KEYS))
            shaped.fail((key,), "unknown key in machining settings", hint=hint,
                        allowed=", ".join(SHOP_KEYS))
    if "machining" not in data:
        shaped.fail(("machining",), "required: the shop's settings (tool_diameter, feed, ...)")
    shaped.keys(data["machining"], MACHINING_KEYS, ("machining",), "machining")
    units = data.get("units")
    context = {"units": units if units in U.MM_PER_UNIT else "mm"}
    try:
        ShopSettings.model_validate(data, context=context)
    except ValidationError as exc:
        raise first_error(exc, doc, shaped) from None
    return Shop(doc, context["units"])


@dataclass(frozen=True)
class ShopDocument(SourceDocument):
    """A design file's document with a shop's settings merged into its ``machining:`` section:
    the keys that came from the shop file (all of them, when the design has no section) are
    located in it, on its lines, naming the design (a rule broken for this design)."""

    shop: SourceDocument = field(default_factory=lambda: SourceDocument("", {}))
    from_shop: frozenset[str] = frozenset()
    whole: bool = False

    def _in_shop(self, path: Path_) -> bool:
        path = tuple(path)
        if not path or path[0] != "machining":
            return False
        return self.whole or (len(path) > 1 and path[1] in self.from_shop)

    def line_of(self, path: Path_) -> int | None:
        return self.shop.line_of(path) if self._in_shop(path) else super().line_of(path)

    def value_at(self, path: Path_) -> Any:
        return self.shop.value_at(path) if self._in_shop(path) else super().value_at(path)

    def locate(self, path: Path_, shown: str | None = None) -> Location:
        if not self._in_shop(path):
            return super().locate(path, shown)
        shown = shown if shown is not None else dotted(path)
        return Location(self.shop.file, self.shop.line_of(path), f"{shown} (with {self.file})")


def with_shop(doc: SourceDocument, shop: Shop) -> SourceDocument:
    """The design document *doc* with *shop*'s settings under its ``machining:`` section where
    it gives none of its own, key by key; the shop's bare lengths and feeds written with its
    units where they differ from the design's. A section that is not a mapping is left for the
    design's own checks to report."""
    own = doc.data.get("machining")
    if own is not None and not isinstance(own, dict):
        return doc
    units = doc.data.get("units")
    units = units if units in U.MM_PER_UNIT else "mm"
    given = {key: _with_unit(key, value, shop.units, units)
             for key, value in shop.section.items() if own is None or key not in own}
    data = {**doc.data, "machining": {**given, **(own or {})}}
    return ShopDocument(file=doc.file, data=data, lines=doc.lines, folder=doc.folder,
                        shop=shop.doc, from_shop=frozenset(given), whole=own is None)


def _with_unit(key: str, value: Any, shop_units: str, design_units: str) -> Any:
    """The shop's *value* of *key* as the design's section would take it: a bare length or feed
    with the shop's unit written out (``"6 mm"``, ``"30 in/minute"``) when the design's units
    differ; every other value as written."""
    if shop_units == design_units or isinstance(value, bool) or not isinstance(
            value, (int, float)):
        return value
    kind = field_kind(Machining, key)
    if not isinstance(kind, U.Kind) or kind.default is not None:
        return value  # a count, an rpm, a word: no length in it
    # a kind whose bare numbers are in the design's length unit states its internal unit in mm
    return f"{value!r} {kind.internal.replace('mm', shop_units, 1)}"
