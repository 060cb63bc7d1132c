"""The design file as the studio edits it: the YAML text with the one value changed in place.

The text is read as a stream of parse events by ruamel.yaml (its C parser when ruamel.yaml.clib
is installed, its pure-Python parser otherwise), as YAML 1.1, and composed into nodes that know
where each value starts and ends; the scalars are resolved by the YAML 1.1 rules of PyYAML,
camfab's design reader, so that the editor reads each value as the design loader does. The
composed document is kept, keyed by the text (:func:`document`). An edit writes the new value
over the old one's characters and leaves every other character as it was — the comments, the
key order, the quotes, the anchors, the flow maps of the motion program and their alignment,
the line endings —, and moves the kept nodes after it by the characters it added: the next
request finds the edited text composed, and a design of some 30,000 table points is not
composed again for each request. A key a mapping lacks is added on a line of its own (or inside
a flow map's braces).

YAML's own forms:

- a value that carries an anchor (``thickness: &t 14``) keeps it (``thickness: &t 15``): its
  aliases (``*t``) are that one value written once, and follow it;
- an alias (``roller_length: *t``) edited is replaced by the value written there: that key
  alone changes, the anchor and its other aliases stay as they are;
- a value inside a mapping or list reached through an alias of it, and a value with an explicit
  tag (``!!str 31``), are refused: edit them in the file;
- a block scalar (``base_radius: >-`` with its text on the lines below) is replaced by the value
  on the key's line, a comment after the ``>-`` kept.

Paths are those camfab's messages name (``cam.base_radius``, ``motion[1].rise.lift``); the
model's form without the segment's kind (``motion[1].lift``, as ``camfab sweep --vary`` takes
it) is accepted too.
"""

from __future__ import annotations

import json
import math
import re
import threading
from collections import OrderedDict
from collections.abc import Callable
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
#: A node's anchor and tag, and the spaces, line breaks and comments between them and the value.
_PROPERTIES = re.compile(r"(?:&[^\s,\[\]{}]+|!<[^>]*>|![^\s,\[\]{}]*|\s+|#[^\r\n]*)*")
#: A block scalar's indicator: ``|`` or ``>``, its indentation and chomping.
_INDICATOR = re.compile(r"[|>][0-9+-]*")
_SPACES = re.compile(r"[ \t]*")
#: Spaces, line breaks and comments between two signs.
_GAP = re.compile(r"(?:\s+|#[^\r\n]*)*")

_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_STR = "tag:yaml.org,2002:str"

#: How many composed texts are kept: the studio's text, the one an edit came from, the file's.
KEPT = 3


class EditError(CamfabError, ValueError):
    """An edit the design file cannot take: a path that names no key of it, or a value that is
    not a number, a word or true/false."""


class NotYaml(EditError):
    """The text is not one YAML document the editor can read (the message says where)."""


class Node:
    """One value of the YAML text. *kind* is ``scalar``, ``map``, ``seq`` or ``alias``;
    *start* and *end* are character offsets of the value itself in the text (after its anchor
    and tag; an alias's ``*name``); *end* is None for a block mapping or list, and a block
    scalar's ends at the start of the line after its text. *value* is a scalar's text as YAML
    reads it, a mapping's (key, value) pairs, a list's items, an alias's anchor name; *style*
    a scalar's quote or block indicator (None: plain) or ``flow`` for a collection in brackets;
    *target* the node an alias names."""

    __slots__ = ("anchor", "end", "kind", "start", "style", "tag", "target", "value")

    def __init__(self, kind: str, start: int, end: int | None, value: Any,
                 style: str | None = None, anchor: str | None = None, tag: str | None = None,
                 target: Node | None = None) -> None:
        self.kind = kind
        self.start = start
        self.end = end
        self.value = value
        self.style = style
        self.anchor = anchor
        self.tag = tag
        self.target = target

    def shown(self) -> Node:
        """The node whose value this one has: an alias's target, else itself."""
        return self.target if self.kind == "alias" and self.target is not None else self


@dataclass
class Document:
    """A YAML text composed: its root node (None for an empty text) and every node in it."""

    root: Node | None
    nodes: list[Node]


_lock = threading.RLock()  # the studio's threads share the kept documents
_kept: OrderedDict[str, Document | EditError] = OrderedDict()


