"""Plots of `diagnose`: residuals before/after against the signature variables, where they were, the steps.

Every number drawn is read from the :class:`pampipe.diagnosis.result.DiagnoseResult`: the row
residuals of the baseline and of the selected model (computed by the command through
:class:`pampipe.model.muscle.Muscle`), the noise floors, the baseline's anchoring pressures, the
cells' checks and the steps of the selection. Nothing is refitted or re-evaluated here.

* ``residuals.png``: model − data before (top row) and after (bottom row) against the length split
  by the sign of L̇ (axial tests), the pressure, the pressure above anchoring (radial tests) and each
  radial test; the noise floor ±2σ is shaded.
* ``disagreement_map.png``: the mean residual of every (test, pressure level) cell before and after,
  in units of its standard error (|value| > 3 is systematic).
* ``candidates.png``: ΔBIC of every refit tried, step by step, and the sum of test RMSE of the
  baseline and of each model taken, against the sum of the noise floors.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure

COLORS = {"lengthening": "tab:red", "shortening": "tab:blue", "radial": "tab:green"}


def plot_diagnosis(result, folder: Path) -> list[Path]:
    """Write the three PNG files into ``folder``; return their paths."""
    return [_residuals(result, folder), _map(result, folder), _candidates(result, folder)]


def _label(result) -> str:
    effects = result.chosen.effects  # the refitted set (named, tied or undetermined)
    return f"with {' + '.join(effects)}" if effects else "baseline (nothing named)"


def _residuals(result, folder):
    data = result.data
    sigma = float(np.sqrt(np.mean([n.sigma**2 for n in result.noise])))
    fig, axes = new_figure(2, 4, figsize=(17, 8), sharey="col")
    for row, (label, residuals) in enumerate((("baseline", result.residuals[0]),
                                              (_label(result), result.residuals[1]))):
        ax_len, ax_p, ax_c, ax_t = axes[row]
        radial_names = []
        for index, (test, r) in enumerate(zip(data.tests, residuals, strict=True)):
            if test.kind == "axial":
                leg = test.leg
                for sign, name in ((1, "lengthening"), (-1, "shortening")):
                    m = leg == sign
                    ax_len.plot(test.length[m] * 1e3, r[m], ".", ms=2, color=COLORS[name], alpha=0.5,
                                label=f"{name} (L' {'>' if sign > 0 else '<'} 0)")
                ax_p.plot(test.pressure / 1e3, r, ".", ms=2, color="0.4", alpha=0.4)
            else:
                p_anchor = result.anchoring[index] or 0.0
                after = test.pressure > p_anchor
                ax_p.plot(test.pressure / 1e3, r, ".", ms=2, color=COLORS["radial"], alpha=0.4)
                ax_c.plot((test.pressure - p_anchor) / 1e3, r, ".", ms=3, alpha=0.6, label=test.name)
                pos = len(radial_names)
                jitter = 0.25 * np.random.default_rng(index).uniform(-1, 1, r.size)
                ax_t.plot(pos + jitter, r, ".", ms=2, alpha=0.6)
                mean = r[after].mean() if np.any(after) else 0.0
                ax_t.plot([pos - 0.35, pos + 0.35], [mean, mean], "k-", lw=2)
                radial_names.append(test.name)
        for ax in axes[row]:
            ax.axhspan(-2 * sigma, 2 * sigma, color="0.85", zorder=0)
            ax.axhline(0, color="k", lw=0.6)
        ax_len.set_title(f"{label}\naxial tests vs length", fontsize=9)
        ax_len.set_xlabel("length L [mm]")
        ax_len.set_ylabel(f"{label}\nresidual model - data [N]")
        ax_p.set_title(f"{label}\nall tests vs pressure (grey axial, green radial)", fontsize=9)
        ax_p.set_xlabel("measured pressure [kPa]")
        ax_c.set_title(f"{label}\nradial tests vs pressure above anchoring", fontsize=9)
        ax_c.set_xlabel("P - P_anchor (baseline) [kPa]")
        ax_c.axvline(0, color="k", lw=0.6, ls=":")
        ax_t.set_title(f"{label}\nradial tests (bar = mean once anchored)", fontsize=9)
        ax_t.set_xticks(range(len(radial_names)), radial_names, rotation=30, ha="right", fontsize=7)
        if row == 0:
            _dedupe_legend(ax_len)
            if radial_names:
                ax_c.legend(fontsize=6, markerscale=3)
    fig.suptitle(f"{Path(str(result.source)).name}: residuals before and after (grey band: noise floor "
                 f"±2σ = ±{2 * sigma:.2g} N); verdict: {result.verdict.verdict}")
    return save_figure(fig, folder, "residuals.png")


def _dedupe_legend(ax):
    handles, labels = ax.get_legend_handles_labels()
    if labels:
        unique = dict(zip(labels, handles, strict=True))
        ax.legend(unique.values(), unique.keys(), fontsize=7, markerscale=4)


def _cells(result, residuals):
    """(test names, level pressures [kPa], z = mean/(σ/√n) matrix tests × levels)."""
    data = result.data
    pressures = sorted({round(float(p) / 1e3) for t in data.tests for p in t.level_pressure})
    z = np.full((len(data.tests), len(pressures)), np.nan)
    for i, (test, r, floor) in enumerate(zip(data.tests, residuals, result.noise, strict=True)):
        for lev, p in enumerate(test.level_pressure):
            m = test.level == lev
            if np.any(m):
                z[i, pressures.index(round(float(p) / 1e3))] = r[m].mean() / (floor.sigma / np.sqrt(m.sum()))
    return [t.name for t in data.tests], pressures, z


def _map(result, folder):
    names, pressures, z_before = _cells(result, result.residuals[0])
    _, _, z_after = _cells(result, result.residuals[1])
    fig, axes = new_figure(1, 2, figsize=(15, 0.5 * len(names) + 3), sharey=True)
    for ax, z, label in ((axes[0], z_before, "baseline"), (axes[1], z_after, _label(result))):
        limit = _limit(z)  # each panel its own scale: the refit's residuals are far smaller
        image = ax.imshow(z, cmap="RdBu_r", vmin=-limit, vmax=limit, aspect="auto")
        ax.grid(False)  # cells, not a chart: the house grid would cross them
        ax.set_xticks(range(len(pressures)), [str(p) for p in pressures], rotation=45)
        ax.set_yticks(range(len(names)), names)
        ax.set_xlabel("pressure level [kPa]")
        ax.set_title(f"{label}: mean residual / standard error per cell\n"
                     "(|z| > 3 is systematic; blank = no data)")
        for (i, j), value in np.ndenumerate(z):
            if np.isfinite(value) and abs(value) > 3:
                ax.text(j, i, f"{value:.0f}", ha="center", va="center", fontsize=6)
        fig.colorbar(image, ax=ax, shrink=0.8, label="z = mean(model - data) / (σ/√n)")
    return save_figure(fig, folder, "disagreement_map.png")


def _limit(z: np.ndarray) -> float:
    """The colour scale's half-width: the 95th percentile of |z|, at least 3 (the systematic threshold)."""
    finite = np.abs(z[np.isfinite(z)])
    return max(3.0, float(np.percentile(finite, 95))) if finite.size else 3.0


