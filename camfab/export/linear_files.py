"""A linear cam's DXF and STL (SPEC §5): the plate for laser, CNC and 3-D printing.

DXF (ezdxf, R2010, ``$INSUNITS`` set, lengths in the design's units): ``CUT`` holds the plate's
outline — the working curve fitted with lines and arcs within the tolerance, the two square ends
and the base line — as one closed chain of LINE and ARC entities, kerf-compensated when the
design gives a kerf. ``PITCH``: the pitch curve over one stroke, an open chain. ``PRIME``: the
trace point's height at zero lift (y = base_height); ``BASE``: the profile's height at zero lift
(y = base_height − roller radius, for a roller). ``MARK``: the base line y = 0 and ticks at
travel 0 (x = 0, the taller) and at the end of the stroke. ``TOOLPATH``: a milling cutter's
centre path with ``cutter_radius``. ``NOTE``: what the drawing is.

STL (manifold3d, written by :mod:`camfab.export.stl`'s binary writer): the plate extruded from
z = 0 to z = thickness, in millimetres, only when the design gives a ``thickness``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camfab.export.dxf import add_contour, dxf_bytes, new_document

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis
    from camfab.geometry.profile import Profile


def render_linear_dxf(analysis: Analysis, cut: Profile, pitch: Profile,
                      toolpath: Profile | None) -> bytes:
    """The DXF of a linear cam as bytes: *cut* on ``CUT`` (mm, kerf-compensated), the open
    *pitch* chain on ``PITCH``, the *toolpath* (or None) on ``TOOLPATH``, and the references."""
    design, geom = analysis.design, analysis.linear
    assert geom is not None
    scale = 1.0 / design.mm_per_unit
    cam = geom.cam
    doc = new_document(design)
    msp = doc.modelspace()
    left, right = -cam.overhang * scale, (cam.stroke + cam.overhang) * scale
    # references first, what is cut last: drawn on top where they coincide (the base line)
    add_contour(msp, pitch, scale, "PITCH", closed=False)
    msp.add_line((left, cam.base_height * scale), (right, cam.base_height * scale),
                 dxfattribs={"layer": "PRIME"})
    if cam.radius > 0.0:
        low = (cam.base_height - cam.radius) * scale
        msp.add_line((left, low), (right, low), dxfattribs={"layer": "BASE"})
    mark = {"layer": "MARK"}
    msp.add_line((left, 0.0), (right, 0.0), dxfattribs=mark)
    tick = 0.5 * (cam.base_height - cam.radius) * scale
    msp.add_line((0.0, 0.0), (0.0, tick), dxfattribs=mark)  # travel 0
    msp.add_line((cam.stroke * scale, 0.0), (cam.stroke * scale, 0.5 * tick), dxfattribs=mark)
    unit = design.units
    lines = [f"{design.name}: linear cam, stroke {cam.stroke * scale:.6g} {unit}, base height "
             f"{cam.base_height * scale:.6g} {unit}; moves toward -X, travel 0 at x = 0",
             f"outline of {len(cut.vertices)} lines and arcs within "
             f"{design.manufacturing.tolerance * scale:.3g} {unit}"]
    kerf = design.manufacturing.kerf
    if kerf > 0.0:
        lines.append(f"CUT offset for a kerf of {kerf * scale:.4g} {unit}")
    cutter = design.manufacturing.cutter_radius
    if toolpath is not None:
        add_contour(msp, toolpath, scale, "TOOLPATH")
        lines.append(f"TOOLPATH: centre of a cutter of radius {cutter * scale:.4g} {unit}")
    height = max(0.008 * geom.plate_length * scale, 1e-3)
    below = -(max(cutter, kerf / 2.0) * scale + 1.5 * height)
    for row, line in enumerate(lines):
        msp.add_text(line, height=height, dxfattribs={"layer": "NOTE"}).set_placement(
            (left, below - 1.6 * row * height))
    add_contour(msp, cut, scale, "CUT")
    return dxf_bytes(doc)


def render_linear_stl(analysis: Analysis) -> tuple[bytes, float, float] | None:
    """The binary STL of the plate (mm) with the part's volume (mm³) and its allowance (mm³:
    the tolerance along the outline through the thickness), or None without a ``thickness``.
    """
    import manifold3d
    import trimesh  # noqa: F401  (before manifold3d computes: see camfab.export.stl)

    from camfab.export.stl import binary_stl, chain_length

    geom, thickness = analysis.linear, analysis.design.cam.thickness
    assert geom is not None
    if thickness is None:
        return None
    chain = geom.outline_points()
    section = manifold3d.CrossSection([chain], manifold3d.FillRule.EvenOdd)
    data = binary_stl(manifold3d.Manifold.extrude(section, thickness))
    perimeter = chain_length(chain)
    tolerance = analysis.design.manufacturing.tolerance
    return data, geom.outline.area * thickness, tolerance * perimeter * thickness

