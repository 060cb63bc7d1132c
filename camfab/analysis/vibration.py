"""The follower train's vibration at speed (THEORY §J): the elastic model of
:mod:`camfab.analysis.elastic` set up from the design and read for what a designer asks of it —
the natural frequency, the dynamic error, the vibration left in each dwell, the dynamic contact
force and the speed at which it first lets go of the cam, and the acceleration's harmonics.

A spring-held follower leaves the cam where the contact force falls below zero (the dynamic
jump). A positive-drive cam (a groove, a conjugate pair, a globoid, a drum without a spring)
holds it both ways: the force's sign says which side drives, and where it changes, the
follower crosses its clearance (the backlash knock). SI units inside; the record's names say
their units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camfab.analysis.dynamics import G, trace_scale
from camfab.analysis.elastic import Train, contact_force, periodic_response, respond, rigid_force
from camfab.arrays import Array, Index
from camfab.design import Design
from camfab.motion.program import MotionProgram, cycle_angles

#: The dynamic jump speed is looked for from this share of the design speed ...
SEARCH_FROM = 0.02
#: ... to this many times it: a follower that holds at three times its speed holds at any
#: speed a designer runs it at.
SEARCH_TO = 3.0
#: Speeds tried in that range, geometrically spaced (4.3 % apart: a resonance of a train damped
#: at ζ = 0.05 is some 10 % wide), and besides them the speeds at which a harmonic of the
#: motion meets the train's natural frequency (ω = ω_d/k, the first :data:`RESONANCES`), where
#: a lightly damped train's narrow resonances lie; then the first bracket of a speed that holds
#: and one that does not is narrowed to :data:`JUMP_TOLERANCE` (relative).
SEARCH_SPEEDS = 121
RESONANCES = 60
JUMP_TOLERANCE = 1e-4
#: The cam-angle steps (rad) of the scan's grid and of the bracket's: the forcing's cubic between
#: points 2° apart is within some 1e-4 of the exact force, 1° apart some 1e-5, well inside what
#: a speed's search needs.
SCAN_STEP = math.radians(2.0)
SEARCH_STEP = math.radians(1.0)

#: The acceleration's harmonics are taken from this many samples of the turn, and shown up to
#: the larger of :data:`SPECTRUM_LEAST` and twice the natural frequency's order.
SPECTRUM_SAMPLES = 3600
SPECTRUM_LEAST = 40


@dataclass(frozen=True)
class Dwell:
    """The vibration left in one dwell: its segment, where it lies (deg) and the dynamic
    error's peak-to-peak swing over it (m)."""

    segment: int
    start_deg: float
    end_deg: float
    peak_to_peak_m: float


@dataclass(frozen=True)
class Vibration:
    """The elastic follower train at the design speed.

    ``theta`` (rad) is the analysis grid; ``error_m`` the dynamic error x − s at the trace
    point (m), of which ``static_m`` = −F_r/K is the train's compression under the rigid force
    (the spring, the loads and the inertia taken quasi-statically: what a train that did not
    vibrate would give) and the rest its vibration; ``force_N`` the elastic contact force along
    the follower's motion and ``rigid_N`` the rigid model's (N). ``one_sided`` is True where
    the follower can leave the cam (a spring holds it on one side), False where the cam holds
    it on both. ``jump_speed_rpm`` is the least speed, from ``searched_from_rpm``, at which a
    one-sided follower first leaves the cam (None: not below ``searched_to_rpm``;
    ``jump_at_every_speed``: it leaves it already at the first speed searched);
    ``flank_changes`` are the cam angles (deg) where a two-sided cam's force changes sign and
    the side it passes onto (+1 the side that pushes the follower along its motion).
    ``harmonics`` and ``amplitudes`` are the acceleration's harmonics (per turn) and their
    amplitudes (m/s² at the trace point); ``trace_m`` is the trace point's metres per unit of
    lift (mm, or rad of an arm's swing)."""

    train: Train
    speed_rpm: float
    theta: Array
    segment: Index
    error_m: Array
    static_m: Array
    force_N: Array
    rigid_N: Array
    one_sided: bool
    dwells: tuple[Dwell, ...]
    jump_speed_rpm: float | None
    searched_from_rpm: float
    searched_to_rpm: float
    jump_at_every_speed: bool
    flank_changes: tuple[tuple[float, int], ...]
    harmonics: Array
    amplitudes: Array
    trace_m: float

    @property
    def natural_Hz(self) -> float:
        """The train's natural frequency f_n = √((k_f + k_s)/m)/2π (Hz)."""
        return self.train.natural / (2.0 * math.pi)

    @property
    def frequency_ratio(self) -> float:
        """f_n over the cam's turning frequency (turns a second)."""
        return self.natural_Hz / (self.speed_rpm / 60.0)

    @property
    def max_error_m(self) -> float:
        return float(np.max(np.abs(self.error_m)))

    @property
    def max_error_at_deg(self) -> float:
        return _deg(self.theta[int(np.argmax(np.abs(self.error_m)))])

    @property
    def max_static_m(self) -> float:
        """The train's largest compression under the rigid force, |F_r|/K (m)."""
        return float(np.max(np.abs(self.static_m)))

    @property
    def max_ringing_m(self) -> float:
        """The largest departure of the mass from where the train's compression alone puts it,
        |x − s − static| (m): its vibration."""
        return float(np.max(np.abs(self.error_m - self.static_m)))

    @property
    def residual_m(self) -> float | None:
        """The largest peak-to-peak vibration over the dwells (m), None without a dwell."""
        return max((d.peak_to_peak_m for d in self.dwells), default=None)

    @property
    def min_force_N(self) -> float:
        return float(np.min(self.force_N))

    @property
    def min_force_at_deg(self) -> float:
        return _deg(self.theta[int(np.argmin(self.force_N))])

    @property
    def max_force_N(self) -> float:
        return float(np.max(self.force_N))


