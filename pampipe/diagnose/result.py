"""Frozen results of `diagnose` and their JSON document (docs/commands.md §6)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pampipe.diagnose.signatures import NoiseFloor, Region, Signature
from pampipe.model.effects import get_effect
from pampipe.model.pam import Moduli, Pam

MPA = 1e6


@dataclass(frozen=True)
class TestRmse:
    name: str
    kind: str
    points: int
    rmse: float  # [N]


@dataclass(frozen=True)
class Candidate:
    """One refitted model: the baseline (effect ``none``) or baseline + one effect."""

    effect: str
    theta: np.ndarray = field(repr=False, compare=False)  # moduli [Pa], b at P_ref = 1 MPa
    parameters: dict[str, float]  # SI, by parameter name
    intervals: dict[str, tuple[float, float]]  # 95 % [SI]
    sse: float  # [N²]
    bic: float
    delta_bic: float  # BIC − BIC(baseline)
    tests: tuple[TestRmse, ...]
    cv_rmse: float | None  # [N], None if not cross-validated
    iterations: int
    wall_time: float  # [s], fit + cross-validation
    status: str
    residuals: tuple[np.ndarray, ...] = field(repr=False, compare=False)  # per test, model − data [N]

    @property
    def sum_rmse(self) -> float:
        """Σ over tests of the test RMSE [N] (the `identify` metric)."""
        return float(sum(t.rmse for t in self.tests))

    def parameter_document(self) -> dict[str, float]:
        if self.effect == "none":
            return {}
        return {p.json_key: self.parameters[p.name] for p in get_effect(self.effect).parameters}

    def interval_document(self) -> dict[str, list[float]]:
        if self.effect == "none":
            return {}
        return {p.json_key: list(self.intervals[p.name]) for p in get_effect(self.effect).parameters}

    def as_document(self) -> dict:
        return {"effect": self.effect, "sum_rmse_N": self.sum_rmse, "bic": self.bic,
                "delta_bic": self.delta_bic,
                "sse_N2": self.sse, "cv_rmse_N": self.cv_rmse, "parameters": self.parameter_document(),
                "intervals_95": self.interval_document(), "iterations": self.iterations,
                "wall_time_s": self.wall_time, "status": self.status,
                "tests": [{"name": t.name, "rmse_N": t.rmse, "points": t.points} for t in self.tests]}


@dataclass(frozen=True)
class DiagnoseResult:
    source: Path
    pam: Pam
    baseline: Candidate
    candidates: tuple[Candidate, ...]  # ranked by BIC, best first
    selected: str  # an effect name or "none"
    reason: str
    confounded_with: str | None
    noise: tuple[NoiseFloor, ...]
    signatures: tuple[Signature, ...]
    regions: tuple[Region, ...]
    anchoring: tuple[float | None, ...]  # baseline P_anchor per test (radial) [Pa]
    baseline_source: str  # "identify" (shared mode, polished by the refit) or "refit"
    timings: dict[str, float]
    data: object = field(repr=False, compare=False)  # the ExperimentData (for plots)

    @property
    def chosen(self) -> Candidate:
        if self.selected == "none":
            return self.baseline
        return next(c for c in self.candidates if c.effect == self.selected)

    @property
    def improvement(self) -> float:
        """1 − selected.sum_rmse / baseline.sum_rmse (0 when none is selected)."""
        return 1.0 - self.chosen.sum_rmse / self.baseline.sum_rmse

    def augmented_pam(self) -> Pam:
        """The muscle with the refitted moduli and the selected effect (none: the baseline moduli)."""
        chosen = self.chosen
        moduli = Moduli.from_vector(chosen.theta, reference_pressure=MPA)
        effects = {chosen.effect: dict(chosen.parameters)} if chosen.effect != "none" else None
        return Pam(self.pam.name, self.pam.geometry, moduli, None, effects)

    def to_dict(self) -> dict:
        """The `diagnose --json` document (docs/commands.md §6)."""
        return self.as_document()

    def as_document(self) -> dict:
        chosen = self.chosen
        noise = {n.test: n for n in self.noise}
        after = {t.name: t.rmse for t in chosen.tests}
        return {
            "baseline": {**self.baseline.as_document(), "source": self.baseline_source},
            "candidates": [c.as_document() for c in self.candidates],
            "selected": {"effect": self.selected, "sum_rmse_N": chosen.sum_rmse,
                         "parameters": chosen.parameter_document(),
                         "intervals_95": chosen.interval_document(),
                         "reason": self.reason, "confounded_with": self.confounded_with},
            "improvement": self.improvement,
            "tests": [{"name": t.name, "kind": t.kind, "points": t.points, "rmse_before_N": t.rmse,
                       "rmse_after_N": after[t.name], "noise_floor_N": noise[t.name].sigma,
                       "noise_floor_high_frequency_N": noise[t.name].high_frequency}
                      for t in self.baseline.tests],
            "signatures": [{"name": s.name, "rms_N": None if not np.isfinite(s.rms) else s.rms,
                            "score": s.score,
                            "rows": s.rows} for s in self.signatures],
            "regions": [{"test": r.test, "pressure_Pa": list(r.pressure),
                         "length_m": None if r.length is None else list(r.length), "anchored": r.anchored,
                         "mean_residual_N": r.mean, "rmse_N": r.rmse, "rows": r.rows, "score": r.score}
                        for r in self.regions],
            "timings": dict(self.timings),
            "source": str(self.source),
        }
