"""Plot of `next-test`: the planned pressure predicted after each test, today's and the D-optimal pick's
marked. Everything drawn is the result's document."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure


def plot_next_test(result, folder: Path | None) -> list[Path]:
    """Write next_test.png into ``folder`` (None: draw only)."""
    doc = result.to_dict()
    ranked = doc["ranked"]
    labels = [c["label"] for c in ranked]
    after = np.array([np.nan if c["predicted"]["pressure_Pa"] is None else c["predicted"]["pressure_Pa"]
                      for c in ranked]) / 1e3
    sd = np.array([c["predicted"]["pressure_sd_Pa"] or 0.0 for c in ranked]) / 1e3
    fig, ax = new_figure(figsize=(8, 0.5 * len(ranked) + 1.5))
    y = np.arange(len(ranked))[::-1]
    colors = ["C2" if c["label"] == doc["d_optimal"]["label"] else "C0" for c in ranked]
    ax.barh(y, after, xerr=sd, color=colors)
    today = doc["current"]["pressure_Pa"]
    if today is not None:
        ax.axvline(today / 1e3, color="k", ls="--", lw=1, label="today")
    ax.set_yticks(y, labels, fontsize=8)
    ax.set(xlabel="planned pressure after the test [kPa]",
           title=f"next test, best first (green: D-optimal), C = {doc['confidence']:g}")
    finite = after[np.isfinite(after)]
    if finite.size:
        ax.set_xlim(0.95 * min(finite.min(), today / 1e3 if today else finite.min()), None)
    ax.legend(fontsize=8, loc="best")
    path = save_figure(fig, folder, "next_test")
    return [path] if path is not None else []
