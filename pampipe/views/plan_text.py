"""The text report of `pampipe plan`: sections as parsed, the plan, coverage (docs/commands.md §4.1, §7).

Pressures are shown in the unit of ``--units`` (kPa, psi or bar; the JSON stays SI). Routes of more
than :data:`FULL_TABLE` sections are summarised: the sections that need the most pressure, the
infeasible ones, and one row per bore; ``--all-sections`` lists every one.
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.bends.plan import Reducers
from pampipe.planning.quantiles import level_text, probability_places
from pampipe.units.display import counted
from pampipe.units.quantities import to_si
from pampipe.views.tables import FULL_TABLE, table
from pampipe.views.tether_text import tether_text

SHOWN = 20  # sections listed in a summary, by largest pressure (and as many infeasible ones)
LISTED_REDUCERS = 6  # reducers worded one by one; a longer route's are summarised by change of bore
INCH = 0.0254


def pressure_scale(unit: str) -> float:
    """Pa per ``unit`` (kPa, psi or bar)."""
    return to_si(f"1 {unit}", "pressure")


def result_text(plan) -> str:
    """The warnings and the plan report, as `plan` prints them (``str(plan)``)."""
    from pampipe.units.display import current

    return "".join(f"warning: {w}\n" for w in plan.warnings) + plan_text(plan, unit=current().pressure)


def plan_text(plan, *, unit: str = "kPa", all_sections: bool = False) -> str:
    """The whole report: header, route, sections as parsed, plan, coverage, payload and verdict."""
    scale = pressure_scale(unit)
    route = plan.arrays.route
    rows = _shown_rows(plan, all_sections)
    parts = [_header(plan, unit, scale)]
    origin = route.origin
    if origin is not None:
        parts.append(_network_line(plan))
    if rows.size < len(route):
        parts.append(f"{len(route)} sections: showing the {rows.size} that need the most pressure"
                     + ("" if origin is not None and origin.whole else " or cannot be planned")
                     + " (--all-sections lists every one; --json has them all).")
    parts += ["sections as parsed:", _parsed_table(plan, rows)]
    if rows.size < len(route):
        parts += ["by bore:", _bore_table(plan, unit, scale)]
    parts += [f"plan (pressures in {unit}, gauge; each segment in the worst bore of its section's range):",
              _plan_table(plan, rows, unit, scale),
              "P_anchor: where the unloaded muscle first touches the largest bore; contact margin = "
              "P - P_anchor (thin: below what a 1 mm wider bore or a 1 deg braid angle error costs); "
              "margin = capacity / W (the safety factor where no slip sets the pressure)."]
    if plan.tether is not None:
        parts.append(tether_text(plan, rows))
    if plan.uncertainty is not None:
        parts += _confidence_text(plan, rows, unit, scale)
    if plan.bends:
        parts += [_bend_table(plan, unit, scale, all_sections)]
    if plan.reducers:
        parts += ["reducers: " + _reducers_text(plan.reducers)]
    if plan.coverage is not None:
        parts.append(_coverage_text(plan.coverage, "the network" if origin.whole else "the route"))
    if plan.max_payload is not None:
        limit = plan.max_payload
        supply = f"{limit.supply_pressure / scale:.4g} {unit}"
        if limit.payload is None:
            parts.append(f"max payload: none; the robot cannot get through section {limit.section!r} at "
                         f"{supply}.")
        else:
            held = "" if plan.confidence is None else f" (held with probability {plan.confidence:.3g})"
            parts.append(f"max payload at {supply}: {limit.payload:.4g} kg{held}, limited by {limit.segment} "
                         f"in section {limit.section!r}.")
    if plan.feasible:
        parts.append("feasible: every segment holds in every section, over each bore's range, within the "
                     "supply" + (", and passes every bend." if plan.bends else "."))
    elif origin is None or not origin.whole:
        parts.append("INFEASIBLE:\n  " + "\n  ".join(_limited(plan.reasons)))
    return "\n".join(parts)


def _bend_table(plan, unit: str, scale: float, all_sections: bool) -> str:
    """One row per bend: angle, radius, bore, limiting segment, its rigid length against the longest that
    passes, the binding position, the steering pressures and curvature, the verdict."""
    bends = list(plan.bends)
    note = ""
    if len(bends) > FULL_TABLE and not all_sections:
        keep = sorted(bends, key=lambda b: (b.passable, -b.angle))[:SHOWN]
        bends = [b for b in bends if b in keep]
        note = (f"\n{len(plan.bends)} bends: showing the {len(bends)} sharpest or impassable "
                "(--all-sections lists every one).")
    rows = []
    for b in bends:
        s = b.limiting
        rows.append((b.after_section, f"{math.degrees(b.angle):.1f}", b.turn, f"{b.radius * 1e3:.4g}",
                     b.radius_text, f"{b.bore * 1e3:.4g}", s.name, f"{s.length * 1e3:.4g}",
                     "bends" if s.flexible else f"{s.longest * 1e3:.4g}",
                     "-" if s.flexible else f"{s.clearance * 1e3:.4g}", *_steering_cells(b, scale),
                     "yes" if b.passable else "no"))
    head = ("bends (each deflated segment as a rigid cylinder L0 + fittings long, D0 wide; L*: the longest "
            "that passes; turn: along travel, the steering module seen from behind with PAM 1 at the top and "
            "PAM 2 lower left; steering: the least-pressure triad toward 1/R, and the PAMs it fills):")
    skipped = [b.steering_note for b in plan.bends if b.steering_note is not None]
    if skipped:
        note += f"\n{len(skipped)} bend(s) with no steering (fills: none (small)): {skipped[0]}."
    if any(b.radius_assumed for b in plan.bends):
        note += ("\nR (assumed): the bend gives no radius; it is the mission's elbow_radius (a network gives "
                 "none): measure it where the clearance is small.")
    return head + "\n" + table(
        ["after section", "angle [deg]", "turn", "R [mm]", "R/D", "bore [mm]", "limiting", "L [mm]",
         "L* [mm]", "clearance [mm]", f"steering P [{unit}]", "fills", "curvature [1/m]", "passes"],
        rows) + note


def _steering_cells(bend, scale: float) -> tuple[str, str, str]:
    """(pressures, the PAMs filled, curvature) of a bend's steering command, dashes where it has none."""
    steer = bend.steering
    if steer is None:
        return "-", "-" if bend.steering_note is None else "none (small)", "-"
    fills = ", ".join(f"PAM {k}" for k in steer.fills) or "none"
    return ("/".join(f"{p / scale:.3g}" for p in steer.pressures), fills,
            f"{steer.curvature:.3g}{'' if steer.reached else ' (short)'}")


