"""The ``camfab`` command line: thin — parse, call the library, print, set the exit status.

Exit status: 0 built and every check passed; 1 built (or checked) with a failed ``error`` check;
2 the design or the command line is invalid (one line on stderr, nothing written); 130 and 143
stopped by Ctrl-C and SIGTERM; 74 standard output could not be written (:mod:`camfab.terminal`,
as the ``camfab`` program).
Heavy libraries are imported inside the commands so ``camfab --version`` stays instant.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from camfab import __version__
from camfab.batch import PROGRESS_FROM, Outcome
from camfab.stopping import RECEIVED, Interrupted, catch, stop_line

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.design.shop import Shop
    from camfab.inspect import Inspection, InspectOptions
    from camfab.inspect.scan_run import ScanResult
    from camfab.sweep.run import SweepOptions
    from camfab.tune.plan import TuneOptions

STARTER_KINDS = ("disc-roller", "disc-knife", "disc-flat", "disc-mushroom", "oscillating",
                 "oscillating-flat", "cylindrical", "circular-arc", "tangent", "groove",
                 "conjugate", "constant-breadth", "linear", "globoidal")
#: ``camfab tune --objective``'s choices (:data:`camfab.tune.objectives.NAMES`).
TUNE_OBJECTIVES = ("residual", "acceleration", "jerk", "stress", "torque")


@contextmanager
def _ctrl_c_as_ours() -> Iterator[None]:
    """Ctrl-C (KeyboardInterrupt) raised as camfab's :class:`Interrupted`, before click's
    handler of it prints a blank line ahead of camfab's one."""
    try:
        yield
    except KeyboardInterrupt:
        import signal

        raise Interrupted(signal.SIGINT) from None


class _Camfab(click.Group):
    """The command group, run so that every way out is one line and a documented status: click's
    usage errors on one line (status 2), Ctrl-C status 130 and SIGTERM 143 (128 + the signal),
    with the temporary files of an interrupted build removed on the way out."""

    def make_context(self, info_name: str | None, args: list[str],
                     parent: click.Context | None = None, **extra: Any) -> click.Context:
        with _ctrl_c_as_ours():  # the command line being parsed
            return super().make_context(info_name, args, parent, **extra)

    def invoke(self, ctx: click.Context) -> Any:
        with _ctrl_c_as_ours():
            return super().invoke(ctx)

    def main(self, args: Any = None, prog_name: str | None = None,
             complete_var: str | None = None, standalone_mode: bool = True,
             process: bool = False, **extra: Any) -> Any:
        """Run the command; *process*: as the ``camfab`` program (:mod:`camfab.start`), which
        ends when it returns."""
        import signal

        catch()
        if standalone_mode or process:
            _freeze_at_exit()
        try:
            result = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
            code = result if isinstance(result, int) else 0
        except SystemExit as exc:  # the commands' sys.exit(status)
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except click.exceptions.Abort:  # click's form of Ctrl-C (KeyboardInterrupt)
            RECEIVED.append(signal.SIGINT)
        except Interrupted as exc:
            RECEIVED.append(exc.signum)
        except click.exceptions.NoArgsIsHelpError as exc:  # a bare ``camfab``: the help
            click.echo(exc.format_message(), err=True)
            code = exc.exit_code
        except click.ClickException as exc:
            click.echo(_usage_line(exc), err=True)
            code = exc.exit_code
        except Exception:
            if not RECEIVED:
                raise
            # a library caught the signal's raise and wrapped it in its own error (pydantic
            # building a model's schema while camfab imports it): it is still the signal
        if RECEIVED:
            click.echo(stop_line(RECEIVED[0]), err=True)
            code = 128 + RECEIVED[0]
        if standalone_mode:
            sys.exit(code)
        return code


@cache
def _freeze_at_exit() -> None:
    """At the process's exit, put every object it holds out of the garbage collector's reach
    (:func:`gc.freeze`), so the interpreter's shutdown does not walk them all again: about
    0.15 s of a 0.7 s build. Registered once (the call is cached); the exit's own work
    (``atexit``, ``finally``, the files) is unchanged."""
    import atexit
    import gc

    atexit.register(gc.freeze)


