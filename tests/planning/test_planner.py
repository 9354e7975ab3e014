"""`pampipe.planning` as a library: the NLP against the closed form and root finding, limits, monotonicity.

Independent references: the closed form of docs/physics.md §8
(P_req = [W(SF/(μπA) + κ) − F_ax(0, L_p)]/∂_P F_ax), scipy's brentq on the full model's holding
capacity, and the published anchoring pressures of docs/physics.md §7.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.errors import InputError
from pampipe.io.mission_schema import load_mission
from pampipe.model import braid, forces
from pampipe.model import no_slip as slip
from pampipe.model.pam import Moduli
from pampipe.planning import max_payload, plan_mission
from pampipe.planning.solve import block_solver
from pampipe.specs.mission import Mission, Section, Segment
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
INCH = 0.0254
KAPPA = {"through_anchor": 1.0, "distributed": 0.5, "none": 0.0}


def random_mission(rng, pam, sections=5, *, contact=False) -> Mission:
    """A valid random mission: diameters inside (D₀, D_max), any incline, friction 0.1–0.6."""
    if contact:
        theta = pam.moduli.as_vector()
        delta = np.zeros_like(theta)
        delta[8] = 4e6  # a much stiffer hoop law once anchored (docs/physics.md §9d) [Pa]
        pam = dataclasses.replace(pam, moduli=Moduli.from_vector(theta, contact=delta))
    segments = tuple(Segment(f"PAM{i + 1}", pam, rng.uniform(0.0, 1.5)) for i in range(3))
    route = tuple(Section(f"s{k}", 1.0, rng.uniform(2.9, 3.8) * INCH, rng.uniform(-math.pi / 2, math.pi / 2),
                          rng.uniform(0.1, 0.6), 0.0) for k in range(sections))
    return Mission(DEMO, segments, rng.uniform(0, 30), 2e6, rng.uniform(1, 3),
                   str(rng.choice(list(KAPPA))), rng.uniform(0, 20), route, {})


def closed_form(mission, s, i):
    """max(P_req, P_a(κW)) from docs/physics.md §8 / §7 for segment i in section s."""
    sec, seg = mission.route[s], mission.segments[i]
    m = seg.pam.moduli
    total = sum(x.mass for x in mission.segments) + mission.payload
    load = slip.anchor_load(total, seg.mass, sec.incline, sec.friction, mission.tether_drag)
    args = (seg.pam.geometry, m.as_vector(), m.reference_pressure)
    amp = braid.amplification_factor(sec.diameter, seg.pam.geometry)
    length = braid.length_at_diameter(sec.diameter, seg.pam.geometry)
    at_zero, slope = forces.axial_force_affine(length, *args)
    grip = sec.friction * math.pi * amp
    required = (load * (mission.safety_factor / grip + mission.kappa) - at_zero) / slope
    return max(required, forces.anchoring_pressure(sec.diameter, *args, mission.kappa * load)), load


def brentq_pressure(mission, s, i):
    """Least P with μπF_r(P, D, κW) = SF·W by brentq on the full model (no contact switch issue: W > 0)."""
    sec, seg = mission.route[s], mission.segments[i]
    m = seg.pam.moduli
    total = sum(x.mass for x in mission.segments) + mission.payload
    load = slip.anchor_load(total, seg.mass, sec.incline, sec.friction, mission.tether_drag)
    contact = m.contact_vector() if np.any(m.contact_vector()) else None
    args = (seg.pam.geometry, m.as_vector(), m.reference_pressure)
    start = forces.anchoring_pressure(sec.diameter, *args, mission.kappa * load)

    def margin(p):
        radial = forces.radial_force(p, sec.diameter, *args, mission.kappa * load, contact)
        return sec.friction * math.pi * radial - mission.safety_factor * load

    if margin(start) >= 0:
        return start
    return brentq(margin, start, 1e8, xtol=1e-9, rtol=1e-14)


@pytest.mark.parametrize("method", ["kkt", "ipopt"])
def test_nlp_matches_closed_form_on_random_missions(radial_pam, method):
    """The issue's agreement test: relative 1e-6 (both solvers converge to ~1e-10; 1e-6 is the goal)."""
    rng = np.random.default_rng(6)
    worst = 0.0
    for _ in range(25):
        mission = random_mission(rng, radial_pam)
        plan = plan_mission(mission, method=method, check=False)
        for s, sec in enumerate(plan.sections):
            assert sec.feasible, sec.reason
            for i, seg in enumerate(sec.segments):
                expected, load = closed_form(mission, s, i)
                assert seg.required_hold == pytest.approx(load, rel=1e-12)
                worst = max(worst, abs(seg.pressure - expected) / expected)
    assert worst < 1e-6


def test_nlp_matches_brentq_with_contact_stiffening(radial_pam):
    """With contact increments the requirement is quadratic in P: compare with brentq on the model."""
    rng = np.random.default_rng(7)
    for _ in range(5):
        mission = random_mission(rng, radial_pam, contact=True)
        kkt = plan_mission(mission)
        ipopt = plan_mission(mission, method="ipopt", check=False)
        assert kkt.checks["bisection_max_rel_diff"] < 1e-9  # 64 bisection halvings of ~2P: ~1e-19 P
        for s, sec in enumerate(kkt.sections):
            for i, seg in enumerate(sec.segments):
                expected = brentq_pressure(mission, s, i)
                assert seg.pressure == pytest.approx(expected, rel=1e-6)
                assert ipopt.sections[s].segments[i].pressure == pytest.approx(expected, rel=1e-6)


