"""The text report of `pampipe identify`: the fit per test and per pressure level, its quality, the geometry,
the coefficients with their intervals, what they determine, and the slip tests (docs/commands.md §3).

Quantities are shown in the display units of ``--units`` (:mod:`pampipe.units.display`); the JSON stays SI.
"""

from __future__ import annotations

import math

from pampipe.model.uncertainty import SCALED_UNITS
from pampipe.units.display import column, counted, scaled
from pampipe.views.slip_text import slip_report
from pampipe.views.tables import table


def _source(result) -> str:
    return str(getattr(result, "experiment_source", "experiment"))


def result_text(result) -> str:
    """The report of `identify` (``str(result)`` of an IdentifyResult), headed by the experiment file."""
    return fit_report(result, _source(result))


def grip_text(result) -> str:
    """The report of `identify` on slip tests only (``str(result)`` of a GripResult)."""
    return grip_report(result, _source(result))


def grip_report(result, source: str) -> str:
    """Slip tests only: the stated PAM's moduli were kept; the slip report and the warnings."""
    return (f"{source}: slip tests only; the moduli are those of the stated PAM\n"
            + slip_report(result.slip) + "".join(f"\nwarning: {w}" for w in result.warnings))


def fit_report(result, source: str) -> str:
    """The moduli report and, when there are slip tests, the slip report."""
    text = report(result, source)
    if result.slip is None:
        return text
    return text + "\n" + slip_report(result.slip) + "".join(f"\nwarning: {w}" for w in result.slip.warnings)


def report(result, source: str) -> str:
    """The human-readable fit report."""
    o, s, u = result.options, result.solver, result.uncertainty
    cache = {"disk": " (loaded from the on-disk cache)", "built": ""}.get(s.origin, "")
    parts = [result.verdict,
             f"{source}: {o.mode} moduli, {o.objective.replace('_', ' ')} objective, degree {o.degree}, "
             f"{result.points:,} rows in {counted(len(result.tests), 'test')}"
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
    lengths = len(m.blocks) - len(m.bands)
    how = (f"cross-validated over {len(m.bands)} pressure bands" + (f" and {lengths} held lengths" if lengths
                                                                     else "")
           + f", each withheld in turn and refitted: held-out RMSE {m.cv_rmse:.3g} N (RMS over blocks)"
           if m.method == "held_blocks"
           else f"in-sample RMSE {m.cv_rmse:.3g} N (one pressure, no held lengths: nothing to hold out)")
    lines = [f"\nModel error {m.value:.3g} N ({m.dof} degrees of freedom) beyond the noise floor "
             f"{m.noise_floor:.3g} N ({how})"]
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
