"""Print what camfab says of broken designs: every example design and starter, mutated in ways
that break one rule or several at once, with the one line camfab prints (or OK) for each.

Run before and after a change to the design file's rules that must change no message, and
compare: when a file breaks several rules, the line names the first one, so this also catches
a change in the order the rules are checked.

    python scripts/rule_messages.py            # one line per variant, then the digest of all
    python scripts/rule_messages.py --summary  # the digest of all only
"""

from __future__ import annotations

import argparse
import copy
import hashlib
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parent.parent

CAM_TYPES = ("disc", "cylindrical", "circular-arc", "tangent", "groove", "conjugate",
             "constant-breadth", "linear", "globoidal")
FOLLOWER_TYPES = ("knife", "roller", "flat", "mushroom", "spherical")
#: Values that break a rule of the key they are given to, or of a rule relating it to others.
CAM_VALUES: dict[str, tuple[Any, ...]] = {
    "base_radius": (0.0005, 2, 400), "bore": (1, 60, 500), "radius": (3, 500),
    "length": (5, 500), "groove_depth": (0.0005, 9, 80), "groove_start": (0, 30, 400),
    "thickness": (2, 50), "outer_radius": (10, 300), "lift": (1, 100),
    "lift_angle": (10, 170), "nose_radius": (1e-12, 2, 50), "flank_angle": (5, 80),
    "top_dwell": (20,), "stroke": (50, 400), "base_height": (2, 80),
    "keyway": ({"width": 4, "depth": 2}, {"width": 40, "depth": 2}, {"width": 3, "depth": 90}),
}
FOLLOWER_VALUES: dict[str, tuple[Any, ...]] = {
    "offset": (5, -500), "roller_radius": (2, 60), "face_radius": (5, 500),
    "face_width": (1,), "pivot_distance": (30, 120, 500), "arm_length": (20, 90, 400),
    "face_offset": (-50, 40), "groove_clearance": (0.2, 5), "roller_spacing": (10, 200),
    "arm_angle": (20, 120), "pivot_side": ("left",),
}
MOTION = [{"rise": {"angle": 180, "lift": 10, "law": "cycloidal"}},
          {"return": {"angle": 180, "lift": 10, "law": "cycloidal"}}]
HALF_TURN = [{"rise": {"angle": 120, "lift": 10, "law": "cycloidal"}},
             {"dwell": {"angle": 60}}]
TRAVEL = [{"rise": {"travel": 60, "lift": 10, "law": "cycloidal"}},
          {"return": {"travel": 60, "lift": 10, "law": "polynomial"}}]


def variants(base: dict[str, Any]) -> Iterator[tuple[str, dict[str, Any]]]:
    """(label, data) for each mutation of *base*."""

    def edit(label: str, change: Any) -> tuple[str, dict[str, Any]]:
        data = copy.deepcopy(base)
        change(data)
        return label, data

    cam, fol = base.get("cam", {}), base.get("follower", {})
    for t in CAM_TYPES:
        yield edit(f"cam.type={t}", lambda d, t=t: d["cam"].update(type=t))
        yield edit(f"cam.type={t}+roller", lambda d, t=t: (
            d["cam"].update(type=t), d["follower"].update(type="roller", roller_radius=5)))
        yield edit(f"cam.type={t}+motion", lambda d, t=t: (
            d["cam"].update(type=t), d.update(motion=MOTION)))
    for f in FOLLOWER_TYPES:
        yield edit(f"follower.type={f}", lambda d, f=f: d["follower"].update(type=f))
    other = "translating" if fol.get("motion") == "oscillating" else "oscillating"
    yield edit(f"follower.motion={other}", lambda d: d["follower"].update(motion=other))
    yield edit(f"follower.motion={other}+arm", lambda d: (
        d["follower"].update(motion=other, pivot_distance=120, arm_length=90),
        d["follower"].pop("offset", None)))
    for key in cam:
        yield edit(f"-cam.{key}", lambda d, key=key: d["cam"].pop(key))
    for key in fol:
        yield edit(f"-follower.{key}", lambda d, key=key: d["follower"].pop(key))
    for key, values in CAM_VALUES.items():
        for v in values:
            yield edit(f"cam.{key}={v}", lambda d, key=key, v=v: d["cam"].update({key: v}))
    for key, values in FOLLOWER_VALUES.items():
        for v in values:
            yield edit(f"follower.{key}={v}",
                       lambda d, key=key, v=v: d["follower"].update({key: v}))
    yield edit("spring", lambda d: d.update(spring={"rate": 1}))
    yield edit("spring+both", lambda d: d.update(
        spring={"rate": 1, "preload": 2, "initial_compression": 3}))
    yield edit("-motion", lambda d: d.pop("motion", None))
    yield edit("motion", lambda d: d.update(motion=MOTION))
    yield edit("motion=half", lambda d: d.update(motion=HALF_TURN))
    yield edit("motion=travel", lambda d: d.update(motion=TRAVEL))
    yield edit("kerf", lambda d: d.update(manufacturing={"kerf": 70}))
    yield edit("tolerance", lambda d: d.update(manufacturing={"tolerance": 1e-4}))
    yield edit("pressure", lambda d: d.update(limits={"pressure_angle": 95}))
    yield edit("table_step", lambda d: d.update(table_step=7))


def messages() -> list[str]:
    """One line per variant: its label and camfab's first message (or OK)."""
    from camfab.errors import CamfabError
    from camfab.pipeline import design_from_text

    bases = [*sorted((ROOT / "designs").glob("*.yaml")),
             *sorted((ROOT / "camfab" / "starters").glob("*.yaml"))]
    lines = []
    for path in bases:
        base = yaml.safe_load(path.read_text(encoding="utf-8"))
        for label, data in variants(base):
            text = yaml.safe_dump(data, sort_keys=False)
            try:
                design_from_text(text, "case.yaml", path.parent)
                said = "OK"
            except CamfabError as exc:
                said = str(exc).replace("\n", " | ")
            lines.append(f"{path.parent.name}/{path.stem} {label}: {said}")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--summary", action="store_true", help="print the digest of all only")
    args = parser.parse_args()
    lines = messages()
    listing = "".join(line + "\n" for line in lines)
    if not args.summary:
        sys.stdout.write(listing)
    print(f"{len(lines)} variants, digest of all: "
          f"{hashlib.sha256(listing.encode()).hexdigest()}")


if __name__ == "__main__":
    main()
