"""Plots of `design`: required pressure against bore (designs, the material's muscle), objective per start."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure

CURVE_POINTS = 400


DIGITS = 6  # significant digits of an objective: IPOPT's tolerance is below them


def plot_design(result, folder: Path) -> list[Path]:
    """Write design_pressure_vs_bore.png and design_starts.png into ``folder``.

    Every number drawn comes from ``result`` (a :class:`pampipe.design.DesignResult`): the curves
    from :meth:`~pampipe.design.DesignResult.pressure_curve`, the points from its pipe tables.
    """
    return [_pressure_vs_bore(result, folder), _starts(result, folder)]


def _pressure_vs_bore(result, folder: Path) -> Path:
    inv = result.inventory
    fig, ax = new_figure(figsize=(8, 4.8))
    pipes = inv.pipes
    low, high = 0.8 * float(pipes.diameter_low.min()), 1.15 * float(pipes.diameter_high.max())
    bores = np.linspace(low, high, CURVE_POINTS)
    load, friction = result.worst_load()
    curves = [(None, f"material's muscle '{inv.material.name}'", "grey")]
    curves += [(k, f"size {k + 1}", f"C{k}") for k in range(len(result.sizes))]
    for which, label, color in curves:
        p = result.pressure_curve(which, bores)
        shown = np.where(np.isfinite(p), p / 1e3, np.nan)
        ax.plot(bores * 1e3, shown, color=color, lw=2 if which is not None else 1.5,
                ls="-" if which is not None else "--", label=label)
    for k in range(len(result.sizes)):
        mine = result.assignment == k
        if mine.any():
            ax.scatter(pipes.diameter[mine] * 1e3, result.sizes[k].table.largest[mine] / 1e3, s=14,
                       color=f"C{k}", edgecolor="k", lw=0.4, zorder=3)
    unserved = result.assignment < 0
    if unserved.any():
        ax.scatter(pipes.diameter[unserved] * 1e3, np.zeros(int(unserved.sum())), marker="x", color="C3",
                   label="pipes not served", zorder=3)
    ax.axhline(inv.supply_pressure / 1e3, color="C3", ls="--", lw=1.2, label="supply pressure")
    ax.set_ylim(0, 1.15 * inv.supply_pressure / 1e3)
    ax.set(xlabel="pipe bore [mm]", ylabel="least holding pressure [kPa]",
           title=f"required pressure against bore (curves: heaviest load {load:.4g} N, friction "
                 f"{friction:g}; dots: each pipe's largest)")
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "design_pressure_vs_bore.png")


def _starts(result, folder: Path) -> Path:
    """The objective each start reaches, to :data:`DIGITS` significant digits (IPOPT's tolerance leaves
    differences of 1e-6 Pa that are round-off, not a spread); failed starts shaded."""
    fig, ax = new_figure(figsize=(8, 4.2))
    unit = result.inventory.space.objective.unit
    reached, any_failed = [], False
    for k, size in enumerate(result.sizes):
        run = size.design.run
        ok = [r for r in run.results if r.success]
        failed = [r for r in run.results if not r.success]
        scale = run.problem.scale
        values = [float(f"{r.objective * scale:.{DIGITS}g}") for r in ok]
        reached += values
        ax.scatter([r.index for r in ok], values, color=f"C{k}", s=18,
                   label=f"size {k + 1}: {run.reached} of {len(run.results)} starts reach the best")
        for r in failed:
            ax.axvspan(r.index - 0.4, r.index + 0.4, color=f"C{k}", alpha=0.2, lw=0,
                       label="IPOPT failed" if not any_failed else None)
            any_failed = True
        if run.best is not None:
            ax.axhline(float(f"{run.best.objective * scale:.{DIGITS}g}"), color=f"C{k}", ls=":", lw=1)
    if reached and max(reached) - min(reached) <= 1e-3 * max(abs(max(reached)), 1e-12):
        middle = 0.5 * (max(reached) + min(reached))  # every start at the same value: a 2 % window, no spread
        ax.set_ylim(middle - 0.01 * abs(middle) - 1e-12, middle + 0.01 * abs(middle) + 1e-12)
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.set(xlabel="start (Latin hypercube index" + ("; shaded: IPOPT failed)" if any_failed else ")"),
           ylabel=f"objective [{unit}]", title=f"objective reached from each start (to {DIGITS} digits)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "design_starts.png")

