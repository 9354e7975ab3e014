"""Is a fit at the noise, test by test? Lack of fit, serial correlation and residual structure.

For one fit (cell residuals r̄, Jacobian J of √n·r̄ with respect to every fitted parameter) and the
noise floors σ_t of :mod:`.noise`, every test t gets these tests, each at level α/m (Bonferroni over
the m tests made in one assessment, :data:`ALPHA` = 1 %):

* **lack of fit**: SS_t = Σ_c n_c r̄_c² against (ν₁ = cells − Σ leverage) σ_t²: F = SS_t/(ν₁σ_t²) ~
  F(ν₁, ν_σ);
* **serial correlation**: lag-1 autocorrelation ρ of z = √n r̄/σ in time order, one-sided
  ρ√m ~ N(0, 1) (runs of one sign);
* **families of terms**, each fitted *jointly with a linearised refit of every parameter*: the sum
  of squares they remove from √n·r̄ beyond what J removes, ΔSS ~ σ_t² χ²_k, F = ΔSS/(kσ_t²) ~
  F(k, ν_σ). Two kinds:

  - *probes*, cheap generic terms that say only that something is there and where it lives, never
    named as physics: ``pressure`` (a cubic in P per test: 1, P, P², P³ as Legendre polynomials),
    ``first_cycle`` (first-cycle indicator × [1, s, P, sP]), ``time_drift`` (1, t and t² per test),
    ``rate`` (the sweep rate dL/dt or dP/dt per test, where most readings are taken while moving);
  - *signatures* that point at library effects: ``length`` (a cubic in the stroke position s),
    ``length_rate`` / ``pressure_rate`` (the direction d and d·P: hysteresis), ``contact`` (step
    and hinge at the fitted anchoring pressure, radial tests).

A test is *at the noise* when none of its tests rejects and its RMSE is at most :data:`FAR_ABOVE` times its
floor (a residual that large is never noise, whatever the tests' power). Its *excess* is
max(SS_t − ν₁σ_t², 0) [N²].
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Family-wise level of one assessment (Bonferroni over every test made in it).
ALPHA = 0.01
#: A test whose RMSE exceeds this many times its noise floor is off the noise whatever the tests say.
FAR_ABOVE = 3.0
PROBES = ("pressure", "first_cycle", "time_drift", "rate")
SIGNATURES = ("length", "length_rate", "pressure_rate", "contact")
#: Cells with |z| above this are "where the residual is" (z = √n·r̄/σ).
Z_REGION = 3.0


@dataclass(frozen=True)
class Family:
    name: str
    probe: bool
    delta_ss: float  # [N²] removed jointly with the linearised refit
    dof: int
    p_value: float


@dataclass(frozen=True)
class Where:
    """Where a test's structured residual lives."""

    test: str
    signature: str  # the family (or "lack_of_fit"/"serial") that rejects most strongly
    p_value: float
    pressure: tuple[float, float]  # [Pa]
    length: tuple[float, float] | None  # [m] (axial tests)
    cells: int
    rows: int
    mean_residual: float  # [N], model − data, over those cells

    def as_document(self) -> dict:
        return {"test": self.test, "signature": self.signature, "p_value": self.p_value,
                "pressure_Pa": list(self.pressure),
                "length_m": None if self.length is None else list(self.length),
                "cells": self.cells, "rows": self.rows, "mean_residual_N": self.mean_residual}


@dataclass(frozen=True)
class TestCheck:
    """The checks of one test for one fit."""

    test: str
    ss: float  # Σ n r̄² [N²]
    rmse: float  # √((SS + SS_within)/(rows − within-cell line coefficients)) [N]
    sigma: float
    lack_dof: float
    lack_ratio: float  # SS/(ν₁σ²)
    lack_p: float
    serial: float  # lag-1 autocorrelation of z
    serial_p: float
    serial_within_p: float  # readings within repeats (model-free)
    families: tuple[Family, ...]
    at_noise: bool
    excess: float  # [N²]
    where: Where | None

    def p_values(self) -> dict[str, float]:
        return {"lack_of_fit": self.lack_p, "serial": self.serial_p,
                "serial_within_repeats": self.serial_within_p,
                **{f.name: f.p_value for f in self.families}}

    def as_document(self) -> dict:
        return {"test": self.test, "rmse_N": self.rmse, "at_noise": self.at_noise,
                "lack_of_fit_ratio": self.lack_ratio,
                "lack_of_fit_p": self.lack_p, "serial_correlation": self.serial, "serial_p": self.serial_p,
                "serial_within_repeats_p": self.serial_within_p,
                "families": [{"name": f.name, "probe": f.probe, "delta_ss_N2": f.delta_ss, "dof": f.dof,
                              "p_value": f.p_value} for f in self.families]}


