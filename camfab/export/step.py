"""``NAME.step``: the part as exact solids for CAD and CAM (AP214, millimetres), written with
the OpenCASCADE bindings of the optional ``step`` extra (``pip install 'camfab[step]'``), and
read back.

The solid is the part's own tree (:mod:`camfab.export.part`) built exactly: an extrusion from the
lines and arcs of its contours (each line a plane, each arc a cylindrical face with a true
circular edge; a circle a cylinder), a revolution from the lines and arcs of its section (a
globoid's blank), a cylinder as a cylinder, differences as booleans, and the plates of a union
as one solid each; a mesh that carries grids of its exact surface's points (a drum's or a
globoid's groove) as cubic B-spline surfaces through them, sewn into one solid, each edge on its
faces to well under a STEP reader's 1e-7 mm (:mod:`camfab.export.step_surfaces`), measured against
probes of the exact surface. A mesh without them, or an extrusion or a revolution of sampled
points only, has no exact form here: the part gets no STEP, and the build says why.

Each solid is a product named for the part: ``NAME``, or a pair's two plates ``NAME-a`` and
``NAME-b`` in an assembly ``NAME``, so that CAD programs list them by name. The file's header
carries no clock time (a fixed stamp), so a design gives the same bytes every build;
OpenCASCADE's progress messages are silenced.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camfab.analysis.verification import StepCheck
from camfab.export.part import (
    Cylinder,
    Difference,
    Extrusion,
    Mesh,
    Revolution,
    Solid,
    Union,
    pieces,
)
from camfab.export.step_surfaces import NotExact

if TYPE_CHECKING:
    from camfab.arrays import Array
    from camfab.curves.profile import Profile

#: The stamp in the header's FILE_NAME: no clock time, so the bytes repeat.
TIME_STAMP = "2000-01-01T00:00:00"
#: The read-back measures a grid of this many points each way over each face's parameters.
FACE_GRID = 5
#: The relative precision to which the read-back's volume is integrated.
VOLUME_PRECISION = 1e-6
#: The points each way of a fitted surface's parameters from the nearest of which a probe's
#: point on it is first looked for (count): a few per patch of the groove's stations, enough
#: for Newton's steps to find the point beside the probe.
SURFACE_GRID = 48
#: How far (mm) below the largest distance found a probe's bound must fall before it is left
#: unprojected: far above the rounding of the distances (some 1e-14 mm), far below any
#: deviation the check reports.
PROBE_SLACK_MM = 1e-9


@dataclass(frozen=True)
class StepFile:
    """A part written as STEP: its bytes, how many solids it holds, its exact volume (mm³)
    from the contours' areas (None for a part with fitted surfaces), and whether it has
    fitted (B-spline) surfaces."""

    data: bytes
    solids: int
    volume_mm3: float | None
    curved: bool


def render_step(solid: Solid, name: str) -> StepFile:
    """*solid* (mm) as AP214 STEP bytes, its product named *name* (raises :class:`NotExact`
    before OpenCASCADE is imported)."""
    _exact(solid)
    shapes = [_shape(part) for part in _parts(solid)]
    curved = _curved(solid)
    if curved:  # the edges where the fitted faces meet the exact ones, on both
        from camfab.export.step_surfaces import meet_exactly

        for shape in shapes:
            meet_exactly(shape)
    try:
        volume: float | None = _volume(solid)
    except NotExact:
        volume = None
    return StepFile(_written(shapes, name, curved), len(shapes), volume, curved)


def _curved(solid: Solid) -> bool:
    """Whether the tree holds surfaces fitted through points (a mesh's)."""
    return any(isinstance(piece, Mesh) and bool(piece.surfaces) for piece in pieces(solid))


def _exact(solid: Solid) -> None:
    """Raise :class:`NotExact` for a tree holding a piece with no exact form."""
    for piece in pieces(solid):
        if isinstance(piece, Extrusion) and piece.exact is None:
            raise NotExact("an extrusion of sampled points only")
        if isinstance(piece, Mesh) and not piece.surfaces:
            raise NotExact("a mesh")
        if isinstance(piece, Revolution) and piece.exact is None:
            raise NotExact("a revolved section of sampled points")


def _parts(solid: Solid) -> list[Solid]:
    """The solids a STEP file holds one each: the plates of a union, or the whole."""
    return list(solid.parts) if isinstance(solid, Union) else [solid]


def _quiet() -> None:
    """OpenCASCADE's messages off (its transfer statistics go to standard output)."""
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


def _shape(solid: Solid) -> Any:
    """*solid* as an OpenCASCADE shape, exactly (its pieces' exact forms, which :func:`_exact`
    has found there)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder

    if isinstance(solid, Extrusion):
        assert solid.exact is not None
        return _extrusion(solid.exact, solid.height, solid.z or 0.0)
    if isinstance(solid, Cylinder):
        return _moved(BRepPrimAPI_MakeCylinder(solid.radius, solid.height).Shape(),
                      solid.z or 0.0)
    if isinstance(solid, Difference):
        return BRepAlgoAPI_Cut(_shape(solid.body), _shape(solid.cut)).Shape()
    if isinstance(solid, Union):
        shapes = [_shape(part) for part in solid.parts]
        fused = shapes[0]
        for shape in shapes[1:]:
            fused = BRepAlgoAPI_Fuse(fused, shape).Shape()
        return fused
    if isinstance(solid, Mesh):
        from camfab.export.step_surfaces import fitted_solid

        return fitted_solid(solid.surfaces)
    assert solid.exact is not None
    return _revolved(solid.exact)


def _signed_volume(shape: Any, precise: bool = False) -> float:
    """The volume (mm³) of *shape*, negative for a solid inside out; *precise*ly, integrated
    adaptively to :data:`VOLUME_PRECISION` (OpenCASCADE's default fixed-order integration,
    some 50 times faster, does not see a surface's loops between its knots)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    if precise:
        BRepGProp.VolumeProperties_s(shape, props, VOLUME_PRECISION)
    else:
        BRepGProp.VolumeProperties_s(shape, props)
    return float(props.Mass())


def _revolved(section: Profile) -> Any:
    """A closed (r, z) section (mm) in the plane y = 0, revolved a full turn about Z."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeRevol
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt

    face = BRepBuilderAPI_MakeFace(_wire(section, meridian=True)).Face()
    axis = gp_Ax1(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0))
    return BRepPrimAPI_MakeRevol(face, axis, 2.0 * math.pi).Shape()


def _extrusion(region: tuple[Profile | float, ...], height: float, z: float) -> Any:
    """The region's outline extruded from *z* up *height* (mm), each hole cut through."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut

    outline, *holes = region
    shape = _moved(_prism(outline, height), z)
    for hole in holes:  # through the plate, a millimetre beyond each face
        shape = BRepAlgoAPI_Cut(shape, _moved(_prism(hole, height + 2.0), z - 1.0)).Shape()
    return shape


def _prism(contour: Profile | float, height: float) -> Any:
    """A closed contour (or a circle's radius about the origin) as a face at z = 0, extruded
    up *height* (mm)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Vec

    face = BRepBuilderAPI_MakeFace(_wire(contour)).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(0.0, 0.0, height)).Shape()


def _wire(contour: Profile | float, meridian: bool = False) -> Any:
    """A closed contour's wire at z = 0 (or, *meridian*, its (r, z) in the plane y = 0): a LINE
    edge per line, a circular arc through the arc's middle per arc (its bulge), or one full
    circle."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.GC import GC_MakeArcOfCircle
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt

    wire = BRepBuilderAPI_MakeWire()
    if isinstance(contour, float):
        circle = gp_Circ(gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0)), contour)
        wire.Add(BRepBuilderAPI_MakeEdge(circle).Edge())
        return wire.Wire()
    start = contour.vertices
    end = np.roll(start, -1, axis=0)
    middle = _arc_middles(start, end, contour.bulges)

    def point(xy: Array) -> Any:
        x, y = float(xy[0]), float(xy[1])
        return gp_Pnt(x, 0.0, y) if meridian else gp_Pnt(x, y, 0.0)

    for a, b, m, bulge in zip(start, end, middle, contour.bulges, strict=True):
        if bulge == 0.0:
            wire.Add(BRepBuilderAPI_MakeEdge(point(a), point(b)).Edge())
        else:
            arc = GC_MakeArcOfCircle(point(a), point(m), point(b)).Value()
            wire.Add(BRepBuilderAPI_MakeEdge(arc).Edge())
    return wire.Wire()


