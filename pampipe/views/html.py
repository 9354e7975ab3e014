"""`--report FILE.html`: one self-contained HTML file to send (plan, identify, diagnose, rehearse).

It opens with the verdict and the headline numbers (:mod:`pampipe.views.report_summary`), then the
inputs (the settings, and the files with their SHA-256), the warnings and reasons, the command's text
report (its tables), the long table of the JSON document with readable column names in the user's
units, the plots as inline SVG (curves of more than :data:`RASTER_POINTS` points drawn as an image, so
that 3·10⁵ rows do not become megabytes of SVG paths) and the model's assumptions with the docs sections
that state them. Nothing is cut at 1280 px (text wraps, wide tables scroll) and ``@media print`` lays it
out for A4. No script, no stylesheet, font or image from elsewhere: the file opens offline and requests
nothing.
"""

from __future__ import annotations

import hashlib
import html
import io
import os
import urllib.parse
from collections.abc import Callable, Iterable, Sequence
from datetime import datetime, timezone
from pathlib import Path

from pampipe._version import __version__
from pampipe.io.files import atomic_write_text
from pampipe.io.streams import safe_text
from pampipe.results import HTML_ROWS, tidy
from pampipe.units.display import column, localize
from pampipe.views.report_summary import headline, quantity, report_inputs, verdict

DOCS = Path(__file__).resolve().parents[2] / "docs"

#: The model's assumptions behind each command: (statement, docs file, section heading).
ASSUMPTIONS = {
    "plan": [
        ("The muscle is the bladder force-balance model with the identified moduli; its braid is "
         "inextensible unless an effect says otherwise.", "physics.md", "4. Bladder force-balance model"),
        ("Anchoring: the muscle grips once its free diameter reaches the pipe's bore; the holding force is "
         "wall friction times the radial force, μπF_r.", "physics.md", "5. Radial expansion model"),
        ("Each segment is planned in the worst bore of its section's range, with the safety factor on the "
         "load it must hold.", "physics.md", "8.4 The planning problem"),
        ("The load on an anchor follows the mission's load path (slip condition).", "physics.md",
         "8.3 Slip condition and the load on an anchor"),
    ],
    "identify": [
        ("The moduli law of the bladder, fitted by least squares (IPOPT) to the axial and radial tests.",
         "physics.md", "6. Identification NLP"),
        ("Stresses and strains of the bladder as the force balance states them.", "physics.md",
         "4.2 Stresses and the moduli law"),
    ],
    "diagnose": [
        ("Candidate effects are those of the effect library; one is kept only when the held-out error "
         "and the BIC both improve.", "physics.md", "9. Missing effects: the effect library"),
        ("The baseline is the model that identify fits.", "physics.md", "6. Identification NLP"),
    ],
}


