"""The machining settings as a user meets them: the design's ``machining:`` section, a shop's
settings file (``camfab build --machining shop.yaml``) under it, ``--gcode``, the units of their
values, and every refusal of settings no program can cut the cam with — one line naming the
file, its line and the key, status 2, nothing written."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import camfab.machining
from camfab.design import design_from_text
from camfab.design.loader import design_from_document
from camfab.design.shop import read_shop, shop_from_text, with_shop
from camfab.design.source import parse_yaml
from camfab.errors import DesignError, DesignFileError
from camfab.machining import Machined
from camfab.pipeline import load_design

from .conftest import DESIGNS, run_cli

#: A plate 12 mm thick, base radius 25 mm, lift 28 mm, bore 16 mm (some 106 mm across).
PLATE = "demo-cnc-cutter"
#: A drum whose groove is 12.1 mm wide (roller radius 6, clearance 0.1) and 8 mm deep.
DRUM = "demo-cylindrical"
#: A face-groove plate whose groove is 16.1 mm wide (roller radius 8, clearance 0.1).
GROOVE = "demo-groove-roller"
#: A concave globoid whose groove is 16.05 mm wide (roller radius 8, clearance 0.05).
GLOBOID = "demo-globoidal-concave"
#: A linear cam: a plate 240 mm long.
LINEAR = "demo-linear-roller"
#: A design in inches.
INCH = "demo-inch-flat"

SHOP = """\
# our router's usual tool
units: mm
machining:
  tool_diameter: 6
  feed: 800
  spindle_rpm: 12000
