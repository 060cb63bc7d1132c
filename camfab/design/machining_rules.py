"""The design file's rules of its ``machining:`` settings
(:class:`~camfab.design.machining.Machining`): a tool, a depth or a machine no program can cut
the cam with is refused on the line of the key to change, before anything is computed, as the
other rules of the design file are (:func:`camfab.design.rules.fail`).

The cam's sizes come from the design's own values (this layer knows no geometry): a groove is
as wide as its roller's diameter and the clearance, 2·roller_radius + groove_clearance (a drum's,
a groove plate's and a globoid's alike); a plate reaches its base radius and its lift. Lengths
are millimetres.

Not refused here: a tool wider than the bore or the keyway (the plate's program deals with the
holes), and a profile concave tighter than the tool's radius (the ``cutter`` check measures it
on the exact profile).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camfab.design.rules import fail, mm

if TYPE_CHECKING:
    from camfab.design.machining import Machining
    from camfab.design.model import Design
    from camfab.motion.program import MotionProgram

#: The axes beyond Grbl's three linear ones that each way of cutting a cam needs
#: (:attr:`~camfab.design.cam_types.CamTypeSpec.machining`).
ROTARY_AXES = {"drum": "a rotary A axis (4 axes)", "globoid": "rotary A and B axes (5 axes)"}

#: How far a tool may pass the groove's width and still count as its width: rounding only.
_WIDTH_SLACK = 1e-9


def check_machining(design: Design, settings: Machining, program: MotionProgram,
                    sizing: frozenset[str] = frozenset()) -> None:
    """Raise :class:`~camfab.design.rules.RuleViolation` for the first of *settings*' keys no
    program can cut *design*'s cam with: a dialect that cannot drive the axes or the
    compensation asked, a tool wider than the groove or larger than the cam, a pass or a cut
    deeper than the tool's flutes reach, a finishing allowance of a tool's radius or more.
    *sizing*: the keys the design leaves to camfab (``auto``), whose rules wait for them."""
    _check_dialect(design, settings)
    _check_tool_size(design, settings, program, sizing)
    _check_depths(design, settings)
    _check_allowance(settings)


def _check_dialect(design: Design, settings: Machining) -> None:
    """Grbl drives three linear axes and has no cutter compensation."""
    if settings.dialect != "grbl":
        return
    axes = ROTARY_AXES.get(design.cam.spec.machining)
    if axes is not None:
        fail(("machining", "dialect"), f"Grbl drives three linear axes only, and a "
             f"{design.cam.type} cam is cut on {axes}: use dialect: linuxcnc",
             allowed="linuxcnc")
    if settings.compensation == "control":
        fail(("machining", "compensation"), "Grbl has no cutter compensation (G41/G42): use "
             "compensation: path (the program carries the tool centre's path)", allowed="path")


def groove_width(design: Design) -> float | None:
    """The width of *design*'s groove (mm), its roller's diameter and the clearance; None for
    a cam without a groove."""
    cam, fol = design.cam, design.follower
    if cam.groove_depth is None:
        return None
    return 2.0 * (fol.roller_radius or 0.0) + fol.groove_clearance


def plate_size(design: Design, program: MotionProgram) -> float | None:
    """Some size of a plate without a groove (mm): the diameter its base radius and lift reach
    (a linear cam's length or height, whichever is more); None while its base radius is left
    to camfab (``auto``)."""
    cam, fol = design.cam, design.follower
    lift = program.max_lift * ((fol.arm_length or 0.0) if fol.oscillating else 1.0)
    if cam.stroke is not None:
        return max(cam.stroke, (cam.base_height or 0.0) + lift)
    if cam.base_radius is None:
        return None
    return 2.0 * (cam.base_radius + lift)


def _check_tool_size(design: Design, settings: Machining, program: MotionProgram,
                     sizing: frozenset[str]) -> None:
    """A groove is cut with a tool at most its width (the roller's diameter cuts exact walls);
    a plate with a tool no larger than the plate."""
    width = groove_width(design)
    if width is not None:
        if settings.tool_diameter > width * (1.0 + _WIDTH_SLACK):
            fail(("machining", "tool_diameter"), f"is wider than the groove, {mm(width)} "
                 "(2 × roller_radius + groove_clearance): it would cut the groove's walls away")
        return
    size = None if "cam.base_radius" in sizing else plate_size(design, program)
    if size is not None and settings.tool_diameter > size:
        fail(("machining", "tool_diameter"), f"is larger than the cam itself (some {mm(size)} "
             "across): no program cuts it with such a tool")


def _check_depths(design: Design, settings: Machining) -> None:
    """No pass deeper than the tool's length of cut, and the cut as a whole within it: a
    plate's thickness (its outline is cut through), a groove's depth."""
    length = settings.length_of_cut
    given = settings.cut_length is not None
    told = mm(length) if given else f"{mm(length)}, 3 × its diameter: no cut_length given"
    if settings.step_down is not None and settings.step_down > length:
        fail(("machining", "step_down"), f"is deeper than the tool's length of cut ({told}): "
             "no pass can cut deeper than the flutes reach")
    cam = design.cam
    if cam.spec.machining == "plate":
        depth, what = cam.thickness, "the plate's thickness (cam.thickness"
        cut = "cut through the plate"
    else:
        depth, what = cam.groove_depth, "the groove's depth (cam.groove_depth"
        cut = "reach the groove's floor"
    if depth is not None and depth > length:
        fail(("machining", "cut_length"), f"the tool's length of cut ({told}) is shorter than "
             f"{what}, {mm(depth)}): it cannot {cut}; give the cut_length of a tool that "
             "reaches", show_got=given)


def _check_allowance(settings: Machining) -> None:
    """The roughing passes stand off the finished wall by less than a tool's radius."""
    radius = settings.tool_radius
    if settings.finish_allowance >= radius:
        fail(("machining", "finish_allowance"), f"must be less than the tool's radius "
             f"({mm(radius)}): the roughing passes would leave the finishing pass more than "
             "a tool's radius of material to take")
