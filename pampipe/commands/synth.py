"""`pampipe synth`: write a synthetic experiment (YAML + CSV) that follows the paper's protocol."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, emit, quantity_type
from pampipe.errors import InputError
from pampipe.io import bundled
from pampipe.io.config import load_pam
from pampipe.io.files import check_not_input
from pampipe.io.pamfile import write_experiment
from pampipe.synth import Protocol, comments, generate

NAME = "synth"
HELP = "generate a synthetic experiment (paper protocol, known moduli, noise, seed) for identify"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("out_dir", type=Path, metavar="OUT_DIR",
                        help="folder for NAME.yaml and data/NAME/*.csv (created if missing)")
    parser.add_argument("--pam", type=Path, metavar="PAM.yaml",
                        help="muscle with the true moduli (default: the bundled paper-radial-pam.yaml)")
    parser.add_argument("--name", default="experiment", help="experiment name (default: experiment)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the noise (default 0)")
    parser.add_argument("--force-noise", type=quantity_type("force", "--force-noise"), default=2.0,
                        metavar="F", help="standard deviation of the force noise (default '2 N')")
    parser.add_argument("--pressure-noise", type=quantity_type("pressure", "--pressure-noise"), default=0.0,
                        metavar="P", help="standard deviation of the pressure-sensor noise (default 0)")
    parser.add_argument("--points-per-leg", type=int, default=50, metavar="N",
                        help="samples per loading or unloading leg of the axial cycles (default 50)")
    parser.add_argument("--cycles", type=int, default=3, metavar="N", help="axial cycles per pressure (3)")
    parser.add_argument("--radial-points", type=int, default=40, metavar="N",
                        help="samples per pressure level of each radial test (default 40)")
    parser.add_argument("--force", action="store_true", help="overwrite an existing experiment file")
    add_output_options(parser, plots=False)


def run(args: argparse.Namespace) -> int:
    for option in ("points_per_leg", "cycles", "radial_points"):
        if getattr(args, option) < 1:
            raise InputError(f"--{option.replace('_', '-')}: {getattr(args, option)} must be at least 1.")
    if args.force_noise < 0 or args.pressure_noise < 0:
        raise InputError("--force-noise and --pressure-noise must not be negative.")
    if not args.name or "/" in args.name or args.name.startswith("."):
        raise InputError(f"--name: {args.name!r} must be a plain file name.")
    pam_file = args.pam or bundled.default_pam()
    pam = load_pam(pam_file)
    protocol = Protocol(cycles=args.cycles, points_per_leg=args.points_per_leg,
                        radial_points=args.radial_points, force_noise=args.force_noise,
                        pressure_noise=args.pressure_noise)
    check_not_input(args.out_dir / f"{args.name}.yaml", [pam_file], option="OUT_DIR")
    target = write_experiment(args.out_dir, args.name, pam, generate(pam, protocol, seed=args.seed),
                              comments=comments(pam, protocol, args.seed), overwrite=args.force)
    document = {"experiment": str(target), "seed": args.seed, "force_noise_N": args.force_noise,
                "pressure_noise_Pa": args.pressure_noise, "pam": pam.name,
                "true_moduli_MPa": [v / 1e6 for v in pam.moduli.as_vector()]}
    emit(args, document, f"wrote {target} (seed {args.seed}, force noise {args.force_noise:g} N, "
                         f"pressure noise {args.pressure_noise / 1e3:g} kPa); fit it with\n"
                         f"  pampipe identify {target} -o fitted-pam.yaml")
    return 0
