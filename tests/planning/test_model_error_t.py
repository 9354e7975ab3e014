"""The model error is drawn as the Student-t predictive of its cross-validated estimate (docs/physics.md §15):
s·t_ν with s the PAM's ``model_error`` and ν its ``model_error_dof``; a normal without ν (older files)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip as slip
from pampipe.model.muscle import Muscle
from pampipe.model.uncertainty import ParameterUncertainty, moduli_names
from pampipe.planning import plan_mission
from pampipe.planning.sources import MuscleUncertainty, draw_muscles
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
ERROR = 6.0  # [N] the written model error s


def _only_error(dof: int | None, n: int, seed: int = 5) -> np.ndarray:
    """n draws of the model-error term of a segment whose only source is that error."""
    size = 8
    m = MuscleUncertainty(np.zeros(size), np.zeros((size, size)), np.zeros(size), ERROR, model_error_dof=dof)
    return draw_muscles([m], n, seed, 0.0).model_error[0]


@pytest.mark.parametrize("dof", [1, 3, 8])
@pytest.mark.parametrize("level", [0.9, 0.95, 0.99])
def test_the_drawn_error_has_the_t_quantile_of_its_dof(dof, level):
    """The empirical C-quantile of 2·10⁵ draws is s·t_ν⁻¹(C) (scipy) within four standard errors of an
    empirical quantile, √(C(1 − C)/n)/f(q); the normal quantile s·z_C lies outside that band."""
    n = 200_000
    drawn = np.quantile(_only_error(dof, n), level)
    exact = ERROR * stats.t.ppf(level, dof)
    band = 4 * math.sqrt(level * (1 - level) / n) / (stats.t.pdf(exact / ERROR, dof) / ERROR)
    assert drawn == pytest.approx(exact, abs=band)
    assert abs(ERROR * stats.norm.ppf(level) - exact) > band


def test_without_dof_the_error_is_normal():
    n = 200_000
    level = 0.95
    drawn = np.quantile(_only_error(None, n), level)
    exact = ERROR * stats.norm.ppf(level)
    band = 4 * math.sqrt(level * (1 - level) / n) / (stats.norm.pdf(exact / ERROR) / ERROR)
    assert drawn == pytest.approx(exact, abs=band)


def test_the_t_draw_moves_no_other_source():
    """The χ² factors have a stream of their own: the normal draws under them, and every other source's,
    are the same whatever ν (a large ν gives the normal draws themselves)."""
    normal = _only_error(None, 1000)
    assert np.allclose(_only_error(10**9, 1000), normal, rtol=1e-3)
    assert not np.allclose(_only_error(2, 1000), normal, rtol=0.05)


def _mission(radial_pam, dof):
    u = ParameterUncertainty(moduli_names(3), np.zeros((16, 16)), ERROR, model_error_dof=dof)
    pam = radial_pam.with_uncertainty(u)
    mission = load_mission(DEMO)
    mission = dataclasses.replace(mission, segments=tuple(dataclasses.replace(s, pam=pam, pam_file=None)
                                                          for s in mission.segments))
    return dataclasses.replace(mission, route=mission.route[:1])


def test_the_plan_rises_as_the_dof_fall_and_meets_the_normal_plan_in_the_limit(radial_pam):
    """With the model error the only source, P_C grows as ν falls (heavier tails); ν → ∞ plans the normal."""
    c = 0.95
    planned = {dof: plan_mission(_mission(radial_pam, dof), confidence=c).arrays.pressure[0, 0]
               for dof in (1, 3, 10, 10**9, None)}
    assert planned[1] > planned[3] > planned[10] > planned[None]
    assert planned[10**9] == pytest.approx(planned[None], rel=1e-5)


def test_the_t_plan_holds_in_c_of_independent_t_draws(radial_pam):
    """A plan made with ν = 3 holds in C ± 2 % of 2·10⁴ independent draws e = s·t₃ (scipy's generator),
    judged by the numeric muscle: F_r = A·(F_ax + e − κW)."""
    c, dof = 0.9, 3
    mission = _mission(radial_pam, dof)
    pressure = plan_mission(mission, confidence=c).arrays.pressure[0, 0]
    e = ERROR * stats.t.rvs(dof, size=20_000, random_state=np.random.default_rng(17))
    seg = mission.segments[0]
    load = slip.anchor_load(sum(s.mass for s in mission.segments) + mission.payload, seg.mass, math.pi / 2,
                            0.3, mission.tether_drag)
    radial = Muscle.from_pam(seg.pam).radial_force(pressure, 3 * 0.0254, load - e)
    held = np.mean(0.3 * math.pi * radial >= mission.safety_factor * load)
    assert held == pytest.approx(c, abs=0.02)
