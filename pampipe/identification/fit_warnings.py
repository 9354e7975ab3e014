"""The warnings of one fit (:mod:`.fit`): what the solve, the uncertainty, the Drucker check, the calibration
and the data leave for the user to know, as sentences."""

from __future__ import annotations

import math

from pampipe.identification.options import FitOptions
from pampipe.identification.result import Calibration


def fit_warnings(status, u, names, minimum, options, structure, calibration, stats, data,
              predictions) -> list[str]:
    out = []
    if status != "Solve_Succeeded":
        out.append(f"IPOPT stopped with {status}: the solution is acceptable but not fully converged.")
    if u.rank_deficient:
        out.append(f"the data determine only {u.rank} of {len(names)} parameter combinations; individual "
                   "coefficients without an interval are not identifiable from these tests "
                   "(docs/physics.md §6); see which predictions are determined, or add a prior (fit.prior).")
    bound = [name for name, flag in zip(names, u.at_bound, strict=True) if flag]
    if bound:
        out.append(f"at a bound: {', '.join(bound)} (intervals ignore the bound; consider fit.bounds"
                   + (" or fit.calibration_bounds" if any(b.startswith("geometry.") for b in bound) else "")
                   + ").")
    if minimum is not None and not minimum.stable:
        out.append(f"Drucker stability fails between the grid points: {minimum.direction} tangent modulus "
                   f"{minimum.value / 1e6:.4g} MPa at P = {minimum.pressure / 1e3:.4g} kPa, L = "
                   f"{minimum.length * 1e3:.5g} mm; refine fit.drucker_grid.")
    if options.mode == "per_pipe" and not (structure.qr or structure.cells):
        out.append("per_pipe without an axial test: the PAM file gets the first pipe's moduli; each pipe's "
                   "moduli are valid only in that pipe (see per_pipe in the JSON).")
    out += geometry_warnings(calibration, options)
    if calibration.search is not None and calibration.search.runner_ups():
        from pampipe.identification import multistart  # imported here: only a calibration searches

        best, other = calibration.search.best, calibration.search.runner_ups()[0]
        shown = ", ".join(f"{name} {value:.4g} {multistart.UNITS[name]}"
                          for name, value in zip(calibration.calibrated, other.geometry, strict=True))
        out.append(f"another local minimum fits almost as well (RMSE {other.rmse:.4g} N against "
                   f"{best.rmse:.4g} N) at {shown}: the data barely tell these geometries apart; a test that "
                   "separates them (a pressure ramp at the rest length, lengths closer to full contraction) "
                   "would, or state the geometry you trust and narrow fit.calibration_bounds.")
    unused = [name for name, *_ in options.calibration_bounds if name not in options.calibrate]
    if unused:
        out.append(f"fit.calibration_bounds for {', '.join(unused)} is not used: only calibrated entries "
                   "have bounds (add them to fit.calibrate or --calibrate).")
    judged = {pipe.pipe_diameter for pipe in predictions.pipes}
    outside = [d for d in options.pipe_diameters if d not in judged]
    if outside:
        g = calibration.geometry
        shown = ", ".join(f"{d * 1e3:.4g} mm" for d in outside)
        out.append(f"pipe diameter(s) {shown} of fit.pipe_diameters cannot be judged: the muscle touches "
                   f"only bores between its rest diameter "
                   f"{g.initial_diameter * 1e3:.4g} mm and {g.largest_diameter * 1e3:.4g} mm.")
    if stats.excluded:
        out.append(f"{stats.excluded} slack row(s) (force <= 0) were excluded from the fit (fit.slack: "
                   "exclude).")
    unknown = [t.name for t in data.tests if t.direction_source == "unknown"]
    if unknown:
        out.append(f"test(s) {', '.join(unknown)}: the rows are not in time order and there is no time or "
                   "direction column, so the loading/unloading legs are unknown (hysteresis effects cannot "
                   "be fitted).")
    return out


def geometry_warnings(calibration: Calibration, options: FitOptions) -> list[str]:
    out = []
    undetermined = [name for name, band in calibration.intervals.items() if band is None]
    if undetermined:
        out.append(f"the data do not determine the calibrated {' and '.join(undetermined)} (no 95 % "
                   "interval): the moduli can absorb the geometry; add a test at the rest length (a pressure "
                   "ramp at L0, where the force depends on the geometry alone) or calibrate less.")
    blocked = calibration.blocked_force
    if blocked is None:
        return out
    g = calibration.geometry
    if not blocked.consistent:
        words = (f"the blocked-force slope dF/dP at L = {blocked.length * 1e3:.5g} mm is "
                 f"{blocked.slope * 1e3:.4g} N/kPa in the data but {blocked.geometry_slope * 1e3:.4g} N/kPa "
                 f"for the {'calibrated' if options.calibrate else 'stated'} geometry (braid angle "
                 f"{math.degrees(g.braid_angle):.4g} deg from the axis, L0 = "
                 f"{g.initial_length * 1e3:.5g} mm)")
        if blocked.fitting_angle is not None:
            words += (f"; a braid angle of {math.degrees(blocked.fitting_angle):.4g} deg from the axis would "
                      "fit it (at this L0)")
        if not options.calibrate:
            words += "; calibrate it: --calibrate braid_angle --calibrate initial_length"
        out.append(words + ".")
    if blocked.has_threshold and "initial_length" not in options.calibrate:
        out.append(f"the muscle needs about {blocked.threshold / 1e3:.3g} kPa before it pulls at its longest "
                   f"tested length ({blocked.length * 1e3:.5g} mm), which the model cannot show at the "
                   "stated rest length: calibrate it (--calibrate initial_length) or diagnose prestrain.")
    return out
