"""Redraw docs/img/report.png, the README's picture of ``sielaff report``.

Runs ``sielaff report decks/example.dat -o out/example.html`` and takes a screenshot
of the top of the page in Debian's headless Chromium (``apt-get install chromium``),
with the flags this machine's closed network needs.  Run from the repository root:

    python3 docs/make_report_image.py
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars"]


def main() -> int:
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        print("make_report_image: needs chromium (apt-get install chromium)", file=sys.stderr)
        return 2
    page = os.path.join(ROOT, "out", "example.html")
    subprocess.run([sys.executable, "-m", "sielaff", "report", "decks/example.dat", "-o",
                    "out/example.html"], cwd=ROOT, check=True)
    target = os.path.join(ROOT, "docs", "img", "report.png")
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile}",
                        f"--screenshot={target}", "--window-size=1000,1400",
                        "file://" + page], check=True, capture_output=True, timeout=300)
    print(target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
