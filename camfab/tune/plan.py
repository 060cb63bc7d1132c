"""A tuning checked before any search: the design read and checked (its own located errors),
the options (a bad one is one line naming the option and the problem, exit 2, before any work
and with nothing written), the families of the segments tuned, the objective and its band of
speeds, the files to write; and the tuned design's text: the design file's with only the law
values that changed written in by the studio's editor (:func:`camfab.serve.yamledit.set_value`:
comments, order and layout kept).

Files: ``NAME-tuned.yaml`` beside the design (or ``-o OUT.yaml``) and ``NAME-tuning.html`` in
the same folder (NAME the design file's name without its suffix).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array
from camfab.errors import CommandError
from camfab.tune.families import Family, Untuned, Written
from camfab.tune.objectives import NAMES, Objective

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.design.source import SourceDocument
    from camfab.tune.trials import Evaluator

#: The default band of the residual objective: the design speed ± this share ...
BAND = 0.10
#: ... at this many speeds.
BAND_SPEEDS = 7
#: The most speeds ``--speeds`` gives.
MOST_SPEEDS = 101
#: The most starts ``--starts`` takes.
MOST_STARTS = 64


class TuneError(CommandError):
    """A tuning's options refused: one line naming the option and the problem (exit 2), after
    ``camfab tune:``."""

    command = "tune"


@dataclass(frozen=True)
class TuneOptions:
    """What ``camfab tune`` was asked for (see the CLI's help)."""

    design: Path
    segments: str | None = None
    objective: str | None = None
    speeds: str | None = None
    starts: int = 4
    output: Path | None = None
    progress: bool = False


@dataclass
class Plan:
    """A checked tuning: the design's text, its data (as read, with each key's line) and
    model, the families, the segments with nothing free, the objective and its band of speeds,
    the evaluator, the families' own values and the files to write."""

    options: TuneOptions
    text: str
    doc: SourceDocument
    design: Design
    families: list[Family]
    untuned: list[Untuned]
    objective: Objective
    band: Array
    evaluator: Evaluator
    start: tuple[Any, ...]
    tuned_path: Path
    report_path: Path


def plan(options: TuneOptions) -> Plan:
    """The tuning checked before any search (raises :class:`TuneError`, or the design file's
    located error)."""
    from camfab.design.source import read_design_file, read_design_text
    from camfab.pipeline import analyse, load_design
    from camfab.tune.families import families_of
    from camfab.tune.objectives import default_objective, objective_of
    from camfab.tune.trials import Evaluator

    design = load_design(options.design)
    doc = read_design_file(options.design)
    data = doc.data
    if not isinstance(data.get("motion"), list) or not design.motion:
        raise TuneError(f"{options.design}: the motion comes from the cam's shape "
                        f"({design.cam.type}): there is no motion law to tune")
    indices = _segments(options.segments, design)
    if options.starts < 1 or options.starts > MOST_STARTS:
        raise TuneError(f"--starts {options.starts}: give 1 to {MOST_STARTS}")
    name = options.objective or default_objective(design)
    if name not in NAMES:
        raise TuneError(f"--objective {name}: not an objective (allowed: {', '.join(NAMES)})")
    band = _speeds(options.speeds, design)
    objective = objective_of(name, design, band, indices)
    analysis = analyse(design, advice=False)
    why = objective.why_not(design, analysis)
    if why is not None:
        raise TuneError(f"--objective {name}: {options.design}: {why}")
    if name == "residual":
        _check_band(design, band)
    families, untuned = families_of(data, design, indices)
    if not families:
        reasons = "; ".join(f"motion[{u.index}]: {u.why}" for u in untuned)
        raise TuneError(f"{options.design}: nothing to tune ({reasons})")
    evaluator = Evaluator(design, data, doc.file, doc.folder, families, objective)
    start = tuple(f.current if f.discrete else f.start()  # type: ignore[attr-defined]
                  for f in families)
    text = read_design_text(options.design)
    _check_editable(text, evaluator.written(start))
    tuned_path, report_path = _paths(options)
    return Plan(options, text, doc, design, families, untuned, objective, band, evaluator,
                start, tuned_path, report_path)


def _segments(given: str | None, design: Design) -> list[int]:
    """The segments ``--segment`` names (default: every rise and return)."""
    segments = design.program.segments
    if given is None:
        return [seg.index for seg in segments if seg.kind != "dwell"]
    out: list[int] = []
    for item in given.split(","):
        item = item.strip()
        if not item.isdigit():
            raise TuneError(f"--segment {given}: {item!r} is not a segment's number (give "
                            "indices of the motion list such as 0,2)")
        index = int(item)
        if index >= len(segments):
            raise TuneError(f"--segment {given}: the motion has {len(segments)} segments, "
                            f"no [{index}]")
        if segments[index].kind == "dwell":
            raise TuneError(f"--segment {given}: motion[{index}] is a dwell, which has no law")
        if index not in out:
            out.append(index)
    return sorted(out)


def _speeds(given: str | None, design: Design) -> Array:
    """The speeds (rpm) of ``--speeds``: ``LOW:HIGH`` (:data:`BAND_SPEEDS` speeds),
    ``LOW:HIGH:N``, ``A,B,C`` or one speed; by default the design speed ± :data:`BAND`."""
    speed = design.cam.speed_rpm
    if given is None:
        if speed is None:
            return np.zeros(0)
        return np.linspace(speed * (1 - BAND), speed * (1 + BAND), BAND_SPEEDS)
    option = f"--speeds {given}"

    def number(text: str, what: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise TuneError(f"{option}: the {what} {text!r} is not a number") from None
        if not math.isfinite(value) or value <= 0:
            raise TuneError(f"{option}: the {what} {text!r} must be a speed > 0 (rpm)")
        return value

    if ":" in given:
        parts = given.split(":")
        if len(parts) not in (2, 3):
            raise TuneError(f"{option}: write a band as LOW:HIGH or LOW:HIGH:N (rpm)")
        low, high = number(parts[0], "low speed"), number(parts[1], "high speed")
        count = BAND_SPEEDS
        if len(parts) == 3:
            if not parts[2].strip().isdigit() or not 1 <= int(parts[2]) <= MOST_SPEEDS:
                raise TuneError(f"{option}: the count {parts[2]!r} must be a whole number "
                                f"from 1 to {MOST_SPEEDS}")
            count = int(parts[2])
        if high < low:
            raise TuneError(f"{option}: the band's high speed is below its low one")
        speeds = np.linspace(low, high, count) if high > low else np.array([low])
    else:
        items = [item.strip() for item in given.split(",")]
        if len(items) > MOST_SPEEDS:
            raise TuneError(f"{option}: {len(items)} speeds; at most {MOST_SPEEDS}")
        speeds = np.unique([number(item, "speed") for item in items])
    return np.round(speeds, 9)


def _check_band(design: Design, band: Array) -> None:
    """Refuse a band holding a speed at which the follower train's periodic state is not
    computable (:func:`~camfab.speed.vibration.build_up`)."""
    from camfab.design.train import train_of
    from camfab.speed.vibration import BUILD_UP_LIMIT, build_up

    train = train_of(design, design.spring is not None)
    assert train is not None
    for speed in band:
        if build_up(train, float(speed) * math.pi / 30.0) > BUILD_UP_LIMIT:
            raise TuneError(f"--speeds: at {speed:.6g} rpm the follower train resonates with "
                            "the cam with next to no damping: its vibration has no value "
                            "(leave that speed out of the band)")


def _check_editable(text: str, written: Sequence[Written]) -> None:
    """Refuse a design file whose law values the editor cannot change in place (a value
    reached through an alias, a tag), before any search."""
    from camfab.design.source import dotted

    try:
        from camfab.serve.yamledit import EditError, set_value
    except ImportError:  # pragma: no cover - the serve extra's ruamel.yaml
        raise TuneError("the tuned design is written by the studio's YAML editor, which "
                        "needs ruamel.yaml: pip install 'camfab[serve]'") from None
    for keys, value in written:
        try:
            text = set_value(text, dotted(keys), value)
        except EditError as exc:
            raise TuneError(f"cannot write the tuned design: {exc}") from None


def _paths(options: TuneOptions) -> tuple[Path, Path]:
    """The tuned design's path and the report's."""
    design = options.design
    stem = design.stem
    out = options.output
    if out is None:
        out = design.with_name(f"{stem}-tuned.yaml")
    elif out.suffix.lower() not in (".yaml", ".yml"):
        raise TuneError(f"-o {out}: the tuned design is a YAML file: name it NAME.yaml")
    elif out.exists() and os.path.samefile(out, design):
        raise TuneError(f"-o {out}: is the design itself; give another file")
    if out.is_dir():
        raise TuneError(f"-o {out}: is a folder; give the tuned design's file")
    return out, out.with_name(f"{stem}-tuning.html")


def tuned_text(tuning: Plan, written: Sequence[Written]) -> str:
    """The design file's text with the values of *written* that differ from the design's
    changed in place (comments, order and layout kept)."""
    from camfab.serve.yamledit import set_value

    text = tuning.text
    for path, _, value in changed(tuning, written):
        text = set_value(text, path, value)
    return text


def changed(tuning: Plan, written: Sequence[Written]) -> list[tuple[str, Any, Any]]:
    """The values of *written* that differ from the design's, (path, before, after): a value
    the file gives that reads otherwise, or a value it leaves to its default (a blend) that
    differs from the default."""
    from camfab.design.source import dotted

    own = dict(tuning.evaluator.written(tuning.start))
    out = []
    for keys, value in written:
        old = tuning.doc.value_at(keys)
        if same_value(old, value) or (old is None and own.get(keys) == value):
            continue
        out.append((dotted(keys), old, value))
    return out


def same_value(old: Any, new: Any) -> bool:
    """True when the design's *old* value reads as *new*: the same number, or the same law
    (by its canonical name: an alias stays as written)."""
    if isinstance(new, str) and isinstance(old, str):
        from camfab.motion.laws import canonical_law_name

        return canonical_law_name(old) == new
    if isinstance(old, bool) or not isinstance(old, (int, float)):
        return False
    return float(old) == float(new)
