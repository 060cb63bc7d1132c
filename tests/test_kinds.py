"""Every cam type the design rules accept has a kind in the registry, and every kind implements
the protocol the pipeline calls."""

from __future__ import annotations

import inspect

from camfab.design.rules import SUPPORTED_CAM_TYPES
from camfab.kinds import REGISTRY, CamKind, kind_of


def test_every_supported_cam_type_has_a_kind() -> None:
    assert set(REGISTRY) == set(SUPPORTED_CAM_TYPES)


def test_every_kind_implements_the_protocol() -> None:
    wanted = {name for name, _ in inspect.getmembers(CamKind, inspect.isfunction)
              if not name.startswith("_")}
    assert wanted == {"check", "analyse", "part", "verify"}
    for cam_type in REGISTRY:
        kind = kind_of(cam_type)
        assert isinstance(kind.drives_both_ways, bool), cam_type
        for name in wanted:
            ours = inspect.signature(getattr(CamKind, name)).parameters
            theirs = inspect.signature(getattr(kind, name)).parameters
            assert list(theirs) == [p for p in ours if p != "self"], (cam_type, name)
