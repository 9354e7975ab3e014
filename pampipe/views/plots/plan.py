"""Plots of `plan`: the required pressure along the route, and holding capacity against pressure."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.units.quantities import to_si
from pampipe.views.tables import new_figure, save_figure

MAX_CURVES = 8  # sections drawn in the capacity plot (the first ones with a plan)


def plot_plan(plan, folder: Path, *, unit: str = "kPa") -> list[Path]:
    """Write required_pressure.png and holding_capacity.png into ``folder``, pressures in ``unit``; for a
    route read from a network also network_pressure.png, and for any route but a whole network
    route_profile.png (:mod:`pampipe.views.plots.network`); with a tether tether_profile.png
    (:mod:`pampipe.views.plots.tether`); with ``--confidence`` confidence_tornado.png
    (:mod:`pampipe.views.plots.tornado`).

    Every number drawn comes from ``plan`` (a :class:`pampipe.planning.MissionPlan`), curves included.
    """
    from pampipe.views.plots.network import network_pressure, route_profile
    from pampipe.views.plots.tornado import plot_tornado

    scale = to_si(f"1 {unit}", "pressure")
    paths = [_required_pressure(plan, folder, unit, scale), _holding_capacity(plan, folder, unit, scale)]
    origin = plan.arrays.route.origin
    if origin is None or not origin.whole:
        paths.append(route_profile(plan, folder, unit, scale))
    if plan.tether is not None:
        from pampipe.views.plots.tether import tether_profile

        paths.append(tether_profile(plan, folder, unit, scale))
    if origin is not None:
        drawn = network_pressure(plan, folder, unit, scale)
        paths += [drawn] if drawn is not None else []
    if plan.bends:
        from pampipe.views.plots.bends import tightest_bend

        drawn = tightest_bend(plan, folder)
        paths += [drawn] if drawn is not None else []
    tornado = plot_tornado(plan, folder, unit, scale)
    return paths + ([tornado] if tornado is not None else [])


def _required_pressure(plan, folder: Path, unit: str, scale: float) -> Path:
    fig, ax = new_figure(figsize=(8, 4.5))
    a = plan.arrays
    edges = np.concatenate([[0.0], np.cumsum(a.route.length)])
    for k, names in enumerate(_distinct_columns(a.pressure, a.segment_names)):
        values = np.where(a.complete, a.pressure[:, a.segment_names.index(names[0])], np.nan) / scale
        ax.stairs(values, edges, baseline=None, lw=2.2 - 0.5 * k, color=f"C{k}",
                  label=f"{', '.join(names)}: planned pressure")
    anchoring = np.where(a.complete, np.max(a.largest_bore_anchoring, axis=1), np.nan) / scale
    ax.stairs(anchoring, edges, baseline=None, color="grey", ls=":", lw=1.5,
              label="anchoring pressure (no load, largest bore)")
    supply = plan.supply_pressure / scale
    low, high = _pressure_range(a.pressure[a.complete] / scale, anchoring, supply)
    if supply <= high:
        ax.axhline(supply, color="C3", ls="--", lw=1.2, label="supply pressure")
    else:  # far above the plan: an axis up to it would flatten every step between sections
        ax.annotate(f"supply pressure {supply:.4g} {unit}: above this axis", (0.01, 0.97),
                    xycoords="axes fraction", va="top", fontsize=8, color="C3")
    for n, s in enumerate(sorted(a.reasons)):
        ax.axvspan(edges[s], edges[s + 1], color="C3", alpha=0.12, lw=0,
                   label="infeasible section" if n == 0 else None)
    if len(a.route) <= 30:
        top = ax.secondary_xaxis("top")
        tilted = len(plan.sections) > 3
        top.set_xticks((edges[:-1] + edges[1:]) / 2, [sec.name for sec in plan.sections],
                       rotation=30 if tilted else 0, fontsize=8, ha="left" if tilted else "center")
        for label, sec in zip(top.get_xticklabels(), plan.sections, strict=True):
            label.set_color("k" if sec.feasible else "C3")
    ax.set_ylim(low, high)
    ax.set(xlabel="distance along the route [m]", ylabel=f"gauge pressure [{unit}]",
           title="required anchoring pressure along the route")
    fig.legend(fontsize=8, loc="outside right upper")
    return save_figure(fig, folder, "required_pressure.png")


def _pressure_range(planned: np.ndarray, anchoring: np.ndarray, supply: float) -> tuple[float, float]:
    """The pressure axis: the planned and anchoring pressures with a margin of a fifth of their spread (at
    least 5 % of the largest), from 0 when they reach down near it; up to the supply when the supply lies
    within half the plan's largest pressure above it (else the supply is named above the axis)."""
    values = np.concatenate([np.ravel(planned), np.ravel(anchoring)])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return 0.0, 1.05 * supply
    lo, hi = float(values.min()), float(values.max())
    pad = max(0.2 * (hi - lo), 0.05 * hi)
    top = 1.05 * supply if supply <= 1.5 * hi else hi + pad
    bottom = 0.0 if lo - pad < 0.25 * hi else lo - pad
    return bottom, top


