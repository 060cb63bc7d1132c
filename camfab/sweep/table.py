"""A sweep's table, written as its rows arrive: Parquet (with ``pyarrow``, the ``sweep`` extra)
or CSV, to a temporary file renamed into place when the sweep ends or is stopped, so the table
is always whole (the rows done so far, in order) and readable as the umask allows.

CSV cells: numbers as Python writes them back exactly (``repr``; the key numbers are rounded to 12
significant digits, as the JSON report's), true/false, empty for none.
Parquet columns are typed: the variant an integer, the numbers floats, ``undercut`` a boolean,
the rest text; a varied key's column is integer, float, boolean or text as its values are all
one of those. Rows go out in groups of :data:`GROUP_ROWS`; the bytes depend only on the rows.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager, suppress
from importlib.util import find_spec
from pathlib import Path
from typing import Any

from camfab.sweep.rows import Row

#: Rows per Parquet row group (and per CSV write).
GROUP_ROWS = 4096


def parquet_available() -> bool:
    """Whether ``pyarrow`` is installed (found without importing it)."""
    return find_spec("pyarrow") is not None


class TableWriter:
    """Rows appended in order to ``folder/name`` (``.parquet`` or ``.csv``) through a temporary
    file; :meth:`finish` completes it for the renaming. Any failure to write (a folder it may
    not write, a full disk) removes the temporary file and raises
    :class:`~camfab.errors.OutputError`: ``FOLDER: cannot write the outputs (reason)``."""

    def __init__(self, folder: Path, stem: str, columns: Sequence[str],
                 kinds: dict[str, str], parquet: bool) -> None:
        from camfab.stopping import deferred
        from camfab.writing import open_temp, remove_stale_temps

        self.columns = tuple(columns)
        self.kinds = kinds
        self.parquet = parquet
        self.path = folder / f"{stem}.{'parquet' if parquet else 'csv'}"
        self.temp: Path | None = None
        self._stream: Any = None
        self._buffer: list[Row] = []
        self._writer: Any = None
        self.rows = 0
        with self._guard():
            remove_stale_temps(folder, [self.path.name])
            with deferred():  # a stop comes once the temporary file is made and noted
                self.temp, self._stream = open_temp(folder, self.path.name)
            if not parquet:
                self._stream.write((",".join(_csv_cell(c) for c in self.columns) + "\n")
                                   .encode("utf-8"))

    def add(self, rows: Sequence[Row]) -> None:
        """Append *rows* (in order)."""
        self._buffer.extend(rows)
        self.rows += len(rows)
        if len(self._buffer) >= GROUP_ROWS:
            with self._guard():
                self._flush()

    def _flush(self) -> None:
        while self._buffer:
            group, self._buffer = self._buffer[:GROUP_ROWS], self._buffer[GROUP_ROWS:]
            if self.parquet:
                self._parquet(group)
            else:
                self._stream.write("".join(",".join(_csv_cell(v) for v in row) + "\n"
                                           for row in group).encode("utf-8"))
            if len(group) < GROUP_ROWS:
                break

    def _parquet(self, group: Sequence[Row]) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        schema = pa.schema([(c, _arrow(self.kinds[c])) for c in self.columns])
        table = pa.Table.from_arrays(
            [pa.array([row[i] for row in group], type=schema.field(i).type)
             for i in range(len(self.columns))], schema=schema)
        if self._writer is None:
            self._writer = pq.ParquetWriter(self._stream, schema, compression="zstd")
        self._writer.write_table(table, row_group_size=GROUP_ROWS)

    def finish(self) -> tuple[Path, Path]:
        """The rows flushed and the file closed: (its temporary path, its final path), for
        :func:`camfab.writing.write_files` to rename with the files written beside it."""
        assert self.temp is not None
        with self._guard():
            self._flush()
            if self.parquet:
                if self._writer is None:
                    self._parquet([])
                self._writer.close()
            self._stream.close()
        return self.temp, self.path

    def discard(self) -> None:
        """The temporary file removed (nothing written)."""
        with suppress(Exception):  # a full disk refuses the close's flush as well
            if self._stream is not None:
                self._stream.close()
        if self.temp is not None:
            self.temp.unlink(missing_ok=True)

    @contextmanager
    def _guard(self) -> Iterator[None]:
        """A failure to write inside the block: the temporary file removed, and one line."""
        try:
            yield
        except BaseException as exc:
            if not _write_failure(exc):
                raise
            from camfab.writing import cannot_write

            self.discard()
            if not isinstance(exc, OSError):  # pyarrow's own error of a write
                exc = OSError(" ".join(str(exc).split())[:200])
            raise cannot_write(self.path.parent, exc) from None


def _write_failure(exc: BaseException) -> bool:
    """True when *exc* is a failure to write: an OSError, or pyarrow's error of one."""
    if isinstance(exc, OSError):
        return True
    import sys

    arrow = sys.modules.get("pyarrow.lib")
    return arrow is not None and isinstance(exc, arrow.ArrowException)


def _arrow(kind: str) -> Any:
    import pyarrow as pa

    return {"int": pa.int64(), "float": pa.float64(), "bool": pa.bool_(), "text": pa.string()}[
        kind]


def column_kinds(paths: Sequence[str], values: Sequence[Sequence[Any]],
                 columns: Sequence[str]) -> dict[str, str]:
    """Each column's kind (``int``, ``float``, ``bool``, ``text``): the varied keys' by the
    *values* each takes (a mix of integers and floats is float; anything else mixed, text)."""
    kinds = {c: "float" for c in columns}
    kinds.update(variant="int", status="text", message="text", motion_units="text",
                 undercut="bool")
    for path, taken in zip(paths, values, strict=True):
        kinds[path] = _kind(taken)
    return kinds


def _kind(values: Sequence[Any]) -> str:
    if all(isinstance(v, bool) for v in values):
        return "bool"
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return "int"
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return "float"
    return "text"


def cell(value: Any, kind: str) -> Any:
    """*value* as its column of *kind* holds it (a number in a text column as text)."""
    if value is None:
        return None
    if kind == "text":
        return value if isinstance(value, str) else _csv_text(value)
    if kind == "float":
        return float(value)
    return value


def typed(row: Row, columns: Sequence[str], kinds: dict[str, str]) -> Row:
    """*row* with each cell as its column's kind holds it."""
    return tuple(cell(v, kinds[c]) for v, c in zip(row, columns, strict=True))


def _csv_text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _csv_cell(value: Any) -> str:
    if value is None:
        return ""
    text = _csv_text(value)
    if any(c in text for c in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text