def document(text: str) -> Document:
    """The YAML *text* composed, kept for the next call with the same text (raises EditError
    when it is not one YAML document)."""
    with _lock:
        found = _kept.get(text)
        if found is None:
            try:
                found = compose(text)
            except EditError as exc:
                found = exc
            _keep(text, found)
        else:
            _kept.move_to_end(text)
        if isinstance(found, EditError):
            raise type(found)(str(found))
        return found


def _keep(text: str, found: Document | EditError) -> None:
    _kept[text] = found
    _kept.move_to_end(text)
    while len(_kept) > KEPT:
        _kept.popitem(last=False)


def compose(text: str, pure: bool = False) -> Document:
    """The nodes of YAML *text*, read by ruamel.yaml's parser as YAML 1.1 (its C parser when
    ruamel.yaml.clib is installed, its own pure-Python one with *pure* or without it); raises
    EditError for a text that is not one YAML document."""
    from ruamel.yaml import YAML, events
    from ruamel.yaml.error import YAMLError
    from ruamel.yaml.parser import Parser

    reader = YAML(typ="safe", pure=pure)
    reader.version = (1, 1)  # the YAML camfab's design reader (PyYAML) reads
    # libyaml does not count a byte-order mark in its offsets
    shift = 1 if reader.Parser is not Parser and text.startswith("\ufeff") else 0
    nodes: list[Node] = []
    anchors: dict[str, Node] = {}
    open_: list[Node] = []
    keys: list[Node | None] = []
    root: Node | None = None
    documents = 0
    last_end = 0  # where the event before ended
    scalar, alias, mapping, sequence = (events.ScalarEvent, events.AliasEvent,
                                        events.MappingStartEvent, events.SequenceStartEvent)
    ends = (events.MappingEndEvent, events.SequenceEndEvent)
    try:
        for event in reader.parse(text):
            cls = type(event)
            start = event.start_mark.index + shift
            after, last_end = last_end, event.end_mark.index + shift
            if cls is scalar or cls is mapping or cls is sequence:
                tag = None if event.tag is None else str(event.tag)
            if cls is scalar:
                end = event.end_mark.index + shift
                if event.anchor is not None or tag is not None:
                    start = min(_PROPERTIES.match(text, start).end(), end)
                elif not event.value and not event.style and open_ and keys[-1] is not None \
                        and open_[-1].style is None:
                    start = end = _after_colon(text, after, start)
                node = Node("scalar", start, _block_end(text, start, end, event.style),
                            event.value, event.style or None, event.anchor, tag)
            elif cls is alias:
                target = anchors.get(event.anchor)
                if target is None or any(target is o for o in open_):
                    raise NotYaml(f"line {event.start_mark.line + 1}: the alias *{event.anchor}"
                                    " names no anchor before it")
                node = Node("alias", start, event.end_mark.index + shift, event.anchor,
                            target=target)
            elif cls is mapping or cls is sequence:
                if event.anchor is not None or tag is not None:
                    start = _PROPERTIES.match(text, start).end()
                node = Node("map" if cls is mapping else "seq", start, None, [],
                            "flow" if event.flow_style else None, event.anchor, tag)
            elif cls in ends:
                done = open_.pop()
                keys.pop()
                if done.style == "flow":
                    done.end = event.end_mark.index + shift
                continue
            elif cls is events.DocumentStartEvent:
                documents += 1
                if documents > 1:
                    raise NotYaml(f"line {event.start_mark.line + 1}: a second YAML document "
                                    "(a design file is one)")
                continue
            else:
                continue
            nodes.append(node)
            if node.anchor is not None:
                anchors[node.anchor] = node
            if not open_:
                root = node
            elif open_[-1].kind == "seq":
                open_[-1].value.append(node)
            elif keys[-1] is None:
                keys[-1] = node
            else:
                open_[-1].value.append((keys[-1], node))
                keys[-1] = None
            if node.kind in ("map", "seq"):
                open_.append(node)
                keys.append(None)
    except YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise NotYaml(f"{where}not YAML ({problem})") from None
    return Document(root, nodes)


