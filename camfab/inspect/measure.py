"""The follower run over an outline: the motion it measures and its derivatives, the turn into
phase with the design, and the base circle lift is measured from.

The follower is pressed onto the outline at every step of a fine grid of cam angles
(:func:`~camfab.geometry.simulate.simulate`, the same engine that verifies camfab's own files);
its position there is the measured motion. Lift is measured from the follower's rest position
on the base circle: the design's base circle when a design is given (so an undersized base circle
shows as a lift error), else the outline's own smallest radius.

Derivatives. A measured lift is known at points, not as a formula, so its derivatives per radian
of cam angle are those of a least-squares cubic fitted over a window of ±``smooth`` about each
angle (a Savitzky–Golay filter, wrapped around the turn). This is exact for a cubic, keeps smooth
motion to within about s⁽⁵⁾·smooth⁴/100, and averages the lift's small ripple (the chords of a
scan, the joints of a drawing's arcs, measuring noise of amplitude σ gives about σ/smooth² of
noise on s″). Its limits: a step in acceleration (a uniform-acceleration or harmonic law meeting a
dwell) is spread over the window, so s″ there ramps over ±smooth instead of jumping, and a peak of
s″ narrower than the window is lowered. Velocity and acceleration at a speed ω are ω·s′ and
ω²·s″; the pressure angle and the pitch curve's radius of curvature follow from s, s′ and s″ by
the exact evaluators of :class:`~camfab.geometry.disc.DiscCam`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from camfab.angles import ranges_deg
from camfab.arrays import Array, Index
from camfab.curves.follower import FollowerGeometry
from camfab.curves.profile import Profile
from camfab.errors import InspectionError
from camfab.geometry.disc import DiscCam
from camfab.inspect.checks import inspection_findings
from camfab.inspect.record import Inspection, InspectionSetup, Reference

#: Largest cam-angle step of the grid the follower is run on: 0.1°, like the verification of
#: camfab's files; a bump of a few tenths of a millimetre along the outline still spans steps.
INSPECT_STEP = math.radians(0.1)

#: Default half-width of the window the derivatives are fitted over: 1° for an outline of lines
#: and arcs (a drawing: its lift ripples by a fraction of its tolerance), 3° for an outline of
#: points (a scan: micrometres of noise per point would swamp s″ over a narrower window).
SMOOTH_DRAWING = math.radians(1.0)
SMOOTH_POINTS = math.radians(3.0)

#: Most (piece, cam angle) pairs one run of the follower over an outline may try: some two
#: seconds of work. A smooth outline needs a few per piece (100,000 points on a circle: some
#: 10,000); only an outline of long spikes about the centre (a star, random points) needs more.
MAX_PAIRS = 10_000_000

#: The alignment's trial turns compare the motion at every this many angles of the grid (0.4°):
#: a least-squares fit over 900 angles, at a quarter of the cost of each trial.
ALIGN_THINNING = 4


def grid(step: float) -> tuple[Array, Index]:
    """The fine grid of cam angles (rad) the follower is run on, at most :data:`INSPECT_STEP`
    apart, holding every row of a table at *step* (rad); and the rows' indices into it."""
    count = max(1, round(2.0 * math.pi / step))
    per_row = max(1, math.ceil((2.0 * math.pi / count) / INSPECT_STEP - 1e-9))
    theta = (2.0 * math.pi / (count * per_row)) * np.arange(count * per_row, dtype=np.float64)
    return theta, np.arange(count) * per_row


def derivatives(values: Array, step: float, smooth: float) -> tuple[Array, Array]:
    """s′ and s″ (per radian) of a periodic *values* sampled every *step* rad, from a cubic fitted
    by least squares over ±*smooth* rad about each sample (see the module's notes)."""
    from scipy.signal import savgol_filter

    half = max(2, round(smooth / step))
    window = min(2 * half + 1, values.size - (1 - values.size % 2))
    first = savgol_filter(values, window, 3, deriv=1, delta=step, mode="wrap")
    second = savgol_filter(values, window, 3, deriv=2, delta=step, mode="wrap")
    return first, second


def run_follower(profile: Profile, follower: FollowerGeometry, theta: Array,
                 sigma: int, file: str, what: str = "the outline") -> Array:
    """The trace point's height (mm) or arm angle (rad) on *profile* at cam angles *theta*.

    Raises
    ------
    InspectionError
        The follower misses the outline (*what*, in the message, read from *file*, which it
        names) at some angle: its line of motion or arm clears it.
    SimulationTooLarge
        The outline is so jagged that the run would try more than :data:`MAX_PAIRS` pairs.
    """
    from camfab.geometry.simulate import simulate

    position = simulate(profile, follower, theta, sigma, MAX_PAIRS)
    missing = ~np.isfinite(position)
    if missing.any():
        where = ", ".join(f"{a:.4g}–{b:.4g}°" for a, b in ranges_deg(theta, missing)[:3])
        raise InspectionError(file, f"the follower does not touch {what} at cam angles "
                              f"{where} (check the offset, pivot and the outline's centre)")
    return position


