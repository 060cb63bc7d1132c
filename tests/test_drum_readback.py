"""Drum builds whose files hold the design: each small design below once failed its own
``verification`` check although the design was good. Each is built in a temporary folder and
its report read: the roller run through the groove of the STL read back stays within the
tolerance, and the STL is closed, with no sliver facet."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import yaml

from camfab.pipeline import build

from .conftest import DESIGNS


def demo_with(tmp_path: Path, **changes: Any) -> dict[str, Any]:
    """The demo drum with *changes* (``cam.radius=70`` style keys, dots as ``__``), built in
    *tmp_path*: its report's ``verification`` check."""
    design = yaml.safe_load((DESIGNS / "demo-cylindrical.yaml").read_text())
    for key, value in changes.items():
        node = design
        *path, last = key.split("__")
        for part in path:
            node = node[part]
        node[last] = value
    source = tmp_path / "design.yaml"
    source.write_text(yaml.safe_dump(design))
    build(source, tmp_path / "out")
    report = json.loads((tmp_path / "out" / f"{design['name']}-report.json").read_text())
    return next(c for c in report["checks"] if c["id"] == "verification")


def test_a_bored_drum_has_no_needle_facet_on_its_end_faces(tmp_path: Path) -> None:
    """Radius 70 with a 20 mm bore: a corner of the surface's polygon fell within 3e-5 mm of
    the line through a chord of the bore's, and the end faces had a needle facet each."""
    check = demo_with(tmp_path, cam__radius=70)
    assert check["ok"], check["message"]
    assert "no degenerate face, short edge or sliver" in check["message"]