def _after_colon(text: str, after: int, at: int) -> int:
    """Where a block mapping's empty value (a null) is: just after its key's colon, the first
    sign after *after* (the key's end), as libyaml and PyYAML place it; *at* (ruamel's pure
    parser places it at the next key) when there is no colon before it."""
    colon = _GAP.match(text, after, at).end()
    if colon < at and text[colon] == ":" and text[colon + 1:colon + 2] in ("", " ", "\t", "\r",
                                                                            "\n"):
        return colon + 1
    return at


def _block_end(text: str, start: int, end: int, style: str | None) -> int:
    """A scalar's end: a block scalar's at the start of the line after its text (the parser
    ends it after the next line's indentation, which depends on what follows)."""
    if style not in ("|", ">"):
        return end
    line = text.rfind("\n", start, end) + 1
    return line if line and not text[line:end].strip(" \t") else end


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


def _lookup(node: Node, key: str | int) -> Node | None:
    """The child of *node* at *key*, or None."""
    if isinstance(key, str) and node.kind == "map":
        for k, v in node.value:
            if k.kind == "scalar" and k.value == key:
                return v
    if isinstance(key, int) and node.kind == "seq" and key < len(node.value):
        return node.value[key]
    return None


def _into_segment(node: Node, key: str | int, path: str, text: str) -> Node:
    """A motion segment (``{rise: {...}}``) stepped into when *key* is one of its body's keys,
    not its kind: ``motion[1].lift`` is ``motion[1].rise.lift``."""
    if node.kind == "map" and len(node.value) == 1 and node.value[0][0].value != key:
        body = node.value[0][1]
        if body.kind == "alias" and body.shown().kind == "map":
            _shared(path, body, text)
        if body.kind == "map":
            return body
    return node


def _shared(path: str, alias: Node, text: str) -> None:
    """Refuse a path through an alias of a mapping or a list."""
    target = alias.shown()
    what = "mapping" if target.kind == "map" else "list"
    line = text.count("\n", 0, target.start) + 1
    raise EditError(f"{path}: reached through the alias *{alias.value} of a {what} written "
                    f"once for all its aliases (line {line}); edit it there")


def _find(root: Node | None, path: str, text: str) -> tuple[Node | None, str | int, Node | None]:
    """The mapping or list holding *path*'s last key, that key, and its node (None when the
    mapping lacks it)."""
    from camfab.design.source import dotted

    keys = parts(path)
    node = root
    for i, key in enumerate(keys[:-1]):
        child = None if node is None else _lookup(_into_segment(node, key, path, text), key)
        if child is not None and child.kind == "alias" and child.shown().kind != "scalar":
            _shared(path, child, text)
        if child is None or child.kind in ("scalar", "alias"):
            raise EditError(f"{path}: the design has no {dotted(tuple(keys[: i + 1]))}")
        node = child
    last = keys[-1]
    if node is None:
        return None, last, None
    node = _into_segment(node, last, path, text)
    return node, last, _lookup(node, last)


def _tag(node: Node) -> str:
    """The tag YAML 1.1 gives a scalar node (as camfab's design reader reads it)."""
    if node.tag is not None:
        return _STR if node.tag == "!" else node.tag
    import yaml

    return yaml.resolver.Resolver().resolve(yaml.ScalarNode, node.value,
                                            (node.style is None, node.style is not None))


def _scalar(value: Any, old: Node | None, flow: bool) -> tuple[str, str, str | None]:
    """*value* as YAML text, quoted as *old* (the value it replaces) was, for a place inside a
    flow collection when *flow*: the text, the scalar's value as YAML reads it, its style."""
    if isinstance(value, bool):
        text = "true" if value else "false"
        return text, text, None
    if isinstance(value, int):
        return str(value), str(value), None
    if isinstance(value, float):
        if value.is_integer() and abs(value) < 1e15 and (old is None or _tag(old) == _INT):
            return str(int(value)), str(int(value)), None
        text = repr(value)
        mantissa, _, exponent = text.partition("e")
        if exponent and "." not in mantissa:  # YAML 1.1 reads 1e-07 as a word: 1.0e-07
            text = f"{mantissa}.0e{exponent}"
        return text, text, None
    style = getattr(old, "style", None)
    if style == "'":
        return "'" + value.replace("'", "''") + "'", value, "'"
    if style != '"' and _reads_plain(value, flow):
        return value, value, None
    return json.dumps(value, ensure_ascii=False), value, '"'


