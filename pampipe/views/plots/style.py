"""One look for every plot: sizes, grid, colours and resolution (applied by ``report.new_figure``).

Every axis is labelled ``quantity [unit]`` by the plot that draws it; this module only sets what all
plots share, so a figure of ``plan`` and one of ``identify`` sit side by side in a report.
"""

from __future__ import annotations

DPI = 150  # raster resolution of PNG plots; SVG and PDF are vector
FONT_SIZE = 9  # tick labels and legends [pt]
GRID_ALPHA = 0.3


def apply(ax) -> None:
    """Give ``ax`` the house style: a light grid below the data and readable ticks."""
    ax.grid(alpha=GRID_ALPHA)
    ax.set_axisbelow(True)
    ax.tick_params(labelsize=FONT_SIZE)
