"""Run by FreeCAD's ``freecadcmd`` (not by pytest): read the STEP file named by the environment's
CAMFAB_STEP with FreeCAD's Part module and print what FreeCAD finds on one line, after the
prefix ``CAMFAB``, as JSON."""

import json
import os

import Part  # FreeCAD's

shape = Part.Shape()
shape.read(os.environ["CAMFAB_STEP"])
found = {
    "valid": shape.isValid(),
    "volume": shape.Volume,
    "solids": len(shape.Solids),
    "closed": all(solid.isClosed() for solid in shape.Solids),
    "circles": sum(1 for edge in shape.Edges if type(edge.Curve).__name__ == "Circle"),
    "bsplines": sum(1 for edge in shape.Edges if "BSpline" in type(edge.Curve).__name__),
}
print("CAMFAB " + json.dumps(found))
