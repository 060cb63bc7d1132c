"""MkDocs hooks: the reference pages generated from camfab's own code when the site is built.

``mkdocs.yml`` names this file under ``hooks:``; MkDocs calls :func:`on_files` before it reads
the pages, and the two pages below join the site as if they were files in ``docs/``:

- ``reference/design-file.md``: every key of the design file, from the pydantic models
  (:class:`camfab.design.model.Design` and every model nested in it): its type and constraints,
  its unit (the kind its converter carries, read as the report reads it:
  :func:`camfab.export.design_record._kind`), its default, and which cam types, followers and
  motion laws take it (the rows of :data:`camfab.design.cam_types.CAM_TYPES` and the loader's
  lists of keys). What each key means is the one thing written by hand, in
  ``docs/design-keys.yml``; a key with no meaning there stops the build (and
  ``tests/test_docs.py``), so a key added to the models cannot go undocumented.
- ``reference/cli.md``: every command of ``camfab`` with its arguments and options and their
  help, from the click commands of :mod:`camfab.cli`.

Run ``python docs/hooks.py design`` (or ``cli``) to print a page without building the site.
"""

from __future__ import annotations

import html
import inspect
import math
import re
import sys
import typing
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import annotated_types
import yaml
from pydantic import BaseModel, BeforeValidator
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

#: What each key means, by its path (the one hand-written part of the design-file reference).
MEANINGS_FILE = Path(__file__).with_name("design-keys.yml")

#: The pages this hook adds to the site, by their path under ``docs/``.
DESIGN_PAGE = "reference/design-file.md"
CLI_PAGE = "reference/cli.md"


# --------------------------------------------------------------------------------------------
# MkDocs


def on_files(files: Any, config: Any) -> Any:
    """Add the generated reference pages to the site's files."""
    from mkdocs.exceptions import PluginError
    from mkdocs.structure.files import File

    try:
        pages = ((DESIGN_PAGE, design_reference()), (CLI_PAGE, cli_reference()))
    except UndocumentedKey as exc:
        raise PluginError(str(exc)) from None
    for uri, text in pages:
        files.append(File.generated(config, uri, content=text))
    return files


# --------------------------------------------------------------------------------------------
# The design file: walking the models


@dataclass(frozen=True)
class Key:
    """One key of the design file: where it is, and the model field that takes it."""

    path: str  # as camfab's messages name it: cam.base_radius, motion[].start.velocity
    model: type[BaseModel]
    name: str  # the field's name in its model

    @property
    def field(self) -> FieldInfo:
        return self.model.model_fields[self.name]

    @property
    def section(self) -> str:
        """The path of the mapping the key is in ("" at the top)."""
        return self.path.rpartition(".")[0]


def _args(annotation: Any) -> Iterator[Any]:
    """*annotation* and everything inside it (unions, Annotated, tuple items), depth first."""
    pending = [annotation]
    while pending:
        item = pending.pop(0)
        yield item
        if typing.get_origin(item) is typing.Annotated:
            pending.append(item.__origin__)
            pending.extend(item.__metadata__)
        else:
            pending.extend(a for a in typing.get_args(item) if a is not Ellipsis)


def _models_in(annotation: Any) -> list[type[BaseModel]]:
    """The pydantic models a field of *annotation* holds (a section, a list's items)."""
    return [a for a in _args(annotation) if isinstance(a, type) and issubclass(a, BaseModel)]


def _is_list(annotation: Any) -> bool:
    return any(typing.get_origin(a) in (tuple, list) for a in _args(annotation))


def design_keys() -> list[Key]:
    """Every key of the design file, top-level first, each section after the key naming it.

    The model fields that are not keys of the file are left out: those excluded from the model's
    dump (``source``, ``sized``: what camfab records, not what a design says) and a segment's
    ``kind``, which the file gives as the segment's one key (``- rise: {...}``)."""
    from camfab.design.model import Design, Segment

    keys: list[Key] = []

    def walk(model: type[BaseModel], prefix: str) -> None:
        nested: list[tuple[str, type[BaseModel]]] = []
        for name, field in model.model_fields.items():
            if field.exclude or (model is Segment and name == "kind"):
                continue
            path = f"{prefix}{name}"
            keys.append(Key(path, model, name))
            for sub in _models_in(field.annotation):
                nested.append((path + ("[]" if _is_list(field.annotation) else ""), sub))
        for path, sub in nested:
            walk(sub, path + ".")

    walk(Design, "")
    return keys