"""


def design_text(name: str, section: str | None) -> str:
    """The example design *name* with the machining *section* (its keys, one a line)."""
    text = (DESIGNS / f"{name}.yaml").read_text()
    if section is None:
        return text
    lines = "".join(f"  {line.strip()}\n" for line in section.strip().splitlines())
    return f"{text.rstrip()}\nmachining:\n{lines}"


def line_of(text: str, words: str) -> int:
    """The 1-based line of *text* that holds *words* (the last such line)."""
    found = [i for i, line in enumerate(text.splitlines(), 1) if words in line]
    assert found, words
    return found[-1]


def refusal(text: str, file: str = "d.yaml") -> DesignError:
    with pytest.raises(DesignError) as caught:
        design_from_text(text, file)
    return caught.value


# (id, design, section, the words on the line blamed, the field, words the message holds)
REFUSALS = [
    ("feed-zero", PLATE, "tool_diameter: 6\nfeed: 0", "feed: 0", "machining.feed",
     ["must be > 0", "got 0"]),
    ("feed-negative", PLATE, "tool_diameter: 6\nfeed: '-100 mm/min'", "feed:", "machining.feed",
     ["must be > 0"]),
    ("plunge-feed-zero", PLATE, "tool_diameter: 6\nfeed: 600\nplunge_feed: 0", "plunge_feed",
     "machining.plunge_feed", ["must be > 0"]),
    ("step-down-past-cut-length", PLATE, "tool_diameter: 6\nfeed: 600\ncut_length: 20\n"
     "step_down: 21", "step_down", "machining.step_down",
     ["deeper than the tool's length of cut (20 mm)"]),
    ("step-down-past-three-diameters", PLATE, "tool_diameter: 5\nfeed: 600\nstep_down: 16",
     "step_down", "machining.step_down", ["length of cut (15 mm, 3 × its diameter"]),
    ("plate-thicker-than-cut", PLATE, "tool_diameter: 6\nfeed: 600\ncut_length: 10",
     "cut_length", "machining.cut_length",
     ["length of cut (10 mm)", "the plate's thickness (cam.thickness, 12 mm)", "got 10"]),
    ("plate-thicker-than-three-diameters", PLATE, "tool_diameter: 3\nfeed: 600", "machining:",
     "machining.cut_length", ["(9 mm, 3 × its diameter", "cam.thickness, 12 mm"]),
    ("groove-deeper-than-cut", DRUM, "tool_diameter: 12\nfeed: 600\ncut_length: 6",
     "cut_length", "machining.cut_length", ["cam.groove_depth, 8 mm", "floor"]),
    ("drum-tool-wider-than-groove", DRUM, "tool_diameter: 12.2\nfeed: 600", "tool_diameter",
     "machining.tool_diameter", ["wider than the groove, 12.1 mm", "groove_clearance"]),
    ("groove-plate-tool-wider", GROOVE, "tool_diameter: 16.2\nfeed: 600", "tool_diameter",
     "machining.tool_diameter", ["wider than the groove, 16.1 mm"]),
    ("globoid-tool-wider", GLOBOID, "tool_diameter: 17\nfeed: 600", "tool_diameter",
     "machining.tool_diameter", ["wider than the groove, 16.05 mm"]),
    ("grbl-with-compensation", PLATE, "tool_diameter: 6\nfeed: 600\ndialect: grbl\n"
     "compensation: control", "compensation", "machining.compensation",
     ["Grbl has no cutter compensation", "compensation: path"]),
    ("grbl-drum", DRUM, "tool_diameter: 12\nfeed: 600\ndialect: grbl", "dialect",
     "machining.dialect", ["rotary A axis (4 axes)", "dialect: linuxcnc"]),
    ("grbl-globoid", GLOBOID, "tool_diameter: 16\nfeed: 600\ndialect: grbl", "dialect",
     "machining.dialect", ["rotary A and B axes (5 axes)"]),
    ("tool-larger-than-plate", PLATE, "tool_diameter: 110\nfeed: 600", "tool_diameter",
     "machining.tool_diameter", ["larger than the cam itself (some 106 mm"]),
    ("tool-longer-than-linear-plate", LINEAR, "tool_diameter: 250\nfeed: 600", "tool_diameter",
     "machining.tool_diameter", ["larger than the cam itself (some 240 mm"]),
    ("allowance-of-a-tool-radius", PLATE, "tool_diameter: 6\nfeed: 600\nfinish_allowance: 3",
     "finish_allowance", "machining.finish_allowance", ["less than the tool's radius (3 mm)"]),
    ("flutes-zero", PLATE, "tool_diameter: 6\nfeed: 600\nflutes: 0", "flutes",
     "machining.flutes", ["must be ≥ 1"]),
    ("unknown-dialect", PLATE, "tool_diameter: 6\nfeed: 600\ndialect: fanuc", "dialect",
     "machining.dialect", ["unknown value", "linuxcnc, grbl"]),
    ("misspelt-key", PLATE, "tool_diameter: 6\nfeed: 600\nstepdown: 2", "stepdown",
     "machining.stepdown", ["did you mean 'step_down'"]),
]


@pytest.mark.parametrize(("design", "section", "blamed", "field", "words"),
                         [case[1:] for case in REFUSALS], ids=[case[0] for case in REFUSALS])
def test_bad_settings_are_refused_on_their_line(design: str, section: str, blamed: str,
                                                field: str, words: list[str]) -> None:
    text = design_text(design, section)
    message = str(refusal(text))
    assert message.startswith(f"d.yaml:{line_of(text, blamed)}: {field}: "), message
    assert "\n" not in message
    for word in words:
        assert word in message, message


@pytest.mark.parametrize(("design", "section"), [
    (DRUM, "tool_diameter: 12\nfeed: 600"),  # the roller's diameter: exact walls
    (DRUM, "tool_diameter: 12.1\nfeed: 600"),  # as wide as the groove
    (GLOBOID, "tool_diameter: 16\nfeed: 600"),
    (GROOVE, "tool_diameter: 10\nfeed: 600"),  # narrower: a centre pass, then each wall
    (PLATE, "tool_diameter: 20\nfeed: 600"),  # wider than the 16 mm bore: the plate's program's
    (PLATE, "tool_diameter: 6\nfeed: 600\ncut_length: 12\nstep_down: 12"),
], ids=["drum-roller-diameter", "drum-groove-width", "globoid-roller-diameter",
        "groove-narrower-tool", "plate-tool-wider-than-bore", "plate-exactly-its-thickness"])
def test_settings_a_program_can_cut_with_are_taken(design: str, section: str) -> None:
    assert design_from_text(design_text(design, section), "d.yaml").machining is not None


def test_grbl_carries_the_tool_centre_path_when_no_compensation_is_given() -> None:
    design = design_from_text(design_text(PLATE, "tool_diameter: 6\nfeed: 600\ndialect: grbl"))
    assert design.machining is not None and design.machining.compensation == "path"
    linuxcnc = design_from_text(design_text(PLATE, "tool_diameter: 6\nfeed: 600"))
    assert linuxcnc.machining is not None and linuxcnc.machining.compensation == "control"


@pytest.mark.parametrize("feed", ["20", "'20 in/min'", "'508 mm/min'"])
def test_an_inch_design_s_feed_is_in_inches_per_minute(feed: str) -> None:
    design = design_from_text(design_text(INCH, f"tool_diameter: 0.25\nfeed: {feed}"))
    assert design.machining is not None
    assert math.isclose(design.machining.feed, 508.0)
    assert math.isclose(design.machining.tool_diameter, 6.35)
    assert math.isclose(design.machining.plunge, 508.0 / 3)


def test_an_inch_design_s_refusal_is_on_its_line() -> None:
    text = design_text(INCH, "tool_diameter: 0.25\nfeed: 20\nstep_down: 0.8")
    message = str(refusal(text))
    assert message.startswith(f"d.yaml:{line_of(text, 'step_down')}: machining.step_down: ")
    assert "length of cut (19.05 mm" in message  # 3 × 0.25 in


# --- a shop's settings file ---------------------------------------------------------------

def merged(design: str, section: str | None, shop: str, file: str = "d.yaml"):
    """The design *design* with *section* and the shop's settings *shop* under it."""
    doc = with_shop(parse_yaml(design_text(design, section), file), shop_from_text(shop,
                                                                                "shop.yaml"))
    return design_from_document(doc)


