"""The studio's state: one design file, the edits made in the page and not saved yet, the last
design that loaded, and what the page shows of it.

A change (an edit, the file saved in an editor, a table law's CSV changed) makes a new
*version*: the design is loaded from the text and analysed at once, and the report page of
that analysis (:func:`~camfab.export.report_html.render_report_html`) is what the page redraws
— tens of milliseconds. The sizing advice of the failed checks (a search of some hundredths of
a second), the files, their read-back and the verification (``camfab build``'s work, up to
seconds for a globoid) follow for the latest version only, a moment after the changes stop
(:data:`SETTLE_SECONDS`), and bring the verified report, its JSON (the same bytes as the
build's ``NAME-report.json``) and the part's STL for the 3-D view.

No web library is imported here: :mod:`camfab.serve.app` puts this behind HTTP.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab.errors import CamfabError

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design import Design
    from camfab.pipeline import Artifacts

#: How long the changes must stop (s) before the files are made and read back for the latest
#: version: while a slider is dragged only the analysis runs, which keeps each redraw quick.
SETTLE_SECONDS = 0.4


class Conflict(CamfabError):
    """The design file changed on disk since the studio loaded it (a save would lose that)."""


class Stale(CamfabError):
    """A version asked for is no longer the current one."""


class Unreadable(CamfabError):
    """The text is not YAML the studio's editor can read (a tab, a second document): its one
    line; the file is to be mended in an editor."""


@dataclass(frozen=True)
class Broken:
    """The edit after which a design that loaded no longer loads: the version it made, its
    path and value, and the text before it (the next edit is made on that text)."""

    version: int
    path: str
    value: Any
    before: str


@dataclass(frozen=True)
class View:
    """What the page shows of one version: the design's report page from its analysis (the
    verification still to come), or the located line of why the text does not load (the page
    then keeps the last good picture)."""

    version: int
    html: str | None
    error: str | None
    name: str | None


@dataclass(frozen=True)
class Verified:
    """One version built as ``camfab build`` builds it: its files (bytes by name), the
    verified analysis, the report page and JSON, and the part's STL files for the 3-D view."""

    version: int
    artifacts: Artifacts
    analysis: Analysis
    html: str
    report_json: bytes
    stl_names: tuple[str, ...]


