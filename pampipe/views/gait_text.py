"""The text report of `pampipe gait`: each segment's needs, the step table of each schedule, the speed gain of
the optimal gait and the bends' extra time (docs/commands.md §5)."""

from __future__ import annotations

import math

from pampipe.views.tables import table

#: The positions of a step's ``positions`` dict shown, and their column headers.
POSITIONS = {"rear": "rear [mm]", "joint_12": "joint 1-2 [mm]", "joint_23": "joint 2-3 [mm]",
             "front": "front [mm]"}


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


def section_text(result) -> str:
    """One gait (``str(result)``): the section's needs and the schedule."""
    return _header(result) + "\n\n" + _schedule_text(result)


def _header(result) -> str:
    lines = [f"section {result.section!r}: "
             f"{result.needs[0].pipe_diameter * 1e3:.1f} mm pipe, safety factor "
             f"{result.needs[0].safety_factor:g}"]
    rows = [(n.name, n.contact_pressure / 1e3, n.required_pressure / 1e3, n.target_pressure / 1e3,
             n.load, n.anchored_length * 1e3, n.rest_length * 1e3) for n in result.needs]
    lines.append(table(["segment", "contact [kPa]", "no slip [kPa]", "planned [kPa]", "hold W [N]",
                        "L(D_p) [mm]", "L0 [mm]"], rows))
    return "\n".join(lines)


def _schedule_text(result) -> str:
    names = result.names
    rows = []
    for s in result.steps:
        margin = min(s.slip_margins.values())
        rows.append((s.step, s.action, "+".join(s.anchored), s.duration,
                     *(s.pressures[n] / 1e3 for n in names),
                     *(round(s.positions[k] * 1e3, 3) + 0.0 for k in POSITIONS), margin))
    head = [f"{result.schedule} schedule"]
    if result.solver is not None:
        sv = result.solver
        head[0] += (f" (IPOPT {sv['status']}, {sv['iterations']} iterations, "
                    f"{sv['solve_wall_time_s']:.2f} s{', warm start' if sv['warm_start'] else ''})")
    body = table(["step", "valve action", "anchored", "duration [s]",
                  *(f"P {n} [kPa]" for n in names), *POSITIONS.values(), "slip margin"], rows)
    ideal = result.needs[0].rest_length - result.needs[0].anchored_length
    tail = (f"stride {result.stride * 1e3:.3f} mm from the simulated positions "
            f"(L0 - L(D_p) = {ideal * 1e3:.3f} mm), cycle time {result.cycle_time:.3f} s, "
            f"speed {result.speed * 1e3:.4g} mm/s; lowest slip margin at any instant "
            f"{result.hold_margin.min():.4g} (safety factor {result.needs[0].safety_factor:g})")
    if not math.isclose(result.kinematic_slip, 0.0, abs_tol=1e-9):
        tail += f"; kinematic mismatch {result.kinematic_slip * 1e3:.3g} mm"
    return "\n".join([*head, body, tail])
