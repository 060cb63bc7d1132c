"""The follower train's vibration at speed (THEORY §J): the elastic model of
:mod:`camfab.speed.elastic` set up from the design and read for what a designer asks of it —
the natural frequency, the dynamic error, the vibration left in each dwell, the dynamic contact
force and the speed at which it first lets go of the cam, and the acceleration's harmonics.

A spring-held follower leaves the cam where the contact force falls below zero (the dynamic
jump). A positive-drive cam (a groove, a conjugate pair, a globoid, a drum without a spring)
holds it both ways: the force's sign says which side drives, and where it changes, the
follower crosses its clearance (the backlash knock). SI units inside; the record's names say
their units.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from camfab.analysis.dynamics import trace_scale
from camfab.arrays import Array, Index
from camfab.design import Design
from camfab.design.train import Train, train_of
from camfab.motion.program import MotionProgram, ProgramSegment, cycle_angles
from camfab.speed.elastic import least_force, periodic_error, respond, rigid_force

#: The dynamic jump speed is looked for from this share of the design speed ...
SEARCH_FROM = 0.02
#: ... to this many times it: a follower that holds at three times its speed holds at any
#: speed a designer runs it at.
SEARCH_TO = 3.0
#: Speeds tried in that range, geometrically spaced (4.3 % apart: a resonance of a train damped
#: at ζ = 0.05 is some 10 % wide), and besides them the speeds at which a harmonic of the
#: motion meets the train's natural frequency (ω = ω_d/k, the first :data:`RESONANCES`), where
#: a lightly damped train's narrow resonances lie; then the first bracket of a speed that holds
#: and one that does not is narrowed to :data:`JUMP_TOLERANCE` (relative) on the bracket's
#: grid, and checked (narrowed again where that grid misjudged it) on the analysis grid, the
#: one the design speed is analysed on. The speed reported is the bracket's safe end, the one
#: at which the follower holds.
SEARCH_SPEEDS = 121
RESONANCES = 60
JUMP_TOLERANCE = 1e-7
#: The cam-angle steps (rad) of the scan's grid and of the bracket's: the forcing's cubic between
#: points 2° apart is within some 1e-4 of the exact force, 1° apart some 1e-5: enough to find
#: the bracket, which the analysis grid (some 1e-13) then narrows. Each speed's least force is
#: the continuous response's (:func:`~camfab.speed.elastic.least_force`), not its grid's.
SCAN_STEP = math.radians(2.0)
SEARCH_STEP = math.radians(1.0)
#: The narrowing of a bracket takes secant steps once it is this narrow (relative: the least
#: force is then close to linear in the speed), at most :data:`SECANT_ROUNDS` of them.
SECANT_FROM = 2e-3
SECANT_ROUNDS = 6

#: The acceleration's harmonics are taken from this many samples of the turn, and shown up to
#: the larger of :data:`SPECTRUM_LEAST` and twice the natural frequency's order.
SPECTRUM_SAMPLES = 3600
SPECTRUM_LEAST = 40


@dataclass(frozen=True)
class Dwell:
    """The vibration left in one dwell: its segment, where it lies (deg) and the mass's
    peak-to-peak swing over it (m; the dynamic error's, where the cam's lift is constant:
    :func:`dwell_swings`)."""

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
    lift (mm, or rad of an arm's swing); ``least_N`` the least contact force of the
    continuous response and ``least_at_rad`` where (:func:`~camfab.speed.elastic.
    least_force`)."""

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
    least_N: float = math.nan
    least_at_rad: float = math.nan

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
        """The least contact force over the turn (N): the continuous response's, which may
        fall between the grid's points."""
        return self.least_N

    @property
    def min_force_at_deg(self) -> float:
        return _deg(self.least_at_rad)

    @property
    def max_force_N(self) -> float:
        return float(np.max(self.force_N))


def _deg(theta: float) -> float:
    return round(math.degrees(float(theta)), 9) + 0.0


#: The most turns' ringing the train's periodic state may add up, 1/|1 − e^{λT}| (λ the train's
#: exponent in τ, T the turn's length): near a resonance with little damping it grows as
#: 1/(2π ζ_t f_n/f) (a whole multiple) or 1/δ (δ the phase the turn misses one by), and with it
#: the steady state and the rounding of e^{λT}, some 1e-16 of the turn's phase. Beyond this the
#: state is not computable to 1e-6, and the train is nothing like a cam follower: refused.
BUILD_UP_LIMIT = 1e6