def _header(plan, unit: str, scale: float) -> str:
    given = "" if not any("safety_factor" in w for w in plan.warnings) else " (none given: default)"
    return (f"plan for {plan.mission}: supply {plan.supply_pressure / scale:.4g} {unit}, payload "
            f"{plan.payload:.4g} kg, safety factor {plan.safety_factor:g}{given}, load path {plan.load_path}"
            + (f", confidence {level_text(plan.confidence)}" if plan.confidence is not None else ""))


def _network_line(plan) -> str:
    route = plan.arrays.route
    origin = route.origin
    net = origin.network
    if origin.whole:
        return (f"route: every pipe of network {net.name} ({net.source}): {counted(len(route), 'pipe')}, "
                f"{route.length.sum() / 1e3:.4g} km; inclines are |asin(dz/length)| (direction unknown).")
    return (f"route: network {net.name} ({net.source}) from {origin.from_node} to {origin.to_node}: "
            f"{counted(len(route), 'pipe')}, {route.length.sum():.6g} m, the shortest path through the pipes "
            "the robot "
            f"passes ({origin.excluded} of {len(net.pipe_ids)} pipes excluded by their bore); every joint "
            "that turns is an elbow of the mission's elbow_radius (bends below).")


def _shown_rows(plan, all_sections: bool) -> np.ndarray:
    """Section indices to list: all of them, or the largest pressures and the infeasible ones."""
    n = len(plan.arrays.route)
    if all_sections or n <= FULL_TABLE:
        return np.arange(n)
    a = plan.arrays
    feasible = a.feasible.all(axis=1)
    pressure = np.where(feasible, plan.section_pressure, -np.inf)
    largest = np.argsort(-pressure, kind="stable")[:min(SHOWN, int(feasible.sum()))]
    whole = a.route.origin is not None and a.route.origin.whole  # coverage counts the others
    bad = np.array([] if whole else sorted(a.reasons)[:SHOWN], dtype=int)
    return np.union1d(largest, bad)