def _usage_line(exc: click.ClickException) -> str:
    """A click error as one line: ``camfab build: No such option: --frobnicate (see camfab
    build --help)``."""
    message = " ".join(exc.format_message().split())
    ctx = getattr(exc, "ctx", None)
    if isinstance(exc, click.UsageError) and ctx is not None:
        return f"{ctx.command_path}: {message} (see {ctx.command_path} --help)"
    return f"camfab: {message}"


@click.group(cls=_Camfab, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "-V", "--version", prog_name="camfab")
def main() -> None:
    """camfab: turn a cam design (YAML) into workshop files and an inspection report."""


@main.command()
@click.argument("designs", nargs=-1, required=True)
@click.option("-o", "--output", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              help="Write the files into DIR instead of exports/<name>/ (several designs: "
                   "each into DIR/<name>/).", metavar="DIR")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), default=1, show_default=True,
              help="Build this many designs in parallel processes.")
@click.option("--progress/--no-progress", default=None,
              help=f"Show a progress bar on stderr (default: for {PROGRESS_FROM} or more designs "
                   "when stderr is a terminal).")
@click.option("--step", is_flag=True,
              help="Write NAME.step too (exact solids for CAD; needs camfab[step]).")
@click.option("--gcode", is_flag=True,
              help="Write NAME.ngc too: the machining program, with the tool and feeds of the "
                   "design's machining section or of --machining FILE.")
@click.option("--machining", "shop_file", metavar="FILE",
              help="A shop's machining settings: a YAML file with a machining section (and its "
                   "units, mm by default). The design's own machining keys override the file's "
                   "key by key. Implies --gcode.")
def build(designs: tuple[str, ...], out_dir: Path | None, jobs: int,
          progress: bool | None, step: bool, gcode: bool, shop_file: str | None) -> None:
    """Build DESIGN files: write the report, motion table and manufacturing files. With several
    designs, a failure of one does not stop the others; a summary table ends the output and the
    exit status is the worst of them."""
    import time
    from functools import partial

    from camfab.batch import run_all, same_names, summary
    from camfab.design.rules import STEP_MISSING, step_available

    if step and not step_available():
        click.echo(f"camfab build: --step: {STEP_MISSING}", err=True)
        sys.exit(2)
    shop = None
    if shop_file is not None:  # read once, for every design; a bad one builds none
        from camfab.design.shop import read_shop
        from camfab.errors import CamfabError

        try:
            shop = read_shop(shop_file)
        except CamfabError as exc:
            click.echo(str(exc), err=True)
            sys.exit(2)
    also = (*(["step"] * step), *(["gcode"] * (gcode or shop is not None)))
    if progress is None:
        progress = len(designs) >= PROGRESS_FROM and sys.stderr.isatty()
    start = time.perf_counter()
    refused = same_names(designs) if len(designs) > 1 else {}
    # several designs into one -o DIR: each in DIR/NAME/, as under exports/
    task = partial(_build_one, also=also, nested=len(designs) > 1, shop=shop)
    built = iter(run_all([p for i, p in enumerate(designs) if i not in refused], out_dir, jobs,
                         task, progress, _import_build))
    outcomes = [refused[i] if i in refused else next(built) for i in range(len(designs))]
    code = _finish(outcomes)
    if len(designs) > 1:
        click.echo("")
        for line in summary(outcomes, time.perf_counter() - start):
            click.echo(line)
    sys.exit(code)


@main.command()
@click.argument("designs", nargs=-1, required=True)
def check(designs: tuple[str, ...]) -> None:
    """Analyse DESIGN files and print the findings; write nothing."""
    outcomes = [_check_one(path) for path in designs]
    sys.exit(_finish(outcomes))


@main.command()
@click.argument("design")
@click.option("--offset", "with_offset", is_flag=True,
              help="Also choose the offset of a translating follower that lets the base radius "
                   "be least (a flat face: the offset that centres it on the contact).")
@click.option("--pivot", "with_pivot", is_flag=True,
              help="Also choose the pivot distance of an oscillating follower, for its arm "
                   "length, that lets the base radius be least.")
def size(design: str, with_offset: bool, with_pivot: bool) -> None:
    """Find the least base radius of DESIGN's cam (a drum's radius) that meets its limits:
    pressure angle, undercut, limits.min_radius_of_curvature, face width, limits.contact_stress,
    limits.roller_life and the fit of bore and follower. Prints what governs it and every limit
    at that size; writes nothing. Exit 0 when a size exists, 1 when none does (a roller's life
    falls as the cam grows: a life the sizes the other limits allow cannot reach is said so)."""
    sys.exit(_finish([_guarded(design, lambda: _size_one(design, with_offset, with_pivot))]))


