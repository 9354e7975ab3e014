"""The one NLP toolkit: IPOPT defaults, the solve call, status → :class:`SolverError`, solver statistics.

Every optimisation in pampipe (identify, diagnose's refits, plan ``--solver ipopt``, the optimal
gait) builds its solver with :func:`nlpsol` and calls it through :func:`solve`, so options are
written in one syntax, defaults once, failures become the same exception, and every result
carries the same :class:`SolverStats` record.
"""

from __future__ import annotations

import hashlib
import re
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass
from functools import cache

import casadi as ca

from pampipe.errors import SolverError
from pampipe.runtime import interrupts
from pampipe.runtime.cache import CACHE_VARIABLE, cache_root, load, source_digest, store  # noqa: F401 (CACHE_VARIABLE re-exported)

#: IPOPT options every pampipe NLP starts from (quiet; bounds are not relaxed, so a solution
#: never leaves the physical box it was given; a NaN or infinity in a constraint Jacobian or the
#: Hessian at any iterate stops the solve with Invalid_Number_Detected, IPOPT's
#: ``check_derivatives_for_naninf``: CasADi already reports a non-finite derivative as a failed
#: evaluation, this also covers a derivative function that returns one without failing).
IPOPT_DEFAULTS = {"print_level": 0, "sb": "yes", "bound_relax_factor": 0.0, "mu_strategy": "adaptive",
                  "check_derivatives_for_naninf": "yes"}

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
    CasADi ``options`` (e.g. ``hess_lag``). CasADi's per-evaluation "NaN detected" warnings are off: IPOPT
    answers a NaN by cutting its step back, and a solve that cannot go on ends in a status that
    :func:`solve` names (a calibration from a far-off angle printed thousands of such lines)."""
    return ca.nlpsol(name, "ipopt", problem,
                     {"print_time": False, "show_eval_warnings": False, **options,
                      "ipopt": {**IPOPT_DEFAULTS, **(ipopt or {})}})


def solve(solver: ca.Function, *, what: str, accept_acceptable: bool = False,
          hints: Mapping[str, str] | None = None, also_accept: tuple[str, ...] = (),
          **arguments) -> tuple[dict, SolverStats]:
    """Call ``solver(**arguments)``; raise :class:`SolverError` naming ``what`` unless it converged.

    ``accept_acceptable`` also accepts IPOPT's "Solved_To_Acceptable_Level" and ``also_accept`` the
    statuses it names (the caller then checks the point itself); ``hints`` replace the generic words
    of :data:`IPOPT_STATUS` for this problem. An interrupt (Ctrl-C or SIGTERM during the solve)
    raises KeyboardInterrupt.
    """
    started = time.perf_counter()
    solution = solver(**arguments)
    wall = time.perf_counter() - started
    raw = solver.stats()
    interrupts.check(raw)  # a signal during the solve, whatever status IPOPT then reports
    status = str(raw.get("return_status", "unknown"))
    acceptable = accept_acceptable and status == "Solved_To_Acceptable_Level"
    success = bool(raw.get("success", False)) or acceptable or status in also_accept
    stats = SolverStats("ipopt", status, success, int(raw.get("iter_count", -1)), wall, ca.__version__,
                        ipopt_version())
    if not success:
        words = {**IPOPT_STATUS, **(hints or {})}.get(status, "IPOPT did not converge")
        raise SolverError(f"{what} failed: {words} (IPOPT status {status}).", status=status)
    _check_derivatives(solver, solution, arguments, what)
    return solution, stats


def _check_derivatives(solver: ca.Function, solution: dict, arguments: dict, what: str) -> None:
    """A solution where the objective's gradient or the constraints' Jacobian is NaN or infinite is no
    solution (CasADi warns "NaN detected" and IPOPT may still report success): SolverError."""
    for name in ("nlp_grad_f", "nlp_jac_g"):
        try:
            oracle = solver.get_function(name)
        except RuntimeError:  # not built for this problem
            continue
        values = oracle(solution["x"], arguments.get("p", ca.DM()))
        if not all(ca.DM(v).is_regular() for v in values):
            raise SolverError(f"{what} failed: the model's derivatives are NaN or infinite at IPOPT's answer "
                              "(a parameter such as contact_smoothing may be out of scale), so the answer "
                              "cannot be trusted.", status="non_finite_derivatives")


@cache
def ipopt_version() -> str:
    """The IPOPT version CasADi was built with (from its build features), or "unknown"."""
    found = re.search(r"BUILD_IPOPT_VERSION=([\w.]+)", ca.CasadiMeta.feature_list())
    return found.group(1) if found else "unknown"


# --------------------------------------------------------------------------------- on-disk cache
#: The file of a cache entry: the labels, then the functions (CasADi's serialisation).
FUNCTIONS = "functions.casadi"


def cached_functions(name: str, key: str, build: Callable[[], dict[str, ca.Function]]
                     ) -> tuple[dict[str, ca.Function], str]:
    """(functions, "disk" | "built"): ``build()`` once per key, kept across processes on disk.

    The entry's key hashes ``name``, ``key`` (the problem structure), the CasADi version and the
    source of the package, so any change to the code that builds the functions makes a new entry.
    CasADi's serialisation stores them in one file, their labels first, so that the graph they share is
    read once (identify's five functions load in 63 ms instead of 86 ms from five files). The file is
    deserialised only after the cache has checked its owner, permissions, length and SHA-256
    (:func:`pampipe.runtime.cache.load`): CasADi trusts what it reads, and a damaged file could crash it.
    A damaged entry is built again and replaced; an unreadable or unwritable cache is skipped.
    """
    root = cache_root()
    if root is None:
        return build(), "built"
    digest = hashlib.sha256("\0".join([name, key, ca.__version__, source_digest()]).encode()).hexdigest()
    files = load(root, name, digest)
    if files is not None and FUNCTIONS in files:
        try:
            stream = ca.StringDeserializer(files[FUNCTIONS].decode("ascii"))
            labels = stream.unpack()
            return {label: stream.unpack() for label in labels}, "disk"
        except Exception:  # checked, so not damaged: of a CasADi that reads it otherwise; built again
            pass
    functions = build()
    stream = ca.StringSerializer()
    stream.pack(list(functions))
    for function in functions.values():
        stream.pack(function)
    store(root, name, digest, {FUNCTIONS: stream.encode().encode("ascii")})
    return functions, "built"
