"""`pampipe gait`: the peristaltic schedule in one pipe section, and the time-optimal gait."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from pampipe import api
from pampipe.commands.common import add_output_options, add_units_option, emit, say
from pampipe.locomotion.result import GaitResult
from pampipe.locomotion.schedule import POSITION_KEYS
from pampipe.runtime.progress import note
from pampipe.views.tables import table

NAME = "gait"
HELP = ("the 7-step peristaltic schedule of a mission section: steps, pressures, positions, valve "
        "timing, speed; --optimal adds the time-optimal gait")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4); its optional gait: block sets the valves")
    parser.add_argument("--section", metavar="NAME", help="route section to walk (default: the first)")
    parser.add_argument("--optimal", action="store_true",
                        help="also solve the minimum-time gait (CasADi/IPOPT) and compare the speeds")
    add_output_options(parser)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    report = api.gait(args.mission, section=args.section, optimal=args.optimal,
                      progress=note)
    emit(args, report.to_dict(), result_text(report))
    if args.plots:
        from pampipe.views.plots.gait import plot_gait

        for result in report.results:
            for path in plot_gait(result, args.plots):
                say(args, f"wrote {path}")
    return 0


def result_text(report) -> str:
    """The report of `gait` (``str(report)``): the needs, the schedules, the speed gain and the bends."""
    sequential, best = report.sequential, report.optimal
    text = [_header(sequential), _schedule_text(sequential)]
    if best is not None:
        text += [_schedule_text(best),
                 f"speed gain of the optimal gait: {100 * report.speed_gain:+.1f} % "
                 f"({sequential.speed * 1e3:.4g} -> {best.speed * 1e3:.4g} mm/s; cycle "
                 f"{sequential.cycle_time:.3f} s -> {best.cycle_time:.3f} s)"]
    if report.bends is not None:
        b = report.bends
        text.append(f"bends: {b['count']} on the route ({b['passable']} passable, see `pampipe plan`); "
                    f"{b['extra_steps']} steering steps add {b['extra_time_s']:.3g} s to the "
                    f"{b['walking_time_s']:.4g} s the route takes at this section's speed "
                    f"({100 * b['extra_share']:.2g} %)")
    return "\n\n".join(text)


def section_text(result: GaitResult) -> str:
    """One gait (``str(result)``): the section's needs and the schedule."""
    return _header(result) + "\n\n" + _schedule_text(result)


def _header(result: GaitResult) -> str:
    lines = [f"section {result.section!r}: "
             f"{result.needs[0].pipe_diameter * 1e3:.1f} mm pipe, safety factor "
             f"{result.needs[0].safety_factor:g}"]
    rows = [(n.name, n.contact_pressure / 1e3, n.required_pressure / 1e3, n.target_pressure / 1e3,
             n.load, n.anchored_length * 1e3, n.rest_length * 1e3) for n in result.needs]
    lines.append(table(["segment", "contact [kPa]", "no slip [kPa]", "planned [kPa]", "hold W [N]",
                        "L(D_p) [mm]", "L0 [mm]"], rows))
    return "\n".join(lines)


def _schedule_text(result: GaitResult) -> str:
    names = result.names
    rows = []
    for s in result.steps:
        margin = min(s.slip_margins.values())
        rows.append((s.step, s.action, "+".join(s.anchored), s.duration,
                     *(s.pressures[n] / 1e3 for n in names),
                     *(round(s.positions[k] * 1e3, 3) + 0.0 for k in POSITION_KEYS), margin))
    head = [f"{result.schedule} schedule"]
    if result.solver is not None:
        sv = result.solver
        head[0] += (f" (IPOPT {sv['status']}, {sv['iterations']} iterations, "
                    f"{sv['solve_wall_time_s']:.2f} s{', warm start' if sv['warm_start'] else ''})")
    body = table(["step", "valve action", "anchored", "duration [s]",
                  *(f"P {n} [kPa]" for n in names), "rear [mm]", "joint 1-2 [mm]", "joint 2-3 [mm]",
                  "front [mm]", "slip margin"], rows)
    ideal = result.needs[0].rest_length - result.needs[0].anchored_length
    tail = (f"stride {result.stride * 1e3:.3f} mm from the simulated positions "
            f"(L0 - L(D_p) = {ideal * 1e3:.3f} mm), cycle time {result.cycle_time:.3f} s, "
            f"speed {result.speed * 1e3:.4g} mm/s; lowest slip margin at any instant "
            f"{result.hold_margin.min():.4g} (safety factor {result.needs[0].safety_factor:g})")
    if not math.isclose(result.kinematic_slip, 0.0, abs_tol=1e-9):
        tail += f"; kinematic mismatch {result.kinematic_slip * 1e3:.3g} mm"
    return "\n".join([*head, body, tail])
