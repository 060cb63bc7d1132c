"""The studio's edits of the YAML text (``camfab.serve.yamledit``), held to an independent reader:
for every value the page offers in every example, the edited text read by PyYAML (camfab's
design reader) is the original's data with that one value changed, and every line but the
value's own is the original's, character for character; a word is quoted only where YAML would
read it as something else; a key a mapping lacks is added in its block or flow map; a comment
after a value stays in its column; a path the design has not, or a value that is not a number,
a word or true/false, is refused."""

from __future__ import annotations

import copy
from typing import Any

import pytest
import yaml

from .conftest import DESIGN_FILES

yamledit = pytest.importorskip("camfab.serve.yamledit")
pytest.importorskip("ruamel.yaml")


def _set(data: Any, keys: list[str | int], value: Any) -> None:
    """*data* (PyYAML's) with the value at *keys* set, a segment's kind stepped into as the
    studio steps into it."""
    for key in keys[:-1]:
        data = data[key]
    data[keys[-1]] = value


def _model_keys(data: Any, keys: list[str | int]) -> list[str | int]:
    """*keys* with a motion segment's kind put in where the path leaves it out."""
    out: list[str | int] = []
    node = data
    for key in keys:
        if isinstance(node, dict) and len(node) == 1 and key not in node \
                and isinstance(next(iter(node.values())), dict):
            (kind,) = node
            out.append(kind)
            node = node[kind]
        out.append(key)
        node = node[key]
    return out


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_every_value_offered_is_changed_alone(path: Any) -> None:
    text = path.read_text(encoding="utf-8")
    original = yaml.safe_load(text)
    fields = yamledit.fields(text)
    assert fields
    for field in fields:
        if field.kind == "number":
            new: Any = round(field.value * 1.25 + 1, 6)
        elif field.choices:
            new = next(c for c in field.choices if c != field.value)
        else:
            new = field.value + " x"
        edited = yamledit.set_value(text, field.path, new)
        want = copy.deepcopy(original)
        _set(want, _model_keys(original, yamledit.parts(field.path)), new)
        assert yaml.safe_load(edited) == want, field.path
        before, after = text.splitlines(), edited.splitlines()
        assert len(before) == len(after)
        assert sum(a != b for a, b in zip(before, after, strict=True)) == 1, field.path
        assert yamledit.get_value(edited, field.path) == new


def test_a_segment_s_key_is_reached_with_or_without_its_kind() -> None:
    text = "motion:\n  - rise:   {angle: 110, lift: 9, law: harmonic}   # up\n"
    for path in ("motion[0].rise.lift", "motion[0].lift"):
        assert yamledit.set_value(text, path, 9.5) == (
            "motion:\n  - rise:   {angle: 110, lift: 9.5, law: harmonic}   # up\n")
    assert yamledit.set_value(text, "motion[0].blend", 0.2) == (
        "motion:\n  - rise:   {angle: 110, lift: 9, law: harmonic, blend: 0.2}   # up\n")


def test_a_key_is_added_to_a_block_and_a_comment_keeps_its_column() -> None:
    text = "cam:\n  type: disc\n  base_radius: 20     # D_b = 40\nfollower:\n  type: knife\n"
    assert yamledit.set_value(text, "cam.base_radius", 125.5) == (
        "cam:\n  type: disc\n  base_radius: 125.5  # D_b = 40\nfollower:\n  type: knife\n")
    assert yamledit.set_value(text, "cam.base_radius", 1234567890.25) == (
        "cam:\n  type: disc\n  base_radius: 1234567890.25 # D_b = 40\nfollower:\n"
        "  type: knife\n")
    assert yamledit.set_value(text, "follower.offset", 3) == text + "  offset: 3\n"


@pytest.mark.parametrize(("value", "written"), [
    ("1300 MPa", "1300 MPa"), ("cycloidal", "cycloidal"), ("yes", '"yes"'), ("on", '"on"'),
    ("null", '"null"'), ("12", '"12"'), ("a: b", '"a: b"'), ("#x", '"#x"'), (True, "true"),
    (2.0, "2"), (0.1, "0.1"), (1e-7, "1.0e-07"), (2.5e20, "2.5e+20"),
])
def test_a_word_is_quoted_only_where_yaml_would_read_it_otherwise(value: Any,
                                                                   written: str) -> None:
    text = "a:\n  b: 1\n"
    edited = yamledit.set_value(text, "a.b", value)
    assert edited == f"a:\n  b: {written}\n"
    assert yaml.safe_load(edited)["a"]["b"] == value


@pytest.mark.parametrize(("path", "value", "said"), [
    ("a.c.d", 1, "a.c.d: the design has no a.c"),
    ("a", 1, "a: holds a mapping, not a value"),
    ("l[5]", 1, "l[5]: the design has no such key"),
    ("a..b", 1, "not a path of the design"),
    ("", 1, "path: must be a key of the design"),
    ("a.b", float("nan"), "a.b: must be a finite number"),
    ("a.b", None, "a.b: must be a number, a word or true/false"),
    ("a.b", "two\nlines", "a.b: must be a number, a word or true/false"),
    ("a.csv", "x.csv", "a.csv: names a file"),
])
def test_what_the_file_cannot_take_is_refused(path: str, value: Any, said: str) -> None:
    with pytest.raises(yamledit.EditError, match=said.replace("[", r"\[").replace("]", r"\]")):
        yamledit.set_value("a:\n  b: 1\n  csv: t.csv\nl: [1, 2]\n", path, value)
