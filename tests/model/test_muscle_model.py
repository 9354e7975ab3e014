"""The muscle's own answers against independent ones (issue 40; the first target of ``make mutate`` for
model/muscle.py, so that most of its mutants die in seconds):

* P* and W_max of the fast path (closed forms, with and without contact increments) and of the effects
  path (bisection) against a brute-force scan of the model's holding margin μπF_r(P, D, κW) − SF·W,
  narrowed by brentq inside the scanned cell;
* the free length against brentq of F_ax(P, L) = F_a between L₀ and B/√3 (contractile and extensile);
* the symbolic muscle against the numeric one, its parameter layout, its name and its errors (the
  unknown effect an InputError — exit 2 at the CLI — naming it and the known ones, not a traceback).

The forces themselves are checked against hand equations in tests/model/test_forces.py."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.errors import InputError, SolverError
from pampipe.model import effects as effects_library
from pampipe.model.muscle import Muscle, Structure
from pampipe.model.pam import Geometry

EFFECTS = {"axial_preload": {"preload": 40.0, "pulley_friction": 0.1},
           "pressure_offset": {"offset": 12e3, "gain": 1.05}}
#: Δθ [Pa] in θ's order [axial a, axial b, hoop a, hoop b] × 4: a stiffer hoop once pressed on the wall
CONTACT = np.array([2e5, 0, 0, 0, 0, 0, 0, 0, 6e5, 0, 0, 0, 1e5, 0, 0, 0])


@pytest.fixture(scope="module")
def plain(radial_pam):
    return Muscle.from_pam(radial_pam)


@pytest.fixture(scope="module")
def touching(plain):
    """The radial muscle with contact increments (docs/physics.md §9d)."""
    return Muscle(plain.geometry, plain.theta, plain.reference_pressure, contact=CONTACT, name="touching")


@pytest.fixture(scope="module")
def with_effects(radial_pam):
    return Muscle.from_pam(dataclasses.replace(radial_pam, effects=EFFECTS))


def margin(muscle, pressure, diameter, load, kappa, mu, sf):
    """μπF_r(P, D, κW) − SF·W [N], from the model's radial force alone (P or W may be an array)."""
    return mu * math.pi * np.asarray(muscle.radial_force(pressure, diameter, kappa * load), float) - sf * load


def scanned_root(f, grid):
    """The first change of sign of f (vectorised) on ``grid``, narrowed by brentq; None if there is none."""
    values = np.broadcast_to(f(grid), grid.shape)
    change = np.flatnonzero(np.sign(values[1:]) != np.sign(values[:-1]))
    if change.size == 0:
        return None
    i = change[0]
    return brentq(lambda x: float(f(x)), grid[i], grid[i + 1], xtol=1e-12, rtol=1e-14)


CASES = [(0.0762, 150.0, 1.0, 0.3, 1.5), (0.0889, 80.0, 0.5, 0.45, 2.0), (0.0889, 300.0, 0.0, 0.2, 1.2),
         (0.0950, 40.0, 1.0, 0.6, 3.0)]


@pytest.mark.parametrize("name", ["plain", "touching", "with_effects"])
def test_least_holding_pressure_is_the_first_pressure_that_holds(name, request):
    """P* = the least P pressing on the wall (F_r > 0) with μπF_r(P, D, κW) ≥ SF·W: a scan of P in 5 kPa
    steps to 3 MPa finds the cell where the margin turns positive, brentq its root."""
    muscle = request.getfixturevalue(name)
    for d, w, kappa, mu, sf in CASES:
        found = float(muscle.least_holding_pressure(d, w, kappa=kappa, friction=mu, safety_factor=sf))
        want = scanned_root(lambda p, a=(d, w, kappa, mu, sf): margin(muscle, p, *a),
                            np.arange(0.0, 3e6, 5e3))
        assert want is not None and found == pytest.approx(want, rel=1e-8, abs=1e-3), (name, d, w)


def test_least_holding_pressure_of_no_load_is_where_the_muscle_touches(with_effects, plain):
    """W = 0 holds at any pressure, but only once the muscle presses on the wall: P* = the anchoring
    pressure (the first P with F_r > 0, by a scan), not 0."""
    grid = np.arange(0, 1e6, 5e3)
    for d in (0.0762, 0.0889):
        touch = scanned_root(lambda p, d=d: np.asarray(with_effects.radial_force(p, d)) - 1e-9, grid)
        assert touch > 5e4
        found = float(with_effects.least_holding_pressure(d, 0.0, kappa=1.0, friction=0.3, safety_factor=1.5))
        assert found == pytest.approx(touch, rel=1e-6)
        assert float(with_effects.anchoring_pressure(d)) == pytest.approx(touch, rel=1e-6)
        assert float(plain.anchoring_pressure(d)) == pytest.approx(
            scanned_root(lambda p, d=d: np.asarray(plain.radial_force(p, d)) - 1e-9, grid), rel=1e-6)