@dataclass(frozen=True)
class Assessment:
    """Checks of every test of one fit, and what all probes together would remove."""

    tests: tuple[TestCheck, ...]
    alpha_each: float
    probe_ss: tuple[float, ...]  # per test: SS left after all probes + linearised refit [N²]
    #: {probe family or "all probes": (SS removed jointly with a linearised refit [N²], terms)}
    probe_families: dict = field(default_factory=dict)

    @property
    def misfit(self) -> tuple[int, ...]:
        return tuple(i for i, t in enumerate(self.tests) if not t.at_noise)

    @property
    def at_noise(self) -> bool:
        return not self.misfit

    def ss(self, tests) -> float:
        return float(sum(self.tests[i].ss for i in tests))

    def excess(self, tests) -> float:
        return float(sum(self.tests[i].excess for i in tests))


def _legendre(x: np.ndarray, degree: int) -> list[np.ndarray]:
    out = [x, (3 * x**2 - 1) / 2, (5 * x**3 - 3 * x) / 2]
    return out[:degree]


def _scaled(values: np.ndarray) -> np.ndarray:
    span = float(np.ptp(values)) if values.size else 0.0
    return 2 * (values - values.min()) / span - 1 if span > 0 else np.zeros(values.size)


def families_of(cells, index: np.ndarray, anchoring: float | None, swept: str, moving: float) -> dict:
    """{family: feature matrix (cells of the test × k)} that apply to one test."""
    p = _scaled(cells.pressure[index])
    s = 2 * cells.sweep[index] - 1
    ones = np.ones(index.size)
    out = {"pressure": np.column_stack([ones, *_legendre(p, 3)])}
    if swept == "length":
        out["length"] = np.column_stack(_legendre(s, 3))
    d = cells.direction[index].astype(float)
    if np.any(d > 0) and np.any(d < 0):
        out["length_rate" if swept == "length" else "pressure_rate"] = np.column_stack([d, d * p])
    first = cells.first[index].astype(float)
    if 0 < first.sum() < index.size:
        out["first_cycle"] = np.column_stack([first, first * s, first * p, first * s * p])
    t = cells.time[index]
    if np.ptp(t) > 0:
        tt = _scaled(t)
        out["time_drift"] = np.column_stack([ones, tt, (3 * tt**2 - 1) / 2])
    rate = cells.rate[index]
    if moving >= 0.5 and np.ptp(rate) > 0:  # a rate term needs readings taken while moving
        out["rate"] = (rate / np.max(np.abs(rate)))[:, None]
    if anchoring is not None and not cells.axial[index[0]]:
        after = (cells.pressure[index] > anchoring).astype(float)
        if 0 < after.sum() < index.size:
            hinge = np.maximum(cells.pressure[index] - anchoring, 0.0)
            out["contact"] = np.column_stack([after, hinge / max(hinge.max(), 1.0)])
    return out


def _basis(matrix: np.ndarray, tol: float = 1e-10) -> np.ndarray:
    """Orthonormal basis of the column space (SVD, relative rank tolerance)."""
    if matrix.size == 0 or matrix.shape[1] == 0:
        return np.zeros((matrix.shape[0], 0))
    u, sv, _ = np.linalg.svd(matrix, full_matrices=False)
    if sv.size == 0 or sv[0] == 0:
        return np.zeros((matrix.shape[0], 0))
    return u[:, sv > tol * sv[0]]


