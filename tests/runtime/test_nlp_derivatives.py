"""A solve whose derivatives are NaN or infinite at its answer, or at any iterate on the way, is a failed
solve (issue 27).

Before: CasADi printed "NaN detected", IPOPT reported Solve_Succeeded and identify exited 0.
"""

from __future__ import annotations

import casadi as ca
import pytest

from pampipe.errors import SolverError
from pampipe.runtime import ipopt


def _solver(objective):
    x = ca.SX.sym("x")
    return ipopt.nlpsol("toy", {"x": x, "f": objective(x)})


def test_finite_derivatives_pass():
    solution, stats = ipopt.solve(_solver(lambda x: (x - 2) ** 2), what="toy", x0=0.0)
    assert float(solution["x"]) == pytest.approx(2.0) and stats.success


def test_infinite_gradient_at_the_answer_fails():
    """f = (x − 2)² + 1e-12·√|x − 2|: the minimum is at x = 2, where the gradient is infinite."""
    solver = _solver(lambda x: (x - 2) ** 2 + 1e-12 * ca.sqrt(ca.fabs(x - 2)))
    with pytest.raises(SolverError) as error:
        ipopt._check_derivatives(solver, {"x": ca.DM(2.0)}, {}, "toy")
    assert error.value.status == "non_finite_derivatives"
    ipopt._check_derivatives(solver, {"x": ca.DM(1.0)}, {}, "toy")  # finite elsewhere: no error


def _region_problem(power, where):
    """f = (x − 5)⁴ (+ the term in g): the term p·u^power, u = max((x − 2)(x − 3), 0), p = 0, is 0 everywhere,
    but its derivative (power ½: the gradient; power 1.5: the Hessian) is NaN (∞·0) for x in [2, 3] only.
    From x₀ = 0, Newton's steps on the quartic pass that interval (0 → 1.67 → 2.78 → ...) on their way to
    the answer x = 5, where every derivative is finite."""
    x, p = ca.SX.sym("x"), ca.SX.sym("p")
    term = p * ca.fmax((x - 2) * (x - 3), 0) ** power
    problem = {"x": x, "p": p, "f": (x - 5) ** 4 + (term if where == "f" else 0)}
    if where == "g":
        problem["g"] = x + term
    return ipopt.nlpsol("toy", problem), x, p, term


@pytest.mark.parametrize(("power", "where"), [(0.5, "f"), (0.5, "g"), (1.5, "f"), (1.5, "g")])
def test_nan_derivatives_at_an_iterate_fail_the_solve(power, where):
    solver, x, p, term = _region_problem(power, where)
    derivatives = ca.Function("d", [x, p], [ca.jacobian(term, x), ca.hessian(term, x)[0]])
    for finite in (0.0, 5.0):  # neither the start nor the answer shows it
        assert all(ca.DM(v).is_regular() for v in derivatives(finite, 0.0))
    assert not all(ca.DM(v).is_regular() for v in derivatives(2.5, 0.0))
    bounds = {"lbg": -10.0, "ubg": 10.0} if where == "g" else {}
    with pytest.raises(SolverError) as error:
        ipopt.solve(solver, what="toy", x0=0.0, p=0.0, **bounds)
    assert error.value.status == "Invalid_Number_Detected"
    assert "toy failed" in str(error.value)


def test_the_same_problem_without_the_nan_region_solves():
    """The control: the term moved to [20, 21], which the iterates never reach, leaves a plain solve."""
    x, p = ca.SX.sym("x"), ca.SX.sym("p")
    solver = ipopt.nlpsol("toy", {"x": x, "p": p,
                                "f": (x - 5) ** 4 + p * ca.sqrt(ca.fmax((x - 20) * (x - 21), 0))})
    solution, stats = ipopt.solve(solver, what="toy", x0=0.0, p=0.0)
    assert stats.success and float(solution["x"]) == pytest.approx(5.0, abs=1e-2)


def test_ipopt_checks_derivatives_for_nan_and_inf():
    assert ipopt.IPOPT_DEFAULTS["check_derivatives_for_naninf"] == "yes"


def test_nan_evaluations_on_the_way_print_no_casadi_warnings(capfd):
    """√x from x₀ = −1: every evaluation there is NaN; the solve fails by its status, named, without CasADi's
    per-evaluation "NaN detected" lines (a far-off calibration printed thousands)."""
    with pytest.raises(SolverError):
        ipopt.solve(_solver(lambda x: ca.sqrt(x) + (x - 2) ** 2), what="toy", x0=-1.0)
    printed = capfd.readouterr()
    assert "NaN detected" not in printed.out + printed.err
