"""Frozen results of `design` and their JSON document (docs/commands.md §8). SI inside."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pampipe.design.evaluate import PipeTable, designed_pam
from pampipe.design.groups import segment_loads
from pampipe.design.multistart import MultiStart
from pampipe.design.single import SizeDesign
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.results import notebook
from pampipe.specs.inventory import Inventory


def _finite(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


@dataclass(frozen=True)
class SizeResult:
    """One designed muscle, its table on every pipe of the inventory and the pipes assigned to it."""

    pam: Pam
    design: SizeDesign
    table: PipeTable
    assigned: np.ndarray  # (pipes,) bool
    objective: float  # over its assigned pipes (unit of the inventory's objective)

    def geometry_document(self) -> dict:
        g = self.pam.geometry
        return {"name": self.pam.name, "initial_length_m": g.initial_length,
                "initial_diameter_m": g.initial_diameter,
                "braid_angle_from_axis_deg": math.degrees(g.braid_angle),
                "braid_angle_from_transverse_deg": 90 - math.degrees(g.braid_angle),
                "bladder_thickness_m": g.bladder_thickness, "wall": g.wall,
                "largest_diameter_m": g.largest_diameter}


def starts_document(run: MultiStart) -> dict:
    """How the multi-start went: totals, the best start and every start's outcome."""
    best = run.best
    return {"total": len(run.results), "succeeded": sum(r.success for r in run.results),
            "reached_best": run.reached, "best_index": None if best is None else best.index,
            "runs": [{"index": r.index, "status": r.status,
                      "objective": _finite(run.problem.physical(r.objective)),
                      "iterations": r.iterations, "wall_time_s": r.wall_time} for r in run.results]}


def _plot():
    from pampipe.views.plots.design import plot_design

    return plot_design


def _text():
    from pampipe.views.design_text import report

    return report


