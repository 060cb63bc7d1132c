"""The design's motion for the inspection follower: exact for the design's own follower, else
that follower run over the design's cam."""

from __future__ import annotations

from typing import TYPE_CHECKING

from camfab.arrays import Array
from camfab.curves.follower import FollowerGeometry
from camfab.curves.profile import Profile
from camfab.errors import InspectionError
from camfab.inspect.measure import run_follower
from camfab.inspect.record import Reference

if TYPE_CHECKING:
    from camfab.analysis.record import Analysis

#: The design's working curve is sampled this many times finer than its tolerance to be the
#: reference a different follower is run over: chords of a convex curve lie inside it, and at
#: the design's own sampling they would shift the reference by up to half the tolerance.
REFERENCE_REFINEMENT = 64.0


def design_reference(analysis: Analysis, follower: FollowerGeometry) -> Reference:
    """The design's motion for *follower*.

    For the design's own follower on a cam that is not undercut this is the design motion itself
    (rest position + s(θ), exact). For another follower (say an inspection roller of another
    radius), or an undercut cam, it is that follower run over the design's cam: the exact working
    curve sampled :data:`REFERENCE_REFINEMENT` times finer than the design's tolerance, or the
    undercut cam's trimmed profile as built.
    """
    from camfab.geometry.disc_geometry import sample_closed

    design, geom = analysis.design, analysis.geometry
    if geom is None:
        raise InspectionError(design.source or design.name,
                              f"a {design.cam.type} cam has no disc outline to inspect")
    program, cam = analysis.program, geom.cam
    name, file = design.name, design.source or design.name
    if follower == cam.follower and not geom.undercut:
        rest = cam.rest

        def exact(theta: Array) -> Array:
            return rest + program.evaluate(theta)[0]

        return Reference(exact, cam.base_radius, f"the design motion of {name}", name,
                         geom.profile, file)
    profile = geom.profile
    source = f"the inspection follower run over {name}'s cam as cut (undercut trimmed)"
    if analysis.result.refine_for_inspection and not geom.undercut:
        fine = sample_closed(cam, program, "working", geom.tolerance / REFERENCE_REFINEMENT)
        profile = Profile.from_points(fine.xy).ccw()
        source = (f"the inspection follower run over {name}'s exact profile (sampled within "
                  f"{geom.tolerance / REFERENCE_REFINEMENT:.2g} mm)")
    sigma = cam.sigma

    def simulated(theta: Array) -> Array:
        return run_follower(profile, follower, theta, sigma, file, f"the design's cam ({name})")

    return Reference(simulated, cam.base_radius, source, name, profile, file)
