"""The steering module's least-pressure triad (docs/physics.md §14.4), checked outside the NLP: the lengths
recomputed from the pressures by the muscle model's own root search, and the curvature from those lengths by
Webster & Jones' closed form (not the NLP's linear expression)."""

from __future__ import annotations

import json
import math

import pytest

from pampipe.bends import steering
from pampipe.bends.steering import curvature_of_lengths, steer
from pampipe.io.pam_schema import load_pam
from pampipe.model.muscle import Muscle
from tests.support.problems import PROBLEMS

PAM = PROBLEMS / "pams" / "extensile-steering.yaml"
RADIUS = 0.015


@pytest.fixture(scope="module")
def muscle():
    return Muscle.from_pam(load_pam(PAM))


@pytest.mark.parametrize(("bend_radius", "direction_deg"), [
    (0.1143, 180), (0.1143, 0), (0.2, 60), (0.08, 200), (0.5, 300), (0.0762, 90)])
def test_reaches_the_bend_curvature_within_two_percent(muscle, bend_radius, direction_deg):
    target = 1 / bend_radius
    command = steer(muscle, curvature=target, direction=math.radians(direction_deg), radius=RADIUS,
                    supply=689e3)
    assert command.reached
    lengths = muscle.free_length(list(command.pressures))
    assert curvature_of_lengths(lengths, RADIUS) == pytest.approx(target, rel=0.02)
    assert all(0 <= p <= 689e3 for p in command.pressures)


def test_pressurises_the_outside_of_the_turn(muscle):
    """Turning away from PAM 1 (180°), only PAM 1 lengthens: [P, 0, 0]; toward it, PAMs 2 and 3 alike."""
    away = steer(muscle, curvature=8.75, direction=math.pi, radius=RADIUS, supply=689e3)
    assert away.pressures[0] > 0 and away.pressures[1] == pytest.approx(0, abs=1.0)
    toward = steer(muscle, curvature=8.75, direction=0.0, radius=RADIUS, supply=689e3)
    assert toward.pressures[0] == pytest.approx(0, abs=1.0)
    assert toward.pressures[1] == pytest.approx(toward.pressures[2], rel=1e-4)


def test_low_supply_says_so(muscle):
    command = steer(muscle, curvature=8.75, direction=math.pi, radius=RADIUS, supply=50e3)
    assert not command.reached
    assert "supply" in command.reason
    assert command.curvature < 8.75
    assert command.pressures[0] == pytest.approx(50e3, rel=1e-4)
    lengths = muscle.free_length(list(command.pressures))
    assert curvature_of_lengths(lengths, RADIUS) == pytest.approx(command.curvature, rel=0.02)


def test_solvers_are_built_once(muscle):
    steer(muscle, curvature=5.0, direction=1.0, radius=RADIUS, supply=689e3)
    before = steering._solvers.cache_info()
    steer(muscle, curvature=6.0, direction=2.0, radius=RADIUS, supply=400e3)
    after = steering._solvers.cache_info()
    assert after.misses == before.misses and after.hits == before.hits + 1


def test_simulate_shows_an_extensile_pam_lengthening(cli, muscle):
    """Without a pipe, simulate gives L(P) of an extensile PAM: from L0 at 0 Pa, rising toward B/√3, each
    point a root of F_ax(P, L) = 0 of the model."""
    out = cli("simulate", PAM, "--json", "-p", "0 kPa", "-p", "100 kPa", "-p", "400 kPa")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["kind"] == "extensile"
    lengths = [p["free_length_m"] for p in doc["points"]]
    assert lengths[0] == pytest.approx(0.1)
    assert lengths[0] < lengths[1] < lengths[2] < doc["braid_limit_length_m"]
    for point in doc["points"]:
        force = muscle.axial_force(point["pressure_Pa"], point["free_length_m"])
        assert abs(float(force)) < 1e-6
    assert cli("simulate", PAM, "-d", "3 in").returncode == 2  # it cannot anchor
