"""camfab side by side with the cam module of the PyPI package ``mechanism`` (run by hand).

    pip install mechanism      # not a camfab dependency
    python benchmarks/mechanism_compare.py [--runs N] [--law cycloidal|harmonic]

One cam both tools can describe: a disc cam turning counter-clockwise, base circle 35 mm, a
translating follower on a radial line, rise 25 mm over 120°, dwell 60°, return over 120°, dwell
60°, the same law for rise and return (``mechanism`` applies one law to the whole program).
Followers: a knife edge, a 10 mm roller, the same roller offset 10 mm, and a flat face.

**Lift error, measured the same way for both tools.** Each tool's cam outline is taken as points
in camfab's frame, made a :class:`camfab.curves.profile.Profile` (for camfab's DXF, the lines
and arcs read back with ``read_cut_outline``), and the ideal follower is run over it with
``camfab.geometry.simulate.simulate`` every 0.1° of cam angle. Its lift is compared with the
design lift s(θ) from camfab's motion program (the closed forms of the laws; ``mechanism``'s own
s(θ) is checked against it and printed). Max and RMS error in mm and in % of the lift.

**mechanism's API and the conversion into camfab's frame.** ``Cam(motion=[("Rise", h, deg),
("Dwell", deg), ("Fall", h, deg), ...], degrees=True, omega=ω, rotation="ccw", h=step)``
evaluates s(θ) of its three laws (``naive``, ``harmonic``, ``cycloidal``) on ``thetas =
arange(0, 2π, step)`` (step 0.0062 rad, 1014 points, by default), and
``cam.<law>.get_profile(base, cam.thetas_r)`` returns the outline as x, y arrays: the polar curve
r = base + s(θ) drawn at the angle −θ (ccw) or +θ (cw), the follower on +X. Its ``profile()``
plot and its ``save_coordinates()`` export fill that curve with ``base`` = the base circle as the
cam, and draw the roller's pitch curve as r = base + roller radius + s(θ): the cam surface is the
pitch curve moved radially inward by the roller radius, not along its normal. The profile takes no
follower offset (``eccentricity`` only enters ``get_base_circle`` and the animation) and no
follower type (a flat face gets the same r = base + s(θ)). The conversion: lengths are the mm
passed in (the package has no units); the points are turned +90° ((x, y) → (−y, x)), which puts
θ = 0 (the start of the motion program, on the follower's line in both tools) from +X onto
camfab's +Y; the rotation sense is kept (both draw the cam at θ = 0 and turn it the stated way).
The script checks this on the knife edge, where ``mechanism``'s curve is exact: of the four
quarter turns and both senses, only this one follows the design (error at the chord level,
≈ 0 on the dwells).

**Time.** ``mechanism``: ``Cam(...)`` (which evaluates s, v, a, j of all three laws) and
``get_profile``; camfab: ``disc_geometry`` (the profile sampled within the tolerance, and the
follower run over it), ``analyse`` (geometry and every check) and ``analyse`` + ``render`` (all
files, verified), medians of N runs in process; and a fresh process each: a script importing
``mechanism``, computing the profile and writing it with ``save_coordinates``, against
``camfab build``. Exits with status 1 and a one-line message if ``mechanism`` is not installed.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import yaml
from timing import median_seconds, use_checkout, wall

if TYPE_CHECKING:
    from camfab.curves.follower import FollowerGeometry
    from camfab.curves.profile import Profile
    from camfab.design import Design
    from camfab.motion.program import MotionProgram

#: The cam both tools describe (mm, degrees).
BASE_RADIUS = 35.0
LIFT = 25.0
ROLLER_RADIUS = 10.0
OFFSET = 10.0
PROGRAM = (("rise", 120.0), ("dwell", 60.0), ("return", 120.0), ("dwell", 60.0))
SPEED_RPM = 1000.0

#: Cam-angle step at which the follower is run over each outline.
CHECK_STEP = math.radians(0.1)

#: mechanism's default step of θ (rad), and a finer one.
MECHANISM_STEPS = (0.0062, 0.001)

#: A fresh process computing mechanism's profile and writing it with its own export.
_MECHANISM_RUN = r"""
import sys
from mechanism import Cam
motion = [("Rise", {lift}, {a0}), ("Dwell", {a1}), ("Fall", {lift}, {a2}), ("Dwell", {a3})]
cam = Cam(motion=motion, degrees=True, omega={omega}, rotation="ccw")
cam.save_coordinates(file=sys.argv[1], kind="{law}", base={base})
"""


@dataclass(frozen=True)
class Case:
    """A follower both tools are run with, by its camfab design keys."""

    label: str
    follower: dict[str, Any]

    def geometry(self) -> FollowerGeometry:
        from camfab.curves.follower import FollowerGeometry

        radius = float(self.follower.get("roller_radius", 0.0))
        return FollowerGeometry(contact=self.follower["type"], radius=radius,
                                offset=float(self.follower.get("offset", 0.0)))

    def rest(self) -> float:
        """Height of the trace point (flat: of the face) at zero lift (mm)."""
        return self.geometry().rest_position(BASE_RADIUS)


CASES = (
    Case("knife edge", {"type": "knife"}),
    Case("roller r=10", {"type": "roller", "roller_radius": ROLLER_RADIUS}),
    Case("roller r=10, offset 10", {"type": "roller", "roller_radius": ROLLER_RADIUS,
                                    "offset": OFFSET}),
    Case("flat face", {"type": "flat", "face_width": 60.0}),
)


def design_mapping(case: Case, law: str, rotation: str = "ccw") -> dict[str, Any]:
    """The camfab design of the shared cam with *case*'s follower."""
    motion: list[dict[str, Any]] = []
    for kind, angle in PROGRAM:
        spec: dict[str, Any] = {"angle": angle}
        if kind != "dwell":
            spec["law"] = law
        if kind == "rise":
            spec["lift"] = LIFT
        motion.append({kind: spec})
    return {"name": "mechanism-compare", "units": "mm",
            "cam": {"type": "disc", "rotation": rotation, "speed_rpm": SPEED_RPM,
                    "base_radius": BASE_RADIUS, "thickness": 10.0, "bore": 10.0},
            "follower": {"motion": "translating", **case.follower},
            "motion": motion}


