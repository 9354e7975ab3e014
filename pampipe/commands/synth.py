"""`pampipe synth`: write a synthetic experiment (YAML + CSV) that follows the paper's protocol."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, add_units_option, emit, integer_type, quantity_type

NAME = "synth"
HELP = ("generate a synthetic experiment (paper protocol, known moduli, noise, seed) for identify; with "
        "--slip-pipe also slip tests of known friction and load coupling")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("out_dir", type=Path, metavar="OUT_DIR",
                        help="folder for NAME.yaml and data/NAME/*.csv (created if missing)")
    parser.add_argument("--pam", type=Path, metavar="PAM.yaml",
                        help="muscle with the true moduli (default: the bundled paper-radial-pam.yaml)")
    parser.add_argument("--name", default="experiment", help="experiment name (default: experiment)")
    parser.add_argument("--seed", type=integer_type("--seed", ge=0, le=2**63 - 1), default=0,
                        help="random seed of the noise, a whole number >= 0 (default 0)")
    parser.add_argument("--force-noise", type=quantity_type("force"), default=2.0,
                        metavar="F", help="standard deviation of the force noise (default '2 N')")
    parser.add_argument("--pressure-noise", type=quantity_type("pressure"), default=0.0,
                        metavar="P", help="standard deviation of the pressure-sensor noise (default 0)")
    parser.add_argument("--points-per-leg", type=integer_type("--points-per-leg", ge=1), default=50,
                        metavar="N",
                        help="samples per loading or unloading leg of the axial cycles (default 50)")
    parser.add_argument("--cycles", type=integer_type("--cycles", ge=1), default=3, metavar="N",
                        help="axial cycles per pressure (3)")
    parser.add_argument("--held-lengths", type=integer_type("--held-lengths", ge=0), default=0,
                        metavar="N",
                        help="hold the axial test's length at N values over the contraction range and ramp "
                             "the pressure at each, as a force map (default 0: the paper's length cycles)")
    parser.add_argument("--radial-points", type=integer_type("--radial-points", ge=1), default=40,
                        metavar="N",
                        help="samples per pressure level of each radial test (default 40)")
    slip = parser.add_argument_group("slip tests (issue 24): added with --slip-pipe")
    slip.add_argument("--slip-pipe", action="append", type=quantity_type("length"), metavar="D",
                      help="add a slip test in a pipe of this bore, e.g. '3 in' (repeatable: two bores "
                           "separate friction from load coupling)")
    slip.add_argument("--friction", type=quantity_type("dimensionless"), default=0.3, metavar="MU",
                      help="true wall friction mu of the slip tests (default 0.3)")
    slip.add_argument("--load-coupling", type=quantity_type("dimensionless"), default=1.0, metavar="KAPPA",
                      help="true load coupling kappa: F_slip = mu*pi*F_r(P, D, kappa*F_slip) (default 1)")
    slip.add_argument("--slip-scatter", type=quantity_type("dimensionless"), default=0.03, metavar="S",
                      help="relative standard deviation of the slip loads, e.g. '3 %%' (default 3 %%)")
    slip.add_argument("--stick-slip", action="store_true",
                      help="the muscle slips in three short jumps, the load rising back between them")
    slip.add_argument("--slip-pressure", action="append", type=quantity_type("pressure"), metavar="P",
                      help="trial pressure (repeatable; default 250 to 600 kPa in 50 kPa steps)")
    slip.add_argument("--held-trial", action="append", type=integer_type("--held-trial", ge=1), metavar="N",
                      help="trial N (1-based, per bore) stops at 70 %% of its slip load: no slip, a censored "
                           "trial (repeatable)")
    slip.add_argument("--pipe-material", metavar="NAME", help="pipe material written into the slip tests")
    slip.add_argument("--slip-only", action="store_true",
                      help="write only the slip tests (the PAM with its moduli inline), no axial or "
                           "radial test")
    parser.add_argument("--force", action="store_true",
                        help="replace existing experiment and data files (never the --pam input)")
    add_output_options(parser, plots=False)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe import api

    result = api.synth(
        args.out_dir, pam=args.pam, name=args.name, seed=args.seed, force_noise=args.force_noise,
        pressure_noise=args.pressure_noise, points_per_leg=args.points_per_leg, cycles=args.cycles,
        held_lengths=args.held_lengths,
        radial_points=args.radial_points, slip_pipe=args.slip_pipe, friction=args.friction,
        load_coupling=args.load_coupling, slip_scatter=args.slip_scatter, stick_slip=args.stick_slip,
        slip_pressure=args.slip_pressure, held_trial=args.held_trial, pipe_material=args.pipe_material,
        slip_only=args.slip_only, force=args.force)
    emit(args, result.document, result.render())
    return 0