def test_capacity_equals_safety_factor_times_hold_where_slip_binds():
    plan = plan_mission(load_mission(DEMO))
    for sec in plan.sections:
        for seg in sec.segments:
            assert seg.binding == "no_slip"
            # at the optimum the no-slip constraint is active: capacity = SF·W (NLP tolerance ~1e-12)
            assert seg.holding_capacity == pytest.approx(1.5 * seg.required_hold, rel=1e-9)
            assert seg.radial_force * math.pi * 0.3 == pytest.approx(seg.holding_capacity, rel=1e-12)


def test_limit_case_needs_only_the_anchoring_pressure():
    """Horizontal, massless, no payload or tether: W = 0, so P = P_anchor (117, 165 kPa;
    docs/physics.md §7)."""
    base = load_mission(DEMO)
    segments = tuple(dataclasses.replace(s, mass=0.0) for s in base.segments)
    route = tuple(dataclasses.replace(s, incline=0.0) for s in base.route)
    mission = dataclasses.replace(base, segments=segments, route=route, payload=0.0, tether_drag=0.0)
    plan = plan_mission(mission)
    for sec, published in zip(plan.sections, (117.0e3, 165.0e3), strict=True):
        for seg in sec.segments:
            assert seg.required_hold == 0.0
            assert seg.binding == "contact"
            # docs/physics.md §7 prints the two anchoring pressures to 0.01 kPa
            assert seg.pressure == pytest.approx(published, abs=10.0)
            assert seg.pressure == pytest.approx(seg.anchoring_pressure, rel=1e-12)


def _pressure(mission, **changes):
    return plan_mission(dataclasses.replace(mission, **changes)).sections[0].segments[1].pressure


def test_monotonicity():
    """More payload, a steeper climb or descent, more safety factor: more pressure; more friction: less."""
    base = load_mission(DEMO)
    slope = dataclasses.replace(base.route[0], incline=math.radians(30))
    base = dataclasses.replace(base, route=(slope,))
    p0 = _pressure(base)
    assert _pressure(base, payload=base.payload + 1) > p0
    assert _pressure(base, safety_factor=2.0) > p0
    for steeper in (math.radians(60), math.radians(-60)):
        assert _pressure(base, route=(dataclasses.replace(slope, incline=steeper),)) > p0
    assert _pressure(base, route=(dataclasses.replace(slope, friction=0.5),)) < p0
    assert (_pressure(base, load_path="none") < _pressure(base, load_path="distributed") < p0)
    # the downhill load equals the uphill load (|sin φ|): same pressure both ways
    down = _pressure(base, route=(dataclasses.replace(slope, incline=-slope.incline),))
    assert down == pytest.approx(p0, rel=1e-12)


def test_max_payload_is_where_the_supply_just_holds():
    mission = load_mission(DEMO)
    limit = max_payload(mission)
    assert limit.section == "riser"  # vertical: the load grows by g per kg, horizontal only by μg
    seg = mission.segments[0]
    m, sec = seg.pam.moduli, mission.route[0]
    # W_max = μπA·F_ax(P) / (SF + κμπA) (docs/physics.md §8), from the model's primitives
    at_zero, slope = forces.axial_force_affine(braid.length_at_diameter(sec.diameter, seg.pam.geometry),
                                               seg.pam.geometry, m.as_vector(), m.reference_pressure)
    grip = sec.friction * math.pi * braid.amplification_factor(sec.diameter, seg.pam.geometry)
    held = grip * (at_zero + slope * mission.supply_pressure) / (mission.safety_factor + mission.kappa * grip)
    others = sum(s.mass for s in mission.segments)
    # vertical: W = g·(segments + payload) (cos φ = 0), so payload = W_max/g − segment masses
    assert limit.payload == pytest.approx(held / slip.STANDARD_GRAVITY - others, rel=1e-12)
    at_limit = plan_mission(mission, payload=limit.payload)
    assert at_limit.feasible
    assert at_limit.sections[0].segments[0].pressure == pytest.approx(mission.supply_pressure, rel=1e-9)
    over = plan_mission(mission, payload=limit.payload * 1.001)
    assert not over.feasible and over.sections[0].reason.startswith("PAM")


def test_pam_without_moduli_says_run_identify(radial_pam):
    mission = load_mission(DEMO)
    bare = dataclasses.replace(radial_pam, moduli=None)
    segments = (dataclasses.replace(mission.segments[0], pam=bare), *mission.segments[1:])
    with pytest.raises(InputError, match="pampipe identify"):
        plan_mission(dataclasses.replace(mission, segments=segments))


def test_new_route_is_a_call_not_a_rebuild(radial_pam):
    rng = np.random.default_rng(1)
    plan_mission(random_mission(rng, radial_pam, 3), method="ipopt")
    built = block_solver.cache_info().misses
    for sections in (2, 4, 5):
        plan_mission(random_mission(rng, radial_pam, sections), method="ipopt")
    assert block_solver.cache_info().misses == built
