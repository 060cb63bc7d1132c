"""LinuxCNC's standalone G-code interpreter, ``rs274``, as the consumer of camfab's machining
programs: it runs a program and prints the canonical machining functions it calls — every move
after its own cutter compensation, in the program's units, with the rotary axes — which
:func:`interpret` reads into :class:`Moves`.

``.ci/run`` unpacks it from Debian's ``linuxcnc-uspace`` package (``apt-get download`` and
``dpkg -x``, nothing installed) into ``$CAMFAB_RS274_ROOT`` (default
``~/.cache/camfab/linuxcnc``). Without it, the tests that need it skip, or fail under
``CAMFAB_REQUIRE_CONSUMERS=1`` (as CI runs them).
"""

from __future__ import annotations

import os
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

#: rs274 reads a tool table in the machine's units, which without an INI file are inches.
MM_PER_IN = 25.4


def root() -> Path:
    return Path(os.environ.get("CAMFAB_RS274_ROOT",
                               Path.home() / ".cache" / "camfab" / "linuxcnc"))


def available() -> bool:
    return (root() / "usr" / "bin" / "rs274").is_file()


def need_rs274() -> None:
    """Skip the test without rs274 (fail when CI requires the consumers)."""
    if available():
        return
    message = f"LinuxCNC's rs274 is not unpacked in {root()} (see .ci/run)"
    if os.environ.get("CAMFAB_REQUIRE_CONSUMERS"):
        pytest.fail(message)
    pytest.skip(message)


@dataclass(frozen=True)
class Moves:
    """The moves rs274 made, in order: *kind* per move (``traverse``, ``feed``, ``arc``),
    *end* (M, 6) positions X Y Z A B C after each (program units; degrees), *start* the
    position before each; for arcs (XY plane) *centre* (M, 2), *turn* (+n counter-clockwise,
    -n clockwise, n the turns begun, as rs274 counts them; 0 for straight moves); *feed_mode*
    per move (``units`` or ``inverse``), *feed* per move (rs274's feed rate), and the messages
    of ``(debug, ...)`` comments."""

    kind: np.ndarray
    start: np.ndarray
    end: np.ndarray
    centre: np.ndarray
    turn: np.ndarray
    feed_mode: np.ndarray
    feed: np.ndarray
    messages: tuple[str, ...]
    canon: str

    def cutting(self) -> Moves:
        """The feed and arc moves alone."""
        keep = self.kind != "traverse"
        return Moves(self.kind[keep], self.start[keep], self.end[keep], self.centre[keep],
                     self.turn[keep], self.feed_mode[keep], self.feed[keep], self.messages,
                     self.canon)

    def sample(self, step: float, angle_step: float | None = None) -> np.ndarray:
        """Points (K, 6) along every move, at most *step* apart in XYZ (program units) and,
        where the rotary axes turn, *angle_step* degrees apart (default: *step*): a straight
        move interpolates every axis linearly, as the interpreter's moves do; an arc follows
        its circle in XY with Z and the rotary axes linear in its angle."""
        angle_step = step if angle_step is None else angle_step
        pieces = []
        for i in range(len(self.kind)):
            a, b = self.start[i], self.end[i]
            if self.kind[i] == "arc":
                c = self.centre[i]
                r0 = np.hypot(*(a[:2] - c))
                t0 = np.arctan2(a[1] - c[1], a[0] - c[0])
                t1 = np.arctan2(b[1] - c[1], b[0] - c[0])
                sweep = (t1 - t0) % (2 * np.pi) if self.turn[i] > 0 else -((t0 - t1) % (2 * np.pi))
                if abs(sweep) < 1e-12:
                    sweep = 2 * np.pi * np.sign(self.turn[i])
                sweep += 2 * np.pi * np.sign(self.turn[i]) * (abs(self.turn[i]) - 1)
                n = int(np.ceil(abs(sweep) * r0 / step)) + 1
                u = np.linspace(0.0, 1.0, n + 1)
                t = t0 + sweep * u
                r1 = np.hypot(*(b[:2] - c))
                r = r0 + (r1 - r0) * u
                p = a + np.outer(u, b - a)
                p[:, 0] = c[0] + r * np.cos(t)
                p[:, 1] = c[1] + r * np.sin(t)
            else:
                length = np.linalg.norm(b[:3] - a[:3])
                turning = np.abs(b[3:] - a[3:]).max()
                n = max(int(np.ceil(length / step)), int(np.ceil(turning / angle_step)), 1)
                u = np.linspace(0.0, 1.0, n + 1)
                p = a + np.outer(u, b - a)
            pieces.append(p)
        return np.concatenate(pieces) if pieces else np.empty((0, 6))