class Studio:
    """The studio of the design file *path* (*label*: the path as the user gave it, which the
    messages name). *notify* is called with an event name and its data (JSON-able, or text
    as it is) after each change: ``state`` for a new version, ``verified`` when its files are
    made and read back, then ``report`` with its report JSON; it may be called from any
    thread."""

    def __init__(self, path: Path, label: str,
                 notify: Callable[[str, dict[str, Any] | str], None] | None = None) -> None:
        from camfab.design.source import read_design_text

        self.path = path
        self.label = label
        self.notify = notify or (lambda event, data: None)
        self._lock = threading.RLock()
        self.disk_text = read_design_text(path)  # raises on a missing or unreadable file
        self.text = self.disk_text
        self.conflict = False
        self.version = 0
        self.view = View(0, None, None, None)
        self.good: tuple[Design, Analysis] | None = None  # the last version that loaded
        self._verified: Verified | None = None
        self._timer: threading.Timer | None = None
        self._building = threading.Lock()
        self._broken: Broken | None = None
        self._change(self.text, origin="load")

    # --- the state -----------------------------------------------------------------------

    @property
    def edited(self) -> bool:
        """True when the page's edits are not saved."""
        return self.text != self.disk_text

    @property
    def broken(self) -> dict[str, Any] | None:
        """The edit that made the current version fail to load, ``{"path": …, "value": …}``
        (None when it loads, or when what does not load is the file's own text)."""
        broken = self._broken
        if broken is None or broken.version != self.version:
            return None
        return {"path": broken.path, "value": broken.value}

    def state(self, fields: bool = True) -> dict[str, Any]:
        """The page's view of the studio: the version, its report page or error, whether there
        are edits to save and whether the file changed on disk meanwhile, and (with *fields*)
        the values to edit."""
        from camfab.serve.yamledit import fields as values

        view = self.view
        state = {"version": view.version, "html": view.html, "error": view.error,
                 "name": view.name, "file": self.label, "edited": self.edited,
                 "conflict": self.conflict}
        if fields:
            try:
                state["fields"] = [f.as_json() for f in values(self.text)]
            except Exception:  # a text YAML cannot read: its line is the error shown
                state["fields"] = []
        return state

    def _summary(self, origin: str) -> dict[str, Any]:
        view = self.view
        return {"version": view.version, "error": view.error, "edited": self.edited,
                "conflict": self.conflict, "origin": origin}

    def _change(self, text: str, origin: str) -> View:
        """Load and analyse *text* as the next version; the page's view of it."""
        from camfab.export.report_html import render_report_html
        from camfab.pipeline import analyse, design_from_text

        with self._lock:
            self.text = text
            self.version += 1
            version = self.version
            try:
                design = design_from_text(text, self.label, self.path.parent)
                analysis = analyse(design, advice=False)  # the advice comes with the files
                html = render_report_html(analysis).decode("utf-8")
            except CamfabError as exc:
                self.view = View(version, self.view.html, str(exc), self.view.name)
            except Exception as exc:  # a fault of camfab's: said as the build says it
                line = (f"{self.label}: internal error: {type(exc).__name__}: {exc} (please "
                        "report it)")
                self.view = View(version, self.view.html, line, self.view.name)
            else:
                self.good = (design, analysis)
                self.view = View(version, html, None, design.name)
            self._verified = None
            self.notify("state", self._summary(origin))
            if self.view.error is None:
                self._settle()
            return self.view

    # --- what the page and the API do ------------------------------------------------------

    def edit(self, path: str, value: Any) -> View:
        """Set the key at *path* to *value* in the text (not saved) and analyse it.

        An edit after which a design that loaded does not load any more is shown (its
        located line; :attr:`broken` names it) and taken back by the next edit, which is made
        on the text before it: a later edit's own error is never masked by it, and a valid
        edit clears it.

        Raises
        ------
        EditError
            A path the design has not (with the closest path it has), or a value that is not
            a number, a word or true/false.
        Unreadable
            The text is not YAML the editor can read: the design's own located line.
        """
        from camfab.serve.yamledit import EditError, NotYaml, set_value

        with self._lock:
            broken = self._broken if self.broken is not None else None
            base = self.text if broken is None else broken.before
            try:
                text = set_value(base, path, value)
            except NotYaml as exc:
                raise Unreadable(self.view.error or _yaml_line(self.label, exc)) from None
            except EditError as exc:
                raise _suggested(exc, path, base) from None
            except RecursionError as exc:
                raise Unreadable(self.view.error or _yaml_line(self.label, exc)) from None
            loaded = broken is not None or self.view.error is None
            view = self._change(text, origin="edit")
            self._broken = (Broken(view.version, path, value, base)
                            if view.error is not None and loaded else None)
            return view

    def from_disk(self) -> bool:
        """Read the file again after a change on disk (or of a table law's CSV file): the page
        follows it, unless it holds edits not saved, which are kept (and a save refused); True
        when it made a new version."""
        from camfab.design.source import read_design_text

        with self._lock:
            try:
                text = read_design_text(self.path)
            except CamfabError as exc:  # gone, or unreadable, for now: say so, keep the rest
                self.fault(str(exc))
                return False
            if self.edited:
                if text != self.disk_text:
                    self.conflict = True
                    self.notify("state", self._summary("disk"))
                return False
            if text == self.disk_text and self.view.error is None:  # touched, not changed
                return False
            self.disk_text = text
            self._change(text, origin="disk")
            return True

    def fault(self, line: str) -> None:
        """Show *line* in the design's error's place (the file cannot be read, or watched,
        for now), the last good picture kept."""
        with self._lock:
            self.view = View(self.version, self.view.html, line, self.view.name)
            self.notify("state", self._summary("disk"))

    def again(self) -> None:
        """Analyse the text again: after a change of the table laws' CSV files it names, or
        once a fault said in its place is over."""
        with self._lock:
            self._change(self.text, origin="disk")

    def reload(self) -> View:
        """Drop the edits and take the file as it is on disk."""
        from camfab.design.source import read_design_text

        with self._lock:
            self.disk_text = read_design_text(self.path)
            self.conflict = False
            return self._change(self.disk_text, origin="reload")

    def save(self) -> str:
        """Write the edited text into the design file (:func:`~camfab.writing.replace_file`:
        as one step, through a symbolic link to its target, the file's permissions, owner and
        group kept, a hard-linked file written in place); the file's path. Refused
        (:class:`Conflict`) when the file changed on disk since it was loaded; raises
        :class:`~camfab.errors.OutputError` (its ``errno`` the system's) when it cannot be
        written, the edits kept."""
        from camfab.design.source import read_design_text
        from camfab.writing import replace_file

        with self._lock:
            try:
                now = read_design_text(self.path)
            except CamfabError:
                now = None
            if self.conflict or now != self.disk_text:
                self.conflict = True
                self.notify("state", self._summary("disk"))
                raise Conflict(f"{self.label}: changed on disk since the studio loaded it; not "
                               "saved (Reload takes the file as it is, dropping the edits)")
            if self.edited:
                replace_file(self.path, self.text.encode("utf-8"), self.label)
                self.disk_text = self.text
                self._broken = None  # what is saved is the file's own, error and all
            self.notify("state", self._summary("save"))
            return self.label

    def size(self) -> dict[str, Any]:
        """``camfab size`` of the text as it is: its lines, and the edits that would give the
        design the size found (the least base radius, or a drum's radius, in the design's
        units)."""
        from camfab.design.loader import unsized_design
        from camfab.pipeline import size_design
        from camfab.sizing_text import sizing_lines

        with self._lock:
            design, sized = unsized_design(self.label, frozenset({"cam.base_radius",
                                                                  "cam.radius"}), self.text)
            sizing = size_design(design, sized)
        edits = []
        if sizing.size is not None:
            edits.append({"path": f"cam.{sizing.key}",
                          "value": round(sizing.size / design.mm_per_unit, 6)})
        return {"lines": sizing_lines(design, sizing), "edits": edits,
                "found": sizing.size is not None}

    def build(self, out_dir: Path | None = None) -> dict[str, Any]:
        """Write the files of the current version as ``camfab build`` writes them
        (``exports/NAME/`` under the working folder); the folder, the files and the exit
        status."""
        from camfab.pipeline import output_folder
        from camfab.writing import write_files

        verified = self.verified()
        design = verified.analysis.design
        folder = output_folder(design, out_dir)
        written = write_files(folder, verified.artifacts.files)
        return {"folder": str(folder), "files": [p.name for p in written],
                "not_produced": list(verified.artifacts.not_produced),
                "exit_code": verified.analysis.exit_code}

    # --- the files, made and read back -----------------------------------------------------

    def verified(self, version: int | None = None) -> Verified:
        """The current version built and verified (made now if not yet); raises CamfabError
        when the current text does not load, or when *version* is given and not current."""
        with self._lock:
            if version is not None and version != self.version:
                raise Stale(f"version {version} is not the current one ({self.version})")
            if self.view.error is not None or self.good is None:
                raise CamfabError(self.view.error or "the design has not loaded")
            cached = self._verified
            if cached is not None and cached.version == self.version:
                return cached
            version, (design, _) = self.version, self.good
        with self._building:  # one build at a time; the lock is free for edits meanwhile
            with self._lock:
                cached = self._verified
                if cached is not None and cached.version == version:
                    return cached
            made = _verify(version, design)
            with self._lock:
                if version == self.version:
                    self._verified = made
            return made

    def _settle(self) -> None:
        """Build and verify the current version once the changes stop for a moment."""
        if self._timer is not None:
            self._timer.cancel()
        self._timer = threading.Timer(SETTLE_SECONDS, self._verify_now, (self.version,))
        self._timer.daemon = True
        self._timer.start()

    def _verify_now(self, version: int) -> None:
        try:
            made = self.verified(version)
        except Stale:  # a newer version came meanwhile: its own build follows
            return
        except CamfabError as exc:  # the files cannot be made: said in the page
            self.notify("fault", {"version": version, "error": str(exc)})
            return
        except Exception as exc:  # a fault of camfab's: said in the page, the studio goes on
            self.notify("fault", {"version": version, "error": f"{type(exc).__name__}: {exc}"})
            return
        self.notify("verified", {"version": made.version,
                                 "exit_code": made.analysis.exit_code})
        if made.version == self.version:  # not replaced meanwhile
            self.notify("report", made.report_json.decode("utf-8").rstrip("\n"))

    def close(self) -> None:
        """Stop the pending build of the files."""
        if self._timer is not None:
            self._timer.cancel()


