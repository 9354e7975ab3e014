"""Plots of `identify`: measured vs model per pressure, residuals, and the Drucker margin."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure

#: At most this many measured points per panel are drawn (a uniform subsample of the rows).
MAX_POINTS = 6000


#: Markers of the direction of a row: lengthening / filling, shortening / venting, held or unknown.
MARKERS = {1: "^", -1: "v", 0: "o"}


def plot_identification(data, result, folder: Path) -> list[Path]:
    """Write axial_fit.png (force against length, isobaric and mixed tests), isometric_fit.png (force
    against pressure, isometric tests), radial_fit.png, residuals.png and drucker_margin.png (those
    that apply)."""
    written = []
    curves = result.curves(data)  # computed by the result; the plots only draw
    axial = [t for t in data.tests if t.kind == "axial" and t.protocol != "isometric"]
    isometric = [t for t in data.tests if t.kind == "axial" and t.protocol == "isometric"]
    radial = [t for t in data.tests if t.kind == "radial"]
    if axial:
        written.append(_axial(axial, curves, result, folder))
    if isometric:
        written.append(_isometric(isometric, curves, result, folder))
    if radial:
        written.append(_radial(radial, curves, result, folder))
    written.append(_residuals(data, curves, result, folder))
    if curves.drucker is not None:
        written.append(_drucker(curves.drucker, result, folder))
    return written


def _subsample(n: int) -> np.ndarray:
    return np.arange(n) if n <= MAX_POINTS else np.linspace(0, n - 1, MAX_POINTS).astype(int)


def _measured(ax, test, x, colors, result):
    """The measured points: one marker per direction (legs visible), slack rows hollow, excluded ×."""
    rows = _subsample(test.points)
    legs = test.pressure_leg if test.protocol == "isometric" else test.leg
    slack = test.slack[rows]
    for sign, marker in MARKERS.items():
        mine = rows[(legs[rows] == sign) & ~slack]
        if mine.size:
            ax.scatter(x[mine], test.force[mine], s=9, marker=marker, c=colors[mine], alpha=0.6, linewidths=0)
    shown = rows[slack]
    if shown.size:
        excluded = result.options.slack == "exclude"
        ax.scatter(x[shown], test.force[shown], s=16, marker="x" if excluded else "o",
                   facecolors="gray" if excluded else "none", edgecolors="gray", linewidths=0.8,
                   label="slack rows (excluded)" if excluded else "slack rows (fitted as max(0, F))")


def _legend_directions(ax, isometric: bool) -> None:
    from matplotlib.lines import Line2D

    up, down = ("filling", "venting") if isometric else ("lengthening", "shortening")
    handles = [Line2D([], [], marker=MARKERS[1], ls="", color="k", label=up),
               Line2D([], [], marker=MARKERS[-1], ls="", color="k", label=down)]
    existing, _ = ax.get_legend_handles_labels()
    ax.legend(handles=existing + handles, fontsize=7, ncol=2)


def _axial(tests, curves, result, folder: Path) -> Path:
    fig, axes = new_figure(1, len(tests), figsize=(7.5 * len(tests), 5), squeeze=False)
    for ax, test in zip(axes[0], tests, strict=True):
        colors = _level_colors(test.level_pressure.size)[test.level]
        _measured(ax, test, test.length * 1e3, colors, result)
        level_colors = _level_colors(test.level_pressure.size)
        for curve in (c for c in curves.axial if c.test == test.name):
            ax.plot(curve.length * 1e3, curve.force, color=level_colors[curve.level], lw=1.5,
                    label=f"{curve.pressure / 1e3:.0f} kPa")
        ax.set(xlabel="length L [mm]", ylabel="axial force F_ax [N]",
               title=f"{test.name} ({test.protocol}): measured (markers) and fitted model (lines)")
        ax.grid(alpha=0.3)
        _legend_directions(ax, isometric=False)
    return save_figure(fig, folder, "axial_fit.png")


def _isometric(tests, curves, result, folder: Path) -> Path:
    fig, axes = new_figure(1, len(tests), figsize=(7.5 * len(tests), 5), squeeze=False)
    for ax, test in zip(axes[0], tests, strict=True):
        palette = _level_colors(test.level_length.size)
        _measured(ax, test, test.pressure / 1e3, palette[test.held_length], result)
        for curve in (c for c in curves.isometric if c.test == test.name):
            ax.plot(curve.pressure / 1e3, curve.force, color=palette[curve.held], lw=1.5,
                    label=f"L = {curve.length * 1e3:.5g} mm")
        ax.set(xlabel="gauge pressure P [kPa]", ylabel="axial force F_ax [N]",
               title=f"{test.name} (isometric): measured (markers) and fitted model (lines)")
        ax.grid(alpha=0.3)
        _legend_directions(ax, isometric=True)
    return save_figure(fig, folder, "isometric_fit.png")


def _radial(tests, curves, result, folder: Path) -> Path:
    fig, ax = new_figure(figsize=(8, 5.5))
    model = {c.test: c for c in curves.radial}
    for i, test in enumerate(tests):
        rows = _subsample(test.points)
        color = f"C{i % 10}"
        ax.plot(test.pressure[rows] / 1e3, test.force[rows], ".", ms=3, alpha=0.35, color=color)
        curve = model[test.name]
        ax.plot(curve.pressure / 1e3, curve.force, color=color, lw=1.5,
                label=f"{test.name} (RMSE {result.tests[_index(result, test.name)].rmse:.3g} N)")
    ax.set(xlabel="gauge pressure P [kPa]", ylabel="radial (split-pipe) force F_r [N]",
           title="radial tests: measured (dots) and fitted model (lines)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, folder, "radial_fit.png")


def _residuals(data, curves, result, folder: Path) -> Path:
    has_axial = any(t.kind == "axial" for t in data.tests)
    fig, axes = new_figure(1, 2 if has_axial else 1, figsize=(13 if has_axial else 7, 4.8), squeeze=False)
    for i, test in enumerate(data.tests):
        residual = curves.residuals[test.name]
        rows = _subsample(test.points)
        axes[0, 0].plot(test.pressure[rows] / 1e3, residual[rows], ".", ms=3, alpha=0.4, color=f"C{i % 10}",
                        label=test.name)
        if test.kind == "axial" and axes.shape[1] > 1:
            axes[0, 1].plot(test.length[rows] * 1e3, residual[rows], ".", ms=3, alpha=0.4, color=f"C{i % 10}",
                            label=test.name)
    sigma = result.uncertainty.sigma
    for ax in axes[0]:
        for sign in (-2, 2):
            ax.axhline(sign * sigma, color="k", ls=":", lw=1)
        ax.axhline(0, color="k", lw=0.8)
        ax.set_ylabel("model − measured [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, markerscale=3)
    axes[0, 0].set(xlabel="gauge pressure P [kPa]",
                   title=f"residuals vs pressure (dotted: ±2σ, σ = {sigma:.3g} N)")
    if has_axial:
        axes[0, 1].set(xlabel="length L [mm]", title="axial residuals vs length")
    return save_figure(fig, folder, "residuals.png")


def _drucker(drucker, result, folder: Path) -> Path:
    grid = result.drucker_grid
    pp, ll = np.meshgrid(drucker.pressure, drucker.length, indexing="ij")
    margin = drucker.margin / 1e6
    low = drucker.minimum
    fig, ax = new_figure(figsize=(7.5, 5))
    image = ax.pcolormesh(ll * 1e3, pp / 1e3, margin, shading="auto", cmap="viridis")
    fig.colorbar(image, ax=ax, label="min(E₁ᵗ, E₂ᵗ) [MPa]")
    if margin.min() < 0 < margin.max():
        zero = ax.contour(ll * 1e3, pp / 1e3, margin, levels=[0], colors="red", linewidths=1.5)
        zero.set_label("margin = 0 (unstable beyond)")
    gp, gl = np.meshgrid(grid["pressures"], grid["lengths"], indexing="ij")
    ax.plot(gl.ravel() * 1e3, gp.ravel() / 1e3, "w+", ms=5, label="constraint grid")
    verdict = "stable" if low.stable else "UNSTABLE"
    ax.plot(low.length * 1e3, low.pressure / 1e3, "r*", ms=12, clip_on=False, zorder=5,
            label=f"exact minimum {low.value / 1e6:.3g} MPa ({low.direction})")
    ax.margins(0.04)  # the minimum often lies on the box's edge: keep the star inside the frame
    ax.set(xlabel="length L [mm]", ylabel="gauge pressure P [kPa]",
           title=f"Drucker margin (exact minimum {low.value / 1e6:.3g} MPa: {verdict})")
    legend = fig.legend(fontsize=8, loc="outside lower center", ncols=2)
    for handle, text in zip(legend.legend_handles, legend.get_texts(), strict=True):
        if text.get_text() == "constraint grid":  # white on the map; white on the legend's white: grey there
            handle.set_color("0.35")
    return save_figure(fig, folder, "drucker_margin.png")


def _level_colors(n: int) -> np.ndarray:
    from matplotlib import colormaps

    return colormaps["viridis"](np.linspace(0, 0.9, max(n, 1)))


def _index(result, name: str) -> int:
    return [t.name for t in result.tests].index(name)


def plot_result(result, folder: Path) -> list[Path]:
    """:func:`plot_identification` of a result returned by :func:`pampipe.identify` (which keeps its data)."""
    return plot_identification(_data(result), result, folder)


def _data(result):
    data = getattr(result, "experiment_data", None)
    if data is None:
        from pampipe.errors import InputError

        raise InputError("plot(): this result does not carry its experiment data; get it from "
                         "pampipe.identify(...), or call "
                         "pampipe.views.plots.identify.plot_identification(data, result, folder).")
    return data
