"""The muscle's bisections (a PAM with effects) and its contact pressure against independent answers
(issue 40): brentq on the full model's radial force for the largest load held at P and the least holding
pressure, and p_c = F_r/(D·L_p) with L_p from the braid's own numbers (L² + (NπD)² = B²,
B = L₀/cos α₀, Nπ = B·sin α₀/D₀: docs/physics.md §1-§2, §5.6)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.model.muscle import Muscle

EFFECTS = {"axial_preload": {"preload": 40.0, "pulley_friction": 0.1},
           "pressure_offset": {"offset": 12e3, "gain": 1.05}}


@pytest.fixture(scope="module")
def effects_muscle(radial_pam):
    return Muscle.from_pam(dataclasses.replace(radial_pam, effects=EFFECTS))


def cases(seed, count=12):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield (rng.uniform(150e3, 700e3), rng.uniform(0.0700, 0.0950), rng.uniform(0.15, 0.6),
               rng.choice([0.0, 0.5, 1.0]), rng.uniform(1.0, 3.0))


def margin(muscle, pressure, diameter, load, kappa, mu, sf):
    return mu * math.pi * float(muscle.radial_force(pressure, diameter, kappa * load)) - sf * load


def test_largest_load_with_effects_is_the_root_of_the_model(effects_muscle):
    """W_max(P) by the muscle's bisection = brentq of μπF_r(P, D, κW) = SF·W; −1 where nothing grips."""
    checked = 0
    below = [(60e3, 0.0889, 0.3, 1.0, 1.5), (90e3, 0.0889, 0.5, 0.0, 2.0)]  # below anchoring: F_r = 0
    for p, d, mu, kappa, sf in [*below, *cases(40)]:
        found = float(effects_muscle.largest_load(p, d, kappa=kappa, friction=mu, safety_factor=sf))
        if margin(effects_muscle, p, d, 0.0, kappa, mu, sf) <= 0:
            assert found == -1.0
            continue
        want = brentq(lambda w, a=(p, d, kappa, mu, sf): margin(effects_muscle, a[0], a[1], w, *a[2:]),
                      0.0, 1e7, xtol=1e-12, rtol=1e-14)
        assert found == pytest.approx(want, rel=1e-9), (p, d, mu, kappa, sf)
        checked += 1
    assert checked >= 8 and checked < 14


def test_least_holding_pressure_with_effects_is_the_root_of_the_model(effects_muscle):
    """P* by the muscle's bisection = brentq of μπF_r(P, D, κW) = SF·W from the anchoring pressure up;
    loads up to 400 N, so that most cases need more than the anchoring pressure (the bisection decides)."""
    beyond = 0
    loads = np.random.default_rng(42).uniform(20.0, 400.0, 12)
    for (_, d, mu, kappa, sf), load in zip(cases(41), loads, strict=True):
        found = float(effects_muscle.least_holding_pressure(d, load, kappa=kappa, friction=mu,
                                                            safety_factor=sf))
        start = max(float(effects_muscle.anchoring_pressure(d, kappa * load)), 0.0)
        if margin(effects_muscle, start, d, load, kappa, mu, sf) >= 0:
            want = start
        else:
            want = brentq(lambda x, a=(d, load, kappa, mu, sf): margin(effects_muscle, x, *a), start, 1e8,
                          xtol=1e-6, rtol=1e-13)
            beyond += 1
        assert found == pytest.approx(want, rel=1e-9, abs=1e-3), (d, mu, kappa, sf, load)
    assert beyond >= 6


def test_contact_pressure_is_the_radial_force_over_the_projected_area(radial_pam):
    """p_c = F_r/(D·L_p) [Pa]; L_p from the braid length B and turns N of the PAM file's geometry."""
    g = radial_pam.geometry
    braid = g.initial_length / math.cos(g.braid_angle)
    n_pi = braid * math.sin(g.braid_angle) / g.initial_diameter
    muscle = Muscle.from_pam(radial_pam)
    for d, radial in ((0.0762, 120.0), (0.0889, 340.0), (0.1, 55.5)):
        length = math.sqrt(braid**2 - (n_pi * d) ** 2)
        assert float(muscle.contact_pressure(radial, d)) == pytest.approx(radial / (d * length), rel=1e-12)
        assert float(muscle.contact_pressure(radial, d, paper_literal=True)) == pytest.approx(
            radial / (math.pi * d * length), rel=1e-12)
