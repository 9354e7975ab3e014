"""Frozen results of `pampipe gait` and their JSON document (docs/commands.md §5.2)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pampipe.locomotion.replay import Trajectory, simulate
from pampipe.locomotion.requirements import MuscleNeed
from pampipe.locomotion.schedule import (
    ANCHORS,
    PHASES,
    POSITION_KEYS,
    STEPS,
    ControlPlan,
    lengths,
    positions,
    valve_action,
)
from pampipe.pneumatics.options import GaitOptions
from pampipe.results import notebook


@dataclass(frozen=True)
class StepState:
    """The state at the end of one step of the cycle (SI)."""

    step: str
    action: str
    anchored: tuple[str, ...]
    duration: float  # [s] of the transition into this step (0 for the reference step I)
    pressures: dict[str, float]  # [Pa] gauge
    lengths: dict[str, float]  # [m]
    positions: dict[str, float]  # [m], rear at 0 at the start of the cycle
    slip_margins: dict[str, float]  # holding capacity / required hold of each anchor (≥ SF)


def _plot():
    from pampipe.views.plots.gait import plot_gait

    return plot_gait


def _text():
    from pampipe.views.gait_text import section_text

    return section_text


@notebook(headline=("section", "kind", "cycle_time_s", "speed_m_per_s"), plot=_plot, text=_text)
@dataclass(frozen=True)
class GaitResult:
    """One simulated gait cycle in one section: steps, timing, speed, and the dense trajectory."""

    section: str
    schedule: str  # "sequential" | "optimal"
    needs: tuple[MuscleNeed, ...] = field(repr=False)
    plan: ControlPlan = field(repr=False)
    trajectory: Trajectory = field(repr=False)
    ends: np.ndarray = field(repr=False)  # (n, 4): rear, joint_12, joint_23, front [m]
    steps: tuple[StepState, ...]
    stride: float  # [m], from the simulated positions
    cycle_time: float  # [s]
    hold_margin: np.ndarray = field(repr=False)  # (n,) best capacity/required hold among anchors
    kinematic_slip: float  # [m] largest mismatch between persisting anchors (0: consistent)
    solver: dict[str, Any] | None = None
    warm_start: Any = field(default=None, repr=False)  # optimal gait: the solution to start the next from

    @property
    def speed(self) -> float:
        """Mean speed [m/s] = stride / cycle time."""
        return self.stride / self.cycle_time

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n.name for n in self.needs)

    def as_document(self) -> dict:
        """The ``gait`` JSON document: docs/commands.md §5.2 keys plus thresholds and checks."""
        doc = {
            "section": self.section, "schedule": self.schedule, "stride_m": self.stride,
            "cycle_time_s": self.cycle_time, "speed_m_per_s": self.speed,
            "safety_factor": self.needs[0].safety_factor,
            "min_hold_margin": float(self.hold_margin.min()),
            "kinematic_slip_m": self.kinematic_slip,
            "phase_durations_s": {s.step: s.duration for s in self.steps[1:]},
            "segments": [{"name": n.name, "contact_pressure_Pa": n.contact_pressure,
                          "no_slip_pressure_Pa": n.required_pressure,
                          "planned_pressure_Pa": n.target_pressure, "required_hold_N": n.load,
                          "anchored_length_m": n.anchored_length, "rest_length_m": n.rest_length}
                         for n in self.needs],
            "steps": [{"step": s.step, "valve_action": s.action, "anchored": list(s.anchored),
                       "duration_s": s.duration, "pressures_Pa": s.pressures, "lengths_m": s.lengths,
                       "positions_m": s.positions, "slip_margins": s.slip_margins}
                      for s in self.steps],
        }
        if self.solver is not None:
            doc["solver"] = self.solver
        return doc


def evaluate(section: str, schedule: str, needs: tuple[MuscleNeed, ...], plan: ControlPlan, *,
             supply: float, options: GaitOptions, samples: int = 10,
             solver: dict | None = None) -> GaitResult:
    """Simulate ``plan`` (``samples`` points per control interval) and collect steps, stride, margins."""
    trajectory = simulate(tuple(n.chamber for n in needs), plan, supply=supply, options=options,
                          samples=samples)
    size = lengths(needs, trajectory.pressures)
    ends, mismatch = positions(needs, trajectory.pressures, size)
    names = [n.name for n in needs]
    ratios = np.stack([needs[i].holding_ratio(trajectory.pressures[:, i]) * needs[i].safety_factor
                       for i in range(3)], axis=1)
    touching = trajectory.pressures >= np.array([n.contact_pressure for n in needs])[None, :]
    hold_margin = np.where(touching, ratios, 0.0).max(axis=1)
    samples_at = [0, *trajectory.boundaries]
    durations = [0.0, *plan.durations]
    steps = []
    for k, index in enumerate(samples_at):
        anchors = ANCHORS[k]
        steps.append(StepState(
            step=STEPS[k],
            action="start (= end of VII)" if k == 0 else valve_action(PHASES[k - 1],
                                                                                          names),
            anchored=tuple(names[i] for i in anchors), duration=float(durations[k]),
            pressures={names[i]: float(trajectory.pressures[index, i]) for i in range(3)},
            lengths={names[i]: float(size[index, i]) for i in range(3)},
            positions={key: float(ends[index, j]) for j, key in enumerate(POSITION_KEYS)},
            slip_margins={names[i]: float(ratios[index, i]) for i in anchors}))
    stride = float(ends[-1, 0] - ends[0, 0])
    return GaitResult(section, schedule, needs, plan, trajectory, ends, tuple(steps), stride,
                      float(np.sum(plan.durations)), hold_margin, mismatch, solver)