def camfab_design(case: Case, law: str, rotation: str = "ccw") -> Design:
    from camfab.pipeline import design_from_mapping

    return design_from_mapping(design_mapping(case, law, rotation))


def mechanism_cam(law: str, rotation: str = "ccw", step: float = MECHANISM_STEPS[0]) -> Any:
    """mechanism's ``Cam`` of the shared program (it evaluates every law it knows)."""
    from mechanism import Cam

    motion: list[tuple[Any, ...]] = []
    for kind, angle in PROGRAM:
        if kind == "dwell":
            motion.append(("Dwell", angle))
        else:
            motion.append(("Rise" if kind == "rise" else "Fall", LIFT, angle))
    return Cam(motion=motion, degrees=True, omega=SPEED_RPM * math.pi / 30.0,
               rotation=rotation, h=step)


def mechanism_outline(cam: Any, law: str, quarter_turns: int = 1) -> np.ndarray:
    """mechanism's cam outline r = Rb + s(θ) as (N, 2) points (mm) in camfab's frame: turned by
    *quarter_turns* × 90° (1 is the conversion; the others are for the frame check)."""
    x, y = getattr(cam, law).get_profile(BASE_RADIUS, cam.thetas_r)
    turn = math.radians(90.0 * quarter_turns)
    c, s = round(math.cos(turn)), round(math.sin(turn))
    return np.stack((c * x - s * y, s * x + c * y), axis=-1)


