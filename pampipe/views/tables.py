"""Human-readable output: aligned text tables, and plot helpers (matplotlib imported lazily)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from pampipe.io.files import atomic_write

#: Sections a text report lists in full (`plan`, `rehearse`); longer routes are summarised.
FULL_TABLE = 60


def table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A plain aligned text table; floats are shown with 4 significant digits. Columns whose header names a
    unit in brackets, and quantities in text cells, are shown in the display units (pampipe.units.display)."""
    from pampipe.units.display import column, localize

    columns = []  # (header, cells); a column the conversion made a copy of another ('bore [in]') is dropped
    for i, h in enumerate(headers):
        header, values = column(h, [r[i] for r in rows])
        shown = (localize(header), [localize(_fmt(v)) for v in values])
        if shown not in columns:
            columns.append(shown)
    headers = [h for h, _ in columns]
    cells = [[col[j] for _, col in columns] for j in range(len(rows))]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h)
              for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))
    rule = "  ".join("-" * w for w in widths)
    body = ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    return "\n".join([line, rule, *body])


def _fmt(value: object) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) < 1e6 else f"{value:.4e}"
    return str(value)


#: The file formats of ``--plot-format`` (the first is the default).
PLOT_FORMATS = ("png", "svg", "pdf")
_FIGURE_KEYS = ("figsize", "dpi", "layout")
_plotting = {"format": "png", "captured": None, "ax": None}


def set_plot_format(name: str) -> None:
    """The format :func:`save_figure` writes (one of :data:`PLOT_FORMATS`)."""
    if name not in PLOT_FORMATS:
        from pampipe.errors import InputError

        raise InputError(f"--plot-format: {name!r} is not one of {', '.join(PLOT_FORMATS)}.")
    _plotting["format"] = name


@contextmanager
def capture(ax=None) -> Iterator[list]:
    """Collect the figures that plot functions finish instead of writing them; the first single-axes
    figure asked for is drawn into ``ax`` when given (``result.plot(ax=...)``, the HTML report)."""
    figures: list = []
    saved = _plotting["captured"], _plotting["ax"]
    _plotting["captured"], _plotting["ax"] = figures, ax
    try:
        yield figures
    finally:
        _plotting["captured"], _plotting["ax"] = saved


def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    """(figure, axes) as ``plt.subplots`` gives, on a plain Figure (no pyplot state, no backend switch),
    in the house style (:mod:`pampipe.views.plots.style`)."""
    from matplotlib.figure import Figure

    from pampipe.views.plots.style import apply

    ax = _plotting["ax"]
    if ax is not None and nrows == ncols == 1 and kwargs.get("squeeze", True):
        _plotting["ax"] = None
        return ax.figure, ax
    fig = Figure(**{"layout": "constrained", **{k: kwargs.pop(k) for k in _FIGURE_KEYS if k in kwargs}})
    axes = fig.subplots(nrows, ncols, **kwargs)
    for one in fig.axes:
        apply(one)
    return fig, axes


def save_figure(fig, folder: Path, name: str) -> Path | None:
    """Save ``fig`` as ``folder/name`` atomically, its suffix that of ``--plot-format``, and return the
    path; while :func:`capture` is on, collect it instead (and return None)."""
    import matplotlib

    from pampipe.views.plots.display_units import localize_figure
    from pampipe.views.plots.style import DPI, PLAIN, plain_text

    localize_figure(fig)  # --units
    plain_text(fig)  # names as text, never mathtext
    if fig.get_layout_engine() is None:  # a figure of the caller's (plot(ax=...))
        fig.tight_layout()
    if _plotting["captured"] is not None:
        _plotting["captured"].append(fig)
        return None
    kind = _plotting["format"]
    target = (Path(folder) / name).with_suffix(f".{kind}")
    with matplotlib.rc_context(PLAIN):
        atomic_write(target, lambda tmp: fig.savefig(tmp, format=kind, dpi=DPI), create_folder=True)
    return target
