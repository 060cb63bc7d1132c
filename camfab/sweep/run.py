"""A sweep end to end: the options checked (a bad ``--vary`` is one line, exit 2, before any
work), the variants run in batches on the engine asked for, each batch's rows written as they
come in the variants' order, the feasible region and the best variants gathered as they pass,
then the summary page and, when asked, the best variants built in full.

Ctrl-C keeps the rows done so far: the table and the page are written with them (whole, each
renamed into place) before the sweep stops.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab.sweep.rows import Row, columns, died_row, evaluate
from camfab.sweep.vary import SweepError, Variants, from_file, from_varies, parse_vary

if TYPE_CHECKING:
    from camfab.design.source import SourceDocument
    from camfab.sweep.page import Region

#: The design-file errors that say a ``--vary`` gives a value of the wrong kind or names no key
#: (the file's shape, pydantic's type errors), rather than a design a value makes invalid.
WRONG_KIND = {"shape", "extra_forbidden", "literal_error", "float_parsing", "float_type",
              "int_parsing", "int_type", "int_from_float", "string_type", "bool_parsing",
              "bool_type", "model_type", "dict_type", "list_type", "tuple_type"}
#: Rows shown on the page without an objective: the first that pass.
SHOWN = 20


@dataclass(frozen=True)
class SweepOptions:
    """What ``camfab sweep`` was asked for (see the CLI's help)."""

    design: Path
    vary: tuple[str, ...] = ()
    variants: Path | None = None
    out_dir: Path | None = None
    jobs: int = 1
    scheduler: str | None = None
    size: bool = False
    build_best: int = 0
    minimize: str | None = None
    maximize: str | None = None
    table_format: str | None = None  # parquet | csv | None: parquet when pyarrow is installed
    progress: bool = False
    cluster_timeout: float | None = None  # s; None: engines.CLUSTER_SECONDS with --scheduler


@dataclass
class Sweep:
    """A sweep's outcome: the table's and the page's paths, the counts by status, the rows
    written, its wall seconds, and the designs built."""

    table: Path
    page: Path
    counts: dict[str, int]
    rows: int
    seconds: float
    built: list[tuple[Path, int]] = field(default_factory=list)


@dataclass(frozen=True)
class Plan:
    """A checked sweep: the design's data, its name, the variants, the columns and kinds, the
    objective (column, +1 to maximise, −1 to minimise) and the output folder."""

    options: SweepOptions
    data: dict[str, Any]
    file: str
    folder: Path
    name: str
    variants: Variants
    columns: tuple[str, ...]
    kinds: dict[str, str]
    objective: tuple[str, float] | None
    out_dir: Path


def plan(options: SweepOptions) -> Plan:
    """The sweep checked before any work (raises :class:`SweepError`, or the design file's
    :class:`~camfab.errors.DesignFileError`)."""
    from camfab.design.source import read_design_file
    from camfab.sweep.table import column_kinds, parquet_available

    doc = read_design_file(options.design)
    if not isinstance(doc.data, dict):
        raise SweepError(f"{options.design}: a design must be a mapping of keys")
    if options.variants is not None and options.vary:
        raise SweepError("--variants: give either --vary options or a --variants file, "
                         "not both")
    if options.variants is not None:
        variants = from_file(options.variants)
    elif options.vary:
        variants = from_varies([parse_vary(v) for v in options.vary])
    else:
        raise SweepError("give what to vary: --vary PATH=SPEC (such as "
                         "--vary cam.base_radius=20:40:5) or --variants FILE")
    _check_paths(doc.data, doc.file, doc.folder, variants)
    cols = columns(variants.paths, options.size)
    taken = [variants.taken(i) for i in range(len(variants.paths))]
    kinds = column_kinds(variants.paths, taken, cols)
    objective = _objective(options, cols, kinds)
    if options.table_format == "parquet" and not parquet_available():
        raise SweepError("--format parquet needs pyarrow: pip install 'camfab[sweep]'")
    from camfab.sweep.engines import check_scheduler
    check_scheduler(options.scheduler, options.cluster_timeout)
    name = _name(doc, options.design)
    out_dir = options.out_dir or Path("exports") / f"{name}-sweep"
    return Plan(options, doc.data, doc.file, doc.folder, name, variants, cols, kinds,
                objective, out_dir)


def _name(doc: SourceDocument, design: Path) -> str:
    """The sweep's name: the design's ``name`` by the rule a build applies (it names files in
    the output folder and nowhere else), else the design file's stem."""
    import re

    from camfab.design.model import NAME_LENGTH, NAME_PATTERN, NAME_RULE
    from camfab.errors import DesignError

    name = doc.data.get("name")
    if not isinstance(name, str) or not name:
        return design.stem
    if len(name) > NAME_LENGTH:
        raise DesignError(f"must be at most {NAME_LENGTH} characters", field="name",
                          location=doc.locate(("name",)))
    if not re.fullmatch(NAME_PATTERN, name):
        raise DesignError(NAME_RULE, field="name", location=doc.locate(("name",)), got=name)
    return name


def _objective(options: SweepOptions, cols: Sequence[str],
               kinds: dict[str, str]) -> tuple[str, float] | None:
    if options.minimize and options.maximize:
        raise SweepError("--minimize, --maximize: give one objective")
    column = options.minimize or options.maximize
    if column is None:
        if options.build_best:
            raise SweepError("--build-best: give the objective, such as "
                             "--minimize cam.base_radius")
        return None
    flag = "--minimize" if options.minimize else "--maximize"
    if column not in cols or kinds[column] not in ("int", "float") or column == "variant":
        numeric = [c for c in cols if kinds[c] in ("int", "float") and c != "variant"]
        raise SweepError(f"{flag} {column}: not a numeric column of the table (allowed: "
                         f"{', '.join(numeric)})")
    return column, (-1.0 if options.minimize else 1.0)


def _check_paths(data: dict[str, Any], file: str, folder: Path, variants: Variants) -> None:
    """Refuse a varied key that names no key of the design, or a value of the wrong kind for
    it, by checking the design with each kind of value each key takes (each text value, one
    number of each type), the others as the file gives them."""
    from camfab.errors import DesignError
    from camfab.pipeline import design_from_mapping
    from camfab.sweep.vary import with_values

    for i, (path, keys) in enumerate(zip(variants.paths, variants.keys, strict=True)):
        option = f"--vary {path}" if variants.varies else f"--variants {path}"
        samples: dict[Any, Any] = {}
        for value in variants.taken(i):
            kind = value if isinstance(value, str) else type(value)
            samples.setdefault(kind, value)
            if len(samples) > 64:
                break
        for value in samples.values():
            try:
                design_from_mapping(with_values(data, [keys], [value]), file, folder)
            except LookupError as exc:
                raise SweepError(f"{option}: {exc}") from None
            except DesignError as exc:
                if exc.kind in WRONG_KIND and (exc.field == path
                                               or exc.field.startswith(path + ".")):
                    detail = str(exc).split(f"{exc.field}: ", 1)[-1]
                    raise SweepError(f"{option}: {value!r}: {detail}") from None
            except Exception:  # a design a value makes invalid: the sweep's row says so
                continue


def run(sweep: Plan, echo: Callable[[str], None] = print) -> Sweep:
    """Run *sweep*: the table, the page and the best builds (see the module)."""
    from camfab.batch import progress_bar
    from camfab.errors import OutputError
    from camfab.sweep.engines import BATCH, DASK_BATCH, dask_rows, local_rows
    from camfab.sweep.page import Region, axis_of
    from camfab.sweep.table import TableWriter, cell, parquet_available, typed
    from camfab.writing import make_folder, remove_made

    options, variants = sweep.options, sweep.variants
    parquet = (options.table_format == "parquet"
               or (options.table_format is None and parquet_available()))
    task = partial(evaluate, sweep.data, sweep.file, sweep.folder, variants.keys,
                   size=options.size)
    if options.scheduler:  # (the scheduler reached before anything is written)
        stream = dask_rows(task, variants.batches(DASK_BATCH), options.scheduler,
                           options.cluster_timeout)
    else:
        stream = local_rows(task, variants.batches(BATCH), options.jobs,
                            lambda: task([(0, variants.values(0))]),
                            partial(died_row, size=options.size))
    made = make_folder(sweep.out_dir)
    axes = [[cell(v, sweep.kinds[path]) for v in variants.taken(i)]
            for i, path in enumerate(variants.paths)]
    region = Region(axis_of(variants.paths[0], axes[0]),
                    axis_of(variants.paths[1], axes[1]) if len(axes) > 1 else None)
    status_at = 1 + len(variants.paths)
    counts = {"OK": 0, "FAIL": 0, "INVALID": 0}
    best: list[tuple[float, int, Row]] = []
    shown: list[Row] = []
    writer: TableWriter | None = None
    bar = progress_bar(variants.count, "sweeping") if options.progress else None
    start = time.perf_counter()
    stopped = False
    try:
        writer = TableWriter(sweep.out_dir, f"{sweep.name}-sweep", sweep.columns, sweep.kinds,
                             parquet)
        for rows in stream:
            rows = [typed(r, sweep.columns, sweep.kinds) for r in rows]
            writer.add(rows)
            region.add(rows, status_at)
            for r in rows:
                counts[r[status_at]] += 1
            _keep_best(rows, sweep, status_at, best, shown)
            if bar is not None:
                bar.update(len(rows))
    except OutputError:  # nothing is written: the table's temporary file is gone already
        remove_made(sweep.out_dir, made)
        raise
    except BaseException:  # a stop: the rows so far are written
        stopped = True
        raise
    finally:
        if bar is not None:
            bar.render_finish()
        seconds = time.perf_counter() - start
        if writer is not None and writer.temp is not None and writer.temp.exists():
            ranked = [r for _, _, r in sorted(best, key=lambda item: (-item[0], -item[1]))]
            try:
                table = writer.finish()
                page = _write_page(sweep, counts, seconds, region, ranked or shown, table,
                                   stopped)
            except OutputError:
                writer.discard()
                remove_made(sweep.out_dir, made)
                raise
            if stopped:
                echo(f"{sweep.name}: stopped after {writer.rows:,} of {variants.count:,} "
                     f"variants; wrote {table[1]} and {page} with them")
    assert writer is not None
    outcome = Sweep(table[1], page, counts, writer.rows, seconds)
    if options.build_best and ranked:
        outcome.built = _build_best(sweep, ranked[:options.build_best])
    return outcome


def _keep_best(rows: Sequence[Row], sweep: Plan, status_at: int,
               best: list[tuple[float, int, Row]], shown: list[Row]) -> None:
    """Keep the best rows by the objective (a heap of the page's and the builds' count), or
    the first that pass."""
    keep = max(SHOWN, sweep.options.build_best)
    if sweep.objective is None:
        shown.extend(r for r in rows if r[status_at] == "OK" and len(shown) < SHOWN)
        return
    column, sign = sweep.objective
    at = sweep.columns.index(column)
    for r in rows:
        if r[status_at] != "OK" or r[at] is None:
            continue
        item = (sign * float(r[at]), -int(r[0]), r)  # ties: the earlier variant
        if len(best) < keep:
            heapq.heappush(best, item)
        elif item[:2] > best[0][:2]:
            heapq.heapreplace(best, item)


def _write_page(sweep: Plan, counts: dict[str, int], seconds: float, region: Region,
                rows: Sequence[Row], table: tuple[Path, Path], stopped: bool) -> Path:
    """The summary page written into the sweep's folder (see :mod:`camfab.sweep.page`), with
    the *table* (its temporary and final paths) renamed into place beside it."""
    from camfab.sweep.page import render_page
    from camfab.writing import write_files

    variants = sweep.variants
    if variants.varies:
        varied = [(v.path, _values_text(v.values)) for v in variants.varies]
    else:
        varied = [(p, f"{len({row[i] for row in variants.rows})} values from "
                      f"{sweep.options.variants}") for i, p in enumerate(variants.paths)]
    shown = [c for c in sweep.columns if c not in ("message", "motion_units")]
    at = [sweep.columns.index(c) for c in shown]
    objective = None
    if sweep.objective is not None:
        objective = f"{'least' if sweep.objective[1] < 0 else 'greatest'} {sweep.objective[0]}"
    data = render_page(f"{sweep.name}-sweep", str(sweep.options.design), varied, counts,
                       seconds, region, shown, [tuple(r[i] for i in at) for r in rows],
                       objective, table[1].name, stopped)
    name = f"{sweep.name}-sweep.html"
    write_files(sweep.out_dir, {name: data}, [table])
    return sweep.out_dir / name


def _values_text(values: Sequence[Any]) -> str:
    shown = ", ".join(str(v) for v in values[:8])
    return f"{shown}, … ({len(values):,} values)" if len(values) > 8 else shown


def _build_best(sweep: Plan, rows: Sequence[Row]) -> list[tuple[Path, int]]:
    """The design file of each of *rows* (best first) written as ``best/NAME-vINDEX.yaml``
    and built into ``best/NAME-vINDEX/``: (folder, exit status) each."""
    from camfab.pipeline import build
    from camfab.writing import write_files

    folder = sweep.out_dir / "best"
    built = []
    for r in rows:
        index = int(r[0])
        name = f"{sweep.name}-v{index}"
        text = (f"# variant {index} of the sweep of {sweep.options.design}\n"
                + _variant_text(sweep, index, name))
        write_files(folder, {f"{name}.yaml": text.encode("utf-8")})
        result = build(folder / f"{name}.yaml", folder / name)
        built.append((folder / name, result.exit_code))
    return built


def _variant_text(sweep: Plan, index: int, name: str) -> str:
    """The design file of variant *index*, named *name*: the sweep's design file as written with
    only the varied values and the name changed (comments, order and layout kept), as the
    studio saves an edit; the variant's data written out afresh where the studio's editor
    (the ``serve`` extra) is not installed or cannot place a value."""
    from camfab.sweep.vary import dotted, with_values

    values = sweep.variants.values(index)
    try:
        from camfab.design.source import read_design_text
        from camfab.serve.yamledit import EditError, set_value

        text = read_design_text(sweep.options.design)
        for path, value in zip(sweep.variants.keys, values, strict=True):
            text = set_value(text, dotted(path), value)
        return set_value(text, "name", name)
    except (ImportError, EditError):
        import yaml

        data = with_values(sweep.data, sweep.variants.keys, values)
        data["name"] = name
        return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)
