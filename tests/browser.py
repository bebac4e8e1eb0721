"""Headless Chromium for the tests of saxum's HTML viewer (saxum.view): load a page from disk,
read the report that the page's self test (#selftest) writes into its DOM, take a
screenshot. Debian's `chromium` package; tests skip where it is not installed."""

import json
import re
import shutil
import subprocess
from pathlib import Path

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
# WebGL without a GPU (SwiftShader); no sandbox: the tests may run as root in a container
FLAGS = ["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--disable-gpu-sandbox", "--hide-scrollbars", "--window-size=1200,800",
         "--virtual-time-budget=20000"]
TIMEOUT = 120.0  # [s] a page that never settles fails the test instead of hanging it


def chromium() -> str | None:
    """The path of a Chromium (or Chrome) on PATH, or None."""
    return next((p for p in map(shutil.which, BROWSERS) if p), None)


def selftest(page: Path) -> dict:
    """Load `page` with #selftest and return the report it writes (saxum/viewer/viewer.js)."""
    done = subprocess.run([chromium(), *FLAGS, "--dump-dom", page.resolve().as_uri()
                           + "#selftest"], capture_output=True, text=True, timeout=TIMEOUT)
    found = re.search(r'<pre id="saxum-selftest"[^>]*>(.*?)</pre>', done.stdout, re.S)
    assert found, f"the page wrote no self-test report; chromium said: {done.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def screenshot(page: Path, png: Path, hash_: str = "") -> Path:
    """A 1200 x 800 px screenshot of `page` (with URL fragment `hash_`) into `png`."""
    subprocess.run([chromium(), *FLAGS, f"--screenshot={png}",
                    page.resolve().as_uri() + hash_], capture_output=True, timeout=TIMEOUT,
                   check=True)
    return png