@dataclass(frozen=True)
class LiftError:
    """The follower run over an outline against the design lift (mm; infinite where the
    follower touched nothing)."""

    theta: np.ndarray
    error: np.ndarray

    @property
    def max_mm(self) -> float:
        return float(np.max(np.abs(self.error)))

    @property
    def rms_mm(self) -> float:
        return float(np.sqrt(np.mean(self.error**2)))

    @property
    def at_deg(self) -> float:
        return float(np.degrees(self.theta[int(np.argmax(np.abs(self.error)))]))

    def dwell_max_mm(self, program: MotionProgram, top: bool = False) -> float:
        """The largest error on the dwell on the base circle (*top*: at full lift), where the
        cam is a circle about its centre."""
        dwell = np.zeros(self.theta.size, dtype=bool)
        for seg, (kind, _) in zip(program.segments, PROGRAM, strict=True):
            if kind == "dwell" and (seg.s0 > 0.0) == top:
                dwell |= (self.theta > seg.start) & (self.theta < seg.start + seg.span)
        return float(np.max(np.abs(self.error[dwell])))


def lift_error(profile: Profile, case: Case, program: MotionProgram, sigma: int) -> LiftError:
    """Run *case*'s follower over *profile* (camfab's frame) and compare with s(θ)."""
    from camfab.geometry.simulate import simulate
    from camfab.motion.program import cycle_angles

    theta = cycle_angles(CHECK_STEP)
    error = simulate(profile, case.geometry(), theta, sigma) - case.rest()
    error -= program.evaluate(theta)[0]
    return LiftError(theta, np.where(np.isnan(error), np.inf, error))


def points_profile(xy: np.ndarray) -> Profile:
    from camfab.curves.profile import Profile

    return Profile.from_points(xy)


def camfab_outlines(design: Design) -> tuple[Profile, Profile, int]:
    """camfab's sampled profile, its DXF CUT outline read back (mm), and the outline's lines
    and arcs."""
    from camfab.export.dxf import read_cut_outline
    from camfab.pipeline import analyse, verify_exports

    analysis = analyse(design)
    assert analysis.geometry is not None
    _, exports = verify_exports(analysis, ("dxf",))
    dxf = next(iter(exports.files["dxf"].values()))
    outline = read_cut_outline(dxf, design.mm_per_unit)
    return analysis.geometry.profile, outline, len(outline.vertices)


def law_check(law: str) -> float:
    """Largest difference (mm) between mechanism's s(θ) and camfab's on mechanism's grid."""
    cam = mechanism_cam(law)
    program = camfab_design(CASES[0], law).program
    return float(np.max(np.abs(getattr(cam, law).S - program.evaluate(cam.thetas)[0])))


def frame_check(law: str) -> list[tuple[str, float, float, float]]:
    """The knife edge over mechanism's outline under each frame conversion: (conversion, max
    error, max error on the base-circle dwell, on the top dwell), mm."""
    case = CASES[0]
    rows = []
    for rotation, sigma in (("ccw", 1), ("cw", -1)):
        cam = mechanism_cam(law, rotation)
        program = camfab_design(case, law, rotation).program
        for quarter in (1, -1, 0, 2):
            for sense in (sigma, -sigma):
                profile = points_profile(mechanism_outline(cam, law, quarter))
                err = lift_error(profile, case, program, sense)
                name = (f"mechanism {rotation}: turn {90 * quarter:+4d}°, camfab "
                        f"{'same' if sense == sigma else 'opposite'} sense")
                rows.append((name, err.max_mm, err.dwell_max_mm(program),
                             err.dwell_max_mm(program, top=True)))
            if rotation == "cw":
                break  # the cw cam: the chosen conversion and its mirror only
    return rows


