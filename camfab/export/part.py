"""What a cam kind makes, as data the format writers serialise: a 2-D drawing per plate (DXF),
the contours to show at true size (SVG), and a solid (STL).

A :class:`Drawing` records lines, arcs, circles and text on camfab's layers in the file's units,
in the order they are drawn; :func:`camfab.export.dxf.render_dxf` writes them in that order. A
:data:`Solid` is a tree of extrusions, cylinders, revolutions, meshes and their booleans (mm);
:func:`camfab.export.stl.render_stl` builds it with manifold3d. The kinds (:mod:`camfab.kinds`)
describe their parts with these; the writers know formats, not kinds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.arrays import Array

if TYPE_CHECKING:
    from camfab.curves.profile import Profile
    from camfab.geometry.plate import Contours

#: Ends of lines and arcs closer than this (file units) meet, for the reader of the CUT layer:
#: an arc's ends are recomputed from its centre, radius and angles, which for a nearly straight
#: arc (radius 10⁶ × its chord) rounds them by about 1e-9.
READ_GAP = 1e-6

Point = tuple[float, float]


@dataclass(frozen=True)
class Line:
    """A LINE from *start* to *end* (file units)."""

    start: Point
    end: Point
    layer: str


@dataclass(frozen=True)
class Arc:
    """An ARC about *centre*, counter-clockwise from *start_deg* to *end_deg* (file units)."""

    centre: Point
    radius: float
    start_deg: float
    end_deg: float
    layer: str


@dataclass(frozen=True)
class Circle:
    """A CIRCLE (file units)."""

    centre: Point
    radius: float
    layer: str


@dataclass(frozen=True)
class Text:
    """A line of TEXT of *height* whose baseline starts *at* (file units)."""

    text: str
    height: float
    at: Point
    layer: str


Entity = Line | Arc | Circle | Text


@dataclass
class Drawing:
    """A plate's drawing in the design's *units* (``mm`` or ``in``): its entities in the order
    drawn (references first, what is cut last, so what is cut lies on top)."""

    units: str
    entities: list[Entity] = field(default_factory=list)

    def line(self, start: Point, end: Point, layer: str) -> None:
        self.entities.append(Line(start, end, layer))

    def circle(self, radius: float, layer: str, centre: Point = (0.0, 0.0)) -> None:
        self.entities.append(Circle(centre, radius, layer))

    def text(self, text: str, height: float, at: Point, layer: str = "NOTE") -> None:
        self.entities.append(Text(text, height, at, layer))

    def contour(self, profile: Profile, scale: float, layer: str, closed: bool = True) -> None:
        """A contour (mm, drawn × *scale*) as LINE and ARC entities meeting end to end (an open
        one without its closing edge).

        Not one LWPOLYLINE with bulges: OpenSCAD's DXF import (among others) drops the bulges
        and cuts chords, while every DXF reader takes lines and arcs, and CAD/CAM programs chain
        them into the closed contour.
        """
        if closed:
            profile = _readable(profile, READ_GAP / scale)
        v = profile.vertices * scale
        following = np.roll(v, -1, axis=0)
        arcs = profile.arcs()
        arc_at = {int(i): k for k, i in enumerate(arcs.index)}
        for i in range(len(v) if closed else len(v) - 1):
            k = arc_at.get(i)
            if k is None:
                self.entities.append(Line(tuple(v[i]), tuple(following[i]), layer))
                continue
            start = math.degrees(float(arcs.start_angle[k]))
            sweep = math.degrees(float(arcs.sweep[k]))
            low, high = (start, start + sweep) if sweep > 0 else (start + sweep, start)
            self.entities.append(Arc(tuple(arcs.centre[k] * scale), float(arcs.radius[k]) * scale,
                                     low, high, layer))

    def contours(self, contours: Contours, scale: float, layer: str) -> None:
        """Closed *contours* (mm): their profiles, then their circles about the cam centre."""
        for profile in contours.profiles:
            self.contour(profile, scale, layer)
        for radius in contours.circles:
            self.circle(radius * scale, layer)


def _readable(profile: Profile, gap: float) -> Profile:
    """*profile* without edges shorter than *gap* (mm): a reader drops them (a tiny nose arc),
    and the edges either side would no longer meet; the edge before now ends where the next
    begins, moved by at most the dropped edge's length."""
    from camfab.curves.profile import Profile

    v = profile.vertices
    keep = np.hypot(*(np.roll(v, -1, axis=0) - v).T) > gap
    if keep.all() or np.count_nonzero(keep) < 2:
        return profile
    return Profile(v[keep], profile.bulges[keep])


