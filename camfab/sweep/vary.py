"""What a sweep varies: ``--vary PATH=SPEC`` options (their product) or a CSV of variants, and
a variant's design data.

A PATH names a key of the design as camfab's messages do: ``cam.base_radius``,
``follower.offset``, ``motion[0].law`` (a segment's key, whatever its kind), ``cam.speed_rpm``.
A SPEC is a range ``START:STOP:STEP`` (STOP included when a step lands on it), a list
``a,b,c`` (each item read as YAML reads a scalar: ``20``, ``cycloidal``, ``1 in``), or
``log:START:STOP:N`` (N values spaced evenly in log between START and STOP, both included).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camfab.errors import CommandError

#: The most variants one sweep takes (count): ten million rows of a few hundred bytes each.
MAX_VARIANTS = 10_000_000
#: The most values one ``--vary`` gives (count).
MAX_VALUES = 1_000_000
#: The largest ``--variants`` file (bytes).
MAX_VARIANTS_BYTES = 64 * 2**20
#: The most rows a ``--variants`` file gives (count): each is held in memory (a product of
#: ``--vary`` options is counted instead, up to :data:`MAX_VARIANTS`).
MAX_FILE_VARIANTS = 1_000_000
#: The most keys one sweep varies (count).
MAX_KEYS = 100

_PATH = re.compile(r"^[a-z_][a-z0-9_]*(\[\d+\])?(\.[a-z_][a-z0-9_]*(\[\d+\])?)*$")
_PART = re.compile(r"([a-z_][a-z0-9_]*)(?:\[(\d+)\])?")
#: The segment kinds a motion entry is keyed by: ``motion[0].law`` reaches into the one present.
SEGMENT_KINDS = ("rise", "dwell", "return")


class SweepError(CommandError):
    """A sweep's options refused: one line naming the option and the problem (exit 2), after
    ``camfab sweep:``."""

    command = "sweep"


@dataclass(frozen=True)
class Vary:
    """One varied key: its *path* as written, its keys (names and list indices), and values."""

    path: str
    keys: tuple[str | int, ...]
    values: tuple[Any, ...]


def parse_path(path: str, option: str) -> tuple[str | int, ...]:
    """The keys of a PATH such as ``motion[0].law`` (raises :class:`SweepError`)."""
    if not _PATH.match(path):
        raise SweepError(f"{option}: {path!r} is not a key of the design (write it as "
                         f"cam.base_radius or motion[0].law)")
    keys: list[str | int] = []
    for part in path.split("."):
        match = _PART.fullmatch(part)
        assert match is not None
        keys.append(match.group(1))
        if match.group(2) is not None:
            keys.append(int(match.group(2)))
    return tuple(keys)


def parse_vary(text: str) -> Vary:
    """A ``--vary PATH=SPEC`` option (raises :class:`SweepError`)."""
    option = f"--vary {text}"
    path, sep, spec = text.partition("=")
    path = path.strip()
    if not sep or not spec.strip():
        raise SweepError(f"{option}: give PATH=SPEC, such as cam.base_radius=20:40:5")
    return Vary(path, parse_path(path, option), parse_spec(spec.strip(), option))


def _number(text: str, option: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise SweepError(f"{option}: the {what} {text!r} is not a number") from None
    if not math.isfinite(value):
        raise SweepError(f"{option}: the {what} {text!r} is not a finite number")
    return value


def parse_spec(spec: str, option: str) -> tuple[Any, ...]:
    """The values of a SPEC: a range, a log range or a list (see the module)."""
    if spec.startswith("log:"):
        parts = spec[4:].split(":")
        if len(parts) != 3:
            raise SweepError(f"{option}: write a log range as log:START:STOP:N")
        start, stop = (_number(p, option, w) for p, w in zip(parts[:2], ("start", "stop"),
                                                              strict=True))
        count = _number(parts[2], option, "count")
        if start <= 0 or stop <= 0:
            raise SweepError(f"{option}: a log range's start and stop must be > 0")
        if count != int(count) or count < 1:
            raise SweepError(f"{option}: the count {parts[2]!r} must be a whole number ≥ 1")
        if count > MAX_VALUES:
            raise SweepError(f"{option}: {int(count):,} values; at most {MAX_VALUES:,}")
        n = int(count)
        if n == 1:
            return (start,)
        low, ratio = math.log(start), math.log(stop) - math.log(start)  # (no overflow)
        return tuple(_tidy(math.exp(low + ratio * i / (n - 1))) for i in range(n))
    if ":" in spec and "," not in spec:
        parts = spec.split(":")
        if len(parts) != 3:
            raise SweepError(f"{option}: write a range as START:STOP:STEP")
        start, stop, step = (_number(p, option, w) for p, w in zip(parts, ("start", "stop",
                                                                           "step"),
                                                                    strict=True))
        if step == 0:
            raise SweepError(f"{option}: the step must not be 0")
        span = (stop - start) / step
        if not math.isfinite(span):  # the difference overflowed; each quotient may not
            span = stop / step - start / step
        if span < -1e-9:
            raise SweepError(f"{option}: the range is empty (a step of {parts[2]} never goes "
                             f"from {parts[0]} to {parts[1]})")
        if not span < MAX_VALUES:  # (infinite too: a step too small to count)
            raise SweepError(f"{option}: more than {MAX_VALUES:,} values; at most "
                             f"{MAX_VALUES:,}")
        count = math.floor(span + 1e-9) + 1
        values = tuple(_tidy(_step_value(start, step, i)) for i in range(count))
        if not all(math.isfinite(v) for v in values):
            raise SweepError(f"{option}: the range goes past the largest number")
        return values
    items = [item.strip() for item in spec.split(",")]
    if not any(items):
        raise SweepError(f"{option}: the list is empty")
    if not all(items):
        raise SweepError(f"{option}: the list has an empty item")
    if len(items) > MAX_VALUES:
        raise SweepError(f"{option}: {len(items):,} values; at most {MAX_VALUES:,}")
    read = _scalars()
    return tuple(read(item) for item in items)


def _step_value(start: float, step: float, i: int) -> float:
    """The *i*-th value of a range from *start* by *step*: ``start + i·step``, or, where that
    overflows on the way, ``(start/step + i)·step``."""
    value = start + i * step
    return value if math.isfinite(value) else (start / step + i) * step


def _tidy(value: float) -> float:
    """*value* rounded to 12 significant digits: 0.1 + 2 × 0.1 is 0.3, as written."""
    return float(f"{value:.12g}")


def scalar(text: str) -> Any:
    """*text* as YAML reads a scalar in a design file: a number, true/false, or text."""
    import yaml

    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        return text
    return value if isinstance(value, (int, float, str, bool)) else text


def count_of(varies: Sequence[Vary]) -> int:
    """How many variants the product of *varies* makes."""
    return math.prod(len(v.values) for v in varies)


def product_values(varies: Sequence[Vary], index: int) -> tuple[Any, ...]:
    """The values of variant *index* of the product of *varies*, the last varying fastest."""
    values = []
    for vary in reversed(varies):
        index, at = divmod(index, len(vary.values))
        values.append(vary.values[at])
    return tuple(reversed(values))


@dataclass(frozen=True)
class Variants:
    """The variants of a sweep: the varied paths and keys, and each variant's values, by index
    (from the product of ``--vary`` options, or from the rows of a ``--variants`` file)."""

    paths: tuple[str, ...]
    keys: tuple[tuple[str | int, ...], ...]
    varies: tuple[Vary, ...] = ()
    rows: tuple[tuple[Any, ...], ...] = ()

    @property
    def count(self) -> int:
        return count_of(self.varies) if self.varies else len(self.rows)

    def values(self, index: int) -> tuple[Any, ...]:
        return product_values(self.varies, index) if self.varies else self.rows[index]

    def taken(self, key: int) -> Sequence[Any]:
        """The values varied key *key* takes (a ``--vary``'s, or a file's column)."""
        return self.varies[key].values if self.varies else [row[key] for row in self.rows]

    def batches(self, size: int) -> Iterator[list[tuple[int, tuple[Any, ...]]]]:
        """The variants in order, *size* at a time, each with its index."""
        for start in range(0, self.count, size):
            yield [(i, self.values(i)) for i in range(start, min(start + size, self.count))]


def from_varies(varies: Sequence[Vary]) -> Variants:
    """The product of the ``--vary`` options (raises :class:`SweepError`)."""
    paths = [v.path for v in varies]
    if len(paths) > MAX_KEYS:
        raise SweepError(f"--vary: {len(paths):,} keys varied; at most {MAX_KEYS}")
    repeated = _repeated(paths)
    if repeated:
        raise SweepError(f"--vary {repeated}: given twice")
    if count_of(varies) > MAX_VARIANTS:
        raise SweepError(f"--vary: {count_of(varies):,} variants; at most {MAX_VARIANTS:,}")
    return Variants(tuple(paths), tuple(v.keys for v in varies), tuple(varies))


def from_file(path: Path) -> Variants:
    """The variants of a CSV file: a header of PATHs, then one row of values per variant
    (raises :class:`SweepError`). Each limit is checked as soon as the file passes it: its size
    before it is read, its keys at the header, its rows as they are read."""
    import csv
    import io

    from camfab.errors import InputFileError
    from camfab.files import read_bounded

    option = f"--variants {path}"
    try:
        raw = read_bounded(path, MAX_VARIANTS_BYTES, "a variants file")
    except InputFileError as exc:
        raise SweepError(f"{option}: {exc.problem}") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise SweepError(f"{option}: not a UTF-8 text file") from None
    del raw
    reader = csv.reader(io.StringIO(text))
    header: list[str] | None = None
    rows: list[tuple[Any, ...]] = []
    read = _scalars()
    try:
        for cells in reader:
            if not any(c.strip() for c in cells):
                continue
            if header is None:
                if len(cells) > MAX_KEYS:
                    raise SweepError(f"{option}: the header has {len(cells):,} keys; a sweep "
                                     f"varies at most {MAX_KEYS}")
                header = [c.strip() for c in cells]
                continue
            if len(cells) != len(header):
                raise SweepError(f"{option}: line {reader.line_num} has {len(cells)} values "
                                 f"for {len(header)} keys")
            if len(rows) == MAX_FILE_VARIANTS:
                raise SweepError(f"{option}: more than {MAX_FILE_VARIANTS:,} variants; a "
                                 f"variants file gives at most {MAX_FILE_VARIANTS:,}")
            rows.append(tuple(read(c.strip()) for c in cells))
    except csv.Error as exc:
        raise SweepError(f"{option}: line {reader.line_num}: not readable as CSV "
                         f"({' '.join(str(exc).split())[:120]})") from None
    if header is None:
        raise SweepError(f"{option}: the file is empty (give a header of keys, then rows)")
    keys = tuple(parse_path(p, f"{option}: header") for p in header)
    repeated = _repeated(header)
    if repeated:
        raise SweepError(f"{option}: the key {repeated} is given twice in the header")
    if not rows:
        raise SweepError(f"{option}: no variants (only the header)")
    return Variants(tuple(header), keys, rows=tuple(rows))


def _repeated(paths: Sequence[str]) -> str | None:
    """The first of *paths* (in sorted order) given more than once, or None."""
    from collections import Counter

    return min((p for p, n in Counter(paths).items() if n > 1), default=None)


_INT = re.compile(r"[-+]?(?:0|[1-9][0-9]*)")
_FLOAT = re.compile(r"[-+]?[0-9]+\.[0-9]+")


def _scalars() -> Callable[[str], Any]:
    """:func:`scalar`, remembered for each text it is given, and at once for plain decimal
    numbers (read as YAML reads them): a variants file's million cells take seconds, not
    minutes."""
    seen: dict[str, Any] = {}

    def read(text: str) -> Any:
        value = seen.get(text)
        if value is None:
            if _INT.fullmatch(text):
                value = int(text)
            elif _FLOAT.fullmatch(text):
                value = float(text)
            else:
                value = scalar(text)
            if len(seen) < MAX_FILE_VARIANTS:
                seen[text] = value
        return value

    return read


def with_values(data: dict[str, Any], keys: Sequence[tuple[str | int, ...]],
                values: Sequence[Any]) -> dict[str, Any]:
    """The design data *data* with each key path of *keys* set to its value (the mappings and
    lists along each path copied, the rest shared). A motion entry's keys are those of its one
    segment (``motion[0].law`` is the law of the first segment, a rise or a return). Raises
    :class:`LookupError` naming the path where a list is too short or a value is not a
    mapping."""
    out = dict(data)
    for path, value in zip(keys, values, strict=True):
        _set(out, path, value)
    return out


def dotted(keys: Sequence[str | int]) -> str:
    """Key paths as written: ``motion[0].law``."""
    return "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in keys).lstrip(".")


def _set(node: dict[str, Any] | list[Any], path: tuple[str | int, ...], value: Any,
         above: tuple[str | int, ...] = ()) -> None:
    head, rest = path[0], path[1:]
    where = dotted(above) or "the design"
    if isinstance(head, int):
        if not isinstance(node, list) or head >= len(node):
            size = len(node) if isinstance(node, list) else 0
            raise LookupError(f"{where} has {size} entries, no [{head}]")
    elif not isinstance(node, dict):
        raise LookupError(f"{where} is not a mapping, no .{head}")
    child = node[head] if isinstance(node, list) else node.get(head)  # type: ignore[index]
    if not rest:
        node[head] = value  # type: ignore[index]
        return
    if isinstance(child, dict):
        child = dict(child)
        # a motion entry: {rise: {...}}; its keys are its segment's
        segment = [k for k in child if k in SEGMENT_KINDS]
        if isinstance(head, int) and len(child) == 1 and segment and rest[0] not in child:
            inner = child[segment[0]]
            inner = dict(inner) if isinstance(inner, dict) else {}
            _set(inner, rest, value, (*above, head))
            child[segment[0]] = inner
            node[head] = child  # type: ignore[index]
            return
    elif isinstance(child, list):
        child = list(child)
    elif child is None:
        child = {} if isinstance(rest[0], str) else []
    else:
        raise LookupError(f"{dotted((*above, head))} is {child!r}, not a mapping")
    _set(child, rest, value, (*above, head))
    node[head] = child  # type: ignore[index]
