"""`diagnose(data)`: cells → baseline → noise floors → checks → forward/backward selection → verdict.

1. Rows are reduced to cells (:mod:`.cells`), so every refit below has a size bounded whatever the
   row count.
2. Baseline: `identify` in ``shared`` moduli mode (one set of moduli for every test), polished by
   the refit NLP of :mod:`.refit` so that baseline and candidates share one objective.
3. Noise floor per test from the baseline residual (:mod:`.noise`); checks of every test
   (:mod:`.structure`).
4. Forward selection of effects from the library, joint refits, then a backward step
   (:mod:`.search`).
5. The verdict (:mod:`.verdict`); intervals of the selected set; for confounded alternatives, the
   experiment that would separate them (:mod:`.separate`); row residuals for the plots.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from pampipe.diagnosis import noise, selection, structure
from pampipe.diagnosis.candidates import DEFAULT, candidate
from pampipe.diagnosis.refit import MPA, SMOOTHING, Fit, Refitter, canonical, effect_parameters
from pampipe.diagnosis.refit_cells import reduce_rows, slack_rows
from pampipe.diagnosis.result import DiagnoseResult, summarize
from pampipe.diagnosis.search import Model, Search
from pampipe.diagnosis.separate import separating_experiment
from pampipe.diagnosis.slip_residuals import diagnose_slip
from pampipe.diagnosis.verdict import Scores, decide, qualify, tie_groups, undetermined_effects
from pampipe.errors import InputError, PampipeError
from pampipe.model.forces import contact_switch
from pampipe.specs.experiment import ExperimentData

DEGREE = 3
#: Generic start when neither identify nor the PAM gives moduli: E₁ = 1.5 MPa, E₂ = 4.4 MPa.
GENERIC_THETA = np.array([1.5, 0, 0, 0, 0, 0, 0, 0, 4.4, 0, 0, 0, 0, 0, 0, 0])


def _initial_theta(data: ExperimentData, say) -> tuple[np.ndarray, str]:
    """θ₀ [MPa, b at 1 MPa] from `identify` (shared mode) if it runs, else the PAM's or a generic one."""
    try:
        from pampipe.identification.fit import identify
        from pampipe.identification.options import parse_fit_options

        options = parse_fit_options(data.fit, source=data.source)
        if options.calibrate:  # the refits and -o use the stated geometry, so the baseline does too
            say(f"fit.calibrate ({', '.join(options.calibrate)}) is not used: diagnose works at the stated "
                "geometry; to diagnose a calibrated muscle, write it with `identify --calibrate -o` first")
        options = options.with_overrides(mode="shared", degree=DEGREE, calibrate=())
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


def _bounds(refitter: Refitter, effects) -> dict[str, dict[str, tuple[float, float]]]:
    """{effect: {parameter: (low, high)}} [SI] of the fitted effects' parameters (the refit's bounds)."""
    low, high = refitter.bounds(effects)
    start = low.size - len(effect_parameters(effects))
    out: dict[str, dict[str, tuple[float, float]]] = {}
    for j, (name, p) in enumerate(effect_parameters(effects)):
        out.setdefault(name, {})[p.name] = (low[start + j] * p.scale, high[start + j] * p.scale)
    return out


def anchoring_pressures(data: ExperimentData, refitter: Refitter, fit: Fit) -> tuple[float | None, ...]:
    """The fitted model's anchoring pressure [Pa] of each radial test (None for axial tests)."""
    muscle = refitter.muscle(fit)
    out = []
    for test in data.tests:
        if test.kind != "radial":
            out.append(None)
            continue
        value = float(np.asarray(muscle.anchoring_pressure(test.spec.pipe_diameter, test.spec.axial_load)))
        out.append(value if np.isfinite(value) else None)
    return tuple(out)


