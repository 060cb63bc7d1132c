"""The pipeline: load -> the kind's analysis -> its part -> files (bytes) -> read back -> written
atomically.

The kinds describe and read back, the format writers serialise; this module decides which files
a design gets and writes them as one set (:mod:`camfab.writing`), so an interrupted or failed
build leaves earlier outputs intact.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab import __version__
from camfab.analysis.kinematics import (
    MotionUnits,
    continuity_findings,
    ringing_words,
    segment_stats,
)
from camfab.analysis.record import Analysis
from camfab.design import Design
from camfab.design.shop import Shop
from camfab.writing import write_files

if TYPE_CHECKING:
    from camfab.analysis.sizing import Sizing
    from camfab.design.model import Sized

#: Every output a design may ask for, in the order files are listed.
ALL_OUTPUTS = ("dxf", "svg", "stl", "report", "csv")
#: The outputs made only when asked for (``outputs``, ``camfab build --step`` or ``--gcode``):
#: STEP needs the optional extra, a machining program the tool and feeds.
ASKED_ONLY = ("step", "gcode")


def load_design(path: str | Path, shop: Shop | str | Path | None = None,
                also: tuple[str, ...] = ()) -> Design:
    """Read, check and return the design in file *path*: the keys it gives as ``auto`` sized
    (:func:`size_design`), the design file's rules, then its cam kind's (those that need the
    kind's geometry), every broken one reported on its line (raises
    DesignError/DesignFileError).

    *shop*: a shop's machining settings (a file, or as :func:`~camfab.design.shop.read_shop`
    read it) under the design's own ``machining:`` keys (:mod:`camfab.design.shop`); a rule a
    setting from it breaks is reported on its line. *also*: the outputs to make besides those
    the design asks for (``step``, ``gcode``: ``camfab build --step``, ``--gcode``); ``gcode``
    without the tool and feeds is refused."""
    from camfab.design import load_design as read
    from camfab.kinds import check_design

    if shop is None:
        design = read(path, check_design, sized_values)
    else:
        from camfab.design.loader import design_from_document
        from camfab.design.shop import read_shop, with_shop
        from camfab.design.source import read_design_file

        settings = shop if isinstance(shop, Shop) else read_shop(shop)
        design = design_from_document(with_shop(read_design_file(path), settings),
                                      check_design, sized_values)
    return with_outputs(design, also) if also else design


def with_outputs(design: Design, also: tuple[str, ...]) -> Design:
    """*design* making the outputs *also* besides those it asks for; ``gcode`` without the
    tool and feeds (no ``machining:`` section, no shop's settings) is refused on the design
    file."""
    from camfab.design.rules import GCODE_UNSET
    from camfab.errors import DesignError, Location

    if "gcode" in also and design.machining is None:
        raise DesignError(f"--gcode {GCODE_UNSET.removeprefix('gcode ')}",
                          location=Location(design.source, None, "machining"))
    asked = design.outputs or ALL_OUTPUTS
    return design.model_copy(update={"outputs": tuple(dict.fromkeys((*asked, *also)))})


def design_from_text(text: str, file: str = "<design>", folder: Path = Path(".")) -> Design:
    """The design in YAML *text*, checked as :func:`load_design` checks a file's."""
    from camfab.design import design_from_text as read
    from camfab.kinds import check_design

    return read(text, file, folder, check_design, sized_values)


def design_from_mapping(data: dict[str, Any], file: str = "<design>",
                        folder: Path = Path(".")) -> Design:
    """A design from already-parsed data, checked as :func:`load_design` checks a file's (the
    files it names found from *folder*)."""
    from camfab.design import design_from_mapping as read
    from camfab.kinds import check_design

    return read(data, file, check_design, sized_values, folder)


def size_design(design: Design, keys: frozenset[str], pivot: bool = False) -> Sizing:
    """The least radius of *design*'s cam that meets its limits (a plate's base radius, a
    drum's radius), with the offset when *keys* holds ``follower.offset`` and the pivot
    distance when *pivot* (:func:`camfab.analysis.sizing.size_design`). The design is one
    whose cam type camfab sizes (``CamTypeSpec.auto_keys``)."""
    from camfab.analysis.sizing import size_design as size
    from camfab.kinds import sizing_of

    problem_of = sizing_of(design.cam.type)
    assert problem_of is not None, "the design file's rules allow auto only where it is sized"
    return size(design, keys, problem_of, pivot)


def sized_values(design: Design, keys: frozenset[str]) -> Sized:
    """What :func:`size_design` chooses for the keys a design gives as ``auto`` (the sizer of
    :func:`camfab.design.load_design`): an offset alone is the one that would let the base
    radius be least, the base radius staying as given. A key no value of which meets the limits
    is a broken rule of the design file."""
    from camfab.analysis.sizing import unmet_words
    from camfab.design.model import Sized
    from camfab.design.rules import fail

    sizing = size_design(design, keys)
    size = sizing.size
    if size is None:
        key = "base_radius" if sizing.key == "base_radius" else "radius"
        fail(("cam", key), f"auto: {unmet_words(sizing, key.replace('_', ' '))}",
             show_got=False)
    governing = sizing.found.governing
    asked = f"cam.{sizing.key}" in keys  # else only the offset: the radius stays as given
    return Sized(
        base_radius=size if asked and sizing.key == "base_radius" else None,
        radius=size if asked and sizing.key == "radius" else None,
        offset=sizing.offset,
        governed_by=governing.id if governing is not None else "",
        what=governing.what if governing is not None else "",
        value=None if governing is None else governing.value,
        limit=None if governing is None else governing.limit,
        unit="mm" if governing is None else governing.unit,
        at_deg=None if governing is None else governing.at_deg,
        rounded_to=sizing.rounded_to)


def analyse(design: Design, advice: bool = True) -> Analysis:
    """Compute the motion, its kinematics, the cam's geometry, the dynamics and the checks of
    *design*: the checks every cam has, then its kind's analysis, then the rigid dynamics, then
    the cam at its speed (the elastic follower train, the contact stress, the roller's life);
    with *advice*, each failed check a sizing answers told the size that passes (a search of
    some hundredths of a second)."""
    from camfab.analysis.cam_checks import bore_finding
    from camfab.kinds import kind_of
    from camfab.speed.model import at_speed, force_note

    kind = kind_of(design.cam.type)
    program = design.program
    units = MotionUnits(design.follower.oscillating)
    omega = design.cam.omega
    ringing = ringing_words(design.follower.stiffness is not None,
                            force_note(design, design.spring is not None,
                                       design.cam.spec.two_sided))
    findings, steps = continuity_findings(program, units, omega, ringing)
    bore = bore_finding(design, kind.mounted)
    findings = [*findings, *([bore] if bore is not None else [])]
    stats = segment_stats(program, steps, units, omega)
    analysis = at_speed(_with_dynamics(kind.analyse(design, program, units, stats, findings),
                                       kind.drives_both_ways))
    return _with_advice(analysis) if advice else analysis


def _with_dynamics(analysis: Analysis, drives_both_ways: bool) -> Analysis:
    """*analysis* with the rigid model's dynamics of a spring-held follower and its ``jump``
    check (:mod:`camfab.analysis.dynamics`)."""
    from dataclasses import replace

    design = analysis.design
    if design.follower.mass is None or drives_both_ways:
        # a groove, a conjugate pair or a yoke drives its follower both ways: no spring to
        # size, and the forces on either side are theirs (camfab.geometry.groove, .conjugate)
        return analysis
    from camfab.analysis.dynamics import dynamics, jump_finding

    dyn = dynamics(design, analysis.program)
    if dyn is None:
        return analysis
    if design.spring is None:  # the spring force it needs, and no spring to check
        return replace(analysis, dynamics=dyn)
    return replace(analysis, dynamics=dyn,
                   findings=[*analysis.findings, jump_finding(design, dyn)])


def _with_advice(analysis: Analysis) -> Analysis:
    """*analysis* with the size that passes, computed, added to each failed check a sizing
    answers (:func:`camfab.analysis.sizing.advice`)."""
    from dataclasses import replace

    from camfab.analysis.sizing import ADVISED, advice
    from camfab.kinds import sizing_of

    failing = {f.id for f in analysis.findings if not f.ok and f.severity == "error"
               and f.id.removesuffix("_b") in ADVISED}
    problem_of = sizing_of(analysis.design.cam.type)
    if not failing or problem_of is None:
        return analysis
    told = advice(analysis.design, problem_of, failing)
    return replace(analysis, findings=[
        replace(f, message=f"{f.message}; {told[f.id]}") if f.id in told else f
        for f in analysis.findings])


@dataclass(frozen=True)
class Exports:
    """The manufacturing files by output name (``dxf``, ``svg``, ``stl``), each as its files'
    bytes by file name (a conjugate pair has a DXF per plate), and, for those a design cannot
    have, why."""

    files: dict[str, dict[str, bytes]]
    withheld: dict[str, str]


def verify_exports(analysis: Analysis, requested: tuple[str, ...]) -> tuple[Analysis, Exports]:
    """The design's part (through its kind) serialised by the format writers, the files read
    back and the follower run over them.

    Returns the analysis with its :class:`~camfab.kinds.readback.Verification` (and the
    ``verification`` check) and the *requested* files. Whatever the verification reads is made
    whether requested or not.
    """
    from dataclasses import replace

    from camfab.export.serialise import serialise
    from camfab.kinds import kind_of
    from camfab.kinds.readback import verification_finding

    kind = kind_of(analysis.design.cam.type)
    part = kind.part(analysis)
    made = serialise(analysis.design, part, requested)
    analysis, check = kind.verify(analysis, part, made)
    files, not_made = made.files, made.withheld
    if made.step is not None:
        from camfab.export.step import check_step

        assert part.solid is not None
        tolerance = analysis.design.manufacturing.tolerance
        measured = None if made.stl is None else (made.stl.volume_mm3,
                                                  tolerance * made.stl.area_mm2)
        check = replace(check, step=check_step(made.step, part.solid, tolerance, measured))
        if not check.step.ok:  # no STEP rather than a wrong one
            files = {k: v for k, v in files.items() if k != "step"}
            not_made = {**not_made, "step": "the solid OpenCASCADE made of the part did not "
                        "read back as the part (see the verification check)"}
    if "gcode" in requested:
        from camfab.machining import machine

        machined = machine(analysis, part)
        analysis = replace(analysis, machining=machined.setups,
                           findings=[*analysis.findings, *machined.findings])
        if machined.withheld is not None:
            not_made = {**not_made, "gcode": machined.withheld}
        else:
            files = {**files, "gcode": machined.files}
    withheld = {k: v for k, v in {**part.withheld, **not_made}.items() if k in requested}
    if withheld:  # the report says what was not made, and why
        check = replace(check, withheld=tuple(withheld.items()))
    findings = [*analysis.findings, verification_finding(analysis, check)]
    wanted = {name: data for name, data in files.items() if name in requested}
    return (replace(analysis, verification=check, findings=findings),
            Exports(wanted, withheld))


def _report_json(analysis: Analysis) -> bytes:
    from camfab.export.report_json import render_report_json

    return render_report_json(analysis)


def _report_html(analysis: Analysis) -> bytes:
    from camfab.export.report_html import render_report_html

    return render_report_html(analysis)


def _motion_csv(analysis: Analysis) -> bytes:
    from camfab.export.motion_csv import render_motion_csv

    return render_motion_csv(analysis)


#: output name -> [(file suffix, renderer)]; outputs without an entry are not produced yet.
RENDERERS: dict[str, list[tuple[str, Callable[[Analysis], bytes]]]] = {
    "report": [("-report.html", _report_html), ("-report.json", _report_json)],
    "csv": [("-motion.csv", _motion_csv)],
}


@dataclass(frozen=True)
class Artifacts:
    """The files of one build, as bytes by file name, and the requested outputs not produced
    (each with why)."""

    files: dict[str, bytes]
    not_produced: tuple[str, ...] = field(default_factory=tuple)
    analysis: Analysis | None = None


def render(analysis: Analysis) -> Artifacts:
    """The bytes of every file the design asks for (all that apply by default), after the
    verification of the exported outline (which the report carries)."""
    requested = analysis.design.outputs or ALL_OUTPUTS
    analysis, exports = verify_exports(analysis, requested)
    files: dict[str, bytes] = {}
    missing = []
    for output in (*ALL_OUTPUTS, *ASKED_ONLY):
        if output not in requested:
            continue
        if output in exports.files:
            files.update(exports.files[output])
            continue
        if output in exports.withheld:
            missing.append(f"{output} ({exports.withheld[output]})")
            continue
        if output not in RENDERERS:
            missing.append(f"{output} (not built by camfab {__version__} for "
                           f"{analysis.design.cam.type} cams)")
            continue
        for suffix, renderer in RENDERERS[output]:
            files[analysis.design.name + suffix] = renderer(analysis)
    return Artifacts(files, tuple(missing), analysis)


@dataclass(frozen=True)
class BuildResult:
    """What one build did."""

    analysis: Analysis
    folder: Path
    written: list[Path]
    not_produced: tuple[str, ...]

    @property
    def exit_code(self) -> int:
        return self.analysis.exit_code


def output_folder(design: Design, out_dir: Path | None, nested: bool = False) -> Path:
    """``exports/<name>/`` under the working directory, or *out_dir* when given (with *nested*,
    as a batch writes: ``<out_dir>/<name>/``, a folder of each design's own)."""
    if out_dir is None:
        return Path("exports") / design.name
    return out_dir / design.name if nested else out_dir


def build(path: str | Path, out_dir: Path | None = None,
          also: tuple[str, ...] = (), nested: bool = False,
          shop: Shop | str | Path | None = None) -> BuildResult:
    """Load, analyse, render and write one design file; *also* the outputs named (``step``,
    ``gcode``) besides those the design asks for, *shop* a shop's machining settings under the
    design's own (:func:`load_design`); *nested*: its files in a folder of its name inside
    *out_dir* (a batch's)."""
    design = load_design(path, shop, also)
    analysis = analyse(design)
    artifacts = render(analysis)
    folder = output_folder(design, out_dir, nested)
    written = write_files(folder, artifacts.files)
    return BuildResult(artifacts.analysis or analysis, folder, written, artifacts.not_produced)


#: The packages a build runs through, every layer under this module's.
BUILD_PACKAGES = ("camfab.motion", "camfab.curves", "camfab.design", "camfab.geometry",
                  "camfab.analysis", "camfab.speed", "camfab.export", "camfab.kinds")


def import_build_modules() -> None:
    """Import what building a design needs, and build nothing: every module of
    :data:`BUILD_PACKAGES` (the kinds, the format writers, the analysis, the geometry, ...) with
    the libraries they import as they load, then the libraries the format writers import when
    first called, through their own loaders: ezdxf
    (:func:`~camfab.export.ezdxf_import.load_ezdxf`) and Jinja2, the report's template compiled.
    A library a module imports only inside a function, for one kind of cam or one output, is
    left to the build that calls it.

    A batch calls this once before it forks its workers, so that they start with all of it
    instead of each importing it again. It computes nothing and leaves no thread running that a
    fork would copy mid-work: numpy's BLAS starts its threads as it is imported, and stops them
    itself before every fork; manifold3d starts its own only when it first computes."""
    import pkgutil
    from importlib import import_module

    from camfab.export.ezdxf_import import load_ezdxf
    from camfab.export.report_html import REPORT_TEMPLATE, page_template

    for name in BUILD_PACKAGES:
        for module in pkgutil.iter_modules(import_module(name).__path__, f"{name}."):
            import_module(module.name)
    load_ezdxf()
    page_template(REPORT_TEMPLATE)
