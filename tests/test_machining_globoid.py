"""A globoidal cam's machining program, read by LinuxCNC's interpreter (``rs274``) and mapped
back onto the cam through the machine the docs declare (docs/machining.md, "Globoidal cams"):
at every point of every move, between the program's points too, the cutter's axis lies on the
roller's axis within the tolerance (a cutter the groove's width), or the cutter touches the
exact flank along the groove's depth (the wall passes of a cutter the roller's size), and never
cuts into a flank; the cutter locations of ``NAME-cl.csv`` agree.

The reference is computed here from the design alone: the pivot at (C, 0, 0), the roller's
axis along a = (−cos ψ, 0, sin ψ), ψ = ψ₀ + s(θ) from the motion program, the cam turned by
−σθ, and the flanks Q ± r·n with n = (σD sin ψ, ψ′ℓ, σD cos ψ)/√(D² + ψ′²ℓ²) (THEORY §H) — not
from camfab's path."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from camfab.design import Design
from camfab.machining import Machined
from camfab.pipeline import analyse, design_from_text

from .rs274 import Moves, interpret

MM_PER_IN = 25.4

CONCAVE = """
name: hourglass
cam: {type: globoidal, globoid: concave, speed_rpm: 60, groove_depth: 14, bore: 30,
      outer_radius: 73, width: 80}
follower: {type: roller, motion: oscillating, pivot_distance: 130, arm_length: 60,
           roller_radius: 8, roller_length: 20, groove_clearance: 0.05}
motion:
  - rise:   {angle: 150, lift: 40, law: cycloidal}
  - dwell:  {angle: 30}
  - return: {angle: 150, law: cycloidal}
  - dwell:  {angle: 30}
limits: {pressure_angle: 40}
"""

#: The convex demo, clockwise, in inches (its lengths given in millimetres).
CONVEX = """
name: barrel
units: in
cam: {type: globoidal, globoid: convex, rotation: cw, speed_rpm: 60, groove_depth: 12 mm,
      outer_radius: 52 mm, width: 90 mm, bore: 25 mm}
follower: {type: roller, motion: oscillating, pivot_distance: 60 mm, arm_length: 110 mm,
           roller_radius: 7 mm, roller_length: 18 mm, groove_clearance: 0.05 mm,
           rest_angle: -10}
motion:
  - rise:   {angle: 150, lift: 25, law: modified-sine}
  - dwell:  {angle: 30}
  - return: {angle: 150, law: modified-sine}
  - dwell:  {angle: 30}
