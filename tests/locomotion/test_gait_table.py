"""The sequential gait of many sections at once (export's gait table, issue 27) against independent answers.

* transition times against QUADPACK (scipy's adaptive ``quad`` at 2e-14, an independent quadrature of the
  same t = ∫ dP/|ṗ|) and against the closed form of choked venting of a rigid chamber;
* the table against the simulated gait of each section (:func:`pampipe.locomotion.sequential_gait`: CVODES
  over the schedule, positions from the sampled lengths), on a route of distinct sections and a robot of
  two different muscles;
* the table's pressures against the plan's own arrays, exactly;
* many-bore chamber fits against one-bore fits, and the free-length interpolant against the exact root.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from scipy.integrate import quad

from pampipe.io.mission_schema import load_mission
from pampipe.locomotion import gait_options, sequential_gait, table
from pampipe.model.muscle import Muscle
from pampipe.planning import plan_mission
from pampipe.pneumatics import timing as pneumatics
from pampipe.pneumatics.options import Gas, Valve
from pampipe.pneumatics.timing import (
    GAS_CONSTANT,
    ISO_DENSITY,
    ISO_TEMPERATURE,
    Chamber,
    chambers_of_muscle,
    free_lengths,
    pressure_rate,
    transition_times,
)
from tests.support.problems import PROBLEMS

ATM = 101325.0


def _quadpack(chamber, start, target, supply, valve, gas):
    command = 1.0 if target > start else -1.0

    def inverse_rate(p):
        return 1.0 / abs(pressure_rate(p, command, chamber, supply=supply, valve=valve, gas=gas))

    lo, hi = sorted((start, target))
    b = valve.critical_pressure_ratio
    points = [p for p in (chamber.anchoring_pressure, b * (supply + ATM) - ATM, ATM / b - ATM) if lo < p < hi]
    value, error = quad(inverse_rate, lo, hi, points=points, epsabs=0.0, epsrel=2e-14, limit=5000)
    assert error < 1e-12 * value
    return value


@pytest.mark.parametrize(("b", "m", "n"), [(0.3, 0.5, 1.0), (0.5, 0.5, 1.4), (0.2, 0.3, 1.2)])
def test_transition_times_agree_with_quadpack(radial_pam, b, m, n):
    """Fills from 500 Pa to just above contact, to mid-range and to 99 % of the supply; vents to 500 Pa
    and to 1 Pa (close to the 0 Pa gauge where ṗ vanishes)."""
    chamber = Chamber.of_muscle(Muscle.from_pam(radial_pam), 0.0762)
    valve, gas, supply = Valve(5e-9, b, m), Gas(293.15, n, ATM), 689e3
    pairs = [(500.0, 1.01 * chamber.anchoring_pressure), (500.0, 300e3), (500.0, 0.99 * supply),
             (300e3, 500.0), (150e3, 1.0), (0.99 * supply, 200e3)]
    got = transition_times(chamber, [p for p, _ in pairs], [t for _, t in pairs], supply=supply, valve=valve,
                           gas=gas)
    want = [_quadpack(chamber, p, t, supply, valve, gas) for p, t in pairs]
    assert got == pytest.approx(want, rel=1e-12)


def test_transition_times_far_from_the_contact_corner(radial_pam):
    """The demo chamber's shape, touching at 300 Pa, filled from 0 Pa to 600 kPa and vented back to 1 Pa: the
    span is 2000 times the corner's pressure, so the panels must keep doubling all the way."""
    demo = Chamber.of_muscle(Muscle.from_pam(radial_pam), 0.0762)
    chamber = Chamber(demo.anchored_volume, demo.rest_volume, 300.0, demo.shape)
    valve, gas, supply = Valve(), Gas(), 689e3
    got = transition_times(chamber, [0.0, 600e3], [600e3, 1.0], supply=supply, valve=valve, gas=gas)
    want = [_quadpack(chamber, p, t, supply, valve, gas) for p, t in ((0.0, 600e3), (600e3, 1.0))]
    assert got == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("index", [1.0, 1.4])
def test_rigid_chamber_choked_venting_matches_closed_form(index):
    """Venting while p_atm/p ≤ b is choked, ṁ = C ρ₀ p √(T₀/T), so V ṗ = −n R T C ρ₀ √(T₀/T) p and
    t = V ln(p₀/p₁) / (n R T C ρ₀ √(T₀/T)) (absolute pressures)."""
    valve = Valve(sonic_conductance=6e-9, critical_pressure_ratio=0.3)
    gas = Gas(temperature=300.0, polytropic_index=index, atmospheric_pressure=ATM)
    volume, start = 4e-4, 600e3
    target = ATM / 0.3 - ATM + 1.0  # just above the end of choked flow
    rate = index * GAS_CONSTANT * 300.0 * 6e-9 * ISO_DENSITY * math.sqrt(ISO_TEMPERATURE / 300.0) / volume
    expected = math.log((start + ATM) / (target + ATM)) / rate
    got = transition_times(Chamber.rigid(volume), start, target, supply=689e3, valve=valve, gas=gas)[0]
    assert got == pytest.approx(expected, rel=1e-13)


