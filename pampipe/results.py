"""What every result shows in a notebook: a short repr, an HTML table, a DataFrame and its main plot.

:func:`notebook` decorates a result class (placed above ``@dataclass``, whose repr it replaces). It
reads nothing but the result's JSON document (``to_dict()``, else ``as_document()``), so the notebook
shows the numbers of ``--json``:

* ``repr(result)``: the class and its headline numbers, under 300 characters;
* ``result._repr_html_()``: the headline numbers and the first rows of the long table, as HTML;
* ``result.to_frame()``: a tidy pandas DataFrame in long form, one row per innermost record of the
  document (a plan's segment in a section, a simulation's pressure point, an identification's pressure
  level of a test), its columns the JSON keys (unit-suffixed: ``pressure_Pa``), the enclosing records'
  keys prefixed with their singular name (``section_name``). Only what varies is a column: the
  document's own scalars (``mission``, ``solver.wall_time_s``, …) and the enclosing records' keys that
  are the same on every row go to ``frame.attrs``. pandas is the optional extra ``pampipe[frames]``;
* ``result.plot(ax=None)``: the command's main figure (the first one ``--plots`` writes), drawn
  into ``ax`` when given, returned as a matplotlib Figure;
* ``result.to_text(units=None)`` and ``str(result)``: the command's text report, in ``units`` (a
  ``--units`` value), by default in the units of :func:`pampipe.set_units` (metric unless set).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

from pampipe.errors import InputError

REPR_LIMIT = 299  # characters of repr()
HTML_ROWS = 40  # rows of the long table shown by _repr_html_


#: A function of no arguments that imports a view and returns it: the result module names its view with a
#: plain import made when the view is first asked for, and the view never imports the result module.
Loader = Callable[[], Callable]


def notebook(*, headline: tuple[str, ...] = (), plot: Loader | None = None, text: Loader | None = None):
    """Class decorator: ``__repr__``, ``_repr_html_``, ``to_frame``, ``records``, ``plot``, ``to_text``.

    ``headline``: the document's top-level keys shown first in the repr (others follow while they
    fit); ``plot``: a :data:`Loader` of the function taking ``(result, folder)`` as the command's
    ``--plots`` does, whose first figure ``plot()`` returns; ``text``: a :data:`Loader` of the function
    taking the result and returning the command's text report (``to_text()`` and ``str()``).
    """

    def decorate(cls):
        cls.__repr__ = lambda self: short_repr(type(self).__name__, document(self), headline)
        cls._repr_html_ = lambda self: html_table(type(self).__name__, document(self), headline)
        cls.records = _records_method
        cls.to_frame = _to_frame
        if plot is not None:
            cls.plot = _plot_method(plot)
        if text is not None:
            cls.to_text = _to_text_method(text)
            cls.__str__ = lambda self: report_text(self, text, None)
        return cls

    return decorate


def _records_method(self) -> list[dict]:
    """The long table of the result's JSON document as a list of dicts, one per innermost record (what
    :meth:`to_frame` holds, before the constant columns move to ``attrs``)."""
    return records(document(self))


def _to_frame(self):
    """A tidy pandas DataFrame of the result's JSON document (SI units, unit-suffixed columns).

    One row per innermost record of the document (a plan's segment in a section, a simulation's
    pressure point, an identification's pressure level of a test, a design's pipe); its columns the
    record's keys, nested keys flattened as ``key.sub``, [low, high] intervals as ``key_low`` and
    ``key_high``, the enclosing records' keys prefixed with their singular name (``section_name``).
    Only what varies is a column: the document's own scalars and the enclosing keys that are the same
    on every row are in ``frame.attrs`` (a dict). Needs pandas (``pip install pampipe[frames]``).
    """
    rows, constants = tidy(document(self))
    table = frame(rows)
    table.attrs.update(constants)
    return table


def _plot_method(plot: Loader):
    def plot_result(self, ax=None):
        """The command's main figure (the first one ``--plots`` writes), as a matplotlib Figure.

        ``ax``: a matplotlib Axes to draw into (default: a new figure). Labels follow the units of
        :func:`pampipe.set_units`. Raises InputError when the result has nothing to plot.
        """
        return main_figure(self, plot, ax)

    return plot_result


def _to_text_method(text: Loader):
    def to_text(self, units: str | None = None) -> str:
        """The command's text report, as the command line prints it.

        ``units``: a ``--units`` value (``metric``, ``us``, ``kPa``, ``psi``, ``bar``); default those of
        :func:`pampipe.set_units` (metric unless set). ``str(result)`` is the same in the default units.
        """
        return report_text(self, text, units)

    return to_text


def document(result) -> dict:
    """The result's JSON document."""
    to_dict = getattr(result, "to_dict", None)
    return to_dict() if to_dict is not None else result.as_document()