def _distinct_columns(pressure: np.ndarray, names) -> list[list[str]]:
    """Segment names grouped by identical planned pressures along the whole route (drawn as one line)."""
    groups: list[list[str]] = []
    for k, name in enumerate(names):
        same = next((g for g in groups if np.array_equal(pressure[:, list(names).index(g[0])], pressure[:, k],
                                                         equal_nan=True)), None)
        if same is None:
            groups.append([name])
        else:
            same.append(name)
    return groups


def _holding_capacity(plan, folder: Path, unit: str, scale: float) -> Path:
    fig, ax = new_figure(figsize=(8, 4.8))
    drawn = [(s, sec) for s, sec in enumerate(plan.sections) if sec.segments][:MAX_CURVES]
    top = max([plan.supply_pressure] + [max(x.pressure for x in sec.segments) for _, sec in drawn])
    grid = np.linspace(0.0, 1.1 * top, 400)
    for n, (s, sec) in enumerate(drawn):
        k = int(np.argmax([x.pressure for x in sec.segments]))
        point = sec.segments[k]
        capacity = plan.capacity_curve(s, k, grid)
        color = f"C{n % 10}"
        capacity = np.where(capacity > 0, capacity, np.nan)  # zero before contact: off the log axis
        ax.plot(grid / scale, capacity, color=color, lw=1.5,
                label=f"{sec.name} ({point.name}, {point.worst_diameter * 1e3:.1f} mm, "
                      f"W = {point.required_hold:.3g} N)")
        ax.axhline(plan.safety_factor * point.required_hold, color=color, ls="--", lw=0.8)
        ax.plot(point.pressure / scale, point.holding_capacity, "o", color=color, ms=7,
                mec="k" if point.feasible else "C3", mew=1.2)
    ax.axvline(plan.supply_pressure / scale, color="C3", ls="--", lw=1.2, label="supply pressure")
    needed = [plan.safety_factor * x.required_hold for _, sec in drawn for x in sec.segments]
    positive = [v for v in needed if v > 0] or [1.0]
    ax.set_yscale("log")
    ax.set_ylim(0.3 * min(positive), 3 * max(max(positive), _capacity_at(plan, drawn, top)))
    ax.set(xlabel=f"gauge pressure P [{unit}]", ylabel="holding capacity μπF_r [N]",
           title=f"holding capacity vs pressure\ndashed: {plan.safety_factor:g} × required hold; dots: "
                 "operating points\n(curves start where the muscle touches the wall)")
    fig.legend(fontsize=7, loc="outside right upper")
    return save_figure(fig, folder, "holding_capacity.png")


def _capacity_at(plan, drawn, pressure: float) -> float:
    """Largest holding capacity [N] of the drawn elements at ``pressure`` (top of the log axis)."""
    best = 1.0
    for s, sec in drawn:
        for k in range(len(sec.segments)):
            best = max(best, float(plan.capacity_curve(s, k, [pressure])[0]))
    return best
