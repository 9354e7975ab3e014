"""The time-optimal gait: a multi-phase optimal-control problem in CasADi (IPOPT), built once.

Phases: the six transitions into steps II…VII in their order (roles in :mod:`.schedule`), each with
a free duration T_k and ``intervals`` piecewise-constant valve commands u_i ∈ [−1, 1] (the sign is
fixed by the role: rise/prefill fill, fall vents, hold/off keep the valve closed).

* Dynamics: multiple shooting on the pressures, RK4 with ``substeps`` per interval of
  ṗ = n·R·T·ṁ(p, u)/(V + n·p·V′) (:mod:`.pneumatics`).
* No slip: at every node of phase k, each holder satisfies μπF_r(P, D_p, κW) ≥ SF·W, written as
  μπA(F_ax(P, L_p) − κW + ΔF_contact) − SF·W ≥ 0 (equal to the clipped model wherever it holds);
  the rising segment satisfies it at the end of its phase, before any other segment may let go.
  The condition is imposed at P − 200 Pa (``HOLD_BACKOFF``), so that the exact re-simulation of the
  controls also holds despite the RK4 error (tens of Pa where a fill crosses the wall contact).
* A falling segment is deflated (P ≤ vented_pressure) at the end of its phase; a pre-filling one
  stays ``contact_margin`` below its contact pressure; the middle segment stays deflated while the
  two end segments may both touch the wall (so the stride L₀ − L(D_p) is kept).
* 0 ≤ P ≤ supply; the cycle is periodic; the objective is the cycle time Σ T_k.
* A falling segment vents at full opening (venting faster can only help), so its command is fixed.

IPOPT runs with a limited-memory Hessian on an MX graph of mapped SX functions: building takes
well under a second and a warm re-solve under a tenth (benchmarks/bench_gait.py).

Everything that depends on the mission (geometry, moduli, pipe, loads, valve, gas) enters as the
NLP parameter vector, so the problem is built once per structure (walls, moduli degrees, grid) and
re-solved warm-started from the previous solution.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cache, cached_property

import casadi as ca
import numpy as np

from pampipe.locomotion.requirements import MuscleNeed
from pampipe.locomotion.schedule import PHASES, ControlPlan
from pampipe.model.muscle import Muscle, Structure
from pampipe.pneumatics.options import GaitOptions, Gas, Valve
from pampipe.pneumatics.timing import CHAMBER_SIZE, Chamber, pressure_rate
from pampipe.runtime.ipopt import nlpsol, solve

SCALE = 1e5  # pressure scaling [Pa]: the states are P / 1e5
HOLD_BACKOFF = 200.0  # [Pa] holders satisfy no slip at P − 200 Pa: covers the RK4 error (tens of Pa)
GLOBALS = 8  # supply, p_atm, T, n, C, b, vented, contact margin


#: Per-segment parameters ahead of the muscle's own: the chamber (V_p, V₀, P_a, shape) and
#: D_p, W, κ, μ, SF and the hold scale 1/max(SF·W, 1 N).
_NEED = CHAMBER_SIZE + 6


def _muscle_parameter_size(structure: Structure) -> int:
    return _NEED + structure.size


def _muscle_parameters(need: MuscleNeed) -> np.ndarray:
    hold = [need.pipe_diameter, need.load, need.kappa, need.friction, need.safety_factor,
            1.0 / max(need.safety_factor * need.load, 1.0)]
    return np.concatenate([need.chamber.as_vector(), hold, need.muscle.parameter_vector()])


def _global_parameters(supply: float, options: GaitOptions) -> np.ndarray:
    v, g = options.valve, options.gas
    return np.array([supply, g.atmospheric_pressure, g.temperature, g.polytropic_index,
                     v.sonic_conductance, v.critical_pressure_ratio,
                     options.vented_pressure, options.contact_margin])


@cache
def _holding_function(structure: Structure) -> ca.Function:
    """excess(P, segment parameters) = (μπF_r(P, D_p, κW) − SF·W)/max(SF·W, 1 N), ≥ 0: no slip.

    F_r is the symbolic :class:`Muscle`'s radial force without the contact clip (smooth; equal to
    the clipped model wherever it holds).
    """
    pressure = ca.SX.sym("pressure")
    need = ca.SX.sym("need", _NEED)
    sym = Muscle.symbolic(structure)
    diameter, load, kappa, friction, safety_factor, hold_scale = (need[_NEED - 6 + j] for j in range(6))
    radial = sym.muscle.radial_force(pressure, diameter, kappa * load, clip=False)
    excess = (friction * np.pi * radial - safety_factor * load) * hold_scale
    return ca.Function("holding_excess", [pressure, ca.vertcat(need, sym.p)], [excess])


def _rk4_step(substeps: int, subsonic_index: float):
    """One control interval: x⁺ = RK4^M(x, u, h) for one chamber, scaled states, u ∈ [0, 1]."""
    x, u, h = ca.SX.sym("x"), ca.SX.sym("u"), ca.SX.sym("h")
    chamber_p = ca.SX.sym("chamber", CHAMBER_SIZE)
    gp = ca.SX.sym("globals", GLOBALS)
    direction = ca.SX.sym("direction")  # +1 fill, −1 vent
    chamber = Chamber.from_vector(chamber_p)
    valve, gas = Valve(gp[4], gp[5], subsonic_index), Gas(gp[2], gp[3], gp[1])

    def f(state):
        pressure = state * SCALE
        command = (ca.fmax(direction, 0) * u, ca.fmax(-direction, 0) * u)
        return pressure_rate(pressure, command, chamber, supply=gp[0], valve=valve, gas=gas) / SCALE

    dt = h / substeps
    state = x
    for _ in range(substeps):
        k1 = f(state)
        k2 = f(state + dt / 2 * k1)
        k3 = f(state + dt / 2 * k2)
        k4 = f(state + dt * k3)
        state = state + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return ca.Function("interval", [x, u, h, direction, chamber_p, gp], [state])


#: IPOPT options of the cold solve, from the sequential schedule.
IPOPT_OPTIONS = {"tol": 1e-8, "max_iter": 500, "bound_relax_factor": 1e-8,
                 "hessian_approximation": "limited-memory", "warm_start_init_point": "yes",
                 "warm_start_bound_push": 1e-6, "warm_start_mult_bound_push": 1e-6}
#: A warm solve starts at a previous optimum with its multipliers: pushing the point, the multipliers and the
#: slacks only 1e-9 off their bounds keeps it there (demo, a new payload: 6 → 4 iterations; the same
#: mission again: 3 → 1). A cold solve from the guess is slower with these (up to twice the iterations).
WARM_IPOPT_OPTIONS = {**IPOPT_OPTIONS, "warm_start_bound_push": 1e-9, "warm_start_mult_bound_push": 1e-9,
                      "warm_start_slack_bound_push": 1e-9}


@dataclass(frozen=True)
class _Problem:
    nlp: dict  # {x, p, f, g}: the MX graph, built once
    solver: ca.Function
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    intervals: int

    @cached_property
    def warm_solver(self) -> ca.Function:
        """The solver of warm starts (:data:`WARM_IPOPT_OPTIONS`), built at the first warm solve."""
        return nlpsol("optimal_gait_warm", self.nlp, ipopt=WARM_IPOPT_OPTIONS)


@dataclass(frozen=True)
class WarmStart:
    """A solution (primal and multipliers) to start the next solve of the same structure from."""

    key: tuple  # (structures, intervals, substeps, subsonic index)
    x: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray


def _layout(intervals: int):
    phases, nodes = len(PHASES), len(PHASES) * intervals + 1
    return phases, nodes, phases + 3 * nodes  # T, X (nodes × 3), then U (intervals total × 3)


@cache
def _problem(structures: tuple[Structure, ...], intervals: int, substeps: int,
             subsonic_index: float) -> _Problem:
    """Build the NLP once for these muscle structures (MX graph of mapped SX functions)."""
    sizes = [_muscle_parameter_size(s) for s in structures]
    p = ca.MX.sym("p", GLOBALS + sum(sizes))
    gp = p[:GLOBALS]
    offsets = np.cumsum([GLOBALS, *sizes])
    muscle_p = [p[offsets[i]:offsets[i + 1]] for i in range(3)]
    phases, nodes, _ = _layout(intervals)
    count = nodes - 1
    durations = ca.MX.sym("T", phases)
    x = ca.MX.sym("X", 3, nodes)
    u = ca.MX.sym("U", 3, count)
    vented, margin, supply = gp[6] / SCALE, gp[7] / SCALE, gp[0] / SCALE
    # structural data: each interval's phase, each segment's role in it
    phase_of = np.repeat(np.arange(phases), intervals)
    roles = [[PHASES[k].roles[i] for k in phase_of] for i in range(3)]
    widths = ca.horzcat(*[durations[k] / intervals for k in phase_of])
    g, lbg, ubg = [], [], []

    def constrain(expr, low, high):
        g.append(ca.vec(expr))
        lbg.append(np.full(expr.numel(), low))
        ubg.append(np.full(expr.numel(), high))

    lbu, ubu = np.zeros((3, count)), np.zeros((3, count))
    for i in range(3):
        for j, role in enumerate(roles[i]):
            low, high = PHASES[phase_of[j]].command_bounds(i)
            ubu[i, j] = max(abs(low), abs(high))
            lbu[i, j] = 1.0 if role == "fall" else 0.0  # venting faster never hurts: full opening
        # valves that move are integrated; closed ones keep the pressure
        moving = [j for j in range(count) if roles[i][j] in ("rise", "fall", "prefill")]
        still = [j for j in range(count) if j not in moving]
        direction = np.array([[-1.0 if roles[i][j] == "fall" else 1.0 for j in moving]])
        step = _rk4_step(substeps, subsonic_index).map(len(moving))
        nxt = step(x[i, moving], u[i, moving], widths[moving], direction,
                   ca.repmat(muscle_p[i][:CHAMBER_SIZE], 1, len(moving)),
                   ca.repmat(gp, 1, len(moving)))
        constrain(x[i, [j + 1 for j in moving]] - nxt, 0, 0)
        constrain(x[i, [j + 1 for j in still]] - x[i, still], 0, 0)
        holds, prefill, deflated = [], [], []
        for k, phase in enumerate(PHASES):
            first, last = k * intervals, (k + 1) * intervals
            role = phase.roles[i]
            if role == "hold":
                holds.extend(range(first, last + 1))
            elif role == "rise":
                holds.append(last)
            elif role == "prefill":
                prefill.extend(range(first, last + 1))
            elif role == "off":
                deflated.extend(range(first, last + 1))
            elif role == "fall":
                deflated.append(last)
        holds = sorted(set(holds))
        hold = _holding_function(structures[i]).map(len(holds))
        constrain(hold(x[i, holds] * SCALE - HOLD_BACKOFF, ca.repmat(muscle_p[i], 1, len(holds))), 0,
                  np.inf)
        anchoring = muscle_p[i][2] / SCALE
        constrain(x[i, sorted(set(prefill))] - (anchoring - margin), -np.inf, 0)
        constrain(x[i, sorted(set(deflated))] - vented, -np.inf, 0)
    constrain(x[:, -1] - x[:, 0], 0, 0)  # periodic cycle
    constrain(ca.vec(x) - supply, -np.inf, 0)  # within the supply
    decision = ca.vertcat(durations, ca.vec(x), ca.vec(u))
    nlp = {"x": decision, "p": p, "f": ca.sum1(durations), "g": ca.vertcat(*g)}
    solver = nlpsol("optimal_gait", nlp, ipopt=IPOPT_OPTIONS)
    lbx = np.concatenate([np.full(phases, 1e-3), np.zeros(3 * nodes), lbu.T.ravel()])
    ubx = np.concatenate([np.full(phases, 1e3), np.full(3 * nodes, np.inf), ubu.T.ravel()])
    return _Problem(nlp, solver, lbx, ubx, np.concatenate(lbg), np.concatenate(ubg), intervals)


def problem_key(needs: tuple[MuscleNeed, ...], options: GaitOptions) -> tuple:
    """What the NLP is built for: the muscles' structures, the grid and the valve's subsonic index."""
    return (tuple(n.muscle.structure for n in needs), options.intervals, options.substeps,
            options.valve.subsonic_index)


def solve_optimal(needs: tuple[MuscleNeed, ...], guess: ControlPlan | None, guess_nodes: np.ndarray | None,
                  *, supply: float, options: GaitOptions, warm_start: WarmStart | None = None
                  ) -> tuple[ControlPlan, dict, WarmStart]:
    """Solve the time-optimal gait from ``warm_start`` (a previous solution of the same structure) if
    given, else from ``guess`` (a plan on the same grid) and its node pressures ``guess_nodes``
    (nodes × 3). Returns the plan, solver facts and the warm start for the next solve.
    """
    key = problem_key(needs, options)
    started = time.perf_counter()
    built = _problem.cache_info().currsize
    problem = _problem(*key)
    build_time = time.perf_counter() - started
    rebuilt = _problem.cache_info().currsize > built
    p = np.concatenate([_global_parameters(supply, options), *(_muscle_parameters(n) for n in needs)])
    phases, nodes, _ = _layout(options.intervals)
    warm = warm_start is not None and warm_start.key == key
    if not warm and guess is None:
        raise ValueError("solve_optimal needs a guess and its node pressures without a matching warm start")
    solver = problem.solver
    if warm:
        rebuilt = rebuilt or "warm_solver" not in problem.__dict__
        solver = problem.warm_solver
        build_time = time.perf_counter() - started
        x0, extra = warm_start.x, {"lam_x0": warm_start.lam_x, "lam_g0": warm_start.lam_g}
    else:
        magnitude = np.abs(guess.commands.reshape(-1, 3))
        x0 = np.concatenate([guess.durations, (guess_nodes / SCALE).ravel(), magnitude.ravel()])
        extra = {}
    sol, stats = solve(solver, what="the time-optimal gait (the sequential schedule is still valid)",
                       x0=x0, p=p, lbx=problem.lbx, ubx=problem.ubx, lbg=problem.lbg, ubg=problem.ubg,
                       **extra)
    z = np.asarray(sol["x"]).ravel()
    after = WarmStart(key, z, np.asarray(sol["lam_x"]).ravel(), np.asarray(sol["lam_g"]).ravel())
    durations = z[:phases]
    states = z[phases:phases + 3 * nodes].reshape(nodes, 3) * SCALE
    magnitude = z[phases + 3 * nodes:].reshape(nodes - 1, 3)
    sign = np.array([[-1.0 if role == "fall" else 1.0 for role in phase.roles] for phase in PHASES])
    commands = magnitude.reshape(phases, options.intervals, 3) * sign[:, None, :]
    info = {"status": stats.status, "iterations": stats.iterations,
            "solve_wall_time_s": stats.wall_time, "build_wall_time_s": build_time if rebuilt else 0.0,
            "warm_start": warm, "intervals_per_phase": options.intervals,
            "rk4_substeps": options.substeps}
    return ControlPlan(durations, commands, states[0]), info, after
