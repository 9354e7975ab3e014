"""`pampipe simulate`: anchoring pressure and radial force of one muscle in one or more pipes."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe import api
from pampipe.commands.common import add_output_options, add_units_option, emit, quantity_type, say, warn

NAME = "simulate"
HELP = "anchoring pressure, anchored length, amplification and radial force of a PAM in a pipe"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("pam", type=Path, metavar="PAM.yaml", help="PAM file with a moduli: block")
    parser.add_argument("--pipe-diameter", "-d", action="append",
                        type=quantity_type("length"), metavar="D",
                        help="pipe inner diameter, e.g. '3 in' (repeat for several pipes); required for a "
                             "contractile PAM. An extensile PAM (braid angle from the axis > 54.74 deg) is "
                             "simulated without it: its extension against pressure")
    parser.add_argument("--axial-load", "-f", action="append",
                        type=quantity_type("force"), metavar="F",
                        help="axial tension on the anchored PAM, e.g. '1024.74 N' (repeatable; default 0)")
    parser.add_argument("--pressure", "-p", action="append",
                        type=quantity_type("pressure"), metavar="P",
                        help="gauge pressure, e.g. '400 kPa' (repeatable; default 69..689 kPa)")
    parser.add_argument("--paper-literal", action="store_true",
                        help="contact pressure as F_r/(pi D L) (the paper's wording) instead of F_r/(D L)")
    add_output_options(parser)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe.views.simulate_text import result_text

    if not args.pipe_diameter:
        return _extension(args)
    result = api.simulate(args.pam, pipe_diameter=args.pipe_diameter, axial_load=args.axial_load or [0.0],
                          pressure=args.pressure, paper_literal=args.paper_literal)
    warn(result.warnings)
    emit(args, result.to_dict(), result_text(result))
    if args.plots:
        from pampipe.views.plots.simulate import plot_simulation

        for path in plot_simulation(result, args.plots):
            say(args, f"wrote {path}")
    return 0


def _extension(args: argparse.Namespace) -> int:
    """An extensile PAM: free length, extension and diameter against pressure (no pipe)."""
    from pampipe.views.simulate_text import extension_text

    result = api.extension(args.pam, pressure=args.pressure)
    warn(result.warnings)
    emit(args, result.to_dict(), extension_text(result))
    if args.plots:
        from pampipe.views.plots.simulate import plot_extension

        say(args, f"wrote {plot_extension(result, args.plots)}")
    return 0
