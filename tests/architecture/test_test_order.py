"""PAMPIPE_TEST_SHUFFLE=SEED runs the suite in an order drawn from SEED (issue 40: no test may rely on another
having run first)."""

from __future__ import annotations

import itertools
from types import SimpleNamespace

from tests.support.order import shuffled

ITEMS = [SimpleNamespace(nodeid=f"tests/{m}/test_x.py::test_{k}") for m in "abcdef" for k in range(6)]


def test_a_shuffle_keeps_every_test_once_and_each_module_together():
    order = shuffled(ITEMS, 7)
    assert sorted(i.nodeid for i in order) == sorted(i.nodeid for i in ITEMS)
    modules = [i.nodeid.split("::")[0] for i in order]
    changes = sum(a != b for a, b in itertools.pairwise(modules))
    assert changes == len(set(modules)) - 1  # each module's tests are one contiguous run


def test_one_seed_gives_one_order_and_two_seeds_two():
    def ids(seed):
        return [i.nodeid for i in shuffled(ITEMS, seed)]

    assert ids(7) == ids(7)  # every xdist worker must collect the same order
    assert ids(7) != ids(8)
    assert ids(7) != [i.nodeid for i in ITEMS]
    firsts = {ids(seed)[0].split("::")[0] for seed in range(40)}
    assert len(firsts) == 6  # every module comes first for some seed
    inside = {ids(seed)[0] for seed in range(40)} & {i.nodeid for i in ITEMS[:6]}
    assert len(inside) > 1  # and the tests inside a module
