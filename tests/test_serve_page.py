"""The studio's page (``camfab serve``) driven in Debian's Chromium through Selenium
(chromium-driver; nothing downloads a browser), on a copy of an example: moving a slider brings
the pressure angle ``camfab check`` gives for that value; Save writes the edit into the YAML with
its comments; the file saved in another editor is followed; a design that does not load shows
its one located line over the last good picture; Size offers ``camfab size``'s answer and Build
lists the files it wrote; the 3-D view draws the part; no script error anywhere."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from .conftest import DESIGNS, chromium, page_wait, serving

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

#: A backstop (s) for waits on the page: a loaded machine is slow, a hung page is not.
BACKSTOP = 120.0
NAME = "seed-10-4"


@pytest.fixture(scope="module")
def browser() -> Any:
    driver = chromium("--window-size=1500,1000", "--use-angle=swiftshader",
                      "--enable-unsafe-swiftshader")
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def studio(tmp_path_factory: pytest.TempPathFactory, browser: Any) -> Iterator[Path]:
    """``camfab serve`` of a copy of the example, its page open; the design file."""
    file = tmp_path_factory.mktemp("page") / "design.yaml"
    shutil.copy(DESIGNS / f"{NAME}.yaml", file)
    with serving(file, BACKSTOP) as url:
        browser.get(url)
        page_wait(browser, "return document.body.dataset.ready === 'yes' && "
                           "+document.body.dataset.verified > 0")
        yield file


def front(browser: Any, script: str) -> Any:
    """*script* run on the report shown (``doc``: its document)."""
    return browser.execute_script(
        "const doc = document.getElementById('report-frame').contentDocument;"
        + script)


def settled(browser: Any) -> int:
    """Wait until the page has drawn its newest version; that version."""
    return int(page_wait(browser, "return document.body.dataset.busy !== 'yes' && "
                                  "document.body.dataset.version"))


def slide(browser: Any, path: str, value: float) -> None:
    """Move the slider of *path* to *value*, as a hand does (its input event), and wait for
    the redraw."""
    shown = int(browser.execute_script("return +document.body.dataset.version"))
    browser.execute_script(
        "const r = document.querySelector('input[type=range][data-path=\"' + arguments[0] + "
        "'\"]'); r.value = arguments[1]; r.dispatchEvent(new Event('input'));", path,
        str(value))
    page_wait(browser, "return +document.body.dataset.version > arguments[0] && "
                       "document.body.dataset.busy === 'no'", shown)


def pressure_angle(browser: Any) -> float:
    """The pressure-angle check's value (deg) in the report in front."""
    text = front(browser, "for (const row of doc.querySelectorAll('#findings tr')) {"
                          "  const cells = row.querySelectorAll('td');"
                          "  if (cells.length > 3 && cells[1].textContent === 'pressure_angle')"
                          "    return cells[3].textContent; } return null;")
    return float(text.split()[0])


def checked(file: Path, text: str) -> float:
    """The largest pressure angle (deg) ``camfab check`` says of design *text*."""
    other = file.with_name("checked.yaml")
    other.write_text(text)
    done = subprocess.run([sys.executable, "-m", "camfab", "check", other.name],
                          cwd=file.parent, capture_output=True, text=True, timeout=BACKSTOP)
    found = re.search(r"pressure_angle: pressure angle (?:reaches|[a-z ]+) ([0-9.]+)°",
                      done.stdout)
    assert found, done.stdout
    return float(found.group(1))


def test_a_slider_brings_the_pressure_angle_camfab_check_gives(browser: Any,
                                                                studio: Path) -> None:
    text = studio.read_text()
    before = pressure_angle(browser)
    assert before == pytest.approx(checked(studio, text), abs=0.01)
    slide(browser, "cam.base_radius", 36)
    after = pressure_angle(browser)
    assert after < before - 5
    assert after == pytest.approx(checked(studio, text.replace("base_radius: 20",
                                                               "base_radius: 36")), abs=0.01)
    assert browser.execute_script("return document.getElementById('edited').hidden") is False
    assert studio.read_text() == text  # not saved


