"""No answer safer than its draws (issue 38, item 4): N(1 − C) ≥ 10, C shown with its digits, draws outside
the physical domain counted as not holding, quantiles no pressure reaches written as null, the draws bounded
by the memory they need."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from statistics import NormalDist

import numpy as np
import pytest

from pampipe.cli import main
from pampipe.errors import InputError
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.planning.confidence import check_resolution
from pampipe.planning.quantiles import level_text, probability_places
from pampipe.runtime import memory
from tests.support.problems import BAD_INPUTS, PROBLEMS

RISER = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"


@pytest.mark.parametrize(("level", "samples", "ok"), [
    (0.95, 200, True), (0.95, 199, False), (0.99, 1000, True), (0.99, 999, False),
    (0.999, 4000, False), (0.9975, 4000, True), (0.9999999999, 4000, False)])
def test_draws_must_resolve_the_quantile(level, samples, ok):
    """N(1 − C) ≥ 10, counted on C as written (1 − 0.95 is 0.05 exactly)."""
    if ok:
        check_resolution(level, samples)
        return
    with pytest.raises(InputError, match=r"N\(1 - C\) must be at least 10"):
        check_resolution(level, samples)


def test_refusal_says_how_many_draws_and_which_confidence_would_do():
    with pytest.raises(InputError) as caught:
        check_resolution(0.9999999999, 4000)
    message = str(caught.value)
    assert "--confidence 0.9999999999 with --samples 4000" in message
    assert "give --samples 100000000000 or more, or --confidence 0.9975 or less" in message


def test_confidence_is_shown_with_its_digits():
    assert level_text(0.9999999999) == "0.9999999999"
    assert level_text(0.95) == "0.95"
    assert level_text(1 - 0.05) == "0.95"
    assert [probability_places(c) for c in (0.5, 0.95, 0.99, 0.999, 0.9999)] == [4, 4, 4, 4, 5]


def test_plan_text_shows_the_level_and_probabilities_to_its_digits(capsys):
    assert main(["plan", str(RISER), "--confidence", "0.9995", "--samples", "20000"]) == 0
    out = capsys.readouterr().out
    assert "confidence 0.9995: 20000 seeded draws" in out
    assert "confidence 1:" not in out
    assert re.search(r"riser +PAM1 +lot +[0-9.]+ +0\.\d{5} ± 0\.\d{5} ", out), out  # 1 − C to 2 digits


def test_draws_are_refused_before_they_are_allocated(monkeypatch):
    """10⁹ draws need ~10³ GB: refused with the figure, not a MemoryError part way."""
    monkeypatch.setattr(memory, "available_memory", lambda: 8 << 30)
    with pytest.raises(InputError, match=r"--samples 1000000000: the draws would need [0-9.,]+ GB of memory "
                                         r"and 8 GB are available"):
        plan_mission(load_mission(RISER), confidence=0.95, samples=10**9)


def test_unphysical_draws_do_not_hold():
    """An initial length of 310.662 mm with an sd of 1000 mm (past the check on reading, here set on the
    loaded PAM) draws L₀ ≤ 0 with probability Φ(−0.310662) = 0.378: such draws are no muscle and do not
    hold, so no pressure holds in 70 % of the draws (before, they held at 0 Pa and the plan was feasible)."""
    mission = load_mission(RISER)
    physical = 1 - NormalDist().cdf(-310.662 / 1000)  # 0.622, independent of the code
    pam = dataclasses.replace(mission.segments[0].pam, geometry_sd={"initial_length": 1.0})
    segments = tuple(dataclasses.replace(s, pam=pam, pam_file=None) for s in mission.segments)
    mission = dataclasses.replace(mission, segments=segments)
    plan = plan_mission(mission, confidence=0.7, samples=4000)
    assert not plan.feasible
    held = plan_mission(mission, confidence=0.55, samples=4000)
    share = held.uncertainty.holding_probability
    assert np.all(share <= physical + 4 * math.sqrt(physical * (1 - physical) / 4000))


def test_quantiles_no_pressure_reaches_are_null_in_json(tmp_path, capsys):
    """The braid-angle sd of the corpus case plan-draws-beyond-reach: at 0.999 no pressure holds in the 3.5 in
    run (the narrower drawn braids do not reach it); the document says null, it does not stop on 'inf'."""
    case = BAD_INPUTS / "plan-draws-beyond-reach"
    for name in ("mission.yaml", "pam.yaml"):
        (tmp_path / name).write_bytes((case / name).read_bytes())
    assert main(["plan", str(tmp_path / "mission.yaml"), "--confidence", "0.95", "--json"]) == 3
    captured = capsys.readouterr()
    assert "came out as" not in captured.err
    document = json.loads(captured.out)
    riser = document["sections"][0]["segments"][0]
    assert riser["pressure_at_Pa"]["0.9"] > 0 and riser["pressure_at_Pa"]["0.999"] is None


def test_friction_draws_at_or_below_zero_do_not_hold(tmp_path, capsys):
    """Friction 0.3 ± 3: 46 % of the draws at μ ≤ 0 hold at no pressure. The plan is infeasible at 0.95 with
    that reason, and the friction source alone, which reaches no pressure, adds null (was: exit 3 "came out
    as inf ... please report the input")."""
    case = BAD_INPUTS / "mission-friction-sd-beyond-zero"
    for name in ("mission.yaml", "pam.yaml"):
        (tmp_path / name).write_bytes((case / name).read_bytes())
    assert main(["plan", str(tmp_path / "mission.yaml"), "--confidence", "0.95", "--json"]) == 3
    captured = capsys.readouterr()
    assert "came out as" not in captured.err and "holds at no pressure" in captured.err
    document = json.loads(captured.out)
    assert document["confidence"]["sources"][0] == {
        "source": "friction", "what": "wall friction sd", "pressure_shift_Pa": None}