def _metadata(field: FieldInfo) -> list[Any]:
    """The constraints and validators of *field*, wherever its annotation holds them."""
    found = list(field.metadata)
    for item in _args(field.annotation):
        if isinstance(item, FieldInfo):
            found += item.metadata
        elif not isinstance(item, type) and typing.get_origin(item) is None:
            found.append(item)
    return found


def _constraint(field: FieldInfo) -> str:
    """*field*'s bounds in words: ``> 0``, ``0.001 to 0.5``."""
    low = high = ""
    pattern = None
    shortest, longest = 0, None
    for item in _metadata(field):
        if isinstance(item, annotated_types.Gt):
            low = f"> {item.gt:g}"
        elif isinstance(item, annotated_types.Ge):
            low = f"≥ {item.ge:g}"
        elif isinstance(item, annotated_types.Le):
            high = f"≤ {item.le:g}"
        elif isinstance(item, annotated_types.Lt):
            high = f"< {item.lt:g}"
        elif isinstance(item, annotated_types.MinLen):
            shortest = item.min_length
        elif isinstance(item, annotated_types.MaxLen):
            longest = item.max_length
        elif getattr(item, "pattern", None):
            pattern = item.pattern
    bounds = " and ".join(p for p in (low, high) if p)
    if longest is not None:
        bounds = f"of {max(shortest, 1)} to {longest} characters"
    if pattern:
        return f"matching `{pattern}`" + (f", {bounds}" if bounds else "")
    return bounds


def _literals(annotation: Any) -> list[str]:
    return [str(v) for a in _args(annotation) if typing.get_origin(a) is Literal
            for v in typing.get_args(a)]


def _converter_names(field: FieldInfo) -> set[str]:
    """The names of *field*'s before-validators (``_material``, ``_point``, ...)."""
    return {getattr(item.func, "__name__", "") for item in _metadata(field)
            if isinstance(item, BeforeValidator)}


def _type_text(key: Key) -> str:
    """The type of *key*'s value in words, with its bounds."""
    from camfab.design.loader import AUTO_KEYS
    from camfab.design.materials import MATERIALS

    field = key.field
    annotation = field.annotation
    converters = _converter_names(field)
    literals = _literals(annotation)
    models = _models_in(annotation)
    if "_material" in converters or (models and _has(annotation, str)):
        names = ", ".join(f"`{n}`" for n in MATERIALS)
        text = (f"a material's name ({names}; see [Materials](#materials)) or a mapping "
                "`{E, poisson}`")
    elif models:
        text = ("a list of mappings" if _is_list(annotation) else "a mapping") + " (below)"
    elif "_point" in converters:
        text = "a list of pairs `[angle, displacement]`"
    elif literals:
        text = "one of " + ", ".join(f"`{v}`" for v in literals)
        if _is_list(annotation):
            text = "a list of " + ", ".join(f"`{v}`" for v in literals)
    elif _has(annotation, bool):
        text = "`true` or `false`"
    elif _has(annotation, float) and _has(annotation, str):
        text = "a number or `match`"
    elif _has(annotation, float):
        text = "a number"
        bound = _constraint(field)
        if bound:
            text += " " + bound
    elif _has(annotation, str):
        text = "text"
        bound = _constraint(field)
        if bound:
            text += " " + bound
    else:
        text = str(annotation)
    if key.path in AUTO_KEYS:
        text += ", or `auto`"
    if key.model.__name__ == "Segment" and key.name == "law":
        text = "a motion law's name or alias (see [Motion laws](#motion-laws))"
    return text


def _has(annotation: Any, kind: type) -> bool:
    return any(a is kind for a in _args(annotation))


# --------------------------------------------------------------------------------------------
# Units and defaults

#: How the pages write pint's unit names.
_UNIT_SYMBOLS = {"degree": "deg", "hour": "h", "N*s/m": "N·s/m"}


def _unit_text(key: Key) -> str:
    """The unit of a bare number of *key*, and the units it may carry, from its converter."""
    from camfab.design import units as U
    from camfab.export.design_record import _RATES, _kind

    kind = _kind(key.model, key.name)
    if kind == "lift":
        return ("a length in the design's `units` (translating follower) or degrees of swing "
                "(oscillating follower)")
    if isinstance(kind, U.Kind):
        return f"{_kind_name(kind)}: {_bare_unit(kind)}"
    if key.name in _RATES and key.model.__name__ == "Conditions":
        order = _RATES[key.name]
        per = "rad" if order == 1 else f"rad^{order}"
        return (f"the lift's derivative per {per} of cam angle: design `units`/{per}, or "
                f"rad/{per} for an oscillating follower")
    if "_point" in _converter_names(key.field):
        return ("angle in degrees from the segment's start; displacement a lift (design "
                "`units`, or degrees of swing)")
    return ""