def _reads_plain(value: str, flow: bool = False) -> bool:
    """True when camfab's YAML reader reads *value* written plain (unquoted) back as this
    text (inside a flow collection when *flow*): a word or a quantity such as ``1300 MPa``, not
    a number, a boolean or text with YAML's signs in it."""
    if not value or value != value.strip() or any(c in value for c in _SIGNS):
        return False
    import yaml  # camfab's design reader: YAML 1.1, where yes and on are booleans

    try:
        return bool(yaml.safe_load(f"k: {value}\n") == {"k": value}
                    and (not flow or yaml.safe_load(f"[{value}]") == [value]))
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


@dataclass
class _Edit:
    """*piece* written over the characters [*at*, *to*) of the text; *done* brings the nodes
    up to the new text once the others are moved."""

    at: int
    to: int
    piece: str
    done: Callable[[], None]
    changed: tuple[Node, ...]  # the nodes *done* places itself: not moved


def set_value(text: str, path: str, value: Any) -> str:
    """*text* with the key at *path* set to *value* (a number, a word or a boolean): the old
    value's characters replaced, all others kept. A mapping the design has may gain the key;
    a list only has its items changed. A key that names a file (:data:`FILE_KEYS`) is not
    edited: no request names a file (raises EditError). The composed document of *text* is
    kept as that of the new text."""
    value = _check_value(path, value)
    with _lock:
        doc = document(text)
        try:
            edit = _plan(doc, text, path, value)
        except _Drifted:  # the kept nodes are not where the text has them: compose it afresh
            doc = compose(text)
            _keep(text, doc)
            edit = _plan(doc, text, path, value)
        new = text[: edit.at] + edit.piece + text[edit.to:]
        _move(doc.nodes, edit)
        edit.done()
        del _kept[text]
        _keep(new, doc)
        return new


class _Drifted(Exception):
    """A kept node's characters are not in the text where the node says."""


def _plan(doc: Document, text: str, path: str, value: Any) -> _Edit:
    holder, key, node = _find(doc.root, path, text)
    if key in FILE_KEYS:
        raise EditError(f"{path}: names a file, which the studio does not change (edit it in "
                        "the design file)")
    if node is not None:
        if node.shown().kind != "scalar":
            raise EditError(f"{path}: holds a {'list' if node.shown().kind == 'seq' else 'mapping'}"
                            ", not a value")
        if node.tag is not None:
            tag = node.tag.replace("tag:yaml.org,2002:", "!!")
            raise EditError(f"{path}: carries the tag {tag} (edit it in the design file)")
        if not _in_place(text, node):
            raise _Drifted
        assert holder is not None
        return _replaced(text, node, value, flow=holder.style == "flow", path=path)
    if holder is None or holder.kind != "map" or not isinstance(key, str):
        raise EditError(f"{path}: the design has no such key")
    return _added(doc, text, holder, key, value, path)


def _in_place(text: str, node: Node) -> bool:
    """True when *node*'s characters are where it says in *text* (a check of the kept nodes
    before an edit writes by them)."""
    start, end = node.start, node.end
    if end is None or not 0 <= start <= end <= len(text):
        return node.kind in ("map", "seq") and node.style is None and 0 <= start <= len(text)
    if node.kind == "alias":
        return text[start:end] == "*" + node.value
    if node.kind != "scalar":
        return text[start:start + 1] in ("{", "[") and text[end - 1:end] in ("}", "]")
    if start == end:
        return node.value == "" and node.style is None
    if node.style in ("'", '"'):
        return text[start] == text[end - 1] == node.style
    if node.style in ("|", ">"):
        return text[start] == node.style
    span = text[start:end]
    return span == node.value or "\n" in span


