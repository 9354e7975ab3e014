"""The text report of `pampipe rehearse` (docs/commands.md §13.1): the walk section by section, the totals,
the supply, the tether's reach and, with ``--confidence``, the completion probability."""

from __future__ import annotations

import numpy as np

from pampipe.planning.quantiles import level_text
from pampipe.views.tables import table

#: Sections listed in full; longer routes list the slowest ones (and the one the walk stops in).
FULL_TABLE = 60
SHOWN = 20


def result_text(result) -> str:
    """The report as `rehearse` prints it (``str(result)``)."""
    return rehearse_text(result)


def duration(seconds: float) -> str:
    """'5.2 h (18 650 s)', '12.3 min (738 s)' or '41.2 s'."""
    if seconds >= 3600:
        return f"{seconds / 3600:.4g} h ({seconds:.6g} s)"
    if seconds >= 60:
        return f"{seconds / 60:.4g} min ({seconds:.6g} s)"
    return f"{seconds:.4g} s"


def rehearse_text(result, *, all_sections: bool = False) -> str:
    """Header, the section table, totals, supply, reach and the Monte Carlo's lines."""
    w, route, t = result.walk, result.route, result.tether
    spec = result.spec
    head = (f"rehearsal of {result.mission}: {result.schedule} gait, supply "
            f"{result.plan.supply_pressure / 1e3:.4g} kPa"
            + ("" if result.plan.confidence is None else f", pressures of plan --confidence "
               f"{result.plan.confidence:.3g}"))
    if spec is not None:
        head += (f"; tether {spec.weight:.4g} N/m, friction {spec.friction:.4g}, back tension "
                 f"{spec.back_tension:.4g} N, {spec.length:.6g} m on the reel")
    rows = _rows(result, all_sections)
    tethered = spec is not None
    body = table(["section", "walked [m]", *(["hose [m]"] if tethered and spec.hose else []), "stride [mm]",
                  "gait cycle [s]", "cycle [s]", "cycles", "time [s]", "air [NL]",
                  *(["T_in [N]", "T_out [N]"] if tethered else []), "note"],
                 [_row(result, s, tethered and spec.hose is not None, tethered) for s in rows.tolist()])
    parts = [head, body]
    if rows.size < len(route):
        parts.append(f"{len(route)} sections: showing the {rows.size} that take longest or stop the walk "
                     "(--json has them all).")
    parts.append(f"gait cycle: the {result.schedule} gait, its valves fed straight from the supply (pampipe "
                 "gait); cycle: with the supply hose and the compressor, the mean over the walked part; "
                 "air: normal litres (ISO 8778, 20 degC, 100 kPa)")
    parts.append(f"total: {duration(result.time)} for {w.walked.sum():.6g} of {route.length.sum():.6g} m, "
                 f"{result.free_air:.4g} m^3 of free air"
                 + (f", steering at bends {duration(float(w.steering_time.sum()))}"
                    if w.steering_time.sum() > 0 else ""))
    parts += _supply_lines(result)
    if spec is not None:
        parts.append(f"largest tether tension on the walk: {result.largest_tension:.4g} N")
    parts.append(t.reach.sentence(tether=spec is not None))
    if result.completion is not None:
        parts += _completion_lines(result)
    parts.append("completed: the robot walks the whole route." if result.completed else
                 f"NOT COMPLETED: the walk ends {w.walked.sum():.6g} m from the entry.")
    return "\n".join(parts)


def _rows(result, all_sections: bool) -> np.ndarray:
    count = len(result.route)
    if all_sections or count <= FULL_TABLE:
        return np.arange(count)
    slowest = np.argsort(-result.walk.time, kind="stable")[:SHOWN]
    return np.union1d(slowest, [result.tether.reach.index])


def _row(result, s: int, hose: bool, tether: bool) -> tuple:
    w, t = result.walk, result.tether
    walked = w.walked[s] > 0
    notes = []
    if w.compressor_limited[s]:
        notes.append("waits for the compressor")
    if w.steering_time[s] > 0:
        notes.append(f"steering {w.steering_time[s]:.3g} s")
    reason = result.plan.arrays.reason_codes.get(s)
    if reason is not None:
        notes.append(reason)
    elif not walked:
        notes.append("beyond the reach")
    return (str(result.route.name[s]), float(w.walked[s]), *([float(w.entry[s])] if hose else []),
            float(w.stride[s] * 1e3) if walked else "-", float(w.gait_cycle_time[s]) if walked else "-",
            float(w.cycle_time[s]) if walked else "-", float(w.cycles[s]), float(w.time[s]),
            float(w.free_air[s] * 1e3),
            *([float(t.tension_in[s]), float(t.tension_out[s])] if tether else []), "; ".join(notes))


def _supply_lines(result) -> list[str]:
    spec, w = result.spec, result.walk
    lines = []
    hose = None if spec is None else spec.hose
    if hose is not None:
        lines.append(f"supply hose: {hose.inner_diameter * 1e3:.4g} mm bore, {w.walked.sum():.6g} m deployed "
                     f"at the end, its pressure drop slowing the fills; filling it takes "
                     f"{result.hose_air() * 1e3:.4g} NL once")
    compressor = None if spec is None else spec.compressor
    if compressor is not None:
        limited = [str(n) for n in result.route.name[w.compressor_limited]]
        where = (f"the fills wait for it in {len(limited)} section(s): {', '.join(limited[:SHOWN])}"
                 if limited else "it never makes the fills wait")
        duty = result.compressor_duty
        lines.append(f"compressor: {compressor.free_air_delivery * 6e4:.4g} NL/min free-air delivery, duty "
                     f"{'-' if duty is None else f'{100 * duty:.3g} %'}; {where}")
    if lines:
        gait = float(np.nansum(w.cycles * w.gait_cycle_time))
        lines.append(f"the supply adds {duration(result.time - gait - float(w.steering_time.sum()))} to the "
                     f"{duration(gait)} the gait's own cycles take")
    return lines


def _completion_lines(result) -> list[str]:
    c, route = result.completion, result.route
    lines = [f"confidence {level_text(c.level)}: {c.samples} seeded draws of {', '.join(c.sources)}; the "
             "robot walks at the plan's pressures and stops at its first slip: completes the route with "
             f"probability "
             f"{c.probability:.4f} ± {c.standard_error:.4f}"]
    slips = np.flatnonzero(c.first_slip > 0)
    if slips.size:
        top = slips[np.argsort(-c.first_slip[slips], kind="stable")][:5]
        lines.append("first slip: " + ", ".join(f"{route.name[s]} ({c.first_slip[s]:.3g})" for s in top))
    lines.append(f"at the {level_text(c.level)} quantile: time {duration(c.time)}, "
                 f"free air {c.free_air:.4g} m^3")
    return lines