def _deg(theta: float) -> float:
    return round(math.degrees(float(theta)), 9) + 0.0


def spring_load(design: Design) -> float:
    """The constant load on a spring-held follower (N): the spring's preload, the external load
    and, with ``gravity``, the follower's weight."""
    spring, mass = design.spring, design.follower.mass or 0.0
    assert spring is not None
    rate = spring.rate * 1000.0
    preload = spring.preload if spring.preload is not None else rate * (
        (spring.initial_compression or 0.0) / 1000.0)
    return preload + spring.external_load + (mass * G if spring.gravity else 0.0)


def train_of(design: Design, held_by_spring: bool) -> Train | None:
    """The design's follower train at its trace point (SI), or None without a stiffness; a
    positive-drive cam's has no spring (*held_by_spring* False)."""
    fol, spring = design.follower, design.spring
    if fol.stiffness is None or fol.mass is None:
        return None
    if not held_by_spring or spring is None:
        return Train(fol.mass, fol.stiffness * 1000.0, 0.0, fol.train_damping_ratio)
    return Train(fol.mass, fol.stiffness * 1000.0, spring.rate * 1000.0,
                 fol.train_damping_ratio, spring.damping, spring_load(design))


def vibration(design: Design, program: MotionProgram, held_by_spring: bool, two_sided: bool,
              step: float) -> Vibration | None:
    """The elastic follower train of *design* at its speed on the analysis grid of *step*
    (rad), or None without a stiffness: held by its spring (*held_by_spring*) or not, by a cam
    that holds it on both sides (*two_sided*: the force's sign is the side that carries it) or
    on one (where the force falls below zero the follower leaves the cam)."""
    train = train_of(design, held_by_spring)
    omega = design.cam.omega
    if train is None or omega is None:
        return None
    scale = trace_scale(design)
    segment, theta, motion = program.segment_grid(step)
    response = respond(train, omega, theta, motion * scale)
    rigid, _ = rigid_force(train, omega, motion * scale)
    dwells = tuple(Dwell(seg.index, _deg(seg.start), _deg(seg.end),
                         float(np.ptp(response.error[segment == seg.index])))
                   for seg in program.segments if seg.kind == "dwell")
    speed = design.cam.speed_rpm
    assert speed is not None
    search = JumpSearch(None, SEARCH_FROM * speed, SEARCH_TO * speed, False)
    changes: tuple[tuple[float, int], ...] = ()
    if two_sided:
        changes = flank_changes(theta, response.force)
    else:
        search = jump_speed(train, program, scale, speed)
    harmonics, amplitudes = spectrum(program, omega, scale, train.natural / omega)
    return Vibration(train, speed, theta, segment, response.error,
                     -rigid / train.total_stiffness, response.force, rigid, not two_sided,
                     dwells, search.speed_rpm, search.low_rpm, search.high_rpm,
                     search.every_speed, changes, harmonics, amplitudes, scale)


@dataclass(frozen=True)
class JumpSearch:
    """The least speed (rpm) at which a one-sided follower first leaves the cam (None: at none
    searched), the speeds searched, and whether it leaves it already at the first."""

    speed_rpm: float | None
    low_rpm: float
    high_rpm: float
    every_speed: bool


def _min_forces(train: Train, theta: Array, motion: Array, speeds_rpm: Array) -> Array:
    """The least contact force (N) over the turn at each of *speeds_rpm*, on the grid
    *theta* of the *motion* (m and per radian)."""
    omega = np.asarray(speeds_rpm, dtype=np.float64) * (math.pi / 30.0)
    force, rate = rigid_force(train, omega[:, None], motion[:, None, :])
    error, error_rate = periodic_response(train, omega, theta, force, rate)
    return np.min(contact_force(train, omega, error, error_rate), axis=1)


