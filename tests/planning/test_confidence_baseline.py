"""The plain numpy Monte Carlo of benchmarks/baseline_confidence.py (the peer of bench_confidence.py) samples
what `plan --confidence` samples: on 20 sections that each differ in incline (the benchmark's all-distinct
route, the riser robot's fit covariance, frictions with an sd, a bore with a tolerance), its 0.95-quantiles,
drawn from its own streams, agree with pampipe's within Monte Carlo error; the same check tells a baseline
without the friction's spread apart, so the two time the same work."""

from __future__ import annotations

import numpy as np

from benchmarks.baseline_confidence import plain_monte_carlo
from benchmarks.bench_network import MISSIONS, write_mission
from pampipe.io.mission_schema import load_mission
from pampipe.planning.confidence import plan_confidence
from pampipe.planning.problem import build_elements, mission_muscles

ROBOT = MISSIONS / "riser-uncertain-friction.yaml"
SAMPLES = 2000


def _mission(folder, friction_sd: float):
    folder.mkdir(exist_ok=True)
    return load_mission(write_mission(folder, 20, robot=ROBOT, friction_sd=friction_sd, distinct=True))


def _z(baseline: np.ndarray, plan) -> np.ndarray:
    """(baseline − pampipe) in units of the sd of the difference of two independent estimates, each with
    the sd that pampipe's order-statistic 95 % band states, (band width)/(2·1.96)."""
    sd = (plan.pressure_ci95[..., 1] - plan.pressure_ci95[..., 0]) / (2 * 1.959964)
    return (baseline - plan.pressure) / (np.sqrt(2) * sd)


def test_the_baseline_quantiles_agree_with_pampipes_within_monte_carlo_error(tmp_path):
    mission = _mission(tmp_path / "a", 0.05)
    muscles = mission_muscles(mission)
    plan = plan_confidence(mission, muscles, build_elements(mission, muscles), 0.95, samples=SAMPLES, seed=3)
    baseline = plain_monte_carlo(mission, 0.95, SAMPLES, seed=7)
    assert baseline.shape == plan.pressure.shape == (20, 3)
    assert np.all(np.isfinite(plan.pressure)) and np.all(np.isfinite(baseline))
    assert np.all(np.abs(_z(baseline, plan)) < 4)
    unspread = plain_monte_carlo(_mission(tmp_path / "b", 0.0), 0.95, SAMPLES, seed=7)  # μ without its sd
    assert np.max(np.abs(_z(unspread, plan))) > 4
