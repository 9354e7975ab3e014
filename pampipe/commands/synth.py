"""`pampipe synth`: write a synthetic experiment (YAML + CSV) that follows the paper's protocol."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pampipe.commands.common import add_output_options, add_units_option, emit, integer_type, quantity_type
from pampipe.errors import InputError
from pampipe.io import bundled
from pampipe.io.csvfile import check_rows
from pampipe.io.pam_schema import load_pam
from pampipe.io.pamfile import write_experiment
from pampipe.model.domain import check_kind
from pampipe.model.muscle import Muscle
from pampipe.simulation.synthetic import Protocol, comments, generate
from pampipe.slip.synthetic_trials import SlipProtocol, generate_slip

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
    document, render = compute(args)
    emit(args, document, render())
    return 0


def compute(args: argparse.Namespace) -> tuple[dict, Callable[[], str]]:
    """(the JSON document, what writes the text report in the display units) of the command; files are
    written here."""
    protocol = Protocol(cycles=args.cycles, points_per_leg=args.points_per_leg,
                        radial_points=args.radial_points, force_noise=args.force_noise,
                        pressure_noise=args.pressure_noise)
    rows = {"axial": len(protocol.pressures) * protocol.cycles * 2 * protocol.points_per_leg,
            "radial": len(protocol.radial_pressures) * protocol.radial_points}
    for kind, count in rows.items():
        check_rows(count, where=f"synth: the {kind} test's",
                   advice="lower --cycles, --points-per-leg or --radial-points")
    if args.force_noise < 0 or args.pressure_noise < 0:
        raise InputError("--force-noise and --pressure-noise must not be negative.")
    if not args.name or "/" in args.name or args.name.startswith("."):
        raise InputError(f"--name: {args.name!r} must be a plain file name.")
    pam_file = args.pam or bundled.default_pam()
    pam = load_pam(pam_file)
    check_kind(pam.geometry, extensile=False, where=f"--pam {pam_file}",
               role="a synthetic experiment (axial and radial tests of an anchoring muscle)")
    slip = _slip_protocol(args)
    if args.slip_only and slip is None:
        raise InputError("--slip-only writes slip tests only: give at least one --slip-pipe, e.g. '3 in'.")
    tests = [] if args.slip_only else generate(pam, protocol, seed=args.seed)
    notes = [f"Synthetic slip tests generated by `pampipe synth` (seed {args.seed})."] if args.slip_only \
        else comments(pam, protocol, args.seed)
    if slip is not None:
        tests += generate_slip(Muscle.from_pam(pam, where=str(pam_file)), slip,
                               np.random.default_rng([args.seed, 24]))
        notes.append(f"Slip tests: friction {slip.friction:g}, load coupling {slip.load_coupling:g}, scatter "
                     f"{slip.scatter:g} (relative sd){', stick-slip' if slip.stick_slip else ''}.")
    target = write_experiment(args.out_dir, args.name, pam, tests, comments=notes, overwrite=args.force,
                              inputs=[pam_file], with_moduli=args.slip_only)
    document = {"experiment": str(target), "seed": args.seed, "force_noise_N": args.force_noise,
                "pressure_noise_Pa": args.pressure_noise, "pam": pam.name,
                "true_moduli_MPa": [v / 1e6 for v in pam.moduli.as_vector()]}
    if slip is not None:
        document["slip"] = {"friction": slip.friction, "load_coupling": slip.load_coupling,
                            "scatter": slip.scatter, "stick_slip": slip.stick_slip,
                            "pipe_diameters_m": list(slip.pipes)}
    return document, lambda: (f"wrote {target} (seed {args.seed}, force noise {args.force_noise:g} N, "
                              f"pressure noise {args.pressure_noise / 1e3:g} kPa); fit it with\n"
                              f"  pampipe identify {target} -o fitted-pam.yaml")


def _slip_protocol(args) -> SlipProtocol | None:
    """The slip tests asked for (None without --slip-pipe), their values checked."""
    if not args.slip_pipe:
        return None
    checks = (("--friction", args.friction, 0 < args.friction <= 5, "in (0, 5]"),
              ("--load-coupling", args.load_coupling, 0 <= args.load_coupling <= 3, "in [0, 3]"),
              ("--slip-scatter", args.slip_scatter, 0 <= args.slip_scatter <= 1, "in [0, 1] (0 to 100 %)"))
    for flag, value, ok, allowed in checks:
        if not ok:
            raise InputError(f"{flag}: {value:g} is outside the allowed range {allowed}.")
    pressures = tuple(args.slip_pressure) if args.slip_pressure else SlipProtocol(()).pressures
    if any(p <= 0 for p in pressures):
        raise InputError("--slip-pressure: each trial pressure must be above 0 (the muscle must grip).")
    return SlipProtocol(tuple(args.slip_pipe), args.friction, args.load_coupling, args.slip_scatter,
                        args.stick_slip, pressures, pipe_material=args.pipe_material,
                        held=tuple(args.held_trial or ()))
