"""The 3-D view's scene: the cam and its follower over the report's animation frames, as JSON for
the studio page (``static/view3d.js``), from the kind's scene (:meth:`CamKind.scene`,
:mod:`camfab.kinds.scene3d`).

The format (lengths in millimetres, in the coordinates of the STL files; every matrix is a 4×4
rigid transform as 16 numbers, row by row, mapping a body's frame into those coordinates)::

    {
      "frames": F,                      # the report animation's frames (its slider's steps)
      "angles_deg": [F numbers],        # the cam angle of each frame (deg)
      "units": "mm",
      "parts": [                        # one per STL file, in the order of the names given
        {"file": "NAME.stl", "matrices": [F matrices]}
      ],
      "follower": {
        "shapes": [                     # the follower's solids, in its frame
          {"type": "cylinder", "role": "roller", "radius": r, "length": l, "matrix": m},
          {"type": "box", "role": "stem", "x": ..., "y": ..., "z": ..., "matrix": m},
          {"type": "wedge", "role": "knife", "width": ..., "height": ..., "length": ...,
           "matrix": m},
          {"type": "cap", "role": "face", "radius": r, "angle": rad, "matrix": m}
        ],
        "matrices": [F matrices]        # the follower's frame at each frame
      },
      "axis": {"point": [x, y, z], "direction": [x, y, z], "motion": "turns" | "slides"},
      "bounds": {"min": [x, y, z], "max": [x, y, z]}   # holds everything over every frame
    }

A shape's own frame: a cylinder lies along its Z axis centred on its origin; a box is centred
on its origin, ``x``, ``y``, ``z`` long along its axes; a wedge (a knife) has its edge along its
Z axis through its origin and opens toward +Y, ``width`` wide at ``height``; a cap (a
mushroom's face) is the sphere of ``radius`` about its origin within ``angle`` of its −Y pole,
closed by the plane there. Rotations are rounded to :data:`ROTATION_DIGITS` decimals and
lengths to :data:`LENGTH_DIGITS` (mm): a 360-frame scene is some 70 kB.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.arrays import Array
    from camfab.kinds.scene3d import Scene3D, Shape

#: Decimals kept of a rotation's entries: 1e-6 turns a point 100 mm from the axis by 0.1 µm,
#: well inside any tolerance camfab writes to.
ROTATION_DIGITS = 6

#: Decimals kept of a length (mm): 0.1 µm.
LENGTH_DIGITS = 4


def scene_json(analysis: Analysis, stl_names: list[str]) -> dict[str, Any]:
    """The scene of *analysis* (a verified analysis, as a build returns it) for the page: its
    parts named by *stl_names* (the build's STL files, in order; none where it wrote none), the
    follower, the axis and the bounds, over the report animation's frames (see the module's
    docstring)."""
    from camfab.export.figures import frame_angles
    from camfab.kinds import kind_of

    design = analysis.design
    theta = frame_angles(design.table_step)
    scene = kind_of(design.cam.type).scene(analysis, theta)
    parts = [{"file": name, "matrices": matrices_json(matrices)}
             for name, matrices in zip(stl_names, scene.part_matrices, strict=False)]
    low, high = bounds(scene)
    return {
        "frames": int(theta.size),
        "angles_deg": np.round(np.degrees(theta), LENGTH_DIGITS).tolist(),
        "units": "mm",
        "parts": parts,
        "follower": {"shapes": [shape_json(shape) for shape in scene.follower_shapes],
                     "matrices": matrices_json(scene.follower_matrices)},
        "axis": {"point": _lengths(scene.axis[0]), "direction": _lengths(scene.axis[1]),
                 "motion": "slides" if scene.slides else "turns"},
        "bounds": {"min": _lengths(low), "max": _lengths(high)},
    }


def matrices_json(matrices: Array) -> list[list[float]]:
    """(..., 4, 4) transforms as lists of 16 numbers, row by row: rotations to
    :data:`ROTATION_DIGITS` decimals, translations (mm) to :data:`LENGTH_DIGITS`."""
    rounded = np.round(matrices, ROTATION_DIGITS)
    rounded[..., :3, 3] = np.round(matrices[..., :3, 3], LENGTH_DIGITS)
    rounded += 0.0  # no negative zeros
    flat: list[list[float]] = rounded.reshape(-1, 16).tolist()
    return flat


def shape_json(shape: Shape) -> dict[str, Any]:
    """A follower's solid: its type, role, named dimensions (mm; a cap's angle in rad) and its
    transform into the follower's frame."""
    from camfab.kinds.scene3d import DIM_NAMES

    dims = {name: round(float(value), LENGTH_DIGITS)
            for name, value in zip(DIM_NAMES[shape.kind], shape.dims, strict=True)}
    return {"type": shape.kind, "role": shape.role, **dims,
            "matrix": matrices_json(shape.matrix)[0]}


def bounds(scene: Scene3D) -> tuple[Array, Array]:
    """The least and greatest corners (mm) of a box holding the parts and the follower at every
    frame: the corners of each body's box moved by every frame's transform."""
    part = _corners(scene.extent)  # (8, 4)
    moved = [np.einsum("pfij,kj->pfki", scene.part_matrices, part)[..., :3].reshape(-1, 3)]
    for shape in scene.follower_shapes:
        local = _corners(shape_box(shape)) @ shape.matrix.T
        moved.append(np.einsum("fij,kj->fki", scene.follower_matrices, local)[..., :3]
                     .reshape(-1, 3))
    points = np.vstack(moved)
    return points.min(axis=0), points.max(axis=0)


def shape_box(shape: Shape) -> Array:
    """(2, 3) the least and greatest corners of a box holding *shape* in its own frame (mm)."""
    dims = shape.dims
    if shape.kind == "cylinder":
        half = np.array([dims[0], dims[0], dims[1] / 2.0])
    elif shape.kind == "box":
        half = np.asarray(dims, dtype=np.float64) / 2.0
    elif shape.kind == "wedge":
        return np.array([[-dims[0] / 2.0, 0.0, -dims[2] / 2.0],
                         [dims[0] / 2.0, dims[1], dims[2] / 2.0]])
    else:  # a cap round its −Y pole
        radius, angle = dims
        rim = radius * (np.sin(angle) if angle < np.pi / 2.0 else 1.0)
        return np.array([[-rim, -radius, -rim], [rim, -radius * np.cos(angle), rim]])
    return np.array([-half, half])


def _corners(box: Array) -> Array:
    """(8, 4) the corners of the box from *box* [0] to [1] (mm), as homogeneous points."""
    index = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    corners = box[index, [0, 1, 2]]
    return np.column_stack((corners, np.ones(8)))


def _lengths(values: Array) -> list[float]:
    """Lengths (mm) rounded to :data:`LENGTH_DIGITS` decimals."""
    rounded: list[float] = (np.round(np.asarray(values, dtype=np.float64), LENGTH_DIGITS)
                            + 0.0).tolist()
    return rounded
