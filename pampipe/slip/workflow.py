"""Slip tests → :class:`SlipResult`: detect every trial, fit μ and κ, check the law and the residuals."""

from __future__ import annotations

import math

import numpy as np
from threadpoolctl import threadpool_limits

from pampipe.model.domain import check_pipe_diameter
from pampipe.slip.detect import Trial, detect
from pampipe.slip.fit import FRICTION_BOUNDS, KAPPA_BOUNDS, Estimate, Likelihood, maximise, profile_interval
from pampipe.slip.law import check_law
from pampipe.slip.result import Effective, SlipResult
from pampipe.slip.trend import trends
from pampipe.specs.experiment import SlipData

#: Detection confidence below which a trial is named in a warning.
LOW_CONFIDENCE = 0.9
#: κ range over which μ is bounded when κ is not determined (no load path .. through the anchor).
KAPPA_PHYSICAL = (0.0, 1.0)


def detect_trials(tests: tuple[SlipData, ...]) -> list[Trial]:
    """Every trial of every slip test, with its slip onset (:func:`pampipe.slip.detect.detect`)."""
    out = []
    for test in tests:
        for i, (first, end) in enumerate(test.trials):
            rows = slice(first, end)
            out.append(detect(test.name, i, test.spec.pipe_diameter, test.time[rows], test.pressure[rows],
                              test.axial_load[rows], test.displacement[rows], first_row=first))
    return out


def fit_slip(tests: tuple[SlipData, ...], muscle) -> SlipResult:
    """μ and κ from the slip tests by ``muscle``'s slip model (a :class:`pampipe.model.muscle.Muscle`).

    BLAS runs on one thread: the fits are hundreds of tiny L-BFGS-B solves, which threaded BLAS slows
    7-fold (measured: 3.0 s against 0.42 s of CPU for 32 trials). Each test's pipe must lie within the
    muscle's reach, as a radial test's (:func:`pampipe.model.domain.check_pipe_diameter`): InputError.
    """
    for test in tests:
        check_pipe_diameter(muscle.geometry, test.spec.pipe_diameter,
                            where=f"test {test.name}: pipe_diameter")
    with threadpool_limits(limits=1, user_api="blas"):
        return _fit_slip(tests, muscle)


def _fit_slip(tests: tuple[SlipData, ...], muscle) -> SlipResult:
    trials = detect_trials(tests)
    pressure = np.array([t.pressure for t in trials])
    diameter = np.array([t.pipe_diameter for t in trials])
    load = np.array([t.slip_load for t in trials])
    censored = np.array([t.censored for t in trials])
    warnings = _trial_warnings(tests, trials, muscle, pressure, diameter)

    def model_on(index):
        return slip_model(muscle, pressure[index], diameter[index])

    everything = np.arange(len(trials))
    bores = sorted(set(diameter.tolist()))
    two = len(bores) > 1
    needed = 5 if two else 4  # slipped trials: the free parameters (μ, κ, σ or μ, σ) plus two
    if int(np.sum(~censored)) < needed:
        return _too_few(trials, bores, muscle, warnings, needed, tests)
    candidates = {noise: Likelihood(load, censored, model_on(everything), noise)
                  for noise in ("relative", "absolute")}
    fits = {noise: maximise(like, kappa=None if two else 0.0) for noise, like in candidates.items()}
    noise = max(fits, key=lambda k: fits[k].loglik)
    like, best = candidates[noise], fits[noise]

    effective = []
    for bore in bores:
        index = np.flatnonzero(diameter == bore)
        # a bore with too few slips for its own scatter takes the joint fit's σ (no spuriously tight interval)
        few = int(np.sum(~censored[index])) < 4
        estimate = bore_estimate(load[index], censored[index], model_on(index), noise,
                                 {k: math.exp(f.log_sigma) for k, f in fits.items()} if few else None)
        amplification = float(muscle.amplification_factor(bore))
        effective.append(Effective(bore, amplification, estimate, int(index.size)))

    friction = load_coupling = friction_range = None
    if two:  # μ and κ: the chosen model's values, their intervals spanning both noise models' (bore_estimate)
        mu, kappa = (spanning(noise, {kind: profile_interval(candidates[kind], fits[kind], which, bounds)
                                      for kind in candidates})
                     for which, bounds in (("friction", FRICTION_BOUNDS), ("load_coupling", KAPPA_BOUNDS)))
        if mu.closed and kappa.closed:
            friction, load_coupling = mu, kappa
    if friction is None:
        bounded = maximise(like, kappa_bounds=KAPPA_PHYSICAL)
        span = profile_interval(like, bounded, "friction", FRICTION_BOUNDS, kappa_bounds=KAPPA_PHYSICAL)
        friction_range = (span.low if span.low is not None else FRICTION_BOUNDS[0], span.high)
    coulomb = best if two else maximise(like, kappa=0.0)
    law = check_law(muscle, pressure, diameter, load, censored, coulomb, noise)
    predicted = np.maximum(like.model(best.mu, best.kappa), 1e-6)
    residual = np.log(load / predicted) if noise == "relative" else load - predicted
    rates = np.array([t.load_rate for t in trials])
    found = trends(residual[~censored], pressure[~censored], rates[~censored])
    warnings += _law_warnings(law, found)
    materials = sorted({t.spec.pipe_material for t in tests if t.spec.pipe_material})
    if len(materials) > 1:
        warnings.append(f"the slip tests name several pipe materials ({', '.join(materials)}); one "
                        "friction is fitted to all of them: split them into separate experiments to compare")
    return SlipResult(tuple(trials), tuple(predicted.tolist()), tuple(residual.tolist()), noise,
                      math.exp(best.log_sigma), friction, load_coupling, friction_range, tuple(effective),
                      law, tuple(found), materials[0] if len(materials) == 1 else None, tuple(warnings))


