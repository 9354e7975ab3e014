"""planning.memo.Memo: values kept by key, the oldest forgotten first beyond the budget of array bytes."""

from __future__ import annotations

import numpy as np

from pampipe.planning.law import Terms
from pampipe.planning.memo import Memo


def test_the_oldest_are_forgotten_beyond_the_budget_and_computed_again():
    memo = Memo(budget=3 * 800)  # three arrays of 100 floats
    calls = []

    def compute(k):
        calls.append(k)
        return np.full(100, float(k))

    for k in range(5):
        assert memo.get(k, lambda k=k: compute(k))[0] == k
    assert calls == [0, 1, 2, 3, 4]
    for k in (2, 3, 4):  # kept: not computed again
        memo.get(k, lambda k=k: compute(k))
    assert calls == [0, 1, 2, 3, 4]
    memo.get(0, lambda: compute(0))  # forgotten: computed again, and 2 goes
    memo.get(2, lambda: compute(2))
    assert calls == [0, 1, 2, 3, 4, 0, 2]


def test_an_object_counts_its_arrays_and_one_value_may_exceed_the_budget():
    memo = Memo(budget=1000)
    terms = Terms(np.zeros(100), np.zeros(100), np.zeros(100))  # 2400 B: over the budget alone
    assert memo.get("a", lambda: terms) is terms
    assert memo.get("a", lambda: None) is terms  # the last value stays, whatever its size
    memo.get("b", lambda: np.zeros(10))
    again = np.ones(3)
    assert memo.get("a", lambda: again) is again  # "a" went to make room
