"""A solve whose derivatives are NaN or infinite at its answer is a failed solve (issue 27).

Before: CasADi printed "NaN detected", IPOPT reported Solve_Succeeded and identify exited 0.
"""

from __future__ import annotations

import casadi as ca
import pytest

from pampipe import nlp
from pampipe.errors import SolverError


def _solver(objective):
    x = ca.SX.sym("x")
    return nlp.nlpsol("toy", {"x": x, "f": objective(x)})


def test_finite_derivatives_pass():
    solution, stats = nlp.solve(_solver(lambda x: (x - 2) ** 2), what="toy", x0=0.0)
    assert float(solution["x"]) == pytest.approx(2.0) and stats.success


def test_infinite_gradient_at_the_answer_fails():
    """f = (x − 2)² + 1e-12·√|x − 2|: the minimum is at x = 2, where the gradient is infinite."""
    solver = _solver(lambda x: (x - 2) ** 2 + 1e-12 * ca.sqrt(ca.fabs(x - 2)))
    with pytest.raises(SolverError) as error:
        nlp._check_derivatives(solver, {"x": ca.DM(2.0)}, {}, "toy")
    assert error.value.status == "non_finite_derivatives"
    nlp._check_derivatives(solver, {"x": ca.DM(1.0)}, {}, "toy")  # finite elsewhere: no error
