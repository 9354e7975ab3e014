"""The 7-step peristaltic gait (docs/physics.md §8): its phases, their simulation and the worm's positions.

Segments are indexed 0, 1, 2 = PAM1 (rear), PAM2, PAM3 (front). A gait is a :class:`ControlPlan`:
six phases (the transitions into steps II…VII; step I is the state a cycle starts from), each
with a duration and piecewise-constant valve commands u_i ∈ [−1, 1] (u > 0 fills from the supply,
u < 0 vents). In each phase every segment has one role:

* ``hold``: anchored in the step before and after: valve closed, must not slip;
* ``rise``: becomes an anchor: fills, and must hold (no slip) at the end of the phase;
* ``fall``: stops being an anchor (the holders hold it): vents, deflated at the end of the phase;
* ``prefill``: an idle end segment: may fill, but stays ``contact_margin`` below the wall contact;
* ``off``: the idle middle segment: valve closed (deflated, rigid at L₀, between two anchors).

Positions come from the pressures alone: a segment touching the wall (P ≥ P_a) keeps both ends
fixed (no slip), a free one has its free-contraction length L_free(P) (docs/physics.md §7), and the
chain rear–PAM1–PAM2–PAM3–front is rebuilt from an anchor that persists between two samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.errors import SolverError
from pampipe.locomotion.requirements import MuscleNeed
from pampipe.pneumatics.options import GaitOptions
from pampipe.pneumatics.timing import free_length_curve, transition_time

STEPS = ("I", "II", "III", "IV", "V", "VI", "VII")
#: anchored segments in each step (docs/physics.md §8, paper Fig. 18)
ANCHORS = ((1,), (0, 1), (0,), (0, 2), (2,), (1, 2), (1,))
POSITION_KEYS = ("rear", "joint_12", "joint_23", "front")
MIDDLE = 1


@dataclass(frozen=True)
class Phase:
    """The transition into ``step``: the role of each segment (see the module docstring)."""

    step: str
    roles: tuple[str, str, str]

    def members(self, role: str) -> tuple[int, ...]:
        return tuple(i for i, r in enumerate(self.roles) if r == role)

    @property
    def anchors(self) -> tuple[int, ...]:
        """Segments anchored at the end of the phase (the step's anchors)."""
        return ANCHORS[STEPS.index(self.step)]

    def command_bounds(self, segment: int) -> tuple[float, float]:
        """Allowed valve command of ``segment`` in this phase."""
        return {"rise": (0.0, 1.0), "prefill": (0.0, 1.0), "fall": (-1.0, 0.0)}.get(
            self.roles[segment], (0.0, 0.0))


def _phases() -> tuple[Phase, ...]:
    phases = []
    for k in range(1, len(STEPS)):
        before, after = set(ANCHORS[k - 1]), set(ANCHORS[k])
        roles = []
        for i in range(3):
            if i in before and i in after:
                roles.append("hold")
            elif i in after:
                roles.append("rise")
            elif i in before:
                roles.append("fall")
            else:
                roles.append("off" if i == MIDDLE else "prefill")
        phases.append(Phase(STEPS[k], tuple(roles)))
    return tuple(phases)


PHASES = _phases()


def valve_action(phase: Phase, names) -> str:
    """Plain words for what the valves do in ``phase``."""
    words = [f"inflate {names[i]}" for i in phase.members("rise")]
    words += [f"vent {names[i]}" for i in phase.members("fall")]
    return ", ".join(words)


@dataclass(frozen=True)
class ControlPlan:
    """A gait as controls: phase durations [s], commands[phase, interval, segment], start pressures."""

    durations: np.ndarray  # (6,)
    commands: np.ndarray  # (6, intervals, 3), in [−1, 1]
    start: np.ndarray  # (3,) gauge pressures [Pa] at the start of step II's transition


def lengths(needs: tuple[MuscleNeed, ...], pressures: np.ndarray) -> np.ndarray:
    """Segment lengths [m], (n, 3): L(D_p) once touching the wall, L_free(P) below.

    L_free is evaluated once per distinct pressure below contact (a closed valve repeats it), by the
    muscle's checked interpolant on [0, P_a] (:func:`free_length_on`) where it has one.
    """
    out = np.empty_like(pressures, dtype=float)
    for i, need in enumerate(needs):
        column = np.maximum(pressures[:, i], 0.0)
        free = column < need.contact_pressure
        distinct, where = np.unique(column[free], return_inverse=True)
        out[:, i] = need.anchored_length
        if distinct.size:
            curve = free_length_on(need.muscle, need.contact_pressure)
            free_length = need.muscle.free_length(distinct) if curve is None else curve(distinct)
            out[free, i] = np.maximum(free_length[where], need.anchored_length)
    return out


def free_length_on(muscle, contact: float):
    """L_free(P) on [0, P_a] as :func:`~pampipe.pneumatics.timing.free_length_curve` (None where no
    interpolant is within its tolerance, e.g. a muscle that stays at L₀ up to some pressure), once per
    muscle content (structure, parameter vector) and P_a [Pa]: a gait evaluates the same muscles again."""
    key = (muscle.structure, muscle.parameter_vector().tobytes(), contact)
    if key not in _CURVES:
        _CURVES[key] = free_length_curve(muscle, 0.0, contact) if contact > 0 else None
        if len(_CURVES) > 64:
            _CURVES.pop(next(iter(_CURVES)))  # the oldest goes
    return _CURVES[key]


#: (structure, parameter bytes, P_a) → interpolant of L_free(P) on [0, P_a] or None, oldest first.
_CURVES: dict = {}


def positions(needs: tuple[MuscleNeed, ...], pressures: np.ndarray,
              size: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Rear, joints and front [m], (n, 4), with the rear at 0 at the first sample, and the largest
    mismatch [m] between two anchors that persist over one sample (0 when nothing slips).

    ``size`` are the :func:`lengths` when already known. An anchor i that persists from sample k − 1
    to k keeps its rear end, so the worm's rear moves by o_{k−1,i} − o_{k,i} (o: the summed
    lengths of the segments behind i); the first persisting anchor carries the worm, and the
    spread of that move over all persisting anchors is the mismatch.
    """
    size = lengths(needs, pressures) if size is None else size
    touching = pressures >= np.array([n.contact_pressure for n in needs])[None, :]
    offsets = np.concatenate([np.zeros((len(pressures), 1)), np.cumsum(size, axis=1)], axis=1)
    persisting = touching[1:] & touching[:-1]
    held = persisting.any(axis=1)
    if not held.all():
        k = int(np.argmin(held)) + 1
        raise SolverError(f"no segment holds the wall at t-sample {k}: the gait lets go", status="no_anchor")
    move = offsets[:-1, :3] - offsets[1:, :3]  # (n − 1, 3): the rear's move if anchor i carries it
    carrier = np.argmax(persisting, axis=1)
    rear = np.concatenate([[0.0], np.cumsum(move[np.arange(len(move)), carrier])])
    spread = np.where(persisting, move, -np.inf).max(axis=1) - np.where(persisting, move, np.inf).min(axis=1)
    mismatch = float(spread.max()) if spread.size else 0.0
    return rear[:, None] + offsets, mismatch


def sequential_plan(needs: tuple[MuscleNeed, ...], *, supply: float, options: GaitOptions) -> ControlPlan:
    """One thing at a time, valves fully open: fill each new anchor to its planned pressure, then
    vent the released one below ``vented_pressure`` (docs/physics.md §8: T_cycle = Σ of the six steps).
    """
    off = options.vented_pressure
    level = np.array([off, needs[MIDDLE].target_pressure, off])
    start = level.copy()
    durations, commands = [], np.zeros((len(PHASES), 1, 3))
    for k, phase in enumerate(PHASES):
        duration = 0.0
        for i in phase.members("rise") + phase.members("fall"):
            goal = needs[i].target_pressure if phase.roles[i] == "rise" else off
            duration = max(duration, transition_time(needs[i].chamber, level[i], goal, supply=supply,
                                                     valve=options.valve, gas=options.gas))
            commands[k, 0, i] = 1.0 if phase.roles[i] == "rise" else -1.0
            level[i] = goal
        durations.append(duration)
    return ControlPlan(np.array(durations), commands, start)
