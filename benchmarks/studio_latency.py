"""The studio's edit-to-redraw latency (``camfab serve``), measured in Debian's Chromium.

For each example, a ``camfab serve`` of a copy of it is started and its page opened in headless
Chromium (Selenium, chromium-driver; a 1280 × 800 window; Chromium draws in software here, with
no GPU). Once the page has its first verified report, a numeric key is dragged: its slider is
moved step by step, each step as the page sends a drag's (the next when the redraw of the last
is done), watched from inside the page so that the harness does not poll it meanwhile. The
page measures each step with the Performance API, from the slider's input event to the frame
after the one that paints the new report (``window.camfabLatencies``), and splits it into the
wait for the answer (of which the server's own time, its Server-Timing) and the drawing
(``window.camfabParts``). Then the edits are saved and the file written again on disk, as
another editor saves it, and the time until the page shows it is taken. Printed per example:
the median and the 95th percentile of the redraws, the parts' medians, the time until the
verified report and the 3-D part follow the last step, and the time until a save on disk
shows (target: 0.5 s).

Targets: p95 ≤ 100 ms for plate cams, ≤ 300 ms for drums and globoids.

    python benchmarks/studio_latency.py --steps 30
    python benchmarks/studio_latency.py --steps 30 --only demo-globoidal-convex
"""

from __future__ import annotations

import argparse
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

#: (example, key dragged, plate?): one of every kind of cam.
EXAMPLES = (
    ("seed-10-4", "cam.base_radius", True),
    ("seed-10-3-oscillating", "cam.base_radius", True),
    ("demo-inch-flat", "cam.base_radius", True),
    ("demo-valve-at-speed", "cam.base_radius", True),
    ("seed-7-10-circular-arc", "cam.base_radius", True),
    ("demo-groove-roller", "cam.base_radius", True),
    ("demo-conjugate", "cam.base_radius", True),
    ("demo-constant-breadth", "cam.base_radius", True),
    ("demo-linear-roller", "follower.roller_radius", True),
    ("demo-cylindrical", "cam.radius", False),
    ("demo-globoidal-convex", "follower.roller_radius", False),
    ("demo-globoidal-concave", "follower.roller_radius", False),
)


#: One step of the drag, run in the page: the slider moved, and the answer given when the page
#: has drawn the new version (watched in the page, so that the harness asks nothing meanwhile).
STEP = """
const [key, value, done] = [arguments[0], arguments[1], arguments[arguments.length - 1]];
const body = document.body, shown = +body.dataset.version;
const watch = new MutationObserver(function () {
  if (+body.dataset.version > shown && body.dataset.busy === "no") { watch.disconnect(); done(); }
});
watch.observe(body, { attributes: true });
const range = document.querySelector('input[type=range][data-path="' + key + '"]');
range.value = value;
range.dispatchEvent(new Event("input"));
"""
#: The browser's window (px): a laptop's screen.
WINDOW = "1280,800"


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", f"--window-size={WINDOW}",
                 "--use-angle=swiftshader", "--enable-unsafe-swiftshader"):
        options.add_argument(flag)
    options.binary_location = shutil.which("chromium") or "/usr/bin/chromium"
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)


def wait(driver, script: str, timeout: float = 60.0) -> object:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.01)
    raise TimeoutError(script)


def drag(driver, design: Path, key: str, steps: int) -> tuple[list[float], list[list[float]],
                                                                float, float]:
    """Serve *design*, open it, drag *key*'s slider *steps* steps; the latencies (ms), their
    parts, the seconds until the last step's verified report and scene are shown, and the
    seconds from the file written on disk (after a Save) to the page's new version."""
    server = subprocess.Popen([sys.executable, "-m", "camfab", "serve", str(design),
                               "--no-open", "--port", "0"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    try:
        url = re.search(r"http://\S+", server.stdout.readline()).group(0)
        driver.get(url)
        wait(driver, "return +document.body.dataset.verified > 0 && "
                     "document.getElementById('view3d').dataset.ready === 'yes'")
        value = float(driver.execute_script(
            f"return +document.querySelector('input[type=range][data-path=\"{key}\"]').value"))
        for k in range(steps):
            step = value * (1.0 + 0.1 * np.sin(2 * np.pi * (k + 1) / steps))
            driver.execute_async_script(STEP, key, f"{step:.4f}")
        last = int(driver.execute_script("return +document.body.dataset.version"))
        started = time.monotonic()
        wait(driver, f"return +document.body.dataset.verified >= {last}")
        settled = time.monotonic() - started
        # the file saved in another editor: from the write to the page drawn anew
        driver.execute_script("document.getElementById('save').click()")
        wait(driver, "return document.getElementById('notice').textContent.startsWith('saved')")
        time.sleep(0.5)
        shown = int(driver.execute_script("return +document.body.dataset.version"))
        text = design.read_text(encoding="utf-8")
        started = time.monotonic()
        design.write_text(text + "# saved elsewhere\n", encoding="utf-8")
        wait(driver, f"return +document.body.dataset.version > {shown}")
        disk = time.monotonic() - started
        latencies = driver.execute_script("return window.camfabLatencies")
        parts = driver.execute_script("return window.camfabParts")
        errors = driver.execute_script("return window.camfabErrors")
        assert errors == 0, f"{errors} script errors"
        return latencies, parts, settled, disk
    finally:
        server.send_signal(signal.SIGINT)
        server.wait(15)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=30, help="slider steps per example")
    parser.add_argument("--only", action="append", help="this example only (repeatable)")
    args = parser.parse_args()
    driver = browser()
    driver.set_script_timeout(120)
    print(f"{'example':28s} {'kind':6s} {'p50':>7s} {'p95':>7s} {'answer':>7s} {'server':>7s} "
          f"{'draw':>7s} {'target':>7s} {'verified':>9s} {'disk':>6s}")
    try:
        with tempfile.TemporaryDirectory() as folder:
            for name, key, plate in EXAMPLES:
                if args.only and name not in args.only:
                    continue
                design = Path(folder) / f"{name}.yaml"
                shutil.copy(ROOT / "designs" / f"{name}.yaml", design)
                for table in (ROOT / "designs").glob("*.csv"):
                    shutil.copy(table, Path(folder) / table.name)
                latencies, parts, settled, disk = drag(driver, design, key, args.steps)
                # the first redraw after the page opened includes its first paint: left out
                ms = np.array(latencies[1:])
                split = np.array(parts[1:])
                target = 100 if plate else 300
                print(f"{name:28s} {'plate' if plate else '3-D':6s} "
                      f"{np.median(ms):7.1f} {np.percentile(ms, 95):7.1f} "
                      f"{np.median(split[:, 0]):7.1f} {np.median(split[:, 2]):7.1f} "
                      f"{np.median(split[:, 1]):7.1f} "
                      f"{target:7d} {settled:8.2f}s {disk:5.2f}s", flush=True)
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
