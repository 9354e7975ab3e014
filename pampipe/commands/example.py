"""`pampipe example`: copy a bundled mission, PAM or experiment (with what it references) to start from."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, emit

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
    from pampipe import api

    result = api.example(args.name, args.out_dir, force=args.force)
    emit(args, result.document, result.render())
    return 0
