"""The result of the slip tests: trials, μ and κ with intervals, what is determined, the law check."""

from __future__ import annotations

import math
from dataclasses import dataclass

from pampipe.model.pam import Grip
from pampipe.slip.detect import Trial
from pampipe.slip.fit import Estimate
from pampipe.slip.law import LawCheck
from pampipe.slip.trend import Trend

#: Name of the combination one bore determines (docs/physics.md §13.3).
EFFECTIVE = "effective_friction"
EFFECTIVE_FORMULA = "friction / (1 + load_coupling * friction * pi * A(D))"


@dataclass(frozen=True)
class Effective:
    """μ_eff = μ/(1 + κμπA(D)) at one bore: the slip load per unloaded normal force π·F_r(P, D, 0)."""

    pipe_diameter: float  # [m]
    amplification: float  # A(D) [-]
    estimate: Estimate
    trials: int

    def as_document(self) -> dict:
        return {"pipe_diameter_m": self.pipe_diameter, "amplification_factor": self.amplification,
                **_estimate(self.estimate), "trials": self.trials}


@dataclass(frozen=True)
class SlipResult:
    """Slip tests → detected trials, μ and κ (None when not determined), per-bore effective friction.

    ``friction_range`` is μ's 95 % range when κ is not determined, for κ anywhere in [0, 1] (the
    load paths from none to through the anchor); its upper end is None when unbounded.
    ``predicted`` is each trial's model slip load at the fit [N], ``residual`` its residual (log ratio
    for relative noise, N for absolute).
    """

    trials: tuple[Trial, ...]
    predicted: tuple[float, ...]
    residual: tuple[float, ...]
    noise: str
    sigma: float
    friction: Estimate | None
    load_coupling: Estimate | None
    friction_range: tuple[float, float | None] | None
    effective: tuple[Effective, ...]
    law: LawCheck | None
    trends: tuple[Trend, ...]
    pipe_material: str | None
    warnings: tuple[str, ...]

    @property
    def determined(self) -> list[str]:
        """What the data fix: ``friction`` and ``load_coupling``, or the effective friction only."""
        if self.friction is not None and self.load_coupling is not None:
            return ["friction", "load_coupling"]
        return [EFFECTIVE]

    @property
    def separating_test(self) -> str | None:
        """The test that would separate μ from κ (None when they are separated)."""
        if self.load_coupling is not None:
            return None
        bores = sorted({e.pipe_diameter for e in self.effective})
        if len(bores) == 1:
            return ("slip tests at a second bore (one where the muscle's amplification factor A differs "
                    f"from {self.effective[0].amplification:.3g}, e.g. a wider pipe) or with a second load "
                    "path (the load applied through the far end fitting): 1/mu_eff = 1/mu + kappa*pi*A is a "
                    "line in A, and two points fix it")
        return ("the tested bores' amplification factors differ too little to fix kappa at this scatter: "
                "add trials, or a bore further apart")

    def grip(self) -> Grip | None:
        """The PAM's ``contact:`` block: (μ, κ) when determined, else the smallest effective friction
        with κ None (conservative with the mission's load path: docs/physics.md §13.3); None when no
        effective friction has a closed interval (e.g. no trial slipped: no upper limit)."""
        bores = tuple(sorted({e.pipe_diameter for e in self.effective}))
        if self.friction is not None and self.load_coupling is not None:
            return Grip(self.friction.value, self.friction.sd, self.load_coupling.value,
                        self.load_coupling.sd, self.pipe_material, bores)
        closed = [e for e in self.effective if e.estimate.closed]
        if not closed:
            return None
        lowest = min(closed, key=lambda e: e.estimate.value)
        return Grip(lowest.estimate.value, lowest.estimate.sd, None, 0.0, self.pipe_material,
                    (lowest.pipe_diameter,))

    def as_document(self) -> dict:
        """The ``slip`` block of the ``identify`` JSON (docs/commands.md, identify)."""
        friction = _estimate(self.friction) if self.friction is not None else {
            "value": None, "ci95": None, "sd": None,
            "range_for_load_coupling_0_to_1":
                None if self.friction_range is None else list(self.friction_range)}
        return {
            "friction": friction,
            "load_coupling": None if self.load_coupling is None else _estimate(self.load_coupling),
            "determined": self.determined,
            "combination": {"name": EFFECTIVE, "formula": EFFECTIVE_FORMULA,
                            "per_bore": [e.as_document() for e in self.effective]},
            "separating_test": self.separating_test,
            "noise": {"model": self.noise, "sigma": _number(self.sigma),
                      "unit": "log ratio" if self.noise == "relative" else "N"},
            "friction_law": None if self.law is None else self.law.as_document(),
            "residual_trends": [t.as_document() for t in self.trends],
            "pipe_material": self.pipe_material,
            "trials": [_trial(t, p, r) for t, p, r in zip(self.trials, self.predicted, self.residual,
                                                          strict=True)],
            "warnings": list(self.warnings),
        }


def _estimate(e: Estimate) -> dict:
    return {"value": _number(e.value), "ci95": [e.low, e.high], "sd": e.sd}


def _number(value: float) -> float | None:
    """A float, or None (JSON null) where it is not a number (not estimated)."""
    return float(value) if math.isfinite(value) else None


def _trial(t: Trial, predicted: float, residual: float) -> dict:
    return {"test": t.test, "trial": t.index + 1, "pipe_diameter_m": t.pipe_diameter,
            "pressure_Pa": t.pressure, "slip_load_N": t.slip_load, "censored": t.censored,
            "confidence": t.confidence, "onset_time_s": t.onset_time,
            "load_rate_N_per_s": _number(t.load_rate), "predicted_slip_load_N": _number(predicted),
            "residual": _number(residual)}
