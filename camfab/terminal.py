"""The ``camfab`` program's standard output and error: written in whatever encoding they have,
and a failure to write them noted rather than raised.

A terminal or pipe need not take UTF-8 (a latin-1 or ASCII locale, a Windows code page): the
characters camfab prints that its encoding lacks (✔ ✖ — θ ° …) are written as ASCII stand-ins
("ok", "x", "-", "theta", " deg", "...") instead of ending the command in a
``UnicodeEncodeError``. Standard output that cannot be written — a full disk, a closed stdout
(``>&-``), a pipe whose reader is gone — does not raise in the middle of the work either: the
first failure is noted, what follows is dropped, and the program ends with one line
(:func:`failure_line`) and :data:`CANNOT_WRITE`. Installed by the program's entry point alone
(:mod:`camfab.start`); camfab used as a library leaves the process's streams as they are.
"""

from __future__ import annotations

import codecs
import errno
import io
import os
import sys
import unicodedata

#: Exit status when standard output could not be written (``EX_IOERR`` of sysexits.h).
CANNOT_WRITE = 74

#: The name of the codec error handler that writes ASCII stand-ins (:func:`stand_in`).
ERRORS = "camfab-stand-ins"

#: ASCII stand-ins of the characters camfab prints that an encoding may lack.
STAND_INS = {
    "✔": "ok", "✖": "x", "—": "-", "–": "-", "−": "-", "‐": "-", "°": " deg", "×": "x",
    "…": "...", "≤": "<=", "≥": ">=", "±": "+/-", "→": "->", "←": "<-", "∞": "inf",
    "·": ".", "′": "'", "″": "''", "‘": "'", "’": "'", "“": '"', "”": '"', "µ": "u",
    "√": "sqrt", "≈": "~", "≠": "!=", "²": "^2", "³": "^3", "½": "1/2", "¼": "1/4",
    "ℓ": "l", "∂": "d", "⊥": "_|_", "§": "S", "\u00a0": " ", "\u2009": " ",
}


def stand_in(char: str) -> str:
    """The ASCII stand-in of *char*: from :data:`STAND_INS`, a Greek letter's name ("theta",
    "Psi"), the letter or digit it decomposes to ("é" → "e", "₀" → "0"), else "?"."""
    if char in STAND_INS:
        return STAND_INS[char]
    name = unicodedata.name(char, "")
    if name.startswith("GREEK") and "LETTER" in name:
        word = name.split()[-1].lower()
        return word.capitalize() if "CAPITAL" in name else word
    plain = unicodedata.normalize("NFKD", char).encode("ascii", "ignore").decode("ascii")
    return plain or "?"


def _stand_ins(exc: UnicodeError) -> tuple[str, int]:
    """The codec error handler :data:`ERRORS`: the unencodable characters as ASCII."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text, start = exc.object, exc.start
    out = "".join(stand_in(c) for c in text[start:exc.end])
    if out.startswith(" ") and (start == 0 or not text[start - 1].isalnum()):
        out = out[1:]  # "40°" reads "40 deg", "(°)" reads "(deg)"
    return out, exc.end


codecs.register_error(ERRORS, _stand_ins)


class _Ascii(codecs.CodecInfo):
    """ASCII under a name of camfab's, for a stream whose encoding is ASCII: command-line
    libraries that take an ASCII stream for a misconfigured one (and write UTF-8 into it
    instead) see a stream of its own encoding, and write to it through :data:`ERRORS`."""


def _search(name: str) -> codecs.CodecInfo | None:
    if name != "camfab_ascii":
        return None
    ascii_ = codecs.lookup("ascii")
    return _Ascii(ascii_.encode, ascii_.decode, name="camfab-ascii",
                  incrementalencoder=ascii_.incrementalencoder,
                  incrementaldecoder=ascii_.incrementaldecoder,
                  streamwriter=ascii_.streamwriter, streamreader=ascii_.streamreader)


codecs.register(_search)


class _Noting(io.RawIOBase):
    """The file descriptor *fd* written straight (``os.write``); the first failure is noted in
    :attr:`failure` and that write and every later one are dropped, not raised."""

    def __init__(self, fd: int, failure: OSError | None = None) -> None:
        super().__init__()
        self.fd = fd
        self.failure = failure

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self.fd

    def isatty(self) -> bool:
        return self.failure is None and os.isatty(self.fd)

    def write(self, data) -> int:  # type: ignore[no-untyped-def]
        size = len(memoryview(data))
        if self.failure is not None:
            return size
        try:
            return os.write(self.fd, data)
        except InterruptedError:
            return 0
        except OSError as exc:
            self.failure = exc
            return size


#: The noting writers under the program's stdout and stderr (empty: not installed).
_RAW: dict[str, _Noting] = {}


def install() -> None:
    """Make the process's standard streams camfab's: stdout and stderr written through
    :class:`_Noting` in their own encoding with :data:`ERRORS`, and a closed standard file
    descriptor (0, 1, 2) opened on the null device, so that no file a command opens takes its
    number (and gets what is printed); a closed stdout is noted as a failure to write it."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            _occupy(fd)
    for name, fd in (("stdout", 1), ("stderr", 2)):
        stream = getattr(sys, name)
        closed = stream is None
        what = "output" if name == "stdout" else "error"
        failure = OSError(errno.EBADF, f"standard {what} is closed") if closed else None
        encoding = _encoding_of(stream)
        raw = _Noting(fd, failure)
        tty = raw.isatty()
        if name == "stdout":
            wrapped = io.TextIOWrapper(io.BufferedWriter(raw), encoding=encoding,
                                       errors=ERRORS, line_buffering=tty)
        else:
            wrapped = io.TextIOWrapper(io.BufferedWriter(raw), encoding=encoding,
                                       errors=ERRORS, line_buffering=True, write_through=True)
        if stream is not None:
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        setattr(sys, name, wrapped)
        _RAW[name] = raw


def _occupy(fd: int) -> None:
    """Open the null device on the closed file descriptor *fd*."""
    null = os.open(os.devnull, os.O_RDWR)
    if null != fd:
        os.dup2(null, fd)
        os.close(null)


def _encoding_of(stream: object) -> str:
    """The encoding to write *stream*'s descriptor in: its own (ASCII as ``camfab-ascii``)."""
    name = getattr(stream, "encoding", None) or "utf-8"
    try:
        name = codecs.lookup(name).name
    except LookupError:
        return "utf-8"
    return "camfab-ascii" if name == "ascii" else name


def failure() -> OSError | None:
    """The first failure to write standard output (flushed first), None when none came or the
    streams are not camfab's."""
    raw = _RAW.get("stdout")
    if raw is None:
        return None
    try:
        sys.stdout.flush()
    except (OSError, ValueError):
        pass
    return raw.failure


def failure_line(exc: OSError) -> str:
    """The one line a failure to write standard output prints."""
    return f"camfab: cannot write the output ({exc.strerror or exc})"


def fit(text: str, stream: object = None) -> str:
    """*text* as the stream (default: standard output) can write it: the characters its
    encoding lacks as their ASCII stand-ins (:func:`stand_in`). For text laid out before it is
    written (a table's cells), whose widths must be those of what is written."""
    stream = sys.stdout if stream is None else stream
    encoding = getattr(stream, "encoding", None) or "utf-8"
    try:
        return text.encode(encoding, errors=ERRORS).decode(encoding)
    except (LookupError, UnicodeError):
        return text