_CALL = re.compile(r"^\s*\d+\s+N\.{5}\s+(?P<name>[A-Z_0-9]+)\((?P<args>.*)\)\s*$")


def interpret(program: bytes | str | Path, tools: dict[int, float], tmp: Path,
              units: str = "mm") -> Moves:
    """Run *program* (its bytes, or a file) through rs274 with a tool table of *tools*
    (number -> diameter in the program's *units*); the moves it made. A program rs274 stops on
    fails the test with rs274's own message."""
    need_rs274()
    tmp.mkdir(parents=True, exist_ok=True)
    if isinstance(program, Path):
        path = program
    else:
        path = tmp / "program.ngc"
        path.write_bytes(program if isinstance(program, bytes) else program.encode())
    factor = 1.0 if units == "in" else 1 / MM_PER_IN
    table = tmp / "tools.tbl"
    table.write_text("".join(f"T{n} P{n} Z0 D{d * factor:.8f}\n" for n, d in tools.items()))
    out = tmp / "canon.txt"
    lib = root() / "usr" / "lib"
    env = {**os.environ, "LD_LIBRARY_PATH": f"{lib}:{lib / 'x86_64-linux-gnu'}"}
    done = subprocess.run([str(root() / "usr" / "bin" / "rs274"), "-g", "-t", str(table),
                           str(path), str(out)], capture_output=True, text=True, env=env,
                          timeout=600, cwd=tmp)
    canon = out.read_text() if out.exists() else ""
    if done.returncode != 0:
        pytest.fail(f"rs274 stopped on {path.name} (exit {done.returncode}): "
                    f"{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return parse(canon)


def parse(canon: str) -> Moves:
    """The moves of rs274's canonical output *canon*."""
    position = np.zeros(6)
    kinds, starts, ends, centres, turns, modes, feeds, messages = [], [], [], [], [], [], [], []
    mode, feed = "units", 0.0
    for line in canon.splitlines():
        match = _CALL.match(line)
        if match is None:
            continue
        name, args = match["name"], match["args"]
        if name in ("MESSAGE", "COMMENT"):
            messages.append(args.strip('"'))
            if "inverse time" in args:
                mode = "inverse"
            elif "units per minute" in args:
                mode = "units"
            continue
        if name == "SET_FEED_RATE":
            feed = float(args)
            continue
        if name not in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED"):
            continue
        values = [float(v) for v in args.split(",")]
        end = position.copy()
        centre, turn = np.zeros(2), 0
        if name == "ARC_FEED":
            first, second, c1, c2, rotation, z = values[:6]
            end[:3] = first, second, z
            end[3:] = values[6:9]
            centre, turn = np.array([c1, c2]), int(rotation)
            kind = "arc"
        else:
            end[:] = values[:6]
            kind = "traverse" if name == "STRAIGHT_TRAVERSE" else "feed"
        kinds.append(kind)
        starts.append(position)
        ends.append(end)
        centres.append(centre)
        turns.append(turn)
        modes.append(mode)
        feeds.append(feed)
        position = end
    return Moves(np.array(kinds), np.array(starts).reshape(-1, 6), np.array(ends).reshape(-1, 6),
                 np.array(centres).reshape(-1, 2), np.array(turns), np.array(modes),
                 np.array(feeds), tuple(messages), canon)
