"""Disc-cam geometry against the generic definitions of THEORY §B.

Every reference here is built independently of camfab's closed forms: the trace point from the
mechanism's geometry, tangents and curvature by finite differences, the working curve as the
envelope of the follower's positions (offset along the finite-difference normal, or the
intersection of neighbouring face lines), and the pressure angle as the angle between the normal
and the trace point's velocity.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camfab.curves.follower import FollowerGeometry
from camfab.curves.plane import perp, signed_angle
from camfab.geometry.disc import DiscCam
from camfab.pipeline import load_design

from .conftest import DESIGNS

H = 1e-5  # finite-difference step in cam angle (rad)


def rot(points: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack((c * points[:, 0] - s * points[:, 1], s * points[:, 0] + c * points[:, 1]), -1)


TRANSLATING_PROGRAM = load_design(DESIGNS / "demo-mushroom-cw.yaml").program
OSCILLATING_PROGRAM = load_design(DESIGNS / "demo-oscillating-mushroom.yaml").program
RB, E, A, L, F_OFF, RR = 40.0, 9.0, 110.0, 85.0, 6.0, 11.0


def follower(contact: str, oscillating: bool, sign: int) -> FollowerGeometry:
    radius = RR if contact in ("roller", "mushroom") else 0.0
    if oscillating:
        return FollowerGeometry(contact, True, radius, pivot_distance=A, arm_length=L,
                                pivot_sign=sign, face_offset=F_OFF if contact == "flat" else 0.0)
    return FollowerGeometry(contact, False, radius, offset=sign * E)


def trace_in_frame(fol: FollowerGeometry, s: np.ndarray) -> np.ndarray:
    """The trace point from the mechanism: on x = e at √(Rp² − e²) + s, or on the arm."""
    rp = RB + fol.radius
    if not fol.oscillating:
        y0 = RB if fol.contact == "flat" else math.sqrt(rp * rp - fol.offset**2)
        return np.stack((np.full_like(s, fol.offset), y0 + s), -1)
    p = fol.pivot_sign
    if fol.contact == "flat":  # the face line at f from the pivot touches the base circle
        psi = math.asin((RB + fol.face_offset) / A) + s
    else:  # the trace point on the prime circle
        psi = math.acos((A * A + L * L - rp * rp) / (2 * A * L)) + s
    return np.stack((p * A - p * L * np.cos(psi), L * np.sin(psi)), -1)


def swing_direction(points: np.ndarray, side: int) -> np.ndarray:
    """How frame *points* on the arm move as Ψ grows: turning about the pivot (side·A, 0)."""
    arm = points - np.array([side * A, 0.0])
    return np.stack((arm[:, 1], -arm[:, 0]), -1) * side


CASES = [(c, o, sigma, sign) for c in ("knife", "roller", "mushroom", "flat")
         for o in (False, True) for sigma in (1, -1) for sign in (1, -1)]
IDS = [f"{c}-{'osc' if o else 'tr'}-{'ccw' if s > 0 else 'cw'}-{'+' if g > 0 else '-'}"
       for c, o, s, g in CASES]


def setup(contact: str, oscillating: bool, sigma: int, sign: int):  # type: ignore[no-untyped-def]
    fol = follower(contact, oscillating, sign)
    program = OSCILLATING_PROGRAM if oscillating else TRANSLATING_PROGRAM
    theta = np.linspace(0.003, 2 * math.pi - 0.003, 1500)
    # keep away from joints, where one-sided derivatives differ
    joints = np.array([seg.start for seg in program.segments] + [2 * math.pi])
    theta = theta[np.min(np.abs(theta[:, None] - joints[None, :]), axis=1) > 20 * H]
    return fol, DiscCam(fol, RB, sigma), program, theta


def pitch_reference(fol, program, sigma, theta):  # type: ignore[no-untyped-def]
    def at(t: np.ndarray) -> np.ndarray:
        return rot(trace_in_frame(fol, program.evaluate(t)[0]), -sigma * t)

    p0, p1, pm = at(theta), at(theta + H), at(theta - H)
    d1 = (p1 - pm) / (2 * H)
    d2 = (p1 - 2 * p0 + pm) / H**2
    convex_curvature = -sigma * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    return p0, d1, convex_curvature


@pytest.mark.parametrize(("contact", "oscillating", "sigma", "sign"), CASES, ids=IDS)
def test_pitch_curve_tangent_and_curvature(contact: str, oscillating: bool, sigma: int,
                                           sign: int) -> None:
    fol, cam, program, theta = setup(contact, oscillating, sigma, sign)
    m = program.evaluate(theta)
    pitch = cam.pitch(theta, m)
    p0, d1, curvature = pitch_reference(fol, program, sigma, theta)
    assert np.max(np.abs(pitch.xy - p0)) < 1e-10
    assert np.max(np.abs(pitch.speed - np.hypot(*d1.T))) < 1e-5
    assert np.max(np.abs(pitch.tangent - d1 / np.hypot(*d1.T)[:, None])) < 1e-7
    assert np.max(np.abs(1.0 / pitch.radius - curvature)) < 1e-5


@pytest.mark.parametrize(("contact", "oscillating", "sigma", "sign"), CASES, ids=IDS)
def test_pitch_parts_are_the_stacked_arithmetic_to_the_bit(contact: str, oscillating: bool,
                                                            sigma: int, sign: int) -> None:
    """The radius and pressure angle the sizing measures on the curve's components are the
    pitch curve's radius and the angle of the plane helpers on the stacked trace, bit for bit
    (signed zeros and infinities too), joints and all."""
    fol, cam, program, _ = setup(contact, oscillating, sigma, sign)
    _, theta, m = program.segment_grid(math.radians(0.5))
    m[:, ::7] = 0.0  # rests of every kind: s′, s″ zero (and s)
    centred = DiscCam(replace(fol, offset=0.0), RB, sigma)  # zeros in C′ as well
    for each in (cam, centred):
        assert np.array_equal(each.pitch_radius(m).view(np.int64),
                              each.pitch(theta, m).radius.view(np.int64))
        if contact != "flat":
            f, df, _, moving = each.trace(m)
            stacked = signed_angle(moving, sigma * perp(df - sigma * perp(f)))
            assert np.array_equal(each.pressure_angle(theta, m).view(np.int64),
                                  stacked.view(np.int64))


@pytest.mark.parametrize(("contact", "oscillating", "sigma", "sign"), CASES, ids=IDS)
def test_pressure_angle_is_the_angle_between_normal_and_motion(
        contact: str, oscillating: bool, sigma: int, sign: int) -> None:
    fol, cam, program, theta = setup(contact, oscillating, sigma, sign)
    m = program.evaluate(theta)
    phi = cam.pressure_angle(theta, m)
    if contact == "flat":
        working = cam.working(theta, m)
        # the common normal is the face normal; the contact point moves about the pivot
        # (oscillating) or along +Y (translating)
        contact_frame = rot(working.xy, sigma * theta)
        if oscillating:
            psi = fol.rest_position(RB) + m[0]
            normal = np.stack((sign * np.sin(psi), np.cos(psi)), -1)
            moving = swing_direction(contact_frame, sign)
        else:
            normal = np.tile([0.0, 1.0], (len(theta), 1))
            moving = normal
    else:
        _, d1, _ = pitch_reference(fol, program, sigma, theta)
        tangent_frame = rot(d1, sigma * theta)
        normal = sigma * np.stack((-tangent_frame[:, 1], tangent_frame[:, 0]), -1)
        b0 = trace_in_frame(fol, m[0])
        b1 = trace_in_frame(fol, program.evaluate(theta + H)[0])
        moving = b1 - b0 if oscillating else np.tile([0.0, 1.0], (len(theta), 1))
        if oscillating:  # the direction a rise moves the trace point in
            moving *= np.sign(m[1] + 1e-300)[:, None]
            still = np.abs(m[1]) < 1e-9
            moving[still] = swing_direction(b0, sign)[still]
    cos = np.einsum("ij,ij->i", normal, moving) / np.hypot(*normal.T) / np.hypot(*moving.T)
    assert np.max(np.abs(np.cos(phi) - cos)) < 1e-6
    if not oscillating and contact != "flat":
        # the seed's formula, with the sign: tan φ = (σs′ − e)/(√(Rp² − e²) + s)
        rp = RB + fol.radius
        ref = np.arctan((sigma * m[1] - fol.offset) / (math.sqrt(rp**2 - fol.offset**2) + m[0]))
        assert np.max(np.abs(phi - ref)) < 1e-12


@pytest.mark.parametrize(("contact", "oscillating", "sigma", "sign"), CASES, ids=IDS)
def test_working_curve_is_the_envelope_of_the_follower(
        contact: str, oscillating: bool, sigma: int, sign: int) -> None:
    fol, cam, program, theta = setup(contact, oscillating, sigma, sign)
    m = program.evaluate(theta)
    working = cam.working(theta, m)
    if contact != "flat":
        # the pitch curve moved one radius along the inward normal −σ·perp(T)
        p0, d1, _ = pitch_reference(fol, program, sigma, theta)
        t = d1 / np.hypot(*d1.T)[:, None]
        inward = -sigma * np.stack((-t[:, 1], t[:, 0]), -1)
        assert np.max(np.abs(working.xy - (p0 + fol.radius * inward))) < 1e-7
        assert np.allclose(np.hypot(*(working.xy - p0).T), fol.radius, atol=1e-9)
    else:
        # intersect the face line at θ − h and θ + h (the envelope's characteristic point)
        def line(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            mm = program.evaluate(t)
            if oscillating:
                psi = fol.rest_position(RB) + mm[0]
                n = np.stack((-sign * np.sin(psi), -np.cos(psi)), -1)  # toward the cam
                point = np.array([sign * A, 0.0]) + F_OFF * n
            else:
                n = np.tile([0.0, -1.0], (len(t), 1))
                point = np.stack((np.zeros_like(t), RB + mm[0]), -1)
            n_cam, p_cam = rot(n, -sigma * t), rot(point, -sigma * t)
            return n_cam, np.einsum("ij,ij->i", n_cam, p_cam)

        n1, c1 = line(theta - H)
        n2, c2 = line(theta + H)
        det = n1[:, 0] * n2[:, 1] - n1[:, 1] * n2[:, 0]
        x = (c1 * n2[:, 1] - c2 * n1[:, 1]) / det
        y = (n1[:, 0] * c2 - n2[:, 0] * c1) / det
        assert np.max(np.hypot(x - working.xy[:, 0], y - working.xy[:, 1])) < 1e-6
        # and the face is tangent there: the curve's tangent is perpendicular to the face normal
        n0, _ = line(theta)
        moving = np.abs(working.speed) > 1e-3
        assert np.max(np.abs(np.einsum("ij,ij->i", working.tangent, n0))[moving]) < 1e-9


@pytest.mark.parametrize(("contact", "oscillating", "sigma", "sign"), CASES, ids=IDS)
def test_working_curve_curvature(contact: str, oscillating: bool, sigma: int, sign: int) -> None:
    _, cam, program, theta = setup(contact, oscillating, sigma, sign)

    def at(t: np.ndarray) -> np.ndarray:
        return cam.working(t, program.evaluate(t)).xy

    w = cam.working(theta, program.evaluate(theta))
    h = 1e-4  # larger than H: second differences of a curve that nearly stops lose digits
    p0, p1, pm = at(theta), at(theta + h), at(theta - h)
    d1, d2 = (p1 - pm) / (2 * h), (p1 - 2 * p0 + pm) / h**2
    # signed along the traversal; the envelope's own convention flips where it runs backwards
    curvature = -sigma * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    regular = w.speed > 0.5  # finite differences lose their digits where the curve stops
    exact = np.abs(1.0 / w.radius)
    assert np.all((np.abs(exact - np.abs(curvature)) < 2e-5 + 1e-4 * exact)[regular])


def test_full_cycle_shm_flat_follower_gives_a_circle() -> None:
    """THEORY §B: s = (h/2)(1 − cos θ) with a flat face is an eccentric of radius Rb + h/2."""
    from camfab.geometry.disc_geometry import disc_geometry

    design = load_design(DESIGNS / "seed-jump-eccentric.yaml")
    rb, h = 22.5, 75.0
    geom = disc_geometry(design)
    centre = np.array([0.0, -h / 2])  # lowest point of the follower at θ = 0
    exact = geom.dense.working.xy
    assert np.max(np.abs(np.hypot(*(exact - centre).T) - (rb + h / 2))) < 1e-9
    assert np.allclose(geom.dense.working.radius, rb + h / 2, atol=1e-9)
    sampled = geom.profile.vertices
    assert np.max(np.abs(np.hypot(*(sampled - centre).T) - (rb + h / 2))) < 1e-9
    assert geom.lift.max_mm < design.manufacturing.tolerance
