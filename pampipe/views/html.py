"""`--report FILE.html`: one self-contained HTML file to send (plan, identify, diagnose).

It holds the inputs with their SHA-256, the command's text report (its tables), the warnings and
reasons, the long table of the JSON document, the plots as inline SVG and the model's assumptions
with the docs sections that state them. No script, no stylesheet, font or image from elsewhere: the
file opens offline and requests nothing.
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
from pampipe.results import HTML_ROWS, records

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


def svg_figures(draw: Callable[[], object]) -> list[str]:
    """The figures that ``draw()`` makes (plot functions under :func:`pampipe.views.tables.capture`) as
    SVG."""
    import matplotlib

    from pampipe.views.plots.style import PLAIN
    from pampipe.views.tables import capture

    with capture() as figures:
        draw()
    texts = []
    for fig in figures:
        buffer = io.StringIO()
        with matplotlib.rc_context(PLAIN):  # names as text, never mathtext (the texts: save_figure)
            fig.savefig(buffer, format="svg")
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
    rows = records(document)
    if not rows or len(rows[0]) <= 1:
        return ""
    columns = list(dict.fromkeys(k for row in rows for k in row))
    if len(rows) > 1:  # what every row shares is in the report above
        columns = [c for c in columns if len({repr(row.get(c)) for row in rows}) > 1 or c == "name"]
    head = "".join(f"<th>{_esc(c)}</th>" for c in columns)
    body = "".join("<tr>" + "".join(f"<td>{_esc(_cell(row.get(c)))}</td>" for c in columns) + "</tr>"
                   for row in rows[:HTML_ROWS])
    more = f"<p>{len(rows) - HTML_ROWS} more rows in the JSON document.</p>" if len(rows) > HTML_ROWS else ""
    return f"<h2>Results table</h2><div class='wide'><table><tr>{head}</tr>{body}</table></div>{more}"


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.5g}"
    return str(value)


STYLE = """body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;font-size:0.85em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f2f2f2}pre{background:#f8f8f8;padding:0.8em;overflow-x:auto;font-size:0.8em}
.wide{overflow-x:auto}.warn{color:#a40}svg{max-width:100%;height:auto}code{font-size:0.9em}"""


def render(command: str, *, title: str, inputs: Iterable[Path], text: str, document: dict,
           warnings: Sequence[str] = (), reasons: Sequence[str] = (), figures: Sequence[str] = (),
           folder: Path | None = None) -> str:
    """The report as one HTML text; its links to the docs are relative to ``folder``, the report's (none
    without it)."""
    esc = _esc
    files = "".join(f"<tr><td style='text-align:left'>{esc(str(p))}</td><td><code>{sha256(p)}</code></td>"
                    "</tr>" for p in dict.fromkeys(Path(p) for p in inputs) if Path(p).is_file())
    warned = "".join(f"<li class='warn'>{esc(w)}</li>" for w in warnings) or "<li>none</li>"
    why = "".join(f"<li>{esc(r)}</li>" for r in reasons)
    plots = "".join(f"<figure>{svg}</figure>" for svg in figures)
    assumptions = "".join(_assumption(*a, folder) for a in ASSUMPTIONS.get(command, []))
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return (f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body><h1>{esc(title)}</h1>"
            f"<p>pampipe {esc(__version__)}, <code>pampipe {esc(command)}</code>, {stamp}.</p>"
            f"<h2>Inputs</h2><table><tr><th>file</th><th>SHA-256</th></tr>{files}</table>"
            f"<h2>Warnings</h2><ul>{warned}</ul>"
            + (f"<h2>Reasons</h2><ul>{why}</ul>" if why else "")
            + f"<h2>Report</h2><pre>{esc(text)}</pre>{_long_table(document)}"
            + (f"<h2>Plots</h2>{plots}" if plots else "")
            + f"<h2>Model assumptions</h2><ul>{assumptions}</ul></body></html>\n")


def write_report(target: Path, command: str, **parts) -> Path:
    """Write :func:`render` to ``target`` atomically; return it."""
    atomic_write_text(Path(target), render(command, folder=Path(target).parent, **parts))
    return Path(target)