def _arc_middles(start: Array, end: Array, bulges: Array) -> Array:
    """The middle of each edge's arc (mm): the chord's middle moved off it by the sagitta
    b·c/2 (b the bulge, c the chord), to the right of the chord for a counter-clockwise arc."""
    chord = end - start
    right = np.stack((chord[:, 1], -chord[:, 0]), axis=1)
    return 0.5 * (start + end) + 0.5 * bulges[:, None] * right


def _moved(shape: Any, z: float) -> Any:
    """*shape* moved up *z* (mm)."""
    if z == 0.0:
        return shape
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Trsf, gp_Vec

    move = gp_Trsf()
    move.SetTranslation(gp_Vec(0.0, 0.0, z))
    return BRepBuilderAPI_Transform(shape, move, True).Shape()


def _written(shapes: list[Any], name: str, pcurves: bool = False) -> bytes:
    """*shapes* as one AP214 STEP file in millimetres, each a product named for its part
    (:func:`_names`; a pair's two under an assembly named *name*), with a fixed header, and
    with the edges' curves on their faces (pcurves) only for fitted surfaces (*pcurves*): a
    reader computes those on a plane or a cylinder exactly itself (OpenCASCADE writes them as
    B-splines, which would more than double a plate's file), but approximates those on a fitted
    surface or a revolved arc to 1e-7 mm or worse, more than it then allows the edge (see
    :mod:`camfab.export.step_surfaces`)."""
    import io

    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.Interface import Interface_Static
    from OCP.STEPCAFControl import STEPCAFControl_Writer
    from OCP.STEPControl import STEPControl_AsIs
    from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
    from OCP.TDataStd import TDataStd_Name
    from OCP.TDocStd import TDocStd_Document
    from OCP.TopLoc import TopLoc_Location
    from OCP.XCAFDoc import XCAFDoc_DocumentTool

    def named(label: Any, text: str) -> Any:
        TDataStd_Name.Set_s(label, TCollection_ExtendedString(text))
        return label

    _quiet()
    document = TDocStd_Document(TCollection_ExtendedString("camfab"))
    tool = XCAFDoc_DocumentTool.ShapeTool_s(document.Main())
    names = _names(name, len(shapes))
    parts = [named(tool.AddShape(shape, False), part)
             for shape, part in zip(shapes, names, strict=True)]
    if len(parts) > 1:
        assembly = named(tool.NewShape(), name)
        for part, called in zip(parts, names, strict=True):
            named(tool.AddComponent(assembly, part, TopLoc_Location()), called)
        tool.UpdateAssemblies()
    writer = STEPCAFControl_Writer()  # (sets the translator's parameters up first)
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    Interface_Static.SetIVal_s("write.surfacecurve.mode", 1 if pcurves else 0)
    writer.SetNameMode(True)
    if not writer.Transfer(document, STEPControl_AsIs):
        raise RuntimeError("OpenCASCADE could not translate the part to STEP")
    header = APIHeaderSection_MakeHeader(writer.ChangeWriter().Model())
    header.SetName(TCollection_HAsciiString(name))
    header.SetTimeStamp(TCollection_HAsciiString(TIME_STAMP))
    for text, setter in (("camfab", header.SetOriginatingSystem),
                         ("camfab", header.SetPreprocessorVersion)):
        setter(TCollection_HAsciiString(text))
    header.SetAuthorValue(1, TCollection_HAsciiString("camfab"))
    header.SetOrganizationValue(1, TCollection_HAsciiString("camfab"))
    stream = io.BytesIO()
    if writer.ChangeWriter().WriteStream(stream) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise RuntimeError("OpenCASCADE could not write the STEP file")
    return _occurrences_numbered(stream.getvalue())


