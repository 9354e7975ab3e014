"""identify reaches the exact least-squares optimum (not IPOPT's tolerance above it).

The peer is scipy's bounded linear least squares (``lsq_linear``, BVLS, and ``least_squares``) on the
same rows, with the regressors of F_ax = offset + Φθ (linear in the moduli at the stated geometry,
docs/physics.md §4.3) and the same coefficient bounds; its SSE is known without pampipe's solver.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares, lsq_linear

from pampipe.identification import FitOptions, identify
from pampipe.model import forces
from tests.support.lab_data import axial, experiment, force_map, truth

MPA = 1e6


@pytest.fixture(scope="module")
def data(radial_pam):
    muscle = truth(radial_pam)
    g = radial_pam.geometry
    lengths = np.linspace(0.8, 0.98, 9) * g.initial_length
    columns = force_map(muscle, np.linspace(150e3, 600e3, 40), lengths, noise=3.0,
                        rng=np.random.default_rng(7))
    keep = columns["force"] > 0  # the peer fits the rows pampipe keeps with slack: exclude
    return experiment(radial_pam, [(axial("map"), {k: v[keep] for k, v in columns.items()})]), columns, keep


def peer_sse(data, columns, keep, degree, low, high):
    """Min Σ(offset + Φθ − F)² over the box, by BVLS and by trf; the smaller SSE."""
    offset, row = forces.axial_force_regressors(columns["pressure"][keep], columns["length"][keep],
                                                data.pam.geometry, degree, MPA)
    phi = np.column_stack([np.broadcast_to(np.asarray(t, float), offset.shape) for t in row]) * MPA
    target = columns["force"][keep] - offset
    k = degree + 1
    lower = np.array([low[0] if i in (0, 2 * k) else low[1] for i in range(4 * k)]) / MPA
    upper = np.array([high[0] if i in (0, 2 * k) else high[1] for i in range(4 * k)]) / MPA
    bvls = lsq_linear(phi, target, bounds=(lower, upper), method="bvls", tol=1e-15)
    start = np.clip(bvls.x, lower + 1e-9, upper - 1e-9)
    trf = least_squares(lambda t: phi @ t - target, start, jac=lambda t: phi, bounds=(lower, upper),
                        method="trf", x_scale="jac", ftol=1e-15, xtol=1e-15, gtol=1e-15)
    return min(float(np.sum(bvls.fun**2)), float(np.sum(trf.fun**2))), bvls.x


@pytest.mark.parametrize("degree", [1, 3])
def test_unconstrained_fit_reaches_the_least_squares_optimum(data, degree):
    experiment_, columns, keep = data
    result = identify(experiment_, FitOptions(degree=degree, drucker="none", slack="exclude"))
    peer, _ = peer_sse(experiment_, columns, keep, degree, (0.0, -50e6), (50e6, 50e6))
    assert result.sse <= peer * (1 + 1e-12)  # IPOPT alone stops 1e-11…1e-10 above it here
    assert result.sse >= peer * (1 - 1e-12)  # the same problem: not below the optimum either


def test_fit_with_coefficients_at_their_bounds_reaches_the_bounded_optimum(data):
    experiment_, columns, keep = data
    # tight bounds on the non-constant terms: some are active. Not tighter: at ±0.2 MPa the fitted model
    # goes negative on measured rows, and the slack hinge (docs/physics.md §6.2) makes it another problem
    low, high = (0.0, -0.5e6), (50e6, 0.5e6)
    result = identify(experiment_, FitOptions(degree=2, drucker="none", slack="exclude",
                                              bounds_constant=low[:1] + high[:1],
                                              bounds_other=(low[1], high[1])))
    peer, theta = peer_sse(experiment_, columns, keep, 2, low, high)
    assert np.sum(np.isclose(np.abs(theta), 0.5)) >= 1  # the peer's optimum has an active bound
    assert result.sse <= peer * (1 + 1e-12)  # IPOPT alone stops 1e-11…1e-10 above it here
    assert result.sse >= peer * (1 - 1e-12)


def test_with_active_drucker_rows_the_exact_solve_is_lower_than_ipopt_and_stays_stable(data, monkeypatch):
    """Drucker rows active (scipy has no general linear constraints): the exact solve ends on the
    constraint, no higher than IPOPT's own point, stable, and above the unconstrained optimum."""
    from pampipe.identification import exact

    experiment_, columns, keep = data
    options = FitOptions(degree=3, slack="exclude")
    polished = identify(experiment_, options)
    monkeypatch.setattr(exact, "applies", lambda structure: False)
    ipopt_only = identify(experiment_, options)
    unconstrained, _ = peer_sse(experiment_, columns, keep, 3, (0.0, -50e6), (50e6, 50e6))
    assert polished.drucker_minimum.stable
    assert unconstrained < polished.sse <= ipopt_only.sse
    assert abs(polished.drucker_minimum.value) < 1.0  # [Pa]: on the constraint, not inside it
    assert ipopt_only.drucker_minimum.value > 1e-3  # IPOPT stopped inside it