def test_save_writes_the_edit_with_every_comment_kept(browser: Any, studio: Path) -> None:
    before = studio.read_text()
    slide(browser, "cam.base_radius", 30)
    browser.find_element("id", "save").click()
    page_wait(browser, "return document.getElementById('notice').textContent.startsWith('saved')")
    after = studio.read_text()
    assert after == before.replace("base_radius: 20          #", "base_radius: 30          #")
    assert after != before


def test_the_page_follows_the_file_saved_in_another_editor(browser: Any, studio: Path) -> None:
    shown = settled(browser)
    studio.write_text(studio.read_text().replace("base_radius: 30", "base_radius: 44"))
    page_wait(browser, "return +document.body.dataset.version > arguments[0] && "
                       "document.querySelector('input[type=number][data-path=\"cam.base_radius\"]')"
                       ".value === '44'", shown)
    page_wait(browser, "return +document.body.dataset.version === "
                       "+document.body.dataset.verified")
    assert pressure_angle(browser) == pytest.approx(checked(studio, studio.read_text()),
                                                    abs=0.01)


def test_a_design_that_does_not_load_shows_its_line_over_the_last_picture(
        browser: Any, studio: Path) -> None:
    good = studio.read_text()
    angle = pressure_angle(browser)
    studio.write_text(good.replace("roller_radius: 7", "roller_radius: -7"))
    line = page_wait(browser, "const e = document.getElementById('error');"
                              "return !e.hidden && e.textContent")
    number = next(i for i, text in enumerate(good.splitlines(), 1) if "roller_radius" in text)
    assert line.startswith(f"design.yaml:{number}: follower.roller_radius: "), line
    assert pressure_angle(browser) == angle  # the last good picture stays
    studio.write_text(good)
    page_wait(browser, "return document.getElementById('error').hidden")


def test_size_offers_camfab_size_s_answer_and_build_lists_its_files(browser: Any,
                                                                   studio: Path) -> None:
    browser.find_element("id", "size").click()
    shown = page_wait(browser, "const b = document.getElementById('apply-size');"
                               "return b && document.getElementById('notice').textContent")
    size = subprocess.run([sys.executable, "-m", "camfab", "size", studio.name],
                          cwd=studio.parent, capture_output=True, text=True, timeout=BACKSTOP)
    assert size.stdout.splitlines()[0] in shown
    least = float(re.search(r"least base radius ([0-9.]+) mm", size.stdout).group(1))
    version = settled(browser)
    browser.find_element("id", "apply-size").click()
    page_wait(browser, "return +document.body.dataset.version > arguments[0] && "
                       "document.body.dataset.busy === 'no'", version)
    value = browser.execute_script(
        "return +document.querySelector('input[type=number][data-path=\"cam.base_radius\"]')"
        ".value")
    assert value == pytest.approx(least)
    browser.find_element("id", "build").click()
    files = page_wait(browser, "const items = document.querySelectorAll('#files li');"
                               "return items.length && Array.from(items, i => i.textContent)")
    folder = studio.parent / "exports" / NAME
    assert sorted(files) == sorted(p.name for p in folder.iterdir())
    assert f"{NAME}.stl" in files


def test_the_3d_view_draws_the_part_and_no_script_fails(browser: Any, studio: Path) -> None:
    view = page_wait(browser, "const v = document.getElementById('view3d');"
                              "return v.dataset.ready === 'yes' && v")
    assert view.find_elements("css selector", "canvas") or "WebGL" in view.text
    before = browser.execute_script("return document.getElementById('view3d').dataset.frame")
    front(browser, "const s = doc.getElementById('angle'); s.value = '90';"
                   "s.dispatchEvent(new Event('input'));")
    page_wait(browser, "return document.getElementById('view3d').dataset.frame === '90'")
    assert before != "90"
    assert browser.execute_script("return window.camfabErrors") == 0
    assert front(browser, "return doc.body.dataset.errors") == "0"
