"""``python -m benchmarks.dashboard_screenshot [OUT.png]``: the dashboard during ``ego demo``,
as a new user sees it, photographed by the system's headless Chromium (docs/dashboard.png).
"""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]  # fmt: skip


def main(argv: list[str]) -> int:
    from playwright.sync_api import sync_playwright

    out = Path(argv[0] if argv else "docs/dashboard.png")
    demo = subprocess.Popen(
        [sys.executable, "-m", "ego", "demo", "--duration", "25", "--dashboard-address",
         "127.0.0.1:0"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )  # fmt: skip
    try:
        assert demo.stdout is not None
        url = ""
        while not url:
            line = demo.stdout.readline()
            if not line:
                raise RuntimeError("ego demo printed no dashboard URL")
            match = re.search(r"dashboard at (\S+)", line)
            url = match.group(1) if match else ""
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.goto(url)
            time.sleep(12)  # a path on the map, and ten seconds of plot
            page.screenshot(path=str(out), full_page=True)
            browser.close()
    finally:
        demo.terminate()
        demo.wait()
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
