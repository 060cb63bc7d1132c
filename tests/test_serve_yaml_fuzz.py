"""The studio's YAML editor (``camfab.serve.yamledit``) over generated YAML documents: mappings
and lists nested in block and flow style (a flow one on a line or over lines), anchors and
aliases (of values, mappings and lists), block scalars (``|`` and ``>``, each chomping) and
plain, single- and double-quoted values (on a line or two), line and trailing comments (after
a flow collection's commas too), LF or CRLF line breaks.

Up to three edits in a row, each of a path drawn from the text as it stands (a value, an alias,
a value reached through an alias of a mapping, a key a mapping lacks) to a drawn value, must
either change that one value or be refused in one line naming the path. Changed: read by
PyYAML, camfab's design reader, the text after is the text before with that value set (an
anchor's value set for all of its aliases, an alias edited set for that key alone), every
comment is kept and so are the file's line breaks; the nodes the editor keeps for the edited
text are those it composes from it afresh. The cases are the same on every run
(``derandomize``)."""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

yamledit = pytest.importorskip("camfab.serve.yamledit")

KEYS = ("angle", "lift", "law", "base_radius", "k1", "k2", "under_score", "dash-key", "csv")
#: Plain words YAML reads as text in block and flow places alike.
WORDS = ("harmonic", "disc", "ccw", "1300 MPa", "two words", "x_y")
#: Text written single- or double-quoted: signs, quotes, words YAML would read otherwise.
QUOTED = ("it's", 'say "hi"', "a: b", "#x", "yes", "12", "x, y", "[a]", "é ü", "", " pad ")
VALUES = st.one_of(
    st.integers(-10**12, 10**12), st.floats(allow_nan=False, allow_infinity=False),
    st.booleans(),
    st.sampled_from(("yes", "on", "null", "12", "1e3", "a: b", "#x", "-", "- x", "?x", "x,y",
                     "[a]", "{a}", "it's", 'say "hi"', "1300 MPa", "cycloidal", " pad", "é ü",
                     "~", "0x1F", "1_000", "1:30", ".inf", "*t", "&t", "!x", "|", ">-", "%x",
                     "a #b", "a# b", "x\u00a0y")),
    st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), min_size=1, max_size=8),
)
FUZZ = settings(max_examples=120, derandomize=True, database=None, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@dataclass
class Writer:
    """Writes a random YAML mapping line by line, with the comments it wrote."""

    draw: Any
    anchors: list[str] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)  # comment lines, as written
    count: int = 0

    def name(self, prefix: str) -> str:
        self.count += 1
        return f"{prefix}{self.count}"

    def comment(self) -> str:
        text = f"# {self.name('c')} {self.draw(st.sampled_from(WORDS))}"
        self.comments.append(text)
        return text

    def trailing(self) -> str:
        return f"  {self.comment()}" if self.draw(st.integers(0, 3)) == 0 else ""

    def anchor(self) -> str | None:
        return self.name("a") if self.draw(st.integers(0, 2)) == 0 else None

    def scalar(self, flow: bool, pad: str = "") -> str:
        """A value on its key's line (*pad*: the indentation of a line it runs on to)."""
        kind = self.draw(st.sampled_from(("int", "float", "bool", "word", "single", "double")
                                         + (() if flow else ("null", "lines"))))
        if kind == "int":
            return str(self.draw(st.integers(-1000, 10**6)))
        if kind == "float":
            return self.draw(st.sampled_from(("0.5", "-2.25", "1.5e+3", "31.0", ".5")))
        if kind == "bool":
            return self.draw(st.sampled_from(("true", "false", "yes", "off")))
        if kind == "word":
            return self.draw(st.sampled_from(WORDS))
        if kind == "single":
            return "'" + self.draw(st.sampled_from(QUOTED)).replace("'", "''") + "'"
        if kind == "double":
            return json.dumps(self.draw(st.sampled_from(QUOTED)), ensure_ascii=False)
        if kind == "lines":  # plain or double-quoted, over two lines
            quote = self.draw(st.sampled_from(("", '"')))
            return f"{quote}two\n{pad}words{quote}"
        return ""

    def alias(self) -> str | None:
        return f"*{self.draw(st.sampled_from(self.anchors))}" if self.anchors else None

    def flow(self, depth: int, pad: str) -> str:
        """A flow mapping or list, on one line or over lines indented by *pad*, with comments
        after its commas."""
        items = []
        mapping = self.draw(st.booleans())
        keys = self.draw(st.lists(st.sampled_from(KEYS), max_size=3, unique=True))
        for key in keys:
            choice = self.draw(st.integers(0, 5))
            if choice == 0 and depth < 3:
                item = self.flow(depth + 1, pad + "  ")
            elif choice in (1, 2) and self.anchors:
                item = self.alias() or ""
            else:
                anchor = self.anchor()
                item = (f"&{anchor} " if anchor else "") + self.scalar(flow=True)
                if anchor:
                    self.anchors.append(anchor)
            items.append(f"{key}: {item}" if mapping else item)
        text = ""
        for i, item in enumerate(items):
            if i and self.draw(st.integers(0, 3)) == 0:  # a line break, maybe a comment
                text += "," + self.trailing() + "\n" + pad
            elif i:
                text += ", "
            text += item
        if items and self.draw(st.integers(0, 5)) == 0:
            text += "," + self.trailing() + "\n" + pad[:-2]
        return ("{%s}" if mapping else "[%s]") % text

    def entry(self, head: str, indent: int, depth: int) -> None:
        """The value of *head* (``  key:`` or ``  -``), on its line or the lines below."""
        choice = self.draw(st.sampled_from(("scalar", "scalar", "block", "alias", "alias", "flow")
                                           + (("map", "seq", "map") if depth < 3 else ())))
        anchor = self.anchor() if choice != "alias" else None
        props = f" &{anchor}" if anchor else ""
        pad = " " * (indent + 2)
        if choice == "alias" and self.anchors:
            self.lines.append(f"{head} {self.alias()}{self.trailing()}")
        elif choice == "block":
            sign = self.draw(st.sampled_from(("|", ">", "|-", ">-", "|+", ">+")))
            self.lines.append(f"{head}{props} {sign}{self.trailing()}")
            self.lines += [pad + w for w in self.draw(st.lists(st.sampled_from(WORDS), min_size=1,
                                                                 max_size=2))]
        elif choice == "flow":
            self.lines.append(f"{head}{props} {self.flow(depth + 1, pad + '  ')}"
                              f"{self.trailing()}")
        elif choice in ("map", "seq"):
            if choice == "map" and head.endswith("-") and not props and self.draw(st.booleans()):
                at = len(self.lines)  # compact: "- key: value" on the dash's line
                self.block_map(indent + 2, depth + 1)
                while self.lines[at].lstrip().startswith("#"):
                    at += 1
                self.lines[at] = head + " " + self.lines[at].lstrip()
            else:
                self.lines.append(f"{head}{props}{self.trailing()}")
                (self.block_map if choice == "map" else self.block_seq)(indent + 2, depth + 1)
        else:
            self.lines.append(f"{head}{props} {self.scalar(False, pad)}".rstrip()
                              + self.trailing())
        if anchor:
            self.anchors.append(anchor)

    def line_comment(self, indent: int) -> None:
        if self.draw(st.integers(0, 4)) == 0:
            self.lines.append(" " * indent + self.comment())

    def block_map(self, indent: int, depth: int) -> None:
        for key in self.draw(st.lists(st.sampled_from(KEYS), min_size=1, max_size=4,
                                      unique=True)):
            self.line_comment(indent)
            self.entry(" " * indent + f"{key}:", indent, depth)

    def block_seq(self, indent: int, depth: int) -> None:
        for _ in range(self.draw(st.integers(1, 3))):
            self.line_comment(indent)
            self.entry(" " * indent + "-", indent, depth)


