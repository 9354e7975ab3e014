"""The gait's re-simulation (CasADi CVODES) and positions, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.io.mission_schema import load_mission
from pampipe.locomotion import gait_options
from pampipe.locomotion.replay import simulate
from pampipe.locomotion.requirements import section_needs
from pampipe.locomotion.schedule import ControlPlan, lengths, positions
from pampipe.pneumatics.options import GaitOptions, Gas, Valve
from pampipe.pneumatics.timing import GAS_CONSTANT, ISO_DENSITY, ISO_TEMPERATURE, Chamber
from tests.support.problems import PROBLEMS

ATM = 101325.0
VALVE = Valve(sonic_conductance=5e-9, critical_pressure_ratio=0.3)
GAS = Gas(temperature=300.0, polytropic_index=1.0, atmospheric_pressure=ATM)
OPTIONS = GaitOptions(valve=VALVE, gas=GAS)
SUPPLY = 600e3  # gauge; 701.3 kPa absolute, choked filling while p ≤ 0.3 × 701.3 = 210.4 kPa absolute


def _plan(commands, durations, start):
    """Six phases of ``intervals`` intervals each; commands (6, intervals, 3)."""
    return ControlPlan(np.asarray(durations, float), np.asarray(commands, float), np.asarray(start, float))


def test_rigid_chambers_fill_linearly_and_vent_exponentially_while_choked():
    """Rigid chambers, isothermal, choked valve: filling has ṗ = RT·C·ρ₀·p_s·√(T₀/T)/V (constant);
    venting has ṗ = −RT·C·ρ₀·√(T₀/T)·p/V, so p = p₀·e^(−λt); the closed one keeps its pressure."""
    volumes = (5e-3, 5e-4, 1e-3)
    chambers = tuple(Chamber.rigid(v) for v in volumes)
    start = [0.0, 500e3, 123e3]  # gauge: filling from 0, venting from 601 kPa absolute, closed
    commands = np.zeros((6, 2, 3))
    commands[..., 0], commands[..., 1] = 1.0, -1.0
    durations = [0.04] * 6  # 0.24 s: still choked at the end for both (checked below)
    traj = simulate(chambers, _plan(commands, durations, start), supply=SUPPLY, options=OPTIONS, samples=5)
    assert traj.times.size == 1 + 6 * 2 * 5 and traj.boundaries.tolist() == [10, 20, 30, 40, 50, 60]
    assert traj.times[-1] == pytest.approx(0.24, rel=1e-14)
    scale = GAS_CONSTANT * GAS.temperature * VALVE.sonic_conductance * ISO_DENSITY * math.sqrt(
        ISO_TEMPERATURE / GAS.temperature)
    fill = start[0] + scale * (SUPPLY + ATM) / volumes[0] * traj.times
    vent = (start[1] + ATM) * np.exp(-scale / volumes[1] * traj.times) - ATM
    assert fill[-1] + ATM <= VALVE.critical_pressure_ratio * (SUPPLY + ATM)  # choked all along
    assert ATM / (vent[-1] + ATM) <= VALVE.critical_pressure_ratio
    # CVODES at relative tolerance 1e-12: measured errors here 1e-11 Pa (fill) and 5e-6 Pa (vent,
    # from 6e5 Pa); 1e-4 Pa is 20× the larger and still 2e-10 of the pressure
    assert traj.pressures[:, 0] == pytest.approx(fill, abs=1e-4)
    assert traj.pressures[:, 1] == pytest.approx(vent, abs=1e-4)
    assert np.all(traj.pressures[:, 2] == start[2])


@pytest.fixture(scope="module")
def demo_needs():
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    return section_needs(mission, 0, gait_options(mission.gait))


def test_positions_measure_the_mismatch_of_two_anchors_across_a_shrinking_segment(demo_needs):
    """PAM1 and PAM3 stay anchored while PAM2 (free) is inflated from 0 to P: the two anchors disagree
    by exactly L₀ − L_free(P) of PAM2, and the rear (carried by PAM1) never moves."""
    contact = [n.contact_pressure for n in demo_needs]
    middle = np.linspace(0.0, 0.5 * contact[1], 7)
    pressures = np.column_stack([np.full(7, 1.1 * contact[0]), middle, np.full(7, 1.1 * contact[2])])
    ends, mismatch = positions(demo_needs, pressures)
    muscle = demo_needs[1].muscle
    shrink = np.diff(muscle.free_length(middle))  # each step's change of PAM2's length (≤ 0)
    # lengths come from the same bisection to ~1e-16 m, so the mismatch matches to round-off
    assert mismatch == pytest.approx(float(np.max(-shrink)), rel=1e-9)
    assert np.all(ends[:, 0] == 0.0)
    assert ends[-1, 3] - ends[0, 3] == pytest.approx(float(np.sum(shrink)), rel=1e-9)
    assert lengths(demo_needs, pressures)[:, 0] == pytest.approx([demo_needs[0].anchored_length] * 7)


def test_positions_refuse_a_gait_that_lets_go(demo_needs):
    contact = np.array([n.contact_pressure for n in demo_needs])
    pressures = np.array([1.1 * contact, 1.1 * contact * [1, 0, 0], 1.1 * contact * [0, 0, 1]])
    with pytest.raises(SolverError, match="t-sample 2"):
        positions(demo_needs, pressures)
