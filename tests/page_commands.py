"""Playing a documentation page as a reader would: its commands run in order in one folder, the
design files it shows put in place as it shows them, and each command's exit status and output
held to what the page says.

The page's conventions (``docs/walkthrough.md`` follows them):

- A fenced ``console`` block holds commands (lines starting ``$ ``), each followed by its
  output. ``$ echo $?`` after a command gives that command's exit status; a command without one
  must exit 0. A line ``…`` in an output stands for lines left out, and a line ending in ``…``
  for a line cut short; the other lines must appear in the command's output, in that order.
- A fenced ``yaml`` block with ``title="NAME"`` shows the file NAME as the reader's copy of it
  now reads: the whole file, or the file with a line ``# …`` for each run of its lines left
  out. Its ``hl_lines`` are exactly the lines changed from the copy
  before (the one in the folder, else the previous file shown). The file itself is in the
  page's folder of files, and is put into the folder the commands run in.
- The page's other files (a scan to inspect) are in the folder from the start.
"""

from __future__ import annotations

import difflib
import re
import shlex
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

#: An output line standing for lines left out, and the mark of a line cut short.
ELIDED = "…"
#: A line of a YAML excerpt standing for lines left out.
ELIDED_YAML = "# …"
#: The shell's way to show the last command's exit status.
STATUS = "echo $?"

_FENCE = re.compile(r"^```(?P<info>[^`\n]*)\n(?P<body>.*?)^```[ \t]*$", re.M | re.S)


@dataclass(frozen=True)
class Fence:
    """A fenced block of the page: its language, its ``key="value"`` options and its lines."""

    lang: str
    options: dict[str, str]
    lines: list[str]


@dataclass(frozen=True)
class Command:
    """A command of a ``console`` block, the output the page shows and the status it says."""

    text: str
    output: list[str]
    status: int = 0


@dataclass
class Played:
    """What playing a page did: the commands run, those left to the test (not run) and every
    way the page and what happened differ."""

    ran: list[str] = field(default_factory=list)
    not_run: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)


def fences(page: str) -> list[Fence]:
    """The page's fenced blocks, in order."""
    found = []
    for match in _FENCE.finditer(page):
        words = shlex.split(match.group("info"))
        lang = words[0] if words else ""
        options = dict(word.split("=", 1) for word in words[1:] if "=" in word)
        found.append(Fence(lang, options, match.group("body").splitlines()))
    return found


def commands(fence: Fence) -> list[Command]:
    """The commands of a ``console`` block, ``echo $?`` folded into the command before it."""
    listed: list[Command] = []
    for line in fence.lines:
        if line.startswith("$ "):
            listed.append(Command(line[2:].strip(), []))
        elif listed:
            listed[-1].output.append(line)
        elif line.strip():
            raise ValueError(f"output before any command: {line!r}")
    folded: list[Command] = []
    for command in listed:
        if command.text == STATUS:
            if not folded or len(command.output) != 1 or not command.output[0].isdigit():
                raise ValueError("`echo $?` must follow a command and show one number")
            folded[-1] = Command(folded[-1].text, folded[-1].output, int(command.output[0]))
        else:
            folded.append(command)
    return folded


def output_problem(shown: list[str], actual: str) -> str | None:
    """Why the output *shown* on the page is not the *actual* output (None when it is): each
    shown line, in order, a line of the actual output (``…`` lines left out, a line ending in
    ``…`` its start); trailing spaces do not count."""
    lines = [line.rstrip() for line in actual.splitlines()]
    at = 0
    for want in (line.rstrip() for line in shown):
        if want == ELIDED:
            continue
        prefix = want.endswith(ELIDED)
        text = want[:-1].rstrip() if prefix else want
        while at < len(lines) and not (lines[at].startswith(text) if prefix else lines[at] == text):
            at += 1
        if at == len(lines):
            return f"the line {want!r} is not in the output (in this order)"
        at += 1
    return None


def excerpt_rows(shown: list[str], text: str) -> list[int | None]:
    """The file's row (0-based) of each line of an excerpt *shown* of the file *text* (None for
    a ``# …`` line): the block is the file with a ``# …`` for every run of its lines left out —
    at the start, between the parts and at the end. An AssertionError says where it is not."""
    file_rows = text.splitlines()
    rows: list[int | None] = []
    part: list[str] = []

    def place() -> None:
        start = next((r + 1 for r in reversed(rows) if r is not None), 0)
        after_gap = bool(rows) and rows[-1] is None
        last = len(file_rows) - len(part) if after_gap else start
        for at in range(start, last + 1):
            if file_rows[at:at + len(part)] == part:
                rows.extend(range(at, at + len(part)))
                part.clear()
                return
        where = "in the file as shown" if after_gap else "where the block puts them"
        raise AssertionError(f"these lines are not {where} (a `# …` left out?): {part!r}")

    for line in shown:
        if line != ELIDED_YAML:
            part.append(line)
            continue
        if part:
            place()
        rows.append(None)
    if part:
        place()
    if rows and rows[-1] is not None and rows[-1] != len(file_rows) - 1:
        raise AssertionError("the file goes on after the block, which has no `# …` to say so")
    return rows


def changed_rows(before: str, after: str) -> set[int]:
    """The rows (0-based) of *after* that are new or changed from *before*."""
    matcher = difflib.SequenceMatcher(a=before.splitlines(), b=after.splitlines(),
                                      autojunk=False)
    return {row for tag, _, _, j1, j2 in matcher.get_opcodes() if tag != "equal"
            for row in range(j1, j2)}


def play(page: str, files: Path, folder: Path,
         run: Callable[[str, Path], tuple[int, str]],
         not_run: Callable[[str], bool] = lambda command: False) -> Played:
    """Play *page* in *folder*: its files from *files* (a design when the page shows it, the
    others at once), its commands through *run* (a command and the folder → the exit status and
    the output, stdout then stderr), but those *not_run* says to leave."""
    played = Played()
    for extra in sorted(files.iterdir()):
        if extra.suffix != ".yaml":
            (folder / extra.name).write_bytes(extra.read_bytes())
    previous: str | None = None
    for fence in fences(page):
        if fence.lang == "yaml" and "title" in fence.options:
            name = fence.options["title"]
            text = (files / name).read_text(encoding="utf-8")
            try:
                rows = excerpt_rows(fence.lines, text)
            except AssertionError as error:
                played.problems.append(f"{name}: {error}")
                continue
            copy = folder / name
            before = copy.read_text(encoding="utf-8") if copy.exists() else previous
            if before is not None:
                marked = {rows[int(n) - 1] for n in fence.options.get("hl_lines", "").split()}
                changed = changed_rows(before, text)
                if marked != changed:
                    shown = sorted(r + 1 for r in marked if r is not None)
                    played.problems.append(f"{name}: the block marks rows {shown} changed, the "
                                           f"file changes rows {sorted(r + 1 for r in changed)}")
            copy.write_text(text, encoding="utf-8")
            previous = text
        elif fence.lang == "console":
            for command in commands(fence):
                if not_run(command.text):
                    played.not_run.append(command.text)
                    continue
                status, output = run(command.text, folder)
                played.ran.append(command.text)
                if status != command.status:
                    played.problems.append(f"`{command.text}` exits {status}, the page says "
                                           f"{command.status}:\n{output}")
                problem = output_problem(command.output, output)
                if problem:
                    played.problems.append(f"`{command.text}`: {problem}; the output:\n{output}")
    return played