def jump_speed(train: Train, program: MotionProgram, scale: float,
               speed_rpm: float) -> JumpSearch:
    """The least speed (rpm) at which the elastic train's contact force first falls below
    zero, searched from :data:`SEARCH_FROM` to :data:`SEARCH_TO` times *speed_rpm*. Speeds at
    which the undamped train resonates are stepped over (its force there has no bound, and the
    scan sees the rise toward it)."""
    _, coarse, coarse_motion = program.segment_grid(SCAN_STEP)
    _, theta, motion = program.segment_grid(SEARCH_STEP)
    coarse_motion, motion = coarse_motion * scale, motion * scale
    low_end, top = SEARCH_FROM * speed_rpm, SEARCH_TO * speed_rpm
    damped = train.natural * math.sqrt(max(1.0 - train.total_zeta**2, 0.0)) * 30.0 / math.pi
    resonant = damped / np.arange(1, RESONANCES + 1)
    speeds = np.union1d(np.geomspace(low_end, top, SEARCH_SPEEDS),
                        resonant[(resonant > low_end) & (resonant < top)])
    if train.total_zeta == 0.0:
        speeds = speeds[_away_from_resonance(train, speeds)]
    with np.errstate(all="ignore"):
        least = _min_forces(train, coarse, coarse_motion, speeds)
    lost = np.flatnonzero(~(least >= 0.0))
    if not lost.size:
        return JumpSearch(None, low_end, top, False)
    k = int(lost[0])
    if k == 0:
        return JumpSearch(float(speeds[0]), low_end, top, True)
    low, high = float(speeds[k - 1]), float(speeds[k])
    while high - low > JUMP_TOLERANCE * high:
        trials = np.linspace(low, high, 9)[1:-1]
        with np.errstate(all="ignore"):
            found = _min_forces(train, theta, motion, trials)
        bad = np.flatnonzero(~(found >= 0.0))
        if bad.size:
            high = float(trials[bad[0]])
            low = float(trials[bad[0] - 1]) if bad[0] > 0 else low
        else:
            low = float(trials[-1])
    return JumpSearch(high, low_end, top, False)


def _away_from_resonance(train: Train, speeds_rpm: Array) -> Array:
    """Which speeds leave an undamped train off its resonances (ω_n/ω a whole number)."""
    order = train.natural / (np.asarray(speeds_rpm) * (math.pi / 30.0))
    return np.abs(order - np.round(order)) > 1e-6 * order


#: A two-sided cam's force must pass this share of its largest value to change sides: the
#: ringing of a train about no force in a dwell (a few newtons' thousandths) floats the follower
#: in its clearance, it does not knock it across.
FLANK_SHARE = 0.01


def flank_changes(theta: Array, force: Array) -> tuple[tuple[float, int], ...]:
    """Where a two-sided cam's contact force changes sign (deg, the first angle at which it
    carries the follower on the new side by more than :data:`FLANK_SHARE` of its largest
    value) and the side it passes onto (+1: the side pushing the follower along its motion)."""
    least = FLANK_SHARE * float(np.max(np.abs(force)))
    sign = np.where(force > least, 1.0, np.where(force < -least, -1.0, 0.0))
    loaded = np.flatnonzero(sign != 0.0)
    if loaded.size < 2:
        return ()
    signs = sign[loaded]
    flips = np.flatnonzero(signs[1:] != signs[:-1]) + 1
    out = [(_deg(theta[loaded[k]]), int(signs[k])) for k in flips]
    if signs[0] != signs[-1]:  # a change across 0°
        out.insert(0, (_deg(theta[loaded[0]]) % 360.0, int(signs[0])))
    return tuple(out)


def spectrum(program: MotionProgram, omega: float, scale: float,
             order: float) -> tuple[Array, Array]:
    """The harmonics n = 1, 2, … of the follower's acceleration over a turn and their
    amplitudes at the speed *omega* (rad/s; m/s² at the trace point, *scale* m per unit of
    lift), up to the larger of :data:`SPECTRUM_LEAST` and twice *order* (the natural
    frequency's)."""
    theta = cycle_angles(2.0 * math.pi / SPECTRUM_SAMPLES)
    acceleration = program.evaluate(theta)[2] * (scale * omega * omega)
    coefficients = np.fft.rfft(acceleration) / theta.size
    count = min(max(SPECTRUM_LEAST, math.ceil(2.0 * order)), coefficients.size - 1)
    harmonics = np.arange(1, count + 1)
    return harmonics, 2.0 * np.abs(coefficients[1:count + 1])
