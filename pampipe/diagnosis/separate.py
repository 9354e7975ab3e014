"""Which new experiment would separate two confounded models (e.g. a third pipe diameter)?

Both refitted models (moduli + effects, through :class:`pampipe.model.muscle.Muscle`) predict a
small menu of experiments not in the data:

* a radial test at a new pipe diameter (midway between tested diameters, or ±8 % around a single
  one, inside the muscle's range), unloaded and at the largest tested load, 0…P_max;
* a radial test at a tested diameter under a new axial load (twice the largest tested, ≥ 500 N);
* an axial test at 1.25 × the largest tested pressure, both legs, from L_free to L₀.

The advice must not follow the noise (the same case gives the same advice on every seed), so it is judged
on the case's structure, not on the noise floor: with G the largest difference of the two models' forces
over an experiment [N] and S the size of the effects in the data, the largest change either model makes to
the baseline's predictions over the tested cells [N], the share G/S does not depend on the noise and, to
first order, not on the effect's magnitude (G and S both scale with it). The experiment proposed is the
first of the menu whose G is within :data:`NEAR_BEST` of the best (the menu's order breaks near-ties, so
two close experiments do not swap between seeds); it *separates* the pair when G/S ≥ :data:`SEPARATES`.
G in units of the pooled noise floor σ (``ratio``) says how many repeats it needs to resolve: n ≈ (3/ratio)².
"""

from __future__ import annotations

import itertools

import numpy as np

from pampipe.diagnosis.refit import SMOOTHING
from pampipe.errors import SolverError

#: An experiment separates two tied models when they differ there by this share of the effects' size.
SEPARATES = 0.1
#: Experiments within this share of the largest difference count as equally good (the first is proposed).
NEAR_BEST = 0.8


def _menu(data, geometry):
    radial = [t for t in data.tests if t.kind == "radial"]
    axial = [t for t in data.tests if t.kind == "axial"]
    items = []
    if radial:
        diameters = sorted({t.spec.pipe_diameter for t in radial})
        loads = sorted({t.spec.axial_load for t in radial})
        p_max = max(float(t.pressure.max()) for t in radial)
        low, high = geometry.initial_diameter * 1.001, geometry.largest_diameter * 0.999
        new = [(a + b) / 2 for a, b in itertools.pairwise(diameters)]
        if len(diameters) == 1:
            new = [diameters[0] * 0.92, diameters[0] * 1.08]
        for d in new:
            if low < d < high:
                for load in {loads[0], loads[-1]}:
                    items.append((f"a radial test in a {d * 1e3:.1f} mm pipe at {load:.0f} N axial load "
                                  f"(diameters tested: {', '.join(f'{x * 1e3:.1f}' for x in diameters)} mm)",
                                  "radial", d, load, p_max))
        load = max(2 * loads[-1], 500.0)
        for d in diameters:
            tested = ", ".join(f"{x:.0f}" for x in loads)
            items.append((f"a radial test in the {d * 1e3:.1f} mm pipe at {load:.0f} N axial load "
                          f"(loads tested: {tested} N)", "radial", d, load, p_max))
    if axial:
        p_max = max(float(t.pressure.max()) for t in axial)
        items.append((f"an axial test at {1.25 * p_max / 1e3:.0f} kPa (tested up to {p_max / 1e3:.0f} kPa), "
                      "both legs", "axial", None, 0.0, 1.25 * p_max))
    return items


def effect_size(base_fit, *fits) -> float:
    """S [N]: the largest change any of ``fits`` makes to ``base_fit``'s prediction of a tested cell (the
    residuals share the data, so their difference is the difference of the predictions)."""
    return max(float(np.max(np.abs(fit.residual - base_fit.residual))) for fit in fits)


def separating_experiment(data, refitter, fit_a, fit_b, floors, base_fit) -> dict | None:
    """{experiment, max_difference_N, effect_size_N, share, separates, noise_floor_N, ratio} of the proposed
    menu item (see the module docstring; None if the menu is empty)."""
    a, b = refitter.muscle(fit_a), refitter.muscle(fit_b)
    sigma = float(np.sqrt(np.mean([f.sigma**2 for f in floors])))
    gaps = []
    for text, kind, diameter, load, p_max in _menu(data, refitter.geometry):
        if kind == "radial":
            pressure = np.linspace(0.0, p_max, 60)
            fa = a.radial_force(pressure, diameter, load, smoothing=SMOOTHING)
            fb = b.radial_force(pressure, diameter, load, smoothing=SMOOTHING)
        else:
            g = refitter.geometry
            try:
                shortest = float(np.min(a.free_length(np.array([p_max]))))
            except SolverError:  # no free length at this pressure: nothing to propose
                continue
            length = np.linspace(max(shortest, g.shortest_length * 1.001), g.initial_length, 40)
            fa = np.concatenate([a.axial_force(p_max, length, leg=leg) for leg in (-1.0, 1.0)])
            fb = np.concatenate([b.axial_force(p_max, length, leg=leg) for leg in (-1.0, 1.0)])
        gap = float(np.nanmax(np.abs(np.asarray(fa, dtype=float) - np.asarray(fb, dtype=float))))
        if np.isfinite(gap):
            gaps.append((text, gap))
    if not gaps:
        return None
    largest = max(gap for _, gap in gaps)
    text, gap = next((text, gap) for text, gap in gaps if gap >= NEAR_BEST * largest)
    size = effect_size(base_fit, fit_a, fit_b)
    share = gap / size if size > 0 else 0.0
    return {"experiment": text, "max_difference_N": gap, "effect_size_N": size, "share": share,
            "separates": share >= SEPARATES, "noise_floor_N": sigma,
            "ratio": gap / sigma if sigma > 0 else None}
