"""`pampipe diagnose`: where the model and the data disagree, the missing effect, the gap before and after."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, emit, integer_type, say
from pampipe.diagnose.selection import FOLDS
from pampipe.io.config import load_experiment
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.files import check_output
from pampipe.io.pamfile import write_pam
from pampipe.model.effects import LIBRARY, get_effect
from pampipe.report import table

NAME = "diagnose"
HELP = "name the effect missing from the model of an experiment, refit with it, show the gap shrink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("experiment", type=Path, metavar="EXPERIMENT.yaml",
                        help="experiment file (docs/formats.md §3): a PAM and its axial and radial tests")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the augmented PAM file (refitted moduli: and the selected effects: "
                             "block), "
                             "which `simulate` and `plan` use")
    parser.add_argument("--effect", action="append", choices=list(LIBRARY), metavar="NAME",
                        help="test only this effect (repeatable; default: all of "
                             f"{', '.join(LIBRARY)})")
    parser.add_argument("--folds", type=integer_type("--folds", ge=2), default=FOLDS, metavar="K",
                        help=f"cross-validation folds across pressure levels (default {FOLDS})")
    add_output_options(parser)
    parser.epilog = ("Effects (docs/physics.md §9): "
                     + "; ".join(f"{e.name}: {e.summary}" for e in LIBRARY.values())
                     + ". Exit codes: 0 success (including 'none'), 2 bad input, 3 solver failure.")


def run(args: argparse.Namespace) -> int:
    from pampipe.diagnose.workflow import diagnose

    experiment = load_experiment(args.experiment)
    if args.output is not None:
        check_output(args.output, experiment.input_files, option="-o")
    data = load_experiment_data(experiment, progress=lambda text: say_err(args, text))
    result = diagnose(data, effects=args.effect, folds=args.folds, progress=lambda text: say_err(args, text))
    emit(args, result.as_document(), report(result))
    if args.output is not None:
        write_pam(args.output, result.augmented_pam(),
                  comments=[f"Written by `pampipe diagnose` from {experiment.source}.",
                            "Moduli refitted in shared mode together with the selected effect: "
                            f"{result.selected}."])
        say(args, f"wrote {args.output}")
    if args.plots:
        from pampipe.plots.diagnose import plot_diagnosis

        for path in plot_diagnosis(result, args.plots):
            say(args, f"wrote {path}")
    return 0


def say_err(args, text: str) -> None:
    """Progress goes to stderr whatever the output mode."""
    import sys

    print(f"diagnose: {text}", file=sys.stderr, flush=True)


def _parameters(candidate) -> str:
    if candidate.effect == "none":
        return "-"
    cells = []
    for p in get_effect(candidate.effect).parameters:
        value = candidate.parameters[p.name] / p.scale
        low, high = (v / p.scale for v in candidate.intervals[p.name])
        unit = "" if p.unit == "-" else f" {p.unit}"
        cells.append(f"{p.name} = {value:.4g}{unit} [{low:.4g}, {high:.4g}]")
    return "; ".join(cells)


def report(result) -> str:
    """The human-readable report: noise, signatures, regions, candidates, decision, before/after."""
    base, chosen = result.baseline, result.chosen
    noise = {n.test: n for n in result.noise}
    parts = [f"{result.source}: {sum(t.points for t in base.tests):,} rows in {len(base.tests)} tests; "
             f"baseline = shared moduli ({result.baseline_source}), sum of test RMSE {base.sum_rmse:.4g} N"]
    parts.append("Where the baseline disagrees (RMSE against the noise floor from repeated points):\n"
                 + table(
        ["test", "kind", "points", "noise floor [N]", "RMSE [N]", "RMSE/floor"],
        [(t.name, t.kind, t.points, noise[t.name].sigma, t.rmse, t.rmse / noise[t.name].sigma)
         for t in base.tests]))
    hints = {}
    for e in LIBRARY.values():
        hints.setdefault(e.signature, []).append(e.name)
    parts.append("Residual signatures (score ~ N(0,1) for pure noise; large = systematic):\n" + table(
        ["signature", "fitted RMS [N]", "score", "points to"],
        [(s.name, s.rms, s.score, ", ".join(hints.get(s.name, ["(any)"]))) for s in result.signatures]))
    parts.append("Largest systematic residuals (mean of model - data per cell):\n" + table(
        ["test", "P [kPa]", "L [mm] / state", "rows", "mean [N]", "RMSE [N]", "score"],
        [(r.test, f"{r.pressure[0] / 1e3:.0f}-{r.pressure[1] / 1e3:.0f}",
          (f"{r.length[0] * 1e3:.1f}-{r.length[1] * 1e3:.1f}" if r.length is not None
           else ("anchored" if r.anchored else "free")), r.rows, r.mean, r.rmse, r.score)
         for r in result.regions]))
    rows = [(i + 1, c.effect, c.delta_bic, "-" if c.cv_rmse is None else f"{c.cv_rmse:.4g}", c.sum_rmse,
             _parameters(c), c.wall_time) for i, c in enumerate(result.candidates)]
    parts.append(f"Candidates, ranked by BIC (baseline CV RMSE {base.cv_rmse:.4g} N):\n" + table(
        ["rank", "effect", "dBIC", "CV RMSE [N]", "sum RMSE [N]", "parameters [95 % interval]", "time [s]"],
        rows))
    decision = f"Selected: {result.selected} ({result.reason})."
    if result.confounded_with:
        decision += f" Caution: {result.confounded_with} explains the data almost as well (confounded)."
    if result.selected != "none":
        decision += f"\n  {get_effect(result.selected).summary}; parameters: {_parameters(chosen)}"
    parts.append(decision)
    after = {t.name: t.rmse for t in chosen.tests}
    parts.append("RMSE per test, before and after the refit:\n" + table(
        ["test", "before [N]", "after [N]", "noise floor [N]", "after/floor"],
        [(t.name, t.rmse, after[t.name], noise[t.name].sigma, after[t.name] / noise[t.name].sigma)
         for t in base.tests])
        + f"\nimprovement (1 - after/before, sum of test RMSE): {result.improvement:.1%}; "
        f"total time {result.timings['total_wall_time_s']:.1f} s")
    return "\n\n".join(parts)
