"""`pampipe simulate`: anchoring pressure and radial force of one muscle in one or more pipes."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from pampipe import api
from pampipe.commands.common import add_output_options, add_units_option, emit, quantity_type, say
from pampipe.views.tables import table

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
    if not args.pipe_diameter:
        return _extension(args)
    result = api.simulate(args.pam, pipe_diameter=args.pipe_diameter, axial_load=args.axial_load or [0.0],
                          pressure=args.pressure, paper_literal=args.paper_literal)
    emit(args, result.to_dict(), result_text(result))
    if args.plots:
        from pampipe.views.plots.simulate import plot_simulation

        for path in plot_simulation(result, args.plots):
            say(args, f"wrote {path}")
    return 0


def _extension(args: argparse.Namespace) -> int:
    """An extensile PAM: free length, extension and diameter against pressure (no pipe)."""
    result = api.extension(args.pam, pressure=args.pressure)
    head = (f"{result.pam} (extensile) at zero axial load: L0 = {result.initial_length * 1e3:.2f} mm, it "
            f"lengthens toward B/sqrt(3) = {result.limit * 1e3:.2f} mm")
    rows = [(p / 1e3, length * 1e3, 100 * (length / result.initial_length - 1), d * 1e3)
            for p, length, d in zip(result.pressures, result.free_length, result.diameter, strict=True)]
    emit(args, result.to_dict(), head + "\n" + table(["P [kPa]", "L [mm]", "extension [%]", "D [mm]"], rows))
    if args.plots:
        from pampipe.views.plots.simulate import plot_extension

        say(args, f"wrote {plot_extension(result, args.plots)}")
    return 0


def result_text(result) -> str:
    """The report of `simulate` (``str(result)``)."""
    return _text(result.pam, result.cases)


def _text(name: str, cases) -> str:
    parts = []
    for c in cases:
        head = (f"{name} in a {c.pipe_diameter * 1e3:.2f} mm pipe, axial load {c.axial_load:.2f} N: "
                f"anchored length {c.anchored_length * 1e3:.2f} mm, amplification factor "
                f"{c.amplification_factor:.4f}, anchoring pressure {c.anchoring_pressure / 1e3:.2f} kPa")
        rows = [(p / 1e3, bool(a), f / 1e0, fl, pc / 1e3, np.pi * f)
                for p, a, f, fl, pc in zip(c.pressures, c.anchored, c.radial_force, c.force_per_length,
                                           c.contact_pressure, strict=True)]
        parts.append(head + "\n" + table(
            ["P [kPa]", "anchored", "F_r [N]", "f_r [N/m]", "p_c [kPa]", "N_tot [N]"], rows))
    return "\n\n".join(parts)