@notebook(headline=("feasible", "objective", "binding"), plot=_plot, text=_text)
@dataclass(frozen=True)
class DesignResult:
    """The design of an inventory: one or K muscles, or the binding constraint where none exists.

    ``sizes`` are ordered by the pipe length they serve, largest first; ``assignment[j]`` is the
    index of the size serving pipe j (-1: unserved). ``material_table`` is the material's own muscle
    in every pipe (None if its PAM has no moduli … it always has: the design needs them).
    """

    inventory: Inventory
    sizes: tuple[SizeResult, ...]
    assignment: np.ndarray
    material_table: PipeTable
    feasible: bool = True
    binding: str | None = None
    reason: str | None = None
    rounds: int = 0
    solves: int = 0  # NLP solves (starts) run, interval checks and refits included
    iterations: int = 0  # IPOPT iterations over all of them
    wall_time: float = 0.0  # [s]
    outputs: tuple[str, ...] = field(default=())  # PAM files written (set by the command)

    @property
    def coverage(self) -> dict:
        pipes = self.inventory.pipes
        served = self.assignment >= 0
        return {"pipes_total": len(pipes), "pipes_served": int(served.sum()),
                "length_total_m": float(pipes.length.sum()),
                "length_served_m": float(pipes.length[served].sum())}

    # ------------------------------------------------------------------------------- curves for plots
    def worst_load(self) -> tuple[float, float]:
        """(W [N], μ) of the pipe and segment with the largest load: the load of the bore curves."""
        loads = segment_loads(self.inventory)
        j = int(np.argmax(loads.max(axis=1)))
        return float(loads[j].max()), float(self.inventory.pipes.friction[j])

    def pressure_curve(self, which: int | None, bores) -> np.ndarray:
        """Least holding pressure [Pa] against bore for size ``which`` (None: the material's muscle),
        at :meth:`worst_load`; inf outside the muscle's reach (docs/physics.md §8)."""
        pam = self.inventory.material if which is None else self.sizes[which].pam
        muscle = Muscle.from_pam(pam)
        g = muscle.geometry
        bores = np.asarray(bores, dtype=float)
        load, friction = self.worst_load()
        inside = (bores > g.initial_diameter) & (bores < g.largest_diameter)
        safe = np.where(inside, bores, 0.5 * (g.initial_diameter + g.largest_diameter))
        with np.errstate(all="ignore"):
            p = muscle.least_holding_pressure(safe, load, kappa=self.inventory.kappa, friction=friction,
                                              safety_factor=self.inventory.safety_factor)
        return np.where(inside, p, np.inf)

    # ------------------------------------------------------------------------------------ document
    def to_dict(self) -> dict:
        """The `design --json` document (the Python API's name for :meth:`as_document`)."""
        return self.as_document()

    def as_document(self) -> dict:
        inv = self.inventory
        doc = {"feasible": self.feasible, "binding_constraint": self.binding, "reason": self.reason,
               "inventory": str(inv.source), "material": inv.material.name, "network": inv.network,
               "objective_kind": inv.space.objective.value, "objective_unit": inv.space.objective.unit,
               "supply_pressure_Pa": inv.supply_pressure, "safety_factor": inv.safety_factor,
               "load_path": inv.load_path, "coverage": self.coverage, "rounds": self.rounds,
               "sizes": [self._size_document(k) for k in range(len(self.sizes))],
               "pipes": self._pipes_document(),
               "solver": {"nlp_solves": self.solves, "iterations": self.iterations,
                          "wall_time_s": self.wall_time}}
        if self.sizes:
            first = doc["sizes"][0]
            doc["design"] = first["design"]
            doc["objective"] = first["objective"]
            doc["starts"] = first["starts"]
        else:
            doc["design"], doc["objective"], doc["starts"] = None, None, None
        return doc

    def _size_document(self, k: int) -> dict:
        s = self.sizes[k]
        pipes = self.inventory.pipes
        mine = s.assigned
        return {"size": k + 1, "design": s.geometry_document(), "objective": _finite(s.objective),
                "largest_pressure_Pa": _finite(float(s.table.largest[mine].max()) if mine.any()
                                               else s.design.largest_pressure),
                "pipes_served": int(mine.sum()), "length_served_m": float(pipes.length[mine].sum()),
                "bores_m": sorted({float(d) for d in pipes.diameter[mine]}),
                "starts": starts_document(s.design.run),
                "pam_file": self.outputs[k] if k < len(self.outputs) else None}

    def _pipes_document(self) -> list[dict]:
        inv = self.inventory
        pipes = inv.pipes
        out = []
        for j, name in enumerate(pipes.name):
            k = int(self.assignment[j])
            table = self.sizes[k].table if k >= 0 else (self.sizes[0].table if self.sizes else None)
            pressure = table.pressure[j] if table is not None else np.full(len(inv.segment_names), np.inf)
            out.append({
                "name": name, "pressure_Pa": _finite(float(pressure.max())),
                "segments": [{"name": n, "pressure_Pa": _finite(float(p))}
                             for n, p in zip(inv.segment_names, pressure, strict=True)],
                "size": k + 1 if k >= 0 else None, "served": k >= 0,
                "reason": None if k >= 0 or table is None else table.reason[j],
                "inner_diameter_m": float(pipes.diameter[j]),
                "inner_diameter_range_m": [float(pipes.diameter_low[j]), float(pipes.diameter_high[j])],
                "length_m": float(pipes.length[j]), "incline_deg": math.degrees(pipes.incline[j]),
                "friction": float(pipes.friction[j]),
                "stride_m": None if table is None else _finite(float(table.stride[j])),
                "anchoring_pressure_Pa": (None if table is None
                                          else _finite(float(table.anchoring_pressure[j]))),
                "material_pressure_Pa": _finite(float(self.material_table.largest[j]))})
        return out


def size_result(inventory: Inventory, design: SizeDesign, table: PipeTable, assigned: np.ndarray, name: str
                ) -> SizeResult:
    """A :class:`SizeResult` with its PAM and objective over its assigned pipes."""
    from pampipe.design.evaluate import objective_value

    pam = designed_pam(inventory, design.geometry, name)
    value = objective_value(inventory.space.objective, table, inventory.pipes, assigned)
    return SizeResult(pam, design, table, assigned, value)
