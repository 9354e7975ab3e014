"""Slip tests (docs/physics.md §13): wall friction μ and load coupling κ with their intervals.

Modules: :mod:`.detect` (slip onset per trial), :mod:`.fit` (censored likelihood, profile intervals),
:mod:`.law` (Coulomb against contact-pressure-dependent friction), :mod:`.trend` (residual trends),
:mod:`.result` and :mod:`.workflow` (:func:`fit_slip`).
"""

from pampipe.slip.result import SlipResult
from pampipe.slip.workflow import detect_trials, fit_slip

__all__ = ["SlipResult", "detect_trials", "fit_slip"]
