"""The contours of a disc-cam plate (mm): the part, what a laser or a cutter follows to make it.

The part is the cam outline fitted with lines and arcs plus the bore (a circle, or a contour with
its keyway). A laser's beam removes a kerf of material, so its path runs kerf/2 off the part on
the waste side: outside the outline and inside the holes. A milling cutter's centre runs a cutter
radius off the part the same way. Offsets of the outline and of keyway holes go through shapely
and are fitted with arcs again; a round bore stays a circle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.curves.profile import Profile
from camfab.design import Design
from camfab.geometry.disc_geometry import DiscGeometry
from camfab.geometry.offset import grow
from camfab.geometry.runs import fit_closed

#: Share of the sampling tolerance left to an offset's round joins and to the flattening of arcs
#: before an offset (:data:`~camfab.geometry.disc_geometry.PLATE_SAMPLING_SHARE` says the
#: whole budget).
OFFSET_SHARE = 0.25

#: The tolerance of the arcs fitted to a plate's sampled chain, as a multiple of the tolerance it
#: was sampled to: the arcs hold its chords (corners and jumps of curvature included) within
#: this, so they lie within ``1 + ARC_FACTOR`` sampling tolerances of the exact curve.
ARC_FACTOR = 2.0


@dataclass(frozen=True)
class Contours:
    """Closed contours (mm): profiles of lines and arcs, and circles about the cam centre given
    by their radii."""

    profiles: tuple[Profile, ...] = ()
    circles: tuple[float, ...] = ()

    def __len__(self) -> int:
        return len(self.profiles) + len(self.circles)

    @property
    def exact(self) -> tuple[Profile | float, ...]:
        """Every contour exactly: the profiles, then the circles' radii (an
        :attr:`~camfab.export.part.Extrusion.exact`'s holes)."""
        return (*self.profiles, *self.circles)


@dataclass(frozen=True)
class Plate:
    """A disc-cam plate's contours (mm).

    Attributes
    ----------
    outline
        The cam outline of the part, fitted with lines and arcs.
    holes
        The part's bore (with its keyway).
    cut
        What is written on ``CUT``: the outline and the holes offset kerf/2 away from the material.
    toolpath
        The centre path of a milling cutter around the outline and inside the holes (None without
        ``cutter_radius``); a hole the cutter does not fit in has none.
    kerf
        The laser's kerf (mm, 0 for none).
    """

    outline: Profile
    holes: Contours
    cut: Contours
    toolpath: Contours | None
    kerf: float


def bore_contour(diameter: float, keyway: tuple[float, float] | None) -> Profile | None:
    """The bore as a closed contour (mm): None for a plain round bore (a circle), or the circle
    with a keyway of (width, depth) cut on +Y, the depth measured from the bore's top."""
    if keyway is None:
        return None
    r = diameter / 2.0
    width, depth = keyway
    half = width / 2.0
    foot = math.sqrt(max(r * r - half * half, 0.0))
    top = r + depth
    # around the hole: up the keyway's right side, across, down its left side, round the bottom
    # of the bore back to the start in two arcs (each under half a circle)
    sweep = 2.0 * math.pi - 2.0 * math.asin(min(half / r, 1.0))
    vertices = np.array([[half, foot], [half, top], [-half, top], [-half, foot], [0.0, -r]])
    bulge = math.tan(sweep / 8.0)
    return Profile(vertices, np.array([0.0, 0.0, 0.0, bulge, bulge]))


def holes(design: Design) -> Contours:
    """The bore (and keyway) of the part."""
    cam = design.cam
    if cam.bore is None:
        return Contours()
    keyway = None if cam.keyway is None else (cam.keyway.width, cam.keyway.depth)
    hole = bore_contour(cam.bore, keyway)
    if hole is None:
        return Contours(circles=(cam.bore / 2.0,))
    return Contours(profiles=(hole,))


def fit_chain(points: np.ndarray, tolerance: float, corners: np.ndarray | None = None) -> Profile:
    """The closed chain *points* (mm), sampled within *tolerance* (mm) of a curve, as lines and
    arcs holding its chords within :data:`ARC_FACTOR` times that, none across a vertex marked
    in the mask *corners* (a trimmed cam's corners)."""
    if corners is None:
        corners = np.zeros(len(points), dtype=bool)
    return fit_closed(points, corners, ARC_FACTOR * tolerance, chords=True)


def offset_outline(points: np.ndarray, distance: float, tolerance: float) -> Profile:
    """The outline through *points* (mm, sampled within *tolerance*, mm) grown by *distance*
    (mm), fitted with :func:`fit_chain`."""
    grown = grow(points, distance, OFFSET_SHARE * tolerance)
    return fit_chain(max(grown, key=len), tolerance)


def offset_holes(part: Contours, distance: float, tolerance: float) -> Contours:
    """The holes shrunk by *distance* (mm), which a beam or cutter of that radius follows inside
    them; a hole that vanishes is dropped."""
    circles = tuple(r - distance for r in part.circles if r - distance > 0.0)
    profiles = []
    for hole in part.profiles:
        flat = hole.points(OFFSET_SHARE * tolerance)
        for ring in grow(flat, -distance, OFFSET_SHARE * tolerance):
            profiles.append(fit_chain(ring, tolerance))
    return Contours(tuple(profiles), circles)


def plate(design: Design, geom: DiscGeometry) -> Plate:
    """The plate's contours: the part, the kerf-compensated CUT contours and the toolpath."""
    tolerance = geom.tolerance
    outline = (geom.profile if geom.exact
               else fit_chain(geom.profile.vertices, tolerance, geom.corners))

    def around(distance: float) -> Profile:
        """The outline grown by *distance*: exactly for an exact outline of lines and arcs
        meeting tangentially, through shapely and an arc fit otherwise."""
        if geom.exact:
            try:
                return outline.offset(distance)
            except ValueError:  # a corner of rounding (a lift of picometres): as a fitted one
                return offset_outline(outline.points(OFFSET_SHARE * tolerance), distance,
                                      tolerance)
        return offset_outline(geom.profile.vertices, distance, tolerance)

    part_holes = holes(design)
    kerf = design.manufacturing.kerf
    cut = Contours((outline, *part_holes.profiles), part_holes.circles)
    if kerf > 0.0:
        beam = offset_holes(part_holes, kerf / 2.0, tolerance)
        cut = Contours((around(kerf / 2.0), *beam.profiles), beam.circles)
    toolpath = None
    cutter = design.manufacturing.cutter_radius
    if cutter > 0.0:
        inside = offset_holes(part_holes, cutter, tolerance)
        toolpath = Contours((around(cutter), *inside.profiles), inside.circles)
    return Plate(outline, part_holes, cut, toolpath, kerf)


def inside_kerf(beam: Profile, kerf: float, tolerance: float, split_lines: bool = True
                ) -> Profile:
    """The part a beam following the outline *beam* (mm) leaves: the region shrunk by kerf/2,
    as a contour of lines within *tolerance* (mm) of the exact offset (its lines cut as finely
    as its arcs unless *split_lines* is False: see :meth:`Profile.points`).

    Raises
    ------
    ValueError
        Nothing is left: kerf/2 is wider than the region.
    """
    share = OFFSET_SHARE * tolerance
    rings = grow(beam.points(share, split_lines), -kerf / 2.0, share)
    if not rings:
        raise ValueError(f"a kerf of {kerf:g} mm leaves nothing of the outline")
    return Profile.from_points(max(rings, key=len))