def _kind_name(kind: Any) -> str:
    """``length`` for "a length"."""
    return re.sub(r"^an? ", "", kind.name)


def _bare_unit(kind: Any) -> str:
    """The unit of a bare number of *kind*."""
    if kind.default is None:
        return "the design's `units`"
    return f"`{_UNIT_SYMBOLS.get(kind.default, kind.default)}`"


def unit_kinds() -> list[Any]:
    """The kinds of quantity the design file's keys take, in the order the keys use them."""
    from camfab.design import units as U
    from camfab.export.design_record import _kind

    found: dict[str, Any] = {}
    for key in design_keys():
        kind = _kind(key.model, key.name)
        if isinstance(kind, U.Kind):
            found.setdefault(kind.name, kind)
    return list(found.values())


def _default_text(key: Key) -> str:
    """*key*'s default as the design file would give it, or ``required`` / ``none``."""
    from camfab.design import units as U
    from camfab.design.cam_types import CAM_TYPES
    from camfab.export.design_record import _kind

    field = key.field
    if field.is_required():
        return "required"
    value = field.default
    if value is PydanticUndefined or value is None:
        return "not set"
    if isinstance(value, BaseModel):
        return "its keys' defaults"
    kind = _kind(key.model, key.name)
    if isinstance(value, bool):
        text = "`true`" if value else "`false`"
    elif isinstance(value, str):
        text = f"`{value}`" if value else '`""`'
    elif isinstance(value, float):
        if kind is U.ANGLE:
            text = f"{math.degrees(value):.6g}°"
        elif value == 0.0:
            text = "0"
        elif kind is U.LENGTH:
            text = f"{value:g} mm"
        elif isinstance(kind, U.Kind):
            text = f"{value:g} {_UNIT_SYMBOLS.get(kind.internal, kind.internal)}"
        else:
            text = f"{value:g}"
    else:
        text = f"`{value}`"
    if key.path == "manufacturing.tolerance":
        # the loader puts a cam type's own tolerance in its place (loader._with_type_tolerance)
        own = [f"{name}: {spec.default_tolerance:g} mm" for name, spec in CAM_TYPES.items()
               if spec.default_tolerance is not None]
        if own:
            text += " (" + "; ".join(own) + ")"
    return text


# --------------------------------------------------------------------------------------------
# Which cam types, followers and laws take a key


def _follower_combinations() -> list[tuple[str, str, str]]:
    """Every (cam type, follower type, follower motion) a cam type's row lets a design name."""
    from camfab.design.cam_types import CAM_TYPES

    return [(name, ftype, motion) for name, spec in CAM_TYPES.items()
            for ftype in spec.followers
            for motion in (("translating",) if spec.translating_only
                           else ("translating", "oscillating"))]


