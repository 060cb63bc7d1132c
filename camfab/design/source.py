"""Read YAML while remembering where every value came from.

PyYAML's composer gives nodes with marks; we construct plain Python data from them and keep a map
from each field path (``("motion", 2, "rise", "angle")``) to its 1-based line, so that every error
can name the line the designer has to fix.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from camfab.errors import DesignError, DesignFileError, Location

Path_ = tuple[str | int, ...]

#: Design files are small; anything larger is almost certainly the wrong file.
MAX_DESIGN_BYTES = 5_000_000

#: Deepest nesting of mappings and lists a design may use (a real one nests four or five deep);
#: checked before composing, whose recursion would otherwise overflow the C stack.
MAX_DEPTH = 50

#: Most YAML values (scalars, mappings, lists) a design may hold, written or through aliases
#: (``*name``): far more than any design needs, few enough to read in well under a second, and
#: an alias bomb (aliases of aliases, expanding exponentially) stops here.
MAX_VALUES = 100_000

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


@dataclass(frozen=True)
class SourceDocument:
    """Plain data parsed from a YAML design plus the line of every field path."""

    file: str
    data: Any
    lines: dict[Path_, int] = field(default_factory=dict)
    folder: Path = Path(".")

    def line_of(self, path: Path_) -> int | None:
        """Line of *path*, or of its nearest ancestor that is in the file."""
        path = tuple(path)
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path[:-1]
        return self.lines.get((), None)

    def value_at(self, path: Path_) -> Any:
        """The raw value at *path*, or ``None`` when it is not in the file."""
        node = self.data
        for key in path:
            try:
                node = node[key]
            except (KeyError, IndexError, TypeError):
                return None
        return node

    def locate(self, path: Path_, shown: str | None = None) -> Location:
        """A :class:`Location` for *path*, displayed as *shown* (default: dotted *path*)."""
        return Location(self.file, self.line_of(path), shown if shown is not None else dotted(path))


def dotted(path: Path_) -> str:
    """``("motion", 2, "angle")`` -> ``"motion[2].angle"``."""
    text = ""
    for key in path:
        text += f"[{key}]" if isinstance(key, int) else (f".{key}" if text else str(key))
    return text


def read_design_file(path: str | Path) -> SourceDocument:
    """Read and parse a design file; errors name the file (and the line when there is one)."""
    path = Path(path)
    return parse_yaml(read_design_text(path), str(path), folder=path.parent)


def read_design_text(path: str | Path) -> str:
    """The text of design file *path* (at most :data:`MAX_DESIGN_BYTES`, UTF-8); errors name
    the file (and the line of text that is not UTF-8)."""
    from camfab.errors import InputFileError
    from camfab.files import read_bounded

    path = Path(path)
    name = str(path)
    try:
        raw = read_bounded(path, MAX_DESIGN_BYTES, "a design file")
    except InputFileError as exc:
        problem = "no such design file" if exc.problem == "no such file" else exc.problem
        raise DesignFileError(name, problem) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise DesignError(
            "not a text file (the design must be YAML in UTF-8)",
            location=Location(name, line, ""),
        ) from None
    return text


def parse_yaml(text: str, file: str = "<design>", folder: Path = Path(".")) -> SourceDocument:
    """Parse YAML *text* into a :class:`SourceDocument`."""
    root, data, lines = compose_yaml(text, file)
    if root is None:
        raise DesignError("the design file is empty", location=Location(file, 1, ""))
    if not isinstance(data, dict):
        raise DesignError(
            "a design must be a mapping of keys (name, cam, follower, motion, ...)",
            location=Location(file, root.start_mark.line + 1, ""),
            got=data,
        )
    return SourceDocument(file=file, data=data, lines=lines, folder=folder)


def compose_yaml(text: str, file: str) -> tuple[yaml.Node | None, Any, dict[Path_, int]]:
    """YAML *text* of the file *file* read within the limits (:data:`MAX_DEPTH`,
    :data:`MAX_VALUES`, the tags of plain data): its root node (None when empty), its value,
    and the line of every value by its key path.

    Raises
    ------
    DesignError
        The text is not YAML, or goes past a limit; the message names the line.
    """
    try:
        _check_size(text, file)
        root = yaml.compose(text, Loader=_Loader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        problem = exc.problem or exc.context or "cannot be parsed"
        if "nesting depth" in problem:  # PyYAML's own limit (6.0.4 on) can come before camfab's
            raise DesignError("nested too deeply", location=Location(file, line, "")) from None
        raise DesignError(
            f"invalid YAML: {problem}", location=Location(file, line, "")
        ) from None
    except yaml.YAMLError as exc:  # reader errors: control characters, bad encodings
        mark = getattr(exc, "problem_mark", None)
        raise DesignError(
            f"invalid YAML: {str(exc).splitlines()[0]}",
            location=Location(file, mark.line + 1 if mark else None, ""),
        ) from None
    if root is None:
        return None, None, {}
    builder = _Builder(file)
    return root, builder.build(root, ()), builder.lines


def _check_size(text: str, file: str) -> None:
    """Refuse YAML nested deeper than :data:`MAX_DEPTH` or with more than :data:`MAX_VALUES`
    values, from the parser's flat event stream (before any recursion)."""
    depth = values = 0
    for event in yaml.parse(text, Loader=_Loader):
        if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
            depth += 1
            if depth > MAX_DEPTH:
                raise DesignError("nested too deeply",
                                  location=Location(file, event.start_mark.line + 1, ""))
        elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
            depth -= 1
            continue
        elif not isinstance(event, (yaml.ScalarEvent, yaml.AliasEvent)):
            continue
        values += 1
        if values > MAX_VALUES:
            raise DesignError(f"holds more than {MAX_VALUES:,} values; a design needs far fewer",
                              location=Location(file, event.start_mark.line + 1, ""))