def test_the_design_s_own_keys_win_over_the_shop_s_key_by_key() -> None:
    design = merged(PLATE, "feed: 500\nstep_down: 2", SHOP)
    settings = design.machining
    assert settings is not None
    assert (settings.tool_diameter, settings.feed, settings.spindle_rpm, settings.step_down) == (
        6.0, 500.0, 12000.0, 2.0)


def test_the_shop_s_settings_stand_alone_for_a_design_without_a_section() -> None:
    settings = merged(PLATE, None, SHOP).machining
    assert settings is not None
    assert (settings.tool_diameter, settings.feed, settings.flutes) == (6.0, 800.0, 2)
    # a design asking for gcode in its outputs takes the shop's settings for its section
    doc = parse_yaml(design_text(DRUM, None) + "outputs: [report, gcode]\n", "drum.yaml")
    drum = design_from_document(with_shop(doc, shop_from_text(
        "machining:\n  tool_diameter: 12\n  feed: 600\n", "shop.yaml")))
    assert drum.machining is not None and drum.outputs == ("report", "gcode")


def test_the_shop_s_bare_numbers_are_in_its_own_units() -> None:
    inch_shop = "units: in\nmachining:\n  tool_diameter: 0.25\n  feed: 20\n  spindle_rpm: 9000\n"
    settings = merged(PLATE, None, inch_shop).machining
    assert settings is not None
    assert math.isclose(settings.tool_diameter, 6.35) and math.isclose(settings.feed, 508.0)
    assert settings.spindle_rpm == 9000.0
    # a millimetre shop on an inch design: its 6 mm tool, not 6 inches
    on_inches = merged(INCH, None, SHOP).machining
    assert on_inches is not None and on_inches.tool_diameter == 6.0
    assert on_inches.feed == 800.0
    # the design's own keys stay in the design's units
    own = merged(INCH, "feed: 20", SHOP).machining
    assert own is not None and math.isclose(own.feed, 508.0)


def test_a_shop_setting_a_design_cannot_take_is_refused_on_the_shop_file_s_line() -> None:
    shop = "machining:\n  tool_diameter: 13\n  feed: 800\n"
    with pytest.raises(DesignError) as caught:
        merged(DRUM, None, shop, file="drum.yaml")
    message = str(caught.value)
    assert message.startswith("shop.yaml:2: machining.tool_diameter (with drum.yaml): is wider "
                              "than the groove, 12.1 mm"), message
    # the design's own tool overrides the shop's: no refusal
    assert merged(DRUM, "tool_diameter: 12", shop).machining is not None
    # a rule of a key neither gives is on the design's section, when it has one
    text = design_text(DRUM, "cut_length: 6")
    with pytest.raises(DesignError) as caught:
        merged(DRUM, "cut_length: 6", "machining:\n  tool_diameter: 12\n  feed: 800\n")
    assert str(caught.value).startswith(f"d.yaml:{line_of(text, 'cut_length')}: "
                                        "machining.cut_length: ")


