"""A kind's part serialised: the DXF of each drawing, the SVG of each view and the STL of the
solid, for the outputs a design asks for and those the kind's read-back needs."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.export.step import StepFile
    from camfab.export.stl import StlFile


@dataclass(frozen=True)
class PartFiles:
    """A part's files by output name (``dxf``, ``svg``, ``stl``, ``step``) and file name, the
    STL as built (its volume and area) and the STEP (its solids and exact volume), when made,
    and why an output asked for could not be made of this part."""

    files: dict[str, dict[str, bytes]]
    stl: StlFile | None = None
    step: StepFile | None = None
    withheld: dict[str, str] = field(default_factory=dict)


def serialise(design: Design, part: Part, requested: tuple[str, ...]) -> PartFiles:
    """The files of *part*: those *requested*, and those its read-back needs."""
    wanted = set(requested) | set(part.needs)
    files: dict[str, dict[str, bytes]] = {}
    stl = None
    if "stl" in wanted and part.solid is not None:
        from camfab.export.stl import render_stl

        stl = render_stl(part.solid)
        files["stl"] = {f"{design.name}.stl": stl.data}
    if "dxf" in wanted:
        from camfab.export.dxf import render_dxf

        files["dxf"] = {f"{stem}.dxf": render_dxf(drawing)
                        for stem, drawing in part.drawings.items()}
    step = None
    withheld: dict[str, str] = {}
    if "step" in requested and "step" not in part.withheld:
        from camfab.export.step import NotExact, render_step

        if part.solid is None:
            withheld["step"] = part.withheld.get("stl", "the part has no solid (give "
                                                 "cam.thickness for a plate)")
        else:
            try:
                step = render_step(part.solid, design.name)
                files["step"] = {f"{design.name}.step": step.data}
            except NotExact as exc:
                withheld["step"] = (f"no exact solid of a {design.cam.type} cam in camfab "
                                    f"{_version()}: its part holds {exc}")
    if "svg" in wanted:
        from camfab.export.svg import render_svg

        files["svg"] = {f"{stem}.svg": render_svg(design, cut, pocket)
                        for stem, (cut, pocket) in part.views.items()}
    return PartFiles(files, stl, step, withheld)


def _version() -> str:
    from camfab import __version__

    return __version__