def build_up(train: Train, omega: float) -> float:
    """1/|1 − e^{λT}| of the *train* at the cam speed *omega* (rad/s): over how many turns its
    ringing adds up in the periodic state (inf exactly at an undamped resonance)."""
    q = train.natural / omega
    zeta = train.total_zeta
    turn = complex(-zeta, math.sqrt(max(1.0 - zeta * zeta, 0.0))) * (2.0 * math.pi * q)
    gap = abs(1.0 - cmath.exp(turn))
    return math.inf if gap == 0.0 else 1.0 / gap


#: Below this natural frequency over the cam's turning frequency, a train whose ringing adds up
#: over more than :data:`BUILD_UP_LIMIT` turns is not at a resonance but far too soft: its
#: first resonance lies at the cam's own frequency.
SLOW_TRAIN_RATIO = 0.5


def resonance_note(design: Design, train: Train) -> str | None:
    """Why the periodic state of the *train* at the design's speed is not computed (its
    ringing adds up over more than :data:`BUILD_UP_LIMIT` turns: a resonance with next to no
    damping, or a train far slower than the cam), in words with what to change; None where it
    is."""
    omega = design.cam.omega
    assert omega is not None
    turns = build_up(train, omega)
    if turns <= BUILD_UP_LIMIT:
        return None
    ratio = train.natural / omega
    if ratio < SLOW_TRAIN_RATIO:
        return (f"the follower train's natural frequency is only {ratio:.3g} times the cam's "
                f"turning frequency at {design.cam.speed_rpm:.6g} rpm: far too soft to follow "
                f"the cam (its ringing adds up over some {min(turns, 1e300):.2g} turns), so its "
                "vibration, forces and stress have no value camfab can give (a train that far "
                "from rigid is no cam follower); raise follower.stiffness, or lower "
                "follower.mass or cam.speed_rpm")
    return (f"the follower train resonates with the cam at {design.cam.speed_rpm:.6g} rpm: its "
            f"natural frequency is {ratio:.6g} times the cam's turning frequency and its "
            f"damping ratio {train.total_zeta:.3g} lets its ringing add up over some "
            f"{min(turns, 1e300):.2g} turns, so its vibration, forces and stress have no value "
            "camfab can give (a train that far from rigid is no cam follower); raise "
            "follower.damping_ratio (0.02–0.1 is usual), or change follower.stiffness, "
            "follower.mass or cam.speed_rpm so that the natural frequency lies between two "
            "whole multiples of the cam's")


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
    swings = dwell_swings(program, segment, motion[0] * scale, response.error)
    dwells = tuple(Dwell(seg.index, _deg(seg.start), _deg(seg.end), float(swing))
                   for seg, swing in swings)
    speed = design.cam.speed_rpm
    assert speed is not None
    search = JumpSearch(None, SEARCH_FROM * speed, SEARCH_TO * speed, False)
    changes: tuple[tuple[float, int], ...] = ()
    if two_sided:
        changes = flank_changes(theta, response.force)
    else:
        search = jump_speed(train, program, scale, speed, step)
    harmonics, amplitudes = spectrum(program, omega, scale, train.natural / omega)
    return Vibration(train, speed, theta, segment, response.error,
                     -rigid / train.total_stiffness, response.force, rigid, not two_sided,
                     dwells, search.speed_rpm, search.low_rpm, search.high_rpm,
                     search.every_speed, changes, harmonics, amplitudes, scale, response.least,
                     response.least_at)


def dwell_swings(program: MotionProgram, segment: Index, lift: Array,
                 error: Array) -> list[tuple[ProgramSegment, Array]]:
    """Each dwell of *program* with the vibration left in it: the peak-to-peak swing (m) of the
    mass's position x = s + e over the dwell, from the cam's *lift* s and the dynamic *error* e
    (m) on the grid whose points lie in the segments *segment* (the last axis of *error*; any
    before it, several speeds). The cam's lift is constant in a dwell, so this is the error's
    swing; a polydyne cam's moves there (the tail of its damped solution) while the mass stands
    still."""
    out = []
    for seg in program.segments:
        if seg.kind == "dwell":
            inside = segment == seg.index
            moved = lift[inside] - lift[inside][0]
            out.append((seg, np.ptp(error[..., inside] + moved, axis=-1)))
    return out


