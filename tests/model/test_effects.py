"""The effect library (docs/physics.md §9): exact null reduction, closed forms, two evaluation paths,
PAM files."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
import yaml

from pampipe.errors import InputError
from pampipe.io.pam_schema import load_pam
from pampipe.model import braid, forces
from pampipe.model.effects import (
    LIBRARY,
    axial_force_with_effects,
    radial_force_with_effects,
)
from pampipe.model.muscle import Muscle
from pampipe.simulation.anchored import simulate_anchored
from tests.support.problems import PROBLEMS

PRESSURES = np.linspace(0.0, 689e3, 12)
LENGTHS = np.linspace(0.215, 0.31, 9)
PIPES = (0.0762, 0.0889)
LOADS = (0.0, 1024.74)
#: Non-null values used by the checks below (SI).
VALUES = {"braid_friction": {"f0": 8.0, "f1": 20e-6}, "braid_extensibility": {"compliance": 0.5e-6},
          "end_effects": {"volume_taper": 0.05, "end_length": 0.4},
          "contact_stiffening": {"axial_increment": 0.4e6, "hoop_increment": 0.7e6},
          "pressure_offset": {"offset": 9e3, "gain": 1.03}, "axial_preload": {"preload": 55.0,
                                                                             "pulley_friction": 0.05},
          "wall_friction": {"lock": 0.01}, "pressure_hysteresis": {"h0": 6.0, "h1": 15e-6},
          "prestrain": {"axial_prestrain": -0.004, "hoop_prestrain": 0.012}}


def test_every_effect_has_values_here():
    assert set(VALUES) == set(LIBRARY)


@pytest.mark.parametrize("name", list(LIBRARY))
def test_null_value_is_exactly_the_baseline(radial_pam, name):
    """At its null value every effect returns the baseline bit for bit (no tolerance)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    null = {name: {}}
    for leg in (-1.0, 1.0):
        for pressure_leg in (-1.0, 0.0, 1.0):
            assert np.array_equal(axial_force_with_effects(4e5, LENGTHS, g, theta, 1e6, null, leg=leg,
                                                           pressure_leg=pressure_leg),
                                  forces.axial_force(4e5, LENGTHS, g, theta, 1e6))
    for d in PIPES:
        for load in LOADS:
            assert np.array_equal(radial_force_with_effects(PRESSURES, d, g, theta, 1e6, load, None, null),
                                  forces.radial_force(PRESSURES, d, g, theta, 1e6, load))


@pytest.mark.parametrize("name", list(LIBRARY))
def test_symbolic_path_equals_numeric_path(radial_pam, name):
    """CasADi SX graph and numpy arrays give the same forces (1e-9 relative: round-off only)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    p, x, load = ca.SX.sym("p"), ca.SX.sym("x"), ca.SX.sym("load")
    symbols = {k: ca.SX.sym(k) for k in VALUES[name]}
    active = {name: symbols}
    f_ax = ca.Function("f", [p, x, *symbols.values()],
                       [axial_force_with_effects(p, x, g, theta, 1e6, active, leg=1.0)])
    f_r = ca.Function("f", [p, x, load, *symbols.values()],
                      [radial_force_with_effects(p, x, g, theta, 1e6, load, None, active)])
    values = list(VALUES[name].values())
    numeric = axial_force_with_effects(4e5, LENGTHS, g, theta, 1e6, {name: VALUES[name]}, leg=1.0)
    symbolic = np.array([float(f_ax(4e5, length, *values)) for length in LENGTHS])
    np.testing.assert_allclose(symbolic, numeric, rtol=1e-9, atol=1e-9)
    numeric = radial_force_with_effects(PRESSURES, 0.0889, g, theta, 1e6, 1024.74, None, {name: VALUES[name]})
    symbolic = np.array([float(f_r(pr, 0.0889, 1024.74, *values)) for pr in PRESSURES])
    np.testing.assert_allclose(symbolic, numeric, rtol=1e-9, atol=1e-9)


def test_braid_friction_adds_the_coulomb_band(radial_pam):
    """§9a: F = F_ax + sgn(L̇)(f₀ + f₁P) on the free muscle; nothing in the pipe (quiescent)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    v = VALUES["braid_friction"]
    base = forces.axial_force(3e5, LENGTHS, g, theta)
    for leg in (-1.0, 1.0):
        got = axial_force_with_effects(3e5, LENGTHS, g, theta, 1e6, {"braid_friction": v}, leg=leg)
        np.testing.assert_allclose(got - base, leg * (8.0 + 20e-6 * 3e5), rtol=1e-12)
    np.testing.assert_array_equal(
        radial_force_with_effects(PRESSURES, 0.0762, g, theta, 1e6, 0.0, None, {"braid_friction": v}),
        forces.radial_force(PRESSURES, 0.0762, g, theta))


