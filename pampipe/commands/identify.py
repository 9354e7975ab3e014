"""`pampipe identify`: fit the bladder moduli to an experiment and write a PAM file."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from pampipe.commands.common import (
    add_output_options,
    add_report_option,
    add_units_option,
    emit,
    quantity_type,
    say,
    write_html_report,
)
from pampipe.errors import InputError
from pampipe.identification import identify
from pampipe.identification.grip import GripResult
from pampipe.identification.options import fit_options, parse_fit_options
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.files import check_output
from pampipe.model.uncertainty import SCALED_UNITS
from pampipe.runtime.heap import retain_freed_memory
from pampipe.runtime.progress import deferred, note
from pampipe.units.display import column, scaled
from pampipe.views.tables import table

NAME = "identify"
HELP = ("fit the bladder moduli to axial and radial test data (IPOPT, Drucker-stable, with uncertainty), and "
        "the wall friction and load coupling to slip tests")


#: Command-line flags that override the experiment file's ``fit:`` block, validated by the same schema.
FLAGS = {"mode": "--mode", "objective": "--objective", "degree": "--degree", "average_legs": "--average-legs",
         "drucker": "--drucker", "max_iterations": "--max-iterations", "slack": "--slack"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("experiment", type=Path, metavar="EXPERIMENT.yaml",
                        help="experiment file: the PAM, the tests (axial, radial, slip) and their CSV "
                             "data, an optional fit: block")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the PAM file with the fitted moduli: and uncertainty: blocks, and "
                             "with slip tests the measured contact: {friction, load_coupling, "
                             "pipe_material} block")
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
    parser.add_argument("--calibrate", action="append", metavar="NAME",
                        choices=("braid_angle", "initial_length", "bladder_thickness"),
                        help="fit this geometry with the moduli: braid_angle, initial_length or "
                             "bladder_thickness (repeatable; adds to fit.calibrate)")
    parser.add_argument("--slack", choices=("unilateral", "exclude"),
                        help="rows with force <= 0: the model predicts max(0, F) there (default), or they "
                             "are excluded (overrides fit.slack)")
    parser.add_argument("--pipe-diameter", action="append", metavar="D",
                        type=quantity_type("length"),
                        help="a pipe diameter where the report judges the radial-force prediction, e.g. "
                             "'3 in' (repeatable; adds to fit.pipe_diameters)")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)


def run(args: argparse.Namespace) -> int:
    experiment, options = validated(args.experiment)
    flags = {key: getattr(args, key) for key in FLAGS}
    if args.calibrate or args.pipe_diameter or any(value is not None for value in flags.values()):
        options = fit_options(experiment.fit, flags, calibrate=args.calibrate or (),
                              pipe_diameters=args.pipe_diameter or (), source=experiment.source,
                              where="command line", names=FLAGS)
    if args.output is not None:
        check_output(args.output, experiment.input_files, option="-o")
    if args.report is not None:
        check_output(args.report, experiment.input_files, option="--report")

    def progress(text: str) -> None:
        note(f"pampipe identify: {text}")

    retain_freed_memory()  # arrays of MBs per test, freed and made again: reuse them (pampipe.runtime.heap)
    data = load_experiment_data(experiment, progress=progress)
    with deferred() as later:  # below 10⁵ rows a step is noted only when it takes more than a second
        result = identify(data, options, progress=progress if data.points >= 100_000 else
                          lambda text: later(f"pampipe identify: {text}"))
    document = result.as_document()
    document["experiment"] = str(experiment.source)
    if args.output is not None:
        from pampipe.io.pamfile import write_pam

        _check_determined(result, experiment.source, args.output)
        write_pam(args.output, result.fitted_pam(experiment.pam),
                  comments=result.pam_comments(experiment.source))
        document["output"] = str(args.output)
    text = full_report(result, str(experiment.source))
    emit(args, document, text)
    write_html_report(args, "identify", inputs=[experiment.source, *experiment.input_files], text=text,
                      document=document, draw=lambda: _draw(data, result), warnings=result.warnings)
    if args.output is not None:
        say(args, f"wrote {args.output}")
    if args.plots:
        from pampipe.views.plots.identify import plot_identification

        if data.tests:
            for path in plot_identification(data, result, args.plots):
                say(args, f"wrote {path}")
        if result.slip is not None:
            from pampipe.views.plots.slip_tests import plot_slip

            for path in plot_slip(data.slip, result.slip, args.plots):
                say(args, f"wrote {path}")
    return 0


def validated(path: Path):
    """(the experiment, the options of its ``fit:`` block) of an experiment file: kept from a previous run
    while every file its validation read is unchanged (:mod:`pampipe.io.validated`: no YAML parse, no
    schema library), else validated and kept."""
    from pampipe.io.validated import cached, keep

    kept = cached("experiment", path)
    if kept is not None:
        return kept
    from pampipe.io.experiment_schema import load_experiment

    experiment = load_experiment(path)
    loaded = experiment, parse_fit_options(experiment.fit, source=experiment.source)
    keep("experiment", path, loaded, experiment.validated_files)
    return loaded


def result_text(result) -> str:
    """The report of `identify` (``str(result)``), headed by the experiment file."""
    return full_report(result, str(getattr(result, "experiment_source", "experiment")))


def full_report(result, source: str) -> str:
    """The moduli report (when the moduli were fitted) and the slip report (when there are slip tests)."""
    from pampipe.views.slip_text import slip_report

    if isinstance(result, GripResult):
        return (f"{source}: slip tests only; the moduli are those of the stated PAM\n"
                + slip_report(result.slip) + "".join(f"\nwarning: {w}" for w in result.warnings))
    text = report(result, source)
    if result.slip is None:
        return text
    return text + "\n" + slip_report(result.slip) + "".join(f"\nwarning: {w}" for w in result.slip.warnings)


def _check_determined(result, source, output) -> None:
    """Refuse to write a PAM from a fit that determines nothing: no coefficient and no pipe's anchoring
    pressure (e.g. one row per test). Its moduli are any of a family that fits as well, and `simulate`
    would print one of them as if measured (before: an anchoring pressure of -5830 kPa). Slip tests alone
    fit no moduli (the stated PAM's are written back with the grip), so there is nothing to check."""
    if isinstance(result, GripResult):
        return
    u = result.uncertainty
    if u.determined.any() or any(p.determined for p in result.predictions.pipes):
        return
    raise InputError(f"{source}: -o {output}: not written: the data determine none of the {len(u.names)} "
                     f"coefficients and no pipe's anchoring pressure ({u.rank} of {len(u.names)} "
                     "combinations identifiable), so the fitted moduli are one of many that fit as well. "
                     "Add tests or rows (the axial test over its pressure range, a radial test per bore), "
                     "or a prior (fit.prior); without -o the report shows which predictions are determined.")


def report(result, source: str) -> str:
    """The human-readable fit report."""
    o, s, u = result.options, result.solver, result.uncertainty
    cache = {"disk": " (loaded from the on-disk cache)", "built": ""}.get(s.origin, "")
    parts = [f"{source}: {o.mode} moduli, {o.objective.replace('_', ' ')} objective, degree {o.degree}, "
             f"{result.points:,} rows in {len(result.tests)} tests"
             + (" (legs averaged)" if o.average_legs else ""),
             f"IPOPT {s.status} after {s.iterations} iterations: solve {s.wall_time:.3g} s, NLP "
             + (f"build {s.build_time:.3g} s{cache}" if s.build_time else "reused")
             + f", data reduction {s.reduce_time:.3g} s"]
    rows = [(t.name, t.kind if t.kind == "radial" else t.protocol, t.points, t.slack, t.rmse,
             max(t.levels, key=lambda lv: lv.rmse).rmse if t.levels else "-",
             max(t.levels, key=lambda lv: lv.rmse).pressure / 1e3 if t.levels else "-") for t in result.tests]
    parts.append("\nFit per test\n" + table(["test", "protocol", "points", "slack rows", "RMSE [N]",
                                              "worst level [N]", "at [kPa]"], rows))
    if any(t.levels for t in result.tests):
        force, scale = scaled("N")
        parts.append(f"\nRMSE per pressure level [{force}]\n" + _level_table(result, scale))
    ramps = [t.name for t in result.tests if not t.levels]
    if ramps:
        parts.append(f"\nno pressure levels in {', '.join(ramps)} (pressure ramps): no per-level RMSE"
                     + ("" if result.sum_rmse is not None else ", and the sum of RMSE is undefined"))
    slack = int(sum(result.slack_rows))
    if slack:
        parts.append(f"slack rows (force <= 0): {slack}, "
                     + (f"{result.excluded_rows} excluded from the fit" if result.excluded_rows
                        else "fitted as max(0, F)"))
    total = f"sum of RMSE over (test, pressure): {result.sum_rmse:.4g} N   " if result.sum_rmse is not None \
        else ""
    force, to_force = scaled("N")
    parts.append(f"\n{total}least squares: {result.sse * to_force**2!r} {force}^2 (RMSE {result.rmse:.4g} "
                 f"N)   residual sigma {u.sigma:.4g} N")
    parts.append(_quality(result))
    parts.append(_geometry(result))
    coeff = []
    for i, name in enumerate(result.names):
        shown, k = _entry(name)
        interval = f"[{u.lower[i] * k:.4g}, {u.upper[i] * k:.4g}]" if u.determined[i] else "not identifiable"
        coeff.append((shown, result.x[i] * k, interval, "yes" if u.at_bound[i] else ""))
    parts.append(f"\nCoefficients [{_scaling()}] with 95 % intervals\n"
                 + table(["coefficient", "value", "95 % interval", "at bound"], coeff))
    parts.append(f"identifiable parameter combinations: {u.rank} of {len(result.names)} (listed in --json); "
                 "what that means for the forces:")
    parts.append(_predictions(result))
    parts.append(_written(result))
    parts.append(_drucker(result))
    parts += [f"warning: {w}" for w in result.warnings]
    return "\n".join(parts)


def _quality(result) -> str:
    """Each test's RMSE against its noise floor and whether its residuals are structured."""
    q = result.quality
    if q is None:
        return ""
    rows = [(t.test, t.rmse, "-" if t.floor is None else t.floor, "-" if t.ratio is None else t.ratio,
             "-" if t.runs_z is None else t.runs_z, "-" if t.lag1 is None else t.lag1,
             "STRUCTURED" if t.structured else "noise-like") for t in q.tests]
    ratio = q.rmse_over_floor
    head = ("\nFit quality: RMSE / noise floor " + ("unknown (too few rows along a path)" if ratio is None
                                                    else f"{ratio:.3g} (worst test; above 3 the fit is "
                                                    "warned about)"))
    return head + "\n" + table(["test", "RMSE [N]", "noise floor [N]", "RMSE/floor", "runs z",
                                "lag-1 autocorr.", "residuals"], rows)


def _geometry(result) -> str:
    c = result.calibration
    g, stated = c.geometry, c.stated
    lines = ["\nGeometry" + (f" (calibrated: {', '.join(c.calibrated)})" if c.calibrated else " (as stated)")]
    rows = []
    for name, label, value, before in (
            ("braid_angle", "braid angle from axis [deg]", math.degrees(g.braid_angle),
             math.degrees(stated.braid_angle)),
            ("initial_length", "rest length L0 [mm]", g.initial_length * 1e3, stated.initial_length * 1e3),
            ("bladder_thickness", "wall thickness [mm]", g.bladder_thickness * 1e3,
             stated.bladder_thickness * 1e3)):
        interval = c.intervals.get(name)
        shown = f"[{interval[0]:.5g}, {interval[1]:.5g}]" if interval else \
            ("undetermined" if name in c.calibrated else "-")
        label, cells = column(label, [before, value, shown])  # a row labelled with its unit
        rows.append((label, *cells))
    lines.append(table(["", "stated", "fitted", "95 % interval"], rows))
    if c.stated_rmse is not None:
        lines.append(f"RMSE at the stated geometry {c.stated_rmse:.4g} N, calibrated {result.rmse:.4g} N")
    if c.search is not None:
        lines += c.search.describe()
    b = c.blocked_force
    if b is not None:
        verdict = "consistent" if b.consistent else "MISMATCH"
        lines.append(f"blocked-force slope dF/dP at L = {b.length * 1e3:.5g} mm: data {b.slope * 1e3:.4g} "
                     f"N/kPa, geometry {b.geometry_slope * 1e3:.4g} N/kPa ({verdict})")
    else:
        lines.append(f"blocked-force check: not possible: {c.blocked_force_skipped or 'no usable rows'}")
    return "\n".join(lines)


def _predictions(result) -> str:
    p = result.predictions
    lines = []
    if p.regions:
        rows = [(r.name, f"{r.pressure[0] / 1e3:.4g}-{r.pressure[1] / 1e3:.4g}",
                 f"{r.length[0] * 1e3:.5g}-{r.length[1] * 1e3:.5g}", r.half_width,
                 "determined" if r.determined else "NOT determined") for r in p.regions]
        lines.append(table(["axial force F(P, L)", "P [kPa]", "L [mm]", "+/- 95 % [N]", "verdict"], rows))
    if p.pipes:
        rows = [(f"{q.pipe_diameter * 1e3:.4g} mm", "tested" if q.tested else ("inside" if q.inside
                 else "EXTRAPOLATION"), q.anchoring_pressure / 1e3, q.anchoring_half_width / 1e3,
                 q.radial_force, q.radial_half_width, "determined" if q.determined else "NOT determined")
                for q in p.pipes]
        top = p.pipes[0].pressure / 1e3
        lines.append(table(["pipe", "envelope", "anchoring [kPa]", "+/- [kPa]", f"F_r at {top:.4g} kPa [N]",
                            "+/- [N]", "verdict"], rows))
    return "\n".join(lines) if lines else "(no predictions: no axial test and no pipe)"


def _written(result) -> str:
    """The PAM file's uncertainty: block in words: the model error and the undetermined directions."""
    m, w = result.model_error, result.parameter_uncertainty
    if m is None or w is None:
        return ""
    how = (f"cross-validated over {len(m.bands)} pressure bands: held-out RMSE {m.cv_rmse:.3g} N, "
           f"{m.expected_rmse:.3g} N expected from noise and refit" if m.method == "pressure_bands"
           else f"in-sample RMSE {m.cv_rmse:.3g} N (one pressure: nothing to hold out)")
    lines = [f"\nModel error {m.value:.3g} N beyond the noise floor {m.noise_floor:.3g} N ({how})"]
    if w.prior_determined:
        lines.append(f"{len(w.prior_determined)} parameter direction(s) determined only by the prior "
                     f"({result.options.prior_source}): what depends on them rests on the prior, not on the "
                     "data (listed under uncertainty.prior_determined)")
    if not w.undetermined:
        lines.append("every other parameter direction is determined by the data")
        return "\n".join(lines)
    lines.append(f"{len(w.undetermined)} parameter direction(s) NOT determined by the data (zero variance in "
                 "the covariance; listed under uncertainty.undetermined). A plan that depends on them rests "
                 "on nothing until the named test or a prior (fit.prior) fixes them:")
    rows = []
    for k, d in enumerate(w.undetermined, 1):
        vector, width = _shown_direction(w.names, d.vector, d.scale)
        top = sorted(zip(w.names, vector, strict=True), key=lambda item: -abs(item[1]))[:3]
        force = {key: v for key, v in d.moves.items() if key.startswith("radial_force_N@")}
        worst = max(force, key=lambda key: abs(force[key]), default=None)
        anchoring = worst and d.moves.get(worst.replace("radial_force_N", "anchoring_pressure_Pa"))
        rows.append((k, ", ".join(f"{n} {v:+.2f}" for n, v in top), width,
                     "-" if worst is None else f"{float(worst.split('@')[1][:-1]) * 1e3:.4g} mm",
                     "-" if worst is None else f"{abs(force[worst]):.4g}",
                     "-" if anchoring is None else f"{abs(anchoring) / 1e3:.4g}", d.test))
    lines.append(table(["#", f"mostly (scaled: {_scaling(', ')})", "width left open", "bore", "moves F_r [N]",
                        "moves anchoring [kPa]", "test that would determine it"], rows))
    return "\n".join(lines)


def _entry(name: str) -> tuple[str, float]:
    """A decision-vector entry (MPa; geometry in deg or mm, named ``..._deg``, ``..._mm``) as the report
    shows it: its name (a length's suffix in the display unit) and the factor to the display units."""
    if name.endswith("_deg"):
        return name, 1.0
    if name.endswith("_mm"):
        unit, k = scaled("mm")
        return name.removesuffix("_mm") + f"_{unit}", k
    return name, scaled("MPa")[1]


def _scaling(between: str = "; geometry in ") -> str:
    """The units of the decision vector as shown: 'MPa; geometry in deg, mm' (metric)."""
    return f"{scaled('MPa')[0]}{between}deg, {scaled('mm')[0]}"


def _shown_direction(names, vector, width: float) -> tuple[list[float], float]:
    """An undetermined direction in the display units' scaling: the step ``width`` x ``vector`` (in
    scaled units: 1 MPa, 1 deg, 1 mm per entry) in display units, as its unit vector and its length."""
    factors = [scaled("deg" if n == "braid_angle" else "mm" if n in SCALED_UNITS and n != "moduli"
                      else "MPa")[1] for n in names]
    if all(f == 1.0 for f in factors):
        return list(vector), width
    step = [width * v * f for v, f in zip(vector, factors, strict=True)]
    length = math.sqrt(sum(s * s for s in step))
    return [s / length for s in step], length


def _drucker(result) -> str:
    m = result.drucker_minimum
    if m is None:
        return "\nDrucker stability: not constrained (fit.drucker: none)"
    where = f"at P = {m.pressure / 1e3:.4g} kPa, L = {m.length * 1e3:.5g} mm ({m.direction})"
    verdict = "stable" if m.stable else "UNSTABLE"
    return (f"\nDrucker: smallest {'tangent modulus' if m.direction != 'sum' else 'second-order work'} "
            f"{m.value / 1e6:.4g} MPa {where}, over the whole tested range (between grid points too): "
            f"{verdict}")


def _level_table(result, scale: float) -> str:
    """RMSE per test and pressure level, times ``scale`` (the display unit of force per newton)."""
    tests = [t for t in result.tests if t.levels]
    pressures = sorted({round(lv.pressure / 1e3, 1) for t in tests for lv in t.levels})
    lookup = {(t.name, round(lv.pressure / 1e3, 1)): lv.rmse * scale for t in tests for lv in t.levels}
    rows = [[p, *(lookup.get((t.name, p), "") for t in tests)] for p in pressures]
    return table(["P [kPa]", *(t.name for t in tests)], rows)


def _draw(data, result) -> None:
    """Every plot of `identify --plots` (into the current figure capture)."""
    from pampipe.views.plots.identify import plot_identification
    from pampipe.views.plots.slip_tests import plot_slip

    if data.tests:
        plot_identification(data, result, None)
    if result.slip is not None:
        plot_slip(data.slip, result.slip, None)