def error_rows(law: str) -> list[tuple[str, str, int, LiftError, float, float]]:
    """(case, outline, point count, error, error on the base-circle dwell and on the top
    dwell) of each tool's outline per case."""
    rows = []
    cams = {step: mechanism_cam(law, step=step) for step in MECHANISM_STEPS}
    for case in CASES:
        design = camfab_design(case, law)
        program = design.program
        profile, outline, entities = camfab_outlines(design)
        outlines: list[tuple[str, int, Profile]] = [
            ("camfab DXF CUT outline (read back)", entities, outline),
            ("camfab profile points", len(profile.vertices), profile)]
        for step, cam in cams.items():
            xy = mechanism_outline(cam, law)
            outlines.append((f"mechanism get_profile, h={step:g}", len(xy), points_profile(xy)))
        for name, count, prof in outlines:
            err = lift_error(prof, case, program, design.cam.sigma)
            rows.append((case.label, name, count, err, err.dwell_max_mm(program),
                         err.dwell_max_mm(program, top=True)))
    return rows


def mechanism_follower_check(law: str) -> tuple[float, float]:
    """mechanism's own followers, those its animation moves, over its cam r = Rb + s(θ): the
    roller (pushed out in steps of 0.001 until it clears the outline's points; every 4th θ) and
    the flat face (at the outline's farthest point across its width). Their largest departure
    (mm) from s(θ), as its ``RollerFollower.plot`` and ``FlatFollower.plot`` draw it."""
    from mechanism.cams import FlatFollower, RollerFollower

    cam = mechanism_cam(law)
    motion = getattr(cam, law)
    found = []
    for follower in (RollerFollower(motion, BASE_RADIUS, cam.thetas_r, 4,
                                    roller_radius=ROLLER_RADIUS),
                     FlatFollower(motion, BASE_RADIUS, cam.thetas_r, 1,
                                  face_width=float(CASES[3].follower["face_width"]))):
        index = np.fromiter(follower.indexes, dtype=int)
        found.append(float(np.max(np.abs(np.asarray(follower.S) - motion.S[index]))))
    return found[0], found[1]


def timings(law: str, runs: int) -> list[tuple[str, str]]:
    """(what, time) rows for the roller case."""
    from camfab.geometry.disc_geometry import (
        dense_curves,
        disc_cam,
        disc_geometry,
        sample_closed,
        segment_tolerances,
    )
    from camfab.pipeline import analyse, render

    case = CASES[1]
    design = camfab_design(case, law)
    rows = []
    for step in MECHANISM_STEPS:
        seconds = median_seconds(lambda s=step: mechanism_outline(mechanism_cam(law, step=s),
                                                                  law), runs)
        count = len(mechanism_cam(law, step=step).thetas)
        rows.append((f"mechanism Cam(...) + get_profile, h={step:g} ({count} points)",
                     f"{1e3 * seconds:.1f} ms"))
    cam, program = disc_cam(design), design.program
    tolerance = design.manufacturing.tolerance
    tolerances = segment_tolerances(cam, dense_curves(cam, program), tolerance,
                                    len(program.segments))
    working = sample_closed(cam, program, "working", tolerances)
    seconds = median_seconds(lambda: sample_closed(cam, program, "working", tolerances), runs)
    rows.append((f"camfab working curve alone (sample_closed, {len(working.xy)} points)",
                 f"{1e3 * seconds:.1f} ms"))
    seconds = median_seconds(lambda: disc_geometry(design), runs)
    rows.append((f"camfab disc_geometry, tolerance {design.manufacturing.tolerance:g} mm "
                 f"({len(disc_geometry(design).profile.vertices)} points)",
                 f"{1e3 * seconds:.1f} ms"))
    rows.append(("camfab analyse (geometry and every check)",
                 f"{1e3 * median_seconds(lambda: analyse(design), runs):.1f} ms"))
    rows.append(("camfab analyse + render (DXF, SVG, STL, report, CSV, verified)",
                 f"{1e3 * median_seconds(lambda: render(analyse(design)), runs):.1f} ms"))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mechanism-compare.yaml"
        path.write_text(yaml.safe_dump(design_mapping(case, law), sort_keys=False))
        angles = [angle for _, angle in PROGRAM]
        script = _MECHANISM_RUN.format(lift=LIFT, a0=angles[0], a1=angles[1], a2=angles[2],
                                       a3=angles[3], omega=SPEED_RPM * math.pi / 30.0, law=law,
                                       base=BASE_RADIUS)
        mech = [sys.executable, "-c", script, str(Path(folder) / "profile.csv")]
        out = Path(folder) / "out"
        build = [sys.executable, "-m", "camfab", "build", str(path), "-o", str(out)]
        wall(mech), wall(build)  # warm the file cache
        mech_s = statistics.median(wall(mech) for _ in range(runs))
        build_s = statistics.median(wall(build) for _ in range(runs))
    rows.append(("fresh process: import mechanism, profile, save_coordinates (CSV)",
                 f"{mech_s:.3f} s"))
    rows.append(("fresh process: camfab build (all files, verified)", f"{build_s:.3f} s"))
    return rows


