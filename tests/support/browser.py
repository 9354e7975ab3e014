"""Headless Chromium checks of an HTML report (issue 42): its width at a 1280 px window, a screenshot and
a print to PDF. Skipped where no `chromium` is installed (apt-get install chromium)."""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--no-first-run", "--disable-sync", "--hide-scrollbars"]
#: Appended to a copy of the page: the document's width after layout, where --dump-dom can read it.
MEASURE = "<script>document.title = 'scrollWidth=' + document.documentElement.scrollWidth;</script>"


@dataclass(frozen=True)
class Layout:
    scroll_width: int  # document.scrollWidth [px] at the window's width
    screenshot: Path
    pdf: Path


def layout(page: Path, folder: Path, width: int = 1280) -> Layout:
    """Open ``page`` in headless Chromium at ``width`` px: its scroll width, a screenshot, a PDF print. One
    launch does all three (on a copy whose title reports the width: the script draws nothing)."""
    measured = folder / f"{page.stem}-measured.html"
    measured.write_text(page.read_text(encoding="utf-8").replace("</body>", MEASURE + "</body>"),
                        encoding="utf-8")
    shot, pdf = folder / f"{page.stem}.png", folder / f"{page.stem}.pdf"
    dom = subprocess.run([CHROMIUM, *FLAGS, f"--window-size={width},1600", "--dump-dom",
                          f"--screenshot={shot}", "--no-pdf-header-footer", f"--print-to-pdf={pdf}",
                          measured.as_uri()],
                         capture_output=True, text=True, timeout=180).stdout
    found = re.search(r"scrollWidth=(\d+)", dom)
    return Layout(int(found.group(1)) if found else -1, shot, pdf)