def _parsed_table(plan, rows: np.ndarray) -> str:
    """Each section as parsed: bore in mm and in (range, as written), length, incline, μ, largest W."""
    route, a = plan.arrays.route, plan.arrays
    origin = route.origin
    bends = origin is not None and not origin.whole
    headers = ["section", "bore [mm]", "bore [in]", "range [mm]", "bore as given", "length [m]",
               "incline [deg]", "friction", "W [N]", *(["bend [deg]"] if bends else [])]
    out = []
    for s in rows.tolist():
        low, high = route.diameter_low[s] * 1e3, route.diameter_high[s] * 1e3
        sd = route.friction_sd[s]
        friction = f"{route.friction[s]:.4g}" + (f" ± {sd:.3g}" if sd else "")
        row = [route.name[s], route.diameter[s] * 1e3, route.diameter[s] / INCH,
               f"{low:.5g}-{high:.5g}" if high > low else "-", route.section_label(s), route.length[s],
               math.degrees(route.incline[s]), friction, float(np.max(a.required_hold[s]))]
        if bends:
            bend = origin.bend[s]
            row.append("-" if math.isnan(bend) else math.degrees(bend))
        out.append(row)
    return table(headers, out)


def _plan_table(plan, rows: np.ndarray, unit: str, scale: float) -> str:
    a = plan.arrays
    thin = a.thin
    uncertain = plan.confidence is not None
    ranged = bool(a.route.toleranced.any())
    headers = ["section", "segment", f"P [{unit}]", *([f"P_nominal [{unit}]"] if uncertain else []),
               *(["worst bore [mm]"] if ranged else []), f"P_anchor [{unit}]", f"contact margin [{unit}]",
               "W [N]", "capacity [N]", "margin", "ok"]
    out = []
    for s in rows.tolist():
        if not a.complete[s]:
            out.append((a.route.name[s], *["-"] * (len(headers) - 2), "NO"))
            continue
        for i, name in enumerate(a.segment_names):
            p, touch, hold = a.pressure[s, i], a.largest_bore_anchoring[s, i], a.required_hold[s, i]
            capacity = a.holding_capacity[s, i]
            margin = (p - touch) / scale
            out.append((a.route.name[s], name, p / scale,
                        *([a.nominal_pressure[s, i] / scale] if uncertain else []),
                        *([a.diameter[s, i] * 1e3] if ranged else []), touch / scale,
                        f"{margin:.4g} (thin)" if thin[s, i] else float(margin), float(hold),
                        float(capacity), float(capacity / hold) if hold > 0 else "inf",
                        "yes" if a.feasible[s, i] else "NO"))
    return table(headers, out)


def _confidence_text(plan, rows: np.ndarray, unit: str, scale: float) -> list[str]:
    """The sampled plan: probabilities and pressures per element, then the sources by influence."""
    c, a = plan.uncertainty, plan.arrays
    levels = list(c.pressure_at)
    places = probability_places(c.level)
    headers = ["section", "segment", "unit", f"P [{unit}]", "P(hold)", "P(contact)",
               *(f"P@{k} [{unit}]" for k in levels)]
    out = []
    for s in rows.tolist():
        if not a.complete[s]:
            continue
        for i, name in enumerate(a.segment_names):
            if c.is_stopped(s, i):
                out.append((a.route.name[s], name, c.units[i], "-", "undetermined", "-",
                            *["-"] * len(levels)))
                continue
            out.append((a.route.name[s], name, c.units[i], a.pressure[s, i] / scale,
                        f"{c.holding_probability[s, i]:.{places}f} ± {c.holding_se[s, i]:.{places}f}",
                        f"{c.contact_probability[s, i]:.{places}f}",
                        *(float(c.pressure_at[k][s, i] / scale) for k in levels)))
    sources = [(r["source"], r["what"], "-" if r["pressure_shift_Pa"] is None
                else r["pressure_shift_Pa"] / scale) for r in c.dominant()]
    text = [f"confidence {level_text(c.level)}: {c.samples} seeded draws (seed {c.seed}) of every stated "
            "uncertainty; "
            "P is the least pressure that holds in that share of the draws (P(hold) ± its Monte Carlo "
            "error; holding includes touching the wall: P(contact) is the share in which the unloaded "
            "muscle touches the largest bore; unit: the muscle it holds for, 'tested' the one its PAM file "
            "was fitted to, 'lot' another of its lot):", table(headers, out),
            f"what each source adds alone (its {level_text(c.level)} quantile with the others at their "
            "nominal values, the worst element):", table(["source", "what", f"adds [{unit}]"], sources)]
    if c.prior:
        text.append("note: part of this margin rests on a prior (--prior-from or a stated geometry sd) "
                    "along directions the muscle's own test data leave undetermined.")
    return text


