"""The globoidal cam's flanks (camfab/geometry/globoid.py) against independent constructions:
the envelope of the roller's poses found numerically, the meshing condition with the relative
velocity by finite differences, the pressure angle from the swept surface's normal, and the
undercut limit against a brute-force scan of the roller radius."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy.optimize import brentq

from camfab.arrays import Array
from camfab.geometry.globoid import Globoid, to_cam, undercut_radius
from camfab.pipeline import design_from_text

#: An oscillating follower's motion: 40° of swing out and back (cycloidal and 3-4-5).
PROGRAM = design_from_text("""
name: swing
cam: {type: disc, base_radius: 30}
follower: {type: roller, motion: oscillating, roller_radius: 8, pivot_distance: 80,
           arm_length: 60}
motion:
  - rise:   {angle: 120, lift: 40, law: cycloidal}
  - dwell:  {angle: 60}
  - return: {angle: 120, law: polynomial-345}
  - dwell:  {angle: 60}
limits: {pressure_angle: 60}
""").program

CASES = [Globoid(100.0, 60.0, 20.0, 8.0, math.radians(-20.0), 1),   # concave, ccw
         Globoid(100.0, 60.0, 20.0, 8.0, math.radians(-20.0), -1),  # concave, cw
         Globoid(40.0, 70.0, 16.0, 6.0, math.radians(-20.0), 1)]    # convex
IDS = ["concave-ccw", "concave-cw", "convex"]


def motion(theta: Any) -> np.ndarray:
    return PROGRAM.evaluate(np.atleast_1d(np.asarray(theta, dtype=float)))


def regularity(globoid: Globoid, theta: Array, ell: Array, motion_at: object, side: int,
               radius: float, step: float = 1e-5) -> Array:
    """J = (∂P/∂ℓ × ∂P/∂θ)·n on the cam (mm²/rad) for the flank on *side* of a roller of
    *radius*: positive where the flank is a regular surface (as the axis surface is, r = 0),
    zero or negative where it folds (an undercut). The derivatives are central differences of
    the exact flank (*step* in mm and rad); *motion_at* gives the motion (4, N) at cam angles
    (N,)."""
    theta = np.asarray(theta, dtype=np.float64)
    ell = np.asarray(ell, dtype=np.float64)

    def evaluate(t: Array) -> Array:  # motion_at takes (N,) angles and gives (4, N)
        flat = motion_at(np.ravel(t))  # type: ignore[operator]
        return np.asarray(flat).reshape((4, *np.shape(t)))

    def at(t: Array, e: Array) -> Array:
        return globoid.flank(t, e, evaluate(t), side, radius)

    d_ell = (at(theta, ell + step) - at(theta, ell - step)) / (2 * step)
    d_theta = (at(theta + step, ell) - at(theta - step, ell)) / (2 * step)
    m = evaluate(theta)
    n = globoid.normal(ell, globoid.rest + m[0], m[1])
    n_cam = to_cam(n, globoid.sigma * theta)
    return np.einsum("...i,...i->...", np.cross(d_ell, d_theta), n_cam)


def cam_axis(g: Globoid, theta: float, ell: float) -> tuple[np.ndarray, np.ndarray]:
    """The roller's axis at cam angle θ on the cam: a point and the unit direction."""
    psi = g.rest + motion(theta)[0, 0]
    q = to_cam(np.array([g.centre - ell * math.cos(psi), 0.0, ell * math.sin(psi)]),
               g.sigma * theta)
    a = to_cam(np.array([-math.cos(psi), 0.0, math.sin(psi)]), g.sigma * theta)
    return q, a


@pytest.mark.parametrize("g", CASES, ids=IDS)
def test_the_normal_is_perpendicular_to_the_relative_velocity(g: Globoid) -> None:
    theta = np.linspace(0.05, 2 * math.pi - 0.05, 37)
    ells = g.ells(5)
    h = 1e-6
    for t in theta:
        m = motion(t)
        for ell in ells:
            ahead, _ = cam_axis(g, t + h, ell)
            behind, _ = cam_axis(g, t - h, ell)
            v_cam = (ahead - behind) / (2 * h)
            # back into the frame at θ: Rot_z(+σθ)
            v = to_cam(v_cam, -g.sigma * t)
            n = g.normal(np.array(ell), np.array(g.rest + m[0, 0]), np.array(m[1, 0]))
            assert abs(float(np.dot(n, v))) <= 1e-7 * max(1.0, float(np.linalg.norm(v)))
            exact = g.relative_velocity(np.array(ell), np.array(g.rest + m[0, 0]),
                                        np.array(m[1, 0]))
            assert np.allclose(exact, v, atol=1e-6)
            assert abs(float(np.dot(n, exact))) < 1e-9


