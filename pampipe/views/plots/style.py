"""One look for every plot: sizes, grid, colours and resolution (applied by ``report.new_figure``).

Every axis is labelled ``quantity [unit]`` by the plot that draws it; this module only sets what all
plots share, so a figure of ``plan`` and one of ``identify`` sit side by side in a report.
"""

from __future__ import annotations

DPI = 150  # raster resolution of PNG plots; SVG and PDF are vector
FONT_SIZE = 9  # tick labels and legends [pt]
GRID_ALPHA = 0.3


#: rcParams under which a figure is drawn and saved: text is drawn as written, never as mathtext, so a '$' in
#: a user's name is a dollar sign (no formula drawn, no parse error); the tick labels made while drawing take
#: it from here, the texts made before from :func:`plain_text`.
PLAIN = {"text.parse_math": False, "text.usetex": False}


def plain_text(fig) -> None:
    """Every text of ``fig`` as written (see :data:`PLAIN`)."""
    from matplotlib.text import Text

    for text in fig.findobj(Text):
        text.set_parse_math(False)


def apply(ax) -> None:
    """Give ``ax`` the house style: a light grid below the data and readable ticks."""
    ax.grid(alpha=GRID_ALPHA)
    ax.set_axisbelow(True)
    ax.tick_params(labelsize=FONT_SIZE)