def test_a_design_section_that_is_not_a_mapping_is_reported_on_the_design() -> None:
    text = design_text(PLATE, None) + "machining: 6\n"
    doc = with_shop(parse_yaml(text, "d.yaml"), shop_from_text(SHOP, "shop.yaml"))
    with pytest.raises(DesignError, match=rf"^d.yaml:{line_of(text, 'machining')}: machining: "):
        design_from_document(doc)


# (id, shop file text, line, field ('' for the file's own), words the message holds)
BAD_SHOPS = [
    ("feed-zero", "units: mm\nmachining:\n  tool_diameter: 6\n  feed: 0\n", 4, "machining.feed",
     ["must be > 0"]),
    ("misspelt-key", "machining:\n  tool_diamter: 6\n", 2, "machining.tool_diamter",
     ["did you mean 'tool_diameter'"]),
    ("key-outside-the-section", "tool_diameter: 6\n", 1, "tool_diameter",
     ["give it under machining:"]),
    ("unknown-top-key", "units: mm\nmachinng:\n  feed: 3\n", 2, "machinng",
     ["did you mean 'machining'"]),
    ("unknown-units", "units: cm\nmachining:\n  feed: 3\n", 1, "units", ["mm, in"]),
    ("no-section", "units: mm\n", 1, "machining", ["required"]),
    ("section-not-a-mapping", "machining: 6\n", 1, "machining", ["must be a mapping"]),
    ("length-of-a-wrong-kind", "machining:\n  step_down: 2 kg\n", 2, "machining.step_down",
     ["must be a length"]),
    ("feed-without-time", "machining:\n  feed: 20 mm\n", 2, "machining.feed",
     ["must be a feed rate"]),
    ("words-for-a-number", "machining:\n  flutes: many\n", 2, "machining.flutes", []),
    ("empty", "", 1, "", ["empty"]),
    ("a-list", "- 6\n", 1, "", ["must be a mapping"]),
    ("not-yaml", "machining: [6\n", 2, "", ["invalid YAML"]),
]


@pytest.mark.parametrize(("text", "line", "field", "words"), [case[1:] for case in BAD_SHOPS],
                         ids=[case[0] for case in BAD_SHOPS])
def test_a_bad_shop_file_is_one_line_naming_it(text: str, line: int, field: str,
                                              words: list[str]) -> None:
    with pytest.raises(DesignError) as caught:
        shop_from_text(text, "shop.yaml")
    message = str(caught.value)
    head = f"shop.yaml:{line}: {field}: " if field else f"shop.yaml:{line}: "
    assert message.startswith(head), message
    assert "\n" not in message
    for word in words:
        assert word in message, message


def test_a_shop_file_that_cannot_be_read_is_named(tmp_path: Path) -> None:
    with pytest.raises(DesignFileError, match=r"shop\.yaml: no such file"):
        read_shop(tmp_path / "shop.yaml")
    (tmp_path / "bin.yaml").write_bytes(b"machining:\n  feed: \xff\n")
    with pytest.raises(DesignError, match=r"bin\.yaml:2: not a text file"):
        read_shop(tmp_path / "bin.yaml")


# --- the command line ---------------------------------------------------------------------

