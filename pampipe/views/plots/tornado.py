"""The tornado plot of a confidence plan: what each uncertain input does alone to the planned pressure."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.planning.quantiles import level_text
from pampipe.views.tables import new_figure, save_figure


def plot_tornado(plan, folder: Path, unit: str, scale: float) -> Path | None:
    """Write confidence_tornado.png for the section with the largest planned pressure, one panel per
    segment of it; None without ``--confidence`` (or without a feasible element). Every number comes from
    ``plan.uncertainty``."""
    c = plan.uncertainty
    if c is None or not c.shifts:
        return None
    a = plan.arrays
    pressure = np.where(np.isfinite(a.pressure) & a.feasible, a.pressure, -np.inf)
    if not np.isfinite(pressure.max()):
        return None
    s, _ = np.unravel_index(int(np.argmax(pressure)), pressure.shape)
    segments = [i for i in range(pressure.shape[1]) if np.isfinite(pressure[s, i])]
    rows = sorted(c.shifts, key=lambda k: max(c.shifts[k][s, i] - c.low_shifts[k][s, i] for i in segments))
    fig, axes = new_figure(len(segments), 1, figsize=(8, 1.6 + (0.5 * len(rows) + 0.6) * len(segments)),
                           sharex=True, squeeze=False)
    for ax, i in zip(axes[:, 0], segments, strict=True):
        _segment(ax, c, a, s, i, rows, unit, scale)
    fig.suptitle(f"{a.route.name[s]}: {level_text(1 - c.level)} to {level_text(c.level)} quantiles, "
                 "one source at a time",
                 fontsize=10)
    axes[-1, 0].set_xlabel(f"least holding pressure [{unit}] (gauge)")
    left, right = axes[-1, 0].get_xlim()
    axes[-1, 0].set_xlim(left, right + 0.2 * (right - left))
    fig.legend(*axes[0, 0].get_legend_handles_labels(), fontsize=8, loc="outside lower center", ncols=2,
               frameon=False)
    return save_figure(fig, folder, "confidence_tornado.png")


def _segment(ax, c, a, s: int, i: int, rows: list[str], unit: str, scale: float) -> None:
    """One segment's bars; each bar's shift written right of the bar and of the planned line, never on it."""
    base, planned = c.certain[s, i] / scale, a.pressure[s, i] / scale
    for y, name in enumerate(rows):
        low, high = c.low_shifts[name][s, i] / scale, c.shifts[name][s, i] / scale
        ax.barh(y, high - low, left=base + low, color="C0", alpha=0.75)
        ax.annotate(f"{high:+.3g} {unit}", (max(base + high, planned), y), xytext=(4, 0),
                    textcoords="offset points", va="center", fontsize=8)
    ax.axvline(base, color="k", lw=1.2, label="every input at its nominal value")
    ax.axvline(planned, color="C3", ls="--", lw=1.4, label="planned, all sources")
    ax.set_yticks(range(len(rows)), rows)
    ax.set_ylabel("source (alone)", fontsize=8)
    ax.set_title(f"{a.segment_names[i]}: nominal {base:.4g} {unit}, planned {planned:.4g} {unit}", loc="left",
                 fontsize=8)
    ax.grid(alpha=0.3, axis="x")
