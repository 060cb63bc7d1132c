"""The design file as the studio edits it: the YAML text with the one value changed in place.

ruamel.yaml composes the text into nodes that know where each value starts and ends; an edit
writes the new value over the old one's characters and leaves every other character as it was
— the comments, the key order, the quotes, the flow maps of the motion program and their
alignment. A key a mapping lacks is added on a line of its own (or inside a flow map's braces).

Paths are those camfab's messages name (``cam.base_radius``, ``motion[1].rise.lift``); the
model's form without the segment's kind (``motion[1].lift``, as ``camfab sweep --vary`` takes
it) is accepted too.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from typing import Any

from camfab.errors import CamfabError

#: A path's parts: a key, or an index in brackets.
_PART = re.compile(r"\.?([A-Za-z_][A-Za-z0-9_-]*)|\[(\d+)\]")
#: Longest path or text value the studio takes (characters): the design file's deepest key and
#: longest word are far shorter.
MAX_PATH = 200
#: Characters that make YAML read plain text as something else, or end it.
_SIGNS = frozenset("#:{}[],&*!|>'\"%@`\n\t")

_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"


class EditError(CamfabError, ValueError):
    """An edit the design file cannot take: a path that names no key of it, or a value that is
    not a number, a word or true/false."""


def compose(text: str) -> Any:
    """The YAML node tree of *text* (ruamel's, with each node's start and end in the text)."""
    from ruamel.yaml import YAML

    return YAML(typ="rt").compose(text)


def parts(path: Any) -> list[str | int]:
    """``"motion[1].rise.lift"`` -> ``["motion", 1, "rise", "lift"]`` (raises EditError)."""
    if not isinstance(path, str) or not path or len(path) > MAX_PATH or path.startswith("."):
        raise EditError(f"path: must be a key of the design such as cam.base_radius, "
                        f"got {json.dumps(str(path)[:60])}")
    found: list[str | int] = []
    at = 0
    while at < len(path):
        match = _PART.match(path, at)
        if match is None:
            raise EditError(f"{json.dumps(path)}: not a path of the design (such as "
                            "cam.base_radius or motion[1].rise.lift)")
        found.append(match.group(1) if match.group(1) is not None else int(match.group(2)))
        at = match.end()
    return found


def _is(node: Any, kind: str) -> bool:
    return type(node).__name__ == kind


def _lookup(node: Any, key: str | int) -> Any:
    """The child of *node* at *key*, or None."""
    if isinstance(key, str) and _is(node, "MappingNode"):
        for k, v in node.value:
            if k.value == key:
                return v
    if isinstance(key, int) and _is(node, "SequenceNode") and key < len(node.value):
        return node.value[key]
    return None


def _into_segment(node: Any, key: str | int) -> Any:
    """A motion segment (``{rise: {...}}``) stepped into when *key* is one of its body's keys,
    not its kind: ``motion[1].lift`` is ``motion[1].rise.lift``."""
    if _is(node, "MappingNode") and len(node.value) == 1 and node.value[0][0].value != key:
        body = node.value[0][1]
        if _is(body, "MappingNode"):
            return body
    return node


def _find(root: Any, path: str) -> tuple[Any, str | int, Any]:
    """The mapping or list holding *path*'s last key, that key, and its node (None when the
    mapping lacks it)."""
    from camfab.design.source import dotted

    keys = parts(path)
    node = root
    for i, key in enumerate(keys[:-1]):
        child = _lookup(_into_segment(node, key), key)
        if child is None or _is(child, "ScalarNode"):
            raise EditError(f"{path}: the design has no {dotted(tuple(keys[: i + 1]))}")
        node = child
    last = keys[-1]
    node = _into_segment(node, last)
    return node, last, _lookup(node, last)


def _scalar(value: Any, old: Any) -> str:
    """*value* as YAML text, quoted as *old* (the value it replaces) was."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if value.is_integer() and abs(value) < 1e15 and (old is None or old.tag == _INT):
            return str(int(value))
        text = repr(value)
        mantissa, _, exponent = text.partition("e")
        if exponent and "." not in mantissa:  # YAML 1.1 reads 1e-07 as a word: 1.0e-07
            text = f"{mantissa}.0e{exponent}"
        return text
    style = getattr(old, "style", None)
    if style == "'":
        return "'" + value.replace("'", "''") + "'"
    if style != '"' and _reads_plain(value):
        return value
    return json.dumps(value, ensure_ascii=False)