def _scalar(value) -> bool:
    return value is None or isinstance(value, str | bool | int | float)


def _number(value) -> bool:
    return value is None or (isinstance(value, int | float) and not isinstance(value, bool))


def _show(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}" if math.isfinite(value) else str(value)
    return str(value)


def headlines(doc: Mapping, first: tuple[str, ...]) -> list[tuple[str, object]]:
    """The document's top-level scalars, the ``first`` keys leading."""
    keys = [k for k in first if k in doc] + [k for k in doc if k not in first]
    return [(k, doc[k]) for k in keys if _scalar(doc[k])]


def short_repr(name: str, doc: Mapping, first: tuple[str, ...]) -> str:
    """``<Name key=value …>`` cut to :data:`REPR_LIMIT` characters."""
    text = f"<{name}"
    for key, value in headlines(doc, first):
        item = f" {key}={_show(value)}"
        if len(text) + len(item) + 5 > REPR_LIMIT:
            return text + " …>"
        text += item
    return text + ">"


def html_table(name: str, doc: Mapping, first: tuple[str, ...]) -> str:
    """The headline scalars as a two-column table, then the first rows of the long table."""
    import html  # here: a command never draws a notebook's table (html.entities is ≈ 5 ms to import)

    esc = html.escape
    head = "".join(f"<tr><th style='text-align:left'>{esc(k)}</th><td>{esc(_show(v))}</td></tr>"
                   for k, v in headlines(doc, first))
    parts = [f"<div><strong>{esc(name)}</strong><table>{head}</table>"]
    rows = records(doc)
    if rows and len(rows[0]) > 1:
        columns = list(dict.fromkeys(k for row in rows for k in row))
        body = "".join("<tr>" + "".join(f"<td>{esc(_show(row.get(c, '')))}</td>" for c in columns) + "</tr>"
                       for row in rows[:HTML_ROWS])
        more = f"<p>… {len(rows) - HTML_ROWS} more rows: <code>.to_frame()</code></p>" \
            if len(rows) > HTML_ROWS else ""
        parts.append("<table><tr>" + "".join(f"<th>{esc(c)}</th>" for c in columns) + f"</tr>{body}</table>"
                     + more)
    return "".join(parts) + "</div>"


def _singular(key: str) -> str:
    if key.endswith("ies"):
        return key[:-3] + "y"
    return key[:-1] if key.endswith("s") and not key.endswith("ss") else key


#: Key fragments that mark a [low, high] pair as an interval (other short lists of numbers, such as a
#: degree-1 modulus [a0, a1], are coefficients: ``key.0``, ``key.1``).
INTERVAL_WORDS = ("interval", "range", "band", "bounds", "limits")
SHORT_LIST = 8  # numeric lists up to this length become columns; longer ones (curves, matrices) do not


def _interval(key: str) -> bool:
    return any(word in key for word in INTERVAL_WORDS)


