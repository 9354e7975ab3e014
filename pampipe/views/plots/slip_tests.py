"""Plots of the slip tests: each test's load and displacement with the detected onsets, and the fit."""

from __future__ import annotations

from pathlib import Path

from pampipe.views.tables import new_figure, save_figure


def plot_slip(tests, result, folder: Path) -> list[Path]:
    """Write slip_<test>.png per slip test and slip_fit.png into ``folder``.

    ``tests`` are the slip tests' data (:class:`pampipe.specs.experiment.SlipData`), ``result`` the
    :class:`pampipe.slip.SlipResult`; every onset and slip load drawn is the result's.
    """
    written = []
    for test in tests:
        fig, (top, bottom) = new_figure(2, 1, figsize=(9, 6), sharex=True)
        top.plot(test.time, test.axial_load, lw=0.8, color="tab:blue")
        bottom.plot(test.time, test.displacement * 1e3, lw=0.8, color="tab:gray")
        for t in (t for t in result.trials if t.test == test.name):
            if t.censored:
                top.plot(test.time[t.peak_row], t.slip_load, "^", color="tab:orange", ms=7,
                         label="no slip: held (lower bound)")
                continue
            top.plot(test.time[t.peak_row], t.slip_load, "v", color="tab:red", ms=7, label="slip load")
            bottom.axvline(test.time[t.onset_row], color="tab:red", lw=0.8, ls=":")
            top.annotate(f"{t.confidence:.2f}", (test.time[t.peak_row], t.slip_load), fontsize=7,
                         textcoords="offset points", xytext=(3, 4))
        handles, labels = top.get_legend_handles_labels()
        unique = dict(zip(labels, handles, strict=True))
        top.legend(unique.values(), unique.keys(), fontsize=8)
        top.set(ylabel="axial load [N]",
                title=f"{test.name}: detected slip onsets (numbers: detection confidence)")
        bottom.set(xlabel="time [s]", ylabel="displacement [mm]")
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
        written.append(save_figure(fig, folder, f"slip_{_safe(test.name)}.png"))

    fig, ax = new_figure(figsize=(7, 4.5))
    for bore in sorted({t.pipe_diameter for t in result.trials}):
        chosen = [(t, p) for t, p in zip(result.trials, result.predicted, strict=True)
                  if t.pipe_diameter == bore]
        line, = ax.plot([t.pressure / 1e3 for t, _ in chosen], [p for _, p in chosen], "_", ms=14,
                        label=f"model, bore {bore * 1e3:.4g} mm")
        ax.plot([t.pressure / 1e3 for t, _ in chosen if not t.censored],
                [t.slip_load for t, _ in chosen if not t.censored], "o", color=line.get_color(), ms=4,
                label=f"slip load, bore {bore * 1e3:.4g} mm")
        held = [t for t, _ in chosen if t.censored]
        if held:
            ax.plot([t.pressure / 1e3 for t in held], [t.slip_load for t in held], "^",
                    color=line.get_color(), ms=6, mfc="none", label="held (lower bound)")
    ax.set(xlabel="gauge pressure P [kPa]", ylabel="slip load [N]", title="slip loads and the fitted model")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    written.append(save_figure(fig, folder, "slip_fit.png"))
    return written


def _safe(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def plot_grip(result, folder: Path) -> list[Path]:
    """slip_fit.png of an `identify` result on slip tests only (the fit needs no raw data)."""
    return plot_slip((), result.slip, folder)