limits: {pressure_angle: 40}
"""


def design(text: str, machining: str) -> Design:
    return design_from_text(f"{text}\nmachining: {{{machining}}}\n")


def made(d: Design) -> Machined:
    from camfab.machining.globoid import machine

    assert d.machining is not None
    return machine(analyse(d), None, d.machining)  # type: ignore[arg-type]


# -- the reference, from the design --------------------------------------------------------------


@dataclass(frozen=True)
class Reference:
    """The roller's axis and the groove's flanks of a globoidal design, and the machine the docs
    declare (mm, rad)."""

    d: Design

    @property
    def c(self) -> float:
        return self.d.follower.pivot_distance  # type: ignore[return-value]

    @property
    def u(self) -> float:
        return 1.0 if self.d.cam.globoid == "concave" else -1.0

    @property
    def sigma(self) -> float:
        return 1.0 if self.d.cam.rotation == "ccw" else -1.0

    @property
    def surface(self) -> float:
        return self.c - self.u * self.d.cam.outer_radius  # type: ignore[operator]

    @property
    def floor(self) -> float:
        return self.surface + self.u * self.d.cam.groove_depth  # type: ignore[operator]

    @property
    def wall(self) -> float:
        f = self.d.follower
        return f.roller_radius + f.groove_clearance / 2  # type: ignore[operator]

    def swing(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ψ and ψ′ at cam angles *theta*."""
        program = self.d.program
        rest = self.d.follower.rest_angle
        rest = -program.max_lift / 2 if rest is None else rest
        s = program.evaluate(theta)
        return rest + s[0], s[1]

    def on_cam(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Points of the design's frame at cam angles *theta*, on the cam: Rot_z(−σθ)."""
        t = -self.sigma * theta
        c, s = np.cos(t), np.sin(t)
        return np.stack((c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1],
                         p[..., 2]), axis=-1)

    def axis_points(self, theta: np.ndarray, ells: np.ndarray) -> np.ndarray:
        """The roller axis' points ℓ from the pivot (len(ells), N, 3), on the cam."""
        psi, _ = self.swing(theta)
        ell = ells[:, None]
        q = np.stack((self.c - ell * np.cos(psi), 0 * ell * psi, ell * np.sin(psi)), axis=-1)
        return self.on_cam(q, theta)

    def flank(self, theta: np.ndarray, ells: np.ndarray, side: int) -> np.ndarray:
        """The flank on *side* (len(ells), N, 3), on the cam."""
        psi, dpsi = self.swing(theta)
        ell = ells[:, None]
        d = self.c - ell * np.cos(psi)
        n = np.stack((self.sigma * d * np.sin(psi), dpsi * ell + 0 * d,
                      self.sigma * d * np.cos(psi)), axis=-1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        q = np.stack((d, 0 * d, ell * np.sin(psi) + 0 * d), axis=-1)
        return self.on_cam(q + side * self.wall * n, theta)

    # the machine: a point p of the cam stands at b + R_Y(B)(R_X(A) M0 p − b)

    def machine_b(self) -> np.ndarray:
        m = self.d.machining.machine  # type: ignore[union-attr]
        return np.array([m.b_axis_x, 0.0, m.b_axis_z])

    def m0(self) -> np.ndarray:
        u = self.u
        return np.array([[0, 0, 1], [0, -u, 0], [u, 0, 0]], dtype=float)

    def tool_on_cam(self, xyz: np.ndarray, a_deg: np.ndarray,
                    b_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The cutter's tip at machine positions *xyz* (mm) and its axis (+Z), on the cam."""
        a, b = np.radians(a_deg), np.radians(b_deg)
        ry = np.zeros((a.size, 3, 3))
        ry[:, 0, 0] = ry[:, 2, 2] = np.cos(b)
        ry[:, 0, 2], ry[:, 2, 0] = np.sin(b), -np.sin(b)
        ry[:, 1, 1] = 1
        rx = np.zeros((a.size, 3, 3))
        rx[:, 1, 1] = rx[:, 2, 2] = np.cos(a)
        rx[:, 1, 2], rx[:, 2, 1] = -np.sin(a), np.sin(a)
        rx[:, 0, 0] = 1
        whole = np.einsum("ij,njk->nik", np.linalg.inv(self.m0()), np.linalg.inv(rx))
        base = self.machine_b()
        tip = np.einsum("nij,nj->ni", whole, base + np.einsum(
            "nij,nj->ni", np.linalg.inv(ry), xyz - base))
        axis = np.einsum("nij,nj->ni", whole, np.einsum("nij,j->ni", np.linalg.inv(ry),
                                                        np.array([0.0, 0.0, 1.0])))
        return tip, axis


def line_distance(points: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Distances of *points* (..., N, 3) from the lines through *origin* along unit
    *direction* (N, 3)."""
    rel = points - origin
    along = np.einsum("...i,...i->...", rel, direction)[..., None] * direction
    return np.linalg.norm(rel - along, axis=-1)


@dataclass(frozen=True)
class Samples:
    """The cutter along rs274's cutting moves, on the cam: cam angle θ (rad), tip, axis."""

    theta: np.ndarray
    tip: np.ndarray
    axis: np.ndarray
    move: np.ndarray


def sampled(ref: Reference, moves: Moves, units: str) -> Samples:
    cutting = moves.cutting()
    pieces, owners = [], []
    for i in range(len(cutting.kind)):
        one = Moves(cutting.kind[i:i + 1], cutting.start[i:i + 1], cutting.end[i:i + 1],
                    cutting.centre[i:i + 1], cutting.turn[i:i + 1], cutting.feed_mode[i:i + 1],
                    cutting.feed[i:i + 1], (), "")
        points = one.sample(0.05, 0.1)
        pieces.append(points)
        owners.append(np.full(len(points), i))
    points = np.concatenate(pieces)
    scale = MM_PER_IN if units == "in" else 1.0
    tip, axis = ref.tool_on_cam(points[:, :3] * scale, points[:, 3], points[:, 4])
    return Samples(ref.sigma * np.radians(points[:, 3]), tip, axis, np.concatenate(owners))


def check_program(d: Design, out: Machined, tmp: Path) -> tuple[Reference, Samples, np.ndarray]:
    """rs274 runs the program; on every sample the cutter never cuts into a flank, and either
    its axis lies on the roller's within the tolerance or it touches one flank along the
    groove's depth; returns the reference, the samples and which they are (0 on the roller's
    axis, ±1 on that wall)."""
    ref = Reference(d)
    assert d.machining is not None
    tol = d.manufacturing.tolerance
    program = out.files[f"{d.name}.ngc"]
    scale = MM_PER_IN if d.units == "in" else 1.0
    moves = interpret(program, {1: d.machining.tool_diameter / scale}, tmp, d.units)
    turning = np.abs(moves.end[:, 3:5] - moves.start[:, 3:5]).max(axis=1) > 0
    assert turning.any()
    assert set(moves.feed_mode[turning & (moves.kind != "traverse")]) == {"inverse"}
    s = sampled(ref, moves, d.units)
    ells = np.linspace(ref.surface, ref.floor, 9)
    on_axis = np.zeros(s.theta.size)
    for ell in (ref.surface, ref.floor):
        on_axis = np.maximum(on_axis, line_distance(ref.axis_points(s.theta, np.array([ell]))[0],
                                                    s.tip, s.axis))
    radius = d.machining.tool_diameter / 2
    which = np.where(on_axis <= tol, 0, 9)
    for side in (1, -1):
        gap = line_distance(ref.flank(s.theta, ells, side), s.tip, s.axis) - radius
        assert gap.min() >= -tol, f"the cutter cuts {-gap.min():.4g} mm into the flank"
        touching = np.abs(gap).max(axis=0) <= tol
        which = np.where((which == 9) & touching, side, which)
    assert (which != 9).all(), "a sample is neither on the roller's axis nor on a wall"
    # never past the floor: the tip's distance from the pivot along the axis
    pivot = ref.on_cam(np.broadcast_to([ref.c, 0.0, 0.0], s.tip.shape), s.theta)
    along = -ref.u * np.einsum("ni,ni->n", s.tip - pivot, s.axis)
    assert (ref.u * (along - ref.floor)).max() <= tol
    return ref, s, which


def covers_the_turn(theta: np.ndarray) -> bool:
    """Whether cam angles *theta* (rad) leave no gap over half a degree round the turn."""
    t = np.sort(np.mod(np.degrees(theta), 360.0))
    gaps = np.diff(np.concatenate((t, [t[0] + 360.0])))
    return bool(gaps.max() < 0.5)


# -- the tests -------------------------------------------------------------------------------------


def test_a_cutter_the_grooves_width_keeps_its_axis_on_the_rollers(tmp_path: Path) -> None:
    d = design(CONCAVE, "tool_diameter: 16.05, feed: 600")
    out = made(d)
    assert out.withheld is None
    ref, s, which = check_program(d, out, tmp_path)
    assert (which == 0).all()
    at_floor = np.abs(np.einsum("ni,ni->n", s.tip - ref.on_cam(np.broadcast_to(
        [ref.c, 0.0, 0.0], s.tip.shape), s.theta), s.axis) + ref.u * ref.floor) <= 0.01
    assert covers_the_turn(s.theta[at_floor])
    setup, = out.setups
    assert setup.axes == "XZAB" and setup.file == f"{d.name}.ngc"
    assert setup.minutes > 0 and setup.tools[0].diameter_mm == 16.05


def test_a_cutter_the_rollers_size_cuts_each_wall_off_its_axis(tmp_path: Path) -> None:
    """The roller's 16 mm cutter in the groove of 16.05 mm: the middle on the roller's axis,
    then each wall touched along the groove's depth all round, by climb milling; B's axis away
    from the pivot, so X and Z make up for it."""
    d = design(CONCAVE, "tool_diameter: 16, feed: 600, machine: {b_axis_x: 30, b_axis_z: -80}")
    out = made(d)
    assert out.withheld is None
    ref, s, which = check_program(d, out, tmp_path)
    for side in (0, 1, -1):
        assert covers_the_turn(s.theta[which == side]), side
    # climb milling: the cutter's edge (M3: turning clockwise seen from the spindle) meets each
    # wall against the cutter's feed along it
    mid = np.array([0.5 * (ref.surface + ref.floor)])
    for side in (1, -1):
        keep = which == side
        theta, tip, axis = s.theta[keep], s.tip[keep], s.axis[keep]
        wall = ref.flank(theta, mid, side)[0]
        rel = wall - tip
        toward = rel - np.einsum("ni,ni->n", rel, axis)[:, None] * axis
        edge = -np.cross(axis, toward)
        feed = np.diff(tip, axis=0)
        across = feed - np.einsum("ni,ni->n", feed, axis[1:])[:, None] * axis[1:]
        along = (s.move[keep][1:] == s.move[keep][:-1]) & (  # (not the plunges)
            np.linalg.norm(across, axis=1) > 1e-6)
        assert along.sum() > 1000
        assert (np.einsum("ni,ni->n", edge[1:], feed)[along] < 0).all()


def test_the_convex_program_in_inches_clockwise(tmp_path: Path) -> None:
    d = design(CONVEX, 'tool_diameter: 14 mm, feed: "600 mm/min", '
               "machine: {b_axis_x: -1, b_axis_z: 2}")
    out = made(d)
    assert out.withheld is None
    program = out.files["barrel.ngc"].decode()
    assert "G20" in program.splitlines()
    _, s, which = check_program(d, out, tmp_path)
    for side in (0, 1, -1):
        assert covers_the_turn(s.theta[which == side]), side


def test_inverse_time_feeds_move_the_cutter_at_the_feed(tmp_path: Path) -> None:
    """Under G93, each move's F is 1/minutes: the faster of the tip and the axis' point at the
    blank's surface moves along the cam at the feed asked."""
    d = design(CONCAVE, "tool_diameter: 16.05, feed: 900")
    out = made(d)
    ref = Reference(d)
    moves = interpret(out.files[f"{d.name}.ngc"], {1: 16.05}, tmp_path).cutting()
    s = sampled(ref, moves, "mm")
    top = s.tip + s.axis * np.einsum(
        "ni,ni->n", ref.axis_points(s.theta, np.array([ref.surface]))[0] - s.tip,
        s.axis)[:, None]
    # rs274 turns an inverse-time F into the feed of the move's XYZ length (or its turn's),
    # which it prints to 0.0001: the moves whose feed that leaves four digits
    turning = np.flatnonzero((np.abs(moves.end[:, 3] - moves.start[:, 3]) > 0)
                             & (moves.feed >= 1.0))
    assert turning.size > 500
    travel = np.linalg.norm(moves.end[:, :3] - moves.start[:, :3], axis=1)
    travel = np.where(travel > 0, travel, np.linalg.norm(moves.end[:, 3:] - moves.start[:, 3:],
                                                         axis=1))
    speeds = []
    for i in turning:
        mine = s.move == i
        lengths = [np.linalg.norm(np.diff(p[mine], axis=0), axis=1).sum() for p in (s.tip, top)]
        speeds.append(max(lengths) / (travel[i] / moves.feed[i]))
    assert np.array(speeds) == pytest.approx(np.full(len(speeds), 900.0), rel=0.01)


def test_the_cutter_locations_lie_on_the_reference(tmp_path: Path) -> None:
    d = design(CONCAVE, "tool_diameter: 16, feed: 600, machine: {b_axis_z: 130}")
    out = made(d)
    ref = Reference(d)
    text = out.files[f"{d.name}-cl.csv"].decode().splitlines()
    assert text[0] == ("pass,move,cam_angle_deg,swing_deg,tip_x_mm,tip_y_mm,tip_z_mm,"
                       "axis_x,axis_y,axis_z")
    rows = [line.split(",") for line in text[1:]]
    assert {r[1] for r in rows} == {"approach", "cut"}
    values = np.array([[float(v) for v in r[2:]] for r in rows])
    theta = np.radians(values[:, 0])
    psi, _ = ref.swing(theta)
    assert np.degrees(psi) == pytest.approx(values[:, 1], abs=1e-5)
    tip, axis = values[:, 2:5], values[:, 5:8]
    a = ref.on_cam(np.stack((-np.cos(psi), 0 * psi, np.sin(psi)), axis=-1), theta)
    assert np.abs(axis + ref.u * a).max() < 2e-6  # from the tip out of the groove
    off = np.maximum(*(line_distance(ref.axis_points(theta, np.array([e]))[0], tip, axis)
                       for e in (ref.surface, ref.floor)))
    passes = np.array([int(r[0]) for r in rows])
    # the middle: on the roller's axis (to the file's six decimals, the axis' over ~70 mm)
    assert off[passes == 1].max() < 1e-4
    for number, side in ((2, 1), (3, -1)):  # the walls: the cutter touches the flank
        mine = passes == number
        gap = line_distance(ref.flank(theta[mine], np.linspace(ref.surface, ref.floor, 9),
                                      side), tip[mine], axis[mine]) - 8.0
        assert np.abs(gap).max() < 0.25 * d.manufacturing.tolerance
    pivot = ref.on_cam(np.broadcast_to([ref.c, 0.0, 0.0], tip.shape), theta)
    depth = -np.einsum("ni,ni->n", tip - pivot, axis) - ref.surface
    assert depth.max() == pytest.approx(14.0, abs=1e-4)


def test_a_cutter_too_small_is_refused_with_the_smallest_that_cuts() -> None:
    d = design(CONCAVE, "tool_diameter: 12, feed: 600")
    out = made(d)
    assert out.withheld is not None and not out.files
    assert "12 mm cutter is too small" in out.withheld
    smallest = float(out.withheld.split("at least ")[1].split(" mm")[0])
    assert 12 < smallest < 16
    fits = made(design(CONCAVE, f"tool_diameter: {smallest}, feed: 600"))
    assert fits.withheld is None
    over = made(design(CONCAVE, f"tool_diameter: {smallest * 0.999:.6f}, feed: 600"))
    assert over.withheld is not None


def test_a_build_writes_the_program_and_the_cutter_locations(tmp_path: Path) -> None:
    from camfab.pipeline import build

    source = tmp_path / "hourglass.yaml"
    source.write_text(f"{CONCAVE}\noutputs: [gcode]\n"
                      "machining: {tool_diameter: 16.05, feed: 600}\n")
    built = build(source, tmp_path / "out")
    assert {"hourglass.ngc", "hourglass-cl.csv"} <= {p.name for p in built.written}
    assert not built.not_produced
    assert math.isfinite(built.analysis.machining[0].minutes)


def test_an_unknown_key_of_the_machine_is_refused_where_it_stands() -> None:
    from camfab.errors import DesignError

    text = f"{CONCAVE}\nmachining:\n  tool_diameter: 16\n  feed: 600\n  machine: {{b_axis_y: 3}}\n"
    with pytest.raises(DesignError) as caught:
        design_from_text(text)
    told = str(caught.value)
    assert "machining.machine.b_axis_y" in told and "b_axis_x" in told
    line = next(i for i, row in enumerate(text.splitlines(), start=1) if "b_axis_y" in row)
    assert f":{line}:" in told
