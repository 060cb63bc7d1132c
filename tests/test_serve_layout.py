"""The studio's page (``camfab serve``) laid out in Debian's Chromium at a laptop's 1280 × 800 and
a desktop's 1920 × 1080, on a design whose checks fail: every failing check's message is there
to read (its text inside every box that clips it, in a type that is not tiny, with room to be
more than a column a word wide), the cam's drawing and the diagrams with text that can be read,
the 3-D part on the screen without scrolling, and no side panel that scrolls sideways."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from typing import Any

import pytest

from .conftest import DESIGNS, chromium, page_wait, serving

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

#: A design whose pressure angle fails (an error) and whose acceleration steps (a warning).
NAME = "seed-10-4"

#: Where a failing check's message cannot be read, as the page lays it out: the text's box
#: (its words, not its cell) against every box around it that clips what overflows it
#: (overflow other than visible, or paint containment: the studio lays the report's sections out
#: lazily), up to the report's frame and the window. A box that scrolls may hold the text
#: below or above what it shows, never beside it: a message is read without scrolling sideways.
UNREAD = r"""
const frame = document.getElementById('report-frame');
const doc = frame.contentDocument, win = frame.contentWindow;
const out = [];
function clips(style) {
  return style.overflowX !== 'visible' || style.overflowY !== 'visible'
    || /paint|strict|content/.test(style.contain) || style.contentVisibility === 'auto';
}
function scrolls(value) { return value === 'auto' || value === 'scroll'; }
const rows = doc.querySelectorAll('#findings tr.fail, #findings tr.warn');
if (!rows.length) { out.push('no failing check on the page'); }
rows.forEach(function (row) {
  const cell = row.cells[row.cells.length - 1];  // the message, the table's last column
  const name = row.cells[1].textContent;
  if (!cell.textContent.trim()) { out.push(name + ': no message'); return; }
  const range = doc.createRange();
  range.selectNodeContents(cell);
  const text = range.getBoundingClientRect();
  const size = parseFloat(win.getComputedStyle(cell).fontSize);
  if (size < 12) { out.push(name + ': type of ' + size + ' px'); }
  if (text.width < 200) { out.push(name + ': a column ' + text.width + ' px wide'); }
  for (let box = cell.parentElement; box && box !== doc.documentElement; box = box.parentElement) {
    const style = win.getComputedStyle(box);
    if (!clips(style)) { continue; }
    const r = box.getBoundingClientRect();
    if (text.left < r.left - 0.5 || text.right > r.right + 0.5) {
      out.push(name + ': cut at the sides by ' + box.tagName + '#' + box.id + '.' + box.className);
    }
    const top = text.top - r.top + box.scrollTop, bottom = text.bottom - r.top + box.scrollTop;
    const reached = scrolls(style.overflowY) && top >= -0.5 && bottom <= box.scrollHeight + 0.5;
    if (!reached && (text.top < r.top - 0.5 || text.bottom > r.bottom + 0.5)) {
      out.push(name + ': cut above or below by ' + box.tagName + '#' + box.id);
    }
  }
  // the report's own window: scrolled up and down, never sideways
  if (text.left < -0.5 || text.right > doc.documentElement.clientWidth + 0.5) {
    out.push(name + ': beyond the report frame\'s width');
  }
});
const shown = frame.getBoundingClientRect();
if (shown.left < 0 || shown.right > innerWidth || shown.bottom > innerHeight + 0.5) {
  out.push('the report frame runs off the window');
}
return out;
"""

#: Each figure of the report in the studio (the drawing, the diagrams, the figures at speed):
#: its section, the height (px) of its smallest text on the screen, and whether it is wider
#: than what its card shows (read only by scrolling sideways).
FIGURES = r"""
const doc = document.getElementById('report-frame').contentDocument;
return Array.prototype.map.call(doc.querySelectorAll('figure svg'), function (svg) {
  const scale = svg.getScreenCTM().a;
  const sizes = Array.prototype.map.call(svg.querySelectorAll('text'), function (t) {
    return parseFloat(getComputedStyle(t).fontSize) * scale; });
  const figure = svg.closest('figure');
  return [svg.closest('section').id, Math.min.apply(null, sizes),
          figure.scrollWidth > figure.clientWidth + 1];
});
"""


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    driver = chromium("--use-angle=swiftshader", "--enable-unsafe-swiftshader")
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def address(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """The address of ``camfab serve`` of a copy of the design."""
    file = tmp_path_factory.mktemp("layout") / "design.yaml"
    shutil.copy(DESIGNS / f"{NAME}.yaml", file)
    with serving(file) as url:
        yield url


def opened(browser: Any, address: str, width: int, height: int) -> None:
    """The studio's page in a window (its viewport) *width* × *height* px, its verified report
    and its 3-D part drawn."""
    browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
    browser.get(address)
    page_wait(browser, "return document.body.dataset.ready === 'yes' && "
                       "+document.body.dataset.verified > 0 && "
                       "document.getElementById('view3d').dataset.ready === 'yes'")
    assert browser.execute_script("return [innerWidth, innerHeight]") == [width, height]


@pytest.mark.parametrize(("width", "height", "smallest"), [(1280, 800, 9.5), (1920, 1080, 11.0)],
                         ids=["1280x800", "1920x1080"])
def test_the_studio_shows_the_verdicts_the_drawing_and_the_part_readably(
        browser: Any, address: str, width: int, height: int, smallest: float) -> None:
    opened(browser, address, width, height)
    assert browser.execute_script(UNREAD) == []
    figures = browser.execute_script(FIGURES)
    assert {f[0] for f in figures} >= {"drawing", "diagrams"}
    for where, text, sideways in figures:
        assert text >= smallest and not sideways, (where, text, sideways)
    view = browser.execute_script(
        "const r = document.getElementById('view3d').getBoundingClientRect();"
        "return [r.left, r.top, r.right, r.bottom];")
    assert view[0] >= 0 and view[1] >= 0 and view[2] <= width and view[3] <= height, view
    assert view[2] - view[0] >= 240 and view[3] - view[1] >= 180, view
    side = browser.execute_script(
        "const s = document.getElementById('side'); return [s.scrollWidth, s.clientWidth];")
    assert side[0] <= side[1], side
    editor = browser.execute_script("return document.getElementById('editor').clientHeight")
    assert editor >= 250
    assert browser.execute_script(
        "return document.documentElement.scrollWidth <= innerWidth && "
        "document.documentElement.scrollHeight <= innerHeight")
    assert browser.execute_script("return window.camfabErrors") == 0
