"""Frozen results of `diagnose` and their JSON document (docs/commands.md §6.2 and §6.3)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pampipe.diagnosis import selection
from pampipe.diagnosis.candidates import candidate, corrected_geometry, library_part
from pampipe.model.pam import Moduli, Pam
from pampipe.results import frame, notebook

MPA = 1e6


def finite(value):
    """A JSON-safe number: None for NaN or ±inf (a missing estimate is said, never printed as NaN)."""
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None


@dataclass(frozen=True)
class TestRmse:
    name: str
    kind: str
    points: int
    rmse: float  # [N]


@dataclass(frozen=True)
class Summary:
    """One refitted model for the report: the baseline (no effects) or baseline + a set of effects."""

    effects: tuple[str, ...]
    theta: np.ndarray = field(repr=False, compare=False)  # moduli [Pa], b at P_ref = 1 MPa
    parameters: dict[str, dict[str, float]]  # {effect: {parameter: SI}}
    intervals: dict[str, dict[str, tuple[float, float]]]  # 95 % [SI]
    sse: float  # [N²]
    bic: float
    delta_bic: float  # BIC − BIC(baseline)
    tests: tuple[TestRmse, ...]
    cv_rmse: float | None  # [N]
    iterations: int
    wall_time: float  # [s]
    status: str

    @property
    def effect(self) -> str:
        """The first effect, or "none"."""
        return self.effects[0] if self.effects else "none"

    @property
    def sum_rmse(self) -> float:
        """Σ over tests of the test RMSE [N] (the `identify` metric)."""
        return float(sum(t.rmse for t in self.tests))

    def _keys(self) -> list[tuple[str, object, str]]:
        """[(effect, Parameter, JSON key)]; keys are prefixed with the effect where two would clash."""
        entries = [(name, p) for name in self.effects for p in candidate(name).parameters]
        keys = [p.json_key for _, p in entries]
        return [(name, p, key if keys.count(key) == 1 else f"{name}.{key}")
                for (name, p), key in zip(entries, keys, strict=True)]

    def parameter_document(self) -> dict[str, float]:
        return {key: self.parameters[name][p.name] for name, p, key in self._keys()}

    def interval_document(self) -> dict[str, list]:
        return {key: [finite(v) for v in self.intervals[name][p.name]] for name, p, key in self._keys()
                if name in self.intervals}

    def as_document(self) -> dict:
        return {"effect": self.effect, "effects": list(self.effects), "sum_rmse_N": self.sum_rmse,
                "bic": self.bic, "delta_bic": self.delta_bic, "sse_N2": self.sse,
                "cv_rmse_N": finite(self.cv_rmse),
                "parameters": self.parameter_document(), "intervals_95": self.interval_document(),
                "iterations": self.iterations, "wall_time_s": self.wall_time, "status": self.status,
                "tests": [{"name": t.name, "rmse_N": t.rmse, "points": t.points} for t in self.tests]}


def summarize(model, base_bic: float, data, cells, refitter) -> Summary:
    """A :class:`Summary` of a :class:`pampipe.diagnosis.search.Model`."""
    fit = model.fit
    rmse = cells.test_rmse(model.test_ss, len(data.tests))
    tests = tuple(TestRmse(t.name, t.kind, t.points, float(rmse[i])) for i, t in enumerate(data.tests))
    full = selection.intervals(fit, cells, refitter)
    bands = {e: {k: (v[1], v[2]) for k, v in ps.items()} for e, ps in full.items()}
    return Summary(fit.effects, refitter.moduli_si(fit.x), fit.effect_values(), bands, model.sse, model.bic,
                   model.bic - base_bic, tests, model.cv_rmse, fit.iterations, fit.wall_time, fit.status)


def _plot():
    from pampipe.views.plots.diagnose import plot_diagnosis

    return plot_diagnosis


def _text():
    from pampipe.views.diagnose_text import result_text

    return result_text


@notebook(headline=("verdict", "reason"), plot=_plot, text=_text)
@dataclass(frozen=True)
class DiagnoseResult:
    source: Path
    pam: Pam
    data: object = field(repr=False, compare=False)  # the ExperimentData
    cells: object = field(repr=False, compare=False)
    noise: tuple = ()  # NoiseFloor per test
    baseline_model: object = field(default=None, repr=False, compare=False)  # search.Model
    chosen_model: object = field(default=None, repr=False, compare=False)
    steps: tuple = ()  # search.Step
    verdict: object = None  # verdict.Verdict
    confounded: tuple[dict, ...] = ()
    summaries: dict = field(default_factory=dict)  # "baseline", "selected" -> Summary
    residuals: tuple = ((), ())  # row residuals per test [N], (baseline, selected)
    baseline_source: str = "refit"
    timings: dict = field(default_factory=dict)
    refitter: object = field(default=None, repr=False, compare=False)
    anchoring: tuple[float | None, ...] = ()  # the baseline's anchoring pressure per test (radial) [Pa]
    slip: object = None  # pampipe.diagnosis.slip_residuals.SlipDiagnosis of the slip tests (None: none)
    ties: dict[str, str] = field(default_factory=dict)  # {"a or b": the test that would separate them}

    @property
    def baseline(self) -> Summary:
        return self.summaries["baseline"]

    @property
    def chosen(self) -> Summary:
        return self.summaries["selected"]

    @property
    def selected_effects(self) -> tuple[str, ...]:
        return self.verdict.effects

    @property
    def selected(self) -> str:
        """The first selected effect, or "none"."""
        return self.selected_effects[0] if self.selected_effects else "none"

    @property
    def improvement(self) -> float:
        """1 − selected.sum_rmse / baseline.sum_rmse of the refit with the fitted effects, named, tied or
        undetermined (0 when nothing is fitted)."""
        return 1.0 - self.chosen.sum_rmse / self.baseline.sum_rmse if self.chosen.effects else 0.0

    @property
    def first_trials(self) -> tuple:
        """The first step's trials (baseline + one effect each), ranked by BIC."""
        return self.steps[0].trials if self.steps else ()

    @property
    def written(self) -> Summary:
        """The refit `-o` writes: the selected one, or after a tie the refit without any tied member."""
        return self.summaries.get("written", self.chosen)

    def candidates(self):
        """A pandas DataFrame of the effects tried in the first step, one row each, in the report's order:
        ``effect``, ``delta_bic``, ``cv_ratio``, ``where_share``, ``where_focus``, ``eligible``, ``note``,
        ``sum_rmse_N``, ``cv_rmse_N``, ``wall_time_s``."""
        from pampipe.diagnosis.frames import candidate_rows

        return frame(candidate_rows(self.to_dict()))

    def augmented_pam(self) -> Pam:
        """The muscle with the refitted moduli and effects of :attr:`written` (none: the baseline moduli);
        after a tie, the tie groups and the tests that would separate them (``Pam.ties``), none applied."""
        written = self.written
        moduli = Moduli.from_vector(written.theta, reference_pressure=MPA)
        effects = {name: dict(written.parameters[name]) for name in library_part(written.effects)} or None
        geometry = corrected_geometry(self.pam.geometry, written.effects, written.parameters)
        return Pam(self.pam.name, geometry, moduli, None, effects, self.pam.grip,
                   geometry_sd=self.pam.geometry_sd,
                   max_pressure=self.pam.max_pressure, max_contraction=self.pam.max_contraction,
                   fitting_length=self.pam.fitting_length, ties=dict(self.ties) or None)

    def step_sum_rmse(self, step) -> float:
        """Σ over tests of the RMSE [N] of the model a step took."""
        model = next(t.model for t in step.trials if t.effect == step.effect)
        return float(np.sum(self.cells.test_rmse(model.test_ss, len(self.data.tests))))

    def trial_summary(self, trial) -> Summary | None:
        if trial.model is None:
            return None
        return summarize(trial.model, self.baseline.bic, self.data, self.cells, self.refitter)

    def to_dict(self) -> dict:
        """The `diagnose --json` document (docs/commands.md §6.2)."""
        return self.as_document()

    def as_document(self) -> dict:
        chosen = self.chosen
        before = self.baseline_model.assessment.tests
        after = self.chosen_model.assessment.tests
        summaries = (self.trial_summary(t) for t in self.first_trials)
        candidates = [s.as_document() for s in summaries if s is not None]
        first_confounded = next((c["with"] for c in self.confounded if c["effect"] == self.selected), None)
        return {
            "verdict": self.verdict.verdict,
            "reason": self.verdict.reason,
            "baseline": {**self.baseline.as_document(), "source": self.baseline_source},
            "candidates": candidates,
            "steps": [_step_document(s) for s in self.steps],
            "selected": {**chosen.as_document(), "effect": self.selected,
                         "effects": list(self.selected_effects), "reason": self.verdict.reason,
                         "confounded_with": first_confounded, "confounded": _clean(list(self.confounded)),
                         "fitted_effects": list(self.verdict.fitted or self.chosen.effects),
                         "indistinguishable": [list(g) for g in self.verdict.indistinguishable],
                         "undetermined": list(self.verdict.undetermined)},
            "judged": self.verdict.judged,
            "cautions": list(self.verdict.cautions),
            "improvement": self.improvement,
            "remaining": [w.as_document() for w in self.verdict.remaining],
            "probes": {"library_removed_N2": self.verdict.library_removed,
                       "probes_removed_N2": self.verdict.probes_removed},
            "tests": [{"name": t.name, "kind": t.kind, "protocol": d.protocol, "points": t.points,
                       "rmse_before_N": t.rmse, "rmse_after_N": a.rmse, **_clean(f.as_document()),
                       "at_noise_before": b.at_noise, "at_noise_after": c.at_noise}
                      for t, d, a, f, b, c in zip(self.baseline.tests, self.data.tests, chosen.tests,
                                                  self.noise, before, after, strict=True)],
            "checks": {"baseline": [_clean(c.as_document()) for c in before],
                       "selected": [_clean(c.as_document()) for c in after]},
            "regions": [w.as_document() for w in (c.where for c in before) if w is not None],
            "cells": {"rows": int(self.cells.rows), "cells": int(self.cells.size)},
            "timings": dict(self.timings),
            "source": str(self.source),
            "slip": None if self.slip is None else self.slip.as_document(),
            "written": {"effects": list(self.written.effects), "ties": dict(self.ties)},
        }


def _clean(value):
    """Recursively replace NaN/inf by None."""
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    if isinstance(value, float):
        return finite(value)
    return value


def _step_document(step) -> dict:
    return {"step": step.number, "action": step.action, "effect": step.effect, "effects": list(step.effects),
            "confounded_with": list(step.confounded), "wall_time_s": step.wall_time,
            "trials": [{"effect": t.effect, "effects": list(t.effects), "delta_bic": finite(t.delta_bic),
                        "cv_ratio": finite(t.cv_ratio), "where_share": t.where_share,
                        "where_focus": t.where_focus, "eligible": t.eligible, "note": t.note,
                        "wall_time_s": t.wall_time} for t in step.trials]}