@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A folder with a plate, a drum (the plate's settings in neither) and the shop's file."""
    (tmp_path / "plate.yaml").write_text(design_text(PLATE, "feed: 500"))
    (tmp_path / "drum.yaml").write_text(design_text(DRUM, None))
    (tmp_path / "shop.yaml").write_text(SHOP)
    return tmp_path


def made(monkeypatch: pytest.MonkeyPatch) -> None:
    """Programs stand-ins: each holds the settings it was asked to cut with (as JSON), so the
    command line's settings are seen as the program's writer gets them."""

    def machine(analysis, part) -> Machined:
        design = analysis.design
        settings = design.machining.model_dump() if design.machining is not None else None
        return Machined(files={f"{design.name}.ngc": json.dumps(settings).encode()})

    monkeypatch.setattr(camfab.machining, "machine", machine)


def test_machining_gives_every_design_the_shop_s_settings_under_its_own(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    made(monkeypatch)
    drum = design_text(DRUM, "tool_diameter: 12")
    (folder / "drum.yaml").write_text(drum)
    result = run_cli("build", "--machining", "shop.yaml", "plate.yaml", "drum.yaml", "-j", "2",
                     "-o", "out", cwd=folder)
    assert result.exit_code in (0, 1), result.output
    plate = json.loads((folder / "out" / PLATE / f"{PLATE}.ngc").read_text())
    assert (plate["tool_diameter"], plate["feed"], plate["spindle_rpm"]) == (6.0, 500.0, 12000.0)
    cylinder = json.loads((folder / "out" / DRUM / f"{DRUM}.ngc").read_text())
    assert (cylinder["tool_diameter"], cylinder["feed"]) == (12.0, 800.0)


def test_gcode_with_the_design_s_own_section(folder: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    made(monkeypatch)
    (folder / "plate.yaml").write_text(design_text(PLATE, "tool_diameter: 8\nfeed: 500"))
    result = run_cli("build", "--gcode", "plate.yaml", "-o", "out", cwd=folder)
    assert result.exit_code in (0, 1), result.output
    written = json.loads((folder / "out" / f"{PLATE}.ngc").read_text())
    assert (written["tool_diameter"], written["feed"]) == (8.0, 500.0)


def test_the_library_loads_a_design_with_a_shop_s_settings(folder: Path) -> None:
    design = load_design(folder / "plate.yaml", shop=folder / "shop.yaml", also=("gcode",))
    assert design.machining is not None
    assert (design.machining.tool_diameter, design.machining.feed) == (6.0, 500.0)
    assert design.outputs is not None and "gcode" in design.outputs
    with pytest.raises(DesignError, match=r"machining\.tool_diameter: required"):
        load_design(folder / "plate.yaml")  # its feed alone, without the shop's tool


def test_gcode_without_settings_is_refused_and_nothing_written(folder: Path) -> None:
    result = run_cli("build", "--gcode", "drum.yaml", "-o", "out", cwd=folder)
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("drum.yaml: machining: --gcode needs the tool "
                                                   "and feeds"), lines
    assert "--machining FILE" in lines[0]
    assert not (folder / "out").exists()


def test_outputs_gcode_without_settings_is_refused_on_its_line(folder: Path) -> None:
    text = design_text(DRUM, None) + "outputs: [report, gcode]\n"
    (folder / "drum.yaml").write_text(text)
    result = run_cli("build", "drum.yaml", "-o", "out", cwd=folder)
    assert result.exit_code == 2
    assert result.stderr.startswith(f"drum.yaml:{line_of(text, 'outputs')}: outputs: gcode needs")
    assert not (folder / "out").exists()


def test_a_bad_shop_file_builds_nothing_and_says_so_once(folder: Path) -> None:
    (folder / "shop.yaml").write_text("units: mm\nmachining:\n  tool_diameter: 6\n  feed: 0\n")
    result = run_cli("build", "--machining", "shop.yaml", "plate.yaml", "drum.yaml", "-o",
                     "out", cwd=folder)
    assert result.exit_code == 2
    assert result.stderr.splitlines() == ["shop.yaml:4: machining.feed: must be > 0 (got 0)"]
    assert result.stdout == ""
    assert not (folder / "out").exists()
    missing = run_cli("build", "--machining", "none.yaml", "plate.yaml", "-o", "out",
                      cwd=folder)
    assert missing.exit_code == 2 and missing.stderr.strip() == "none.yaml: no such file"
    assert not (folder / "out").exists()


def test_a_shop_setting_one_design_cannot_take_refuses_that_design(
        folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    made(monkeypatch)
    (folder / "shop.yaml").write_text("machining:\n  tool_diameter: 13\n  feed: 800\n")
    result = run_cli("build", "--machining", "shop.yaml", "drum.yaml", "plate.yaml", "-j", "2",
                     "-o", "out", cwd=folder)
    assert result.exit_code == 2
    assert ("shop.yaml:2: machining.tool_diameter (with drum.yaml): is wider than the groove"
            in result.stderr), result.stderr
    assert not (folder / "out" / DRUM).exists()
    assert (folder / "out" / PLATE / f"{PLATE}.ngc").exists()


def test_build_help_tells_the_machining_options() -> None:
    text = " ".join(run_cli("build", "--help").output.split())
    assert "--gcode" in text and "--machining FILE" in text
    assert "override the file's key by key" in text
