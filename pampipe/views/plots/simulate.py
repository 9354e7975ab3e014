"""Plots of `simulate`: radial force curves, the free-contraction curve, the amplification factor."""

from __future__ import annotations

from pathlib import Path

from pampipe.views.tables import new_figure, save_figure


def plot_simulation(result, folder: Path) -> list[Path]:
    """Write radial_force.png, free_contraction.png and amplification.png into ``folder``.

    Every number drawn comes from ``result`` (a :class:`pampipe.simulation.anchored.SimulateResult`).
    """
    cases, curves, name = result.cases, result.curves, result.pam
    grid = curves.pressure
    written = []

    fig, ax = new_figure(figsize=(7, 4.5))
    for c, radial in zip(cases, curves.radial_force, strict=True):
        line, = ax.plot(grid / 1e3, radial, label=f"D_p = {c.pipe_diameter * 1e3:.1f} mm, "
                                                   f"F_a = {c.axial_load:.0f} N")
        ax.plot(c.pressures / 1e3, c.radial_force, "o", color=line.get_color(), ms=4)
        ax.axvline(c.anchoring_pressure / 1e3, color=line.get_color(), ls=":", lw=1)
    ax.set(xlabel="gauge pressure P [kPa]", ylabel="radial (split-pipe) force F_r [N]",
           title=f"{name}: radial force (dotted: anchoring pressure)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    written.append(save_figure(fig, folder, "radial_force.png"))

    fig, ax = new_figure(figsize=(7, 4.5))
    for k, (load, lengths) in enumerate(curves.free_length.items()):
        ax.plot(grid / 1e3, lengths * 1e3, "k-" if k == 0 else "k--", lw=1.5 if k == 0 else 1,
                label=f"free contraction, F_a = {load:.0f} N")
    for c in cases:
        ax.axhline(c.anchored_length * 1e3, ls=":", lw=1, color="grey")
        ax.plot(c.anchoring_pressure / 1e3, c.anchored_length * 1e3, "o", ms=7,
                label=f"anchors in {c.pipe_diameter * 1e3:.1f} mm pipe, F_a = {c.axial_load:.0f} N: "
                      f"{c.anchoring_pressure / 1e3:.1f} kPa")
    ax.set(xlabel="gauge pressure P [kPa]", ylabel="length L [mm]",
           title=f"{name}: free contraction; anchoring where L_free = L(D_p) (dotted)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    written.append(save_figure(fig, folder, "free_contraction.png"))

    fig, ax = new_figure(figsize=(7, 4.5))
    ax.plot(curves.diameter * 1e3, curves.amplification_factor, "k-")
    ax.axhline(1.0, color="grey", lw=1, ls=":")
    for c in {c.pipe_diameter: c for c in cases}.values():
        ax.plot(c.pipe_diameter * 1e3, c.amplification_factor, "o", ms=7)
        ax.annotate(f"  A = {c.amplification_factor:.3f}", (c.pipe_diameter * 1e3, c.amplification_factor),
                    fontsize=8)
    ax.set(xlabel="pipe diameter D_p [mm]", ylabel="amplification factor A = 2πN²D/L [-]",
           title=f"{name}: amplification factor (A > 1 amplifies)")
    ax.grid(alpha=0.3)
    written.append(save_figure(fig, folder, "amplification.png"))
    return written


def plot_extension(result, folder: Path) -> Path:
    """Write extension.png: an extensile PAM's free length against pressure (from ``result``)."""
    fig, ax = new_figure(figsize=(7, 4.5))
    ax.plot(result.curve_pressure / 1e3, result.curve_length * 1e3, "k-", lw=1.5,
            label="free length, F_a = 0")
    ax.plot(result.pressures / 1e3, result.free_length * 1e3, "o", ms=4)
    ax.axhline(result.limit * 1e3, color="C3", ls=":", lw=1, label="braid limit B/√3")
    ax.axhline(result.initial_length * 1e3, color="0.5", ls="--", lw=1, label="rest length L₀")
    ax.set(xlabel="gauge pressure P [kPa]", ylabel="length L [mm]",
           title=f"{result.pam}: extension of an extensile PAM")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, folder, "extension.png")
