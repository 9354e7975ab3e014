"""Plots of `gait`: segment pressures against time with their thresholds, and a space-time diagram."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure

COLORS = ("C0", "C1", "C2")


def _step_marks(ax, result, *, label: bool) -> None:
    """Vertical lines at the step ends, with the step names on top."""
    ends = result.trajectory.times[result.trajectory.boundaries]
    starts = np.concatenate([[0.0], ends[:-1]])
    for start, end, step in zip(starts, ends, (s.step for s in result.steps[1:]), strict=True):
        ax.axvline(end, color="grey", lw=0.6, ls=":")
        if label:
            ax.annotate(step, ((start + end) / 2, 1.0), xycoords=("data", "axes fraction"),
                        ha="center", va="bottom", fontsize=8)


def plot_gait(result, folder: Path) -> list[Path]:
    """Write gait_pressures_<schedule>.png and gait_space_time_<schedule>.png into ``folder`` (``result``: a
    :class:`pampipe.locomotion.GaitResult`)."""
    traj, names = result.trajectory, result.names
    written = []
    fig, axes = new_figure(3, 1, figsize=(8, 7.5), sharex=True)
    for i, (ax, need) in enumerate(zip(axes, result.needs, strict=True)):
        # shade the steps in which this segment is a designated anchor
        bounds = np.concatenate([[0.0], traj.times[traj.boundaries]])
        for k, step in enumerate(result.steps[1:], start=1):
            if need.name in step.anchored:
                ax.axvspan(bounds[k - 1], bounds[k], color=COLORS[i], alpha=0.08, lw=0)
        ax.plot(traj.times, traj.pressures[:, i] / 1e3, color=COLORS[i], lw=1.6, label="pressure")
        ax.axhline(need.contact_pressure / 1e3, color="k", ls="--", lw=0.9,
                   label=f"anchoring (wall contact) {need.contact_pressure / 1e3:.1f} kPa")
        ax.axhline(need.required_pressure / 1e3, color="r", ls=":", lw=1.2,
                   label=f"no slip (SF {need.safety_factor:g}) {need.required_pressure / 1e3:.1f} kPa")
        _step_marks(ax, result, label=i == 0)
        ax.set_ylabel(f"{need.name} P [kPa]")
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="center right")
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(f"{result.schedule} gait in '{result.section}': pressures (shaded: the segment is an "
                      f"anchor of that step); cycle {result.cycle_time:.2f} s", pad=16, fontsize=10)
    written.append(save_figure(fig, folder, f"gait_pressures_{result.schedule}.png"))

    fig, (ax, shift) = new_figure(2, 1, figsize=(8, 8), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 2]})
    ends = result.ends * 1e3
    touching = traj.pressures >= np.array([n.contact_pressure for n in result.needs])[None, :]
    for i in range(3):
        low, high = ends[:, i], ends[:, i + 1]
        ax.fill_between(traj.times, low, high, color=COLORS[i], alpha=0.15, lw=0)
        ax.fill_between(traj.times, low, high, where=touching[:, i], color=COLORS[i], alpha=0.55, lw=0,
                        label=f"{names[i]} (dark: gripping the wall)")
    labels = ("rear", "joint 1-2", "joint 2-3", "front")
    for j, label in enumerate(labels):
        ax.plot(traj.times, ends[:, j], color="k", lw=0.9)
        ax.annotate(f" {label}", (traj.times[-1], ends[-1, j]), fontsize=8, va="center")
        shift.plot(traj.times, ends[:, j] - ends[0, j], lw=1.4, label=label)
    _step_marks(ax, result, label=True)
    _step_marks(shift, result, label=False)
    shift.axhline(result.stride * 1e3, color="grey", ls="--", lw=0.8,
                  label=f"stride {result.stride * 1e3:.2f} mm")
    ax.set_ylabel("position along the pipe [mm]")
    ax.set_title(f"{result.schedule} gait in '{result.section}': {result.stride * 1e3:.2f} mm per "
                 f"{result.cycle_time:.2f} s cycle ({result.speed * 1e3:.3g} mm/s)", pad=16, fontsize=10)
    ax.set_xlim(0, traj.times[-1] * 1.12)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)  # off the curves
    shift.set(xlabel="time [s]", ylabel="displacement since the cycle start [mm]")
    shift.grid(alpha=0.3)
    shift.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    written.append(save_figure(fig, folder, f"gait_space_time_{result.schedule}.png"))
    return written


def plot_report(report, folder: Path) -> list[Path]:
    """:func:`plot_gait` of each schedule of a :class:`~pampipe.api.gait_report.GaitReport`, the optimal
    one first."""
    return [path for result in reversed(report.results) for path in plot_gait(result, folder)]