def _size_one(path: str, with_offset: bool, with_pivot: bool) -> Outcome:
    from camfab.design.loader import unsized_design
    from camfab.errors import CamfabError
    from camfab.pipeline import size_design
    from camfab.sizing_text import sizing_lines

    keys = frozenset({"cam.base_radius", "cam.radius", *(["follower.offset"] * with_offset)})
    design, sized = unsized_design(path, keys)
    fol = design.follower
    if with_offset and (fol.oscillating or "follower.offset" not in sized):
        reason = ("an oscillating follower has no offset (--pivot sizes its pivot distance)"
                  if fol.oscillating else f"a {design.cam.type} cam's follower offset is not sized")
        raise CamfabError(f"{path}: --offset: {reason}")
    if with_pivot and not (fol.oscillating and design.cam.spec.disc_curves):
        raise CamfabError(f"{path}: --pivot: sizes the pivot distance of an oscillating follower "
                          f"on a plate cam; this design's follower is {fol.motion}")
    sizing = size_design(design, sized, with_pivot)
    return Outcome(0 if sizing.size is not None else 1, out=sizing_lines(design, sizing))


@main.command()
@click.argument("design")
@click.option("--vary", multiple=True, metavar="PATH=SPEC",
              help="Vary a key of the design: PATH such as cam.base_radius, follower.offset, "
                   "motion[0].law; SPEC a range START:STOP:STEP, a list a,b,c or "
                   "log:START:STOP:N. Repeat for more keys: the variants are their product.")
@click.option("--variants", type=click.Path(path_type=Path), metavar="FILE.csv",
              help="The variants as a CSV file: a header of PATHs, one row of values each.")
@click.option("-o", "--output", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              help="Write the table and page into DIR instead of exports/<name>-sweep/.",
              metavar="DIR")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), default=None,
              help="Worker processes (default: all the processors).")
@click.option("--scheduler", metavar="tcp://HOST:8786",
              help="Run on the Dask cluster of the scheduler at tcp://HOST:PORT or HOST:PORT "
                   "(not tls://; needs camfab[cluster]). It must take the connection within 5 s "
                   "and answer within 10 s.")
@click.option("--cluster-timeout", type=float, default=None, metavar="SECONDS",
              help="With --scheduler: how long to wait for the cluster's first worker when it "
                   "has none (default 60; 0: do not wait; at most 86400).")
@click.option("--size", is_flag=True,
              help="Also find each variant's least base radius (a drum's radius) that meets its "
                   "limits (some hundredths of a second a variant).")
@click.option("--build-best", type=click.IntRange(0, 1000), default=0, metavar="K",
              help="Build the files of the K best variants by the objective.")
@click.option("--minimize", metavar="COLUMN", help="The objective: a numeric column to minimise "
              "(a varied key such as cam.base_radius, or a key number).")
@click.option("--maximize", metavar="COLUMN", help="The objective: a numeric column to maximise.")
@click.option("--format", "table_format", type=click.Choice(["parquet", "csv"]),
              help="The table's format (default: Parquet when pyarrow is installed, else CSV).")
@click.option("--progress/--no-progress", default=None,
              help="Show a progress bar on stderr (default: when stderr is a terminal).")
def sweep(design: str, vary: tuple[str, ...], variants: Path | None, out_dir: Path | None,
          jobs: int | None, scheduler: str | None, cluster_timeout: float | None, size: bool,
          build_best: int, minimize: str | None, maximize: str | None,
          table_format: str | None, progress: bool | None) -> None:
    """Sweep DESIGN over varied keys: validate and analyse every variant (no files), one row of
    key numbers each (status OK, FAIL or INVALID; pressure angle, curvature, undercut, motion
    maxima, face width, jump speed, contact force; contact stress, residual vibration, the
    elastic follower's jump speed, roller life) in a table (NAME-sweep.parquet or .csv) and a
    summary page with the feasible region (NAME-sweep.html). Exit 0 when the sweep ran, 2 for
    bad options, 1 when a best variant's build fails."""
    from camfab.sweep.run import SweepOptions

    if progress is None:
        progress = sys.stderr.isatty()
    options = SweepOptions(Path(design), vary, variants, out_dir,
                           jobs or _processors(), scheduler, size, build_best, minimize,
                           maximize, table_format, progress, cluster_timeout=cluster_timeout)
    sys.exit(_finish([_guarded(design, lambda: _sweep_one(options))]))


