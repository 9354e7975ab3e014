"""`--report FILE.pdf`: the report to send as a PDF, drawn by matplotlib alone (no browser needed).

The same parts as the HTML report (:mod:`pampipe.views.html`) in the same order: the version, the command
and when it ran (UTC), the verdict and the headline numbers, the inputs (settings, and the files with their
SHA-256), the warnings and reasons, the command's text report (its tables, in a monospace face, lines longer
than :data:`COLUMNS` characters wrapped), then one page per figure. Pages are A4 portrait (210 × 297 mm) with
12 mm margins; the text is written as text, so a PDF reader can search and copy it. Curves of many points are
drawn as images, as in the HTML report.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from pampipe._version import __version__
from pampipe.io.files import atomic_write
from pampipe.units.display import localize
from pampipe.views.html import BAD, rasterize_dense, sha256, utc_stamp
from pampipe.views.report_summary import headline, report_inputs, verdict

#: A4 in inches, and the margin (12 mm).
PAGE = (210 / 25.4, 297 / 25.4)
MARGIN = 12 / 25.4
#: Characters of a monospace line of the text report (6.5 pt DejaVu Sans Mono: 0.6 em a character).
COLUMNS = 125


@dataclass(frozen=True)
class Style:
    size: float  # [pt]
    family: str = "sans-serif"
    weight: str = "normal"
    columns: int = 110  # wrap width [characters]
    color: str = "#222222"

    @property
    def height(self) -> float:
        """Line height [in]: 1.3 × the font size."""
        return 1.3 * self.size / 72


TITLE = Style(13, weight="bold", columns=80)
HEADING = Style(10, weight="bold")
VERDICT = Style(9.5, weight="bold", columns=100, color="#227a55")
BAD_VERDICT = Style(9.5, weight="bold", columns=100, color="#bb2222")
BODY = Style(8, columns=120)
WARNING = Style(8, columns=120, color="#aa4400")
MONO = Style(6.5, family="monospace", columns=COLUMNS)
GAP = Style(4)


def lines(command: str, *, title: str, inputs: Iterable[Path], text: str, document: dict,
          warnings: Sequence[str] = (), reasons: Sequence[str] = ()) -> list[tuple[str, Style]]:
    """The report's text as (line, style), wrapped: what the text pages show, in order."""
    said = verdict(text)
    out: list[tuple[str, Style]] = []

    def add(line: str, style: Style = BODY) -> None:
        out.extend((part, style) for part in textwrap.wrap(line, style.columns, replace_whitespace=False,
                                                           drop_whitespace=False) or [""])

    add(title, TITLE)
    add(f"pampipe {__version__}, pampipe {command}, {utc_stamp()}", BODY)
    out.append(("", GAP))
    add(said, BAD_VERDICT if said.startswith(BAD) or reasons else VERDICT)
    for name, value in headline(command, document):
        add(f"{name}: {localize(value)}")
    out += [("", GAP), ("Inputs", HEADING)]
    for name, value in report_inputs(command, document):
        add(f"{name}: {localize(value)}")
    for path in dict.fromkeys(Path(p) for p in inputs):
        if path.is_file():
            add(f"{path}  SHA-256 {sha256(path)}")
    out += [("", GAP), ("Warnings", HEADING)]
    for line in warnings or ["none"]:
        add(line, WARNING if warnings else BODY)
    if reasons:
        out += [("", GAP), ("Reasons", HEADING)]
        for line in reasons:
            add(line)
    out += [("", GAP), ("Report", HEADING)]
    for line in text.splitlines():
        add(line.rstrip(), MONO)
    return out


def _text_pages(rows: list[tuple[str, Style]]):
    """The A4 figures that hold ``rows``, filled top to bottom."""
    from matplotlib.figure import Figure

    width, height = PAGE
    pages, fig, y = [], None, 0.0
    for line, style in rows:
        if fig is None or y - style.height < MARGIN:
            fig, y = Figure(figsize=PAGE), height - MARGIN
            pages.append(fig)
        y -= style.height
        if line.strip():
            fig.text(MARGIN / width, y / height, line, fontsize=style.size, family=style.family,
                     weight=style.weight, color=style.color, va="baseline", ha="left", parse_math=False,
                     fontfeatures=["-liga"])  # "fi" stays two letters: searchable, copyable
    return pages


def write_pdf(target: Path, command: str, *, draw: Callable[[], object] | None = None, **parts) -> Path:
    """Write the report (:func:`lines`, then the figures ``draw()`` makes) to ``target`` atomically."""
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfPages

    from pampipe.views.plots.style import PLAIN
    from pampipe.views.tables import capture

    figures: list = []
    if draw is not None:
        with capture() as figures:
            draw()
    pages = _text_pages(lines(command, **parts))

    metadata = {"Title": parts.get("title", f"pampipe {command}"), "Creator": f"pampipe {__version__}"}

    def write(tmp: Path) -> None:
        with matplotlib.rc_context(PLAIN), PdfPages(tmp, metadata=metadata) as pdf:
            for fig in [*pages, *figures]:
                rasterize_dense(fig)
                pdf.savefig(fig, dpi=150)

    atomic_write(Path(target), write)
    return Path(target)