def _candidates(result, folder):
    steps = [s for s in result.steps if s.trials]
    fig, (ax_bic, ax_rmse) = new_figure(1, 2, figsize=(14, 0.35 * sum(len(s.trials) for s in steps) + 3))
    labels, values, colors = [], [], []
    for step in steps:
        for trial in step.trials:
            sign = "-" if step.action in ("remove", "keep") else "+"
            labels.append(f"step {step.number}: {sign}{trial.effect}")
            values.append(trial.delta_bic if np.isfinite(trial.delta_bic) else 0.0)
            taken = step.action in ("add", "remove") and trial.effect == step.effect
            colors.append("tab:orange" if taken else ("tab:gray" if trial.model is not None else "tab:red"))
    ax_bic.barh(labels, values, color=colors)
    ax_bic.axvline(-10, color="k", ls=":", lw=1)
    ax_bic.axvline(10, color="k", ls=":", lw=1)
    ax_bic.set_xscale("symlog", linthresh=10)
    ax_bic.set_xlabel("BIC(tried) - BIC(model before the step)  (orange: taken)")
    ax_bic.invert_yaxis()
    taken = [s for s in steps if s.action in ("add", "remove")]
    names = ["baseline"] + [f"step {s.number}: {' + '.join(s.effects)}" for s in taken]
    sums = [result.baseline.sum_rmse] + [result.step_sum_rmse(s) for s in taken]
    ax_rmse.barh(names, sums, color="tab:blue")
    floor = sum(n.sigma for n in result.noise)
    ax_rmse.axvline(floor, color="k", ls="--", lw=1, label=f"sum of noise floors {floor:.3g} N")
    ax_rmse.set_xlabel("sum over tests of RMSE [N]")
    ax_rmse.invert_yaxis()
    ax_rmse.legend(fontsize=8)
    fig.suptitle(f"selection steps (verdict: {result.verdict.verdict}; named: "
                 f"{' + '.join(result.selected_effects) or 'none'})")
    return save_figure(fig, folder, "candidates.png")
