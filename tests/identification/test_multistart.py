"""The multi-start of a calibrated fit (pampipe/identification/multistart.py): where every start's solve
fails, the stated geometry's fit is tried as the last start before the fit is given up."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.identification import multistart


def _run(failing: set):
    """A fake ``run(x)``: fails at the braid angles in ``failing``, else ends where it started."""
    calls = []

    def run(x):
        calls.append(float(x[0]))
        if float(x[0]) in failing:
            raise SolverError(f"start {x[0]:g} failed (IPOPT status Error_In_Step_Computation).",
                              status="Error_In_Step_Computation")
        return f"payload {x[0]:g}", 4.0, np.asarray(x, float)

    return run, calls


def test_the_stated_fit_is_the_last_start_where_every_other_failed():
    run, calls = _run({24.0, 30.0})
    fallback = (multistart.FALLBACK, np.array([24.08]), lambda: run(np.array([24.08])))
    report, payload = multistart.search(run, [("screened", np.array([24.0])), ("seed", np.array([30.0]))],
                                        ("braid_angle",), rows=4, fallback=fallback)
    assert payload == "payload 24.08" and calls == [24.0, 30.0, 24.08]
    assert report.failed == ("screened", "seed")
    assert [label for label, _ in report.starts] == ["screened", "seed", multistart.FALLBACK]
    assert report.best.starts == (multistart.FALLBACK,) and report.best.rmse == 1.0  # √(4 N² / 4 rows)
    assert "2 failed" in report.describe()[0]


def test_the_fallback_is_not_run_where_a_start_converged_and_a_failed_fallback_raises_the_first_error():
    run, calls = _run({24.0, 24.08})
    fallback = (multistart.FALLBACK, np.array([24.08]), lambda: run(np.array([24.08])))
    report, _ = multistart.search(run, [("screened", np.array([24.0])), ("seed", np.array([30.0]))],
                                  ("braid_angle",), rows=4, fallback=fallback)
    assert calls == [24.0, 30.0] and len(report.starts) == 2
    run, calls = _run({24.0, 30.0, 24.08})
    fallback = (multistart.FALLBACK, np.array([24.08]), lambda: run(np.array([24.08])))
    with pytest.raises(SolverError, match="start 24 failed"):
        multistart.search(run, [("screened", np.array([24.0])), ("seed", np.array([30.0]))],
                          ("braid_angle",), rows=4, fallback=fallback)
    assert calls == [24.0, 30.0, 24.08]


@pytest.mark.slow
def test_the_coverage_fit_ipopt_could_not_step_from_its_only_start_now_calibrates():
    """Seed 1, trial 13 of benchmarks/bench_coverage.py (axial + radial data of a muscle of known truth):
    its only start (the moduli's bounded least squares, several on their ±50 MPa bounds) ended in IPOPT's
    Error_In_Step_Computation and the fit wrote nothing. From the stated geometry's fit it converges, to a
    braid angle within the stated sd (1°) of the truth's."""
    from benchmarks.bench_coverage import TESTED, drawn_around, fitted, stated_muscle
    from pampipe.simulation.synthetic import Protocol

    stated = stated_muscle(1.0, 1.0)
    truth = drawn_around(stated, stated.geometry_sd, np.random.default_rng([1, 1000, 1000, 13]))
    protocol = Protocol(pipes=(TESTED * stated.geometry.initial_diameter,), loads=(0.0,), cycles=1)
    pam = fitted(stated, truth, protocol, 1013, ("braid_angle",))
    assert abs(math.degrees(pam.geometry.braid_angle - truth.geometry.braid_angle)) < 1.0
    assert pam.uncertainty is not None and pam.uncertainty.model_error_dof == 3