def row_residuals(data: ExperimentData, refitter: Refitter, fit: Fit) -> tuple[np.ndarray, ...]:
    """Model − data [N] at every recorded row, through :class:`pampipe.model.muscle.Muscle`."""
    muscle = refitter.muscle(fit)
    out = []
    for test in data.tests:
        if test.kind == "axial":
            pressure_leg = 0.0 if test.pressure_leg is None else test.pressure_leg.astype(float)
            model = muscle.axial_force(test.pressure, test.length, leg=test.leg.astype(float),
                                       pressure_leg=pressure_leg)
            model = np.where(slack_rows(test), contact_switch(model, SMOOTHING), model)  # as in the refit
        else:
            model = muscle.radial_force(test.pressure, test.spec.pipe_diameter, test.spec.axial_load,
                                        smoothing=SMOOTHING)
        out.append(np.asarray(model, dtype=float) - test.force)
    return tuple(out)


def diagnose(data: ExperimentData, *, effects: list[str] | None = None, folds: int = selection.FOLDS,
             reduce: bool = True, progress: Callable[[str], None] | None = None) -> DiagnoseResult:
    """Find the effects missing from the baseline model of ``data`` (see the module docstring)."""
    say = progress or (lambda _text: None)
    started = time.perf_counter()
    names = _candidates(data, effects)
    n = data.points
    timings = {}
    t0 = time.perf_counter()
    cells = reduce_rows(data, reduce=reduce)
    timings["reduce_wall_time_s"] = time.perf_counter() - t0
    say(f"{n:,} rows reduced to {cells.size:,} cells in {timings['reduce_wall_time_s']:.2f} s")
    refitter = Refitter(data, cells, degree=DEGREE)
    t0 = time.perf_counter()
    theta0, source = _initial_theta(data, say)
    base_fit = refitter.fit((), theta0, jacobian=True)
    floors = noise.noise_floors(data, cells, base_fit.residual)

    def assess(fit: Fit):
        return structure.assess(data, cells, fit, floors, anchoring_pressures(data, refitter, fit))

    def refit(chosen, start: Model) -> Fit:
        return refitter.fit(chosen, start.fit.theta, known=start.fit.eta(), jacobian=True, trial=True)

    search = Search(cells, refit, assess, lambda fit: selection.cross_validate(refitter, fit, k=folds), say)
    baseline = search.taken(search.model(base_fit))
    timings["baseline_wall_time_s"] = time.perf_counter() - t0
    say(f"baseline: {len(baseline.assessment.misfit)} of {len(data.tests)} tests off the noise "
        f"({timings['baseline_wall_time_s']:.1f} s)")
    t0 = time.perf_counter()
    final, steps = search.run(baseline, names)
    timings["selection_wall_time_s"] = time.perf_counter() - t0
    test_names = [t.name for t in data.tests]
    scores = Scores(cells.rows, baseline.sse, baseline.fit.x.size, final.sse, final.fit.x.size)
    verdict = decide(test_names, baseline.assessment, final.assessment, final.effects, scores)
    chosen = final if verdict.effects else baseline
    selected_summary = summarize(chosen, baseline.bic, data, cells, refitter)
    groups = tie_groups(steps, verdict.effects)
    undetermined = undetermined_effects(selected_summary, _bounds(refitter, chosen.fit.effects))
    verdict = qualify(verdict, groups=groups, undetermined=undetermined, floors=floors,
                      noisy=noise.noisier_than_twins(data, floors))

    t0 = time.perf_counter()
    confounded = _confounded(data, refitter, steps, chosen, floors, search.cache)
    timings["separate_wall_time_s"] = time.perf_counter() - t0
    if confounded:
        verdict = replace(verdict, reason=f"{verdict.reason}; " + "; ".join(_separations(confounded)))
    written = _untied(search, refit, baseline, chosen, verdict.indistinguishable)
    baseline, chosen = search.with_cv(baseline), search.with_cv(chosen)
    summaries = {"baseline": summarize(baseline, baseline.bic, data, cells, refitter),
                 "selected": summarize(chosen, baseline.bic, data, cells, refitter)}
    if written is not chosen:
        summaries["written"] = summarize(written, baseline.bic, data, cells, refitter)
    residuals = (row_residuals(data, refitter, baseline.fit), row_residuals(data, refitter, chosen.fit))
    timings["total_wall_time_s"] = time.perf_counter() - started
    result = DiagnoseResult(data.source, data.pam, data=data, cells=cells, noise=floors,
                            baseline_model=baseline, chosen_model=chosen, steps=tuple(steps), verdict=verdict,
                            confounded=tuple(confounded), summaries=summaries, residuals=residuals,
                            baseline_source=source, timings=timings, refitter=refitter,
                            anchoring=anchoring_pressures(data, refitter, baseline.fit),
                            ties=_ties(verdict.indistinguishable, confounded))
    if data.slip:
        say("slip tests: fitting friction with the diagnosed muscle and testing the residuals")
        result = replace(result, slip=diagnose_slip(data.slip, result.augmented_pam()))
    return result


