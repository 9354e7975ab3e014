"""`pampipe example`: copy a bundled mission, PAM or experiment (with what it references) to start from."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from pampipe.commands.common import add_output_options, emit
from pampipe.io import bundled

NAME = "example"
HELP = ("copy a bundled mission, PAM, experiment or pipe inventory (and the files it uses) into a folder to "
        "start from")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", nargs="?", metavar="NAME",
                        help="a bundled problem, e.g. vertical-climb-3in (omit it to list them)")
    parser.add_argument("out_dir", nargs="?", type=Path, metavar="DIR", help="folder to copy into")
    parser.add_argument("--force", action="store_true", help="overwrite files that already exist in DIR")
    add_output_options(parser, plots=False)


def run(args: argparse.Namespace) -> int:
    document, render = compute(args)
    emit(args, document, render())
    return 0


def compute(args: argparse.Namespace) -> tuple[dict, Callable[[], str]]:
    """(the JSON document, what writes the text report in the display units) of the command; files are
    written here."""
    from pampipe.errors import InputError
    from pampipe.io.experiment_schema import load_experiment
    from pampipe.io.inventory_file import load_inventory
    from pampipe.io.mission_schema import load_mission

    if args.name is None:
        listing = bundled.catalogue()
        text = "\n".join(f"{kind}: {', '.join(names)}" for kind, names in listing.items())
        return {"examples": listing}, lambda: text + "\ncopy one with: pampipe example NAME DIR"
    if args.out_dir is None:
        raise InputError(f"example {args.name}: give the folder to copy into, e.g. "
                         f"`pampipe example {args.name} my-{args.name}`.")
    source = bundled.find(args.name)
    kind = source.parent.name
    if kind == "missions":
        files = load_mission(source).input_files
    elif kind == "experiments":
        files = load_experiment(source).input_files
    elif kind == "inventories":
        files = load_inventory(source).input_files
    else:
        files = [source]
    written = bundled.copy(files, args.out_dir, overwrite=args.force)
    main = written[0]
    commands = {"missions": "plan", "experiments": "identify", "pams": "simulate", "inventories": "design"}
    hint = f"pampipe {commands[kind]} {main}" + (" --pipe-diameter '3 in'" if kind == "pams" else "")
    return ({"example": args.name, "kind": kind, "files": [str(p) for p in written]},
            lambda: "\n".join(f"wrote {p}" for p in written) + f"\ntry: {hint}")
