"""The fitted surfaces of a STEP solid (:mod:`camfab.export.step`): a drum's or a globoid's groove,
given as grids of its exact surface's points, made cubic B-spline surfaces whose shared edges are
the same curves, sewn into one closed solid; and, once the part's booleans have cut it, the edges
where those surfaces meet an exact face (a cylinder, a plane, a torus, a revolved arc) computed
again on both.

Why the edges must lie on their faces to well under 1e-7 mm: a STEP file carries no tolerances
of its own, so a reader (OpenCASCADE's, FreeCAD's) builds each edge anew from its curve and gives
it the largest distance it finds from the edge's faces at a couple of dozen points along it, and
no less than 1e-7 mm. FreeCAD's full check (``shape.check(True)``, OpenCASCADE's
``BOPAlgo_ArgumentAnalyzer`` with its curve-on-surface test) then looks for the largest distance
everywhere along the edge and reports the edge as an invalid curve on its surface wherever it
exceeds what the reader gave. Edges between surfaces fitted each on its own, or between a fitted
surface and an exact one as a boolean's intersection approximates them, stray 1e-7 to 1e-5 mm
between the reader's points: harmless for booleans, alarming to a user. So:

- the grids share their edge rows and columns exactly, and each grid becomes one surface,
  interpolated round the cam at parameters the grids share and fitted across (its ends kept), so
  that a row or a column two grids share gives both the same curve, control point for control
  point; each surface is then cut into :data:`FIT_PATCHES` patches at parameters (no face closes
  on itself) whose shared edges are the same curve, and the seam round the cam closes exactly;
- an edge between a fitted face and an exact one is recomputed point by point on both surfaces
  (Newton's steps on the fitted surface towards the exact one's implicit form) and its three
  curves (in space, on each face) fitted to those points, until they lie within about
  :data:`EDGE_MM` of each other between them. The file carries those curves on the faces
  (pcurves): a reader that computes them itself approximates them on a fitted surface or a
  revolved arc to 1e-7 mm or worse, more than it then allows the edge.

The module holds OpenCASCADE's imports inside its functions, as :mod:`camfab.export.step` does.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from collections.abc import Callable

    from camfab.arrays import Array

#: How near (mm) each surface comes to its grid's points across the cam (round it, it passes
#: through them), as near as the fits before these came: far below any tolerance; the
#: read-back's probes measure what lies between the points.
FIT_MM = 1e-5
#: The patches each fitted surface is cut into round the cam (count).
FIT_PATCHES = 4
#: How near (mm) the fitted surfaces' shared edges must be to be sewn into one: their edges are
#: the same curves, so this only bounds rounding; far below any tolerance.
SEWING_MM = 1e-4
#: How near (mm) an edge between a fitted face and an exact one comes to both, between the points
#: it was computed at: a fifth of the 1e-7 mm a STEP reader gives an edge at least, so that no
#: reader's check along it finds it off its faces; more knots stop helping at 1e-8 to 3e-8 mm.
EDGE_MM = 2e-8
#: The points (at least; two a knot line of the fitted surface otherwise) along such an edge at
#: which it is first followed, to find where it crosses the fitted surface's knot lines.
EDGE_POINTS = 64
#: Rounds of knots added where the curves stray, at most (the last round's curves are kept: some
#: 3e-8 mm from the faces at worst, where the boolean's strayed 1e-7 to 1e-5 mm).
EDGE_ROUNDS = 6


class NotExact(ValueError):
    """The part holds a piece camfab has no exact solid for (its message says which)."""


def fitted_solid(grids: tuple[Array, ...]) -> Any:
    """The closed solid bounded by cubic B-spline surfaces through *grids* (mm; each (N, M, 3),
    closed round its first axis, its first and last columns the neighbouring grids' edges),
    sewn and oriented outward (raises :class:`NotExact` when they do not sew into one shell)."""
    from OCP.BRepBuilderAPI import (
        BRepBuilderAPI_MakeFace,
        BRepBuilderAPI_MakeSolid,
        BRepBuilderAPI_Sewing,
    )
    from OCP.BRepLib import BRepLib
    from OCP.TopAbs import TopAbs_SHELL
    from OCP.TopoDS import TopoDS

    count = grids[0].shape[0]
    closed = [grid[np.arange(count + 1) % count] for grid in grids]  # the first row again
    # round the cam, one set of parameters for every grid: their shared columns meet exactly
    around = _chord_parameters(np.concatenate(closed, axis=1), axis=0)
    ends = [round(k * count / FIT_PATCHES) for k in range(FIT_PATCHES + 1)]
    sewing = BRepBuilderAPI_Sewing(SEWING_MM)
    for grid in closed:
        surface = _surface(*_fit(grid, around))
        for first, last in itertools.pairwise(ends):
            patch = surface.Copy()
            patch.Segment(float(around[first]), float(around[last]), 0.0, 1.0)
            sewing.Add(BRepBuilderAPI_MakeFace(patch, SEWING_MM).Face())
    sewing.Perform()
    sewn = sewing.SewedShape()
    if sewn.ShapeType() != TopAbs_SHELL:
        raise NotExact("surfaces fitted through the groove's points that do not sew into one "
                       "closed shell")
    solid = BRepBuilderAPI_MakeSolid(TopoDS.Shell(sewn)).Solid()
    BRepLib.OrientClosedSolid_s(solid)
    if _signed_volume(solid) < 0.0:  # (the orientation is not always found)
        solid = TopoDS.Solid(solid.Reversed())
    return solid


def _signed_volume(shape: Any) -> float:
    """The volume (mm³) of *shape*, negative for a solid inside out."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    return float(props.Mass())


def _chord_parameters(points: Array, axis: int) -> Array:
    """Parameters from 0 to 1 along *axis* (0 or 1) of an (N, M, 3) grid: the chords between
    its rows (or columns), averaged across, summed."""
    chords = np.linalg.norm(np.diff(points, axis=axis), axis=-1).mean(axis=1 - axis)
    summed = np.concatenate(([0.0], np.cumsum(chords)))
    return summed / summed[-1]


def _fit(grid: Array, around: Array) -> tuple[Array, Array, Array]:
    """The control points (U, V, 3) and the knot vectors round and across of the cubic B-spline
    surface through *grid*'s rows at the parameters *around* (not-a-knot interpolation: its
    ends are the end rows') and within :data:`FIT_MM` of its columns (least squares on as few
    spans as reach it, the end columns kept)."""
    from scipy.interpolate import make_interp_spline

    rows = make_interp_spline(around, grid, k=3, axis=0)
    poles = np.asarray(rows.c)  # (U, M, 3): each column's control points round the cam
    across = _chord_parameters(grid, axis=1)
    spans = 1
    while True:
        knots = _clamped_knots(across, spans)
        fitted, basis = _least_squares(across, knots, np.moveaxis(poles, 1, 0))
        error = np.linalg.norm(np.einsum("jb,bik->jik", basis, fitted)
                               - np.moveaxis(poles, 1, 0), axis=-1)
        if float(np.max(error)) <= FIT_MM or spans >= len(across) - 1:
            return np.moveaxis(fitted, 0, 1), np.asarray(rows.t), knots
        spans = min(2 * spans, len(across) - 1)


def _clamped_knots(parameters: Array, spans: int) -> Array:
    """A clamped cubic knot vector over *parameters* with *spans* spans, its inner knots at the
    parameters spread evenly by index."""
    last = len(parameters) - 1
    inner = parameters[np.round(np.linspace(0, last, spans + 1)[1:-1]).astype(int)]
    return np.concatenate(([parameters[0]] * 4, inner, [parameters[-1]] * 4))


def _least_squares(parameters: Array, knots: Array, values: Array) -> tuple[Array, Array]:
    """The control points of the cubic B-spline on *knots* nearest (least squares) to *values*
    ((N, ...) at *parameters*) whose first and last are the first and last values (so that two
    fits whose values share an end share that end exactly), and the basis at the parameters."""
    import scipy.linalg
    from scipy.interpolate import BSpline

    basis = BSpline.design_matrix(parameters, knots, 3).toarray()
    flat = values.reshape(len(parameters), -1)
    rest = flat - np.outer(basis[:, 0], flat[0]) - np.outer(basis[:, -1], flat[-1])
    inner = scipy.linalg.lstsq(basis[:, 1:-1], rest, lapack_driver="gelsy",
                               check_finite=False)[0]
    poles = np.concatenate((flat[:1], inner, flat[-1:]))
    return poles.reshape((basis.shape[1], *values.shape[1:])), basis


def _knots_and_multiplicities(knots: Array) -> tuple[Any, Any]:
    """A full knot vector as OpenCASCADE takes it: its distinct knots and their counts."""
    from OCP.OCP.collections import Array1_double, Array1_int

    values, counts = np.unique(knots, return_counts=True)
    distinct, multiplicities = Array1_double(1, len(values)), Array1_int(1, len(values))
    for i, (value, count) in enumerate(zip(values, counts, strict=True)):
        distinct.SetValue(i + 1, float(value))
        multiplicities.SetValue(i + 1, int(count))
    return distinct, multiplicities


def _surface(poles: Array, around: Array, across: Array) -> Any:
    """The cubic B-spline surface of control points *poles* (U, V, 3) and knot vectors."""
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt
    from OCP.OCP.collections import Array2_gp_Pnt

    count_u, count_v = poles.shape[:2]
    points = Array2_gp_Pnt(1, count_u, 1, count_v)
    for i in range(count_u):
        for j in range(count_v):
            x, y, z = poles[i, j]
            points.SetValue(i + 1, j + 1, gp_Pnt(float(x), float(y), float(z)))
    knots_u, multiplicities_u = _knots_and_multiplicities(around)
    knots_v, multiplicities_v = _knots_and_multiplicities(across)
    return Geom_BSplineSurface(points, knots_u, knots_v, multiplicities_u, multiplicities_v,
                               3, 3)


def _curve(poles: Array, knots: Array) -> Any:
    """The cubic B-spline curve (3D for (N, 3) *poles*, 2D for (N, 2)) of *poles* and the knot
    vector *knots*."""
    distinct, multiplicities = _knots_and_multiplicities(knots)
    if poles.shape[1] == 2:
        from OCP.Geom2d import Geom2d_BSplineCurve
        from OCP.gp import gp_Pnt2d
        from OCP.OCP.collections import Array1_gp_Pnt2d

        flat = Array1_gp_Pnt2d(1, len(poles))
        for i, (x, y) in enumerate(poles):
            flat.SetValue(i + 1, gp_Pnt2d(float(x), float(y)))
        return Geom2d_BSplineCurve(flat, distinct, multiplicities, 3)
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt
    from OCP.OCP.collections import Array1_gp_Pnt

    space = Array1_gp_Pnt(1, len(poles))
    for i, (x, y, z) in enumerate(poles):
        space.SetValue(i + 1, gp_Pnt(float(x), float(y), float(z)))
    return Geom_BSplineCurve(space, distinct, multiplicities, 3)


def meet_exactly(shape: Any) -> None:
    """Compute again, in place, each edge of *shape* between a fitted (B-spline) face and an
    exact one, so that it lies on both within :data:`EDGE_MM` (an edge whose exact face has no
    implicit form here, or whose points do not converge, is left as it was)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_SurfaceType
    from OCP.OCP.collections import (
        IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as EdgeFaces,
    )
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from OCP.TopoDS import TopoDS

    found = EdgeFaces()
    TopExp.MapShapesAndUniqueAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, found)
    for index in range(1, found.Extent() + 1):
        faces = [TopoDS.Face(face) for face in found.FindFromIndex(index)]
        if len(faces) != 2:
            continue
        fitted = [BRepAdaptor_Surface(face).GetType()
                  == GeomAbs_SurfaceType.GeomAbs_BSplineSurface for face in faces]
        if fitted[0] != fitted[1]:
            on, off = (faces[0], faces[1]) if fitted[0] else (faces[1], faces[0])
            _meet(TopoDS.Edge(found.FindKey(index)), on, off)


def _implicit(surface: Any) -> Callable[[Array], tuple[Array, Array]] | None:
    """The exact surface (a ``BRepAdaptor_Surface``) as a function of points (K, 3) giving
    their signed distances from it and its unit normals there; None for a kind of surface
    without one here."""
    from OCP.GeomAbs import GeomAbs_CurveType, GeomAbs_SurfaceType

    kind = surface.GetType()

    def frame(axis: Any) -> tuple[Array, Array]:
        return np.array(axis.Location().Coord()), np.array(axis.Direction().Coord())

    if kind == GeomAbs_SurfaceType.GeomAbs_Plane:
        origin, normal = frame(surface.Plane().Axis())
        return lambda p: ((p - origin) @ normal, np.broadcast_to(normal, p.shape))
    if kind == GeomAbs_SurfaceType.GeomAbs_Cylinder:
        cylinder = surface.Cylinder()
        origin, axis = frame(cylinder.Axis())
        radius = cylinder.Radius()

        def from_cylinder(p: Array) -> tuple[Array, Array]:
            w = p - origin
            radial = w - np.outer(w @ axis, axis)
            rho = np.linalg.norm(radial, axis=1)
            return rho - radius, radial / rho[:, None]

        return from_cylinder
    # a torus, or an arc revolved (a globoid's blank): a circle of radius `minor` in each plane
    # through the axis, its centre `across` from the axis (negative: beyond it) at `height`
    if kind == GeomAbs_SurfaceType.GeomAbs_Torus:
        torus = surface.Torus()
        origin, axis = frame(torus.Axis())
        across, height, minor = torus.MajorRadius(), 0.0, torus.MinorRadius()
    elif kind == GeomAbs_SurfaceType.GeomAbs_SurfaceOfRevolution:
        basis = surface.BasisCurve()
        if basis.GetType() != GeomAbs_CurveType.GeomAbs_Circle:
            return None
        origin, axis = frame(surface.AxeOfRevolution())
        circle = basis.Circle()
        centre = np.array(circle.Location().Coord()) - origin
        height = float(centre @ axis)
        middle = np.array(basis.Value(0.5 * (basis.FirstParameter()
                                             + basis.LastParameter())).Coord()) - origin
        side = middle - (middle @ axis) * axis  # the arc's side of the axis
        across = float((centre - height * axis) @ side / np.linalg.norm(side))
        minor = circle.Radius()
    else:
        return None

    def from_circles(p: Array) -> tuple[Array, Array]:
        w = p - origin
        h = w @ axis
        radial = w - np.outer(h, axis)
        rho = np.linalg.norm(radial, axis=1)
        out = radial / rho[:, None]
        dr, dh = rho - across, h - height
        length = np.hypot(dr, dh)
        return length - minor, (dr[:, None] * out + dh[:, None] * axis) / length[:, None]

    return from_circles


def _meet(edge: Any, on: Any, off: Any) -> None:
    """*edge*, between the fitted face *on* and the exact face *off*, computed again: points of
    *on*'s surface on *off*'s at parameters along the edge, and its curve and its curves on both
    faces fitted to them (least squares, its ends kept) on knots where it crosses the fitted
    surface's knot lines (where it may bend abruptly), more knots where the curves stray (it is
    left as it was where Newton's steps do not converge)."""
    from OCP.BRep import BRep_Builder, BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d, BRepAdaptor_Surface
    from OCP.gp import gp_Pnt
    from OCP.TopExp import TopExp

    fitted, exact = BRepAdaptor_Surface(on), BRepAdaptor_Surface(off)
    implicit = _implicit(exact)
    if implicit is None:
        return
    first, last = BRep_Tool.Range_s(edge)
    on_fitted, on_exact = BRepAdaptor_Curve2d(edge, on), BRepAdaptor_Curve2d(edge, off)
    surface = fitted.BSpline()
    lines = (np.array([surface.UKnot(i) for i in range(1, surface.NbUKnots() + 1)]),
             np.array([surface.VKnot(i) for i in range(1, surface.NbVKnots() + 1)]))
    t = np.linspace(first, last, max(EDGE_POINTS, 2 * sum(len(k) for k in lines)))
    breaks = _crossings(t, np.array([on_fitted.Value(float(x)).Coord() for x in t]), lines)
    for _ in range(EDGE_ROUNDS):
        knots = np.concatenate(([first] * 4, breaks, [last] * 4))
        t = np.unique(np.concatenate([np.linspace(a, b, 5) for a, b in
                                      itertools.pairwise(np.unique(knots))]))
        solved = _on_both(fitted, implicit,
                          np.array([on_fitted.Value(float(x)).Coord() for x in t]))
        if solved is None:
            return
        uv, points = solved
        reference = np.array([on_exact.Value(float(x)).Coord() for x in t])
        st = _parameters(exact, BRep_Tool.Surface_s(off), points, reference)
        poles = _least_squares(t, knots, np.column_stack((points, uv, st)))[0]
        curves = (_curve(poles[:, :3], knots), _curve(poles[:, 3:5], knots),
                  _curve(poles[:, 5:], knots))
        middles = 0.5 * (t[1:] + t[:-1])
        strays = middles[_strays(fitted, exact, curves, middles) > EDGE_MM]
        if not len(strays):
            break
        spans = np.unique(np.searchsorted(knots, strays))  # a knot in the middle of each
        breaks = np.sort(np.concatenate((breaks, 0.5 * (knots[spans - 1] + knots[spans]))))
    builder = BRep_Builder()
    tolerance = max(BRep_Tool.Tolerance_s(edge), 1e-7)
    builder.UpdateEdge(edge, curves[0], tolerance)
    builder.UpdateEdge(edge, curves[1], on, tolerance)
    builder.UpdateEdge(edge, curves[2], off, tolerance)
    builder.Range(edge, first, last)
    ends = [gp_Pnt(*map(float, points[0])), gp_Pnt(*map(float, points[-1]))]
    for vertex in (TopExp.FirstVertex_s(edge), TopExp.LastVertex_s(edge)):
        gap = min(BRep_Tool.Pnt_s(vertex).Distance(end) for end in ends)
        builder.UpdateVertex(vertex, max(BRep_Tool.Tolerance_s(vertex), 2.0 * gap))


def _crossings(t: Array, uv: Array, lines: tuple[Array, Array]) -> Array:
    """The parameters (between *t*'s first and last) where a curve, at *uv* (K, 2) at *t*,
    crosses the knot lines *lines* (its surface's u and v knots), each found linearly between
    the two of *t* it falls between; none nearer each other or the ends than 1e-6 of the
    range."""
    found = []
    for axis, knots in enumerate(lines):
        values = uv[:, axis]
        for i in np.flatnonzero(np.searchsorted(knots, values[1:])
                                != np.searchsorted(knots, values[:-1])):
            low, high = sorted((values[i], values[i + 1]))
            for knot in knots[(knots > low) & (knots < high)]:
                share = (knot - values[i]) / (values[i + 1] - values[i])
                found.append(t[i] + share * (t[i + 1] - t[i]))
    gap = 1e-6 * (t[-1] - t[0])
    kept: list[float] = []
    for x in sorted(found):
        if x - t[0] > gap and t[-1] - x > gap and (not kept or x - kept[-1] > gap):
            kept.append(float(x))
    return np.array(kept)


def _on_both(fitted: Any, implicit: Callable[[Array], tuple[Array, Array]],
             uv: Array) -> tuple[Array, Array] | None:
    """From the fitted surface's parameters *uv* (K, 2), Newton's least steps to its points on
    the exact surface: their parameters and points (mm), or None if they do not converge."""
    from OCP.gp import gp_Pnt, gp_Vec

    point, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
    uv = uv.copy()
    for _ in range(12):
        values = np.empty((len(uv), 3, 3))
        for i, (u, v) in enumerate(uv):
            fitted.D1(float(u), float(v), point, du, dv)
            values[i] = (point.Coord(), du.Coord(), dv.Coord())
        distance, normal = implicit(values[:, 0])
        if float(np.max(np.abs(distance))) <= 1e-11:
            return uv, values[:, 0]
        slope = np.einsum("ijk,ik->ij", values[:, 1:], normal)
        uv -= (distance / np.einsum("ij,ij->i", slope, slope))[:, None] * slope
    return None


def _parameters(exact: Any, surface: Any, points: Array, reference: Array) -> Array:
    """The exact surface's parameters (K, 2) of *points* on it, a periodic one taken nearest
    the edge's old curve on it (*reference*)."""
    from OCP.ElSLib import ElSLib
    from OCP.GeomAbs import GeomAbs_SurfaceType
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt

    kind = exact.GetType()
    elementary = {GeomAbs_SurfaceType.GeomAbs_Plane: exact.Plane,
                  GeomAbs_SurfaceType.GeomAbs_Cylinder: exact.Cylinder,
                  GeomAbs_SurfaceType.GeomAbs_Torus: exact.Torus}.get(kind)
    found = np.empty((len(points), 2))
    if elementary is not None:
        form = elementary()
        for i, (x, y, z) in enumerate(points):
            found[i] = ElSLib.Parameters_s(form, gp_Pnt(float(x), float(y), float(z)))
    else:
        projection = GeomAPI_ProjectPointOnSurf()
        projection.Init(surface, *surface.Bounds())
        for i, (x, y, z) in enumerate(points):
            projection.Perform(gp_Pnt(float(x), float(y), float(z)))
            found[i] = projection.LowerDistanceParameters()
    for axis, periodic, period in ((0, exact.IsUPeriodic(), exact.UPeriod),
                                   (1, exact.IsVPeriodic(), exact.VPeriod)):
        if periodic:
            turn = period()
            found[:, axis] += turn * np.round((reference[:, axis] - found[:, axis]) / turn)
    return found


def _strays(fitted: Any, exact: Any, curves: tuple[Any, Any, Any], at: Array) -> Array:
    """How far (mm) the edge's curve lies from its curves on the two faces at parameters *at*."""
    space, on_fitted, on_exact = curves
    found = np.empty(len(at))
    for i, x in enumerate(at):
        point = space.Value(float(x))
        a, b = on_fitted.Value(float(x)), on_exact.Value(float(x))
        found[i] = max(point.Distance(fitted.Value(a.X(), a.Y())),
                       point.Distance(exact.Value(b.X(), b.Y())))
    return found
