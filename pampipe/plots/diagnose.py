"""Plots of `diagnose`: residuals before/after against the signature variables, and where they were.

* ``residuals.png``: model − data before (top row, baseline) and after (bottom row, refit with the
  selected effect) against the length split by the sign of L̇ (axial tests), the pressure, the
  pressure above anchoring (radial tests) and each radial test (load, pipe); the noise floor ±2σ
  is shaded.
* ``disagreement_map.png``: the mean residual of every (test, pressure level) cell, before and after,
  in units of its standard error (|value| > 3 is systematic), so the missing effect shows where it acts.
* ``candidates.png``: ΔBIC and the sum of test RMSE of each candidate.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.report import new_figure, save_figure

COLORS = {"lengthening": "tab:red", "shortening": "tab:blue", "radial": "tab:green"}


def plot_diagnosis(result, folder: Path) -> list[Path]:
    """Write the three PNG files into ``folder``; return their paths."""
    return [_residuals(result, folder), _map(result, folder), _candidates(result, folder)]


def _residuals(result, folder):
    data = result.data
    before, after = result.baseline.residuals, result.chosen.residuals
    sigma = float(np.sqrt(np.mean([n.sigma**2 for n in result.noise])))
    fig, axes = new_figure(2, 4, figsize=(17, 8), sharey="col")
    for row, (label, residuals) in enumerate((("baseline", before),
                                              (f"with {result.selected}", after))):
        ax_len, ax_p, ax_c, ax_t = axes[row]
        radial_names = []
        for index, (test, r) in enumerate(zip(data.tests, residuals, strict=True)):
            if test.kind == "axial":
                for leg, name in ((1, "lengthening"), (-1, "shortening")):
                    m = test.leg == leg
                    ax_len.plot(test.length[m] * 1e3, r[m], ".", ms=2, color=COLORS[name], alpha=0.5,
                                label=f"{name} (L' {'>' if leg > 0 else '<'} 0)")
                ax_p.plot(test.pressure / 1e3, r, ".", ms=2, color="0.4", alpha=0.4)
            else:
                p_anchor = result.anchoring[index] or 0.0
                ax_p.plot(test.pressure / 1e3, r, ".", ms=2, color=COLORS["radial"], alpha=0.4)
                ax_c.plot((test.pressure - p_anchor) / 1e3, r, ".", ms=3, alpha=0.6, label=test.name)
                pos = len(radial_names)
                ax_t.plot(pos + 0.25 * np.random.default_rng(index).uniform(-1, 1, r.size), r, ".", ms=2,
                          alpha=0.6)
                ax_t.plot([pos - 0.35, pos + 0.35], [r[test.pressure > p_anchor].mean()] * 2
                          if np.any(test.pressure > p_anchor) else [0, 0], "k-", lw=2)
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
            ax_c.legend(fontsize=6, markerscale=3)
    fig.suptitle(f"{Path(str(result.source)).name}: residuals before and after "
                 f"(grey band: noise floor ±2σ = ±{2 * sigma:.2g} N); selected: {result.selected}")
    return save_figure(fig, folder, "residuals.png")


def _dedupe_legend(ax):
    handles, labels = ax.get_legend_handles_labels()
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
    names, pressures, z_before = _cells(result, result.baseline.residuals)
    _, _, z_after = _cells(result, result.chosen.residuals)
    limit = max(5.0, float(np.nanpercentile(np.abs(z_before), 95)))
    fig, axes = new_figure(1, 2, figsize=(15, 0.5 * len(names) + 3), sharey=True)
    for ax, z, label in ((axes[0], z_before, "baseline"), (axes[1], z_after, f"with {result.selected}")):
        image = ax.imshow(z, cmap="RdBu_r", vmin=-limit, vmax=limit, aspect="auto")
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


def _candidates(result, folder):
    cands = list(result.candidates)
    fig, (ax_bic, ax_rmse) = new_figure(1, 2, figsize=(13, 4.5))
    names = [c.effect for c in cands]
    colors = ["tab:orange" if c.effect == result.selected else "tab:gray" for c in cands]
    ax_bic.barh(names, [c.delta_bic for c in cands], color=colors)
    ax_bic.axvline(-10, color="k", ls=":", lw=1)
    ax_bic.set_xscale("symlog", linthresh=10)
    ax_bic.set_xlabel("BIC(candidate) - BIC(baseline)  (< -10 needed)")
    ax_bic.invert_yaxis()
    ax_rmse.barh(["baseline", *names], [result.baseline.sum_rmse, *[c.sum_rmse for c in cands]],
                 color=["tab:blue", *colors])
    floor = sum(n.sigma for n in result.noise)
    ax_rmse.axvline(floor, color="k", ls="--", lw=1, label=f"sum of noise floors {floor:.3g} N")
    ax_rmse.set_xlabel("sum over tests of RMSE [N]")
    ax_rmse.invert_yaxis()
    ax_rmse.legend(fontsize=8)
    fig.suptitle(f"candidates (selected: {result.selected})")
    return save_figure(fig, folder, "candidates.png")
