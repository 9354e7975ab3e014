"""The model error's held-out fits solved from the full fit (:mod:`pampipe.identification.held_out`) give what
the IPOPT refits give: each block's held-out RMSE and the model error, on bundled experiments.

The IPOPT refits (``identify(..., refits="ipopt")``) are the reference: one fit of the withheld data from
the linear screen, as every fit. Where the withheld data leave a direction undetermined that the withheld
rows see (the end lengths of the Festo map), the minimum is not unique and the two starts would reach
different moduli (measured: 12.2 N against 14.1 N on one block): such a block must fall back to IPOPT.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from pampipe.identification import exact, held_out, identify
from pampipe.identification import solve as solve_module
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.experiment_schema import load_experiment
from tests.support.problems import PROBLEMS


@pytest.mark.parametrize("name", ["festo-dmsp20-300", "festo-dmsp20-300-slack-zeros", "paper-protocol"])
def test_held_out_fits_from_the_full_fit_match_the_ipopt_refits(name, monkeypatch):
    data = load_experiment_data(load_experiment(PROBLEMS / "experiments" / f"{name}.yaml"))
    solved = []
    original = held_out.refit

    def counted(*args):
        found = original(*args)
        solved.append(found is not None)
        return found

    monkeypatch.setattr("pampipe.identification.fit.refit_from_full", counted)
    fast = identify(data).model_error
    reference = identify(data, refits="ipopt").model_error
    assert any(solved)  # some blocks are solved from the full fit (not all fell back)
    assert [b.rows for b in fast.blocks] == [b.rows for b in reference.blocks]
    for mine, theirs in zip(fast.blocks, reference.blocks, strict=True):
        assert mine.rmse == pytest.approx(theirs.rmse, rel=1e-5, abs=1e-9)
    assert fast.value == pytest.approx(reference.value, rel=1e-5)


def test_undetermined_directions_are_the_flat_ones_off_the_binding_rows():
    hessian = np.diag([2.0, 0.0, 3.0])
    free = exact.undetermined(hessian, np.zeros((0, 3)))
    assert free.shape == (3, 1) and abs(abs(free[1, 0]) - 1.0) < 1e-12
    assert exact.undetermined(hessian, np.array([[0.0, 1.0, 0.0]])).shape == (3, 0)  # held by a row


def test_the_fits_rounds_by_active_set_steps_reach_the_ipopt_rounds_answer(monkeypatch):
    """The re-solves of the full fit and of a held-out refit that falls back to IPOPT (slack cells changing
    side, the slack hinge's next round) by active-set steps from the last IPOPT solution
    (:func:`pampipe.identification.exact.resolved`) give what IPOPT re-solves give: the same SSE, moduli and
    model error, with fewer IPOPT solves and iterations."""
    data = load_experiment_data(load_experiment(PROBLEMS / "experiments" / "paper-protocol.yaml"))
    original, used = exact.resolved, []

    def counted(*args, **kwargs):
        found = original(*args, **kwargs)
        used.append(found is not None)
        return found

    monkeypatch.setattr(exact, "resolved", counted)
    ipopt_solves = []

    def solve(*args, **kwargs):
        ipopt_solves.append(1)
        return original_solve(*args, **kwargs)

    original_solve = solve_module.solve
    monkeypatch.setattr(solve_module, "solve", solve)
    fast = identify(data)
    assert any(used)  # the bundled protocol's slack rows make rounds that the steps finish
    # one IPOPT solve for the full fit, one for the held-out block that falls back to IPOPT (its withheld
    # rows see a direction its data leave flat); every later round of either is active-set steps
    assert len(ipopt_solves) == 2
    ipopt_rounds = SimpleNamespace(applies=exact.applies, resolved=lambda *args, **kwargs: None)
    monkeypatch.setattr("pampipe.identification.solve.exact", ipopt_rounds)  # every round by IPOPT
    reference = identify(data)
    assert len(ipopt_solves) > 2 + 2
    assert fast.solver.iterations < reference.solver.iterations
    assert fast.sse == pytest.approx(reference.sse, rel=1e-9)
    assert np.allclose(fast.x, reference.x, rtol=1e-6, atol=1e-6)
    assert fast.model_error.value == pytest.approx(reference.model_error.value, rel=1e-6)