@pytest.mark.parametrize("g", CASES, ids=IDS)
def test_the_flanks_are_the_envelope_of_the_rollers_poses(g: Globoid) -> None:
    """Points of the roller's surface at θ₀, fixed on the cam, whose distance from the roller's
    axis is stationary as θ passes θ₀: found by a root search round the roller, they are the
    two flank points of the closed form."""
    h = 1e-5
    for t0 in (0.4, 1.3, 2.6, 3.9, 4.8):
        for ell in g.ells(3):
            q, a = cam_axis(g, t0, ell)
            e1 = np.cross(a, [0.0, 0.0, 1.0])
            e1 /= np.linalg.norm(e1)
            e2 = np.cross(a, e1)

            ahead = cam_axis(g, t0 + h, ell)
            behind = cam_axis(g, t0 - h, ell)

            def point(beta: float, q: np.ndarray = q, e1: np.ndarray = e1,
                      e2: np.ndarray = e2) -> np.ndarray:
                return q + g.radius * (math.cos(beta) * e1 + math.sin(beta) * e2)

            def drift(beta: float, ahead: Any = ahead, behind: Any = behind,
                      point: Any = point) -> float:
                """How fast the distance from the point to the roller's axis changes."""
                x = point(beta)

                def dist(axis: tuple[np.ndarray, np.ndarray]) -> float:
                    p, d = axis  # the distance from x to the pose's axis line
                    return float(np.linalg.norm(np.cross(x - p, d)))

                return (dist(ahead) - dist(behind)) / (2 * h)

            # a grid that does not start on a root (the roots are half a turn apart)
            betas = np.linspace(0.0, 2 * math.pi, 74) + 0.0123
            values = [drift(b) for b in betas]
            found = [brentq(drift, betas[k], betas[k + 1], xtol=1e-13)
                     for k in range(len(betas) - 1) if values[k] * values[k + 1] < 0]
            assert len(found) == 2
            m = motion(t0)
            flanks = [g.flank(np.array(t0), np.array(ell), m[:, 0], side) for side in (1, -1)]
            for beta in found:
                x = point(beta)
                assert min(float(np.linalg.norm(x - f)) for f in flanks) < 1e-6


@pytest.mark.parametrize("g", CASES, ids=IDS)
def test_the_pressure_angle_is_that_of_the_swept_surfaces_normal(g: Globoid) -> None:
    theta = np.linspace(0.1, 2 * math.pi - 0.1, 29)
    ell = g.ells(4)
    h = 1e-6
    for t in theta:
        m = motion(t)[:, 0]
        psi = g.rest + m[0]
        for e in ell:
            d_ell = (g.flank(t, e + h, m, 1) - g.flank(t, e - h, m, 1)) / (2 * h)
            d_theta = (g.flank(t + h, e, motion(t + h)[:, 0], 1)
                       - g.flank(t - h, e, motion(t - h)[:, 0], 1)) / (2 * h)
            normal = to_cam(np.cross(d_ell, d_theta), -g.sigma * t)
            normal /= np.linalg.norm(normal)
            along = np.array([math.sin(psi), 0.0, math.cos(psi)])  # where Q moves as ψ grows
            fd = math.acos(min(1.0, abs(float(np.dot(normal, along)))))
            assert fd == pytest.approx(float(g.pressure_angle(e, psi, m[1])), abs=1e-6)


@pytest.mark.parametrize("g", CASES, ids=IDS)
def test_the_undercut_limit_matches_a_scan_of_the_roller_radius(g: Globoid) -> None:
    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    ell = g.ells(9)[:, None]
    step = 1e-4
    limit = undercut_radius(g, theta[None, :], ell, motion(theta)[:, None, :],
                            motion(theta + step)[:, None, :], motion(theta - step)[:, None, :],
                            step)
    # the scan below: the flank's own J by differences of the flank, at each roller radius
    assert math.isfinite(limit) and limit > 0

    def folds(radius: float) -> bool:
        return any(float(np.min(regularity(g, theta[None, :], ell, motion, side, radius)))
                   <= 0.0 for side in (1, -1))

    radii = np.linspace(0.2, 3.0 * limit, 60)
    first = next(r for r in radii if folds(r))
    spacing = radii[1] - radii[0]
    assert limit <= first + 1e-6 and limit > first - spacing - 1e-6
    assert not folds(0.99 * limit) and folds(1.01 * limit)


@pytest.mark.parametrize("g", CASES, ids=IDS)
def test_the_groove_tube_is_one_closed_solid(g: Globoid) -> None:
    import manifold3d

    from camfab.export.stl import StlMesh
    from camfab.geometry.globoid import groove_tube

    theta = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    half = g.length / 2.0
    inward = 1.0 if g.concave else -1.0  # along the arm toward the cam's inside
    top = g.arm - inward * (half + 3.0)  # outside the blank
    floor = g.arm + inward * (half + 0.5)
    vertices, faces = groove_tube(g, theta, motion(theta), np.linspace(top, floor, 8))
    mesh = StlMesh(vertices, faces)
    closed, wound = mesh.edges()
    assert closed and wound
    solid = manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(vertices, dtype=np.float64),
        tri_verts=np.ascontiguousarray(faces, dtype=np.uint64)))
    assert solid.status() == manifold3d.Error.NoError
    volume = float(solid.volume())
    assert volume == pytest.approx(mesh.volume(), rel=1e-9)
    # Pappus, station by station: the section's area times the path of its centroid
    area = abs(floor - top) * 2 * g.radius  # the section is a rectangle in (ℓ, u)
    m = motion(theta)
    centre = to_cam(g.axis_point(np.full(theta.size, g.arm), g.rest + m[0]), g.sigma * theta)
    path = float(np.sum(np.linalg.norm(np.roll(centre, -1, axis=0) - centre, axis=1)))
    assert volume == pytest.approx(area * path, rel=0.05)