@st.composite
def documents(draw: Any) -> tuple[str, str, Writer]:
    """A YAML text of one block mapping (after ``---`` or not), its line break, and what
    wrote it."""
    writer = Writer(draw)
    if draw(st.integers(0, 4)) == 0:
        writer.lines.append("---")
    writer.line_comment(0)
    writer.block_map(0, 0)
    writer.line_comment(0)
    eol = draw(st.sampled_from(("\n", "\r\n")))
    text = "\n".join(writer.lines) + ("\n" if draw(st.integers(0, 5)) else "")
    return text.replace("\n", eol), eol, writer


@dataclass(frozen=True)
class Place:
    """A path of the text as PyYAML composes it: *keys*; *alias* when its scalar is an alias's
    (not where its anchor is written); *shared* when it is reached through an alias of a
    mapping or list; *new* for a key its mapping lacks."""

    keys: tuple[str | int, ...]
    alias: bool = False
    shared: bool = False
    new: bool = False
    block_end: bool = False  # a key to add after a block: a mapping or list, or a text block
    #                          whose line break would end the file and join its value

    @property
    def path(self) -> str:
        from camfab.design.source import dotted

        return dotted(self.keys)


def places(text: str, root: yaml.Node) -> list[Place]:
    """Every scalar's path in *root* (an alias's node is the object of its anchor's: the first
    seen is where it is written), and a key each mapping not reached through an alias lacks."""
    seen: set[int] = set()
    found: list[Place] = []

    def walk(node: yaml.Node, keys: tuple[str | int, ...], shared: bool) -> None:
        first = id(node) not in seen
        seen.add(id(node))
        if isinstance(node, yaml.ScalarNode):
            found.append(Place(keys, alias=not first, shared=shared))
            return
        shared = shared or not first
        if isinstance(node, yaml.MappingNode):
            aliased = False  # its last value an alias's
            for key, value in node.value:
                aliased = id(value) in seen
                walk(value, (*keys, key.value), shared)
            names = [k.value for k, _ in node.value]
            missing = [k for k in KEYS if k not in names and k != "csv"]
            stepped = len(node.value) == 1 and isinstance(node.value[0][1], yaml.MappingNode)
            if missing and not shared and not stepped:  # a segment's key is its body's
                last = node.value[-1][1] if node.value else None
                block = (last is not None and not isinstance(last, yaml.ScalarNode)
                         and not last.flow_style and not aliased)
                if isinstance(last, yaml.ScalarNode) and last.style in ("|", ">") \
                        and last.end_mark.index == len(text) and text[-1:] != "\n":
                    header = text[last.start_mark.index:].split("\n", 1)[0].split("#")[0]
                    block = "-" not in re.search(r"[|>][0-9+-]*", header).group()
                found.append(Place((*keys, missing[0]), new=True, block_end=block))
        else:
            for i, value in enumerate(node.value):
                walk(value, (*keys, i), shared)

    walk(root, (), False)
    return found


