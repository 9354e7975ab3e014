"""The noise floor σ of each test [N], with its degrees of freedom, from the baseline's cell residuals.

Two estimates, both unbiased for white noise and both only *inflated* by structured error:

* ``repeats`` (pure error): the scatter of rows within an exact cell (rows sharing one set point;
  binned cells do not count, see below) plus the scatter of exact cells that repeat one set point
  in other cycles,
  σ²_rep = (Σ SS_within + Σ_g Σ_c n_c (r̄_c − r̄_g)²) / (Σ dof_within + Σ_g (cells_g − 1));
* ``neighbours`` (a high-pass estimate): along each path (cells of a test, held group, direction
  and cycle, sorted by the swept coordinate), e_i = r̄_i − w₋r̄_{i−1} − w₊r̄_{i+1} with linear
  interpolation weights; Var e_i = σ²(1/n_i + w₋²/n_{i−1} + w₊²/n_{i+1}), so a residual linear along
  the path cancels. Terms beyond 5 robust (MAD) standard deviations are dropped (kinks such as the
  anchoring point). The terms overlap (correlations −2/3 and 1/6 between neighbours), so the
  estimate has ν ≈ m/1.944 degrees of freedom for m terms.

Choice: with both estimates at ≥ :data:`MIN_DOF` degrees of freedom they are compared by a two-sided
F test at level :data:`FLOOR_ALPHA`; consistent → ``repeats``; inconsistent → the smaller one (the
larger is inflated by structure, and the report says which kind: between repeats = cycle to cycle
or in time; between neighbours = along the path). With one estimate available, that one. With
neither (too few rows), the fallback is the dof-weighted pool of the other tests of the same kind,
then of all tests, said in ``note``; if no test has a floor, σ is taken as the test's own RMSE
(``method = "assumed"``, ν = 0: that test cannot be tested against the noise).

Slack cells (readings of exactly 0 N) carry no noise and are left out of both estimates. Binned
cells (a ramp's distinct set points, :mod:`.cells`) are not repeats: the scatter about their
within-bin line does not enter the repeats estimate (the line is fitted to the same rows, so it
would read low), and such a test's floor comes from its neighbours.

A floor cannot be lower than the noise, but it can be *higher* when the test itself is noisier than
the others: :func:`noisier_than_twins` names every test whose own floor is :data:`NOISY` times the
pooled floor of its twins (the other tests of its kind), significant by an F test at FLOOR_ALPHA
(Bonferroni over the tests). The
uncertainty is stated as a 95 % interval from σ̂²ν/σ² ~ χ²_ν.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Least degrees of freedom for an estimate to be used on its own.
MIN_DOF = 8.0
#: Two-sided level of the consistency test between the two estimates.
FLOOR_ALPHA = 0.01
#: Variance inflation of the mean of overlapping second differences (1 + 2Σρ_k², ρ = −2/3, 1/6).
OVERLAP = 1.944
#: Terms beyond this many robust standard deviations are dropped from the neighbour estimate.
TRIM = 5.0
#: A test whose own floor is this many times its twins' (same kind, pooled) is "noisier than its twins".
NOISY = 3.0


@dataclass(frozen=True)
class NoiseFloor:
    """σ [N] of one test and how it was found."""

    test: str
    sigma: float  # [N]
    dof: float  # degrees of freedom of σ (0: assumed, untestable)
    method: str  # "repeats", "neighbours", "pooled" or "assumed"
    repeats: float | None  # σ from repeats [N] (None: no repeats)
    repeats_dof: float
    neighbours: float | None  # σ from neighbours [N]
    neighbours_dof: float
    note: str = ""

    @property
    def interval(self) -> tuple[float, float] | None:
        """95 % interval of σ [N] from χ²_ν (None without degrees of freedom)."""
        if self.dof <= 0:
            return None
        from scipy.special import chdtri  # inverse survival function of χ²

        return (self.sigma * float(np.sqrt(self.dof / chdtri(self.dof, 0.025))),
                self.sigma * float(np.sqrt(self.dof / chdtri(self.dof, 0.975))))

    def as_document(self) -> dict:
        interval = self.interval
        return {"noise_floor_N": self.sigma, "noise_floor_dof": self.dof, "noise_floor_method": self.method,
                "noise_floor_interval_95_N": None if interval is None else list(interval),
                "noise_floor_repeats_N": self.repeats, "noise_floor_neighbours_N": self.neighbours,
                "noise_floor_note": self.note}


def repeats_estimate(cells, index: np.ndarray, residual: np.ndarray) -> tuple[float, float]:
    """(SS, dof) of pure error over the cells ``index`` of one test."""
    index = index[cells.spread[index] == 0]  # repeats of one set point: exact cells only
    ss = float(cells.within_ss[index].sum())
    dof = float(cells.within_dof[index].sum())
    groups = cells.repeat[index]
    n, r = cells.count[index], residual[index]
    _, inverse, sizes = np.unique(groups, return_inverse=True, return_counts=True)
    total = np.bincount(inverse, weights=n)
    mean = np.bincount(inverse, weights=n * r) / total
    ss += float(np.sum(n * (r - mean[inverse]) ** 2))
    dof += float(np.sum(sizes - 1))
    return ss, dof


def neighbours_estimate(cells, index: np.ndarray, residual: np.ndarray) -> tuple[float, float]:
    """(σ², dof) from second differences along the paths of one test (σ² NaN if no terms)."""
    seq, x, n, r = cells.sequence[index], cells.sweep[index], cells.count[index], residual[index]
    order = np.lexsort((x, seq))
    seq, x, n, r = seq[order], x[order], n[order], r[order]
    same = (seq[2:] == seq[1:-1]) & (seq[1:-1] == seq[:-2])
    span = x[2:] - x[:-2]
    safe = np.where(span > 0, span, 1.0)
    w_next = np.where(span > 0, (x[1:-1] - x[:-2]) / safe, 0.5)
    w_prev = 1 - w_next
    e = r[1:-1] - w_prev * r[:-2] - w_next * r[2:]
    v = 1 / n[1:-1] + w_prev**2 / n[:-2] + w_next**2 / n[2:]
    q = (e**2 / v)[same]
    if q.size == 0:
        return float("nan"), 0.0
    robust = (1.4826 * np.median(np.sqrt(q))) ** 2
    kept = q[q <= TRIM**2 * robust] if robust > 0 else q
    return float(np.mean(kept)), float(kept.size / OVERLAP)


def noise_floors(data, cells, residual: np.ndarray) -> tuple[NoiseFloor, ...]:
    """The floor of every test of ``data`` from the baseline residual per cell (see the module)."""
    from scipy.special import fdtri  # inverse CDF of the F distribution

    found = []
    for i, test in enumerate(data.tests):
        index = cells.of_test(i)
        index = index[~cells.slack[index]]  # exact zeros of a slack muscle carry no noise
        ss_rep, dof_rep = repeats_estimate(cells, index, residual)
        var_hp, dof_hp = neighbours_estimate(cells, index, residual)
        rep = float(np.sqrt(ss_rep / dof_rep)) if dof_rep > 0 else None
        hp = float(np.sqrt(var_hp)) if dof_hp > 0 and np.isfinite(var_hp) else None
        ok_rep, ok_hp = rep is not None and dof_rep >= MIN_DOF, hp is not None and dof_hp >= MIN_DOF
        note = ""
        if ok_rep and ok_hp and rep > 0 and hp > 0:
            ratio = rep**2 / hp**2
            high = fdtri(dof_rep, dof_hp, 1 - FLOOR_ALPHA / 2)
            low = fdtri(dof_rep, dof_hp, FLOOR_ALPHA / 2)
            if ratio > high:
                sigma, dof, method = hp, dof_hp, "neighbours"
                note = (f"repeats scatter {np.sqrt(ratio):.2f}x more than neighbouring points: structure "
                        "from cycle to cycle or in time")
            elif ratio < low:
                sigma, dof, method = rep, dof_rep, "repeats"
                note = (f"neighbouring points scatter {1 / np.sqrt(ratio):.2f}x more than repeats: "
                        "structure along the path")
            else:
                sigma, dof, method = rep, dof_rep, "repeats"
        elif ok_rep and rep > 0:
            sigma, dof, method = rep, dof_rep, "repeats"
        elif ok_hp and hp > 0:
            sigma, dof, method = hp, dof_hp, "neighbours"
        else:
            sigma, dof, method = float("nan"), 0.0, "pooled"
        found.append(NoiseFloor(test.name, sigma, dof, method, rep, dof_rep, hp, dof_hp, note))
    return tuple(_fallbacks(data, cells, residual, found))


def _fallbacks(data, cells, residual, found: list[NoiseFloor]) -> list[NoiseFloor]:
    """Fill the tests without a floor from the other tests (same kind first), else assume."""
    out = []
    for i, (test, floor) in enumerate(zip(data.tests, found, strict=True)):
        if floor.method != "pooled":
            out.append(floor)
            continue
        pool, where = None, ""
        for label, kinds in (("tests of the same kind", {test.kind}), ("all tests", {"axial", "radial"})):
            donors = [f for t, f in zip(data.tests, found, strict=True)
                      if f.method != "pooled" and t.kind in kinds]
            if donors:
                dof = sum(f.dof for f in donors)
                pool = (float(np.sqrt(sum(f.sigma**2 * f.dof for f in donors) / dof)), dof)
                where = label
                break
        reason = (f"too few rows to estimate its own floor ({floor.repeats_dof:.0f} dof from repeats, "
                  f"{floor.neighbours_dof:.0f} from neighbours; {MIN_DOF:g} needed)")
        if pool is not None:
            out.append(NoiseFloor(test.name, pool[0], pool[1], "pooled", floor.repeats, floor.repeats_dof,
                                  floor.neighbours, floor.neighbours_dof,
                                  f"{reason}: pooled over {where}"))
        else:
            index = cells.of_test(i)
            n = cells.count[index]
            rmse = float(np.sqrt((np.sum(n * residual[index] ** 2) + cells.within_ss[index].sum())
                                 / max(n.sum(), 1)))
            out.append(NoiseFloor(test.name, max(rmse, 1e-12), 0.0, "assumed", floor.repeats,
                                  floor.repeats_dof, floor.neighbours, floor.neighbours_dof,
                                  f"{reason}, and no other test has one: σ assumed = its RMSE, untested"))
    return out


def noisier_than_twins(data, floors) -> list[tuple[str, float, float, float]]:
    """[(test, σ/σ_twins, σ, σ_twins)] of the tests noisier than their twins (see the module)."""
    from scipy.special import fdtrc  # survival function of the F distribution

    own = [f if f.method in ("repeats", "neighbours") and f.dof >= MIN_DOF else None for f in floors]
    out = []
    for test, floor in zip(data.tests, own, strict=True):
        twins = [f for t, f in zip(data.tests, own, strict=True) if f is not None and f is not floor
                 and t.kind == test.kind]
        if floor is None or not twins:
            continue
        dof = sum(f.dof for f in twins)
        pooled = float(np.sqrt(sum(f.sigma**2 * f.dof for f in twins) / dof))
        if pooled <= 0 or floor.sigma < NOISY * pooled:
            continue
        if fdtrc(floor.dof, dof, (floor.sigma / pooled) ** 2) < FLOOR_ALPHA / len(floors):
            out.append((floor.test, floor.sigma / pooled, floor.sigma, pooled))
    return out
