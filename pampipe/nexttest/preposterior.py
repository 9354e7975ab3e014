"""The preposterior check of the top-ranked tests (docs/commands.md §14.4): what the test would really buy.

For each of the top tests and each of ``truths`` draws (seeded per draw, the same for every test):

1. a truth θ_k ~ N(θ̂, Σ₀) over the PAM's ``uncertainty:`` names (Σ₀ of :mod:`.posterior`: the covariance,
   and the open width along each undetermined direction);
2. the test's data synthesised from the truth with the protocol's noise (:mod:`pampipe.simulation.synthetic`:
   2 N on every force row; an isometric test is an axial test at one held length, reading 0 N where the
   muscle is slack there: the held length below its free length at P);
3. a refit by ``identify`` of those data, the PAM's moduli and covariance as its Gaussian prior
   (``fit.prior``: what `next-test -o` writes);
4. the mission planned again at C with the refit muscle (:class:`.ranking.Planner`), on the prior along the
   directions the refit leaves open, and whether plan would still stop (exit 3).

The check's pressure is the mean of J over the truths and its spread their standard deviation. Each
(test, truth) is a task of :func:`pampipe.runtime.executors.run_all` (plain numbers and the seed): serial,
local processes and a Dask cluster give the same numbers. A slip test is synthesised and refitted by
:mod:`.slip_check` (identify fits μ and κ to slip tests, not the moduli), after the candidate's other tests.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from pampipe.errors import SolverError
from pampipe.identification import identify
from pampipe.identification.options import parse_fit_options
from pampipe.nexttest.posterior import extended, prior_covariance, shifted
from pampipe.nexttest.slip_check import grip, refit_slip, trials
from pampipe.runtime.executors import executor, run_all
from pampipe.simulation.synthetic import Protocol, generate
from pampipe.specs.experiment import ExperimentData, TestSpec, make_test_data

#: Truths per checked test.
DEFAULT_TRUTHS = 8
CHECKED_KINDS = ("radial", "axial", "isometric", "slip")


def truth(pam, u, seed: int, k: int):
    """Truth k: the PAM with its moduli (and geometry) drawn from N(θ̂, Σ₀) over the names of ``u`` (its
    uncertainty, :func:`.posterior.extended`) (module docstring)."""
    rng = np.random.default_rng([seed, k])
    cov = prior_covariance(u)
    values, vectors = np.linalg.eigh(cov)
    return shifted(pam, u, vectors @ (np.sqrt(np.clip(values, 0.0, None)) * rng.standard_normal(values.size)))


def synthesise(truth_pam, test, seed: int) -> list:
    """The test's data from ``truth_pam`` with the protocol's noise (:func:`generate`), as TestData."""
    levels = tuple(float(p) for p in test.pressures)
    if test.kind == "radial":
        protocol = Protocol(pipes=(test.pipe_diameter,), loads=(test.axial_load,), radial_pressures=levels)
        made = generate(truth_pam, protocol, seed=seed)[1:]  # the radial test, not the axial one
    elif test.kind == "axial":
        made = generate(truth_pam, Protocol(pressures=levels, pipes=()), seed=seed)
    else:  # isometric: the held length, the pressure at each level, Protocol.radial_points rows
        from pampipe.model.muscle import Muscle

        protocol = Protocol()
        rng = np.random.default_rng(seed)
        pressure = np.repeat(np.asarray(levels), protocol.radial_points)
        model = np.asarray(Muscle.from_pam(truth_pam).axial_force(pressure, test.length), dtype=float)
        force = np.maximum(model, 0.0)  # a slack muscle (held below its free length) reads 0 N
        columns = {"time": np.arange(pressure.size) * protocol.sample_time, "pressure": pressure,
                   "length": np.full(pressure.size, test.length),
                   "force": force + protocol.force_noise * rng.standard_normal(pressure.size)}
        made = [(TestSpec("isometric", "axial", Path("data/isometric.csv"), None, 0.0, protocol="isometric"),
                 columns)]
    return [make_test_data(spec, columns) for spec, columns in made]


#: [Pa] The prior sd of a coefficient the PAM states without variance and without an undetermined direction:
#: the plan takes it as known, so the refit does too (a prior of no variance would carry no information).
KNOWN = 1e3


def refit(pam, u, tests):
    """identify of ``tests`` from the PAM's moduli, with what the plan knows of them as the Gaussian prior:
    the moduli block of Σ₀ (:func:`.posterior.prior_covariance`, in Pa²), :data:`KNOWN` on a coefficient of
    no variance there; the braid angle calibrated where a radial test and its stated sd allow; returns the
    refitted PAM."""
    units = u.scaled_units()
    n = u.moduli_count
    cov = (prior_covariance(u) * np.outer(units, units))[:n, :n]
    cov[np.diag_indices(n)] = np.where(np.diag(cov) > 0, np.diag(cov), KNOWN**2)
    prior = {"mean": pam.moduli.as_vector().tolist(), "covariance": cov.tolist()}
    options = parse_fit_options({"degree": pam.moduli.degree, "prior": prior}, source="next-test check")
    if "braid_angle" in u.names and any(t.kind == "radial" for t in tests):
        options = options.calibrating("braid_angle")
    data = ExperimentData(Path("next-test-check.yaml"), pam, tuple(tests), {})
    result = identify(data, options)
    return dataclasses.replace(result.fitted_pam(pam), geometry_sd=dict(pam.geometry_sd or {}))


def check_task(task) -> tuple[float, bool]:
    """(J [Pa] after the refit, plan still stops) of one candidate (a test, or a pair) and truth k (module
    docstring; a picklable task). Slip tests refit last, with what the other tests left as their prior
    (:mod:`.slip_check`)."""
    planner, tests, seed, k = task
    pam, u = planner.pam, planner.uncertainty
    drawn = truth(pam, u, seed, k)
    seeds = [(seed * 1000 + k) * 10 + j for j in range(len(tests))]
    try:  # a truth whose moduli never balance the pressure (no free length), or a refit IPOPT cannot finish
        data = [d for s, t in zip(seeds, tests, strict=True) if t.kind != "slip"
                for d in synthesise(drawn, t, s)]
        if data:
            pam = refit(pam, u, data)
            u = extended(pam, planner.tested)
        for s, t in zip(seeds, tests, strict=True):
            if t.kind == "slip":
                friction, kappa = grip(pam)
                pressure, load = trials(drawn, t, s, friction, kappa)
                pam = refit_slip(pam, u, t.pipe_diameter, pressure, load, friction, kappa)
                u = extended(pam, planner.tested)
    except SolverError:
        return math.nan, True
    return planner.refitted(pam)


def checked(tests) -> bool:
    """Every test of a candidate is of a kind the check synthesises."""
    return all(t.kind in CHECKED_KINDS for t in tests)


def check(planner, candidates, *, truths: int = DEFAULT_TRUTHS, seed: int = 0, workers=None,
          scheduler=None) -> list[dict | None]:
    """The check document of each candidate (a tuple of tests; None: a kind not checked): ``pressure_Pa``
    (mean of J over the truths), ``pressure_sd_Pa``, ``exit_3_share``, ``truths`` and ``failed`` refits."""
    tasks = [(planner, c, seed, k) for c in candidates if checked(c) for k in range(truths)]
    with executor(workers=workers, scheduler=scheduler) as pool:
        results = run_all(check_task, tasks, pool, what="preposterior refits")
    out, start = [], 0
    for c in candidates:
        if not checked(c):
            out.append(None)
            continue
        part = results[start:start + truths]
        start += truths
        values = np.array([v for v, _ in part])
        finite = values[np.isfinite(values)]
        out.append({"pressure_Pa": float(finite.mean()) if finite.size else None,
                    "pressure_sd_Pa": float(finite.std(ddof=1)) if finite.size > 1 else None,
                    "exit_3_share": float(np.mean([s for _, s in part])), "truths": truths,
                    "failed": int(np.sum(~np.isfinite(values)))})
    return out
