"""Run by FreeCAD's ``freecadcmd`` (not by pytest): read each STEP file named by the environment's
CAMFAB_STEP (several joined by the path separator: one FreeCAD start for them all) and print what
FreeCAD finds on one line per file, after the prefix ``CAMFAB``, as JSON.

For each file: what its Part module reads (the shape's validity, volume, solids, circles and
B-splines among its edges) and, when CAMFAB_FULL_CHECK is set, what its full check
(``shape.check(True)``: OpenCASCADE's BOP argument check, curves on their surfaces included) says
of each solid, None when it passes; when CAMFAB_IMPORT is set, the objects FreeCAD's Import
module (its File > Open of a STEP file) makes of it, by label, type and solids. Run it with HOME
set to a scratch folder: the Import module's preferences are set there, not in the user's."""

import json
import os

import FreeCAD  # FreeCAD's
import Import
import Part


def full_check(shape):  # type: ignore[no-untyped-def]
    """None when *shape* passes FreeCAD's full check, else FreeCAD's message."""
    try:
        shape.check(True)
    except Exception as error:  # FreeCAD raises its own ValueError-like error, with the findings
        return " | ".join(str(error).splitlines())[:2000]
    return None


def imported(path):  # type: ignore[no-untyped-def]
    """The objects FreeCAD's Import module makes of the file: (label, type, solids)."""
    # link groups make freecadcmd crash without its GUI; plain objects carry the same names
    preferences = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Import")
    preferences.SetBool("UseLinkGroup", False)
    document = FreeCAD.newDocument("camfab")
    try:
        Import.insert(path, document.Name)
        return [(item.Label, item.TypeId,
                 len(item.Shape.Solids) if hasattr(item, "Shape") else None)
                for item in document.Objects if not item.TypeId.startswith("App::Origin")
                and item.TypeId not in ("App::Line", "App::Plane")]
    finally:
        FreeCAD.closeDocument(document.Name)


for path in os.environ["CAMFAB_STEP"].split(os.pathsep):
    shape = Part.Shape()
    shape.read(path)
    found = {
        "file": os.path.basename(path),
        "valid": shape.isValid(),
        "volume": shape.Volume,
        "solids": len(shape.Solids),
        "closed": all(solid.isClosed() for solid in shape.Solids),
        "circles": sum(1 for edge in shape.Edges if type(edge.Curve).__name__ == "Circle"),
        "bsplines": sum(1 for edge in shape.Edges if "BSpline" in type(edge.Curve).__name__),
    }
    if os.environ.get("CAMFAB_FULL_CHECK"):
        found["full_check"] = [full_check(solid) for solid in shape.Solids]
    if os.environ.get("CAMFAB_IMPORT"):
        found["objects"] = imported(path)
    print("CAMFAB " + json.dumps(found), flush=True)
