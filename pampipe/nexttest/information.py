"""The Fisher information a test of the menu adds about a fitted muscle (docs/commands.md, next-test).

In scaled coordinates q (1 MPa, 1 deg, 1 mm: :mod:`pampipe.model.uncertainty`) over the PAM's
``uncertainty:`` names, a test that records the predictions y_r(q) in levels l (rows r of one level share a
set point) adds

    F = Σ_l J_lᵀ J_l / (σ_F²/n_l + σ_m²),   J_l = ∂y_l/∂q  (exact, CasADi),

σ_F the protocol's force noise (:class:`pampipe.simulation.synthetic.Protocol`, 2 N), n_l its rows per level,
σ_m the PAM's ``model_error`` [N] (a residual shared by the rows of a level: more rows do not average it).
Per kind, y at each pressure level P of the test:

* ``radial``: F_r(P; D, F_a), the rows of :attr:`Protocol.radial_points`;
* ``axial``: F_ax(P, L) at :data:`LENGTHS` lengths from the free length at P to L₀, each standing for its
  share of the cycles' rows (2 legs × points per leg × cycles);
* ``isometric``: F_ax(P, L) at the held length, :attr:`Protocol.radial_points` rows;
* ``slip``: ln F_slip = ln μ + ln(πF_r(P; D, F_a)), one row per trial, relative noise
  :attr:`SlipProtocol.scatter` (3 %); ln μ is a nuisance parameter with no prior, so the moduli gain the
  Schur complement F_θθ − F_θμ F_μμ⁻¹ F_μθ (a slip test alone fixes shapes of F_r, not its size). The
  load coupling κ is taken as known.

Rows below first contact (F_r = 0, or F_ax ≤ 0: a slack muscle) carry no information: their Jacobian is 0.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from pampipe.model.muscle import Muscle, Structure
from pampipe.model.uncertainty import scaled_unit
from pampipe.simulation.synthetic import Protocol
from pampipe.slip.synthetic_trials import SlipProtocol

#: Lengths per pressure level that stand for an axial test's cycles.
LENGTHS = 12


@cache
def _functions(structure: Structure):
    """CasADi (p, P, D, F_a) → (F_r, ∂F_r/∂p) and (p, P, L) → (F_ax, ∂F_ax/∂p)."""
    import casadi as ca

    sym = Muscle.symbolic(structure)
    pressure, diameter, load, length = (ca.SX.sym(n) for n in ("pressure", "diameter", "load", "length"))
    radial = sym.muscle.radial_force(pressure, diameter, load)
    axial = sym.muscle.axial_force(pressure, length)
    return (ca.Function("radial_jacobian", [sym.p, pressure, diameter, load],
                        [radial, ca.jacobian(radial, sym.p)]),
            ca.Function("axial_jacobian", [sym.p, pressure, length], [axial, ca.jacobian(axial, sym.p)]))


def predictions(muscle: Muscle, test) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(y (m,) [N], ∂y/∂p (m, size) in the muscle's layout, rows each stands for (m,)) of a menu ``test``."""
    radial, axial = _functions(muscle.structure)
    p = muscle.parameter_vector()
    pressures = np.asarray(test.pressures, dtype=float)
    protocol = Protocol()
    if test.kind in ("radial", "slip"):
        f = radial.map(pressures.size)
        value, jac = f(p, pressures[None, :], test.pipe_diameter, test.axial_load)
        per_level = protocol.radial_points if test.kind == "radial" else test.trials
        rows = np.full(pressures.size, float(per_level))
    elif test.kind == "isometric":
        value, jac = axial.map(pressures.size)(p, pressures[None, :], test.length)
        rows = np.full(pressures.size, float(protocol.radial_points))
    else:
        free = np.asarray(muscle.free_length(pressures), dtype=float)
        length = muscle.geometry.initial_length
        grid = free[:, None] + (length - free)[:, None] * (np.arange(LENGTHS) + 0.5) / LENGTHS
        level_p = np.repeat(pressures, LENGTHS)
        value, jac = axial.map(level_p.size)(p, level_p[None, :], grid.ravel()[None, :])
        share = 2 * protocol.points_per_leg * protocol.cycles / LENGTHS
        rows = np.full(level_p.size, share)
    value = np.asarray(value, dtype=float).ravel()
    jac = np.asarray(jac, dtype=float).reshape(value.size, -1) if value.size else np.zeros((0, p.size))
    if jac.shape[0] != value.size:  # a mapped Jacobian comes as (1, m·size)
        jac = jac.reshape(value.size, p.size)
    live = value > 0
    return value, np.where(live[:, None], jac, 0.0), rows


def fisher(muscle: Muscle, uncertainty, test) -> np.ndarray:
    """F (k, k) [1/scaled unit²] of ``test`` over the ``uncertainty``'s names (module docstring)."""
    layout = muscle.structure.names()
    index = [layout.index(name) for name in uncertainty.names]
    units = np.array([scaled_unit(name) for name in uncertainty.names])
    value, jac, rows = predictions(muscle, test)
    j = jac[:, index] * units  # ∂y/∂q
    if test.kind == "slip":
        with np.errstate(divide="ignore", invalid="ignore"):
            j = np.where(value[:, None] > 0, j / value[:, None], 0.0)  # ∂ ln F_r/∂q
        weight = rows / SlipProtocol(pipes=()).scatter ** 2
        nuisance = (value > 0).astype(float)  # ∂ ln F_slip/∂ ln μ
        full = np.column_stack([j, nuisance]) * np.sqrt(weight)[:, None]
        info = full.T @ full
        tail = info[-1, -1]
        schur = info[:-1, -1:] @ info[-1:, :-1] / tail if tail > 0 else 0.0
        return info[:-1, :-1] - schur
    variance = Protocol().force_noise ** 2 / rows + uncertainty.model_error ** 2
    weighted = j / np.sqrt(variance)[:, None]
    return weighted.T @ weighted
