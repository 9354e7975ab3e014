"""Plots in the display units of ``--units`` (:mod:`pampipe.units.display`), applied to a finished figure.

The plots draw in SI-metric (kPa, mm, m, N). An axis labelled with such a unit keeps its data and gets
ticks at round values of the display unit, labelled in it (1 psi = 6.895 kPa: a tick '20' sits at
137.9 kPa); titles, texts and legends are rewritten like :func:`pampipe.units.display.localize`.
"""

from __future__ import annotations

from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator

from pampipe.units.display import PRESETS, current, localize, relabel


class ScaledLocator(MaxNLocator):
    """Ticks at round values of value x ``scale`` (the display unit), placed in the data's unit."""

    def __init__(self, scale: float):
        super().__init__(nbins="auto", steps=[1, 2, 2.5, 5, 10])
        self.scale = scale

    def tick_values(self, vmin, vmax):
        return super().tick_values(vmin * self.scale, vmax * self.scale) / self.scale


class ScaledLogLocator(LogLocator):
    """Decades of the display unit (1, 10, 100 lbf), placed in the data's unit."""

    def __init__(self, scale: float, subs=(1.0,)):
        super().__init__(subs=subs)
        self.scale = scale

    def tick_values(self, vmin, vmax):
        return super().tick_values(vmin * self.scale, vmax * self.scale) / self.scale


def localize_figure(fig) -> None:
    """Every axis, title, text and legend of ``fig`` in the display units (nothing under metric)."""
    if current() == PRESETS["metric"]:
        return
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            _localize_axis(axis)
        for where in ("left", "center", "right"):
            ax.set_title(localize(ax.get_title(loc=where)), loc=where)
        legend = ax.get_legend()
        for text in [*ax.texts, *(legend.get_texts() if legend is not None else [])]:
            text.set_text(localize(text.get_text()))
    for legend in fig.legends:  # a legend of the whole figure (below the axes)
        for text in legend.get_texts():
            text.set_text(localize(text.get_text()))
    if getattr(fig, "_suptitle", None) is not None:
        fig._suptitle.set_text(localize(fig._suptitle.get_text()))


def _localize_axis(axis) -> None:
    label = axis.get_label_text()
    relabelled = relabel(label)
    if relabelled is None:
        axis.set_label_text(localize(label))
        return
    label, scale = relabelled
    axis.set_label_text(localize(label))
    if axis.get_scale() == "linear":
        axis.set_major_locator(ScaledLocator(scale))
    elif axis.get_scale() == "log":
        axis.set_major_locator(ScaledLogLocator(scale))
        axis.set_minor_locator(ScaledLogLocator(scale, subs="auto"))
    axis.set_major_formatter(FuncFormatter(lambda value, _, k=scale: f"{value * k:.4g}"))
