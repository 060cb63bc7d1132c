"""A groove plate's drawing read as scan points: the two walls on its ``POCKET`` layer (a
camfab drawing's, or a CMM's section of the part traced into one), sampled densely at the
plate's mid-thickness, so that the groove is judged like a scan of it (the phase found as a
fixtured scan's: a drawing is in the cam's frame but may be turned)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camfab.errors import InspectionError
from camfab.inspect.scan import Scan

#: Spacing (mm) of the points sampled along the drawing's walls (chords of its arcs within a
#: micrometre).
DRAWING_SPACING_MM = 0.05


def drawing_scan(path: Path, thickness: float, units: str) -> Scan:
    """The groove's walls of the DXF *path* (its coordinates in *units* unless it says) as
    points at z = *thickness*/2 (mm).

    Raises
    ------
    InspectionError
        The file does not hold two closed contours on layer POCKET (which it names), or is no
        DXF a reader can open.
    """
    from camfab.export.dxf import read_dxf
    from camfab.export.outline import MAX_BYTES, UNITS_MM
    from camfab.files import read_bounded

    name = str(path)
    data = read_bounded(path, MAX_BYTES, "a DXF drawing")
    try:
        drawing = read_dxf(data, UNITS_MM[units])
    except Exception as exc:  # ezdxf's and the decoder's errors: the file is no DXF
        raise InspectionError(name, f"cannot be read as a DXF drawing ({type(exc).__name__})"
                              ) from None
    if len(drawing.pocket) < 2:
        raise InspectionError(name, f"holds {len(drawing.pocket)} closed contour(s) on layer "
                              "POCKET: a groove's drawing has its two walls there (the outer "
                              "and the inner)")
    points = []
    for wall in drawing.pocket[:2]:
        chain = wall.points(1e-3, split_lines=False)
        ring = np.vstack((chain, chain[:1]))
        step = np.linalg.norm(np.diff(ring, axis=0), axis=1)
        at = np.concatenate(([0.0], np.cumsum(step)))
        s = np.arange(0.0, at[-1], DRAWING_SPACING_MM)
        points.append(np.column_stack((np.interp(s, at, ring[:, 0]),
                                       np.interp(s, at, ring[:, 1]),
                                       np.full(s.size, 0.5 * thickness))))
    xyz = np.vstack(points)
    return Scan(xyz, None, None, f"the two walls on layer POCKET of a DXF drawing, sampled "
                f"every {DRAWING_SPACING_MM:g} mm at mid-thickness ({len(xyz):,} points)",
                f"{units}")