def _flat(item: Mapping, prefix: str = "") -> dict:
    """The scalars of ``item``, nested dicts of scalars flattened to ``key.sub``; [low, high] intervals
    to ``key_low``/``key_high``; other short lists of numbers to ``key.0``, ``key.1``, …"""
    out = {}
    for key, value in item.items():
        name = f"{prefix}{key}"
        if _scalar(value):
            out[name] = value
        elif isinstance(value, Mapping):
            out.update(_flat(value, f"{name}."))
        elif isinstance(value, list | tuple) and value and all(_number(v) for v in value):
            if len(value) == 2 and _interval(str(key)):
                out[f"{name}_low"], out[f"{name}_high"] = value
            elif len(value) <= SHORT_LIST:
                out.update({f"{name}.{i}": v for i, v in enumerate(value)})
    return out


def _depth(value) -> int:
    """How deep lists of records nest in ``value`` (0: none)."""
    if isinstance(value, list) and value and all(isinstance(v, Mapping) for v in value):
        return 1 + max(_depth(v) for v in value)
    if isinstance(value, Mapping):
        return max((_depth(v) for v in value.values()), default=0)
    return 0


def _record_lists(doc: Mapping, path: str = "") -> dict[str, list]:
    """Every list of records in ``doc``, also inside nested dicts (``fit.tests``), by its dotted path."""
    out = {}
    for key, value in doc.items():
        if isinstance(value, list) and value and all(isinstance(x, Mapping) for x in value):
            out[f"{path}{key}"] = value
        elif isinstance(value, Mapping):
            out.update(_record_lists(value, f"{path}{key}."))
    return out


def _walk(doc: Mapping, context: dict, name: str) -> list[tuple[dict, dict]]:
    """(enclosing keys, the innermost record's own keys) per innermost record of ``doc``."""
    lists = _record_lists(doc)
    if not lists:
        return [(context, _flat(doc))]
    path = max(lists, key=lambda k: (_depth(lists[k]), len(lists[k])))
    own = {f"{name}_{k}" if name else k: v for k, v in _flat(doc).items()}
    singular = _singular(path.rsplit(".", 1)[-1])
    return [pair for item in lists[path] for pair in _walk(item, {**context, **own}, singular)]


def records(doc: Mapping) -> list[dict]:
    """The long table: one row per innermost record of ``doc``, following its deepest list of records
    (also one inside nested dicts) and carrying the enclosing records' scalars (prefixed with the
    singular of their list's key)."""
    return [{**context, **own} for context, own in _walk(doc, {}, "")]


def tidy(doc: Mapping) -> tuple[list[dict], dict]:
    """The long table without its constant columns, and those constants: the document's own scalars
    and the enclosing records' keys that are the same on every row (a document without lists of records
    is one row of everything, no constants)."""
    pairs = _walk(doc, {}, "")
    if not _record_lists(doc):
        return [own for _, own in pairs], {}
    keys = list(dict.fromkeys(k for context, _ in pairs for k in context))
    constant = {k for k in keys if len({repr(context.get(k)) for context, _ in pairs}) == 1}
    rows = [{**{k: v for k, v in context.items() if k not in constant}, **own} for context, own in pairs]
    return rows, {k: pairs[0][0].get(k) for k in keys if k in constant}


def frame(rows: list[dict]):
    """A pandas DataFrame of ``rows`` (ImportError naming the extra without pandas)."""
    try:
        import pandas
    except ImportError:
        raise ImportError("to_frame() needs pandas: install the optional extra with "
                          "`pip install pampipe[frames]` (or `pip install pandas`).") from None
    return pandas.DataFrame.from_records(rows)


def report_text(result, text: Loader, units: str | None) -> str:
    """The text that the view ``text()`` writes of ``result``, in ``units`` (a --units value; None: those
    of :func:`pampipe.units.display.set_units`)."""
    from contextlib import nullcontext

    from pampipe.units import display

    build = text()
    with nullcontext() if units is None else display.shown_in(units):
        return display.localize(build(result))


def main_figure(result, plot: Loader, ax=None):
    """The first figure that the view ``plot()`` draws for ``result``, into ``ax`` if given."""
    from pampipe.views.tables import capture

    draw = plot()
    with capture(ax) as figures:
        draw(result, None)
    if not figures:
        raise InputError(f"{type(result).__name__}: there is nothing to plot.")
    return figures[0]
