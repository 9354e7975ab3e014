"""The result of `pampipe rehearse` and its JSON document (docs/commands.md §13.2). SI inside."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pampipe.pneumatics.timing import GAS_CONSTANT, ISO_DENSITY
from pampipe.results import notebook


def _plot():
    from pampipe.views.plots.rehearse import plot_rehearsal

    return plot_rehearsal


def _text():
    from pampipe.views.rehearse_text import result_text

    return result_text


@notebook(headline=("mission", "completed", "time_s", "free_air_m3", "walked_m", "completion_probability"),
          plot=_plot, text=_text)
@dataclass(frozen=True)
class Rehearsal:
    """The whole route in time: the walk section by section, the tether, the supply and the totals."""

    mission: str  # source file
    schedule: str  # "sequential" | "optimal"
    walk: object = field(repr=False)  # pampipe.rehearsal.walk.Walk
    tether: object = field(repr=False)  # pampipe.planning.reach.TetherPlan (zero tensions without a tether)
    plan: object = field(repr=False)  # the MissionPlan walked
    spec: object = field(default=None, repr=False)  # pampipe.specs.tether.Tether, or None
    gas: object = field(default=None, repr=False)  # pampipe.pneumatics.options.Gas of the gait
    completion: object | None = field(default=None, repr=False)  # pampipe.rehearsal.completion.Completion
    wall_time: float = 0.0  # [s] (set by the API)

    def timed(self, wall_time: float) -> Rehearsal:
        return replace(self, wall_time=wall_time)

    @property
    def route(self):
        return self.plan.arrays.route

    @property
    def completed(self) -> bool:
        """True when the robot walks the whole route (at the nominal inputs)."""
        return bool(np.all(self.walk.walked == self.route.length))

    @property
    def time(self) -> float:
        """[s] of the whole walk."""
        return float(self.walk.time.sum())

    @property
    def free_air(self) -> float:
        """[m³] normal (ISO 8778) the gait uses on the whole walk."""
        return float(self.walk.free_air.sum())

    @property
    def largest_tension(self) -> float:
        """[N] the largest tether tension along the walked part (0 without a tether)."""
        walked = self.walk.walked > 0
        return float(np.max(self.tether.largest[walked], initial=0.0))

    @property
    def compressor_duty(self) -> float | None:
        """Share of the time the compressor delivers: air / (Q·time) (None without a compressor)."""
        compressor = None if self.spec is None else self.spec.compressor
        if compressor is None or self.time <= 0:
            return None
        return self.free_air / (compressor.free_air_delivery * self.time)

    def hose_air(self) -> float:
        """[m³] normal: the air that fills the deployed hose to the supply pressure,
        π/4·d²·L·(p_s + p_atm)/(R·T)/ρ_N (once, not per cycle)."""
        hose = None if self.spec is None else self.spec.hose
        if hose is None:
            return 0.0
        volume = math.pi / 4 * hose.inner_diameter ** 2 * float(self.walk.walked.sum())
        absolute = self.plan.supply_pressure + self.gas.atmospheric_pressure
        return volume * absolute / (GAS_CONSTANT * self.gas.temperature) / ISO_DENSITY

    def section_documents(self) -> list[dict]:
        w, r, t = self.walk, self.route, self.tether
        reasons = self.plan.arrays.reasons
        docs = []
        for s in range(len(r)):
            walked = bool(w.walked[s] > 0)
            docs.append({"name": str(r.name[s]), "length_m": float(r.length[s]),
                         "walked_m": float(w.walked[s]), "time_s": float(w.time[s]),
                         "cycles": float(w.cycles[s]),
                         "stride_m": float(w.stride[s]) if walked else None,
                         "cycle_time_s": float(w.cycle_time[s]) if walked else None,
                         "gait_cycle_time_s": float(w.gait_cycle_time[s]) if walked else None,
                         "free_air_m3": float(w.free_air[s]), "air_per_cycle_m3": float(w.air_per_cycle[s]),
                         "steering_time_s": float(w.steering_time[s]), "hose_length_m": float(w.entry[s]),
                         "compressor_limited": bool(w.compressor_limited[s]),
                         "tether": t.section_document(s), "reason": reasons.get(s)})
        return docs

    def to_dict(self) -> dict:
        """The `rehearse --json` document (docs/commands.md §13.2)."""
        spec = self.spec
        doc = {"mission": self.mission, "schedule": self.schedule, "completed": self.completed,
               "supply_pressure_Pa": self.plan.supply_pressure, "confidence": self.plan.confidence,
               "sections": self.section_documents(), "time_s": self.time, "free_air_m3": self.free_air,
               "walked_m": float(self.walk.walked.sum()), "route_length_m": float(self.route.length.sum()),
               "steering_time_s": float(self.walk.steering_time.sum()),
               "largest_tension_N": self.largest_tension, "reach": self.tether.reach.as_document(),
               "hose": None, "compressor": None, "warnings": list(self.plan.warnings),
               "wall_time_s": self.wall_time}
        if spec is not None and spec.hose is not None:
            doc["hose"] = {"inner_diameter_m": spec.hose.inner_diameter, "roughness_m": spec.hose.roughness,
                           "deployed_m": float(self.walk.walked.sum()), "fill_free_air_m3": self.hose_air()}
        if spec is not None and spec.compressor is not None:
            limited = [str(n) for n in self.route.name[self.walk.compressor_limited]]
            doc["compressor"] = {"free_air_delivery_m3_per_s": spec.compressor.free_air_delivery,
                                 "duty": self.compressor_duty, "limited_sections": limited}
        if self.completion is not None:
            doc["completion_probability"] = self.completion.probability
            doc["monte_carlo"] = self.completion.as_document(self.route, self.walk.entry)
        return doc
