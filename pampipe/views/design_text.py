"""The text report of `pampipe design`: the sizes, then every pipe (or one row per bore), the coverage
(docs/commands.md §8); and the comments of the PAM files it writes."""

from __future__ import annotations

import math
from collections import defaultdict

from pampipe.units.display import counted
from pampipe.views.tables import table

MAX_PIPE_ROWS = 40  # pipes listed one by one; longer inventories are summarised per bore


def pam_comments(inventory, size, result) -> list[str]:
    """The header comments of the PAM file of ``size``: where it comes from and what it serves."""
    bores = sorted({round(float(d) * 1e3, 2) for d in inventory.pipes.diameter[size.assigned]})
    return [f"Designed by pampipe design from {inventory.source} (objective "
            f"{inventory.space.objective.value}).",
            f"Bladder material and moduli from '{inventory.material.name}'"
            + (f" ({inventory.material_file})." if inventory.material_file else "."),
            f"Serves {counted(int(size.assigned.sum()), 'pipe')}, bores "
            f"{', '.join(f'{b:g}' for b in bores)} mm; "
            f"largest required pressure {size.table.largest[size.assigned].max() / 1e3:.4g} kPa at supply "
            f"{inventory.supply_pressure / 1e3:.4g} kPa, safety factor {inventory.safety_factor:g}."]


def report(result, *, all_pipes: bool = False) -> str:
    """The human-readable design report: the sizes, then the pipes (or a summary per bore)."""
    inv = result.inventory
    cov = result.coverage
    unit = inv.space.objective.unit
    head = (f"design for {inv.source}: material '{inv.material.name}', {counted(len(inv.pipes), 'pipe')} "
            f"({cov['length_total_m']:.6g} m), supply {inv.supply_pressure / 1e3:.4g} kPa, safety factor "
            f"{inv.safety_factor:g}, load path {inv.load_path}, objective {inv.space.objective.value}")
    parts = [head]
    rows = []
    for k, s in enumerate(result.sizes):
        g, run = s.pam.geometry, s.design.run
        served = s.assigned
        rows.append((k + 1, g.initial_length * 1e3, g.initial_diameter * 1e3, math.degrees(g.braid_angle),
                     g.largest_diameter * 1e3, int(served.sum()), float(inv.pipes.length[served].sum()),
                     s.table.largest[served].max() / 1e3 if served.any() else "-",
                     s.objective if math.isfinite(s.objective) else "-", f"{run.reached}/{len(run.results)}"))
    if rows:
        parts.append(table(["size", "L0 [mm]", "D0 [mm]", "angle from axis [deg]", "opens to [mm]", "pipes",
                            "length [m]", "largest P [kPa]", f"objective [{unit}]", "starts at best"], rows))
    parts.append(_pipes_table(result, all_pipes))
    share = 100 * cov["length_served_m"] / cov["length_total_m"]
    parts.append(f"served: {cov['pipes_served']} of {cov['pipes_total']} pipes, {cov['length_served_m']:.6g} "
                 f"of {cov['length_total_m']:.6g} m ({share:.3g} %).")
    if not result.feasible:
        parts.append(f"INFEASIBLE: {result.reason}")
    return "\n".join(parts)


def _kpa(value: float):
    return value / 1e3 if math.isfinite(value) else "-"


def _pipes_table(result, all_pipes: bool) -> str:
    inv = result.inventory
    pipes = inv.pipes
    if not result.sizes:
        return "no design to tabulate."
    tables = [result.sizes[k].table if k >= 0 else result.sizes[0].table for k in result.assignment]
    if len(pipes) <= MAX_PIPE_ROWS or all_pipes:
        rows = []
        for j, name in enumerate(pipes.name):
            t, k = tables[j], int(result.assignment[j])
            rows.append((name, pipes.diameter[j] * 1e3, pipes.length[j], math.degrees(pipes.incline[j]),
                         *(_kpa(p) for p in t.pressure[j]), _kpa(result.material_table.largest[j]),
                         t.stride[j] * 1e3 if math.isfinite(t.stride[j]) else "-",
                         k + 1 if k >= 0 else "-", t.reason[j] or "yes"))
        return table(["pipe", "bore [mm]", "length [m]", "incline [deg]",
                      *(f"{n} [kPa]" for n in inv.segment_names), "material [kPa]", "stride [mm]", "size",
                      "served"], rows)
    groups = defaultdict(list)
    for j in range(len(pipes)):
        groups[round(float(pipes.diameter[j]) * 1e3, 3)].append(j)
    rows = []
    for bore, members in sorted(groups.items()):
        sizes = sorted({int(result.assignment[j]) + 1 for j in members if result.assignment[j] >= 0})
        largest = max(tables[j].largest[j] for j in members)
        served = [j for j in members if result.assignment[j] >= 0]
        rows.append((bore, len(members), float(pipes.length[members].sum()), len(served),
                     _kpa(largest), _kpa(max(result.material_table.largest[j] for j in members)),
                     ", ".join(map(str, sizes)) or "-"))
    headers = ["bore [mm]", "pipes", "length [m]", "served", "largest P [kPa]", "material [kPa]", "sizes"]
    return table(headers, rows) + "\n(one row per bore; --all-pipes or --json for every pipe)"
