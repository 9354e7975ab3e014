"""`pampipe design`: the muscle geometry (or K sizes) for a pipe inventory (docs/commands.md §8)."""

from __future__ import annotations

import argparse
import dataclasses
import math
from collections import defaultdict
from pathlib import Path

from pampipe.commands.common import add_output_options, add_parallel_options, add_units_option, emit, say
from pampipe.errors import InfeasibleError
from pampipe.io.files import check_not_input
from pampipe.io.inventory_file import load_inventory
from pampipe.io.pamfile import write_pam
from pampipe.views.tables import table

NAME = "design"
HELP = "choose the rest length, rest diameter and braid angle of the muscle for a pipe inventory"
MAX_PIPE_ROWS = 40  # pipes listed one by one; longer inventories are summarised per bore

EPILOG = """\
The bladder material (moduli and wall thickness of the 'material:' PAM) is fixed; the rest length,
rest diameter and braid angle are chosen within the design: bounds so that the muscle passes the
smallest bore with the clearance and, in every pipe, every segment holds its load with the safety
factor at no more than the supply pressure (docs/physics.md sections 7-8). The NLP is solved from a
Latin hypercube of starts; the best is kept. With design.sizes: K, up to K muscles serve the most length.

examples:
  pampipe design problems/inventories/riser.yaml -o riser-pam.yaml
  pampipe design problems/inventories/ky4.yaml --workers 2 --json --plots plots/
  pampipe design INVENTORY.yaml --scheduler tcp://127.0.0.1:8786

-o writes the first size to the path given and size k > 1 beside it as STEM-sizeK.yaml.
exit codes: 0 designed; 2 bad input; 3 no muscle within the bounds serves the inventory (the binding
constraint is named)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("inventory", type=Path, metavar="INVENTORY.yaml",
                        help="inventory file: material PAM, robot, supply, pipes, design bounds")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the designed PAM file(s): the geometry and the material's moduli")
    add_parallel_options(parser, "the starts")
    parser.add_argument("--starts", type=int, metavar="N",
                        help="Latin-hypercube starts (overrides design.starts)")
    parser.add_argument("--seed", type=int, metavar="S", help="seed of the starts (overrides design.seed)")
    parser.add_argument("--sizes", type=int, metavar="K",
                        help="choose up to K muscles that serve the most length (overrides design.sizes)")
    parser.add_argument("--objective", choices=("max_pressure", "air", "speed"),
                        help="what to minimise (overrides design.objective)")
    parser.add_argument("--all-pipes", action="store_true",
                        help=f"list every pipe even in inventories of more than {MAX_PIPE_ROWS} pipes")
    add_output_options(parser)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe import api

    inventory = load_inventory(args.inventory)
    if args.output is not None:
        for path in _outputs(args.output, args.sizes or inventory.space.sizes or 1):
            check_not_input(path, inventory.input_files, option="-o")
    result = api.design_inventory(inventory, objective=args.objective, sizes=args.sizes, starts=args.starts,
                        seed=args.seed, workers=args.workers, scheduler=args.scheduler)
    inventory = result.inventory
    if args.output is not None and result.feasible:
        paths = _outputs(args.output, len(result.sizes))
        for size, path in zip(result.sizes, paths, strict=True):
            write_pam(path, size.pam, comments=_comments(inventory, size, result))
        result = dataclasses.replace(result, outputs=tuple(str(p) for p in paths))
    emit(args, result.as_document(), report(result, all_pipes=args.all_pipes))
    for path in result.outputs:
        say(args, f"wrote {path}")
    if args.plots:
        from pampipe.views.plots.design import plot_design

        for path in plot_design(result, args.plots):
            say(args, f"wrote {path}")
    if not result.feasible:
        raise InfeasibleError(f"no muscle within the design bounds serves {args.inventory}; binding "
                              f"constraint: {result.binding} (the reason is given above).")
    return 0


def _outputs(path: Path, count: int) -> list[Path]:
    """PAM_OUT.yaml for size 1, PAM_OUT-size2.yaml … beside it for the others."""
    suffix = path.suffix or ".yaml"
    return [path] + [path.with_name(f"{path.stem}-size{k}{suffix}") for k in range(2, count + 1)]


def _comments(inventory, size, result) -> list[str]:
    bores = sorted({round(float(d) * 1e3, 2) for d in inventory.pipes.diameter[size.assigned]})
    return [f"Designed by pampipe design from {inventory.source} (objective "
            f"{inventory.space.objective.value}).",
            f"Bladder material and moduli from '{inventory.material.name}'"
            + (f" ({inventory.material_file})." if inventory.material_file else "."),
            f"Serves {int(size.assigned.sum())} pipes, bores {', '.join(f'{b:g}' for b in bores)} mm; "
            f"largest required pressure {size.table.largest[size.assigned].max() / 1e3:.4g} kPa at supply "
            f"{inventory.supply_pressure / 1e3:.4g} kPa, safety factor {inventory.safety_factor:g}."]


def report(result, *, all_pipes: bool = False) -> str:
    """The human-readable design report: the sizes, then the pipes (or a summary per bore)."""
    inv = result.inventory
    cov = result.coverage
    unit = inv.space.objective.unit
    head = (f"design for {inv.source}: material '{inv.material.name}', {len(inv.pipes)} pipes "
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
