"""Writing the fitted muscle as a PAM file (docs/formats.md §2) that `simulate` and `plan` read."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pampipe.identify.result import MPA, IdentifyResult
from pampipe.io.files import atomic_write_text
from pampipe.model.pam import Pam


def pam_yaml(base: Pam, result: IdentifyResult, *, source: Path | str) -> str:
    """YAML text: ``base``'s name and geometry, the fitted ``moduli:`` (MPa) and ``uncertainty:``.

    The covariance is that of θ = [axial.a, axial.b, hoop.a, hoop.b] in MPa², restricted to the
    identifiable combinations (see :mod:`pampipe.identify.uncertainty`).
    """
    g, m, u = base.geometry, result.moduli, result.uncertainty
    k = m.degree + 1
    lines = [f"# Written by `pampipe identify` from {source}",
             f"# mode {result.options.mode}, objective {result.options.objective}, degree {m.degree}; "
             f"IPOPT {result.status} in {result.solver.iterations} iterations",
             f"# RMSE {result.rmse:.4g} N over {result.points} rows; sum of RMSE per (test, pressure) "
             f"{result.sum_rmse:.4g} N; sigma {u.sigma:.4g} N",
             f"# identifiable parameter combinations: {u.rank} of {len(result.names)}"]
    if result.options.mode == "per_pipe":
        lines.append("# per_pipe: these are the muscle's (axial-test) moduli; the per-pipe sets are in the "
                     "JSON output")
    lines += [f"name: {base.name}", "geometry:",
              f"  initial_length: {_num(g.initial_length * 1e3)} mm",
              f"  initial_diameter: {_num(g.initial_diameter * 1e3)} mm",
              f"  braid_angle_from_axis: {_num(math.degrees(g.braid_angle))} deg",
              f"  bladder_thickness: {_num(g.bladder_thickness * 1e3)} mm",
              f"  wall: {g.wall}",
              "moduli:", "  unit: MPa", f"  reference_pressure: {_num(m.reference_pressure / 1e6)} MPa",
              f"  axial: {_law(m.axial_a, m.axial_b)}", f"  hoop: {_law(m.hoop_a, m.hoop_b)}"]
    if m.contact is not None:
        c = np.asarray(m.contact)
        lines += ["  contact:", f"    axial: {_law(c[:k], c[k:2 * k])}",
                  f"    hoop: {_law(c[2 * k:3 * k], c[3 * k:])}"]
    covariance = result.theta_covariance()
    if covariance is not None:
        lines += ["uncertainty:", "  unit: MPa", "  covariance:"]
        lines += [f"    - [{', '.join(_num(v) for v in row / MPA**2)}]" for row in covariance]
    return "\n".join(lines) + "\n"


def write_pam(target: Path, base: Pam, result: IdentifyResult, *, source: Path | str) -> None:
    """Write :func:`pam_yaml` to ``target`` atomically (the caller checks it is not an input)."""
    atomic_write_text(target, pam_yaml(base, result, source=source))


def _law(a, b) -> str:
    return (f"{{a: [{', '.join(_num(v / MPA) for v in a)}], "
            f"b: [{', '.join(_num(v / MPA) for v in b)}]}}")


def _num(value: float) -> str:
    return f"{float(value):.10g}"
