"""One model, three evaluation paths (float, numpy array, CasADi Function), and exact derivatives."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from pampipe.model import braid, forces
from pampipe.model.muscle import Muscle, Structure


def test_float_array_and_casadi_paths_agree(radial_pam):
    """The same radial force from per-point floats, one numpy call and one CasADi Function call."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    rng = np.random.default_rng(0)
    pressures = rng.uniform(0, 7e5, 200)
    diameters = rng.uniform(0.06, 0.095, 200)
    loads = rng.uniform(-200, 1500, 200)
    floats = np.array([forces.radial_force(float(p), float(d), g, theta, 1e6, float(f))
                       for p, d, f in zip(pressures, diameters, loads, strict=True)])
    arrays = forces.radial_force(pressures, diameters, g, theta, 1e6, loads)
    sym = Muscle.symbolic(Structure("thick", 3))
    p, d, f = ca.SX.sym("p"), ca.SX.sym("d"), ca.SX.sym("f")
    function = ca.Function("radial", [p, d, f, sym.p], [sym.muscle.radial_force(p, d, f)])
    symbolic = np.asarray(function(pressures[None, :], diameters[None, :], loads[None, :],
                                   sym.pack(Muscle.from_pam(radial_pam)))).ravel()
    # identical operations in a different order (CasADi's VM vs numpy): agree to round-off
    np.testing.assert_allclose(arrays, floats, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(symbolic, floats, rtol=1e-9, atol=1e-7)
    assert np.any(floats == 0) and np.any(floats > 0)  # both sides of the contact switch are exercised


def test_axial_function_matches_regressor_form(radial_pam):
    """F_ax from the CasADi Function equals offset + φ·θ (the linear-in-θ form used by identify)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    rng = np.random.default_rng(1)
    theta = theta + rng.uniform(-2e5, 2e5, 16)
    sym = Muscle.symbolic(Structure("thick", 3))
    p, length_sym = ca.SX.sym("p"), ca.SX.sym("length")
    f = ca.Function("axial", [p, length_sym, sym.p], [sym.muscle.axial_force(p, length_sym)])
    parameters = Muscle(g, theta, 1e6).parameter_vector()
    for pressure, length in zip(rng.uniform(0, 7e5, 20), rng.uniform(0.22, 0.31, 20), strict=True):
        offset, row = forces.axial_force_regressors(pressure, length, g, 3)
        assert float(f(pressure, length, parameters)) == pytest.approx(offset + np.dot(row, theta), rel=1e-10)


def test_casadi_derivatives_match_finite_differences(radial_pam):
    """∂F_r/∂(P, D, F_a, θ) by AD against central differences (step chosen per variable, see below)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    p, d, f = ca.SX.sym("p"), ca.SX.sym("d"), ca.SX.sym("f")
    th = ca.SX.sym("th", 16)
    x = ca.vertcat(p, d, f, th)
    expr = forces.radial_force(p, d, g, th, 1e6, f)
    grad = ca.Function("grad", [x], [expr, ca.gradient(expr, x)])
    point = np.concatenate([[4e5, 0.08, 300.0], theta])
    value, exact = (np.asarray(v).ravel() for v in grad(point))
    assert value[0] > 0  # anchored: the max() is smooth here
    # steps ~ 1e-6 of each variable's scale: truncation O(h²) and round-off O(ε/h) both ≲ 1e-7 relative
    steps = np.concatenate([[1.0, 1e-8, 1e-3], np.full(16, 1.0)])
    numeric = np.empty_like(point)
    for i, h in enumerate(steps):
        up, down = point.copy(), point.copy()
        up[i] += h
        down[i] -= h
        numeric[i] = (float(grad(up)[0]) - float(grad(down)[0])) / (2 * h)
    np.testing.assert_allclose(exact, numeric, rtol=1e-5, atol=1e-9 * np.abs(exact).max())


def test_dl_dd_matches_finite_difference(radial_pam):
    """dL/dD = −(Nπ)²D/L against a central difference of L(D) (h = 1e-7 m)."""
    g = radial_pam.geometry
    for diameter in (0.065, 0.0762, 0.0889):
        h = 1e-7
        up, down = braid.length_at_diameter(diameter + h, g), braid.length_at_diameter(diameter - h, g)
        numeric = (up - down) / (2 * h)
        assert braid.dlength_ddiameter(diameter, g) == pytest.approx(numeric, rel=1e-7)


def test_angle_conventions_give_one_muscle():
    """β₀ from the transverse plane and α₀ = 90° − β₀ from the axis describe the same braid (B, N)."""
    from pampipe.model.pam import Geometry

    a = Geometry.from_transverse_angle(initial_length=0.314325, initial_diameter=0.05715,
                                       braid_angle_from_transverse=np.radians(65.92),
                                       bladder_thickness=0.003175)
    b = Geometry(0.314325, 0.05715, np.radians(24.08), 0.003175)
    assert a.braid_length == pytest.approx(b.braid_length, rel=1e-12)
    assert a.turns == pytest.approx(b.turns, rel=1e-12)


def test_smoothed_contact_switch_never_overflows(radial_pam):
    """softplus s·log(1 + e^(u/s)) stays finite for u/s ≫ 700 and tends to max(0, u) as s → 0."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    pressures = np.array([0.0, 50e3, 400e3, 7e5])
    exact = forces.radial_force(pressures, 0.0762, g, theta)
    smooth = forces.radial_force(pressures, 0.0762, g, theta, smoothing=1e-3)  # u/s up to ~1e7
    assert np.all(np.isfinite(smooth))
    # the softplus exceeds max(0, u) by at most s·log 2 (at u = 0), here 7e-4 N
    np.testing.assert_allclose(smooth, exact, rtol=0, atol=1e-3 * np.log(2) + 1e-9)
