"""`diagnose(data)`: baseline → residual structure → one refit per effect → scores → decision.

1. Baseline: `identify` in ``shared`` moduli mode (one set of moduli for every test), polished by
   the refit NLP of :mod:`.refit` so that baseline and candidates share one objective.
2. Residual structure of the baseline: noise floor per test, signatures, worst regions.
3. Every effect of the library: baseline + effect refit, warm-started from the baseline.
4. BIC for all, cross-validated RMSE for the baseline and the candidates that pass the BIC
   margin, intervals, the decision (:mod:`.selection`).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from pampipe.diagnose import selection, signatures
from pampipe.diagnose.refit import MPA, Fit, Refitter, rows_of
from pampipe.diagnose.result import Candidate, DiagnoseResult, TestRmse
from pampipe.errors import InputError, PampipeError
from pampipe.experiment import ExperimentData
from pampipe.model.effects import LIBRARY, get_effect
from pampipe.model.muscle import Muscle

DEGREE = 3
#: Generic start when neither identify nor the PAM gives moduli: E₁ = 1.5 MPa, E₂ = 4.4 MPa.
GENERIC_THETA = np.array([1.5, 0, 0, 0, 0, 0, 0, 0, 4.4, 0, 0, 0, 0, 0, 0, 0])


def _per_test(data: ExperimentData, rows, fit: Fit) -> tuple[np.ndarray, ...]:
    """Split a fit's residuals back into the tests' recorded rows."""
    out = []
    for index, _test in enumerate(data.tests):
        ra = fit.residual_axial[rows.axial_test == index]
        rr = fit.residual_radial[rows.radial_test == index]
        out.append(ra if ra.size else rr)
    return tuple(out)


def _initial_theta(data: ExperimentData, say) -> tuple[np.ndarray, str]:
    """θ₀ [MPa, b at 1 MPa] from `identify` (shared mode) if it runs, else the PAM's or a generic one."""
    try:
        from pampipe.identify import identify, parse_fit_options

        options = parse_fit_options(data.fit, source=data.source).with_overrides(mode="shared", degree=DEGREE)
        say("baseline: identify (shared moduli mode)")
        result = identify(data, options)
        return result.moduli.as_vector() / MPA * _b_scale(result.moduli.reference_pressure), "identify"
    except (ImportError, PampipeError) as exc:
        say(f"baseline: identify unavailable ({exc}); starting from the PAM's moduli")
    moduli = data.pam.moduli
    if moduli is not None and moduli.degree == DEGREE:
        return moduli.as_vector() / MPA * _b_scale(moduli.reference_pressure), "refit"
    return GENERIC_THETA.copy(), "refit"


def _b_scale(reference_pressure: float) -> np.ndarray:
    """Factors that turn b at P_ref into b at 1 MPa (E = a + b P/P_ref)."""
    k = DEGREE + 1
    scale = np.ones(4 * k)
    scale[k:2 * k] = scale[3 * k:] = MPA / reference_pressure
    return scale


def _candidate(name, fit: Fit, data, rows, refitter, n, base_bic, wall) -> Candidate:
    residuals = _per_test(data, rows, fit)
    tests = tuple(TestRmse(t.name, t.kind, t.points, float(np.sqrt(np.mean(r**2))))
                  for t, r in zip(data.tests, residuals, strict=True))
    b = selection.bic(fit, n)
    params = selection.intervals(fit, n) if fit.effect else {}
    return Candidate(name, refitter.moduli_si(fit.x), {k: v[0] for k, v in params.items()},
                     {k: (v[1], v[2]) for k, v in params.items()}, selection.sse(fit), b,
                     b - (b if base_bic is None else base_bic), tests, None, fit.iterations, wall, fit.status,
                     residuals)


def diagnose(data: ExperimentData, *, effects: list[str] | None = None, folds: int = selection.FOLDS,
             cross_validate_top: int = 3, progress: Callable[[str], None] | None = None) -> DiagnoseResult:
    """Name the effect missing from the baseline model of ``data`` (see the module docstring)."""
    say = progress or (lambda _text: None)
    started = time.perf_counter()
    names = list(LIBRARY) if effects is None else list(effects)
    for name in names:
        try:
            get_effect(name)
        except KeyError as exc:
            raise InputError(str(exc.args[0])) from None
    rows = rows_of(data)
    n = rows.n
    if n <= 4 * (DEGREE + 1) + 4:
        raise InputError(f"{data.source}: {n} data rows are too few to diagnose a "
                         f"{4 * (DEGREE + 1)}-parameter "
                         "model; record more points.")
    refitter = Refitter(data, rows, degree=DEGREE)
    theta0, source = _initial_theta(data, say)
    t0 = time.perf_counter()
    base_fit = refitter.fit(None, theta0, jacobian=True)
    baseline = _candidate("none", base_fit, data, rows, refitter, n, None, time.perf_counter() - t0)
    timings = {"baseline_wall_time_s": time.perf_counter() - started}

    noise = tuple(signatures.noise_floor(t, r) for t, r in zip(data.tests, baseline.residuals, strict=True))
    pooled = float(np.sqrt(sum(f.sigma**2 * t.points for f, t in zip(noise, data.tests, strict=True)) / n))
    fitted = Muscle(data.pam.geometry, refitter.moduli_si(base_fit.x), MPA)
    anchoring = tuple(float(fitted.anchoring_pressure(t.spec.pipe_diameter, t.spec.axial_load))
                      if t.kind == "radial" else None for t in data.tests)
    sigs = tuple(signatures.signatures(data, list(baseline.residuals), list(anchoring), pooled))
    regs = tuple(signatures.regions(data, list(baseline.residuals), list(anchoring), pooled))

    fits, candidates = {}, []
    for name in names:
        say(f"refit: baseline + {name}")
        t0 = time.perf_counter()
        fit = refitter.fit(name, base_fit.x, jacobian=True)
        fits[name] = fit
        candidates.append(_candidate(name, fit, data, rows, refitter, n, baseline.bic,
                                     time.perf_counter() - t0))
    candidates.sort(key=lambda c: c.bic)

    say(f"cross-validation over {folds} folds of pressure levels")
    t0 = time.perf_counter()
    base_cv = selection.cross_validate(refitter, base_fit, k=folds)
    baseline = _with(baseline, cv_rmse=base_cv, wall_time=baseline.wall_time + time.perf_counter() - t0)
    ranked = []
    for rank, c in enumerate(candidates):
        if rank < cross_validate_top and c.delta_bic <= -selection.BIC_MARGIN:
            t0 = time.perf_counter()
            cv = selection.cross_validate(refitter, fits[c.effect], k=folds)
            c = _with(c, cv_rmse=cv, wall_time=c.wall_time + time.perf_counter() - t0)
        ranked.append(c)
    ratio = max(t.rmse / f.sigma for t, f in zip(baseline.tests, noise, strict=True))
    chosen, reason, confounded = selection.decide(ratio, [
        {"effect": c.effect, "delta_bic": c.delta_bic,
         "cv_ratio": None if c.cv_rmse is None else c.cv_rmse / base_cv} for c in ranked])
    timings["total_wall_time_s"] = time.perf_counter() - started
    return DiagnoseResult(data.source, data.pam, baseline, tuple(ranked), chosen, reason, confounded, noise,
                          sigs,
                          regs, anchoring, source, timings, data)


def _with(candidate: Candidate, **changes) -> Candidate:
    from dataclasses import replace

    return replace(candidate, **changes)
