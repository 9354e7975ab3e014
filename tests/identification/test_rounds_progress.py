"""identify's progress names the round of the slack hinge it solves (issue 42): the paper protocol's
cubic fit refits twice with its slack rows as max(0, F), and says so, instead of repeating one line."""

from __future__ import annotations

import pampipe
from pampipe.identification import identify
from pampipe.identification.fit import HINGE_ROUNDS
from tests.support.problems import PROBLEMS


def test_each_refit_of_the_slack_hinge_says_which_round_it_is():
    _, data = pampipe.load_experiment(PROBLEMS / "experiments" / "paper-protocol.yaml")
    said: list[str] = []
    identify(data, progress=said.append)
    solving = [line for line in said if line.startswith("solving the")]
    assert len(solving) >= 2 and len(set(solving)) == len(solving)  # no line repeated
    assert "round" not in solving[0]
    for k, line in enumerate(solving[1:], start=2):
        assert line.endswith(f"round {k} of at most {HINGE_ROUNDS} (slack rows as max(0, F))")