def test_pressure_hysteresis_adds_the_band_against_the_pressure_rate(radial_pam):
    """§9k: F = F_ax − sgn(Ṗ)(h₀ + h₁P): venting (−1) above filling (+1) by 2(h₀ + h₁P); the leg of L
    and the anchored muscle are untouched."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    v = {"pressure_hysteresis": VALUES["pressure_hysteresis"]}
    base = forces.axial_force(3e5, LENGTHS, g, theta)
    for pressure_leg in (-1.0, 1.0):
        for leg in (-1.0, 1.0):
            got = axial_force_with_effects(3e5, LENGTHS, g, theta, 1e6, v, leg=leg, pressure_leg=pressure_leg)
            np.testing.assert_allclose(got - base, -pressure_leg * (6.0 + 15e-6 * 3e5), rtol=1e-12)
    muscle = Muscle(g, theta, 1e6, effects=v)
    venting, filling = (muscle.axial_force(3e5, LENGTHS, pressure_leg=s) for s in (-1.0, 1.0))
    band = venting - filling
    np.testing.assert_allclose(band, 2 * (6.0 + 4.5), rtol=1e-12)
    np.testing.assert_array_equal(radial_force_with_effects(PRESSURES, 0.0762, g, theta, 1e6, 0.0, None, v),
                                  forces.radial_force(PRESSURES, 0.0762, g, theta))


def test_prestrain_with_constant_moduli_needs_the_hand_computed_threshold_pressure(radial_pam):
    """§9j with pressure-independent constant moduli (σ = Eε): ΔF = E₁ε₁,pre V_b/L − E₂ε₂,pre·lever₂ at
    every length, so at L₀ (no strain) the muscle pulls only above P_th = (E₂ε₂,pre lever₂ −
    E₁ε₁,pre V_b/L₀)/area(L₀), computed here from the Eq. 9 levers by hand."""
    g = radial_pam.geometry
    e1, e2 = 1.5e6, 4.0e6
    theta = np.array([e1, 0, 0, 0, e2, 0, 0, 0], dtype=float)  # degree 1: a = [E, 0], b = [0, 0]
    pre = {"axial_prestrain": 0.002, "hoop_prestrain": 0.02}
    muscle = Muscle(g, theta, 1e6, effects={"prestrain": pre})
    _, lever1, lever2 = forces.axial_levers(LENGTHS, g)
    expected = e1 * 0.002 * lever1 - e2 * 0.02 * lever2
    np.testing.assert_allclose(muscle.axial_force(2e5, LENGTHS) - forces.axial_force(2e5, LENGTHS, g, theta),
                               expected, rtol=1e-10)
    area0, lever1_0, lever2_0 = (float(v) for v in forces.axial_levers(g.initial_length, g))
    threshold = (e2 * 0.02 * lever2_0 - e1 * 0.002 * lever1_0) / area0
    assert threshold > 10e3  # a real threshold: tens of kPa
    assert float(muscle.axial_force(threshold, g.initial_length)) == pytest.approx(0.0, abs=1e-9)
    assert float(Muscle(g, theta, 1e6).axial_force(threshold, g.initial_length)) > 0  # baseline pulls at once


def test_axial_preload_shifts_force_and_anchoring_by_the_closed_forms(radial_pam):
    """§9g: F_r shifts by −A·F_a,eff change and P_anchor by ΔF_a/∂_P F_ax (docs/physics.md §5.8, §7)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    v = VALUES["axial_preload"]
    for d in PIPES:
        for load in LOADS:
            extra = load * v["pulley_friction"] + v["preload"]
            amp = braid.amplification_factor(d, g)
            high = PRESSURES[PRESSURES > 3e5]
            got = radial_force_with_effects(high, d, g, theta, 1e6, load, None, {"axial_preload": v})
            np.testing.assert_allclose(got, forces.radial_force(high, d, g, theta, 1e6, load) - amp * extra,
                                       rtol=1e-12)
            _, slope = forces.axial_force_affine(braid.length_at_diameter(d, g), g, theta)
            anchor = Muscle(g, theta, 1e6, effects={"axial_preload": v}).anchoring_pressure(d, load)
            # bisection to 1e8/2^80 Pa; the closed form is exact
            assert anchor == pytest.approx(forces.anchoring_pressure(d, g, theta, 1e6, load) + extra / slope,
                                           abs=1e-3)