def expected(text: str, place: Place, value: Any) -> Any:
    """The data of *text* with *value* set at *place*, PyYAML's nodes changed: an alias's slot
    given a node of its own, a written value's node changed for every alias of it."""
    root = yaml.compose(text, Loader=yaml.SafeLoader)
    new = yaml.compose(yaml.safe_dump(value), Loader=yaml.SafeLoader)
    node = root
    for key in place.keys[:-1]:
        node = dict((k.value, v) for k, v in node.value)[key] if isinstance(key, str) else \
            node.value[key]
    last = place.keys[-1]
    if place.new:
        node.value.append((yaml.ScalarNode("tag:yaml.org,2002:str", last), new))
    elif isinstance(last, int):
        if place.alias:
            node.value[last] = new
        else:
            node.value[last].tag, node.value[last].value = new.tag, new.value
    else:
        i = next(i for i, (k, _) in enumerate(node.value) if k.value == last)
        if place.alias:
            node.value[i] = (node.value[i][0], new)
        else:
            node.value[i][1].tag, node.value[i][1].value = new.tag, new.value
    return yaml.SafeLoader("").construct_document(root)


def canon(data: Any) -> Any:
    """*data* with its scalars told apart by kind (True is not 1; 2 is 2.0)."""
    if isinstance(data, dict):
        return {k: canon(v) for k, v in data.items()}
    if isinstance(data, list):
        return [canon(v) for v in data]
    if isinstance(data, bool):
        return ("bool", data)
    if isinstance(data, (int, float)):
        return ("number", data)
    return (type(data).__name__, data)


def acceptable(value: Any) -> bool:
    """The values the editor takes: a boolean, a finite number, a line of printable text."""
    if isinstance(value, (bool, int)):
        return True
    if isinstance(value, float):
        return math.isfinite(value)
    return 0 < len(value) <= yamledit.MAX_PATH and value.isprintable()


def outline(node: Any) -> Any:
    """A tree of the editor's nodes as plain tuples (an alias by its name, not followed)."""
    if node is None or node.kind in ("scalar", "alias"):
        return node and (node.kind, node.start, node.end, node.value, node.style, node.anchor)
    items = [(outline(k), outline(v)) for k, v in node.value] if node.kind == "map" else [
        outline(v) for v in node.value]
    return node.kind, node.start, node.end, node.style, node.anchor, items


@FUZZ
@given(st.data())
def test_an_edit_changes_that_value_alone_or_is_refused(data: st.DataObject) -> None:
    text, eol, writer = data.draw(documents(), label="document")
    eol = eol if "\n" in text else "\n"  # a text of one line: the editor's line break is LF
    assert outline(yamledit.compose(text).root) == outline(yamledit.compose(text, pure=True).root)
    for _ in range(data.draw(st.integers(1, 3), label="edits")):
        found = places(text, yaml.compose(text, Loader=yaml.SafeLoader))
        if not found:
            break
        place = data.draw(st.sampled_from(found), label="place")
        value = data.draw(VALUES, label="value")
        refused = (place.shared or place.keys[-1] == "csv" or place.block_end
                   or not acceptable(value))
        kind = ("new key" if place.new else "through an alias" if place.shared
                else "alias" if place.alias else "value")
        try:
            edited = yamledit.set_value(text, place.path, value)
        except yamledit.EditError as exc:
            event(f"refused: {kind}")
            said = str(exc)
            assert refused, said
            assert "\n" not in said and said.startswith(place.path + ":"), said
            continue
        assert not refused, place
        event(f"edited: {kind}")
        assert canon(yaml.safe_load(edited)) == canon(expected(text, place, value)), place
        lines = edited.split(eol)
        assert all(c in edited for c in writer.comments)
        assert all(line in lines for line in writer.lines if line.lstrip().startswith("#"))
        assert edited.count("\n") == edited.count(eol) and "\r\r" not in edited
        assert outline(yamledit.document(edited).root) == outline(yamledit.compose(edited).root)
        if isinstance(value, (str, int, float)) and not isinstance(value, bool):
            assert yamledit.get_value(edited, place.path) == value
        text = edited
