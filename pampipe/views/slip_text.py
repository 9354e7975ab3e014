"""The slip-test part of the `identify` report (and of `diagnose`'s residual trends)."""

from __future__ import annotations

import math

from pampipe.units.display import scaled
from pampipe.views.tables import table


def slip_report(slip) -> str:
    """Trials, μ and κ with their 95 % intervals, what is determined, the friction law and the trends."""
    rows = [(t.test, t.index + 1, f"{t.pipe_diameter * 1e3:.4g}", t.pressure / 1e3,
             (">" if t.censored else "") + f"{t.slip_load:.5g}", f"{predicted:.5g}", f"{t.confidence:.3f}")
            for t, predicted in zip(slip.trials, slip.predicted, strict=True)]
    parts = ["\nSlip trials (> : no slip, a lower bound)",
             table(["test", "trial", "bore [mm]", "P [kPa]", "slip load [N]", "model [N]", "confidence"],
                   rows)]
    if slip.friction is not None:
        parts.append(f"friction mu = {_value(slip.friction)}; load coupling kappa = "
                     f"{_value(slip.load_coupling)} (95 % profile-likelihood intervals)")
    elif slip.friction_range is None:
        parts.append("friction mu and load coupling kappa: not estimated (too few trials slipped)")
    else:
        low, high = slip.friction_range
        parts.append("friction mu and load coupling kappa are NOT separately determined; the data fix the "
                     "effective friction mu/(1 + kappa*mu*pi*A) per bore:")
        rng = f"[{low:.4g}, {high:.4g}]" if high is not None else f"[{low:.4g}, unbounded)"
        parts.append(f"mu lies in {rng} for kappa anywhere in [0, 1]; to separate them: "
                     f"{slip.separating_test}")
    parts.append(table(["bore [mm]", "A", "effective friction", "95 % interval", "trials"],
                       [(f"{e.pipe_diameter * 1e3:.4g}", e.amplification, e.estimate.value,
                         _interval(e.estimate), e.trials) for e in slip.effective]))
    unit = "(log ratio)" if slip.noise == "relative" else "N"
    if math.isfinite(slip.sigma):
        parts.append(f"slip-load scatter: {slip.noise}, sigma {slip.sigma:.3g} {unit}")
    law = slip.law
    if law is not None:
        parts.append(f"friction law: Coulomb vs mu0*(p/{law.reference_pressure / 1e3:.4g} kPa)^n: n = "
                     f"{law.exponent:.3g}, likelihood ratio {law.likelihood_ratio:.3g} "
                     f"(p = {law.p_value:.2g}), delta BIC {law.delta_bic:.3g}: the data support "
                     f"{law.supported.replace('_', '-')} friction")
    parts.append(trend_lines(slip.trends))
    return "\n".join(parts)


def trend_lines(trends) -> str:
    """One line per residual trend test."""
    if not trends:
        return "slip residual trends: too few slipped trials (or no spread) to test"
    return "\n".join(f"slip residual vs {_against(t)}, p = {t.p_value:.2g} over "
                     f"{t.trials} trials: {'TREND' if t.significant else 'no trend'}" for t in trends)


#: SI unit suffix of a trend's variable -> (its metric unit, that unit in SI).
TREND_UNITS = {"_Pa": ("kPa", 1e3), "_N_per_s": ("N/s", 1.0)}


def _against(trend) -> str:
    """'pressure_Pa: slope 3.79e-09' (metric), or the slope per the display unit ('pressure_Pa: slope
    2.6e-05 per psi') when --units changes the variable's unit."""
    suffix = next((s for s in TREND_UNITS if trend.against.endswith(s)), None)
    if suffix is None:
        return f"{trend.against}: slope {trend.slope:.3g}"
    metric, size = TREND_UNITS[suffix]
    unit, k = scaled(metric)
    if k == 1.0:
        return f"{trend.against}: slope {trend.slope:.3g}"
    return f"{trend.against.removesuffix(suffix)}: slope {trend.slope * size / k:.3g} per {unit}"


def _value(e) -> str:
    return f"{e.value:.4g} {_interval(e)}"


def _interval(e) -> str:
    low = "-inf" if e.low is None else f"{e.low:.4g}"
    high = "open" if e.high is None else f"{e.high:.4g}"
    return f"[{low}, {high}]"