class _Builder:
    """Turns composed nodes into plain data, recording lines by path."""

    def __init__(self, file: str) -> None:
        self.file = file
        self.lines: dict[Path_, int] = {}
        self._scalars = yaml.constructor.SafeConstructor()
        self._depth = 0
        self._built = 0

    def build(self, node: yaml.Node, path: Path_) -> Any:
        self.lines.setdefault(path, node.start_mark.line + 1)
        self._depth += 1
        self._built += 1
        try:
            if self._depth > MAX_DEPTH:
                raise DesignError(
                    "nested too deeply", location=Location(self.file, node.start_mark.line + 1, "")
                )
            if self._built > MAX_VALUES:  # aliases of aliases: an "alias bomb"
                raise DesignError(
                    f"YAML aliases (*name) expand to more than {MAX_VALUES:,} values",
                    location=Location(self.file, node.start_mark.line + 1, ""),
                )
            if isinstance(node, yaml.MappingNode):
                return self._mapping(node, path)
            if isinstance(node, yaml.SequenceNode):
                return [self.build(item, (*path, i)) for i, item in enumerate(node.value)]
            try:
                return self._scalars.construct_object(node)
            except Exception:  # a tag its text does not fit ("!!bool x" is a KeyError): as text
                return node.value
        finally:
            self._depth -= 1

    def _mapping(self, node: yaml.MappingNode, path: Path_) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for key_node, value_node in node.value:
            line = key_node.start_mark.line + 1
            if key_node.tag == "tag:yaml.org,2002:merge":
                raise DesignError(
                    "YAML merge keys (<<) are not supported in designs",
                    location=Location(self.file, line, ""),
                )
            if not isinstance(key_node, yaml.ScalarNode):
                raise DesignError(
                    "keys must be plain names", location=Location(self.file, line, "")
                )
            key = str(key_node.value)
            child = (*path, key)
            if key in out:
                raise DesignError(
                    f"duplicate key '{key}' (first given on line {self.lines[child]})",
                    location=Location(self.file, line, dotted(child)),
                )
            self.lines[child] = line
            out[key] = self.build(value_node, child)
            self.lines[child] = line
        return out