def _follower_taken_by(name: str) -> str:
    """Which followers of which cam types take follower key *name* (the loader's
    ``follower_keys``), in words."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import follower_keys

    combos = _follower_combinations()
    taking = [(c, f, m) for c, f, m in combos
              if name in follower_keys(CAM_TYPES[c], {"type": f, "motion": m})]
    if not taking:
        return "no follower (not accepted)"
    if len(taking) == len(combos):
        return "every follower of every cam type"
    wanted = {(f, m) for _, f, m in taking}  # the followers it is a key of, on some cam
    cams = list(dict.fromkeys(c for c, _, _ in taking))
    if all(((c, f, m) in taking) == ((f, m) in wanted and c in cams) for c, f, m in combos):
        # the same followers on every cam type that takes it
        which = "every cam type" if len(cams) == len(CAM_TYPES) else ", ".join(cams)
        return f"{_followers_words(wanted)}: {which}"
    return "; ".join(f"{_followers_words({(f, m) for c, f, m in taking if c == cam})}: {cam}"
                     for cam in cams)


def _followers_words(wanted: set[tuple[str, str]]) -> str:
    """``translating roller followers`` for the (type, motion) pairs *wanted*."""
    types = [f for f in ("knife", "roller", "flat", "mushroom") if any(w[0] == f for w in wanted)]
    motions = [m for m in ("translating", "oscillating") if any(w[1] == m for w in wanted)]
    if {(f, m) for f in types for m in motions} != wanted:
        return ", ".join(f"{m} {f}" for f, m in sorted(wanted)) + " followers"
    motion = "" if len(motions) == 2 else motions[0] + " "
    follower = "" if len(types) == 4 else " or ".join(types) + " "
    return f"{motion}{follower}followers" if motion or follower else "every follower"


def _segment_taken_by(name: str) -> str:
    """Which segments (kind, law) of which cam types take segment key *name* (the loader's
    ``segment_keys``), in words."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import SEGMENT_KINDS, segment_keys
    from camfab.motion.laws import LAW_NAMES

    kinds = list(dict.fromkeys(SEGMENT_KINDS.values()))
    spans = {spec.span for spec in CAM_TYPES.values() if not spec.shaped}
    parts = []
    for span in sorted(spans):
        cams = [n for n, s in CAM_TYPES.items() if not s.shaped and s.span == span]
        segs = [k for k in kinds
                if any(name in segment_keys(k, law, span) for law in LAW_NAMES)]
        if not segs:
            continue
        laws = [law for law in LAW_NAMES
                if any(name in segment_keys(k, law, span) for k in segs if k != "dwell")]
        words = ("every segment" if len(segs) == len(kinds)
                 else " and ".join(f"`{k}`" for k in segs))
        if "dwell" not in segs and len(laws) < len(LAW_NAMES):
            words += " with the law " + " or ".join(f"`{law}`" for law in laws)
        parts.append((words, cams))
    if len({w for w, _ in parts}) == 1 and len(parts) > 1:
        return parts[0][0] + " (every cam type with a motion list)"
    return "; ".join(f"{w}: {', '.join(cams)}" for w, cams in parts)


def _taken_by(key: Key) -> str:
    """Which cam types (and followers, laws) take *key*, in words."""
    from camfab.design.cam_types import CAM_TYPES

    model = key.model.__name__
    top = key.path.split(".")[0].split("[")[0]
    if model == "Cam":
        cams = []
        for name, spec in CAM_TYPES.items():
            if key.name in spec.cam_keys:
                marks = [m for m, on in (("required", key.name in spec.required),
                                         ("`auto`", key.path in spec.auto_keys)) if on]
                cams.append(name + (f" ({', '.join(marks)})" if marks else ""))
        return ", ".join(cams) if len(cams) < len(CAM_TYPES) else "every cam type"
    if key.path.startswith("machining.machine"):
        return "globoidal (the others do not use it)"
    if model == "Keyway":
        return _taken_by(Key("cam.keyway", type_of("Cam"), "keyway"))
    if model == "Follower":
        text = _follower_taken_by(key.name)
        if key.path in {k for spec in CAM_TYPES.values() for k in spec.auto_keys}:
            sized = [n for n, s in CAM_TYPES.items() if key.path in s.auto_keys]
            text += f"; `auto`: {', '.join(sized)}"
        return text
    if model in ("Segment", "Conditions"):
        name = key.name if model == "Segment" else key.path.split(".")[1]
        return _segment_taken_by(name)
    if top == "motion":
        shaped = [n for n, s in CAM_TYPES.items() if s.shaped]
        return "every cam type but " + ", ".join(shaped) + " (their shape sets the motion)"
    if top == "spring" and key.path != "spring":
        return "with `spring`"
    if top == "spring":
        both = [n for n, s in CAM_TYPES.items() if s.positive_drive]
        return ("cam types that need a spring to hold the follower; refused by "
                + ", ".join(both) + " (positive drive)")
    return "every cam type"


def type_of(name: str) -> type[BaseModel]:
    """The design model called *name*."""
    from camfab.design import model

    return getattr(model, name)


# --------------------------------------------------------------------------------------------
# The design-file page


def meanings() -> dict[str, str]:
    """What each key means, by path, from :data:`MEANINGS_FILE`."""
    data = yaml.safe_load(MEANINGS_FILE.read_text(encoding="utf-8"))
    return {str(k): " ".join(str(v).split()) for k, v in data.items()}


class UndocumentedKey(Exception):
    """A key of the design models with no meaning in ``docs/design-keys.yml`` (or a meaning
    there for a key the models do not take)."""


def _cell(text: str) -> str:
    """*text* made safe in a Markdown table cell: its pipes escaped outside code spans (the
    tables extension leaves those inside alone)."""
    parts = text.replace("\n", " ").split("`")
    return "`".join(p if i % 2 else p.replace("|", "\\|") for i, p in enumerate(parts))


