"""The part's outline: a laser's kerf taken off, moved so the cam centre is the origin, and
checked (it encloses an area, does not cross itself and holds the centre)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camfab.errors import InspectionError
from camfab.inspect.values import length

if TYPE_CHECKING:
    from camfab.curves.profile import Profile
    from camfab.export.outline import Outline
    from camfab.inspect.options import InspectOptions

#: Tolerance of the shapely offset that takes a laser's kerf off a beam path (mm): a micrometre.
KERF_OFFSET_TOLERANCE_MM = 1e-3

#: Largest kerf (mm): a laser's is a few tenths of a millimetre, a plasma cutter's a few.
MAX_KERF_MM = 10.0

#: Most pairs of an outline's edges whose bounding boxes overlap (estimated from a sample of
#: its edges) for it to be checked for crossing itself: GEOS's test takes some 30 ns a pair. A
#: smooth outline's edges overlap only their neighbours' (200,000 points: some 600,000 pairs);
#: a star of long spikes, or points out of order, overlap thousands each.
MAX_OVERLAPS = 50_000_000

#: Edges sampled for that estimate.
OVERLAP_SAMPLES = 256

#: Most the direction of an outline may turn, in all (rad: 300 turns), for a kerf to be taken
#: off it. A beam's path is smooth (one turn, and a little more where it is concave); a jagged
#: one (the noise of a dense scan, random points) makes the offset's round joins cross each
#: other so often that it could take minutes.
MAX_KERF_TURNING = 600.0 * math.pi


def part_outline(options: InspectOptions, outline: Outline, units: str
                 ) -> tuple[Profile, float, str]:
    """The part's outline: a laser's beam path less kerf/2 (``--kerf``, or the kerf a camfab
    drawing's note declares)."""
    from camfab.geometry.plate import inside_kerf

    name = str(options.profile)
    if options.kerf is not None:
        kerf, what = length("--kerf", options.kerf, units), "--kerf"
        source = "--kerf"
    elif outline.kerf_note is not None:
        kerf = outline.kerf_note.kerf_mm(name)
        what = f"{name}: {outline.kerf_note.entity}: the note's kerf"
        source = "the drawing's note (CUT offset for a kerf)"
    else:
        return outline.profile, 0.0, "none"
    if not 0.0 <= kerf <= MAX_KERF_MM:
        raise InspectionError(what, f"must be from 0 to {MAX_KERF_MM:g} mm (got {kerf:g} mm)")
    if kerf == 0.0:
        return outline.profile, 0.0, source
    turning = _turning(outline.profile)
    if turning > MAX_KERF_TURNING:
        raise InspectionError(what, f"cannot be taken off an outline this jagged: its direction "
                              f"turns {turning / (2 * math.pi):,.0f} times round in all (at most "
                              f"{MAX_KERF_TURNING / (2 * math.pi):,.0f}); a beam's path is smooth")
    try:
        part = inside_kerf(outline.profile, kerf, KERF_OFFSET_TOLERANCE_MM, split_lines=False)
    except ValueError as exc:
        raise InspectionError(what, f"{exc} (kerf/2 is wider than the part)") from None
    return part.ccw(), kerf, source


def _turning(profile: Profile) -> float:
    """How far (rad) the direction of *profile* turns in all, one way or the other: 2π for a
    convex outline."""
    import numpy as np

    start, end = profile.normal_angles()
    corners = np.mod(start - np.roll(end, 1) + math.pi, 2.0 * math.pi) - math.pi
    return float(np.sum(np.abs(corners)) + np.sum(np.abs(profile.arcs().sweep)))


def centred(profile: Profile, centre: tuple[float, float], path: Path) -> Profile:
    """*profile* moved so *centre* is the origin; the centre must lie inside it."""
    import numpy as np

    from camfab.curves.profile import Profile as P
    from camfab.geometry.undercut import is_simple

    moved = P(profile.vertices - np.array(centre), profile.bulges)
    chain = moved.points(KERF_OFFSET_TOLERANCE_MM, split_lines=False)
    if len(np.unique(chain, axis=0)) < 3:
        raise InspectionError(str(path), "the outline encloses no area (fewer than three "
                              "distinct points)")
    overlaps = _overlapping_edges(chain)
    if overlaps > MAX_OVERLAPS:
        raise InspectionError(str(path), f"the outline is too jagged to check: its edges' boxes "
                              f"overlap in some {overlaps:.2g} pairs (at most {MAX_OVERLAPS:.2g}"
                              "); are the points in order along the outline?")
    if not is_simple(chain):
        raise InspectionError(str(path), "the outline crosses itself (are the points in order "
                              "along the outline?)")
    if not _inside(chain):
        raise InspectionError(str(path), f"the cam centre ({centre[0]:.6g}, {centre[1]:.6g}) mm "
                              "lies outside the outline; give it with --centre X,Y")
    return moved


def _overlapping_edges(chain: Any) -> float:
    """About how many pairs of the closed polyline *chain*'s edges have overlapping bounding
    boxes (the work of a test for self-crossing): counted for every so many edges
    (:data:`OVERLAP_SAMPLES` of them), scaled to all."""
    import numpy as np

    following = np.roll(chain, -1, axis=0)
    (x0, y0), (x1, y1) = np.minimum(chain, following).T, np.maximum(chain, following).T
    picked = np.arange(0, len(chain), max(1, len(chain) // OVERLAP_SAMPLES))
    count = 0
    for k in picked.tolist():
        count += int(np.count_nonzero((x0 <= x1[k]) & (x1 >= x0[k]) & (y0 <= y1[k])
                                      & (y1 >= y0[k])))
    return count / len(picked) * len(chain)


def _inside(chain: Any) -> bool:
    """True when the origin lies inside the closed polyline *chain* (even-odd rule)."""
    import numpy as np

    a, b = chain, np.roll(chain, -1, axis=0)
    straddles = (a[:, 1] > 0.0) != (b[:, 1] > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (0.0 - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(straddles & (x > 0.0)) % 2)
