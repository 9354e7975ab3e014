"""Forward selection of several effects, then a backward step (every fit joint: moduli + all effects).

Forward: from the current model (first the baseline), refit it with each candidate not yet in it
(library effects and mis-stated geometry entries, :mod:`.candidates`), warm-started.
An addition is *eligible* when it

1. lowers BIC by at least :data:`BIC_MARGIN` (Kass & Raftery: > 10 is "very strong");
2. lowers the cross-validated RMSE by at least :data:`CV_MARGIN` (additions are cross-validated in
   BIC order until one passes, at most :data:`CV_TOP` of them);
3. reduces the residual *where it was*: of the tests the current model leaves off the noise
   (:mod:`.structure`), it removes at least :data:`WHERE_SHARE` of their excess sum of squares, and
   at least :data:`WHERE_FOCUS` of everything it removes is removed there.

The eligible addition with the lowest BIC is taken; every other addition within BIC_MARGIN of it
(eligible or not) is *confounded* with it. Forward stops when no addition is eligible or when
every test is at the noise. A small beam keeps a wrong first step from being final: forward (and
backward) selection is run from each of the :data:`BEAM` best eligible first additions (up to
CV_TOP + BEAM − 1 are cross-validated) until one path ends with every test at the noise, and the
path that ends at the lowest BIC is taken.
Backward: each effect of a set of two or more is removed in turn; the
weakest whose removal does not cost both BIC_MARGIN of BIC and CV_MARGIN of cross-validated RMSE is
dropped, and so on.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pampipe.diagnosis import selection
from pampipe.diagnosis.refit import Fit, canonical
from pampipe.diagnosis.structure import Assessment
from pampipe.errors import SolverError

BIC_MARGIN = 10.0
CV_MARGIN = 0.02
CV_TOP = 3
#: First additions from which forward selection is run (a small beam: a wrong first step is not final).
BEAM = 3
WHERE_SHARE = 0.25
WHERE_FOCUS = 0.5


@dataclass(frozen=True)
class Model:
    """A fitted model and its scores (``assessment`` only for models that were taken)."""

    fit: Fit
    bic: float
    sse: float
    test_ss: np.ndarray = field(repr=False)  # Σ n r̄² per test [N²]
    cv_rmse: float | None = None
    assessment: Assessment | None = None

    @property
    def effects(self) -> tuple[str, ...]:
        return self.fit.effects


@dataclass(frozen=True)
class Trial:
    """One refit tried at one step."""

    effect: str  # the effect added (forward) or removed (backward)
    effects: tuple[str, ...]  # the model tried
    model: Model | None  # None: the solve failed
    delta_bic: float  # BIC(tried) − BIC(current)
    cv_ratio: float | None  # cv_rmse(tried) / cv_rmse(current)
    where_share: float  # share of the misfit tests' excess removed (forward)
    where_focus: float  # share of the removed SS that was on the misfit tests (forward)
    eligible: bool
    note: str
    wall_time: float


@dataclass(frozen=True)
class Step:
    number: int
    action: str  # "add", "remove", "stop"
    effect: str | None
    effects: tuple[str, ...]  # the model after the step
    trials: tuple[Trial, ...]  # ranked by BIC
    confounded: tuple[str, ...]
    wall_time: float


class Search:
    """Runs the selection for one experiment; ``refit(effects, start)`` and ``assess(fit)`` come
    from the workflow."""

    def __init__(self, cells, refit: Callable[[tuple[str, ...], Model], Fit],
                 assess: Callable[[Fit], Assessment], cross_validate: Callable[[Fit], float],
                 say: Callable[[str], None]):
        self.cells, self._refit, self._assess, self._cv, self.say = cells, refit, assess, cross_validate, say
        self.n_tests = int(cells.test.max()) + 1 if cells.size else 0
        self.cache: dict[tuple[str, ...], Model] = {}
        self.cv_values: dict[tuple[str, ...], float] = {}
        self.refit_times: list[float] = []  # [s] of every refit solved, for the progress estimate
        self.cv_times: list[float] = []  # [s] of every cross-validation, for the progress estimate

    def cv(self, model: Model) -> float:
        """The model's cross-validated RMSE [N], computed once (only when a decision needs it); the progress
        says which model is cross-validated and its time at the mean cross-validation so far."""
        if model.effects not in self.cv_values:
            eta = f", about {np.mean(self.cv_times):.0f} s at the mean so far" if self.cv_times else ""
            self.say(f"cross-validating {' + '.join(model.effects) or 'baseline'} (fold refits{eta})")
            started = time.perf_counter()
            self.cv_values[model.effects] = self._cv(model.fit)
            self.cv_times.append(time.perf_counter() - started)
        return self.cv_values[model.effects]

    def with_cv(self, model: Model) -> Model:
        """The model with its cross-validated RMSE where one was computed."""
        return Model(model.fit, model.bic, model.sse, model.test_ss, self.cv_values.get(model.effects),
                     model.assessment)

    def model(self, fit: Fit) -> Model:
        ss = np.bincount(self.cells.test, weights=self.cells.count * fit.residual**2, minlength=self.n_tests)
        return Model(fit, selection.bic(fit, self.cells), selection.sse(fit, self.cells), ss)

    def taken(self, model: Model) -> Model:
        """The model with its assessment (once)."""
        assessment = model.assessment or self._assess(model.fit)
        out = Model(model.fit, model.bic, model.sse, model.test_ss, self.cv_values.get(model.effects),
                    assessment)
        self.cache[model.effects] = out
        return out

    def _try(self, effects: tuple[str, ...], start: Model) -> tuple[Model | None, float, str]:
        started = time.perf_counter()
        if effects in self.cache:
            return self.cache[effects], 0.0, ""
        try:
            model = self.model(self._refit(effects, start))
        except SolverError as exc:
            return None, time.perf_counter() - started, str(exc)
        self.cache[effects] = model
        self.refit_times.append(time.perf_counter() - started)
        return model, time.perf_counter() - started, ""

    def progress(self, done: int, total: int, effects: tuple[str, ...], what: str = "refit") -> None:
        """Say which refit runs, how many of this step's are left, and their time at the mean so far."""
        left = total - done
        mean = float(np.mean(self.refit_times)) if self.refit_times else None
        eta = "" if mean is None else f", about {left * mean:.0f} s at {mean:.1f} s each"
        self.say(f"{what} {done + 1} of {total} of this step: {' + '.join(effects) or 'baseline'} "
                 f"({left} left{eta})")

    def run(self, baseline: Model, names: list[str]) -> tuple[Model, list[Step]]:
        """Forward then backward from the baseline, from the best eligible first addition and, unless
        that path ends at the noise, from the next of the :data:`BEAM` best; the path that ends at the
        lowest BIC wins (its steps are returned)."""
        current = self.taken(baseline)
        first, starts = self._step(current, names, [], wanted=BEAM)
        if not starts:
            return current, [first]
        paths = []
        for start in starts:
            if paths and paths[0][0].assessment.at_noise:
                break  # the best first step already ends at the noise: no other path can do better
            steps = [self._added(first, start)]
            model = self.taken(start.model)
            self.say(f"step 1: add {start.effect} (dBIC {start.delta_bic:.1f})"
                     + (f", beam {len(paths) + 1} of {len(starts)}" if len(starts) > 1 else ""))
            model = self._forward(model, names, steps)
            paths.append(self._backward(model, steps))
        best = min(paths, key=lambda path: path[0].bic)
        if len(paths) > 1:
            others = [f"{' + '.join(m.effects) or 'baseline'} ({m.bic - best[0].bic:+.1f})" for m, _ in paths
                      if m is not best[0]]
            self.say(f"beam: {' + '.join(best[0].effects)} ends lowest; other paths: {', '.join(others)}")
        return best

    def _added(self, step: Step, trial: Trial) -> Step:
        """The step that takes ``trial`` (its confounded alternatives within BIC_MARGIN of it)."""
        confounded = tuple(t.effect for t in step.trials if t is not trial and t.model is not None
                           and t.delta_bic - trial.delta_bic < BIC_MARGIN and t.delta_bic <= -BIC_MARGIN)
        return Step(step.number, "add", trial.effect, trial.effects, step.trials, confounded, step.wall_time)

    def _step(self, current: Model, names: list[str], steps: list[Step], *, wanted: int = 1
              ) -> tuple[Step, list[Trial]]:
        """One forward step's trials: (a stop step or the step's trials, the eligible additions)."""
        started = time.perf_counter()
        misfit = current.assessment.misfit
        remaining = [n for n in names if n not in current.effects]
        number = len(steps) + 1
        if not misfit or not remaining:
            why = "every test is at the noise" if not misfit else "no effect left to add"
            self.say(f"step {number}: stop ({why})")
            return Step(number, "stop", None, current.effects, (), (), 0.0), []
        trials = self._forward_trials(current, remaining, misfit, wanted)
        eligible = [t for t in trials if t.eligible]
        wall = time.perf_counter() - started
        if not eligible:
            self.say(f"step {number}: no eligible addition ({wall:.1f} s)")
            return Step(number, "stop", None, current.effects, tuple(trials), (), wall), []
        return Step(number, "add", None, current.effects, tuple(trials), (), wall), eligible[:wanted]

    def _forward(self, current: Model, names: list[str], steps: list[Step]) -> Model:
        while True:
            step, eligible = self._step(current, names, steps)
            if not eligible:
                steps.append(step)
                return current
            best = eligible[0]
            current = self.taken(best.model)
            steps.append(self._added(step, best))
            self.say(f"step {len(steps)}: add {best.effect} (dBIC {best.delta_bic:.1f}) in "
                     f"{step.wall_time:.1f} s")

    def _backward(self, current: Model, steps: list[Step]) -> tuple[Model, list[Step]]:
        while len(current.effects) >= 2:
            started = time.perf_counter()
            trials = self._backward_trials(current)
            removable = [t for t in trials if t.eligible]
            wall = time.perf_counter() - started
            if not removable:
                steps.append(Step(len(steps) + 1, "keep", None, current.effects, tuple(trials), (), wall))
                self.say(f"step {len(steps)}: backward, every effect kept ({wall:.1f} s)")
                break
            weakest = removable[0]
            current = self.taken(weakest.model)
            steps.append(Step(len(steps) + 1, "remove", weakest.effect, current.effects, tuple(trials), (),
                              wall))
            self.say(f"step {len(steps)}: remove {weakest.effect} ({wall:.1f} s)")
        return current, steps

    def _forward_trials(self, current: Model, remaining: list[str], misfit: tuple[int, ...], wanted: int = 1
                        ) -> list[Trial]:
        excess = current.assessment.excess(misfit)
        rows = []
        for done, name in enumerate(remaining):
            effects = canonical((*current.effects, name))
            self.progress(done, len(remaining), effects)
            model, wall, error = self._try(effects, current)
            if model is None:
                rows.append(Trial(name, effects, None, np.inf, None, 0.0, 0.0, False, error, wall))
                continue
            removed = current.test_ss - model.test_ss
            on_misfit = float(removed[list(misfit)].sum())
            total = float(removed.sum())
            share = on_misfit / excess if excess > 0 else 0.0
            focus = on_misfit / total if total > 0 else 0.0
            rows.append(Trial(name, effects, model, model.bic - current.bic, None, share, focus, False, "",
                              wall))
        rows.sort(key=lambda t: t.delta_bic)
        out, validated = [], 0
        for trial in rows:
            notes = []
            if trial.model is None:
                out.append(trial)
                continue
            if trial.delta_bic > -BIC_MARGIN:
                notes.append(f"BIC not {BIC_MARGIN:g} lower")
            if trial.where_share < WHERE_SHARE or trial.where_focus < WHERE_FOCUS:
                share, focus = (round(v, 2) + 0.0 for v in (trial.where_share, trial.where_focus))
                notes.append(f"removes {share:.0%} of the excess where the residual was "
                             f"({focus:.0%} of its gain there)")
            ratio = None
            passed = sum(t.eligible for t in out)
            if not notes and validated < CV_TOP + passed and passed < wanted:
                started = time.perf_counter()
                cv, reference = self.cv(trial.model), self.cv(current)
                validated += 1
                model = self.with_cv(trial.model)
                self.cache[trial.effects] = model
                ratio = cv / reference if reference and np.isfinite(cv) and np.isfinite(reference) else None
                trial = Trial(trial.effect, trial.effects, model, trial.delta_bic, ratio, trial.where_share,
                              trial.where_focus, False, "", trial.wall_time + time.perf_counter() - started)
                if ratio is None or ratio > 1 - CV_MARGIN:
                    notes.append(f"cross-validated RMSE not {CV_MARGIN:.0%} lower")
            elif not notes:
                notes.append("not cross-validated (a better addition passed)" if any(t.eligible for t in out)
                             else "not cross-validated (not among the best)")
            out.append(Trial(trial.effect, trial.effects, trial.model, trial.delta_bic, ratio,
                             trial.where_share, trial.where_focus, not notes, "; ".join(notes),
                             trial.wall_time))
        return out

    def _backward_trials(self, current: Model) -> list[Trial]:
        out = []
        for done, name in enumerate(current.effects):
            effects = tuple(e for e in current.effects if e != name)
            self.progress(done, len(current.effects), effects, what=f"refit without {name},")
            model, wall, error = self._try(effects, current)
            if model is None:
                out.append(Trial(name, effects, None, np.inf, None, 0.0, 0.0, False, error, wall))
                continue
            started = time.perf_counter()
            cv, reference = self.cv(model), self.cv(current)
            model = self.with_cv(model)
            self.cache[effects] = model
            ratio = cv / reference if reference and np.isfinite(cv) and np.isfinite(reference) else None
            delta = model.bic - current.bic
            needed = delta >= BIC_MARGIN and ratio is not None and reference <= (1 - CV_MARGIN) * cv
            note = ("needed" if needed
                    else f"removing it costs {delta:.1f} BIC, CV ratio {ratio or float('nan'):.3f}")
            out.append(Trial(name, effects, model, delta, ratio, 0.0, 0.0, not needed, note,
                             wall + time.perf_counter() - started))
        out.sort(key=lambda t: t.delta_bic)
        return out
