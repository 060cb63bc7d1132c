"""Where the follower bears on the cam, against generic definitions: the curvature of the curve or
surface it touches (finite differences of the exact points: a plane curve's, and a surface's
second fundamental form across the contact line plus the roller's curvature in that direction),
the normal force from the balance of forces or moments about the pivot, and the stress of an
eccentric cam under a flat face in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from camfab.geometry.drum import polar_to_xy
from camfab.geometry.globoid import to_cam
from camfab.pipeline import analyse, design_from_mapping, load_design
from camfab.speed.hertz import effective_modulus

from .conftest import DESIGNS


def _with(name: str, **follower: object) -> object:
    """The example *name* with a mass, a speed and a spring where it lacks them."""
    data = yaml.safe_load((DESIGNS / f"{name}.yaml").read_text())
    data["follower"].update({"mass": 0.5, **follower})
    data["cam"].setdefault("speed_rpm", 300)
    if data["cam"]["type"] in ("disc", "circular-arc", "tangent", "linear") \
            and "spring" not in data:
        data["spring"] = {"rate": 10, "preload": 100}
    return design_from_mapping(data, name, DESIGNS)


def test_eccentric_cam_under_a_flat_face_in_closed_form() -> None:
    """The seed's eccentric: a circle of 60 mm under a flat face, 12 mm thick, the force
    F = P + ke + (meω² − ke) cos θ along the face's normal: p = √(F E*/(π L · 60))."""
    analysis = analyse(load_design(DESIGNS / "seed-jump-eccentric.yaml"))
    stress = analysis.at_speed.stress  # type: ignore[union-attr]
    assert stress is not None and stress.contact.shape == "line"
    m, k, e, omega = 1.75, 24000.0, 0.0375, 1500 * math.pi / 30
    force = m * 9.80665 + k * 0.03125 + k * e + (m * e * omega**2 - k * e) * np.cos(
        stress.theta)
    modulus = effective_modulus(206e3, 0.3, 206e3, 0.3)
    expected = np.sqrt(np.maximum(force, 0) * modulus / (math.pi * 12.0 * 60.0))
    np.testing.assert_allclose(stress.stress, expected, rtol=1e-9)
    assert stress.cam_radius_at(stress.index) == pytest.approx(60.0, rel=1e-9)


def _frame(points: np.ndarray, sigma: int, theta: np.ndarray) -> np.ndarray:
    c, s = np.cos(sigma * theta), np.sin(sigma * theta)
    return np.stack((c * points[:, 0] - s * points[:, 1], s * points[:, 0] + c * points[:, 1]),
                    axis=-1)


@pytest.mark.parametrize(("name", "extra"), [
    ("seed-10-4", {}), ("demo-mushroom-cw", {}), ("demo-oscillating-flat", {}),
    ("seed-10-3-oscillating", {}), ("demo-inch-flat", {}), ("demo-oscillating-mushroom", {}),
])
def test_a_plates_contact_against_its_exact_points(name: str, extra: dict) -> None:
    """The profile's curvature at the contact (the working curve's points differenced in θ, its
    sign the cam's side), and the normal force per newton along the follower's motion: the
    force's balance along a translating follower's line, the moments about an arm's pivot."""
    design = _with(name, **extra)
    analysis = analyse(design)
    contact = analysis.result.contact(analysis)
    [side] = contact.sides
    geom = analysis.geometry
    cam, program = geom.cam, analysis.program
    theta = contact.theta
    inside = np.ones(theta.size, dtype=bool)
    for seg in program.segments:  # away from the joints, where the differences straddle one
        inside &= np.abs(theta - seg.start) > 2e-3
        inside &= np.abs(theta - seg.start - 2 * math.pi) > 2e-3
    picked = np.flatnonzero(inside)[::37]
    t = theta[picked]
    h = 1e-4

    def working(at: np.ndarray) -> np.ndarray:
        motion = program.evaluate(at)
        lines = cam.face_lines(at, motion) if cam.follower.flat else None
        return cam.working(at, motion, lines).xy

    p0, p1, p2 = working(t - h), working(t), working(t + h)
    d1, d2 = (p2 - p0) / (2 * h), (p2 - 2 * p1 + p0) / h**2
    turning = np.sign(np.mean(d1[:, 0] * p1[:, 1] * -1 + d1[:, 1] * p1[:, 0]))
    kappa = turning * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    np.testing.assert_allclose(side.curvature[picked], kappa, rtol=2e-5, atol=1e-7)
    # the normal at the contact, in the frame, and the follower's balance
    tangent = _frame(d1, cam.sigma, t)
    normal = np.stack((-tangent[:, 1], tangent[:, 0]), axis=-1) / np.hypot(*tangent.T)[:, None]
    point = _frame(p1, cam.sigma, t)
    fol = cam.follower
    if fol.oscillating:
        pivot = np.array([fol.pivot_sign * fol.pivot_distance, 0.0])
        lever = np.abs((point - pivot)[:, 0] * normal[:, 1] - (point - pivot)[:, 1]
                       * normal[:, 0])
        expected = fol.arm_length / lever
    else:
        expected = 1.0 / np.abs(normal[:, 1])
    np.testing.assert_allclose(side.normal[picked], expected, rtol=1e-6)