@dataclass(frozen=True)
class Extrusion:
    """The region of closed *chains* of (N, 2) points (mm; even-odd: the first the outline, the
    rest holes) extruded from z = 0 to *height*, then moved up by *z* (when given); with the
    same region *exact*ly, as the contours of lines and arcs the chains sample (or a circle's
    radius about the origin), for the writers of exact solids (STEP)."""

    chains: tuple[Array, ...]
    height: float
    z: float | None = None
    exact: tuple[Profile | float, ...] | None = None


@dataclass(frozen=True)
class Cylinder:
    """A cylinder along Z of *radius* from z = 0 to *height* as a polygon of *segments* sides,
    then moved up by *z* (when given)."""

    height: float
    radius: float
    segments: int
    z: float | None = None


@dataclass(frozen=True)
class Revolution:
    """The region of the closed chain *section* of (N, 2) points (r, z) (mm, r ≥ 0) revolved
    about Z as a polygon of *segments* sides; with the same section *exact*ly, as the contour of
    lines and arcs the chain samples, for the writers of exact solids (STEP)."""

    section: Array
    segments: int
    exact: Profile | None = None


@dataclass(frozen=True)
class Mesh:
    """A closed triangle mesh (mm): (V, 3) vertices and (F, 3) faces, outward; for the writers
    of exact solids (STEP), the same closed surface as *surfaces*, grids of points on it
    ((N, M, 3) each, closed round N: the last row joins the first; each grid's first and last
    columns the neighbouring grids' edges), to be interpolated by B-spline surfaces, and
    *probes*, (K, 3) points of the exact surface between the grids' points, to measure them
    by."""

    vertices: Array
    faces: Array
    surfaces: tuple[Array, ...] = ()
    probes: Array | None = None


@dataclass(frozen=True)
class Difference:
    """*body* less *cut* (*cut* built first when *cut_first*: the order manifold3d numbers
    its meshes in); with a *tolerance* (mm), both given it first (manifold3d's
    ``set_tolerance``: the boolean then merges what lies closer than it, rather than leaving
    the thin facets two curved tessellations make where their surfaces cross)."""

    body: Solid
    cut: Solid
    cut_first: bool = False
    tolerance: float | None = None


@dataclass(frozen=True)
class Union:
    """*parts* joined into one solid."""

    parts: tuple[Solid, ...]


Solid = Extrusion | Cylinder | Revolution | Mesh | Difference | Union


def pieces(solid: Solid) -> list[Extrusion | Cylinder | Revolution | Mesh]:
    """The pieces of *solid*'s tree (its extrusions, cylinders, revolutions and meshes), in
    order: each difference's body then its cut, each union's parts."""
    if isinstance(solid, Difference):
        return [*pieces(solid.body), *pieces(solid.cut)]
    if isinstance(solid, Union):
        return [piece for part in solid.parts for piece in pieces(part)]
    return [solid]


@dataclass(frozen=True)
class Part:
    """What a kind makes of one design: its drawings by file stem (``NAME``, or ``NAME-a`` and
    ``NAME-b`` for a pair of plates), the contours shown at true size by file stem (the CUT
    contours and a groove's POCKET walls), its solid (None without a thickness, or withheld),
    which outputs its read-back needs whether asked for or not, and why an output it cannot
    have is withheld."""

    drawings: dict[str, Drawing]
    views: dict[str, tuple[Contours, Contours | None]]
    solid: Solid | None = None
    needs: tuple[str, ...] = ("dxf",)
    withheld: dict[str, str] = field(default_factory=dict)
    #: The kind's own record of what it made, for its read-back (the plate's contours, ...).
    made: Any = None
