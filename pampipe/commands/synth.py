"""`pampipe synth`: write a synthetic experiment (YAML + CSV) that follows the paper's protocol."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, emit, integer_type, quantity_type
from pampipe.errors import InputError
from pampipe.io import bundled
from pampipe.io.config import load_pam
from pampipe.io.csvfile import check_rows
from pampipe.io.pamfile import write_experiment
from pampipe.model.domain import check_kind
from pampipe.synth import Protocol, comments, generate

NAME = "synth"
HELP = "generate a synthetic experiment (paper protocol, known moduli, noise, seed) for identify"


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
    parser.add_argument("--force", action="store_true",
                        help="replace existing experiment and data files (never the --pam input)")
    add_output_options(parser, plots=False)


def run(args: argparse.Namespace) -> int:
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
    target = write_experiment(args.out_dir, args.name, pam, generate(pam, protocol, seed=args.seed),
                              comments=comments(pam, protocol, args.seed), overwrite=args.force,
                              inputs=[pam_file])
    document = {"experiment": str(target), "seed": args.seed, "force_noise_N": args.force_noise,
                "pressure_noise_Pa": args.pressure_noise, "pam": pam.name,
                "true_moduli_MPa": [v / 1e6 for v in pam.moduli.as_vector()]}
    emit(args, document, f"wrote {target} (seed {args.seed}, force noise {args.force_noise:g} N, "
                         f"pressure noise {args.pressure_noise / 1e3:g} kPa); fit it with\n"
                         f"  pampipe identify {target} -o fitted-pam.yaml")
    return 0