def _across(surface, t0: float, l0: float, ht: float, hl: float) -> tuple[float, np.ndarray,
                                                                         np.ndarray]:
    """The normal curvature of the surface P(t, l) across the line l ↦ P(t0, l) (the second
    fundamental form over the first in the direction perpendicular to the line), with the
    surface's unit normal and that direction."""
    p = surface
    pt = (p(t0 + ht, l0) - p(t0 - ht, l0)) / (2 * ht)
    pl = (p(t0, l0 + hl) - p(t0, l0 - hl)) / (2 * hl)
    ptt = (p(t0 + ht, l0) - 2 * p(t0, l0) + p(t0 - ht, l0)) / ht**2
    pll = (p(t0, l0 + hl) - 2 * p(t0, l0) + p(t0, l0 - hl)) / hl**2
    ptl = (p(t0 + ht, l0 + hl) - p(t0 + ht, l0 - hl) - p(t0 - ht, l0 + hl)
           + p(t0 - ht, l0 - hl)) / (4 * ht * hl)
    n = np.cross(pl, pt)
    n /= np.linalg.norm(n)
    across = np.cross(n, pl / np.linalg.norm(pl))
    (a, b), *_ = np.linalg.lstsq(np.column_stack((pt, pl)), across, rcond=None)
    return a * a * (ptt @ n) + 2 * a * b * (ptl @ n) + b * b * (pll @ n), n, across


def _near_joint(program: object, theta: float, margin: float) -> bool:
    return any(abs((theta - seg.start + math.pi) % (2 * math.pi) - math.pi) < margin
               for seg in program.segments)  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", ["demo-globoidal-concave", "demo-globoidal-convex"])