def _processors() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        (os.cpu_count() or 1)


def _sweep_one(options: SweepOptions) -> Outcome:
    from camfab.sweep.run import plan, run

    sweep = plan(options)
    done = run(sweep, click.echo)
    c = done.counts
    rate = f" ({done.rows / done.seconds:.1f} a second)" if done.seconds > 0 else ""
    lines = [f"{sweep.name}: {done.rows:,} variants — {c['OK']:,} OK, {c['FAIL']:,} FAIL, "
             f"{c['INVALID']:,} INVALID — in {done.seconds:.1f} s{rate}",
             f"  {done.table}", f"  {done.page}"]
    code = 0
    for folder, status in done.built:
        lines.append(f"  built {folder}/ ({ {0: 'OK', 1: 'FAIL'}.get(status, 'INVALID') })")
        code = max(code, status)
    return Outcome(code, out=lines)


@main.command()
@click.argument("design")
@click.option("--segment", "segments", metavar="I,J",
              help="Tune these segments of the motion list (numbered from 0; default: every "
                   "rise and return).")
@click.option("--objective", type=click.Choice(TUNE_OBJECTIVES),
              help="What to minimise: the largest residual vibration over the speeds of "
                   "--speeds (default with a follower.stiffness), the peak acceleration "
                   "(default without) or jerk of the motion, the peak contact stress, or the "
                   "peak camshaft torque.")
@click.option("--speeds", metavar="LOW:HIGH[:N]",
              help="The band of cam speeds (rpm) the residual vibration is taken over: "
                   "LOW:HIGH (7 speeds), LOW:HIGH:N, a list A,B,C or one speed (default: the "
                   "design speed ±10 %).")
@click.option("--starts", type=click.IntRange(1, 64), default=4, show_default=True,
              help="Starts of the optimisation of the continuous parameters (the design's own "
                   "values, then seeded random ones).")
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path),
              metavar="OUT.yaml",
              help="Write the tuned design here instead of NAME-tuned.yaml beside the design "
                   "(the report NAME-tuning.html goes beside it).")
@click.option("--progress/--no-progress", default=None,
              help="Show a progress line on stderr (default: when stderr is a terminal).")
def tune(design: str, segments: str | None, objective: str | None, speeds: str | None,
         starts: int, output: Path | None, progress: bool | None) -> None:
    """Tune DESIGN's motion laws: choose the free parameters of the laws of its rises and
    returns (a standard law among those its neighbours' continuity allows, a polynomial's
    points, a spline's control values, a blend) to minimise the objective under every limit of
    the design, and write the tuned design (only those values changed, comments kept) and a
    report comparing before and after. Exit 0 when the tuned design meets every limit, 1 when
    no candidate does (the report says why, no design is written), 2 for bad input (nothing
    written); Ctrl-C writes the best found so far and stops (130)."""
    from camfab.tune.plan import TuneOptions

    if progress is None:
        progress = sys.stderr.isatty()
    options = TuneOptions(Path(design), segments, objective, speeds, starts, output, progress)
    sys.exit(_finish([_guarded(design, lambda: _tune_one(options))]))


def _tune_one(options: TuneOptions) -> Outcome:
    from camfab.tune.run import tune as run

    done = run(options, click.echo, lambda text: click.echo(text, err=True, nl=False),
               sys.stderr.isatty())
    return Outcome(done.code, out=done.lines)


@main.command()
@click.argument("design")
@click.option("--port", type=click.IntRange(0, 65535), default=8765, show_default=True,
              help="The port to listen on (0: any free one).")
@click.option("--host", metavar="ADDR",
              help="Listen on this address instead of 127.0.0.1 (this machine only); another "
                   "machine can then reach the studio with its URL.")
@click.option("--open/--no-open", "open_page", default=None,
              help="Open the page in the desktop's browser (default: when there is a desktop).")
