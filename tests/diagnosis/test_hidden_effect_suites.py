"""The hidden-effect suites of `diagnose` (slow), on the TEST set of tests/support/diagnose_suite.py.

Acceptance (issue 13), every case generated from known parameters with σ = 2 N white force noise:

* clean data: ``none`` in at least 95 % of 20 seeds;
* single library effects at their default magnitude: every one named (or, for two effects the data
  cannot tell apart, reported in one indistinguishable group), every test at ≤ 1.2 σ after;
* pairs of library effects (all 28, at ×0.7 and ×1.4): both named (or flagged) in at least 80 %;
* effects outside the library (5 kinds × 4): ``unexplained`` or ``partly_explained`` in at least
  80 %, and a confident wrong name (``explained``) in at most 10 %;
* every row order and short radial ramps: exit 0 through the command line;
* binned cells (dense data, issue 17): the same verdicts and named sets as unbinned cells.

The TEST set's seeds and magnitudes were not used to choose any threshold (the TUNING set was).
Run with ``pytest -m slow tests/diagnosis/test_hidden_effect_suites.py`` (≈ 25 min on 2 cores).
"""

from __future__ import annotations

import json
from dataclasses import replace
from multiprocessing import get_context

import numpy as np
import pytest

from pampipe.diagnosis.hidden import MAGNITUDES, hidden_experiment, hidden_protocol, hidden_tests
from pampipe.diagnosis.workflow import diagnose
from pampipe.io.pamfile import write_experiment
from tests.support.diagnose_suite import held_out_cases, outcome_class, run_case
from tests.support.processes import run_cli

SIGMA = 2.0


def _run(group: str) -> list[dict]:
    cases = [c for c in held_out_cases() if c.group == group]
    with get_context("spawn").Pool(2) as pool:
        return pool.map(run_case, cases)


@pytest.mark.slow
def test_clean_data_says_none_in_19_of_20_seeds():
    outcomes = _run("clean")
    assert sum(o["verdict"] == "none" for o in outcomes) >= 19, [o["verdict"] for o in outcomes]


@pytest.mark.slow
def test_single_effects_at_default_magnitude_are_all_named():
    """Each named, or, where two candidates fit the data equally (prestrain and a pressure offset
    both give a threshold pressure), reported in one group the tests cannot separate."""
    for outcome in _run("single"):
        (effect,) = outcome["case"].effects
        grouped = any(effect in group for group in outcome["groups"])
        assert effect in outcome["named"] or grouped, outcome
        assert outcome["verdict"] == "explained", outcome
        assert max(outcome["rmse_after"]) <= 1.2 * SIGMA, outcome


@pytest.mark.slow
def test_pairs_are_both_named_in_80_percent():
    outcomes = _run("pair")
    both = [o for o in outcomes if outcome_class(o).startswith("all named")]
    assert len(both) >= 0.8 * len(outcomes), [(o["case"].label, o["named"]) for o in outcomes]


@pytest.mark.slow
def test_effects_outside_the_library_are_not_explained_by_it():
    outcomes = _run("foreign")
    classes = [outcome_class(o) for o in outcomes]
    honest = sum(c in ("unexplained", "partly_explained") for c in classes)
    wrong = sum(c == "confident wrong name" for c in classes)
    assert honest >= 0.8 * len(outcomes), classes
    assert wrong <= 0.1 * len(outcomes), classes


def _reordered(tests, how: str, seed: int):
    rng = np.random.default_rng(seed)
    out = []
    for spec, columns in tests:
        length = columns.get("length", np.zeros(columns["force"].size))
        order = {"length": np.lexsort((columns["pressure"], length)),
                 "pressure": np.lexsort((length, columns["pressure"])),
                 "shuffled": rng.permutation(columns["force"].size)}[how]
        out.append((spec, {k: v[order] for k, v in columns.items()}))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("how", ["length", "pressure", "shuffled"])
def test_every_row_order_exits_0_and_finds_the_effect(radial_pam, tmp_path, how):
    """Rows in length-major, pressure-major and shuffled order (the time column kept): exit 0, and
    braid friction, which needs the direction of motion, is still named (from the time order)."""
    tests, comments = hidden_tests(radial_pam, "braid_friction", seed=5500)
    path = write_experiment(tmp_path, how, radial_pam, _reordered(tests, how, 5501), comments=comments)
    out = run_cli("diagnose", path, "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["verdict"] == "explained" and doc["selected"]["effects"] == ["braid_friction"]


@pytest.mark.slow
@pytest.mark.parametrize("effect", [None, *MAGNITUDES])
def test_binned_cells_select_as_unbinned_cells(radial_pam, effect):
    """Dense axial legs (200 points, 400 distinct lengths per level: binned into 64 per level and
    evaluated at two points per bin) give the same verdict and the same named set as cells that keep
    every distinct length (TEST seed 5600)."""
    protocol = hidden_protocol(points_per_leg=200)
    data = hidden_experiment(radial_pam, effect, seed=5600, protocol=protocol)
    binned = diagnose(data)
    exact = diagnose(data, reduce=False)
    assert binned.cells.size < exact.cells.size
    assert binned.verdict.verdict == exact.verdict.verdict
    assert binned.selected_effects == exact.selected_effects


@pytest.mark.slow
def test_two_pipes_name_wall_friction_since_contact_stiffening_keeps_its_sign(radial_pam):
    """With the paper's two pipes, contact stiffening (two increments) could fit wall friction's two slope
    factors only by softening (negative increments); fitted with its physical sign (≥ 0, issue 41) it
    cannot, so wall friction is named on its own and brings every test to the noise (seeds 5700-5702 all
    did, measured in round 3; seed 5700 here)."""
    from pampipe.simulation.synthetic import PAPER_PIPES

    protocol = replace(hidden_protocol(), pipes=PAPER_PIPES)
    result = diagnose(hidden_experiment(radial_pam, "wall_friction", seed=5700, protocol=protocol))
    assert result.verdict.verdict == "explained", result.verdict.reason
    assert result.selected_effects == ("wall_friction",)
    assert not result.verdict.indistinguishable
