"""A kind's part serialised: the DXF of each drawing, the SVG of each view and the STL of the
solid, for the outputs a design asks for and those the kind's read-back needs."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from camfab.design import Design
    from camfab.export.part import Part
    from camfab.export.stl import StlFile


@dataclass(frozen=True)
class PartFiles:
    """A part's files by output name (``dxf``, ``svg``, ``stl``) and file name, and the STL as
    built (its volume and area), when one was made."""

    files: dict[str, dict[str, bytes]]
    stl: StlFile | None = None


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
    if "svg" in wanted:
        from camfab.export.svg import render_svg

        files["svg"] = {f"{stem}.svg": render_svg(design, cut, pocket)
                        for stem, (cut, pocket) in part.views.items()}
    return PartFiles(files, stl)
