"""The model's forces for recorded test rows, and fit quality per test and pressure level.

Used by ``identify`` for its report and by anything that needs residuals (``diagnose``): the
exact, unsmoothed model of docs/physics.md §4.3 (axial tests) and §5.3 (radial tests, contact switch and
contact increments included).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.model.pam import Moduli, Pam
from pampipe.specs.experiment import ExperimentData, TestData

#: Rows evaluated at a time (the model's temporaries stay a few MB whatever the row count).
CHUNK = 1 << 16


@dataclass(frozen=True)
class LevelFit:
    pressure: float  # level pressure [Pa]
    points: int
    rmse: float  # [N]


@dataclass(frozen=True)
class TestFit:
    """Fit quality of one test, from the exact (unsmoothed) model on every row it was fitted to.

    ``levels`` is empty when the test has no pressure levels (a ramp); ``slack`` counts its rows
    with force ≤ 0 (fitted as max(0, F) or excluded, see ``excluded``).
    """

    name: str
    kind: str
    points: int
    rmse: float  # [N]
    levels: tuple[LevelFit, ...]
    moduli_block: str  # which fitted moduli the test used (theta, pipe<k>)
    protocol: str = "isobaric"
    slack: int = 0
    excluded: int = 0


def predict(pam: Pam, test: TestData) -> np.ndarray:
    """Model force [N] at every row of ``test``: F_ax(P, L) (axial) or F_r(P; D_p, F_a) (radial)."""
    muscle = Muscle.from_pam(pam)
    out = np.empty(test.points)
    pressure_leg = np.zeros(test.points) if test.pressure_leg is None else test.pressure_leg
    for start in range(0, test.points, CHUNK):
        rows = slice(start, start + CHUNK)
        if test.kind == "axial":
            force = muscle.axial_force(test.pressure[rows], test.length[rows], leg=test.leg[rows],
                                       pressure_leg=pressure_leg[rows])
        else:
            force = muscle.radial_force(test.pressure[rows], test.spec.pipe_diameter, test.spec.axial_load)
        out[rows] = force
    return out


def residuals(pam: Pam, test: TestData) -> np.ndarray:
    """Model minus measured force [N], row by row."""
    return predict(pam, test) - test.force


def test_fit(pam: Pam, test: TestData, *, block: str = "theta", slack: str = "unilateral",
             model: np.ndarray | None = None) -> tuple[TestFit, float, np.ndarray, np.ndarray]:
    """(fit quality of one test, its sum of squared residuals [N²], the model force of every row [N]
    as scored, and before the hinge).

    An axial test's rows are predicted as max(0, F): a muscle cannot push (the slack hinge,
    docs/physics.md §6.2); its slack rows (force ≤ 0) are scored so (``unilateral``) or left out
    (``exclude``). The per-level table is kept only for tests with pressure levels. ``model``: the
    model force of every row before the hinge (:func:`predict`), if already evaluated.
    """
    unclipped = model = predict(pam, test) if model is None else model
    used = np.ones(test.points, dtype=bool)
    slack_rows = test.slack if test.kind == "axial" else np.zeros(test.points, dtype=bool)
    if test.kind == "axial":
        model = np.maximum(model, 0.0)
    if slack == "exclude":
        used = ~slack_rows
    squared = np.where(used, model - test.force, 0.0) ** 2
    n_used = int(used.sum())
    levels = []
    if test.has_levels:
        count = np.bincount(test.level, weights=used, minlength=test.level_pressure.size)
        sums = np.bincount(test.level, weights=squared, minlength=test.level_pressure.size)
        levels = [LevelFit(float(pressure), int(count[lev]), float(np.sqrt(sums[lev] / count[lev])))
                  for lev, pressure in enumerate(test.level_pressure) if count[lev]]
    total = float(squared.sum())
    fit = TestFit(test.name, test.kind, n_used, float(np.sqrt(total / max(n_used, 1))), tuple(levels), block,
                  test.protocol, int(slack_rows.sum()), test.points - n_used)
    return fit, total, model, unclipped


def evaluate_tests(data: ExperimentData, geometry, moduli: Moduli, pipe_moduli: dict[float, Moduli],
                   blocks: dict, *, slack: str = "unilateral", evaluated: dict[int, np.ndarray] | None = None
                   ) -> tuple[tuple[TestFit, ...], float, float | None, dict[str, np.ndarray],
                              dict[str, np.ndarray]]:
    """(per-test fits, Σ squared residuals [N²], Σ over (test, level) of RMSE [N] or None when some
    test has no pressure levels, {test name: model force of every row as scored [N]}, the same
    before the hinge max(0, F) of the axial tests). ``evaluated``: test index → the model force of
    every row before the hinge (:func:`predict`) of the tests already evaluated."""
    names = {id(m): name for name, m in blocks.items()}
    fits, sse, models, unclipped = [], 0.0, {}, {}
    for index, test in enumerate(data.tests):
        used = moduli if test.kind == "axial" else pipe_moduli.get(test.spec.pipe_diameter, moduli)
        fit, total, models[test.name], unclipped[test.name] = test_fit(
            Pam(data.pam.name, geometry, used), test, block=names.get(id(used), "theta"), slack=slack,
            model=(evaluated or {}).get(index))
        fits.append(fit)
        sse += total
    sum_rmse = float(sum(level.rmse for fit in fits for level in fit.levels)) \
        if all(t.has_levels for t in data.tests) else None
    return tuple(fits), sse, sum_rmse, models, unclipped