def table(header: tuple[str, ...], rows: list[tuple[str, ...]], markdown: bool) -> None:
    if markdown:
        print("| " + " | ".join(header) + " |")
        print("| " + " | ".join("---" if i == 0 else "---:" for i in range(len(header))) + " |")
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(r[i]) for r in (header, *rows)) for i in range(len(header))]
        for row in (header, *rows):
            print("  ".join(c.ljust(w) if i == 0 else c.rjust(w)
                            for i, (c, w) in enumerate(zip(row, widths, strict=True))))
    print(flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=7, help="runs per median (default 7)")
    parser.add_argument("--law", choices=("cycloidal", "harmonic"), default="cycloidal")
    parser.add_argument("--markdown", action="store_true", help="print Markdown tables")
    options = parser.parse_args()
    try:
        import mechanism
    except ImportError:
        print("mechanism_compare.py needs the mechanism package, which camfab does not depend "
              "on: pip install mechanism", file=sys.stderr)
        return 1
    use_checkout()
    law, md = options.law, options.markdown
    version = getattr(mechanism, "__version__", None)
    if version is None:
        from importlib.metadata import version as dist_version

        version = dist_version("mechanism")
    print(f"mechanism {version}; law: {law}; base radius {BASE_RADIUS:g} mm, lift {LIFT:g} mm, "
          f"program {', '.join(f'{k} {a:g}°' for k, a in PROGRAM)}\n")
    print(f"s(θ): mechanism's against camfab's, largest difference {law_check(law):.1e} mm\n")

    print("Frame check: the knife edge over mechanism's outline, each conversion (mm)")
    table(("conversion", "max error", "base dwell", "top dwell"),
          [(name, f"{m:.4g}", f"{b:.2g}", f"{t:.2g}") for name, m, b, t in frame_check(law)],
          md)

    print(f"Lift error of each tool's outline (follower run every {math.degrees(CHECK_STEP):g}°"
          f", against s(θ); lift {LIFT:g} mm)")
    rows = [(case, name, str(count), f"{err.max_mm:.2e}", f"{100 * err.max_mm / LIFT:.3g}",
             f"{err.rms_mm:.2e}", f"{err.at_deg:.1f}", f"{base:.1e}", f"{top:.1e}")
            for case, name, count, err, base, top in error_rows(law)]
    table(("follower", "outline", "points", "max mm", "max % lift", "rms mm", "at deg",
           "base dwell mm", "top dwell mm"), rows, md)

    roller, flat = mechanism_follower_check(law)
    print("mechanism's own followers (those its animation moves) over its cam r = Rb + s(θ) "
          f"depart from s(θ) by at most:\nroller {roller:.3f} mm (found in steps of 0.001 mm), "
          f"flat face {flat:.3f} mm\n")

    print(f"Time, roller r=10 (medians of {options.runs})")
    table(("what", "time"), timings(law, options.runs), md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
