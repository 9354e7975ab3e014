"""The fit with a block of the protocol withheld (:mod:`.model_error`), solved from the full fit.

At a fixed geometry the least-squares objective of the withheld data, f_−b(θ) = (SSE_−b(θ) + prior)/2
[N²], is quadratic in the moduli θ [MPa] (docs/physics.md §4.3) and the constraints (bounds, Drucker
rows C·θ ≥ 0) are linear, so its minimum is found by the active-set steps of :mod:`.exact` started at the
full fit θ̂ instead of by IPOPT from the linear screen: from θ̂ the first step is the Newton step

    θ_−b = θ̂ − H_−b⁻¹ g_−b,   H_−b = ∇²f_−b(θ̂) = H − H_b,   g_−b = ∇f_−b(θ̂) = −g_b on the free entries

(the full fit's gradient vanishes on its free entries), on the null space of the constraints active at
θ̂; a step that would cross a bound or a Drucker row stops on it and takes it into the working set, a
negative multiplier drops one, until none is left. The gradient and Hessian are those of the withheld
data's own statistics (the same NLP functions, fed its reduction), so H_−b is exact, not a difference of
Gram matrices. The slack cells are set clipped or live from θ̂ and re-solved while they change side,
as the IPOPT fit does (:func:`.solve.solve_fit`).

Where the objective is not quadratic (a radial bin straddling anchoring, contact increments) the steps
are Newton steps; the result is kept only if the last one was below :data:`.exact.SETTLED`. Otherwise,
and for the ``sum_rmse`` objective, :func:`refit` gives None and the caller solves with IPOPT.
"""

from __future__ import annotations

import numpy as np

from pampipe.identification import exact, problem
from pampipe.identification.fit_setup import Setup, set_up, updater_for
from pampipe.identification.options import FitOptions
from pampipe.identification.solve import UPDATE_ROUNDS
from pampipe.identification.statistics import Memo
from pampipe.specs.experiment import ExperimentData


def refit(data: ExperimentData, options: FitOptions, x_full: np.ndarray, hessian: np.ndarray,
          setup: Setup | None = None):
    """(muscle, {pipe: muscle}) of the least-squares fit to ``data`` (a block withheld, the geometry as
    stated: a calibrated one is held by the caller) from the full fit's ``x_full`` (``hessian``: H of the
    full fit there), or None where the active-set solve does not apply, did not converge or its minimum
    is not unique along a direction the full data see (module docstring). ``setup``: the fit's set-up of
    ``data`` (:func:`.fit_setup.set_up`, no hinge, no start) if the caller made it (for IPOPT where this gives
    None); it is left as it was (the steps change a copy of its parameter values)."""
    setup = setup or set_up(data, options, lambda _text: None, {}, None, Memo())
    if not exact.applies(setup.structure) or x_full.size != setup.x0.size:
        return None
    values = {key: np.array(value, copy=True) for key, value in setup.values.items()}
    update = updater_for(values, data, options, setup)
    x, seen = np.clip(x_full, setup.lbx, setup.ubx), set()
    update(x, seen)  # the slack cells' sides at the full fit
    for _ in range(UPDATE_ROUNDS):
        x = exact.resolved(setup.nlp, values, x, setup.lbx, setup.ubx, hessian)
        if x is None:
            return None
        if not update(x, seen):
            moduli, pipe_moduli, _ = problem.moduli_of(setup.structure, setup.stats, x)
            return problem.muscles(data.pam.geometry, moduli, pipe_moduli)
    return None
