#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Opens an HTML page in headless Chromium and checks it as a person would see it.

  check_page.py PAGE [--screenshot FILE.png] [--width 1200] [--height 2400]

Fails (exit 1, a line saying why) when: the page refers to anything outside
itself (a src or href that is not a data: URI or an #anchor: a report must be
one self-contained file); Chromium does not load it; the browser's console
shows anything (an error, an uncaught exception, a resource that did not
load: palpa's pages have no scripts, so any console line is a fault); the
screenshot is blank (fewer than 1% of its pixels differ from the background,
or fewer than 16 distinct colours). Exit 2 for a missing page or browser.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

from PIL import Image


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("page")
    ap.add_argument("--screenshot", default="")
    ap.add_argument("--width", type=int, default=1200)
    ap.add_argument("--height", type=int, default=2400)
    a = ap.parse_args()
    if not os.path.isfile(a.page):
        print("no page %s" % a.page)
        return 2
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        print("no chromium on PATH (scripts/setup.sh installs it)")
        return 2
    with open(a.page, encoding="utf-8") as f:
        html = f.read()
    for m in re.finditer(r'\b(?:src|href)\s*=\s*"([^"]*)"', html):
        target = m.group(1)
        if not (target.startswith("data:") or target.startswith("#")):
            print("the page refers to %s outside itself" % target)
            return 1
    shot = a.screenshot or os.path.join(tempfile.mkdtemp(prefix="palpa-page-"), "page.png")
    with tempfile.TemporaryDirectory(prefix="palpa-chromium-") as profile:
        run = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                              "--no-first-run", "--user-data-dir=" + profile, "--enable-logging=stderr", "--v=0",
                              "--window-size=%d,%d" % (a.width, a.height), "--screenshot=" + shot,
                              "file://" + os.path.abspath(a.page)],
                             capture_output=True, text=True, timeout=120)
    console = [l for l in run.stderr.splitlines() if ":CONSOLE" in l]
    if console:
        print("the browser's console: %s" % " | ".join(console))
        return 1
    if run.returncode != 0 or not os.path.isfile(shot):
        print("chromium did not load the page (exit %d): %s" % (run.returncode, run.stderr.strip()[-400:]))
        return 1
    img = Image.open(shot).convert("RGB")
    counts = img.getcolors(maxcolors=1 << 24)
    background = max(counts)[1]
    differ = sum(n for n, c in counts if max(abs(c[k] - background[k]) for k in range(3)) > 24)
    share = differ / (img.width * img.height)
    colours = len(counts)
    if share < 0.01 or colours < 16:
        print("the page looks blank: %.2f%% of its pixels differ from the background, %d colours" % (
            100 * share, colours))
        return 1
    print("ok: %s, %dx%d, %.1f%% drawn, %d colours" % (a.page, img.width, img.height, 100 * share, colours))
    return 0


if __name__ == "__main__":
    sys.exit(main())
