"""Coulomb or contact-pressure-dependent friction? (docs/physics.md §13.4)

The alternative law is μ(p) = μ₀·(p/p_ref)^n, p the mean contact pressure F_r/(D·L_p) while the load
acts (:meth:`pampipe.model.muscle.Muscle.contact_pressure`), p_ref the geometric mean of the trials'
unloaded contact pressures (so μ₀ is μ at the typical tested pressure). Its slip load solves
F = μ(p(F))·π·F_r(P, D, κF) by bisection. Coulomb is its n = 0 case: the likelihood ratio
LR = 2(ℓ_n − ℓ_0) is χ²₁ under Coulomb, and ΔBIC = BIC_n − BIC_0 = ln N − LR; the data support the
pressure-dependent law when ΔBIC < 0 and LR's p-value is below 0.05.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.slip.fit import Fit, Likelihood, maximise

#: Range of the exponent n searched.
EXPONENT_BOUNDS = (-0.5, 1.0)
#: Bisection halvings of the slip load.
STEPS = 40


@dataclass(frozen=True)
class LawCheck:
    """Coulomb against μ₀(p/p_ref)^n: the evidence and the verdict (``supported``)."""

    exponent: float
    friction_at_reference: float  # μ₀
    reference_pressure: float  # p_ref [Pa]
    likelihood_ratio: float
    p_value: float
    delta_bic: float  # BIC(pressure-dependent) − BIC(Coulomb): > 0 favours Coulomb
    supported: str  # coulomb | pressure_dependent

    def as_document(self) -> dict:
        return {"alternative": "friction = mu0 * (contact_pressure / reference)^n",
                "exponent": self.exponent, "mu0": self.friction_at_reference,
                "reference_contact_pressure_Pa": self.reference_pressure,
                "likelihood_ratio": self.likelihood_ratio, "p_value": self.p_value,
                "delta_bic": self.delta_bic, "supported": self.supported}


def power_law_model(muscle, pressure, diameter, kappa: float, reference: float):
    """model(μ₀, n) → every trial's slip load [N] under μ = μ₀(p/p_ref)^n (bisection on F)."""
    pressure, diameter = np.asarray(pressure, float), np.asarray(diameter, float)
    unloaded = np.maximum(np.asarray(muscle.radial_force(pressure, diameter, 0.0), float), 0.0)

    def model(mu0, n):
        p, d, r0 = pressure, diameter, unloaded
        low, high = np.zeros(p.shape), 10.0 * math.pi * r0 + 1.0
        for _ in range(STEPS):
            mid = 0.5 * (low + high)
            radial = np.maximum(np.asarray(muscle.radial_force(p, d, kappa * mid), float), 0.0)
            contact = np.asarray(muscle.contact_pressure(radial, d), float)
            mu = np.minimum(mu0 * np.power(np.maximum(contact, 1e-9) / reference, n), 10.0)
            holds = mu * math.pi * radial >= mid
            low, high = np.where(holds, mid, low), np.where(holds, high, mid)
        return np.where(r0 > 0, low, 0.0)

    return model


def check_law(muscle, pressure, diameter, load, censored, coulomb: Fit, noise: str) -> LawCheck | None:
    """Fit μ₀ and n at Coulomb's κ and compare (None with fewer than 3 slipped trials, or none touching)."""
    if int(np.sum(~np.asarray(censored))) < 3:
        return None
    reference = reference_pressure(muscle, pressure, diameter)
    if reference is None:
        return None
    like = Likelihood(np.asarray(load, float), np.asarray(censored, bool),
                      power_law_model(muscle, pressure, diameter, coulomb.kappa, reference), noise)
    # the exponent rides in maximise's second slot (its "κ"), searched over EXPONENT_BOUNDS
    alternative = maximise(like, start=(coulomb.mu, 0.0), kappa_bounds=EXPONENT_BOUNDS,
                           sigma=coulomb.log_sigma, multistart=False)
    ratio, p_value, delta_bic = evidence(alternative.loglik, coulomb.loglik, len(load))
    return LawCheck(alternative.kappa, alternative.mu, reference, ratio, p_value, delta_bic,
                    verdict(delta_bic, p_value))


def reference_pressure(muscle, pressure, diameter) -> float | None:
    """p_ref [Pa]: the geometric mean of the unloaded contact pressures F_r(P, D, 0)/(D·L_p) of the trials
    that touch (F_r > 0); None where none does."""
    contact = np.asarray(muscle.contact_pressure(
        np.maximum(np.asarray(muscle.radial_force(pressure, diameter, 0.0), float), 0.0), diameter), float)
    positive = contact[contact > 0]
    if positive.size == 0:
        return None
    return float(np.exp(np.mean(np.log(positive))))


def evidence(alternative: float, coulomb: float, trials: int) -> tuple[float, float, float]:
    """(LR, p, ΔBIC) from the two maximised log-likelihoods: LR = max(2(ℓ_n − ℓ_0), 0) (the alternative
    nests Coulomb, so a shortfall is the optimiser's), p = P(χ²₁ > LR), ΔBIC = ln N − LR."""
    from scipy.special import chdtrc

    ratio = max(2 * (alternative - coulomb), 0.0)
    return ratio, float(chdtrc(1, ratio)), math.log(trials) - ratio


def verdict(delta_bic: float, p_value: float) -> str:
    """``pressure_dependent`` where ΔBIC < 0 and the likelihood ratio's p-value < 0.05, else ``coulomb``."""
    return "pressure_dependent" if delta_bic < 0 and p_value < 0.05 else "coulomb"
