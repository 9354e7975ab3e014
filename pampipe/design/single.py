"""One muscle for a set of pipes: checks, the multi-start, and the binding constraint when none exists.

The largest-pressure problem is always solved first with the supply cap relaxed: its optimum is the
least largest pressure any muscle within the bounds needs, so a value above the supply names the
supply as the binding constraint (with the pipe and segment where it binds). With the ``air`` or
``speed`` objective that design is then a feasible start of the second NLP (every pressure ≤ supply).
When no start finds a valid geometry at all, each constraint family is dropped in turn (a deletion
filter); the first whose removal makes the problem solvable is named.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from pampipe.design import design_nlp
from pampipe.design.groups import Groups, make_groups
from pampipe.design.multistart import MultiStart, Problem, make_problem, multistart
from pampipe.errors import InfeasibleError
from pampipe.specs.inventory import Inventory, Objective, Pipes

#: Constraint families (rows of :data:`pampipe.design.design_nlp.ROWS`) with the names reported to users.
FAMILIES = {
    "grip": ("slope", "grip_light", "grip_heavy"),
    "contact_margin": ("reach",),
    "min_stride": ("stride",),
    "material_stability": ("axial_stability_0", "axial_stability_supply", "hoop_stability_0",
                           "hoop_stability_supply"),
}
DELETION_STARTS = 4  # starts per relaxed solve of the deletion filter


class DesignInfeasible(InfeasibleError):
    """No muscle within the bounds serves the pipes; ``binding`` names the constraint (exit 3)."""

    def __init__(self, message: str, binding: str, best: SizeDesign | None = None):
        super().__init__(message)
        self.binding = binding
        self.best = best


@dataclass(frozen=True)
class SizeDesign:
    """The muscle designed for one set of pipes, with the multi-start runs that found it."""

    geometry: tuple[float, float, float]  # (L₀ [m], D₀ [m], α₀ [rad])
    runs: tuple[MultiStart, ...]  # the largest-pressure run, then the objective's run (if another)
    largest_pressure: float  # [Pa] the least largest pressure (the relaxed optimum)

    @property
    def run(self) -> MultiStart:
        """The run whose best start is the design."""
        return self.runs[-1]


def design_for(inventory: Inventory, pipes: Pipes, pool, *, extra: np.ndarray | None = None,
               diagnose: bool = True, polish: bool = True) -> SizeDesign:
    """The best muscle for ``pipes`` (all must be served), or :class:`DesignInfeasible`.

    ``extra`` is one more start (scaled geometry) tried first; ``diagnose=False`` skips the deletion
    filter when only feasibility matters (the binding is then ``"unknown"``); ``polish=False`` stops
    after the largest-pressure run (for the ``air`` and ``speed`` objectives too).
    """
    space = inventory.space
    groups = make_groups(inventory, pipes)
    _check_clearance(inventory, groups)
    _check_reach(inventory, groups)
    relaxed = make_problem(inventory, groups, objective=Objective.MAX_PRESSURE, relaxed=True)
    first = multistart(relaxed, starts=space.starts, seed=space.seed, pool=pool,
                       extra=extra)
    best = first.best
    if best is None:
        if not diagnose:
            raise DesignInfeasible("no start found a valid muscle", "unknown")
        binding, message = _deletion(inventory, relaxed, pool, first)
        raise DesignInfeasible(message, binding)
    pressure = best.x[3] * inventory.supply_pressure
    design = SizeDesign(relaxed.geometry(best.x), (first,), pressure)
    if best.x[3] > 1.0 + 1e-9:
        raise DesignInfeasible(_supply_message(inventory, relaxed, best.x, pipes), "supply_pressure", design)
    if space.objective is Objective.MAX_PRESSURE or not polish:
        return design
    problem = make_problem(inventory, groups)
    second = multistart(problem, starts=space.starts, seed=space.seed, pool=pool,
                        extra=best.x[:3])
    if second.best is None:  # cannot happen from the feasible extra start unless IPOPT fails there
        raise DesignInfeasible(f"IPOPT found no design for the {space.objective.value} objective although "
                               "the largest-pressure design is feasible: "
                               f"{', '.join(sorted({r.status for r in second.results}))}.", "solver", design)
    return replace(design, geometry=problem.geometry(second.best.x), runs=(first, second))


def _mm(value: float) -> str:
    return f"{value * 1e3:.4g} mm"


def _check_clearance(inventory: Inventory, groups: Groups) -> None:
    space = inventory.space
    top = groups.smallest_bore - space.clearance
    if top < space.initial_diameter[0]:
        raise DesignInfeasible(
            f"binding constraint: clearance. The smallest bore {_mm(groups.smallest_bore)} less the "
            f"clearance {_mm(space.clearance)} leaves {_mm(top)}, below the smallest allowed rest diameter "
            f"design.initial_diameter[0] = {_mm(space.initial_diameter[0])}: no muscle within the bounds "
            "passes it at rest. Lower that bound or the clearance, or leave the narrow pipes out.",
            "clearance")


def _check_reach(inventory: Inventory, groups: Groups) -> None:
    """The widest reach within the bounds: D₀ as large as the clearance allows, α₀ as small as allowed."""
    space = inventory.space
    d0 = min(space.initial_diameter[1], groups.smallest_bore - space.clearance)
    reach = (1 - space.contact_margin) * math.sqrt(2 / 3) * d0 / math.sin(space.braid_angle[0])
    if groups.widest_bore > reach:
        raise DesignInfeasible(
            f"binding constraint: contact_margin. The widest bore {_mm(groups.widest_bore)} is beyond what "
            f"any braid within the bounds opens to with the {space.contact_margin:.3g} contact margin: at "
            f"most {_mm(reach)} = (1 - margin) D0 sqrt(2/3)/sin(alpha0) with D0 = {_mm(d0)} (the largest the "
            f"clearance allows) and alpha0 = {math.degrees(space.braid_angle[0]):.4g} deg (the smallest "
            "allowed). Allow a smaller braid angle, or serve the wide and the narrow pipes with different "
            "sizes (design.sizes).", "contact_margin")


def _supply_message(inventory: Inventory, problem: Problem, x: np.ndarray, pipes: Pipes) -> str:
    from pampipe.design.evaluate import evaluate_pipes

    length, diameter, angle = problem.geometry(x)
    table = evaluate_pipes(inventory, (length, diameter, angle), pipes)
    j, i = np.unravel_index(np.argmax(np.where(np.isfinite(table.pressure), table.pressure, -1)),
                            table.pressure.shape)
    at_bounds = _active_bounds(problem, x)
    return (f"binding constraint: supply_pressure. The least largest pressure any muscle within the bounds "
            f"needs is {x[3] * inventory.supply_pressure / 1e3:.4g} kPa (pipe {pipes.name[j]}, segment "
            f"{inventory.segment_names[i]}), more than the {inventory.supply_pressure / 1e3:.4g} kPa supply. "
            f"That muscle: L0 = {_mm(length)}, D0 = {_mm(diameter)}, braid angle "
            f"{math.degrees(angle):.4g} deg from the axis{at_bounds}.")


def _active_bounds(problem: Problem, x: np.ndarray) -> str:
    names = ("design.initial_length", "design.initial_diameter", "design.braid_angle_from_axis")
    parts = []
    for k, name in enumerate(names):
        if x[k] <= problem.lbx[k] + 1e-6:
            parts.append(f"{name} at its lower bound")
        elif x[k] >= problem.ubx[k] - 1e-6:
            parts.append(f"{name} at its upper bound" + (" (set by the clearance)" if k == 1 and
                                                         problem.ubx[1] < 1 else ""))
    return f" ({'; '.join(parts)})" if parts else ""


def _deletion(inventory: Inventory, problem: Problem, pool, run: MultiStart) -> tuple[str, str]:
    """(binding, message): drop each constraint family, then each pair; name the first whose removal helps."""
    names = list(FAMILIES)
    trials = [(f,) for f in names] + [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    for dropped in trials:
        lbg, ubg = problem.lbg.copy(), problem.ubg.copy()
        for row in (r for family in dropped for r in FAMILIES[family]):
            k = design_nlp.ROWS.index(row)
            lbg[k * problem.size:(k + 1) * problem.size] = -np.inf
            ubg[k * problem.size:(k + 1) * problem.size] = np.inf
        trial = multistart(replace(problem, lbg=lbg, ubg=ubg), starts=DELETION_STARTS,
                           seed=inventory.space.seed, pool=pool)
        if trial.best is not None:
            binding = " + ".join(dropped)
            why = "; ".join(_explain(family, inventory) for family in dropped)
            them = "them together" if len(dropped) > 1 else "it"
            return binding, (f"binding constraint: {binding}. No muscle within the bounds meets {them} in "
                             f"every pipe ({why}); without {them.split()[0]} IPOPT finds a design. Widen the "
                             "design bounds, or serve the pipes with several sizes (design.sizes).")
    statuses = ", ".join(sorted({r.status for r in run.results}))
    return "no_valid_geometry", (
        f"binding constraint: none alone or in pairs. No start found a valid muscle within the bounds "
        f"(IPOPT: {statuses}), and dropping any one or two families of constraints ({', '.join(FAMILIES)}) "
        "does not help.")


def _explain(family: str, inventory: Inventory) -> str:
    space = inventory.space
    return {
        "grip": "the holding force must rise with pressure at the anchored length",
        "contact_margin": f"every bore at most {1 - space.contact_margin:.3g} of the widest the braid opens "
                          "to",
        "min_stride": f"a stride of at least {_mm(space.min_stride)} per cycle in every pipe",
        "material_stability": "the moduli law stable (tangent moduli >= 0, docs/physics.md §6) at the "
                              "anchored strain, from 0 to the supply pressure",
    }[family]
