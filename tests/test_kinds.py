"""Every cam type the design file accepts has a kind in the registry, and every kind implements
the protocol the pipeline calls."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path
from typing import get_args

from camfab.design.model import Cam
from camfab.kinds import REGISTRY, CamKind, kind_of

PACKAGE = Path(__file__).resolve().parent.parent / "camfab"


def test_every_cam_type_of_the_design_file_has_a_kind() -> None:
    accepted = set(get_args(Cam.model_fields["type"].annotation))
    assert set(REGISTRY) == accepted
    for cam_type in accepted:
        assert kind_of(cam_type) is not None, cam_type


def test_every_kind_implements_the_protocol() -> None:
    wanted = {name for name, _ in inspect.getmembers(CamKind, inspect.isfunction)
              if not name.startswith("_")}
    assert wanted == {"check", "analyse", "part", "verify", "scene"}
    for cam_type in REGISTRY:
        kind = kind_of(cam_type)
        assert isinstance(kind.drives_both_ways, bool), cam_type
        for name in wanted:
            ours = inspect.signature(getattr(CamKind, name)).parameters
            theirs = inspect.signature(getattr(kind, name)).parameters
            assert list(theirs) == [p for p in ours if p != "self"], (cam_type, name)


def _names_the_cam_type(node: ast.AST) -> bool:
    """True for ``cam.type``, ``design.cam.type``, ``analysis.design.cam.type`` or ``cam_type``."""
    if isinstance(node, ast.Name):
        return node.id == "cam_type"
    return (isinstance(node, ast.Attribute) and node.attr == "type"
            and ((isinstance(node.value, ast.Name) and node.value.id == "cam")
                 or (isinstance(node.value, ast.Attribute) and node.value.attr == "cam")))


def _is_type_name(node: ast.AST) -> bool:
    """True for a string constant, or a tuple, list or set of them."""
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return bool(node.elts) and all(_is_type_name(e) for e in node.elts)
    return isinstance(node, ast.Constant) and isinstance(node.value, str)


def test_no_module_branches_on_the_cam_type() -> None:
    """What differs between cam types is asked of the type's row or its kind: no comparison of
    ``cam.type`` with a type's name (or a tuple of names) and no ``match`` on it anywhere."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Compare):
                sides = [node.left, *node.comparators]
                if any(map(_names_the_cam_type, sides)) and any(map(_is_type_name, sides)):
                    found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}")
            elif isinstance(node, ast.Match) and _names_the_cam_type(node.subject):
                found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}")
    assert found == []