def test_wall_friction_divides_by_one_plus_lock_pi_a(radial_pam):
    """§9f: F_r = A(F_ax − F_a)/(1 + λμ_wπA)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    amp = braid.amplification_factor(0.0889, g)
    got = radial_force_with_effects(PRESSURES, 0.0889, g, theta, 1e6, 0.0, None,
                                    {"wall_friction": {"lock": 0.01}})
    expected = forces.radial_force(PRESSURES, 0.0889, g, theta) / (1 + 0.01 * math.pi * amp)
    np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_pressure_offset_evaluates_the_model_at_the_true_pressure(radial_pam):
    """§9e: the force at P_meas is the baseline force at g_P·P_meas + P_off."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    v = VALUES["pressure_offset"]
    true = 1.03 * PRESSURES + 9e3
    np.testing.assert_allclose(
        radial_force_with_effects(PRESSURES, 0.0762, g, theta, 1e6, 0.0, None, {"pressure_offset": v}),
        forces.radial_force(true, 0.0762, g, theta), rtol=1e-12)
    np.testing.assert_allclose(
        axial_force_with_effects(2e5, LENGTHS, g, theta, 1e6, {"pressure_offset": v}),
        forces.axial_force(1.03 * 2e5 + 9e3, LENGTHS, g, theta), rtol=1e-12)


def test_contact_stiffening_equals_the_models_contact_increments(radial_pam):
    """§9d: the same as muscle.radial_force with contact Δθ = [ΔE₁, 0.., ΔE₂, 0..] (another code path)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    v = VALUES["contact_stiffening"]
    delta = np.zeros(16)
    delta[0], delta[8] = v["axial_increment"], v["hoop_increment"]
    for d in PIPES:
        for load in LOADS:
            np.testing.assert_allclose(
                radial_force_with_effects(PRESSURES, d, g, theta, 1e6, load, None, {"contact_stiffening": v}),
                forces.radial_force(PRESSURES, d, g, theta, 1e6, load, delta), rtol=1e-12, atol=1e-9)


def test_end_effect_volume_term_is_virtual_work_of_the_tapered_volume(radial_pam):
    """§9c: ΔF_ax = −P d(ΔV)/dL along the braid, ΔV = −πc_vD(L)³/4 (central difference, h = 1 µm)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    c_v, h, pressure = 0.05, 1e-6, 4e5

    def extra_volume(length):
        return -math.pi * c_v * braid.diameter_at_length(length, g) ** 3 / 4

    expected = -pressure * (extra_volume(LENGTHS + h) - extra_volume(LENGTHS - h)) / (2 * h)
    got = (axial_force_with_effects(pressure, LENGTHS, g, theta, 1e6, {"end_effects": {"volume_taper": c_v}})
           - forces.axial_force(pressure, LENGTHS, g, theta))
    np.testing.assert_allclose(got, expected, rtol=1e-6)  # O(h²) truncation of the difference