def _replaced(text: str, node: Node, value: Any, flow: bool, path: str) -> _Edit:
    """The edit writing *value* over *node*'s characters (an alias's ``*name``; a block
    scalar's indicator and the lines of its text), a comment after it kept in its column."""
    new, read, style = _scalar(value, node.shown(), flow)
    at, to = node.start, node.end
    assert to is not None
    before = after = ""
    if at == to:  # an empty value (null): after its key's colon, a space between
        if node.anchor is None and not _after_indicator(text, at):
            raise EditError(f"{path}: has no value to replace (write one in the design file)")
        if text[at:at + 1] in (" ", "\t"):
            at = to = at + 1
        before = "" if text[at - 1:at] in (" ", "\t") else " "
        after = " " if text.startswith("#", at) else ""
    elif node.kind == "scalar" and node.style in ("|", ">"):  # its header line and its text
        head = _INDICATOR.match(text, at).end()
        brk = text.find("\n", at)
        line_end = len(text) if brk < 0 else brk + 1
        stop = len(text) if brk < 0 else brk - (text[brk - 1] == "\r")
        spaces = _SPACES.match(text, head).end()
        if spaces < stop and text[spaces] == "#":  # the comment stays in its column
            after = " " * max(1, spaces - at - len(new)) + text[spaces:line_end]
        else:
            after = text[stop:line_end]
    else:
        spaces = _SPACES.match(text, to).end()
        if spaces > to and text.startswith("#", spaces):  # the comment stays in its column
            one_line = "\n" not in text[at:to]
            after = " " * (max(1, spaces - at - len(new)) if one_line else spaces - to)
            to = spaces

    start = at + len(before)

    def done() -> None:
        node.kind, node.start, node.end = "scalar", start, start + len(new)
        node.value, node.style, node.target = read, style, None

    return _Edit(at, to, before + new + after, done, (node,))


def _after_indicator(text: str, at: int) -> bool:
    """True when the last sign before *at* (spaces aside) is a key's colon or a list's dash."""
    i = at - 1
    while i >= 0 and text[i] in " \t":
        i -= 1
    return i >= 0 and text[i] in ":-"


def _added(doc: Document, text: str, mapping: Node, key: str, value: Any, path: str) -> _Edit:
    """The edit adding ``key: value`` to *mapping*: inside a flow map's braces, or on a line
    of its own after a block mapping's last key (whose value ends on its line); the line break
    is the file's."""
    flow = mapping.style == "flow"
    name, name_read, name_style = _scalar(key, None, flow)
    new, read, style = _scalar(value, None, flow)
    grown: Node | None = None  # a block scalar ending the text, ended now by a line break
    if flow:
        last = mapping.value[-1][1] if mapping.value else None
        if not _in_place(text, mapping) or (last is not None and not _in_place(text, last)):
            raise _Drifted
        at, lead, tail = (mapping.start + 1, "", "") if last is None else (last.end, ", ", "")
    else:
        last = mapping.value[-1][1] if mapping.value else None
        if last is None or last.end is None:
            raise EditError(f"{path}: the design has no such key (add it to the file)")
        first = mapping.value[0][0]
        if not (_in_place(text, last) and _in_place(text, first)):
            raise _Drifted
        eol = _line_break(text)
        block = last.kind == "scalar" and last.style in ("|", ">")
        if block and text[last.end - 1:last.end] == "\n":
            at, lead = last.end, ""
        else:
            brk = text.find("\n", last.end)
            at, lead = (len(text), eol) if brk < 0 else (brk + 1, "")
            if block and brk < 0:  # its text ends the file: a line break would join its value
                if not text[last.start:text.find("\n", last.start)].split("#")[0].rstrip() \
                        .endswith("-"):
                    raise EditError(f"{path}: the design has no such key (add it to the file: "
                                    "the text block before it ends the file without a line "
                                    "break)")
                grown = last
        lead += " " * (first.start - (text.rfind("\n", 0, first.start) + 1))
        tail = eol
    assert at is not None
    key_start = at + len(lead)
    key_node = Node("scalar", key_start, key_start + len(name), name_read, name_style)
    value_start = key_node.end + 2  # after ": "
    assert value_start is not None
    value_node = Node("scalar", value_start, value_start + len(new), read, style)
    added = len(lead) - len(lead.lstrip("\r\n"))

    def done() -> None:
        if grown is not None and grown.end is not None:
            grown.end += added
        mapping.value.append((key_node, value_node))
        doc.nodes.extend((key_node, value_node))

    return _Edit(at, at, f"{lead}{name}: {new}{tail}", done, ())


def _line_break(text: str) -> str:
    """The file's line break: that of its first line (``\\n`` for a text of one line)."""
    brk = text.find("\n")
    return "\r\n" if brk > 0 and text[brk - 1] == "\r" else "\n"


