"""Drawings read as scan points: a groove plate's two walls on its ``POCKET`` layer, or a
conjugate pair's two plates (two drawings, their CUT outlines), sampled densely at each plate's
mid-thickness, so that they are judged like a scan of the part (the phase found as a fixtured
scan's: a drawing is in the cam's frame but may be turned)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from camfab.arrays import Array
from camfab.errors import InspectionError
from camfab.inspect.scan import Scan

if TYPE_CHECKING:
    from camfab.curves.profile import Profile
    from camfab.export.dxf import DrawingRead

#: Spacing (mm) of the points sampled along the drawing's walls (chords of its arcs within a
#: micrometre).
DRAWING_SPACING_MM = 0.05


def _ring_points(profile: Profile, z: float) -> Array:
    """(N, 3) points along the closed *profile* every :data:`DRAWING_SPACING_MM` at height
    *z* (mm)."""
    chain = profile.points(1e-3, split_lines=False)
    ring = np.vstack((chain, chain[:1]))
    step = np.linalg.norm(np.diff(ring, axis=0), axis=1)
    at = np.concatenate(([0.0], np.cumsum(step)))
    s = np.arange(0.0, at[-1], DRAWING_SPACING_MM)
    return np.column_stack((np.interp(s, at, ring[:, 0]), np.interp(s, at, ring[:, 1]),
                            np.full(s.size, z)))


def _drawing(path: Path, units: str) -> DrawingRead:
    """The DXF *path* read (mm), refused in one line if no reader can open it."""
    from camfab.export.dxf import read_dxf
    from camfab.export.outline import MAX_BYTES, UNITS_MM
    from camfab.files import read_bounded

    data = read_bounded(path, MAX_BYTES, "a DXF drawing")
    try:
        return read_dxf(data, UNITS_MM[units])
    except Exception as exc:  # ezdxf's and the decoder's errors: the file is no DXF
        raise InspectionError(str(path), f"cannot be read as a DXF drawing "
                              f"({type(exc).__name__})") from None


def pair_scan(path_a: Path, path_b: Path, thickness: float, units: str) -> Scan:
    """A conjugate pair's two drawings (camfab's ``NAME-a.dxf`` and ``NAME-b.dxf``: each
    plate's CUT outline, cam b's drawn in the frame it is made in) as points at each plate's
    mid-thickness in the pair's frame (plate a from z = 0, plate b on it).

    Raises
    ------
    InspectionError
        A drawing holds no closed contour on layer CUT (naming it), or cannot be read.
    """
    points = []
    for path, z in ((path_a, 0.5 * thickness), (path_b, 1.5 * thickness)):
        drawing = _drawing(path, units)
        if not drawing.cut_profiles:
            raise InspectionError(str(path), "holds no closed contour on layer CUT: a plate's "
                                  "drawing has its outline there")
        points.append(_ring_points(drawing.cut_profiles[0], z))
    xyz = np.vstack(points)
    return Scan(xyz, None, None, f"the CUT outlines of two DXF drawings (plate a, plate b), "
                f"sampled every {DRAWING_SPACING_MM:g} mm at each plate's mid-thickness "
                f"({len(xyz):,} points)", f"{units}")


def drawing_scan(path: Path, thickness: float, units: str) -> Scan:
    """The groove's walls of the DXF *path* (its coordinates in *units* unless it says) as
    points at z = *thickness*/2 (mm).

    Raises
    ------
    InspectionError
        The file does not hold two closed contours on layer POCKET (which it names), or is no
        DXF a reader can open.
    """
    name = str(path)
    drawing = _drawing(path, units)
    if len(drawing.pocket) < 2:
        raise InspectionError(name, f"holds {len(drawing.pocket)} closed contour(s) on layer "
                              "POCKET: a groove's drawing has its two walls there (the outer "
                              "and the inner)")
    xyz = np.vstack([_ring_points(wall, 0.5 * thickness) for wall in drawing.pocket[:2]])
    return Scan(xyz, None, None, f"the two walls on layer POCKET of a DXF drawing, sampled "
                f"every {DRAWING_SPACING_MM:g} mm at mid-thickness ({len(xyz):,} points)",
                f"{units}")