def test_a_globoids_flanks_against_their_surfaces(name: str) -> None:
    """Each flank's curvature across the contact (the build's, from the flanks' regularity),
    plus the roller's, is the relative curvature the flank's exact surface and the roller
    give; and the flank that carries the follower along its swing lies behind the roller."""
    analysis = analyse(_with(name))
    dense = analysis.result.globoid
    g, program = dense.blank.follower, analysis.program
    contact = analysis.result.contact(analysis)
    for k in range(300, dense.theta.size, 700):
        theta = float(dense.theta[k])
        if _near_joint(program, theta, 1e-3):
            continue
        motion = program.evaluate(np.array([theta]))[:, 0]
        psi = g.rest + motion[0]
        for row in (0, dense.ells.size // 2, dense.ells.size - 1):
            ell = float(dense.ells[row])
            axis = to_cam(g.axis_point(ell, psi), g.sigma * theta)
            normal = to_cam(g.normal(ell, psi, motion[1]), g.sigma * theta)
            ahead = to_cam(g.axis_point(ell, psi + 1e-6) - g.axis_point(ell, psi),
                           g.sigma * theta)
            a_dir = to_cam(g.axis_direction(psi), g.sigma * theta)
            for side in contact.sides:
                # the flank's side: behind the roller (against its swing) carries it along
                flank_side = next(s for s in (1, -1)
                                  if np.sign(s * normal @ ahead) == -side.carries)

                def surface(t: float, along: float, s: int = flank_side) -> np.ndarray:
                    m = program.evaluate(np.array([t]))[:, 0]
                    return g.across(np.array(t), np.array(along), m, s)

                kappa, n, across = _across(surface, theta, ell, 1e-4, 1e-4)
                into = surface(theta, ell) - axis
                kappa *= np.sign(n @ into)  # convex as the material (beyond the flank) sees it
                roller = (1 - (across @ a_dir) ** 2) / g.radius
                assert side.curvature[row, k] + 1 / g.radius == pytest.approx(
                    kappa + roller, rel=1e-5)


@pytest.mark.parametrize("name", ["demo-cylindrical", "demo-drum-steep"])
def test_a_drums_flanks_against_their_walls(name: str) -> None:
    """The lower and upper flanks' curvature in closed form against the drum's exact walls
    (its own construction, point by point at each radius), away from the joints and from
    where the steep drum's walls fold."""
    analysis = analyse(_with(name))
    dense = analysis.result.drum
    d, program = dense.drum, analysis.program
    contact = analysis.result.contact(analysis)
    checked = 0
    for k in range(50, dense.theta.size, 211):
        theta = float(dense.theta[k])
        if _near_joint(program, theta, 2e-3):
            continue
        motion = program.evaluate(np.array([theta]))[:, 0]
        alpha = float(d.axis_angle(theta))
        radial = np.array([*polar_to_xy(1.0, alpha), 0.0])
        for row, r in enumerate(dense.radii):
            axis = r * radial + np.array([0.0, 0.0, d.start + motion[0]])
            for side, lower in zip(contact.sides, (True, False), strict=True):
                def surface(t: float, radius: float, lower: bool = lower) -> np.ndarray:
                    m = program.evaluate(np.array([t]))[:, 0]
                    w = d.walls(t, m[0], m[1], radius)
                    phi, z = (w.phi_lower, w.z_lower) if lower else (w.phi_upper, w.z_upper)
                    return np.array([*polar_to_xy(radius, phi), z])

                # the wall's point of this axis point lies at its own radius
                on = _wall_radius(surface, theta, axis, radial, r, d.roller)
                if on is None:
                    continue
                kappa, n, across = _across(surface, theta, on, 1e-4, 1e-3)
                kappa *= np.sign(n @ (surface(theta, on) - axis))
                roller = (1 - (across @ radial) ** 2) / d.roller
                total = side.curvature[row, k] + 1 / d.roller
                if abs(kappa) > 10.0:  # a fold of the steep drum's wall
                    continue
                assert total == pytest.approx(kappa + roller, rel=1e-4, abs=1e-6)
                checked += 1
    assert checked > 20


def _wall_radius(surface, theta: float, axis: np.ndarray, radial: np.ndarray, r: float,
                 roller: float) -> float | None:
    """The radius of the wall's point nearest the roller's axis point at radius *r*: the wall
    point lies on the roller, square to its axis (within a micrometre)."""
    from scipy.optimize import brentq

    def along(radius: float) -> float:
        return float((surface(theta, radius) - axis) @ radial)

    low, high = r - roller, r + roller
    if along(low) * along(high) > 0:
        return None
    return float(brentq(along, low, high, xtol=1e-12))


@pytest.mark.parametrize("name", ["demo-cylindrical", "demo-drum-steep"])
def test_a_drums_normal_force_is_the_mean_over_its_contact_line(name: str) -> None:
    """The force along the motion balances the normal force's axial parts along the contact
    line, the load spread evenly from the groove's floor to the drum's surface:
    F = F_n·mean_r cos φ(r), tan φ = s′/r. The mean against an independent quadrature of the
    pressure angle's cosine (scipy's adaptive quad, to 1e-13), at every cam angle to 1e-9."""
    from scipy.integrate import quad

    analysis = analyse(_with(name))
    dense = analysis.result.drum
    d = dense.drum
    contact = analysis.result.contact(analysis)
    for k in range(0, dense.theta.size, 97):
        ds = float(dense.motion[1, k])
        mean = quad(lambda r, ds=ds: math.cos(math.atan2(ds, r)), d.root, d.radius,
                    epsabs=0.0, epsrel=1e-13)[0] / (d.radius - d.root)
        for side in contact.sides:
            assert side.normal[k] == pytest.approx(1.0 / mean, rel=1e-9)


@pytest.mark.parametrize("name", ["demo-globoidal-convex", "demo-globoidal-concave"])
def test_a_globoids_normal_force_is_the_mean_lever_along_its_roller(name: str) -> None:
    """F·L = F_n·mean_ℓ(ℓ cos α(ℓ)), the load spread evenly along the roller inside the
    groove: the mean against scipy's adaptive quad (to 1e-13) of the pressure angle along the
    roller, at every cam angle to 1e-9."""
    from scipy.integrate import quad

    analysis = analyse(_with(name))
    dense = analysis.result.globoid
    g = dense.blank.follower
    contact = analysis.result.contact(analysis)
    inner, outer = float(dense.ells[0]), float(dense.ells[-1])
    for k in range(0, dense.theta.size, 211):
        psi, dpsi = g.rest + float(dense.motion[0, k]), float(dense.motion[1, k])
        mean = quad(lambda ell, psi=psi, dpsi=dpsi: ell * math.cos(float(g.pressure_angle(
            np.array(ell), np.array(psi), np.array(dpsi)))), inner, outer, epsabs=0.0,
                    epsrel=1e-13)[0] / (outer - inner)
        for side in contact.sides:
            assert side.normal[k] == pytest.approx(g.arm / mean, rel=1e-9)