def _move(nodes: list[Node], edit: _Edit) -> None:
    """The nodes after *edit* moved by the characters it adds: a node starting at or after its
    end (not a null where it inserts, which stays before); a node ending after it (at its end
    too, when it replaces characters: a collection around them)."""
    delta = len(edit.piece) - (edit.to - edit.at)
    if not delta:
        return
    to, inclusive = edit.to, edit.to > edit.at
    skip = {id(n) for n in edit.changed}
    for node in nodes:
        start = node.start
        if (start > to or (start == to and (inclusive or node.end != start))) \
                and id(node) not in skip:  # a null at the place of an insertion stays before it
            node.start = start + delta
        end = node.end
        if end is not None and (end > to or (inclusive and end == to)) and id(node) not in skip:
            node.end = end + delta


def get_value(text: str, path: str) -> Any:
    """The value at *path* of the YAML *text*, as YAML reads it (raises EditError where there
    is none)."""
    with _lock:
        _, _, node = _find(document(text).root, path, text)
        if node is None or node.shown().kind != "scalar":
            raise EditError(f"{path}: the design has no such value")
        return _typed(node.shown())


def _typed(node: Node) -> Any:
    """A scalar's value: a number as camfab's reader reads it, else its text."""
    tag = _tag(node)
    if tag not in (_INT, _FLOAT):
        return node.value
    import yaml

    make = yaml.constructor.SafeConstructor()
    try:
        read = (make.construct_yaml_int if tag == _INT else make.construct_yaml_float)(
            yaml.ScalarNode(tag, node.value))
    except (ValueError, TypeError):
        return node.value
    return read


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
CHOICES = {"rotation": ("ccw", "cw"), "units": ("mm", "in"), "pivot_side": ("left", "right"),
           "motion_target": ("cam", "output")}
#: Keys that are an angle (deg): their slider runs over a turn (or a quarter of one).
_ANGLES = {"angle", "start", "end", "pressure_angle", "phase"}


def _values(root: Node | None) -> list[tuple[tuple[str | int, ...], Node]]:
    """Every scalar of the tree under *root* that a key names, with its path, in the file's
    order (an alias of a scalar as its value; not into an alias of a mapping or list, which is
    edited where it is written, nor the items of a list that are values)."""
    found: list[tuple[tuple[str | int, ...], Node]] = []
    pending: list[tuple[tuple[str | int, ...], Node]] = [((), root)] if root is not None else []
    while pending:
        path, node = pending.pop()
        if node.kind == "map":
            pending.extend(((*path, str(k.value)), v) for k, v in reversed(node.value)
                           if k.kind == "scalar")
        elif node.kind == "seq":  # its mappings, and its lists that hold more than values
            held = [(i, v) for i, v in enumerate(node.value) if v.kind == "map" or (
                v.kind == "seq" and any(c.kind in ("map", "seq") for c in v.value))]
            pending.extend(((*path, i), v) for i, v in reversed(held))
        elif node.shown().kind == "scalar" and path and isinstance(path[-1], str):
            found.append((path, node.shown()))
    return found


def fields(text: str) -> list[Field]:
    """Every value of the design in YAML *text* the page edits, in the file's order: the
    numbers (a slider each, its range from the value as loaded), the motion laws as a choice,
    the words that are a choice, other text; not the name and description, the keys that name
    a file, the items of a list (a table law's points), nor the values inside an alias of a
    mapping (they are edited where it is written)."""
    from camfab.design.source import dotted
    from camfab.motion.laws import LAW_NAMES

    with _lock:
        values = _values(document(text).root)
        return [_field(dotted(path), path[-1], node, LAW_NAMES) for path, node in values
                if path[-1] not in ("name", *FILE_KEYS) and path != ("description",)]


def named_files(text: str) -> list[str]:
    """The values of the keys in YAML *text* that name a file (:data:`FILE_KEYS`), as
    written; none when the text is not YAML."""
    with _lock:
        try:
            values = _values(document(text).root)
        except EditError:  # a text YAML cannot read: its line is the error the page shows
            return []
        return [str(node.value) for path, node in values if path[-1] in FILE_KEYS]


def _field(path: str, key: Any, node: Node, laws: tuple[str, ...]) -> Field:
    value = _typed(node)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        low, high, step = slider(str(key), float(value))
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
