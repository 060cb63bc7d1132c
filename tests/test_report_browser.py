"""The HTML report in a real browser: headless Chromium (Debian's ``chromium``; ``.ci/run``
installs it) loads every example design's report offline, runs its script without an error,
and draws a page that is not blank."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from camfab.pipeline import analyse, load_design, render

from .conftest import DESIGN_FILES

REQUIRED = bool(os.environ.get("CAMFAB_REQUIRE_CONSUMERS"))

#: Flags for a headless run on a machine without a network or a display.
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars"]


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    if REQUIRED:
        pytest.fail("chromium is not installed")
    pytest.skip("chromium is not installed (apt-get install chromium)")


def browse(page: Path, *args: str) -> subprocess.CompletedProcess[str]:
    profile = page.parent / "chromium-profile"
    return subprocess.run([chromium(), *FLAGS, f"--user-data-dir={profile}", *args,
                           page.as_uri()], capture_output=True, text=True, timeout=120,
                          check=False)


@pytest.mark.parametrize("path", DESIGN_FILES, ids=[p.stem for p in DESIGN_FILES])
def test_report_renders_in_chromium(path: Path, tmp_path: Path) -> None:
    design = load_design(path)
    files = render(analyse(design)).files
    page = tmp_path / f"{design.name}-report.html"
    page.write_bytes(files[page.name])
    text = page.read_text()
    # self-contained: nothing fetched from anywhere (namespaces are names, not fetches)
    assert not re.search(r"""(src|href)\s*=\s*["']?https?:|url\(\s*["']?https?:|@import""",
                         text, flags=re.I)
    # the page's own script ran to the end, and no script error was raised
    dom = browse(page, "--dump-dom")
    assert dom.returncode == 0, dom.stderr[-2000:]
    body = re.search(r"<body[^>]*>", dom.stdout.split("</head>", 1)[-1])
    assert body is not None
    assert 'data-ready="yes"' in body.group(0), body.group(0)
    assert 'data-errors="0"' in body.group(0), body.group(0)
    assert dom.stdout.count("<svg") >= 2  # the drawing and the diagrams, inline
    # a screenshot that shows a page: many colours, ink over much of it
    shot = tmp_path / "shot.png"
    taken = browse(page, f"--screenshot={shot}", "--window-size=1200,2400")
    assert taken.returncode == 0 and shot.is_file(), taken.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    ink = np.any(pixels < 200, axis=-1)
    assert ink.mean() > 0.02
    assert len(np.unique(pixels.reshape(-1, 3)[::97], axis=0)) > 20
    assert np.ptp(np.nonzero(ink)[0]) > pixels.shape[0] / 2
