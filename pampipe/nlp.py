"""The one NLP toolkit: IPOPT defaults, the solve call, status → :class:`SolverError`, solver statistics.

Every optimisation in pampipe (identify, diagnose's refits, plan ``--solver ipopt``, the optimal
gait) builds its solver with :func:`nlpsol` and calls it through :func:`solve`, so options are
written in one syntax, defaults once, failures become the same exception, and every result
carries the same :class:`SolverStats` record.
"""

from __future__ import annotations

import re
import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from functools import cache

import casadi as ca

from pampipe import interrupts
from pampipe.errors import SolverError

#: IPOPT options every pampipe NLP starts from (quiet; bounds are not relaxed, so a solution
#: never leaves the physical box it was given).
IPOPT_DEFAULTS = {"print_level": 0, "sb": "yes", "bound_relax_factor": 0.0, "mu_strategy": "adaptive"}

#: IPOPT return statuses, in words (the ones a user can meet).
IPOPT_STATUS = {
    "Maximum_Iterations_Exceeded": "the iteration limit was reached before convergence",
    "Maximum_CpuTime_Exceeded": "the time limit was reached before convergence",
    "Infeasible_Problem_Detected": "the constraints cannot all be met",
    "Restoration_Failed": "IPOPT could not find a feasible point (restoration failed)",
    "Error_In_Step_Computation": "IPOPT could not compute a step (badly scaled or degenerate problem)",
    "Invalid_Number_Detected": "the model returned NaN or infinity during the solve",
    "Search_Direction_Becomes_Too_Small": "IPOPT's steps became too small to make progress",
    "Diverging_Iterates": "the iterates diverged",
    "User_Requested_Stop": "the solve was interrupted",
    "Solved_To_Acceptable_Level": "converged only to IPOPT's acceptable tolerance",
}


@dataclass(frozen=True)
class SolverStats:
    """What one solve did (as cvxpy's ``SolverStats``): status, iterations, time and versions."""

    solver: str
    status: str
    success: bool
    iterations: int
    wall_time: float  # [s] of the solve call
    casadi_version: str
    ipopt_version: str

    def as_document(self) -> dict:
        doc = asdict(self)
        doc["wall_time_s"] = doc.pop("wall_time")
        return doc


def nlpsol(name: str, problem: dict, *, ipopt: dict | None = None, **options) -> ca.Function:
    """An IPOPT solver for ``problem`` ({x, p, f, g}) with the defaults, ``ipopt`` overrides and
    CasADi ``options`` (e.g. ``hess_lag``)."""
    return ca.nlpsol(name, "ipopt", problem,
                     {"print_time": False, **options, "ipopt": {**IPOPT_DEFAULTS, **(ipopt or {})}})


def solve(solver: ca.Function, *, what: str, accept_acceptable: bool = False,
          hints: Mapping[str, str] | None = None, **arguments) -> tuple[dict, SolverStats]:
    """Call ``solver(**arguments)``; raise :class:`SolverError` naming ``what`` unless it converged.

    ``accept_acceptable`` also accepts IPOPT's "Solved_To_Acceptable_Level"; ``hints`` replace the
    generic words of :data:`IPOPT_STATUS` for this problem. An interrupt (Ctrl-C or SIGTERM during
    the solve) raises KeyboardInterrupt.
    """
    started = time.perf_counter()
    solution = solver(**arguments)
    wall = time.perf_counter() - started
    raw = solver.stats()
    interrupts.check(raw)  # a signal during the solve, whatever status IPOPT then reports
    status = str(raw.get("return_status", "unknown"))
    acceptable = accept_acceptable and status == "Solved_To_Acceptable_Level"
    success = bool(raw.get("success", False)) or acceptable
    stats = SolverStats("ipopt", status, success, int(raw.get("iter_count", -1)), wall, ca.__version__,
                        ipopt_version())
    if not success:
        words = {**IPOPT_STATUS, **(hints or {})}.get(status, "IPOPT did not converge")
        raise SolverError(f"{what} failed: {words} (IPOPT status {status}).", status=status)
    return solution, stats


@cache
def ipopt_version() -> str:
    """The IPOPT version CasADi was built with (from its build features), or "unknown"."""
    found = re.search(r"BUILD_IPOPT_VERSION=([\w.]+)", ca.CasadiMeta.feature_list())
    return found.group(1) if found else "unknown"
