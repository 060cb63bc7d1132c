"""The studio's edits of the YAML text (``camfab.serve.yamledit``), held to an independent reader:
for every value the page offers in every example, the edited text read by PyYAML (camfab's
design reader) is the original's data with that one value changed, and every line but the
value's own is the original's, character for character; a word is quoted only where YAML would
read it as something else; a key a mapping lacks is added in its block or flow map, with the
file's line breaks; a comment after a value stays in its column; an anchored value keeps its
anchor (its aliases follow), an alias edited becomes that key's value alone, a block scalar is
replaced on its key's line, the keys after it intact; a path the design has not, one through an
alias of a mapping, a tagged value, or a value that is not a number, a word or true/false, is
refused; a text of 33,000 table points is composed once for many edits and reads."""

from __future__ import annotations

import copy
import time
from typing import Any

import pytest
import yaml

from .conftest import DESIGN_FILES
from .test_serve_yaml_fuzz import outline

yamledit = pytest.importorskip("camfab.serve.yamledit")


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


ANCHORED = ("cam:\n  thickness: &t 14   # plate\n  base_radius: 30\nfollower:\n"
            "  roller_length: *t\n  width: *t\n")


def test_an_anchored_value_keeps_its_anchor_and_its_aliases_follow() -> None:
    edited = yamledit.set_value(ANCHORED, "cam.thickness", 15)
    assert edited == ANCHORED.replace("&t 14", "&t 15")
    assert yaml.safe_load(edited)["follower"] == {"roller_length": 15, "width": 15}


def test_an_alias_edited_becomes_that_value_alone() -> None:
    edited = yamledit.set_value(ANCHORED, "follower.roller_length", 20)
    assert edited == ANCHORED.replace("roller_length: *t", "roller_length: 20")
    data = yaml.safe_load(edited)
    assert (data["cam"]["thickness"], data["follower"]) == (14, {"roller_length": 20, "width": 14})
    assert yamledit.get_value(edited, "follower.width") == 14


def test_a_value_inside_an_aliased_mapping_is_refused_in_one_line() -> None:
    text = "rest: &r {angle: 90}\nmotion:\n  - dwell: *r\n  - dwell: {angle: 10}\n"
    for path in ("motion[0].dwell.angle", "motion[0].angle"):
        with pytest.raises(yamledit.EditError, match=r"alias \*r .*\(line 1\); edit it there$"):
            yamledit.set_value(text, path, 5)
    assert yaml.safe_load(yamledit.set_value(text, "rest.angle", 80))["motion"] == [
        {"dwell": {"angle": 80}}, {"dwell": {"angle": 10}}]
    assert [f.path for f in yamledit.fields(text)] == ["rest.angle", "motion[1].dwell.angle"]


def test_a_tagged_value_is_refused() -> None:
    with pytest.raises(yamledit.EditError, match=r"^a\.b: carries the tag !!str "):
        yamledit.set_value("a:\n  b: !!str 31\n", "a.b", 32)


@pytest.mark.parametrize(("block", "kept"), [
    (">-\n    31\n", ""), ("|\n    31\n\n", ""), ("|+  # D_b = 62\n    31\n", "  # D_b = 62"),
])
def test_a_block_scalar_is_replaced_on_its_key_s_line(block: str, kept: str) -> None:
    text = f"cam:\n  base_radius: {block}  thickness: 14\nfollower: {{type: knife}}\n"
    edited = yamledit.set_value(text, "cam.base_radius", 32)
    assert edited == f"cam:\n  base_radius: 32{kept}\n  thickness: 14\nfollower: {{type: knife}}\n"
    assert yaml.safe_load(edited)["cam"] == {"base_radius": 32, "thickness": 14}
    added = yamledit.set_value(text, "cam.bore", 8)
    assert yaml.safe_load(added)["cam"]["bore"] == 8
    assert yamledit.set_value(text, "cam.thickness", 9).startswith(f"cam:\n  base_radius: {block}")


def test_a_null_before_the_next_key_is_written_after_its_colon() -> None:
    text = "cam:\n  bore:  # none yet\n  # the cam\n  base_radius: 20\nname:\n"
    edited = yamledit.set_value(text, "cam.bore", 8)
    assert edited == "cam:\n  bore: 8 # none yet\n  # the cam\n  base_radius: 20\nname:\n"
    assert yamledit.set_value(text, "name", "lobe") == text.replace("name:", "name: lobe")


def test_a_key_added_to_a_crlf_file_keeps_its_line_endings() -> None:
    text = "cam:\r\n  type: disc\r\n  base_radius: 20\r\nfollower: {type: knife}\r\n"
    edited = yamledit.set_value(text, "cam.bore", 8)
    assert edited == ("cam:\r\n  type: disc\r\n  base_radius: 20\r\n  bore: 8\r\n"
                      "follower: {type: knife}\r\n")
    last = "a:\r\n  b: 1"  # no line break at its end
    assert yamledit.set_value(last, "a.c", 2) == "a:\r\n  b: 1\r\n  c: 2\r\n"


def _table_design(points: int) -> str:
    rows = ",\n        ".join(f"[{100 * i / (points - 1):.6f}, {18 * i / (points - 1):.6f}]"
                               for i in range(points))
    return ("name: big  # a table law of many points\ncam:\n  type: disc\n  base_radius: 30\n"
            "  thickness: &t 8\nmotion:\n  - rise:\n      angle: 100\n      law: table\n"
            f"      points: [\n        {rows}]\n  - dwell: {{angle: 260}}\nfollower:\n"
            "  type: roller\n  roller_radius: 6\n  width: *t\n")


def test_a_text_is_composed_once_and_edited_in_place(monkeypatch: pytest.MonkeyPatch) -> None:
    text = _table_design(33_000)
    made: list[int] = []
    compose = yamledit.compose
    monkeypatch.setattr(yamledit, "compose", lambda t, pure=False: made.append(1) or compose(t))
    started = time.process_time()
    assert len(yamledit.fields(text)) == 9
    for path, value in [("cam.base_radius", 31), ("follower.width", 9), ("cam.bore", 10),
                        ("motion[0].rise.angle", 95.5), ("motion[1].angle", 265),
                        ("follower.roller_radius", "7"), ("cam.thickness", 8.5)]:
        text = yamledit.set_value(text, path, value)
        assert yamledit.get_value(text, path) == value
        assert len(yamledit.fields(text)) == 9 + ("bore: 10" in text)
    assert time.process_time() - started < 30.0  # CPU: composed once (seconds), not 8 times
    assert made == [1]
    kept = yamledit.document(text)
    assert outline(kept.root) == outline(compose(text).root)