def _candidates(data: ExperimentData, effects: list[str] | None) -> list[str]:
    """The candidate effects to try (every default one when ``effects`` is None), once each; InputError for an
    unknown name, an experiment of slip tests only, or too few rows for the baseline model."""
    names = list(DEFAULT) if effects is None else list(dict.fromkeys(effects))
    for name in names:
        try:
            candidate(name)
        except KeyError as exc:
            raise InputError(str(exc.args[0])) from None
    n = data.points
    if not data.tests and data.slip:
        raise InputError(f"{data.source}: only slip tests: `pampipe identify` fits their friction, and "
                         "`pampipe diagnose` tests their residuals together with axial or radial tests of "
                         "the muscle; for slip tests alone see the residual trends in `identify`'s report.")
    if n <= 4 * (DEGREE + 1) + 4:
        raise InputError(f"{data.source}: {n} data rows are too few to diagnose a "
                         f"{4 * (DEGREE + 1)}-parameter model; record more points.")
    return names


def _confounded(data: ExperimentData, refitter: Refitter, steps, chosen: Model, floors, models) -> list[dict]:
    """For each chosen effect that a step found confounded with another not chosen: the experiment that
    would separate the two ({effect, with, separate_by}), once per pair (one piece of advice each), judged
    against the model before the step (``models``: the search's cache of fitted models)."""
    confounded, seen = [], set()
    for step in steps:
        if step.action != "add" or step.effect not in chosen.effects:
            continue
        trials = {t.effect: t for t in step.trials}
        before = models[tuple(e for e in step.effects if e != step.effect)]
        for other in step.confounded:
            if other in chosen.effects or frozenset((step.effect, other)) in seen:
                continue
            seen.add(frozenset((step.effect, other)))
            separate = separating_experiment(data, refitter, trials[step.effect].model.fit,
                                             trials[other].model.fit, floors, before.fit)
            confounded.append({"effect": step.effect, "with": other, "separate_by": separate})
    return confounded


def _separations(confounded: list[dict]) -> list[str]:
    """A sentence per confounded pair, the pair in the library's order and without the noise's numbers (the
    same case gives the same advice on every seed, :mod:`.separate`): the test that separates them, or that
    none in range does (its ``separate_by`` is then cleared)."""
    words = []
    for c in confounded:
        sep = c["separate_by"]
        first, second = canonical((c["effect"], c["with"]))
        if sep is not None and sep["separates"]:
            words.append(f"{sep['experiment']} would separate {first} and {second}")
        else:
            c["separate_by"] = None
            words.append(f"no test in range separates {first} and {second}")
        c["sentence"] = words[-1]
    return words


def _untied(search: Search, refit, baseline: Model, chosen: Model, groups) -> Model:
    """The model `-o` writes: ``chosen``, or after a tie the refit without any member of a tie group (the
    data support the group, not one of its members): the other fitted effects, else the baseline."""
    tied = {name for group in groups for name in group}
    if not tied & set(chosen.effects):
        return chosen
    kept = tuple(e for e in chosen.effects if e not in tied)
    if not kept:
        return baseline
    return search.cache.get(kept) or search.model(refit(kept, chosen))


def _ties(groups, confounded: list[dict]) -> dict[str, str]:
    """{"a or b": the test that would separate them} of each tie group, from its confounded pairs'
    sentences (:func:`_separations`)."""
    out = {}
    for group in groups:
        sentences = [c["sentence"] for c in confounded if {c["effect"], c["with"]} <= set(group)]
        out[" or ".join(group)] = "; ".join(sentences) or "no separating test was found"
    return out