def _occurrences_numbered(data: bytes) -> bytes:
    """*data* with the assembly's occurrences numbered 1, 2… in the file's order instead of by
    OpenCASCADE's counter, which runs on through the process and would make each build's bytes
    differ."""
    import re

    numbers = itertools.count(1)
    return re.sub(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('[^']*'",
                  lambda _: b"NEXT_ASSEMBLY_USAGE_OCCURRENCE('%d'" % next(numbers), data)


def _names(name: str, count: int) -> list[str]:
    """The products' names: *name* for one solid, ``NAME-a``, ``NAME-b``… for a pair's."""
    return [name] if count == 1 else [f"{name}-{chr(ord('a') + i)}" for i in range(count)]


def _volume(solid: Solid) -> float:
    """The exact volume (mm³) of *solid* from its contours' areas (arcs included): an
    extrusion's area × height, a cylinder's, a union's plates summed, a difference's body less
    the cut's area over the height it shares with the body (a pocket inside the plate)."""
    if isinstance(solid, Extrusion):
        assert solid.exact is not None
        return _area(solid.exact) * solid.height
    if isinstance(solid, Cylinder):
        return math.pi * solid.radius**2 * solid.height
    if isinstance(solid, Difference) and isinstance(solid.cut, Cylinder):
        # a bore through a cylinder
        return _volume(solid.body) - math.pi * solid.cut.radius**2 * _height(solid.body)
    if isinstance(solid, Union):
        return sum(_volume(part) for part in solid.parts)
    if isinstance(solid, Difference) and isinstance(solid.cut, Extrusion) \
            and isinstance(solid.body, Extrusion):
        assert solid.cut.exact is not None
        low = max(solid.body.z or 0.0, solid.cut.z or 0.0)
        high = min((solid.body.z or 0.0) + solid.body.height,
                   (solid.cut.z or 0.0) + solid.cut.height)
        return _volume(solid.body) - _area(solid.cut.exact) * max(high - low, 0.0)
    raise NotExact(type(solid).__name__)


