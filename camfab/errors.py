"""The errors camfab raises.

Every error derives from :class:`CamfabError`; the subclasses also inherit the matching builtin so
callers can catch ``ValueError`` or ``OSError`` as usual. Errors carry their fields and build the
message from them; the command line prints ``str(error)`` as its one line and exits with status 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass


class CamfabError(Exception):
    """Base of every error camfab raises on purpose."""


class CommandError(CamfabError, ValueError):
    """A command's options refused: one line, after ``camfab COMMAND:``, naming the option and
    the problem (exit 2). What the user typed is echoed: a character that is not printable (a
    line or record separator, a control) is shown escaped, so the message stays one line on
    any terminal."""

    command = ""

    def __init__(self, message: str) -> None:
        shown = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)
        super().__init__(f"camfab {self.command}: {shown}")


@dataclass(frozen=True)
class Location:
    """Where in a design file something is: file name, 1-based line, dotted field path."""

    file: str
    line: int | None
    field: str

    def __str__(self) -> str:
        where = self.file if self.line is None else f"{self.file}:{self.line}"
        return f"{where}: {self.field}" if self.field else where


class DesignError(CamfabError, ValueError):
    """An invalid design: one line ``FILE:LINE: field.path: problem (got X; allowed ...)``.

    Parameters
    ----------
    problem
        What is wrong, phrased as the rule that is broken ("must be > 0").
    location
        Where it is; filled in by the loader when raised without one.
    got
        The offending value as the user wrote it (``None``: not shown).
    allowed
        The valid choices or range, shown after ``allowed:``.
    hint
        A suggestion such as ``did you mean 'cycloidal'?``.
    kind
        What kind of value the schema refused, pydantic's error type (``float_parsing``,
        ``literal_error``, ``extra_forbidden``, ...); empty for a broken design rule.
    """

    def __init__(
        self,
        problem: str,
        *,
        field: str = "",
        location: Location | None = None,
        got: object = None,
        allowed: Sequence[str] | str | None = None,
        hint: str | None = None,
        show_got: bool = True,
        kind: str = "",
    ) -> None:
        self.problem = problem
        self.kind = kind
        self.field = field or (location.field if location else "")
        self.location = location
        self.got = got
        self.allowed = allowed
        self.hint = hint
        self.show_got = show_got and got is not None
        super().__init__(self._message())

    def _message(self) -> str:
        parts = []
        if self.show_got:
            parts.append(f"got {_show(self.got)}")
        if self.hint:
            parts.append(self.hint)
        if self.allowed:
            allowed = self.allowed if isinstance(self.allowed, str) else ", ".join(self.allowed)
            parts.append(f"allowed: {allowed}")
        detail = f" ({'; '.join(parts)})" if parts else ""
        if self.location is not None:
            head = str(self.location)
        else:
            head = self.field
        text = f"{head}: {self.problem}{detail}" if head else f"{self.problem}{detail}"
        return " ".join(text.split())  # always one line


class DesignFileError(CamfabError, OSError):
    """A design file that cannot be read at all (missing, a folder, not text)."""

    def __init__(self, file: str, problem: str) -> None:
        self.file = file
        self.problem = problem
        super().__init__(f"{file}: {problem}")


class InputFileError(CamfabError, OSError):
    """An input file refused before it is read: ``FILE: problem`` (missing, a folder, not a
    regular file, or larger than the reader takes)."""

    def __init__(self, file: str, problem: str) -> None:
        self.file = file
        self.problem = problem
        super().__init__(" ".join(f"{file}: {problem}".split()))


class OutputError(CamfabError, OSError):
    """Outputs that cannot be written (no permission, disk full, a file in the way)."""


def did_you_mean(word: object, choices: Sequence[str], cutoff: float = 0.6) -> str | None:
    """``"did you mean 'x'?"`` for the choice closest to *word*, or None when none is close."""
    import difflib

    if not isinstance(word, str):
        return None
    match = difflib.get_close_matches(word.lower(), list(choices), n=1, cutoff=cutoff)
    return f"did you mean '{match[0]}'?" if match else None


def _show(value: object) -> str:
    """A short, one-line rendering of a user value for messages."""
    if isinstance(value, str):
        text = repr(value)
    elif isinstance(value, bool):
        text = "true" if value else "false"
    elif value is None:
        text = "null"
    elif isinstance(value, float):
        text = f"{value:g}"
    elif isinstance(value, dict):
        text = "a mapping {" + ", ".join(str(k) for k in list(value)[:4]) + "}"
    elif isinstance(value, (list, tuple)):
        text = f"a list of {len(value)}"
    else:
        text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class OutlineError(CamfabError, ValueError):
    """An outline file that cannot be used: ``FILE[:LINE]: problem``."""

    def __init__(self, file: str, problem: str, line: int | None = None) -> None:
        self.file = file
        self.problem = problem
        self.line = line
        where = file if line is None else f"{file}:{line}"
        super().__init__(" ".join(f"{where}: {problem}".split()))


class ScanError(OutlineError):
    """A 3-D scan file that cannot be used: ``FILE[:LINE]: problem``."""


class InspectionError(CamfabError, ValueError):
    """An inspection that cannot be run: ``WHAT: problem`` (a file or an option)."""

    def __init__(self, what: str, problem: str) -> None:
        self.what = what
        self.problem = problem
        super().__init__(" ".join(f"{what}: {problem}".split()))
