"""`pampipe design`: the muscle geometry (or K sizes) for a pipe inventory (docs/commands.md §8)."""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

from pampipe.commands.common import add_output_options, add_parallel_options, add_units_option, emit, say
from pampipe.errors import InfeasibleError
from pampipe.io.files import check_not_input
from pampipe.views.design_text import MAX_PIPE_ROWS, pam_comments, report

NAME = "design"
HELP = "choose the rest length, rest diameter and braid angle of the muscle for a pipe inventory"

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
    from pampipe.io.inventory_file import load_inventory
    from pampipe.io.pamfile import write_pam

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
            write_pam(path, size.pam, comments=pam_comments(inventory, size, result))
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
