"""An independent check of a plate's machining program by another library: OpenCAMLib's
waterline of the plate's STL — where the centre of a flat end mill of the program's diameter
stands when it touches the solid, at half the plate's thickness — against the tool centre's path
at full depth as LinuxCNC's rs274 makes it from the program (after its own cutter
compensation, or the program's own path).

The two agree to within twice the tolerance (the STL's facets and the program's arcs each lie
within it of the exact cam): the finishing pass runs on the waterline, and no point of any pass
puts the tool into the part's section."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from camfab.pipeline import analyse, design_from_mapping, render

from .conftest import DESIGNS
from .rs274 import interpret

#: The tool (mm) and the spacing of OpenCAMLib's fibres and of the samples of rs274's moves
#: (mm): fine enough that neither adds more than a tenth of the bound.
TOOL_MM = 6.0
FIBRES_MM = 0.25
SAMPLES_MM = 0.002


@pytest.mark.parametrize("compensation", ["control", "path"])
def test_the_waterline_of_the_stl_is_the_programs_tool_centre_path(compensation: str,
                                                                   tmp_path: Path) -> None:
    ocl = pytest.importorskip("opencamlib")
    shapely = pytest.importorskip("shapely")
    from scipy.spatial import cKDTree

    path = DESIGNS / "seed-10-4.yaml"
    data = yaml.safe_load(path.read_text())
    data = {**data, "outputs": ["stl", "gcode"],
            "machining": {"tool_diameter": TOOL_MM, "feed": 600, "cut_length": 20,
                          "compensation": compensation}}
    design = design_from_mapping(data, str(path), path.parent)
    files = render(analyse(design, advice=False)).files
    stl = tmp_path / "plate.stl"
    stl.write_bytes(files[f"{design.name}.stl"])
    thickness = design.cam.thickness
    assert thickness is not None
    bound = 2 * design.manufacturing.tolerance

    moves = interpret(files[f"{design.name}.ngc"], {1: TOOL_MM}, tmp_path / "rs274")
    points = moves.cutting().sample(SAMPLES_MM)
    through = points[points[:, 2] <= -thickness + 1e-9]  # the passes at full depth
    assert len(through), "no pass reaches the plate's bottom"

    surface = ocl.STLSurf()
    ocl.STLReader(str(stl), surface)
    waterline = ocl.Waterline()
    waterline.setSTL(surface)
    waterline.setCutter(ocl.CylCutter(TOOL_MM, 2 * thickness))
    waterline.setZ(thickness / 2)  # (the STL stands on z = 0; the program's top face is Z0)
    waterline.setSampling(FIBRES_MM)
    waterline.run()
    loops = [np.array([[p.x, p.y] for p in loop]) for loop in waterline.getLoops()]
    assert len(loops) == 2, "the outline's loop and the bore's"

    # every point of the waterline has the program's tool centre on it
    near, _ = cKDTree(through[:, :2]).query(np.concatenate(loops))
    assert near.max() <= bound, near.max()
    # and no point of the program's, in the material, puts the tool into the part: its
    # centre is never nearer than the tool's radius to the STL's section (trimesh's, the
    # facets cut at mid-thickness: a polygon, where the waterline's fibres only sample it)
    import trimesh

    mesh = trimesh.load_mesh(stl)
    lines = trimesh.intersections.mesh_plane(mesh, [0, 0, 1], [0, 0, thickness / 2])
    section = shapely.STRtree(shapely.linestrings(lines[:, :, :2]))
    xy = points[points[:, 2] < 0.0][:, :2]
    _, gap = section.query_nearest(shapely.points(xy), return_distance=True, all_matches=False)
    assert gap.min() >= TOOL_MM / 2 - bound, TOOL_MM / 2 - gap.min()