def test_a_muscle_already_pressing_at_zero_pressure_anchors_at_zero(with_effects, plain):
    """In a pipe narrower than the sleeve (D < D₀) the stretched muscle presses at 0 Pa: anchoring 0 Pa
    exactly with effects (the closed form of the plain muscle is negative there)."""
    d = 0.05
    assert float(with_effects.radial_force(0.0, d)) > 0
    assert float(with_effects.anchoring_pressure(d)) == 0.0
    assert float(plain.anchoring_pressure(d)) < 0


@pytest.mark.parametrize("name", ["plain", "touching", "with_effects"])
def test_largest_load_is_the_last_load_held(name, request):
    """W_max(P) = the largest W with μπF_r(P, D, κW) ≥ SF·W: a scan of W in 2 N steps finds the cell
    where the margin turns negative, brentq its root; −1 (effects) or < 0 (closed form) where the muscle
    does not press at P."""
    muscle = request.getfixturevalue(name)
    for p, d, kappa, mu, sf in [(300e3, 0.0762, 1.0, 0.3, 1.5), (500e3, 0.0889, 0.5, 0.45, 2.0),
                                (700e3, 0.0950, 0.0, 0.2, 1.2), (250e3, 0.0889, 1.0, 0.6, 3.0)]:
        found = float(muscle.largest_load(p, d, kappa=kappa, friction=mu, safety_factor=sf))
        want = scanned_root(lambda w, a=(p, d, kappa, mu, sf): margin(muscle, a[0], a[1], w, *a[2:]),
                            np.arange(0.0, 40000.0, 10.0))
        assert want is not None and found == pytest.approx(want, rel=1e-9), (name, p, d)
    below = float(muscle.largest_load(60e3, 0.0889, kappa=1.0, friction=0.3, safety_factor=1.5))
    assert float(muscle.radial_force(60e3, 0.0889)) == 0.0 and below < 0
    if name == "with_effects":
        assert below == -1.0


def test_holding_capacity_is_mu_pi_radial_force(touching):
    """μ·π·F_r(P, D, κW) [N] (docs/physics.md §8)."""
    radial = float(touching.radial_force(400e3, 0.0889, 0.5 * 120.0))
    assert float(touching.holding_capacity(400e3, 0.0889, 120.0, kappa=0.5, friction=0.35)) == pytest.approx(
        0.35 * math.pi * radial, rel=1e-14)


def test_closed_form_pressure_is_infinite_only_where_its_derivation_fails(plain):
    """Valid with any μ > 0 (μ below 1 included); inf at μ = 0 (no friction holds nothing)."""
    for mu in (0.05, 0.5, 0.99, 1.5):
        assert math.isfinite(float(plain.closed_form_pressure(0.0889, 100.0, kappa=1.0, friction=mu,
                                                              safety_factor=1.5)))
    with np.errstate(divide="ignore"):
        nothing = plain.closed_form_pressure(0.0889, 100.0, kappa=1.0, friction=0.0, safety_factor=1.5)
    assert float(nothing) == math.inf


def contractile_free_length(muscle, p, load=0.0):
    g = muscle.geometry
    return brentq(lambda length: float(muscle.axial_force(p, length)) - load,
                  g.shortest_length * (1 + 1e-9), g.initial_length, xtol=1e-15, rtol=1e-15)


def test_free_length_is_the_root_of_the_axial_force(plain):
    """L_free(P): F_ax(P, L) = F_a between B/√3 and L₀ (brentq), one pressure at a time and several at
    once; L₀ where the pressure cannot move the muscle."""
    pressures = np.linspace(20e3, 3e6, 23)
    for p in pressures:
        assert float(plain.free_length(p)[0]) == pytest.approx(contractile_free_length(plain, p), rel=1e-12)
    together = plain.free_length(pressures)
    assert together == pytest.approx([contractile_free_length(plain, p) for p in pressures], rel=1e-12)
    loaded = float(plain.free_length(400e3, 30.0)[0])
    assert loaded == pytest.approx(contractile_free_length(plain, 400e3, 30.0), rel=1e-12)
    held = float(plain.axial_force(5e3, plain.geometry.initial_length))
    assert float(plain.free_length(5e3, held + 1.0)[0]) == plain.geometry.initial_length


def test_free_length_of_an_extensile_braid_grows_toward_the_neutral_length(plain):
    """α₀ = 62° > 54.74°: the muscle lengthens from L₀ toward B/√3; −F_ax(P, L) = 0 there (brentq)."""
    g = dataclasses.replace(plain.geometry, braid_angle=math.radians(62.0), initial_length=0.12)
    muscle = Muscle(g, plain.theta, plain.reference_pressure)
    assert g.extensile
    for p in (50e3, 200e3, 600e3):
        want = brentq(lambda length, p=p: float(muscle.axial_force(p, length)), g.initial_length,
                      g.shortest_length * (1 - 1e-9), xtol=1e-15, rtol=1e-15)
        assert g.initial_length < want < g.shortest_length
        assert float(muscle.free_length(p)[0]) == pytest.approx(want, rel=1e-12)