#: A polydyne cam's vibration against speed is shown from this share of its design speed to
#: that, :data:`BAND_STEPS` steps each side (1 % apart).
BAND_FROM, BAND_TO, BAND_STEPS = 0.6, 1.4, 40


@dataclass(frozen=True)
class SpeedBand:
    """A polydyne cam's vibration against speed, beside its motion list cut directly as the
    cam: the speeds (rpm), the largest dwell swing (m) at each of the polydyne cam and of the
    direct cam (NaN where the train resonates: :data:`BUILD_UP_LIMIT`), and the band of speeds
    about the design speed over which the polydyne cam rings less (rpm)."""

    speeds_rpm: Array
    polydyne_m: Array
    direct_m: Array
    low_rpm: float
    high_rpm: float

    @property
    def at(self) -> int:
        """The index of the design speed (as many speeds below it as above)."""
        return self.speeds_rpm.size // 2


def speed_band(train: Train, cam: MotionProgram, direct: MotionProgram, speed_rpm: float,
               scale: float, step: float) -> SpeedBand:
    """The vibration against speed of the *cam* (a polydyne cam's lift, cut for *speed_rpm*)
    and of the *direct* cam (its motion list as the lift), with the *train* at its trace point
    (*scale* m per unit of lift) on the analysis grid of *step* (rad)."""
    steps = np.arange(-BAND_STEPS, BAND_STEPS + 1)
    share = np.where(steps < 0, 1.0 + steps * ((1.0 - BAND_FROM) / BAND_STEPS),
                     1.0 + steps * ((BAND_TO - 1.0) / BAND_STEPS))
    speeds = speed_rpm * share
    omega = speeds * (math.pi / 30.0)
    usable = np.array([build_up(train, w) <= BUILD_UP_LIMIT for w in omega])
    found = []
    for program in (cam, direct):
        segment, theta, motion = program.segment_grid(step)
        lifted = motion * scale
        with np.errstate(all="ignore"):
            force, rate = rigid_force(train, omega[:, None], lifted[:, None, :])
            error = periodic_error(train, omega, theta, force, rate)
        swings = [swing for _, swing in dwell_swings(program, segment, lifted[0], error)]
        found.append(np.where(usable, np.max(swings, axis=0), np.nan))
    polydyne, plain = found
    better = polydyne < plain
    low = high = BAND_STEPS
    while low > 0 and better[low - 1]:
        low -= 1
    while high < steps.size - 1 and better[high + 1]:
        high += 1
    return SpeedBand(speeds, polydyne, plain, float(speeds[low]), float(speeds[high]))


@dataclass(frozen=True)
class JumpSearch:
    """The least speed (rpm) at which a one-sided follower first leaves the cam (None: at none
    searched), the speeds searched, and whether it leaves it already at the first."""

    speed_rpm: float | None
    low_rpm: float
    high_rpm: float
    every_speed: bool


class _Least:
    """The least contact force (N) over the turn of the continuous periodic response at given
    speeds (rpm), on the grid of one cam-angle *step* (rad)."""

    def __init__(self, train: Train, program: MotionProgram, scale: float, step: float):
        _, self.theta, motion = program.segment_grid(step)
        self.motion = motion * scale
        self.train = train

    def __call__(self, speeds_rpm: Array | list[float], floor: float = math.inf) -> Array:
        """The least forces at *speeds_rpm*, exact as far as they decide the comparison with
        *floor* (:func:`~camfab.speed.elastic.least_force`)."""
        omega = np.asarray(speeds_rpm, dtype=np.float64) * (math.pi / 30.0)
        with np.errstate(all="ignore"):
            force, rate = rigid_force(self.train, omega[:, None], self.motion[:, None, :])
            return least_force(self.train, omega, self.theta, force, rate, floor)[0]