def _anchor(path: str) -> str:
    return "key-" + re.sub(r"[^a-z0-9]+", "-", path.lower()).strip("-")


def design_reference() -> str:
    """The design-file reference page, in Markdown."""
    from camfab.design.cam_types import CAM_TYPES
    from camfab.design.loader import SEGMENT_KINDS
    from camfab.design.materials import ALIASES as MATERIAL_ALIASES
    from camfab.design.materials import MATERIALS
    from camfab.motion.laws import LAWS

    keys = design_keys()
    meaning = meanings()
    paths = [k.path for k in keys]
    missing = [p for p in paths if p not in meaning]
    extra = [p for p in meaning if p not in paths]
    if missing or extra:
        raise UndocumentedKey(
            f"docs/design-keys.yml: {len(missing)} key(s) of the design models without a "
            f"meaning ({', '.join(missing) or 'none'}); {len(extra)} meaning(s) for no key "
            f"({', '.join(extra) or 'none'})")

    out = [
        "---",
        "hide: [navigation]",  # the tables take the page's width
        "---",
        "",
        "# Design-file reference",
        "",
        "<!-- Generated by docs/hooks.py from camfab's design models when the site is built; "
        "edit docs/design-keys.yml for what a key means. -->",
        "",
        "Every key a design file takes, generated from camfab's own models when this site is "
        "built: the type and bounds, the unit of a bare number, the default, and which cam "
        "types (and followers, segments and motion laws) take it. Keys are written as camfab's "
        "messages and `camfab sweep --vary` name them: `cam.base_radius`, `motion[].angle` "
        "(`motion[2].angle` for the third segment; in the file a segment's keys sit under its "
        "one key, `- rise: {angle: 120, ...}`). A key a cam type does not take is refused on "
        "its line, with the keys it does take. [Writing a design file](../design-files.md) "
        "explains the file; the design rules that join keys together (a spring that a groove "
        "cam refuses, a lift angle that gives no cam) are in the guide's pages of each kind.",
        "",
        "## Units",
        "",
        "A number may carry a unit (`\"1.5 in\"`, `\"24 N/mm\"`, `\"600 rpm\"`) of the "
        "key's kind of quantity, and only of that kind; a bare number is in the unit the "
        "*Unit* of its row gives. Defaults are as the design file would write them.",
        "",
        "| quantity | a bare number is in | units it may carry | largest magnitude |",
        "| --- | --- | --- | --- |",
        *(f"| {_kind_name(k)} | {_bare_unit(k)} | {k.examples} | {k.maximum_text or '—'} |"
          for k in unit_kinds()),
        "",
    ]
    sections: dict[str, list[Key]] = {}
    for key in keys:
        sections.setdefault(key.section, []).append(key)
    for section, members in sections.items():
        title = "Top level" if not section else f"`{section}`"
        out += [f"## {title}", ""]
        if section:
            out += [meaning[section.removesuffix("[]")], ""]
        if section == "motion[]":
            kinds = ", ".join(f"`{k}`" if k == v else f"`{k}` (= `{v}`)"
                              for k, v in SEGMENT_KINDS.items())
            out += [f"Each entry is a one-key map whose key is the segment's kind: {kinds}.", ""]
        out += ["| Key | Meaning | Value | Taken by |", "| --- | --- | --- | --- |"]
        for key in members:
            unit = _unit_text(key)
            value = "<br>".join([_type_text(key), *([f"*Unit:* {unit}"] if unit else []),
                                 f"*Default:* {_default_text(key)}"])
            cells = [f'<a id="{_anchor(key.path)}"></a>`{key.path}`', meaning[key.path], value,
                     _taken_by(key)]
            out.append("| " + " | ".join(_cell(c) for c in cells) + " |")
        out.append("")

    out += ["## Cam types", "",
            "What each `cam.type` takes (the rows of camfab's registry of cam types).", "",
            "| `cam.type` | `cam` keys (required in bold) | followers | follower motion | "
            "motion given by |",
            "| --- | --- | --- | --- | --- |"]
    for name, spec in CAM_TYPES.items():
        cam_keys = ", ".join(f"**`{k}`**" if k in spec.required else f"`{k}`"
                             for k in spec.cam_keys)
        motion = "translating" if spec.translating_only else "translating or oscillating"
        given = ("its shape (no `motion` list)" if spec.shaped
                 else f"`motion` segments of `{spec.span}`")
        out.append("| " + " | ".join(_cell(c) for c in (
            f"`{name}`", cam_keys, ", ".join(spec.followers), motion, given)) + " |")
    out.append("")

    out += ["## Motion laws", "",
            "A segment's `law` is one of these names or their aliases (any case; `_` or a "
            "space for `-`). Their peak coefficients are in [THEORY §A](../THEORY.md#a-motion-"
            "laws) and `camfab laws` prints them.", "",
            "| law | aliases | what it is | its own keys | continuity next to dwells |",
            "| --- | --- | --- | --- | --- |"]
    for info in LAWS:
        out.append("| " + " | ".join(_cell(c) for c in (
            f"`{info.name}`", ", ".join(f"`{a}`" for a in info.aliases) or "—", info.summary,
            ", ".join(f"`{p}`" for p in info.params) or "—", info.continuity or "—")) + " |")
    out.append("")

    out += ["## Materials", "",
            "The names `materials.cam` and `materials.follower` take (E in MPa); any other "
            "material is given by its constants, `{E: \"200 GPa\", poisson: 0.29}`.", "",
            "| name | E (MPa) | Poisson's ratio | what it is |", "| --- | --- | --- | --- |"]
    for name, mat in MATERIALS.items():
        out.append(f"| `{name}` | {mat.youngs_modulus:,.0f} | {mat.poisson:g} | {mat.what} |")
    aliases = ", ".join(f"`{a}` (`{n}`)" for a, n in MATERIAL_ALIASES.items())
    out += ["", f"Aliases: {aliases}.", ""]
    return "\n".join(out)