def serve(design: str, port: int, host: str | None, open_page: bool | None) -> None:
    """Open DESIGN in the studio: a page in the browser that shows its report live — the cam
    animated in 2-D and 3-D, its diagrams and checks — with every number of the design to edit;
    Save writes the edits into the file (comments kept), and a save in any editor shows at once.
    Needs camfab[serve]. Prints the page's URL (with its token); Ctrl-C stops it."""
    from camfab.batch import Outcome

    def work() -> Outcome:
        from camfab.serve.run import serve as run

        return Outcome(run(design, port, host, open_page))

    sys.exit(_finish([_guarded(design, work)]))


@main.command()
def laws() -> None:
    """List the motion laws with their peak coefficients Cv, Ca, Cj."""
    from camfab.report_text import laws_table

    laws_table()


@main.command()
@click.argument("kind", required=False)
def new(kind: str | None) -> None:
    """Print a commented starter design of KIND (disc-roller, disc-flat, oscillating, ...)."""
    from importlib import resources

    from camfab.errors import did_you_mean

    if kind is None:
        click.echo("starter designs: " + ", ".join(STARTER_KINDS))
        click.echo("usage: camfab new KIND > design.yaml")
        return
    if kind not in STARTER_KINDS:
        suggestion = did_you_mean(kind, STARTER_KINDS, cutoff=0.5)
        hint = f"{suggestion}; " if suggestion else ""
        click.echo(f"camfab new: unknown kind '{kind}' ({hint}allowed: "
                   f"{', '.join(STARTER_KINDS)})", err=True)
        sys.exit(2)
    text = (resources.files("camfab") / "starters" / f"{kind}.yaml").read_text(encoding="utf-8")
    click.echo(text, nl=False)


@main.command()
@click.argument("profile", type=click.Path(path_type=Path))
@click.option("--design", type=click.Path(path_type=Path), metavar="DESIGN.yaml",
              help="Compare with this design's motion (follower, rotation, speed and tolerance "
                   "default to the design's).")
@click.option("--follower", "follower_file", type=click.Path(path_type=Path), metavar="F.yaml",
              help="The follower (and rotation, speed_rpm, units, tolerance) from a small YAML.")
@click.option("--type", "kind", type=click.Choice(["knife", "roller", "flat", "mushroom"]),
              help="Follower type.")
@click.option("--roller-radius", metavar="R", help="Roller radius (e.g. of a dial indicator).")
@click.option("--face-radius", metavar="R", help="Mushroom follower's face radius.")
@click.option("--offset", metavar="E", help="Translating follower's offset (signed, +X).")
@click.option("--pivot-distance", metavar="A", help="Oscillating: cam centre to pivot.")
@click.option("--arm-length", metavar="L", help="Oscillating: pivot to trace point.")
@click.option("--pivot-side", type=click.Choice(["right", "left"]), help="Oscillating: pivot side.")
@click.option("--face-offset", metavar="F", help="Oscillating flat face: distance from the pivot.")
@click.option("--rotation", type=click.Choice(["ccw", "cw"]), help="Cam rotation (default ccw).")
@click.option("--speed", metavar="RPM", help="Cam speed for velocities and accelerations.")
@click.option("--units", type=click.Choice(["mm", "in"]),
              help="Unit of the file's coordinates and of bare lengths on the command line.")
@click.option("--layer", metavar="NAME", help="DXF layer of the outline (default CUT if present, "
                                              "else all).")
@click.option("--centre", metavar="X,Y", help="Cam centre in the file's coordinates (default 0,0).")
@click.option("--step", metavar="DEG", help="Row step of the lift table (default 1°).")
@click.option("--smooth", metavar="DEG", help="Half-width of the window the derivatives are "
                                              "fitted over (default 1° drawings, 3° points).")
@click.option("--tolerance", metavar="T", help="Largest deviation accepted, a length (default the "
                                                "design's inspection.tolerance: 0.025 mm, "
                                                "0.001 in).")
@click.option("--kerf", metavar="K", help="The outline is a laser's path: take kerf/2 off "
                                           "(default: what a camfab DXF's note says, else 0).")
@click.option("--align", is_flag=True, help="Turn the outline into phase with the design first.")
@click.option("--scan", is_flag=True, help="Read PROFILE as a 3-D scan (x, y, z points) even "
                                           "when it is the CSV of a disc cam.")
