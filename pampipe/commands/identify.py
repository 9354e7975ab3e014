"""`pampipe identify`: fit the bladder moduli to an experiment and write a PAM file."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from pampipe.commands.common import add_output_options, emit, say
from pampipe.identify import identify
from pampipe.identify.options import fit_options
from pampipe.io.config import load_experiment
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.files import check_output
from pampipe.io.pamfile import write_pam
from pampipe.report import table

NAME = "identify"
HELP = "fit the bladder moduli to axial and radial test data (IPOPT, Drucker-stable, with uncertainty)"


#: Command-line flags that override the experiment file's ``fit:`` block, validated by the same schema.
FLAGS = {"mode": "--mode", "objective": "--objective", "degree": "--degree", "average_legs": "--average-legs",
         "drucker": "--drucker", "max_iterations": "--max-iterations"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("experiment", type=Path, metavar="EXPERIMENT.yaml",
                        help="experiment file: the PAM, the tests and their CSV data, an optional fit: block")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the PAM file with the fitted moduli: and uncertainty: blocks")
    parser.add_argument("--mode", choices=("shared", "per_pipe", "contact_increment"),
                        help="one moduli set for all tests (default), separate radial moduli per pipe, "
                             "or axial moduli plus contact-stiffening increments (overrides fit.mode)")
    parser.add_argument("--objective", choices=("least_squares", "sum_rmse"),
                        help="least squares (default) or the paper's sum of RMSE per pressure")
    parser.add_argument("--degree", type=int, choices=range(0, 8), metavar="{0..7}",
                        help="polynomial degree of the moduli in strain (default 3: 16 coefficients)")
    parser.add_argument("--average-legs", action="store_true", default=None,
                        help="fit the mean of the loading and unloading legs per length bin (the paper)")
    parser.add_argument("--drucker", choices=("tangent", "sum", "none"),
                        help="Drucker stability: each tangent modulus >= 0 (default), their weighted sum, "
                             "or no constraint")
    parser.add_argument("--max-iterations", type=int, metavar="N", help="IPOPT iteration limit")
    add_output_options(parser)


def run(args: argparse.Namespace) -> int:
    experiment = load_experiment(args.experiment)
    options = fit_options(experiment.fit, {key: getattr(args, key) for key in FLAGS},
                          source=experiment.source, where="command line", names=FLAGS)
    if args.output is not None:
        check_output(args.output, experiment.input_files, option="-o")

    def progress(text: str) -> None:
        print(f"pampipe identify: {text}", file=sys.stderr, flush=True)

    data = load_experiment_data(experiment, progress=progress)
    result = identify(data, options, progress=progress if data.points >= 100_000 else None)
    document = result.as_document()
    document["experiment"] = str(experiment.source)
    if args.output is not None:
        write_pam(args.output, result.fitted_pam(experiment.pam),
                  comments=result.pam_comments(experiment.source))
        document["output"] = str(args.output)
    emit(args, document, report(result, str(experiment.source)))
    if args.output is not None:
        say(args, f"wrote {args.output}")
    if args.plots:
        from pampipe.plots.identify import plot_identification

        for path in plot_identification(data, result, args.plots):
            say(args, f"wrote {path}")
    return 0


def report(result, source: str) -> str:
    """The human-readable fit report."""
    o, s, u = result.options, result.solver, result.uncertainty
    parts = [f"{source}: {o.mode} moduli, {o.objective.replace('_', ' ')} objective, degree {o.degree}, "
             f"{result.points:,} rows in {len(result.tests)} tests"
             + (" (legs averaged)" if o.average_legs else ""),
             f"IPOPT {s.status} after {s.iterations} iterations: solve {s.wall_time:.3g} s, NLP build "
             f"{s.build_time:.3g} s{' (cached)' if s.build_time == 0 else ''}, "
             f"data reduction {s.reduce_time:.3g} s"]
    rows = [(t.name, t.kind, t.points, t.rmse, max(lv.rmse for lv in t.levels),
             max(t.levels, key=lambda lv: lv.rmse).pressure / 1e3) for t in result.tests]
    parts.append("\nFit per test\n" + table(["test", "kind", "points", "RMSE [N]", "worst level [N]",
                                              "at [kPa]"], rows))
    parts.append("\nRMSE per pressure level [N]\n" + _level_table(result))
    parts.append(f"\nsum of RMSE over (test, pressure): {result.sum_rmse:.4g} N   least squares: "
                 f"{result.sse:.4g} N^2 (RMSE {result.rmse:.4g} N)   residual sigma {u.sigma:.4g} N")
    coeff = []
    for i, name in enumerate(result.names):
        interval = (f"[{u.lower[i]:.4g}, {u.upper[i]:.4g}]" if u.determined[i] else "not identifiable")
        coeff.append((name, result.x[i], interval, "yes" if u.at_bound[i] else ""))
    parts.append("\nCoefficients [MPa] with 95 % intervals\n"
                 + table(["coefficient", "value", "95 % interval", "at bound"], coeff))
    combos = []
    for c in u.combinations:
        if not c.identifiable:
            continue
        scale = np.max(np.abs(c.weights))  # normalised: largest weight 1, value in MPa
        top = np.argsort(np.abs(c.weights))[::-1][:3]
        terms = " ".join(f"{'+' if c.weights[j] >= 0 else '-'} {abs(c.weights[j]) / scale:.3g} "
                         f"{result.names[j]}" for j in top)
        combos.append((terms.lstrip("+ ").replace("1 ", "", 1), c.value / scale, 1.96 * c.std / scale))
    parts.append(f"\nIdentifiable combinations ({u.rank} of {len(result.names)}; largest three terms)\n"
                 + table(["combination", "value [MPa]", "+/- 95 % [MPa]"], combos))
    margin = ("not constrained" if o.drucker == "none"
              else f"{result.drucker_margin / 1e6:.4g} MPa (>= 0: stable) on the {o.drucker} grid")
    parts.append(f"\nDrucker margin: {margin}")
    parts += [f"warning: {w}" for w in result.warnings]
    return "\n".join(parts)


def _level_table(result) -> str:
    pressures = sorted({round(lv.pressure / 1e3, 1) for t in result.tests for lv in t.levels})
    lookup = {(t.name, round(lv.pressure / 1e3, 1)): lv.rmse for t in result.tests for lv in t.levels}
    rows = [[p, *(lookup.get((t.name, p), "") for t in result.tests)] for p in pressures]
    return table(["P [kPa]", *(t.name for t in result.tests)], rows)
