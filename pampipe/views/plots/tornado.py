"""The tornado plot of a confidence plan: what each uncertain input does alone to the planned pressure."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.planning.quantiles import level_text
from pampipe.views.tables import new_figure, save_figure


def plot_tornado(plan, folder: Path, unit: str, scale: float) -> Path | None:
    """Write confidence_tornado.png for the element with the largest planned pressure; None without
    ``--confidence`` (or without a feasible element). Every number comes from ``plan.uncertainty``."""
    c = plan.uncertainty
    if c is None or not c.shifts:
        return None
    a = plan.arrays
    pressure = np.where(np.isfinite(a.pressure) & a.feasible, a.pressure, -np.inf)
    if not np.isfinite(pressure.max()):
        return None
    s, i = np.unravel_index(int(np.argmax(pressure)), pressure.shape)
    base = c.certain[s, i] / scale
    rows = sorted(c.shifts, key=lambda k: c.shifts[k][s, i] - c.low_shifts[k][s, i])
    fig, ax = new_figure(figsize=(8, 2.4 + 0.6 * len(rows)))
    for y, name in enumerate(rows):
        low, high = c.low_shifts[name][s, i] / scale, c.shifts[name][s, i] / scale
        ax.barh(y, high - low, left=base + low, color="C0", alpha=0.75)
        ax.text(base + high, y, f" {high:+.3g} {unit}", va="center", fontsize=8)
    ax.axvline(base, color="k", lw=1.2, label=f"every input at its nominal value ({base:.4g} {unit})")
    ax.axvline(a.pressure[s, i] / scale, color="C3", ls="--", lw=1.4,
               label=f"planned, all sources ({a.pressure[s, i] / scale:.4g} {unit})")
    ax.set_yticks(range(len(rows)), rows)
    ax.set(xlabel=f"least holding pressure [{unit}] (gauge)", ylabel="source of uncertainty (alone)",
           title=f"{a.route.name[s]}, {a.segment_names[i]}: {level_text(1 - c.level)} to "
                 f"{level_text(c.level)} quantiles, "
                 "one source at a time")
    left, right = ax.get_xlim()
    ax.set_xlim(left, right + 0.15 * (right - left))
    ax.grid(alpha=0.3, axis="x")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=2, frameon=False)
    return save_figure(fig, folder, "confidence_tornado.png")