def bore_estimate(load, censored, model, noise: str, sigmas: dict[str, float] | None) -> Estimate:
    """μ_eff of one bore (κ held at 0) under the chosen ``noise`` model, its 95 % interval spanning the
    intervals under both noise models (``sigmas``: σ held per model, or None: estimated).

    The joint fit picks relative or absolute scatter by likelihood, a choice that few trials make at random;
    the absolute model's interval assumes one scatter in newtons over loads that differ 2-3-fold in a bore,
    and over 40 generated data sets (4–12 trials per bore, relative truth) it held μ_eff in 11 of 18 bores
    where it was chosen (61 %), the relative model in 61 of 62. Spanning both keeps the chosen value and
    covers what either model allows; an end open under either model stays open."""
    ends = {}
    for kind in ("relative", "absolute"):
        like = Likelihood(load, censored, model, kind, None if sigmas is None else sigmas[kind])
        ends[kind] = profile_interval(like, maximise(like, kappa=0.0), "friction", FRICTION_BOUNDS,
                                      kappa_fixed=0.0)
    return spanning(noise, ends)


def spanning(noise: str, ends: dict[str, Estimate]) -> Estimate:
    """The ``noise`` model's value with an interval from the lowest to the highest end of ``ends`` (one
    :class:`Estimate` per noise model); an end open under any model stays open."""
    lows, highs = [e.low for e in ends.values()], [e.high for e in ends.values()]
    return Estimate(ends[noise].value, None if None in lows else min(lows),
                    None if None in highs else max(highs))


def _too_few(trials, bores, muscle, warnings, needed, tests) -> SlipResult:
    """The result when too few trials slipped to estimate the scatter: trials only, nothing claimed."""
    slipped = sum(not t.censored for t in trials)
    warnings = [*warnings, f"only {slipped} trial(s) slipped; at least {needed} are needed to estimate the "
                           "scatter of the slip loads, so no friction is claimed and -o writes no contact: "
                           "block; record more trials"]
    effective = tuple(Effective(b, float(muscle.amplification_factor(b)), Estimate(math.nan, None, None),
                                sum(t.pipe_diameter == b for t in trials)) for b in bores)
    materials = sorted({t.spec.pipe_material for t in tests if t.spec.pipe_material})
    nan = tuple(math.nan for _ in trials)
    return SlipResult(tuple(trials), nan, nan, "relative", math.nan, None, None, None, effective, None, (),
                      materials[0] if len(materials) == 1 else None, tuple(warnings))


def slip_model(muscle, pressure, diameter):
    """model(μ, κ) → slip loads [N]: :meth:`~pampipe.model.muscle.Muscle.largest_load` at safety factor 1,
    with the μ- and κ-free terms computed once when the muscle has the affine fast path."""
    if muscle.has_effects:
        def model(mu, kappa):
            return np.asarray(muscle.largest_load(pressure, diameter, kappa=kappa, friction=mu,
                                                  safety_factor=1.0), dtype=float)
        return model
    per_friction, axial = (np.asarray(v, dtype=float) for v in muscle.grip_terms(pressure, diameter))

    def model(mu, kappa):
        grip = mu * per_friction
        return grip * axial / (1.0 + kappa * grip)

    return model


def _trial_warnings(tests, trials, muscle, pressure, diameter) -> list[str]:
    out = []
    weak = [f"{t.test} trial {t.index + 1} ({t.confidence:.2f})" for t in trials
            if t.confidence < LOW_CONFIDENCE]
    if weak:
        out.append("slip onsets detected with low confidence: " + ", ".join(weak)
                   + "; look at the slip plot (--plots) before trusting them")
    anchoring = np.asarray(muscle.anchoring_pressure(diameter), dtype=float)
    below = [f"{t.test} trial {t.index + 1}" for t, p, a in zip(trials, pressure, anchoring, strict=True)
             if p <= a]
    if below:
        out.append("trials at or below the model's anchoring pressure (the model says the muscle does not "
                   "touch the wall there): " + ", ".join(below) + "; check the moduli or the pressure column")
    if all(t.censored for t in trials):
        out.append("no trial slipped: every slip load is a lower bound, so friction has no upper limit from "
                   "these data, and -o writes no contact: block; raise the load further")
    return out


def _law_warnings(law, found) -> list[str]:
    out = []
    if law is not None and law.supported == "pressure_dependent":
        out.append(f"the data support a contact-pressure-dependent friction (n = {law.exponent:.3g}, "
                   f"delta BIC {law.delta_bic:.3g}): the reported Coulomb friction is an average over the "
                   "tested contact pressures, and plans far from them are less certain")
    for t in found:
        if t.significant:
            out.append(f"the slip residuals trend with {t.against.rsplit('_', 1)[0].replace('_', ' ')} "
                       f"(p = {t.p_value:.2g}): something beyond Coulomb friction acts; see "
                       "`pampipe diagnose`")
    return out