@pytest.fixture(scope="module")
def mixed(tmp_path_factory):
    """The demo robot with a different middle muscle (braid angle 2° steeper) on 12 distinct sections."""
    folder = tmp_path_factory.mktemp("mixed")
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    pam["geometry"]["braid_angle_from_transverse"] = "68.4373 deg"
    (folder / "steeper.yaml").write_text(yaml.safe_dump(pam))
    document = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for segment in document["robot"]["segments"]:
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    document["robot"]["segments"][1]["pam"] = "steeper.yaml"
    rng = np.random.default_rng(27)
    document["route"] = [{"name": f"s{i}", "length": "2 m",
                          "inner_diameter": f"{rng.uniform(76.5, 89.5):.5f} mm",
                          "incline": f"{rng.uniform(-89, 89):.5f} deg",
                          "friction": round(rng.uniform(0.2, 0.8), 5)} for i in range(12)]
    path = folder / "mixed.yaml"
    path.write_text(yaml.safe_dump(document))
    mission = load_mission(path)
    plan = plan_mission(mission)
    crossable = [i for i in range(len(mission.route)) if i not in plan.arrays.reasons]
    assert len(crossable) >= 8
    options = gait_options(mission.gait, source=mission.source)
    return mission, plan, options, crossable, table.sequential_table(mission, plan, options, crossable)


def test_table_matches_the_simulated_gait(mixed):
    mission, plan, options, crossable, got = mixed
    for k, index in enumerate(crossable):
        gait = sequential_gait(mission, index, options=options, mission_plan=plan)
        assert got.durations[k] == pytest.approx(gait.plan.durations, rel=1e-12)
        assert got.cycle_time[k] == pytest.approx(gait.cycle_time, rel=1e-12)
        # stride: closed form against positions rebuilt from 600 simulated samples
        assert got.stride[k] == pytest.approx(gait.stride, rel=1e-9)
        for j, state in enumerate(gait.steps):
            simulated = [state.pressures[n] for n in gait.names]
            assert got.pressures[k, j] == pytest.approx(simulated, rel=1e-9, abs=1e-4)  # CVODES' error


def test_table_pressures_are_the_plans_levels(mixed):
    """Each step ends with its anchors at the plan's pressure and the others vented (docs/physics.md §8)."""
    _, plan, options, crossable, got = mixed
    planned = plan.arrays.pressure[crossable]
    vented = np.full(len(crossable), options.vented_pressure)
    anchors = [(1,), (0, 1), (0,), (0, 2), (2,), (1, 2), (1,)]  # steps I … VII (paper Fig. 18)
    for step, held in enumerate(anchors):
        for i in range(3):
            assert np.array_equal(got.pressures[:, step, i], planned[:, i] if i in held else vented)


def test_segments_of_one_muscle_share_their_fits(monkeypatch):
    mission = load_mission(PROBLEMS / "missions" / "downhill-drain.yaml")
    plan = plan_mission(mission)
    calls = []

    def counted(muscle, diameters):
        calls.append(len(diameters))
        return chambers_of_muscle(muscle, diameters)

    monkeypatch.setattr(table, "chambers_of_muscle", counted)
    crossable = [i for i in range(len(mission.route)) if i not in plan.arrays.reasons]
    table.sequential_table(mission, plan, gait_options(mission.gait), crossable)
    assert len(calls) == 1  # three segments, one PAM: one fit per distinct bore
    assert calls[0] == len(np.unique(plan.arrays.diameter[crossable]))


def test_many_bore_fits_equal_one_bore_fits(radial_pam):
    muscle = Muscle.from_pam(radial_pam)
    bores = np.linspace(0.0765, 0.0895, 40)  # 40 × 200 pressures: the interpolated free lengths
    many = chambers_of_muscle(muscle, bores)
    for k in range(0, 40, 7):
        one = Chamber.of_muscle(muscle, bores[k])  # 200 pressures: exact roots
        row = Chamber(many.anchored_volume[k], many.rest_volume[k], many.anchoring_pressure[k],
                      tuple(c[k] for c in many.shape))
        pressures = np.linspace(0.0, 1.2 * one.anchoring_pressure, 50)
        assert row.volume(pressures) == pytest.approx(one.volume(pressures), rel=1e-12)
        assert row.compliance(pressures) == pytest.approx(one.compliance(pressures), rel=1e-9, abs=1e-22)


def test_free_length_interpolant_and_its_fallback(radial_pam, monkeypatch):
    muscle = Muscle.from_pam(radial_pam)
    pressures = np.linspace(0.0, 250e3, 3001)
    exact = muscle.free_length(pressures)
    assert np.max(np.abs(free_lengths(muscle, pressures) - exact)) <= 1e-13 * muscle.geometry.initial_length
    monkeypatch.setattr(pneumatics, "FREE_LENGTH_TOLERANCE", -1.0)  # no interpolant passes: exact roots
    assert np.array_equal(free_lengths(muscle, pressures), exact)