def _bore_table(plan, unit: str, scale: float) -> str:
    """One row per nominal bore: pipes, length, pipes planned, and the largest pressure among them."""
    route = plan.arrays.route
    pressure = plan.section_pressure
    feasible = np.ones(len(route), dtype=bool)
    feasible[list(plan.arrays.reasons)] = False
    rows = []
    for d in np.unique(route.diameter).tolist():
        at = route.diameter == d
        ok = at & feasible
        top = float(np.max(pressure[ok])) / scale if ok.any() else "-"
        rows.append((d * 1e3, d / INCH, int(at.sum()), float(route.length[at].sum()), int(ok.sum()), top))
    return table(["bore [mm]", "bore [in]", "pipes", "length [m]", "planned", f"largest P [{unit}]"], rows)


def _coverage_text(coverage, scope: str) -> str:
    from pampipe.planning.feasibility import REASONS

    share = coverage.pipes_feasible / coverage.pipes_total if coverage.pipes_total else 0.0
    length = coverage.length_feasible / coverage.length_total if coverage.length_total else 0.0
    text = (f"coverage of {scope}: {coverage.pipes_feasible} of {coverage.pipes_total} pipes ({share:.1%}), "
            f"{coverage.length_feasible / 1e3:.4g} of {coverage.length_total / 1e3:.4g} km ({length:.1%}) "
            "can be served")
    if coverage.reasons:
        text += "; the others: " + "; ".join(f"{REASONS.get(code, code)}: {count}"
                                              for code, count in coverage.reasons.items())
    return text + "."


def _limited(reasons: list[str]) -> list[str]:
    if len(reasons) <= SHOWN:
        return reasons
    return [*reasons[:SHOWN], f"... and {len(reasons) - SHOWN} more (--json lists every reason)"]


def _reducers_text(reducers) -> str:
    """'after NAME D1 -> D2 mm: passes (...)' per reducer; each change of bore is worded once (a long route
    repeats a few). More than :data:`LISTED_REDUCERS` reducers are summarised: one line per change of bore,
    naming the first sections after which it comes and counting the rest (--json lists every reducer).
    ``reducers``: a sequence of reducers, or their columns (:class:`~pampipe.bends.plan.Reducers`)."""
    if isinstance(reducers, Reducers):
        names, before, after = reducers.after_section, reducers.before.tolist(), reducers.after.tolist()
        passable = reducers.passable.tolist()
    else:
        names, before, after, passable = ([getattr(r, key) for r in reducers]
                                          for key in ("after_section", "before", "after", "passable"))
    places: dict[tuple[float, float, bool], list[int]] = {}
    for i, key in enumerate(zip(before, after, passable, strict=True)):
        places.setdefault(key, []).append(i)
    worded = {key: (f" {key[0] * 1e3:.4g} -> {key[1] * 1e3:.4g} mm: {'passes' if key[2] else 'does NOT pass'}"
                    " (a rigid segment passes if it fits the smaller bore)") for key in places}
    if len(names) <= LISTED_REDUCERS:
        keys = list(zip(before, after, passable, strict=True))
        return "; ".join(f"after {names[i]!r}{worded[key]}" for i, key in enumerate(keys))
    lines = [f"{len(names)} changes of bore, {counted(len(worded), 'kind')} (--json lists every reducer):"]
    for key, where in places.items():
        more = f" and {len(where) - LISTED_REDUCERS} more" if len(where) > LISTED_REDUCERS else ""
        lines.append(f"{worded[key].strip()}, {counted(len(where), 'time')}: after "
                     f"{', '.join(repr(names[i]) for i in where[:LISTED_REDUCERS])}{more}")
    return "\n  ".join(lines)


def infeasible_reason(plan, shown: int = SHOWN) -> str:
    """How many sections and bends cannot be planned or passed, and which (``shown`` names at most)."""
    parts = []
    bad = plan.arrays.route.name[sorted(plan.arrays.reasons)].tolist()
    if bad:
        names = ", ".join(bad[:shown]) + (f" and {len(bad) - shown} more" if len(bad) > shown else "")
        parts.append(f"{len(bad)} of {len(plan.arrays.route)} sections cannot be planned ({names})")
    blocked = [b.after_section for b in plan.bends if not b.passable]
    if blocked:
        names = ", ".join(f"after {n!r}" for n in blocked[:shown])
        more = f" and {len(blocked) - shown} more" if len(blocked) > shown else ""
        parts.append(f"{len(blocked)} of {len(plan.bends)} bends cannot be passed ({names}{more})")
    if plan.tether is not None and plan.tether.reason() is not None:
        parts.append(plan.tether.reason().rstrip("."))
    return "; ".join(parts) + "; the reasons are listed above."
