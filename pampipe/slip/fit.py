"""Friction μ and load coupling κ from slip trials, by the plan's own slip model (docs/physics.md §13.3).

The model is the no-slip condition at safety factor 1: the slip load F solves F = μ·π·F_r(P, D, κF)
(:meth:`pampipe.model.muscle.Muscle.largest_load`). Slip loads scatter about it, either relatively
(log F = log F̂ + ε) or absolutely (F = F̂ + ε), ε ~ N(0, σ²); the noise model with the larger
likelihood gives the values, and the reported intervals span both models'
(:func:`pampipe.slip.workflow.spanning`). A censored trial (no slip up to its largest load F_c) enters as
the survival term P(F > F_c) = 1 − Φ((F_c − F̂)/σ) (or its log form). 95 % intervals are profile-likelihood
intervals: the values where 2·(ℓ̂ − ℓ_profile) = c, the other parameters re-optimised. With σ estimated
from n slipped trials and p free slip parameters, c = n·ln(1 + t²/(n − p)) with t the 97.5 % quantile of
Student's t on n − p degrees of freedom: the likelihood-ratio form of the exact t interval of a normal
model, which tends to χ²₁ = 3.841 for many trials and is wider for few (4 trials, p = 1: c = 5.90).
With σ held, c = 3.841. A bound reached before that leaves the interval open: the quantity is then not
determined.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: χ²₁ quantile of a 95 % profile-likelihood interval (σ known, or many trials).
CHI2_95 = 3.841458820694124
#: Search bounds of μ and κ (a bound reached by the interval leaves it open).
FRICTION_BOUNDS = (1e-3, 5.0)
KAPPA_BOUNDS = (0.0, 3.0)
#: Smallest model slip load [N] (a trial below the anchoring pressure is predicted to hold nothing).
FLOOR = 1e-6

Model = Callable[[float, float], np.ndarray]  # (μ, κ) -> every trial's slip load [N]


@dataclass(frozen=True)
class Estimate:
    """A fitted value with its 95 % profile interval; an end is None where the interval is open."""

    value: float
    low: float | None
    high: float | None

    @property
    def closed(self) -> bool:
        return self.low is not None and self.high is not None

    @property
    def sd(self) -> float | None:
        """(high − low)/(2·1.96): the normal sd of the same width (None when open)."""
        return None if not self.closed else (self.high - self.low) / (2 * 1.959963984540054)


def interval_threshold(slipped: int, free: int, sigma_held: bool) -> float:
    """c of a 95 % profile interval, 2·(ℓ̂ − ℓ_profile) = c: n·ln(1 + t²₀.₉₇₅,ₙ₋ₚ/(n − p)) for n slipped
    trials and p free slip parameters with σ estimated (the small-sample form of χ²₁), χ²₁ with σ held;
    inf (an open interval) with no degree of freedom left."""
    if sigma_held:
        return CHI2_95
    dof = slipped - free
    if dof < 1:
        return math.inf
    from scipy.special import stdtrit

    t = float(stdtrit(dof, 0.975))
    return slipped * math.log1p(t * t / dof)


@dataclass(frozen=True)
class Likelihood:
    """The log-likelihood of slip loads ``load`` (``censored``: lower bounds) under a slip model."""

    load: np.ndarray  # [N]
    censored: np.ndarray  # bool
    model: Model
    noise: str = "relative"  # relative | absolute
    sigma: float | None = None  # σ held at this value (then the log_sigma argument is ignored)

    def __call__(self, mu: float, kappa: float, log_sigma: float) -> float:
        predicted = np.maximum(self.model(mu, kappa), FLOOR)
        if self.sigma is not None:
            log_sigma = math.log(self.sigma)
        sigma = math.exp(log_sigma)
        if self.noise == "relative":
            z = (np.log(np.maximum(self.load, FLOOR)) - np.log(predicted)) / sigma
            jacobian = np.log(np.maximum(self.load, FLOOR))
        else:
            z = (self.load - predicted) / sigma
            jacobian = 0.0
        exact = -0.5 * z**2 - math.log(math.sqrt(2 * math.pi)) - log_sigma - jacobian
        from scipy.special import log_ndtr  # here: importing scipy.special costs every identify 0.2 s

        survival = log_ndtr(-z)
        return float(np.sum(np.where(self.censored, survival, exact)))


@dataclass(frozen=True)
class Fit:
    """Maximum likelihood of (μ, κ, log σ) with κ free or held (``kappa_free``)."""

    mu: float
    kappa: float
    log_sigma: float
    loglik: float
    kappa_free: bool


def maximise(like: Likelihood, *, kappa: float | None = None, mu: float | None = None,
             start: tuple[float, float] = (0.3, 0.5), kappa_bounds=KAPPA_BOUNDS, sigma: float | None = None,
             multistart: bool = True) -> Fit:
    """Maximum likelihood over the free ones of μ, κ (each held when given) and log σ.

    ``sigma``: the start of log σ; ``multistart``: also start κ at both ends of its range (the
    likelihood may be flat in κ), else only at ``start``.
    """
    from scipy.optimize import minimize

    free_mu, free_kappa = mu is None, kappa is None
    sigma0 = sigma if sigma is not None else \
        math.log(0.1 if like.noise == "relative" else max(0.1 * float(np.median(like.load)), 1e-3))

    def unpack(x):
        i = 0
        m = x[i] if free_mu else mu
        i += free_mu
        k = x[i] if free_kappa else kappa
        i += free_kappa
        return m, k, x[i]

    x0 = ([start[0]] if free_mu else []) + ([start[1]] if free_kappa else []) + [sigma0]
    bounds = ([FRICTION_BOUNDS] if free_mu else []) + ([kappa_bounds] if free_kappa else []) + [(-12.0, 8.0)]
    best = None
    starts = [x0]
    if free_kappa and multistart:  # the likelihood may be flat in κ: start from both ends of its range too
        for k0 in kappa_bounds:
            alt = list(x0)
            alt[int(free_mu)] = k0
            starts.append(alt)
    for guess in starts:
        result = minimize(lambda x: -like(*unpack(x)), np.clip(guess, [b[0] for b in bounds],
                                                                  [b[1] for b in bounds]),
                          method="L-BFGS-B", bounds=bounds)
        if best is None or result.fun < best.fun:
            best = result
    m, k, s = unpack(best.x)
    return Fit(float(m), float(k), float(s), float(-best.fun), free_kappa)


def profile_interval(like: Likelihood, best: Fit, which: str, bounds, *,
                     kappa_bounds=KAPPA_BOUNDS, kappa_fixed: float | None = None) -> Estimate:
    """The 95 % profile-likelihood interval of ``which`` (``friction`` or ``load_coupling``).

    The other parameters (κ unless ``kappa_fixed``, and σ) are re-optimised at each trial value;
    an end is None where the profile stays within χ²₁/2 of the maximum up to ``bounds``.
    """
    from scipy.optimize import brentq

    value = best.mu if which == "friction" else best.kappa
    free = 2 if which == "load_coupling" or (kappa_fixed is None and best.kappa_free) else 1  # μ; κ if free
    slipped = int(np.sum(~like.censored))
    target = best.loglik - interval_threshold(slipped, free, like.sigma is not None) / 2

    def profile(v: float) -> float:
        if which == "friction":
            fit = maximise(like, mu=v, kappa=kappa_fixed, start=(v, best.kappa), kappa_bounds=kappa_bounds,
                           sigma=best.log_sigma, multistart=False)
        else:
            fit = maximise(like, kappa=v, start=(best.mu, v), sigma=best.log_sigma, multistart=False)
        return fit.loglik - target

    ends = []
    for edge in bounds:
        if not math.isfinite(target) or abs(edge - value) < 1e-12 or profile(edge) > 0:
            ends.append(None)
            continue
        ends.append(float(brentq(profile, *sorted((value, edge)), xtol=1e-6 * max(abs(value), 1e-3))))
    low, high = ends
    if low is None and which == "load_coupling" and bounds[0] == 0.0:
        low = 0.0  # κ ≥ 0 is physics (no load path pushes the anchor): the interval ends there
    return Estimate(value, low, high)