def _suggested(error: CamfabError, path: str, text: str) -> CamfabError:
    """*error* (a path the design has not) with the closest path the design has, as the
    design's loader suggests a key (:func:`~camfab.errors.did_you_mean`)."""
    from camfab.errors import did_you_mean
    from camfab.serve.yamledit import EditError, fields

    if "did you mean" in str(error):
        return error
    try:
        known = [f.path for f in fields(text)]
    except (EditError, RecursionError):
        return error
    hint = None if path in known else did_you_mean(path, known)
    return error if hint is None else EditError(f"{error}; {hint}")


def _yaml_line(label: str, exc: BaseException) -> str:
    """The one line of a text the YAML editor cannot read: ``FILE:LINE: problem``."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    where = f"{label}:{mark.line + 1}" if mark is not None else label
    if isinstance(exc, RecursionError):
        problem = "nested too deeply"
    else:
        problem = getattr(exc, "problem", None) or str(exc).split("\n", 1)[0]
    return f"{where}: not YAML the studio can edit ({problem}); mend it in an editor"


def _verify(version: int, design: Design) -> Verified:
    """*design* analysed and rendered as ``camfab build`` does it (each failed check a sizing
    answers told the size that passes): its files, read back."""
    from camfab.pipeline import analyse, render

    analysis = analyse(design)
    artifacts = render(analysis)
    done = artifacts.analysis or analysis
    files = artifacts.files
    name = done.design.name
    page = files.get(f"{name}-report.html")
    report = files.get(f"{name}-report.json")
    if page is None or report is None:  # a design whose outputs leave the report out
        from camfab.export.report_html import render_report_html
        from camfab.export.report_json import render_report_json

        page, report = render_report_html(done), render_report_json(done)
    return Verified(version, artifacts, done, page.decode("utf-8"), report,
                    tuple(n for n in files if n.endswith(".stl")))