@click.option("--fixtured", is_flag=True, help="Scan: its coordinates are the cam's (its axis "
                                               "Z, as a CMM's fixture holds it); only the phase "
                                               "is fitted. Default: a free rigid fit.")
@click.option("--fit", metavar="LENGTH", help="Scan: size of the box its deviation is averaged "
                                              "over before the follower is run (default 1 mm).")
@click.option("--gate", metavar="LENGTH", help="Scan: points farther from their flank are set "
                                               "aside (default 1 mm).")
@click.option("--plate-b", type=click.Path(path_type=Path), metavar="B.dxf",
              help="A conjugate pair: the drawing of its plate b (PROFILE is plate a's); both "
                   "plates are judged together.")
@click.option("-o", "--output", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              help="Write the files into DIR instead of exports/<stem>-inspection/.",
              metavar="DIR")
def inspect(profile: Path, design: Path | None, follower_file: Path | None, kind: str | None,
            roller_radius: str | None, face_radius: str | None, offset: str | None,
            pivot_distance: str | None, arm_length: str | None, pivot_side: str | None,
            face_offset: str | None, rotation: str | None, speed: str | None, units: str | None,
            layer: str | None, centre: str | None, step: str | None, smooth: str | None,
            tolerance: str | None, kerf: str | None, align: bool, scan: bool, fixtured: bool,
            fit: str | None, gate: str | None, plate_b: Path | None, out_dir: Path | None
            ) -> None:
    """Inspect a made or scanned cam. PROFILE is its outline (DXF, or CSV of x, y points), or a
    3-D scan or CMM points of any cam (PLY, STL, or CSV of x, y, z and optionally the normal).

    Runs the follower over the outline (or the scanned flanks) and writes the lift table, the
    JSON and HTML reports; with --design, the deviation from the design's motion (exit 1 when
    over the tolerance). A scan needs --design; it is placed on the part by a best fit.
    """
    given = {"type": kind, "roller_radius": roller_radius, "face_radius": face_radius,
             "offset": offset, "pivot_distance": pivot_distance, "arm_length": arm_length,
             "pivot_side": pivot_side, "face_offset": face_offset}
    from camfab.inspect import InspectOptions

    options = InspectOptions(
        profile, design, follower_file, {k: v for k, v in given.items() if v is not None},
        rotation, speed, units, layer, centre, step, smooth, tolerance, kerf, align, out_dir,
        scan, fixtured, fit, gate, plate_b)
    sys.exit(_finish([_guarded(str(profile), lambda: _inspect_one(options))]))


def _inspect_one(options: InspectOptions) -> Outcome:
    from camfab.inspect import inspect as run_inspection
    from camfab.inspect.scan_run import ScanResult

    result = run_inspection(options)
    if isinstance(result, ScanResult):
        return _scan_outcome(result, options)
    ins = result.inspection
    stem = options.profile.stem
    worst = ins.max_deviation()
    if worst is None or ins.reference is None:
        steepest = next(f.value for f in ins.findings if f.id == "pressure_angle")
        head = f"{stem}: MEASURED — lift {_lift_text(ins)}, pressure angle up to {steepest:.3g}°"
    else:
        state = "FAIL" if result.exit_code else "PASS"
        head = (f"{stem}: {state} — deviation from {ins.reference.name} {worst[0]:.3g} mm at "
                f"most (at {worst[1]:.4g}°), RMS {ins.rms_deviation():.3g} mm, tolerance "
                f"{ins.setup.tolerance:.3g} mm")
        if ins.align is not None:
            head += f"; turned {math.degrees(ins.align):.4g}° into phase"
    lines = [f"{head} — wrote {len(result.written)} file(s) to {result.folder}/"]
    lines += [f"  {p.name}" for p in result.written]
    lines += [f"  {f.mark} {f.id}: {f.message}" for f in ins.findings if not f.ok]
    return Outcome(result.exit_code, out=lines)


