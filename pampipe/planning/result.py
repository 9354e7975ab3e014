"""Frozen results of `plan`, and their JSON document (docs/commands.md §4.2, §4.3, §7). SI inside."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from pampipe.errors import InputError
from pampipe.planning.payload import PayloadLimit
from pampipe.results import notebook
from pampipe.runtime.alike import Picked


def thin_contact(pressure, touch, cost):
    """True where the contact margin P − P_a(D_high) is below ``cost`` [Pa], what a 1 mm wider bore or a
    1° braid angle error moves P_a (:mod:`pampipe.planning.contact`); False where any is NaN."""
    return np.asarray(pressure) - np.asarray(touch) < np.asarray(cost)


@dataclass(frozen=True)
class SegmentPlan:
    """One segment anchored alone in one section.

    ``pressure`` is the least pressure that holds (for an infeasible element: the pressure it would
    need); ``anchoring_pressure`` the pressure at which the unloaded muscle touches the wall;
    ``required_hold`` the axial load W it must hold, before the safety factor; ``holding_capacity``
    μπF_r at ``pressure`` under that load; ``radial_force`` F_r; ``contact_pressure`` F_r/(D L). All
    are those of ``worst_diameter``, the bore of the section's range where the pressure is largest;
    ``largest_bore_anchoring_pressure`` is where the unloaded muscle first touches the largest bore, and
    ``contact_margin`` the planned pressure above it.
    """

    name: str
    pressure: float  # [Pa]
    anchoring_pressure: float  # [Pa], P_a(D_p, 0)
    required_hold: float  # [N]
    holding_capacity: float  # [N]
    radial_force: float  # [N]
    contact_pressure: float  # [Pa]
    loaded_anchoring_pressure: float = math.nan  # [Pa], P_a(D_p, κW): the contact bound
    air_volume: float = math.nan  # [m³], V at the anchored length
    binding: str = "no_slip"  # which constraint sets the pressure: "no_slip" | "contact"
    feasible: bool = True
    nominal_pressure: float | None = None  # [Pa], the plan without uncertainty (with --confidence)
    worst_diameter: float = math.nan  # [m]
    largest_bore_anchoring_pressure: float = math.nan  # [Pa], P_a(D_high, 0)
    contact_cost_bore: float = math.nan  # [Pa], P_a(D_high + 1 mm) − P_a(D_high)
    contact_cost_angle: float = math.nan  # [Pa], P_a at a braid angle 1° off − P_a(D_high)

    @property
    def margin(self) -> float:
        """holding_capacity / required_hold [-]: equals the safety factor where no slip binds."""
        return self.holding_capacity / self.required_hold if self.required_hold > 0 else math.inf

    @property
    def contact_margin(self) -> float:
        """P − P_a(D_high, 0) [Pa]: how far the plan is above first touching the largest bore."""
        return self.pressure - self.largest_bore_anchoring_pressure

    @property
    def thin_contact(self) -> bool:
        """True where a 1 mm wider bore or a 1° braid angle error would cost more than the contact margin."""
        cost = max(self.contact_cost_bore, self.contact_cost_angle)
        return bool(thin_contact(self.pressure, self.largest_bore_anchoring_pressure, cost))

    def as_document(self) -> dict:
        doc = {"name": self.name, "pressure_Pa": self.pressure,
               "anchoring_pressure_Pa": self.anchoring_pressure,
               "required_hold_N": self.required_hold, "holding_capacity_N": self.holding_capacity,
               "radial_force_N": self.radial_force, "contact_pressure_Pa": self.contact_pressure,
               "loaded_anchoring_pressure_Pa": self.loaded_anchoring_pressure,
               "air_volume_m3": self.air_volume, "margin": self.margin, "binding": self.binding,
               "feasible": self.feasible, "worst_inner_diameter_m": self.worst_diameter,
               "largest_bore_anchoring_pressure_Pa": self.largest_bore_anchoring_pressure,
               "contact_margin_Pa": self.contact_margin, "contact_cost_1mm_bore_Pa": self.contact_cost_bore,
               "contact_cost_1deg_braid_Pa": self.contact_cost_angle,
               "thin_contact_margin": self.thin_contact}
        if self.nominal_pressure is not None:
            doc["nominal_pressure_Pa"] = self.nominal_pressure
        return doc


@dataclass(frozen=True)
class SectionPlan:
    """The plan of one route section: feasible with its segments, or a reason in words.

    ``diameter`` is the nominal bore, ``diameter_range`` (low, high) the bores it may take; ``network``
    holds ``pipe``, ``from``, ``to``, ``bend_deg`` and ``incline_clipped`` for a pipe of a network route.
    """

    name: str
    feasible: bool
    reason: str | None
    segments: tuple[SegmentPlan, ...]  # empty where the pipe itself is impassable
    length: float  # [m]
    diameter: float  # [m]
    incline: float  # [rad]
    friction: float  # [-]
    diameter_range: tuple[float, float] = (math.nan, math.nan)  # [m]
    diameter_sd: float = 0.0  # [m]
    label: str = ""
    friction_sd: float = 0.0
    network: dict | None = None

    def as_document(self) -> dict:
        doc = {"name": self.name, "feasible": self.feasible, "reason": self.reason,
               "length_m": self.length, "inner_diameter_m": self.diameter,
               "inner_diameter_range_m": list(self.diameter_range), "inner_diameter_sd_m": self.diameter_sd,
               "inner_diameter_label": self.label, "incline_rad": self.incline,
               "incline_deg": math.degrees(self.incline), "friction": self.friction,
               "friction_sd": self.friction_sd, "segments": [s.as_document() for s in self.segments]}
        if self.network is not None:
            doc.update(self.network)
        return doc


@dataclass(frozen=True)
class PlanArrays:
    """The whole plan as (sections, segments) arrays [SI], for long routes and vectorised use.

    ``complete[s]`` is False where the pipe itself is impassable (no per-segment numbers).
    """

    pressure: np.ndarray  # [Pa]
    anchoring_pressure: np.ndarray  # [Pa], unloaded
    loaded_anchoring_pressure: np.ndarray  # [Pa]
    required_hold: np.ndarray  # [N]
    holding_capacity: np.ndarray  # [N]
    radial_force: np.ndarray  # [N]
    contact_pressure: np.ndarray  # [Pa]
    air_volume: np.ndarray  # [m³]
    anchored_length: np.ndarray  # [m], L(D_p)
    slip_active: np.ndarray  # bool
    feasible: np.ndarray  # bool
    complete: np.ndarray  # bool, per section
    nominal_pressure: np.ndarray | None  # [Pa], with --confidence
    segment_names: tuple[str, ...]
    route: object  # the mission's Route (columns)
    reasons: dict[int, str]  # {section index: why it cannot be planned}, infeasible sections only
    diameter: np.ndarray  # [m], the worst bore of each element
    largest_bore_anchoring: np.ndarray  # [Pa], P_a(D_high, 0) (NaN where the pipe is impassable)
    reason_codes: dict[int, str]  # {section index: reason code}, infeasible sections only
    contact_cost: np.ndarray | None = None  # (S, segments, 2) [Pa]: 1 mm wider bore, 1° braid angle

    @property
    def contact_margin(self) -> np.ndarray:
        """P − P_a(D_high, 0) [Pa] per element."""
        return self.pressure - self.largest_bore_anchoring

    @property
    def thin(self) -> np.ndarray:
        """True per element where a 1 mm / 1° error costs more than the contact margin."""
        with np.errstate(invalid="ignore"):
            return thin_contact(self.pressure, self.largest_bore_anchoring, np.max(self.contact_cost, axis=2))


def _plot():
    from pampipe.views.plots.plan import plot_plan

    return plot_plan


def _text():
    from pampipe.views.plan_text import result_text

    return result_text


@notebook(headline=("mission", "feasible", "payload_kg", "supply_pressure_Pa", "safety_factor"), plot=_plot,
          text=_text)
@dataclass(frozen=True)
class MissionPlan:
    """The anchoring pressures of a whole mission; ``feasible`` only if every section is.

    ``sections`` (SectionPlan objects) are built on first use from ``arrays``.
    """

    feasible: bool
    arrays: PlanArrays = field(repr=False)
    mission: str  # source file
    supply_pressure: float  # [Pa]
    safety_factor: float
    load_path: str
    payload: float  # [kg]
    method: str  # "kkt" | "ipopt"
    iterations: int
    checks: dict = field(default_factory=dict)  # largest relative differences to the cross-checks
    confidence: float | None = None
    max_payload: PayloadLimit | None = None
    muscles: tuple = field(default=(), repr=False)  # the segments' Muscle objects, rear to front
    kappa: float = 1.0  # κ of the load path
    wall_time: float = 0.0  # [s] from reading the mission to the plan (set by the API)
    warnings: tuple[str, ...] = ()  # sentences for the engineer: defaults taken, thin contact margins, ...
    coverage: object | None = None  # pampipe.specs.network.Coverage of a network plan (the route's pipes, or
    # all)
    bends: tuple = ()  # pampipe.bends.plan.BendPlan per bend, in travel order
    reducers: tuple = ()  # pampipe.bends.plan.ReducerPlan per change of bore
    uncertainty: object | None = field(default=None, repr=False)  # planning.confidence.Confidence (sampled)
    tether: object | None = field(default=None, repr=False)  # planning.reach.TetherPlan: tensions, reach

    def timed(self, wall_time: float) -> MissionPlan:
        """A copy that reports ``wall_time`` [s]."""
        return replace(self, wall_time=wall_time)

    def to_dict(self) -> dict:
        """The `plan --json` document (docs/commands.md §4.2)."""
        return self.as_document()

    def capacity_curve(self, section: int, segment: int, pressures) -> np.ndarray:
        """μπF_r(P, D, κW) [N] of one segment in one section (its worst bore) over ``pressures``
        (InputError for an index out of range)."""
        a = self.arrays
        for name, index, count in (("section", section, len(a.route)),
                                   ("segment", segment, len(self.muscles))):
            whole = isinstance(index, int | np.integer) and not isinstance(index, bool)
            if not (whole and 0 <= index < count):
                raise InputError(f"capacity_curve: {name} {index!r} is not allowed; give a whole number "
                                 f"from 0 to {count - 1}.")
        load = a.required_hold[section, segment]
        capacity = self.muscles[segment].holding_capacity(
            np.asarray(pressures, dtype=float), a.diameter[section, segment], load, kappa=self.kappa,
            friction=a.route.friction[section])
        return np.asarray(capacity, dtype=float) * np.ones(np.shape(pressures))

    @property
    def section_pressure(self) -> np.ndarray:
        """The largest planned pressure of each section [Pa] (NaN where the pipe is impassable)."""
        a = self.arrays
        return np.where(a.complete, a.pressure.max(axis=1), np.nan)

    @cached_property
    def sections(self) -> tuple[SectionPlan, ...]:
        """One SectionPlan per route section, in travel order."""
        return tuple(self._section_plans())

    def _section_plans(self):
        """The SectionPlans one at a time, built from the columns."""
        if "sections" in self.__dict__:  # built before
            yield from self.sections
            return
        a, r = self.arrays, self.arrays.route
        columns = [x.tolist() for x in (a.pressure, a.anchoring_pressure, a.required_hold, a.holding_capacity,
                                        a.radial_force, a.contact_pressure, a.loaded_anchoring_pressure,
                                        a.air_volume, a.slip_active, a.feasible, a.diameter,
                                        a.largest_bore_anchoring, a.contact_cost[..., 0],
                                        a.contact_cost[..., 1])]
        nominal = None if a.nominal_pressure is None else a.nominal_pressure.tolist()
        section_columns = zip(r.name.tolist(), r.length.tolist(), r.diameter.tolist(), r.incline.tolist(),
                              r.friction.tolist(), r.friction_sd.tolist(), r.diameter_low.tolist(),
                              r.diameter_high.tolist(), r.diameter_sd.tolist(), a.complete.tolist(),
                              strict=True)
        networks = _network_columns(r)
        for s, (name, length, d, incline, mu, mu_sd, low, high, sd, complete) in enumerate(section_columns):
            reason = a.reasons.get(s)
            segments = ()
            if complete:
                p, pa, w, cap, fr, pc, pl, vol, active, ok, worst, touch, c_d, c_a = (c[s] for c in columns)
                segments = tuple(
                    SegmentPlan(seg, p[i], pa[i], w[i], cap[i], fr[i], pc[i],
                                loaded_anchoring_pressure=pl[i], air_volume=vol[i],
                                binding="no_slip" if active[i] else "contact", feasible=ok[i],
                                nominal_pressure=None if nominal is None else nominal[s][i],
                                worst_diameter=worst[i], largest_bore_anchoring_pressure=touch[i],
                                contact_cost_bore=c_d[i], contact_cost_angle=c_a[i])
                    for i, seg in enumerate(a.segment_names))
            yield SectionPlan(name, reason is None, reason, segments, length, d, incline, mu, (low, high), sd,
                              r.section_label(s), mu_sd, None if networks is None else networks[s])

    @property
    def reasons(self) -> list[str]:
        """'section: reason' for every infeasible section, then the reason of every impassable bend."""
        reel = [] if self.tether is None or self.tether.reason() is None else [self.tether.reason()]
        return ([f"{self.arrays.route.name[s]}: {r}" for s, r in sorted(self.arrays.reasons.items())]
                + [b.reason() for b in self.bends if not b.passable] + reel)

    def section_documents(self):
        """The documents of the sections one at a time (their uncertainty entries included)."""
        for s, section in enumerate(self._section_plans()):
            doc = section.as_document()
            if self.uncertainty is not None:
                for i, segment in enumerate(doc["segments"]):
                    segment.update(self.uncertainty.element_document(s, i))
            if self.tether is not None:
                doc["tether"] = self.tether.section_document(s)
            yield doc

    def section_columns(self, start: int, stop: int) -> tuple[dict, dict] | None:
        """Sections ``start:stop`` of :meth:`section_documents` as columns, for a column-wise JSON writer:
        (the sections' keys → one value each; {"segments": (the segments' keys → one value per segment
        of each complete section, sections first; segments per section; ``complete``)}), the floats
        unrounded, as the documents hold them. With --confidence each segment's entries of
        :meth:`~pampipe.planning.confidence.Confidence.element_columns` join them; None where those are
        not columns (a segment stopped by an undetermined direction, or with its shift)."""
        a, r, rows = self.arrays, self.arrays.route, slice(start, stop)
        complete = a.complete[rows]
        segments = self._segment_columns(rows, complete)
        if self.uncertainty is not None:
            sampled = self.uncertainty.element_columns(rows, complete)
            if sampled is None:
                return None
            segments.update(sampled)
        reasons = [a.reasons.get(s) for s in range(start, stop)] if a.reasons else [None] * (stop - start)
        sections = {"name": r.name[rows].tolist(), "feasible": np.array([x is None for x in reasons], bool),
                    "reason": reasons, "length_m": r.length[rows], "inner_diameter_m": r.diameter[rows],
                    "inner_diameter_range_m": np.stack([r.diameter_low[rows], r.diameter_high[rows]], axis=1),
                    "inner_diameter_sd_m": r.diameter_sd[rows],
                    "inner_diameter_label": r.section_labels(rows),
                    "incline_rad": r.incline[rows], "incline_deg": np.degrees(r.incline[rows]),
                    "friction": r.friction[rows], "friction_sd": r.friction_sd[rows]}
        networks = _network_columns(r.subset(rows))
        if networks:
            sections.update({key: [n[key] for n in networks] for key in networks[0]})
        if self.tether is not None:
            sections["tether"] = {"tension_in_N": self.tether.tension_in[rows],
                                  "tension_out_N": self.tether.tension_out[rows]}
        width = len(a.segment_names)
        return sections, {"segments": (segments, width, complete)}

    def reducer_columns(self, start: int, stop: int) -> tuple[dict, dict]:
        """Reducers ``start:stop`` of the document as columns (:func:`~pampipe.bends.plan.reducer_columns`),
        in the shape of :meth:`section_columns`."""
        from pampipe.bends.plan import reducer_columns

        return reducer_columns(self.reducers[start:stop]), {}

    def _segment_columns(self, rows: slice, complete: np.ndarray) -> dict:
        """The segments' columns of :meth:`section_columns`: (complete sections × segments), flattened (the
        nominal pressure with --confidence only)."""
        a, every = self.arrays, bool(complete.all())

        def flat(column):  # a view where every section is complete (a long route's usual case)
            return column[rows].ravel() if every else column[rows][complete].ravel()

        p, w, cap, touch = flat(a.pressure), flat(a.required_hold), flat(a.holding_capacity), \
            flat(a.largest_bore_anchoring)
        cost_bore, cost_angle = flat(a.contact_cost[..., 0]), flat(a.contact_cost[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            margin = np.where(w > 0, cap / np.where(w > 0, w, 1.0), np.inf)
            thin = thin_contact(p, touch, np.where(cost_angle > cost_bore, cost_angle, cost_bore))
        width, sections = len(a.segment_names), int(complete.sum())
        columns = {"name": Picked(a.segment_names, np.tile(np.arange(width), sections)), "pressure_Pa": p,
                   "anchoring_pressure_Pa": flat(a.anchoring_pressure), "required_hold_N": w,
                   "holding_capacity_N": cap, "radial_force_N": flat(a.radial_force),
                   "contact_pressure_Pa": flat(a.contact_pressure),
                   "loaded_anchoring_pressure_Pa": flat(a.loaded_anchoring_pressure),
                   "air_volume_m3": flat(a.air_volume), "margin": margin,
                   "binding": Picked(("contact", "no_slip"), flat(a.slip_active).astype(np.intp)),
                   "feasible": flat(a.feasible).astype(bool), "worst_inner_diameter_m": flat(a.diameter),
                   "largest_bore_anchoring_pressure_Pa": touch, "contact_margin_Pa": p - touch,
                   "contact_cost_1mm_bore_Pa": cost_bore, "contact_cost_1deg_braid_Pa": cost_angle,
                   "thin_contact_margin": np.asarray(thin, bool)}
        if a.nominal_pressure is not None:
            columns["nominal_pressure_Pa"] = flat(a.nominal_pressure)
        return columns

    def as_document(self, *, sections=None, reducers=None) -> dict:
        """The document; ``sections`` and ``reducers`` in place of the built lists (the `plan` command
        passes lazy ones, from :meth:`section_documents`, to stream a large document)."""
        doc = {"feasible": self.feasible, "sections": list(self.section_documents()) if sections is None
               else sections,
               "mission": self.mission, "supply_pressure_Pa": self.supply_pressure,
               "safety_factor": self.safety_factor, "load_path": self.load_path, "load_coupling": self.kappa,
               "payload_kg": self.payload, "confidence": self.confidence, "warnings": list(self.warnings),
               "solver": {"method": self.method, "iterations": self.iterations, **self.checks,
                          "wall_time_s": self.wall_time}}
        if self.uncertainty is not None:
            doc["confidence"] = self.uncertainty.as_document()
        if self.max_payload is not None:
            doc["max_payload"] = self.max_payload.as_document()
            if self.uncertainty is not None:
                doc["max_payload"]["confidence"] = self.confidence
        doc["bends"] = [b.as_document() for b in self.bends]
        doc["bends_extra_time_s"] = float(sum(b.steps.extra_time for b in self.bends if b.steps is not None))
        doc["reducers"] = [r.as_document() for r in self.reducers] if reducers is None else reducers
        origin = self.arrays.route.origin
        if origin is not None:
            net = origin.network
            doc["route"] = {"network": net.name, "network_file": str(net.source), "from": origin.from_node,
                            "to": origin.to_node, "pipes": len(self.arrays.route),
                            "length_m": float(self.arrays.route.length.sum()),
                            "excluded_pipes": origin.excluded}
        if self.coverage is not None:
            doc["coverage"] = {**self.coverage.as_document(), "scope": "network" if origin.whole else "route"}
        if self.tether is not None:
            doc["reach"] = self.tether.reach.as_document()
        return doc


def _network_columns(route) -> list[dict] | None:
    """Per section: its pipe, end nodes, bend and clipped flag, for a route read from a network."""
    origin = route.origin
    if origin is None:
        return None
    ids = origin.network.node_ids
    return [{"pipe": pipe, "from": a, "to": b, "bend_deg": None if math.isnan(t) else math.degrees(t),
             "incline_clipped": c}
            for pipe, a, b, t, c in zip(route.name.tolist(), ids[origin.entry].tolist(),
                                        ids[origin.exit].tolist(), origin.bend.tolist(),
                                        origin.clipped.tolist(), strict=True)]