def _reads_plain(value: str) -> bool:
    """True when camfab's YAML reader reads *value* written plain (unquoted) back as this
    text: a word or a quantity such as ``1300 MPa``, not a number, a boolean or text with
    YAML's signs in it."""
    if not value or value != value.strip() or any(c in value for c in _SIGNS):
        return False
    import yaml  # camfab's design reader: YAML 1.1, where yes and on are booleans

    try:
        return bool(yaml.safe_load(f"k: {value}\n") == {"k": value})
    except yaml.YAMLError:
        return False


def _check_value(path: str, value: Any) -> Any:
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise EditError(f"{path}: must be a finite number, got {value!r}")
        return value
    if isinstance(value, str) and 0 < len(value) <= MAX_PATH and value.isprintable():
        return value
    raise EditError(f"{path}: must be a number, a word or true/false")


def set_value(text: str, path: str, value: Any) -> str:
    """*text* with the key at *path* set to *value* (a number, a word or a boolean): the old
    value's characters replaced, all others kept. A mapping the design has may gain the key;
    a list only has its items changed. A key that names a file (:data:`FILE_KEYS`) is not
    edited: no request names a file (raises EditError)."""
    value = _check_value(path, value)
    root = compose(text)
    holder, key, node = _find(root, path)
    if key in FILE_KEYS:
        raise EditError(f"{path}: names a file, which the studio does not change (edit it in "
                        "the design file)")
    if node is not None:
        if not _is(node, "ScalarNode"):
            raise EditError(f"{path}: holds a {'list' if _is(node, 'SequenceNode') else 'mapping'}"
                            ", not a value")
        start, end = node.start_mark.index, node.end_mark.index
        new = _scalar(value, node)
        gap = len(text[end:]) - len(text[end:].lstrip(" "))
        if gap and text[end + gap: end + gap + 1] == "#":  # the comment stays in its column
            gap = max(1, gap + (end - start) - len(new))
            return text[:start] + new + " " * gap + text[end:].lstrip(" ")
        return text[:start] + new + text[end:]
    if not (_is(holder, "MappingNode") and isinstance(key, str)):
        raise EditError(f"{path}: the design has no such key")
    return _added(text, holder, key, _scalar(value, None), path)


def _added(text: str, mapping: Any, key: str, value: str, path: str) -> str:
    """*text* with ``key: value`` added to *mapping*: inside a flow map's braces, or on a line
    of its own after a block mapping's last key (whose value is on its line)."""
    if mapping.flow_style:
        end = mapping.end_mark.index - 1  # the closing brace
        while end > 0 and text[end] != "}":
            end -= 1
        gap = ", " if mapping.value else ""
        return text[:end].rstrip() + f"{gap}{key}: {value}" + text[end:]
    if not mapping.value or not _is(mapping.value[-1][1], "ScalarNode"):
        raise EditError(f"{path}: the design has no such key (add it to the file)")
    first = mapping.value[0][0]
    last = mapping.value[-1][1]
    line_end = text.find("\n", last.end_mark.index)
    if line_end < 0:
        return text + "\n" + " " * first.start_mark.column + f"{key}: {value}\n"
    return (text[: line_end + 1] + " " * first.start_mark.column + f"{key}: {value}\n"
            + text[line_end + 1:])


def get_value(text: str, path: str) -> Any:
    """The value at *path* of the YAML *text*, as YAML reads it (raises EditError where there
    is none)."""
    _, _, node = _find(compose(text), path)
    if node is None or not _is(node, "ScalarNode"):
        raise EditError(f"{path}: the design has no such value")
    return _typed(node)


def _typed(node: Any) -> Any:
    if node.tag == _INT:
        try:
            return int(node.value.replace("_", ""), 0)
        except ValueError:
            return node.value
    if node.tag == _FLOAT:
        try:
            return float(node.value.replace("_", ""))
        except ValueError:
            return node.value
    return node.value