def jump_speed(train: Train, program: MotionProgram, scale: float, speed_rpm: float,
               step: float) -> JumpSearch:
    """The least speed (rpm) at which the elastic train's contact force first falls below
    zero, searched from :data:`SEARCH_FROM` to :data:`SEARCH_TO` times *speed_rpm*, to
    :data:`JUMP_TOLERANCE` on the analysis grid of *step* (rad), and reported at its safe end
    (a speed at which the follower holds). Speeds at which the undamped train resonates are
    stepped over (its force there has no bound, and the scan sees the rise toward it)."""
    scan = _Least(train, program, scale, SCAN_STEP)
    low_end, top = SEARCH_FROM * speed_rpm, SEARCH_TO * speed_rpm
    damped = train.natural * math.sqrt(max(1.0 - train.total_zeta**2, 0.0)) * 30.0 / math.pi
    resonant = damped / np.arange(1, RESONANCES + 1)
    speeds = np.union1d(np.geomspace(low_end, top, SEARCH_SPEEDS),
                        resonant[(resonant > low_end) & (resonant < top)])
    if train.total_zeta == 0.0:
        speeds = speeds[_away_from_resonance(train, speeds)]
    lost = np.flatnonzero(~(scan(speeds, 0.0) >= 0.0))
    if not lost.size:
        return JumpSearch(None, low_end, top, False)
    k = int(lost[0])
    if k == 0:
        return JumpSearch(float(speeds[0]), low_end, top, True)
    low, high = float(speeds[k - 1]), float(speeds[k])
    # narrowed on the bracket's grid, then checked (and where its grid misjudged the ends,
    # narrowed again) on the analysis grid
    for least in (_Least(train, program, scale, SEARCH_STEP),
                  _Least(train, program, scale, step)):
        confirmed = _confirm(least, low, high, low_end, top)
        if confirmed is None:  # it holds up to the top
            return JumpSearch(None, low_end, top, False)
        low, high, f_low, f_high = confirmed
        if f_low < 0.0:  # it leaves the cam already at the first speed searched
            return JumpSearch(low, low_end, top, True)
        low, high = _narrow(least, low, high, f_low, f_high)
    return JumpSearch(low, low_end, top, False)


def _confirm(least: _Least, low: float, high: float, low_end: float,
             top: float) -> tuple[float, float, float, float] | None:
    """The bracket [*low*, *high*] (rpm) checked on the grid of *least*, with the least forces
    at its ends: where a coarser grid misjudged an end (a speed within its error of the
    jump), the bracket is widened, eightfold each time, until it holds at its lower end (or
    that is *low_end*, where the least force is then negative) and not at its upper; None if
    it holds up to *top*."""
    width = high - low
    f_low, f_high = (float(v) for v in least([low, high]))
    while not f_low >= 0.0 and low > low_end:
        high, f_high = low, f_low
        width *= 8.0
        low = max(low - width, low_end)
        f_low = float(least([low])[0])
    while f_high >= 0.0:
        if high >= top:
            return None
        low, f_low = high, f_high
        width *= 8.0
        high = min(high + width, top)
        f_high = float(least([high])[0])
    return low, high, f_low, f_high


def _narrow(least: _Least, low: float, high: float, f_low: float,
            f_high: float) -> tuple[float, float]:
    """The bracket [*low*, *high*] (rpm; least forces *f_low* ≥ 0 > *f_high* on the grid of
    *least*) narrowed to :data:`JUMP_TOLERANCE`: rounds of seven speeds between the ends to
    :data:`SECANT_FROM`, then secant steps through the last two speeds tried, each tried on
    both sides of its guess at the tolerance and kept inside the bracket; rounds of seven
    speeds again where they have not closed it."""
    rounds = 0
    last = [(low, f_low), (high, f_high)]
    while high - low > JUMP_TOLERANCE * high:
        secant = rounds < SECANT_ROUNDS and high - low <= SECANT_FROM * high
        if secant:
            (x0, f0), (x1, f1) = last
            guess = x1 - f1 * (x1 - x0) / (f1 - f0) if f1 != f0 else 0.5 * (low + high)
            half = 0.4 * JUMP_TOLERANCE * high
            trials = np.clip([guess - half, guess + half], low + half, high - half)
        else:
            trials = np.linspace(low, high, 9)[1:-1]
        rounds += secant
        values = least(trials)
        for trial, value in zip(trials, values, strict=True):
            if value >= 0.0:
                low, f_low = float(trial), float(value)
            else:
                high, f_high = float(trial), float(value)
                break
        last = [(low, f_low), (high, f_high)] if not secant else [
            (float(trials[0]), float(values[0])), (float(trials[1]), float(values[1]))]
    return low, high


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