def sha256(path: Path) -> str:
    """The SHA-256 of a file's bytes (hex)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


#: A curve or scatter of more points than this is drawn as an image inside the SVG (axes, labels and
#: text stay vectors): the eye sees no more at the report's size, and the file stays small.
RASTER_POINTS = 500
RASTER_DPI = 64
FEW_POINTS = 20  # a fitted line or a threshold: stays a vector


def _points(artist) -> int:
    """Points of a curve; markers or cells (a pcolormesh's quadrilaterals) of a collection."""
    if hasattr(artist, "get_xydata"):
        return len(artist.get_xydata())
    return max(len(artist.get_offsets()), len(artist.get_paths()))


def rasterize_dense(fig) -> None:
    """In every axes of ``fig`` whose curves and markers hold more than :data:`RASTER_POINTS` points in
    all, draw those of more than :data:`FEW_POINTS` points as an image."""
    for ax in fig.axes:
        artists = [*ax.lines, *ax.collections]
        if sum(_points(a) for a in artists) > RASTER_POINTS:
            for artist in artists:
                if _points(artist) > FEW_POINTS:
                    artist.set_rasterized(True)


def svg_figures(draw: Callable[[], object]) -> list[str]:
    """The figures that ``draw()`` makes (plot functions under :func:`pampipe.views.tables.capture`) as
    SVG, dense curves rasterized (:func:`rasterize_dense`)."""
    import matplotlib

    from pampipe.views.plots.style import PLAIN
    from pampipe.views.tables import capture

    with capture() as figures:
        draw()
    texts = []
    for fig in figures:
        rasterize_dense(fig)
        buffer = io.StringIO()
        # names as text, never mathtext (the texts: save_figure); text as text, not as glyph outlines
        with matplotlib.rc_context({**PLAIN, "svg.fonttype": "none"}):
            fig.savefig(buffer, format="svg", dpi=RASTER_DPI)
        svg = buffer.getvalue()
        texts.append(svg[svg.index("<svg"):])  # drop the XML prolog and DOCTYPE (an external DTD)
    return texts


def _anchor(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    kept = "".join(c for c in heading.lower() if c.isalnum() or c in " -_")
    return kept.replace(" ", "-")


def _assumption(text: str, doc: str, heading: str, folder: Path | None) -> str:
    where = DOCS / doc
    label = f"docs/{doc} §{heading}"
    link = (f"<a href='{_esc(_relative_uri(where, folder))}#{_anchor(heading)}'>{_esc(label)}</a>"
            if where.is_file() and folder is not None else _esc(label))
    return f"<li>{_esc(text)} ({link})</li>"


def _relative_uri(target: Path, folder: Path) -> str:
    """``target`` as a URI reference relative to ``folder`` (the report's): no absolute path of the
    installation in a report that is sent on."""
    return urllib.parse.quote(Path(os.path.relpath(target, folder.resolve())).as_posix())


def _esc(text) -> str:
    """``text`` for HTML: markup escaped, and control and bidi characters (U+202A-202E, U+2066-2069, ...)
    shown as ``\\u202e`` (:func:`pampipe.io.streams.safe_text`), so a name cannot reorder what is shown."""
    return html.escape(safe_text(str(text)))


def _long_table(document: dict) -> str:
    """The tidy long table (what varies; the constants are in the report above), its columns named for
    a reader and shown in the user's units."""
    rows, _ = tidy(document)
    if len(rows) <= 1 or len(rows[0]) <= 1:
        return ""
    keys = [k for k in dict.fromkeys(k for row in rows for k in row)
            if not k.endswith("_rad") and not isinstance(rows[0].get(k), list | dict)]
    shown = rows[:HTML_ROWS]
    columns = []
    for key in keys:
        name, _ = quantity(key, 1.0)
        label, unit = _unit_of(key)
        values = [_number(row.get(key), key) for row in shown]
        header, values = column(f"{name} [{label}]", values) if unit else (name, values)
        columns.append((header, values))
    head = "".join(f"<th>{_esc(h)}</th>" for h, _ in columns)
    body = "".join("<tr>" + "".join(f"<td>{_esc(_cell(values[i]))}</td>" for _, values in columns)
                   + "</tr>" for i in range(len(shown)))
    more = f"<p>{len(rows) - HTML_ROWS} more rows in the JSON document.</p>" if len(rows) > HTML_ROWS else ""
    return f"<h2>Results table</h2><div class='wide'><table><tr>{head}</tr>{body}</table></div>{more}"


def _unit_of(key: str) -> tuple[str, bool]:
    """(the metric unit of a JSON key, whether it has one)."""
    _, text = quantity(key, 1.0)
    unit = text.partition(" ")[2]
    return unit, bool(unit)


def _number(value, key: str):
    """A JSON value in the metric unit :func:`quantity` names for ``key``."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value
    _, text = quantity(key, 1.0)
    return value * float(text.partition(" ")[0])


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.5g}"
    return str(value)


STYLE = """body{font-family:sans-serif;max-width:76em;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;font-size:0.85em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f2f2f2}pre{background:#f8f8f8;padding:0.8em;font-size:0.8em;white-space:pre-wrap;
overflow-wrap:anywhere}.wide{overflow-x:auto;max-width:100%}.warn{color:#a40}svg{max-width:100%;height:auto}
code{font-size:0.9em;overflow-wrap:anywhere}td{white-space:nowrap}th{min-width:4em}
.verdict{font-size:1.25em;font-weight:bold;padding:0.5em 0.8em;border-left:6px solid #2a7}
.verdict.bad{border-color:#c33}.headline th,.facts th{text-align:left}
@media print{@page{size:A4;margin:12mm}body{max-width:none;margin:0;padding:0;font-size:9pt}
.wide{overflow:visible}table{font-size:7pt}pre{font-size:6.5pt}figure{break-inside:avoid;margin:0}
h2{break-after:avoid}tr{break-inside:avoid}}"""
BAD = ("infeasible", "not feasible", "the robot stops", "pampipe plan: no solution", "Verdict: unexplained",
       "fit: IPOPT")


def _facts(rows: Sequence[tuple[str, str]], css: str) -> str:
    cells = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(localize(v))}</td></tr>" for k, v in rows)
    return f"<table class='{css}'>{cells}</table>" if cells else ""


def utc_stamp() -> str:
    """When a report was written, to the minute, in UTC ("2026-11-29 04:20 UTC"): both reports say it."""
    return datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def render(command: str, *, title: str, inputs: Iterable[Path], text: str, document: dict,
           warnings: Sequence[str] = (), reasons: Sequence[str] = (), figures: Sequence[str] = (),
           folder: Path | None = None) -> str:
    """The report as one HTML text: the verdict and headline numbers first; its links to the docs are
    relative to ``folder``, the report's (none without it)."""
    esc = _esc
    files = "".join(f"<tr><td style='text-align:left'>{esc(str(p))}</td><td><code>{sha256(p)}</code></td>"
                    "</tr>" for p in dict.fromkeys(Path(p) for p in inputs) if Path(p).is_file())
    warned = "".join(f"<li class='warn'>{esc(w)}</li>" for w in warnings) or "<li>none</li>"
    why = "".join(f"<li>{esc(r)}</li>" for r in reasons)
    plots = "".join(f"<figure>{svg}</figure>" for svg in figures)
    assumptions = "".join(_assumption(*a, folder) for a in ASSUMPTIONS.get(command, []))
    stamp = utc_stamp()
    said = verdict(text)
    bad = " bad" if said.startswith(BAD) or reasons else ""
    return (f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            f"<meta name='viewport' content='width=device-width, initial-scale=1'><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body><h1>{esc(title)}</h1>"
            f"<p class='verdict{bad}'>{esc(said)}</p>{_facts(headline(command, document), 'headline')}"
            f"<p>pampipe {esc(__version__)}, <code>pampipe {esc(command)}</code>, {stamp}.</p>"
            f"<h2>Inputs</h2>{_facts(report_inputs(command, document), 'facts')}"
            f"<table><tr><th>file</th><th>SHA-256</th></tr>{files}</table>"
            f"<h2>Warnings</h2><ul>{warned}</ul>"
            + (f"<h2>Reasons</h2><ul>{why}</ul>" if why else "")
            + f"<h2>Report</h2><pre>{esc(text)}</pre>{_long_table(document)}"
            + (f"<h2>Plots</h2>{plots}" if plots else "")
            + f"<h2>Model assumptions</h2><ul>{assumptions}</ul></body></html>\n")


def write_report(target: Path, command: str, **parts) -> Path:
    """Write :func:`render` to ``target`` atomically; return it."""
    atomic_write_text(Path(target), render(command, folder=Path(target).parent, **parts))
    return Path(target)