def align_phase(profile: Profile, follower: FollowerGeometry, theta: Array, sigma: int,
                position: Array, reference: Array, file: str) -> float:
    """The angle α (rad) by which *profile* (read from *file*) must be turned in the direction
    of rotation so the follower's motion on it best matches *reference* (least squares over
    the turn).

    Turning the cam by α in its direction of rotation advances its motion by α:
    ``position'(θ) = position(θ + α)``. The best whole grid step comes from the circular
    cross-correlation (FFT), refined by a parabola through the neighbouring steps and then by
    running the follower over the outline turned by each trial angle (compared every
    :data:`ALIGN_THINNING` grid angles).
    """
    from scipy.optimize import minimize_scalar

    step = float(theta[1] - theta[0])
    a, b = position - position.mean(), reference - reference.mean()
    corr = np.fft.irfft(np.fft.rfft(a) * np.conj(np.fft.rfft(b)), n=a.size)
    ssd = np.sum(a * a) + np.sum(b * b) - 2.0 * corr
    k = int(np.argmin(ssd))
    lo, mid, hi = ssd[k - 1], ssd[k], ssd[(k + 1) % ssd.size]
    curve = lo - 2.0 * mid + hi
    shift = k + (0.5 * (lo - hi) / curve if curve > 0 else 0.0)
    guess = math.remainder(shift * step, 2.0 * math.pi)

    sparse, target = theta[::ALIGN_THINNING], reference[::ALIGN_THINNING]

    def misfit(alpha: float) -> float:
        turned = turn(profile, alpha, sigma)
        return float(np.mean((run_follower(turned, follower, sparse, sigma, file) - target)
                             ** 2))

    found = minimize_scalar(misfit, bounds=(guess - step, guess + step), method="bounded",
                            options={"xatol": 1e-5})
    return float(found.x)


def turn(profile: Profile, alpha: float, sigma: int) -> Profile:
    """*profile* turned by *alpha* (rad) about the cam centre in the direction of rotation."""
    c, s = math.cos(sigma * alpha), math.sin(sigma * alpha)
    v = profile.vertices
    return Profile(np.column_stack((c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1])),
                   profile.bulges.copy())


def inspect_profile(profile: Profile, setup: InspectionSetup, reference: Reference | None = None,
                    align: bool = False, *, file: str) -> Inspection:
    """Run the inspection follower over *profile* (mm, cam centre at the origin, drawn at θ = 0)
    and derive its motion; with a *reference*, its deviation from the design (after turning the
    outline into phase with the design when *align*). A refusal about the outline names *file*
    (the file it was read from)."""
    fol, sigma = setup.follower, setup.sigma
    theta, rows = grid(setup.step)
    position = run_follower(profile, fol, theta, sigma, file)
    design = None if reference is None else reference.position(theta)
    alpha = None
    if align and design is not None:
        alpha = align_phase(profile, fol, theta, sigma, position, design, file)
        profile = turn(profile, alpha, sigma)
        position = run_follower(profile, fol, theta, sigma, file)
    measured_base = float(profile.distance(np.zeros((1, 2)))[0])
    base, lift_from = base_circle(fol, measured_base, position, reference, file)
    cam = DiscCam(fol, base, sigma)
    lift = position - cam.rest
    first, second = derivatives(lift, float(theta[1] - theta[0]), setup.smooth)
    motion = np.vstack((lift, first, second, np.zeros_like(lift)))
    contact = cam.working(theta, motion).xy
    inspection = Inspection(setup, profile, theta, rows, position, cam.rest, base, measured_base,
                            motion, cam.pressure_angle(theta, motion),
                            cam.pitch(theta, motion).radius, contact, reference, align=alpha,
                            lift_from=lift_from)
    if design is not None:
        deviation = position - design
        scale = fol.arm_length if fol.oscillating else 1.0
        inspection = replace(inspection, design_lift=design - cam.rest, deviation=deviation,
                             deviation_mm=deviation * scale)
    return replace(inspection, findings=inspection_findings(inspection))


def base_circle(follower: FollowerGeometry, smallest_radius: float, position: Array,
                reference: Reference | None, file: str) -> tuple[float, str]:
    """The base circle (radius, mm) lift is measured from, and a sentence saying which.

    With a design, the design's base circle. Without one, the outline's *smallest_radius* (mm);
    when the follower cannot rest on a circle that small (its offset or pivot keeps it off, and
    the smallest radius lies in a notch it cannot enter), the circle it rests on at its lowest
    *position* (mm or rad) over the turn.

    Raises
    ------
    InspectionError
        The follower cannot rest on the design's base circle (naming the design file), or on
        any circle of the outline (naming *file*, the outline's).
    """
    if reference is not None:
        if not math.isfinite(_rest(follower, reference.base_radius)):
            raise InspectionError(reference.file, "the follower cannot rest on the design's base "
                                  f"circle of radius {reference.base_radius:.6g} mm (its offset "
                                  "or pivot puts it beyond the prime circle)")
        return reference.base_radius, "the design's base circle"
    if math.isfinite(_rest(follower, smallest_radius)):
        return smallest_radius, "the outline's smallest radius (its base circle)"
    lowest = float(np.min(position))
    base = _base_under(follower, lowest)
    if not (base > 0.0 and math.isfinite(_rest(follower, base))):
        raise InspectionError(file, "the follower cannot rest on a base circle of the outline "
                              "(its offset or pivot keeps it beyond every circle about the "
                              "centre)")
    return base, (f"the follower's lowest position (it cannot reach the outline's smallest "
                  f"radius, {smallest_radius:.6g} mm)")


def _rest(follower: FollowerGeometry, base_radius: float) -> float:
    """The follower's rest position on a base circle (mm or rad), NaN where it has none."""
    try:
        return follower.rest_position(base_radius)
    except ValueError:  # math domain: the circle is out of the follower's reach
        return math.nan


def _base_under(follower: FollowerGeometry, lowest: float) -> float:
    """The radius (mm) of the base circle whose rest position is *lowest* (mm or rad): the
    inverse of :meth:`FollowerGeometry.rest_position`."""
    r = follower.radius
    if not follower.oscillating:
        return lowest if follower.flat else math.hypot(follower.offset, lowest) - r
    a, arm = follower.pivot_distance, follower.arm_length
    if follower.flat:
        return a * math.sin(lowest) - follower.face_offset
    return math.sqrt(max(a * a + arm * arm - 2.0 * a * arm * math.cos(lowest), 0.0)) - r