def _scan_outcome(result: ScanResult, options: InspectOptions) -> Outcome:
    ins = result.inspection
    worst = ins.worst()
    assert worst is not None
    state = "FAIL" if result.exit_code else "PASS"
    judged = len(ins.deviations.flank)
    head = (f"{options.profile.stem}: {state} — lift error through the scanned flanks "
            f"{worst[0]:.3g} mm at most (on the {worst[1]}, at {worst[2]:.4g}°), tolerance "
            f"{ins.setup.tolerance:.3g} mm; {judged - ins.deviations.aside:,} of {judged:,} "
            f"points on the flanks, placed with a residual of "
            f"{ins.alignment.residual_mm:.2g} mm")
    lines = [f"{head} — wrote {len(result.written)} file(s) to {result.folder}/"]
    lines += [f"  {p.name}" for p in result.written]
    lines += [f"  {f.mark} {f.id}: {f.message}" for f in ins.findings if not f.ok]
    return Outcome(result.exit_code, out=lines)


def _lift_text(ins: Inspection) -> str:
    import numpy as np

    if ins.oscillating:
        return f"{math.degrees(float(np.max(ins.lift))):.4g}°"
    return f"{float(np.max(ins.lift)):.4g} mm"


def _finish(outcomes: list[Outcome]) -> int:
    for outcome in outcomes:
        for line in outcome.out:
            click.echo(line)
        for line in outcome.err:
            click.echo(line, err=True)
    return max((o.code for o in outcomes), default=0)


def _guarded(path: str, work) -> Outcome:
    """Run *work*; invalid input becomes its one-line message and status 2. numpy's warnings on
    extreme values stay off the terminal: what a design does wrong is a finding or an error. An
    error raised after a stopping signal is that signal, whatever a library made of it."""
    import warnings

    from camfab.errors import CamfabError

    try:
        with warnings.catch_warnings():
            if not os.environ.get("CAMFAB_DEBUG"):
                warnings.simplefilter("ignore", RuntimeWarning)
            return work()
    except Exception as exc:
        if RECEIVED:  # a library caught the signal's raise and wrapped it (pydantic's schemas)
            raise Interrupted(RECEIVED[0]) from None
        if isinstance(exc, CamfabError):
            return Outcome(2, err=[str(exc)])
        if os.environ.get("CAMFAB_DEBUG"):
            raise
        return Outcome(2, err=[f"{path}: internal error: {type(exc).__name__}: {exc} "
                               "(set CAMFAB_DEBUG=1 for details; please report it)"])


def _build_one(path: str, out_dir: Path | None, also: tuple[str, ...] = (),
               nested: bool = False, shop: Shop | None = None) -> Outcome:
    def work() -> Outcome:
        from camfab.analysis.sizing_words import sized_words
        from camfab.export.machining_page import cycle_time_line
        from camfab.pipeline import build as build_design

        result = build_design(path, out_dir, also, nested, shop)
        lines = [f"{result.analysis.design.name}: {_verdict(result.analysis)} — wrote "
                 f"{len(result.written)} file(s) to {result.folder}/"]
        lines += [f"  {p.name}" for p in result.written]
        lines += [f"  {cycle_time_line(setup)}" for setup in result.analysis.machining]
        sized = sized_words(result.analysis.design)
        if sized is not None:
            lines.append(f"  {sized}")
        if result.not_produced:
            lines.extend(f"  not produced: {item}" for item in result.not_produced)
        lines += [f"  {f.mark} {f.id}: {f.message}" for f in result.analysis.findings
                  if not f.ok]
        from camfab.analysis.findings import count

        findings = result.analysis.findings
        return Outcome(result.exit_code, out=lines, name=result.analysis.design.name,
                       errors=count(findings, "error"), warnings=count(findings, "warning"),
                       files=len(result.written))

    return _guarded(path, work)


def _import_build() -> None:
    """Import what :func:`_build_one` needs, building nothing (a batch's workers start with it)."""
    from camfab.pipeline import import_build_modules

    import_build_modules()


def _check_one(path: str) -> Outcome:
    def work() -> Outcome:
        from camfab.pipeline import analyse, load_design
        from camfab.report_text import print_summary

        analysis = analyse(load_design(path))
        print_summary(analysis)
        return Outcome(analysis.exit_code)

    return _guarded(path, work)


def _verdict(analysis: Analysis) -> str:
    from camfab.analysis.findings import count

    errors, warnings = count(analysis.findings, "error"), count(analysis.findings, "warning")
    state = "FAIL" if analysis.exit_code else "OK"
    return f"{state} ({errors} error(s), {warnings} warning(s))"


if __name__ == "__main__":  # pragma: no cover
    main()
