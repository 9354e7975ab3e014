"""Residual structure of a fit: the noise floor, the candidate signatures, the worst regions.

All residuals are r = F_model − F_data [N].

**Noise floor** (per test). Two estimates that ignore slow, systematic residuals:
``repeats``: rows sorted by their signature variables (axial: level, leg, length; radial: level,
pressure); each row is compared with the line through its two neighbours (see
:func:`_neighbour_sigma`): with repeated cycles the neighbours are repeats of the same point, and
a systematic part that is locally linear in (P, L, leg) cancels.
``high_frequency``: the same in recorded order within each pressure level. The floor is the
``repeats`` value.

**Signatures**: least-squares fits of r on small feature sets (per test or pooled), each reported
as the RMS of the fitted part [N] and a score z = (SS_fit/σ² − k)/√(2k) (≈ N(0, 1) for pure noise
with k features; large when the structure is real):

* ``length_rate``: the sign of L̇ per pressure level (axial tests; hysteresis, §9a);
* ``pressure``: 1 and P per test (an offset or a gain, §9e, §9b);
* ``contact``: before/after anchoring and (P − P_anchor)₊ per radial test (§9d, §9f, §9c);
* ``axial_load``: loaded against unloaded radial tests of the same pipe, once anchored (§9g);
* ``stroke_ends``: (1 − s)⁴ and s⁴ per axial level, s = (L − L_min)/(L₀ − L_min) (§9c);
* ``autocorrelation``: the lag-1 autocorrelation of r in recorded order, per test (z = ρ₁√n).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIGNATURES = ("length_rate", "pressure", "contact", "axial_load", "stroke_ends", "autocorrelation")


@dataclass(frozen=True)
class NoiseFloor:
    test: str
    repeats: float  # [N]
    high_frequency: float  # [N]

    @property
    def sigma(self) -> float:
        return self.repeats if np.isfinite(self.repeats) else self.high_frequency


@dataclass(frozen=True)
class Signature:
    name: str
    rms: float  # RMS of the fitted part over the rows it applies to [N]
    score: float  # z score (see the module docstring)
    rows: int


@dataclass(frozen=True)
class Region:
    """A cell (test × pressure range × length range) with a systematic mean residual."""

    test: str
    pressure: tuple[float, float]  # [Pa]
    length: tuple[float, float] | None  # [m] (axial tests)
    anchored: bool | None  # radial tests: after anchoring?
    mean: float  # mean residual [N]
    rmse: float  # [N]
    rows: int
    score: float  # |mean|√n/σ


def _neighbour_sigma(r: np.ndarray, x: np.ndarray, order: np.ndarray, groups: np.ndarray) -> float:
    """σ from each row's deviation from the line through its two neighbours (sorted by ``x``).

    e_i = r_i − (w₋r_{i−1} + w₊r_{i+1}) with linear-interpolation weights in x (½, ½ when the
    neighbours share x); Var e_i = σ²(1 + w₋² + w₊²) for white noise, and a residual that is locally
    linear in x cancels, also with repeated x (repeated cycles).
    """
    r, x, groups = r[order], x[order], groups[order]
    same = (groups[2:] == groups[1:-1]) & (groups[1:-1] == groups[:-2])
    span = x[2:] - x[:-2]
    safe = np.where(span > 0, span, 1.0)
    w_next = np.where(span > 0, (x[1:-1] - x[:-2]) / safe, 0.5)
    w_prev = 1 - w_next
    e = r[1:-1] - w_prev * r[:-2] - w_next * r[2:]
    scaled = (e**2 / (1 + w_prev**2 + w_next**2))[same]
    return float(np.sqrt(np.mean(scaled))) if scaled.size else float("nan")


def noise_floor(test, r: np.ndarray) -> NoiseFloor:
    """Both estimates of σ [N] for one test (``test`` is a :class:`pampipe.experiment.TestData`)."""
    recorded = np.arange(r.size)
    hf = _neighbour_sigma(r, recorded.astype(float), recorded, test.level)
    if test.kind == "axial":
        order = np.lexsort((test.length, test.leg, test.level))
        group, x = test.level * 3 + (test.leg + 1), test.length
    else:
        order = np.lexsort((test.pressure, test.level))
        group, x = test.level, test.pressure
    return NoiseFloor(test.name, _neighbour_sigma(r, x, order, group), hf)


def _fit_part(r: np.ndarray, features: np.ndarray) -> tuple[float, int]:
    """(SS of the least-squares fit of r on the columns of ``features``, rank)."""
    if r.size == 0 or features.size == 0:
        return 0.0, 0
    coef, *_ = np.linalg.lstsq(features, r, rcond=None)
    fitted = features @ coef
    return float(fitted @ fitted), int(np.linalg.matrix_rank(features))


def _score(ss: float, k: int, sigma: float) -> float:
    return (ss / sigma**2 - k) / np.sqrt(2 * k) if k else 0.0


def _dummies(labels: np.ndarray) -> np.ndarray:
    values = np.unique(labels)
    return (labels[:, None] == values[None, :]).astype(float)


def signatures(data, residuals: list[np.ndarray], anchoring: list[float | None], sigma: float
               ) -> list[Signature]:
    """Every signature of :data:`SIGNATURES`, pooled over the tests it applies to.

    ``residuals[i]`` and ``anchoring[i]`` (P_anchor of the baseline, radial tests) follow
    ``data.tests``; ``sigma`` is the pooled noise floor [N]. Each feature set includes the
    per-test (or per-level) constants, whose share is subtracted, so a plain offset is not
    counted twice.
    """
    sums = {name: [0.0, 0, 0] for name in SIGNATURES}  # SS, k, rows

    def add(name, r, with_features, base):
        ss_full, k_full = _fit_part(r, np.column_stack([base, with_features]))
        ss_base, k_base = _fit_part(r, base)
        entry = sums[name]
        entry[0] += ss_full - ss_base
        entry[1] += k_full - k_base
        entry[2] += r.size

    loads_by_pipe: dict[float, list] = {}
    for test, r, p_anchor in zip(data.tests, residuals, anchoring, strict=True):
        x = test.pressure / 1e6
        const = np.ones((r.size, 1))
        add("pressure", r, x[:, None], const)
        if r.size > 2:
            rho = float(np.corrcoef(r[:-1], r[1:])[0, 1])
            sums["autocorrelation"][0] += rho * np.sqrt(r.size)  # z of ρ₁, summed then averaged
            sums["autocorrelation"][1] += 1
            sums["autocorrelation"][2] += r.size
        if test.kind == "axial":
            levels = _dummies(test.level)
            add("length_rate", r, levels * test.leg[:, None], levels)
            s = np.zeros(r.size)
            for lev in np.unique(test.level):
                m = test.level == lev
                lo, hi = test.length[m].min(), test.length[m].max()
                s[m] = (test.length[m] - lo) / max(hi - lo, 1e-12)
            ends = np.column_stack([levels * ((1 - s) ** 4)[:, None], levels * (s**4)[:, None]])
            add("stroke_ends", r, ends,
                levels)
        else:
            after = (test.pressure > (p_anchor if p_anchor is not None else 0.0)).astype(float)
            excess = np.maximum(test.pressure - (p_anchor or 0.0), 0.0) / 1e6
            add("contact", r, np.column_stack([after, excess]), const)
            loads_by_pipe.setdefault(test.spec.pipe_diameter, []).append((test.spec.axial_load, r, after))
    for group in loads_by_pipe.values():
        if len({load for load, _, _ in group}) < 2:
            continue
        r = np.concatenate([g[1] for g in group])
        after = np.concatenate([g[2] for g in group])
        loaded = np.concatenate([np.full(g[1].size, g[0] != 0.0, dtype=float) for g in group])
        add("axial_load", r, (after * loaded)[:, None], np.column_stack([np.ones(r.size), after]))
    out = []
    for name in SIGNATURES:
        ss, k, rows = sums[name]
        if name == "autocorrelation":
            score = ss / max(k, 1)
            out.append(Signature(name, float("nan"), float(score), int(rows)))
        else:
            rms = float(np.sqrt(max(ss, 0.0) / max(rows, 1)))
            out.append(Signature(name, rms, float(_score(ss, k, sigma)),
                                 int(rows)))
    return out


def regions(data, residuals: list[np.ndarray], anchoring: list[float | None], sigma: float, *,
            top: int = 5, length_bins: int = 3) -> list[Region]:
    """The ``top`` cells with the largest systematic mean residual (score |mean|√n/σ)."""
    cells = []
    for test, r, p_anchor in zip(data.tests, residuals, anchoring, strict=True):
        for lev in np.unique(test.level):
            m = test.level == lev
            if test.kind == "axial":
                lengths = test.length[m]
                edges = np.linspace(lengths.min(), lengths.max(), length_bins + 1)
                which = np.clip(np.searchsorted(edges, lengths, side="right") - 1, 0, length_bins - 1)
                parts = [(which == b, (edges[b], edges[b + 1]), None) for b in range(length_bins)]
            else:
                after = test.pressure[m] > (p_anchor if p_anchor is not None else 0.0)
                parts = [(after, None, True), (~after, None, False)]
            rr, pp = r[m], test.pressure[m]
            for sel, span, anchored in parts:
                if not np.any(sel):
                    continue
                mean = float(rr[sel].mean())
                cells.append(Region(test.name, (float(pp[sel].min()), float(pp[sel].max())), span, anchored,
                                    mean, float(np.sqrt(np.mean(rr[sel] ** 2))), int(sel.sum()),
                                    abs(mean) * np.sqrt(sel.sum()) / sigma))
    cells.sort(key=lambda c: -c.score)
    return cells[:top]