def test_free_length_beyond_the_braid_limit_is_an_error_naming_the_pressure(plain):
    with pytest.raises(SolverError, match=r"at 1e\+07 Pa"):
        plain.free_length(1e7)
    with pytest.raises(SolverError, match=r"at 2e\+07 Pa"):
        plain.free_length([1e5, 2e7, 3e7])
    assert float(plain.free_length(1e7, braid_limit=True)[0]) == plain.geometry.shortest_length


def test_symbolic_muscle_gives_the_numeric_muscles_forces(touching):
    """Muscle.symbolic(structure) fed the packed vector of a muscle gives that muscle's F_ax and F_r."""
    import casadi as ca

    built = Muscle.symbolic(touching.structure)
    p = built.pack(touching)
    assert p.size == touching.structure.size == len(touching.structure.names()) == 5 + 32
    pressure, length, d = ca.SX.sym("P"), ca.SX.sym("L"), ca.SX.sym("D")
    f = ca.Function("f", [built.p, pressure, length, d],
                    [built.muscle.axial_force(pressure, length),
                     built.muscle.radial_force(pressure, d, 20.0)])
    for args in ((300e3, 0.25, 0.0889), (800e3, 0.22, 0.0762)):
        axial, radial = (float(v) for v in f(p, *args))
        assert axial == pytest.approx(float(touching.axial_force(args[0], args[1])), rel=1e-12)
        assert radial == pytest.approx(float(touching.radial_force(args[0], args[2], 20.0)), rel=1e-12)


def test_parameter_vector_layout(touching, with_effects):
    """[L₀, D₀, α₀, t₀, P_ref, θ, Δθ, effect parameters]: each entry where Structure.names puts it."""
    g = touching.geometry
    v = touching.parameter_vector()
    assert list(v[:5]) == [g.initial_length, g.initial_diameter, g.braid_angle, g.bladder_thickness, 1e6]
    assert list(v[5:21]) == list(np.ravel(touching.theta)) and list(v[21:]) == list(CONTACT)
    names = with_effects.structure.names()
    values = dict(zip(names, with_effects.parameter_vector(), strict=True))
    assert values["axial_preload.preload"] == 40.0 and values["pressure_offset.offset"] == 12e3
    assert values["hoop.a0"] == pytest.approx(4.443711e6)


def test_pack_refuses_a_muscle_of_another_structure(plain, touching):
    built = Muscle.symbolic(touching.structure)
    assert built.pack(touching) == pytest.approx(touching.parameter_vector(), rel=0)
    with pytest.raises(ValueError, match="cannot fill"):
        built.pack(plain)


def test_repr_names_the_geometry_in_millimetres_and_degrees(plain, with_effects):
    assert repr(plain) == ("Muscle('paper-radial-pam', L0=310.7 mm, D0=57.15 mm, alpha0=23.56 deg, "
                           "t0=3.175 mm, theta=[1.5, 0, 0, 0, 0, 0, 0, 0, 4.444, -1.615, 0, 0, 0, 0, 0, 0] "
                           "MPa)")
    assert repr(with_effects).endswith("effects=['axial_preload', 'pressure_offset'])")


def test_unknown_effect_is_an_input_error_naming_it(plain):
    """An unknown effect name is an InputError (the CLI's exit 2) naming it and the known effects."""
    with pytest.raises(InputError, match="unknown effect 'bogus'; known effects: braid_friction") as caught:
        Muscle(plain.geometry, plain.theta, effects={"bogus": {}})
    assert all(name in str(caught.value) for name in effects_library.LIBRARY)
    with pytest.raises(InputError, match="unknown effect 'nonesuch'"):
        Muscle.symbolic(Structure(effects=("nonesuch",)))


def test_from_pam_refuses_what_is_no_pam_or_has_no_moduli(radial_pam):
    with pytest.raises(InputError, match=r"^pam: a dict is not a PAM"):
        Muscle.from_pam({})
    with pytest.raises(InputError, match=r"^PAM file: the PAM 'paper-radial-pam' has no 'moduli:' block"):
        Muscle.from_pam(dataclasses.replace(radial_pam, moduli=None))
    with pytest.raises(InputError, match=r"^x\.yaml: the PAM"):
        Muscle.from_pam(dataclasses.replace(radial_pam, moduli=None), where="x.yaml")


def test_geometry_unchanged_by_construction(plain):
    """The muscle keeps the Geometry it was given (the symbolic one reads L₀, D₀, α₀, t₀ in that order)."""
    g = Muscle.symbolic(Structure()).muscle.geometry
    assert [str(v) for v in (g.initial_length, g.initial_diameter, g.braid_angle, g.bladder_thickness)] == [
        "geometry_0", "geometry_1", "geometry_2", "geometry_3"]
    assert isinstance(plain.geometry, Geometry)