# --------------------------------------------------------------------------------------------
# The command line


def cli_reference() -> str:
    """The command-line reference page, in Markdown."""
    import click

    from camfab.cli import STARTER_KINDS, main

    root = click.Context(main, info_name="camfab", **main.context_settings)
    out = [
        "# Command-line reference",
        "",
        "<!-- Generated by docs/hooks.py from camfab's click commands when the site is built. -->",
        "",
        "Every command of `camfab`, its arguments and options with their help, generated from "
        "the command line's own definitions when this site is built. "
        "[Using camfab](../usage.md) explains the commands with examples, and the exit "
        "statuses they share.",
        "",
        "## camfab",
        "",
        "```",
        " ".join(main.collect_usage_pieces(root)).join(("camfab ", "")),
        "```",
        "",
        _help(main),
        "",
    ]
    out += _options(main, root)
    out += ["| Command | What it does |", "| --- | --- |"]
    for name, command in main.commands.items():
        out.append(f"| [`camfab {name}`](#camfab-{name}) | "
                   f"{_plain(command.get_short_help_str(limit=400))} |")
    out.append("")
    for name, command in main.commands.items():
        ctx = click.Context(command, info_name=name, parent=root)
        out += [f"## camfab {name}", "", "```",
                "camfab " + name + " " + " ".join(command.collect_usage_pieces(ctx)), "```", "",
                _help(command), ""]
        arguments = [p for p in command.params if isinstance(p, click.Argument)]
        if arguments:
            out += ["| Argument | |", "| --- | --- |"]
            for arg in arguments:
                many = "one or more" if arg.nargs == -1 else "one"
                need = "required" if arg.required else "optional"
                extra = ""
                if name == "new":
                    extra = "; one of " + ", ".join(f"`{k}`" for k in STARTER_KINDS)
                out.append(f"| `{arg.make_metavar(ctx)}` | {many}, {need}{extra} |")
            out.append("")
        out += _options(command, ctx)
    return "\n".join(out)


def _help(command: Any) -> str:
    """A command's help, its paragraphs as click shows them."""
    return html.escape(inspect.cleandoc(command.help or "").replace("\b\n", ""), quote=False)


def _plain(text: str) -> str:
    """Plain *text* (click's help) made safe in a Markdown table cell."""
    return _cell(html.escape(text, quote=False))


def _options(command: Any, ctx: Any) -> list[str]:
    import click

    rows = []
    for param in command.get_params(ctx):
        if not isinstance(param, click.Option):
            continue
        record = param.get_help_record(ctx)
        if record is None:
            continue
        names, text = record
        rows.append(f"| `{names}` | {_plain(text)} |")
    if not rows:
        return []
    return ["| Option | |", "| --- | --- |", *rows, ""]


if __name__ == "__main__":  # pragma: no cover
    which = sys.argv[1] if len(sys.argv) > 1 else "design"
    print(design_reference() if which == "design" else cli_reference())