def _height(solid: Solid) -> float:
    if isinstance(solid, (Extrusion, Cylinder)):
        return solid.height
    raise NotExact(type(solid).__name__)


def _area(region: tuple[Profile | float, ...]) -> float:
    """The area (mm²) of an outline less its holes."""
    areas = [math.pi * c * c if isinstance(c, float) else c.area for c in region]
    return areas[0] - sum(areas[1:])


def check_step(step: StepFile, solid: Solid, tolerance: float,
               measured: tuple[float, float] | None = None) -> StepCheck:
    """*step* read back (its bytes, as a CAD program would) and held to *solid* (mm), its volume
    within *tolerance* (mm) over the surface of the exact one, or, for a part with fitted
    surfaces (no exact volume), of the *measured* one (the STL's volume, mm³, and how far that
    may be off it): see :class:`StepCheck`."""
    import re

    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    shape = read_step(step.data)
    area = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shape, area)
    text = step.data.decode("ascii", errors="replace")
    allowance = tolerance * float(area.Mass())
    expected = step.volume_mm3
    if expected is None:
        assert measured is not None, "a part with fitted surfaces is held to its STL's volume"
        expected, allowance = measured[0], allowance + measured[1]
    return StepCheck(
        solids=_count_solids(shape),
        expected_solids=step.solids,
        valid=bool(BRepCheck_Analyzer(shape).IsValid()),
        volume_mm3=_signed_volume(shape, precise=True),
        expected_volume_mm3=expected,
        volume_allowance_mm3=allowance,
        deviation_mm=_deviation(shape, solid),
        tolerance_mm=tolerance,
        circles=len(re.findall(r"=\s*CIRCLE\(", text)),
        cylinders=len(re.findall(r"=\s*CYLINDRICAL_SURFACE\(", text)),
        b_splines=len(re.findall(r"B_SPLINE", text)),
        fitted=step.curved,
    )


def read_step(data: bytes) -> Any:
    """The shape of STEP *data*, read by OpenCASCADE's reader (raises ValueError)."""
    import io

    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.STEPControl import STEPControl_Reader

    _quiet()
    reader = STEPControl_Reader()
    if reader.ReadStream("part.step", io.BytesIO(data)) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise ValueError("OpenCASCADE cannot read the STEP file")
    reader.TransferRoots()
    return reader.OneShape()