def assess(data, cells, fit, floors, anchoring, *, alpha: float = ALPHA) -> Assessment:
    """Check every test of ``data`` for ``fit`` (see the module docstring)."""
    from scipy.special import fdtrc  # survival function of the F distribution

    sqrt_n = np.sqrt(cells.count)
    y = sqrt_n * fit.residual
    basis = _basis(fit.jacobian)
    y_perp = y - basis @ (basis.T @ y)
    leverage = np.sum(basis**2, axis=1)

    pending, probe_columns = [], {}
    for i, (test, floor) in enumerate(zip(data.tests, floors, strict=True)):
        index = cells.of_test(i)
        fams = families_of(cells, index, anchoring[i], cells.swept[i], cells.moving[i])
        gains = {}
        for name, features in fams.items():
            full = np.zeros((cells.size, features.shape[1]))
            full[index] = sqrt_n[index, None] * features
            perp = full - basis @ (basis.T @ full)
            q = _basis(perp)
            gains[name] = (float(np.sum((q.T @ y_perp) ** 2)), q.shape[1])
            if name in PROBES:
                probe_columns.setdefault(name, []).append(perp)
        pending.append((i, test, floor, index, gains))

    n_tests = sum(3 + len(g) for *_, g in pending)
    alpha_each = alpha / max(n_tests, 1)
    removed = {}
    for name, columns in probe_columns.items():
        q = _basis(np.hstack(columns))
        removed[name] = (float(np.sum((q.T @ y_perp) ** 2)), q.shape[1])
    every = [c for columns in probe_columns.values() for c in columns]
    q_all = _basis(np.hstack(every)) if every else np.zeros((cells.size, 0))
    after_probes = y_perp - q_all @ (q_all.T @ y_perp)
    removed["all probes"] = (float(np.sum((q_all.T @ y_perp) ** 2)), q_all.shape[1])

    checks, probe_ss = [], []
    for i, test, floor, index, gains in pending:
        sigma2, nu = floor.sigma**2, floor.dof
        ss = float(np.sum(y[index] ** 2))
        rows = float(cells.count[index].sum())
        effective = rows - float(cells.within_fitted[index].sum())  # the within-cell lines' dof
        rmse = float(np.sqrt((ss + cells.within_ss[index].sum()) / max(effective, 1)))
        lack_dof = float(max(index.size - leverage[index].sum(), 0.0))
        testable = nu > 0 and sigma2 > 0
        lack_ratio = ss / (lack_dof * sigma2) if lack_dof > 0.5 and sigma2 > 0 else float("nan")
        lack_p = float(fdtrc(lack_dof, nu, lack_ratio)) if testable and np.isfinite(lack_ratio) else 1.0
        serial, serial_p = _serial(cells, index, y, sigma2) if testable else (0.0, 1.0)
        within_p = _serial_within(cells.serial_within[i])
        families = tuple(Family(name, name in PROBES, gain, k,
                                float(fdtrc(k, nu, gain / (k * sigma2))) if testable and k else 1.0)
                         for name, (gain, k) in gains.items())
        p_values = [lack_p, serial_p, within_p, *(f.p_value for f in families)]
        far = floor.sigma > 0 and rmse > FAR_ABOVE * floor.sigma  # never "at the noise" at 3x its floor
        at_noise = min(p_values) >= alpha_each and not far
        excess = max(ss - lack_dof * sigma2, 0.0)
        where = None if at_noise else _where(test, cells, index, fit.residual, sigma2,
                                             [("lack_of_fit", lack_p), ("serial", serial_p),
                                              ("serial_within_repeats", within_p)], families)
        checks.append(TestCheck(test.name, ss, rmse, floor.sigma, lack_dof, float(lack_ratio) if np.isfinite(
            lack_ratio) else 0.0, lack_p, serial, serial_p, within_p, families, at_noise, excess, where))
        probe_ss.append(float(np.sum(after_probes[index] ** 2)))
    return Assessment(tuple(checks), alpha_each, tuple(probe_ss), removed)


def _serial(cells, index, y, sigma2) -> tuple[float, float]:
    """(lag-1 autocorrelation of z in time order, one-sided p) of one test (p = 1 below 8 cells)."""
    from scipy.special import ndtr

    if index.size < 8:
        return 0.0, 1.0
    z = y[index][np.argsort(cells.time[index], kind="stable")] / np.sqrt(sigma2)
    denominator = float(np.sum(z**2))
    if denominator <= 0:
        return 0.0, 1.0
    rho = float(np.sum(z[:-1] * z[1:]) / denominator)
    return rho, float(ndtr(-rho * np.sqrt(index.size)))


def _serial_within(stat: tuple[float, float, int]) -> float:
    """One-sided p of the within-repeat autocorrelation, (ρ − ρ₀)√pairs ~ N(0, 1) (1 below 8 pairs)."""
    from scipy.special import ndtr

    rho, rho0, pairs = stat
    return float(ndtr(-(rho - rho0) * np.sqrt(pairs))) if pairs >= 8 else 1.0


def _where(test, cells, index, residual, sigma2, checks, families) -> Where:
    """The strongest rejection of a misfit test and the cells with |z| > Z_REGION (else the top 10 %)."""
    candidates = [*checks, *((f.name, f.p_value) for f in families)]
    name, p = min(candidates, key=lambda c: c[1])
    z = np.sqrt(cells.count[index]) * residual[index] / np.sqrt(sigma2)
    chosen = np.abs(z) > Z_REGION
    if not np.any(chosen):
        chosen = np.abs(z) >= np.quantile(np.abs(z), 0.9)
    picked = index[chosen]
    pressure = (float(cells.pressure[picked].min()), float(cells.pressure[picked].max()))
    length = None
    if cells.axial[index[0]]:
        length = (float(cells.length[picked].min()), float(cells.length[picked].max()))
    n = cells.count[picked]
    return Where(test.name, name, p, pressure, length, int(picked.size), int(n.sum()),
                 float(np.sum(n * residual[picked]) / n.sum()))