@dataclass(frozen=True)
class Field:
    """One value of the design the page offers to edit: its path (as messages name it), what
    it is (``number``, ``law`` — a choice of the motion laws —, ``choice`` or ``text``), its
    value, and for a number the range of its slider."""

    path: str
    kind: str
    value: Any
    low: float | None = None
    high: float | None = None
    step: float | None = None
    choices: tuple[str, ...] = ()

    def as_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"path": self.path, "kind": self.kind, "value": self.value}
        if self.kind == "number":
            out.update(low=self.low, high=self.high, step=self.step)
        if self.choices:
            out["choices"] = list(self.choices)
        return out


#: Keys whose value names a file (a table law's CSV): shown, not edited, in the studio.
FILE_KEYS = frozenset({"csv"})
#: Words the design file takes as a choice, by key (the others are text).
CHOICES = {"rotation": ("ccw", "cw"), "units": ("mm", "in"), "pivot_side": ("left", "right")}
#: Keys that are an angle (deg): their slider runs over a turn (or a quarter of one).
_ANGLES = {"angle", "start", "end", "pressure_angle", "phase"}


def fields(text: str) -> list[Field]:
    """Every value of the design in YAML *text* the page edits, in the file's order: the
    numbers (a slider each, its range from the value as loaded), the motion laws as a choice,
    the words that are a choice, other text; not the name and description, the keys that name
    a file, nor the items of a list (a table law's points)."""
    from camfab.design.source import dotted
    from camfab.motion.laws import LAW_NAMES

    out: list[Field] = []

    def walk(path: tuple[str | int, ...], node: Any) -> None:
        if _is(node, "MappingNode"):
            for key, value in node.value:
                walk((*path, str(key.value)), value)
        elif _is(node, "SequenceNode"):
            for i, value in enumerate(node.value):
                walk((*path, i), value)
        elif path and isinstance(path[-1], str) and path[-1] not in ("name", *FILE_KEYS) \
                and path != ("description",):
            out.append(_field(dotted(path), path[-1], node, LAW_NAMES))

    root = compose(text)
    if root is not None:
        walk((), root)
    return out


def named_files(text: str) -> list[str]:
    """The values of the keys in YAML *text* that name a file (:data:`FILE_KEYS`), as
    written; none when the text is not YAML."""
    try:
        root = compose(text)
    except Exception:  # a text YAML cannot read: its line is the error the page shows
        return []
    found: list[str] = []
    pending = [root] if root is not None else []
    while pending:
        node = pending.pop()
        if _is(node, "MappingNode"):
            for key, value in node.value:
                if key.value in FILE_KEYS and _is(value, "ScalarNode"):
                    found.append(str(value.value))
                else:
                    pending.append(value)
        elif _is(node, "SequenceNode"):
            pending.extend(node.value)
    return found


def _field(path: str, key: str, node: Any, laws: tuple[str, ...]) -> Field:
    value = _typed(node)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        low, high, step = slider(key, float(value))
        return Field(path, "number", value, low, high, step)
    text = str(value)
    if key == "law":
        return Field(path, "law", text, choices=laws)
    if key in CHOICES:
        return Field(path, "choice", text, choices=CHOICES[key])
    return Field(path, "text", text)


def slider(key: str, value: float) -> tuple[float, float, float]:
    """A slider's range and step for a number *value* of *key* as loaded: an angle over a
    turn (a quarter turn for one under 90°), a signed value (an offset, a preload) either side
    of zero, another from zero to twice it; 400 steps of a round size."""
    if not math.isfinite(value):
        value = 0.0
    if key in _ANGLES:
        low, high = (-180.0, 180.0) if value < 0 else (0.0, 360.0 if value > 90 else 90.0)
    elif value < 0 or key in ("offset", "preload", "external_load", "gravity"):
        span = max(abs(value) * 2.0, 10.0)
        low, high = -span, span
    else:
        low, high = 0.0, max(value * 2.0, 1.0)
    raw = (high - low) / 400.0
    step = 10.0 ** math.floor(math.log10(raw))
    for nice in (1.0, 2.0, 5.0, 10.0):
        if nice * step >= raw:
            return low, high, nice * step
    return low, high, step