def _count_solids(shape: Any) -> int:
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    explorer = TopExp_Explorer(shape, TopAbs_SOLID)
    count = 0
    while explorer.More():
        count += 1
        explorer.Next()
    return count


def _deviation(shape: Any, solid: Solid) -> float:
    """The largest distance (mm) of the shape's faces from the part's exact surfaces: on each
    face a grid of points over its parameters, a flat face's against the nearest of the part's
    planes (along Z), a side face's against the nearest contour of the part (across, in
    plan)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepTools import BRepTools
    from OCP.GeomAbs import GeomAbs_SurfaceType
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    planes = np.array(sorted(_planes(solid)))
    worst = 0.0
    fitted = []
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    grid = np.linspace(0.0, 1.0, FACE_GRID)
    while explorer.More():
        face = TopoDS.Face(explorer.Current())
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        surface = BRepAdaptor_Surface(face)
        if surface.GetType() == GeomAbs_SurfaceType.GeomAbs_BSplineSurface:
            fitted.append(face)  # measured by the probes of the exact surface, below
            explorer.Next()
            continue
        xyz = np.array([surface.Value(u0 + a * (u1 - u0), v0 + b * (v1 - v0)).Coord()
                        for a in grid for b in grid])
        if float(np.ptp(xyz[:, 2])) <= 1e-9:  # a flat face square to Z
            worst = max(worst, float(np.min(np.abs(planes - xyz[0, 2]))))
        else:
            worst = max(worst, float(np.max(_contour_distance(solid, xyz))))
        explorer.Next()
    probes = _probes(solid)
    if fitted and probes.size:
        worst = max(worst, _probe_distance(fitted, probes))
    return worst


def _probes(solid: Solid) -> Array:
    """The exact surface's probes of the tree's meshes (mm)."""
    found = [piece.probes for piece in pieces(solid)
             if isinstance(piece, Mesh) and piece.probes is not None]
    return np.concatenate(found) if found else np.zeros((0, 3))


def _probe_distance(faces: list[Any], probes: Array) -> float:
    """The largest distance (mm) of the *probes* (points of the exact surface) from the
    nearest of the fitted *faces*, each projected onto their surfaces; only the probes the
    part keeps are found near a face (a wall's stretch beyond the drum's surface is cut away
    with the face's), so each probe's distance is the least over the faces.

    OpenCASCADE's projection (its search over the whole surface for the nearest point) is
    asked only for the probes that can be the farthest: each probe's distance is first bounded
    above by a point of each face's surface found near it (Newton's steps from the nearest of
    a grid of the surface's points), and the probes are projected from the highest bound down
    until no bound left exceeds the largest distance found (by :data:`PROBE_SLACK_MM`). The
    answer is the projection's, as if every probe were projected: the projection finds the
    surface's nearest point, nearer than any other of its points but by its rounding."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRep import BRep_Tool
    from OCP.BRepBndLib import BRepBndLib
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf

    projections, boxes, surfaces = [], [], []
    for face in faces:
        box = Bnd_Box()
        BRepBndLib.Add_s(face, box)
        surface = BRep_Tool.Surface_s(face)
        projection = GeomAPI_ProjectPointOnSurf()  # its search grid made once per face
        projection.Init(surface, *surface.Bounds())
        projections.append(projection)
        surfaces.append(surface)
        boxes.append(np.array([box.CornerMin().Coord(), box.CornerMax().Coord()]))
    # the faces within a millimetre of each probe
    near = np.array([((box[0] - 1.0 <= probes) & (probes <= box[1] + 1.0)).all(axis=1)
                     for box in boxes]).reshape(len(faces), len(probes))
    bound = np.full(len(probes), math.inf)
    for surface, on in zip(surfaces, near, strict=True):
        rows = np.flatnonzero(on)
        if rows.size:
            bound[rows] = np.minimum(bound[rows], _local_distances(surface, probes[rows]))

    worst = 0.0
    for index in np.argsort(-bound, kind="stable"):
        if bound[index] + PROBE_SLACK_MM <= worst:
            break  # no probe left can lie farther
        worst = max(worst, _projected(projections, near[:, index], probes[index]))
    return worst


def _projected(projections: list[Any], near: Array, probe: Array) -> float:
    """The least distance (mm) of *probe* from the faces *near* it (a mask), by their
    surfaces' *projections* (inf where none finds it)."""
    from OCP.gp import gp_Pnt

    x, y, z = probe
    point = gp_Pnt(float(x), float(y), float(z))
    best = math.inf
    for projection, on in zip(projections, near, strict=True):
        if not on:
            continue  # a face a millimetre or more away
        projection.Perform(point)
        if projection.NbPoints():
            best = min(best, float(projection.LowerDistance()))
    return best


def _local_distances(surface: Any, points: Array) -> Array:
    """The distance (mm) of each of *points* from a point of the (B-spline) *surface* within
    its bounds found near it: Newton's steps from the nearest of :data:`SURFACE_GRID` ×
    :data:`SURFACE_GRID` points of the surface (inf where they lead nowhere, or outside it).
    Each is at least the point's least distance from the surface."""
    from OCP.Extrema import Extrema_GenLocateExtPS
    from OCP.GeomAdaptor import GeomAdaptor_Surface
    from OCP.gp import gp_Pnt

    u0, u1, v0, v1 = surface.Bounds()
    us, vs = np.linspace(u0, u1, SURFACE_GRID), np.linspace(v0, v1, SURFACE_GRID)
    grid = np.array([surface.Value(float(u), float(v)).Coord() for u in us for v in vs])
    square = np.einsum("ij,ij->i", grid, grid)
    # the nearest grid point of each: |p − g|² = |p|² − 2 p·g + |g|² (only the order counts),
    # a thousand points at a time (a few megabytes)
    chunks = np.array_split(points, max(1, -(-len(points) // 1024)))
    nearest = np.concatenate([np.argmin(square[None, :] - 2.0 * (chunk @ grid.T), axis=1)
                              for chunk in chunks])
    start_u, start_v = us[nearest // SURFACE_GRID], vs[nearest % SURFACE_GRID]
    adaptor = GeomAdaptor_Surface(surface)  # held: the search keeps a reference to it
    locate = Extrema_GenLocateExtPS(adaptor)
    found = np.full(len(points), math.inf)
    for k, (x, y, z) in enumerate(points):
        locate.Perform(gp_Pnt(float(x), float(y), float(z)), float(start_u[k]),
                       float(start_v[k]))
        if not locate.IsDone():
            continue
        u, v = locate.Point().Parameter()
        if u0 <= u <= u1 and v0 <= v <= v1:
            found[k] = math.sqrt(locate.SquareDistance())
    return found


def _planes(solid: Solid) -> set[float]:
    """The heights (mm) of the part's flat faces."""
    heights: set[float] = set()
    for piece in pieces(solid):
        if isinstance(piece, (Extrusion, Cylinder)):
            z = piece.z or 0.0
            heights |= {z, z + piece.height}
        elif isinstance(piece, Revolution) and piece.exact is not None:
            v = piece.exact.vertices  # its lines across, square to Z
            edges = np.roll(v, -1, axis=0) - v
            heights |= {float(v[i, 1]) for i in np.flatnonzero(np.abs(edges[:, 1]) < 1e-12)}
    return heights


def _contour_distance(solid: Solid, xyz: Array) -> Array:
    """The distance (mm) of each point from the nearest contour of the part: in plan for an
    extrusion's or a cylinder's, in the point's plane through Z for a revolved section's."""
    best = np.full(len(xyz), np.inf)
    meridian = np.column_stack((np.hypot(xyz[:, 0], xyz[:, 1]), xyz[:, 2]))
    for piece in pieces(solid):
        if isinstance(piece, Extrusion):
            for contour in piece.exact or ():
                best = np.minimum(best, np.abs(meridian[:, 0] - contour)
                                  if isinstance(contour, float) else contour.distance(xyz[:, :2]))
        elif isinstance(piece, Cylinder):
            best = np.minimum(best, np.abs(meridian[:, 0] - float(piece.radius)))
        elif isinstance(piece, Revolution) and piece.exact is not None:
            best = np.minimum(best, piece.exact.distance(meridian))
    return best