def test_braid_extensibility_satisfies_the_stretched_kinematics(radial_pam):
    """§9b: in the pipe, L = √(B₀²(1 + c_B T)² − (NπD)²) with T cos α = PπR_i² − σ₁V_b/L + F_a.

    The fixed point is iterated 3 times; the residual of the kinematic equation must be below
    1e-4 mm (c_B T ≈ 2e-3, so the error contracts by ~1e-3 per iteration), and the force must grow
    with c_B as the muscle gets longer (more pressure area)."""
    from pampipe.model.bladder import split_moduli, strains, stress
    from pampipe.model.forces import bladder_volume, wall_section

    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    c_b, d, load, pressure = 0.5e-6, 0.0762, 1024.74, 6e5
    b0, n_pi = braid.braid_length(g), braid.turns(g) * math.pi
    length = b0 * 0 + braid.length_at_diameter(d, g)
    for _ in range(50):  # converge independently, far beyond the model's 3 iterations
        _, r_i, _ = wall_section(length, g, d)
        a1, b1, _, _ = split_moduli(theta)
        sigma1 = stress(strains(length, d, g)[0], pressure, a1, b1, 1e6)
        tension = (pressure * math.pi * r_i**2 - sigma1 * bladder_volume(g) / length + load) * b0 / length
        length = math.sqrt((b0 * (1 + c_b * tension)) ** 2 - (n_pi * d) ** 2)
    amp = 2 * math.pi * braid.turns(g) ** 2 * d / length
    expected = amp * (forces.axial_force(pressure, length, g, theta, diameter=d) - load)
    got = radial_force_with_effects(pressure, d, g, theta, 1e6, load, None,
                                    {"braid_extensibility": {"compliance": c_b}})
    assert got == pytest.approx(expected, rel=1e-6)
    assert length > braid.length_at_diameter(d, g)


# ------------------------------------------------------------------------------- PAM files
def _pam_with(tmp_path, effects) -> object:
    raw = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    raw["effects"] = effects
    path = tmp_path / "pam.yaml"
    path.write_text(yaml.safe_dump(raw))
    return path


def test_pam_file_effects_block_with_units(tmp_path):
    pam = load_pam(_pam_with(tmp_path, {"braid_friction": {"f0": "12 N", "f1": "30 N/MPa"},
                                        "pressure_offset": {"offset": "1.2 psi"}}))
    assert pam.effects["braid_friction"] == pytest.approx({"f0": 12.0, "f1": 30e-6})
    assert pam.effects["pressure_offset"]["offset"] == pytest.approx(1.2 * 6894.757, rel=1e-6)


@pytest.mark.parametrize(("effects", "words"), [
    ({"braid_fricton": {"f0": "1 N"}}, ["unknown effect 'braid_fricton'", "braid_friction"]),
    ({"braid_friction": {"f2": "1 N"}}, ["unknown parameter 'f2'", "f0, f1"]),
    ({"braid_friction": {"f0": "1 kPa"}}, ["effects.braid_friction.f0", "not a force"]),
    ({"wall_friction": {"lock": 3}}, ["effects.wall_friction.lock", "[0, 1]"]),
])
def test_pam_file_effects_errors_name_key_value_and_allowed(tmp_path, effects, words):
    path = _pam_with(tmp_path, effects)
    with pytest.raises(InputError) as info:
        load_pam(path)
    for word in words:
        assert word in str(info.value)
    assert str(path) in str(info.value)


def test_simulate_uses_the_effects_of_the_pam(tmp_path, radial_pam):
    """`simulate` with an axial preload: F_r drops by A·F₀ and P_anchor rises by F₀/∂_P F_ax."""
    pam = load_pam(_pam_with(tmp_path, {"axial_preload": {"preload": "50 N"}}))
    plain = simulate_anchored(Muscle.from_pam(radial_pam), pipe_diameter=0.0762, pressures=[4e5, 6e5])
    loaded = simulate_anchored(Muscle.from_pam(pam), pipe_diameter=0.0762, pressures=[4e5, 6e5])
    np.testing.assert_allclose(plain.radial_force - loaded.radial_force, plain.amplification_factor * 50.0,
                               rtol=1e-9)
    _, slope = forces.axial_force_affine(plain.anchored_length, radial_pam.geometry,
                                         radial_pam.moduli.as_vector())
    assert loaded.anchoring_pressure - plain.anchoring_pressure == pytest.approx(50.0 / slope, abs=1e-3)
