"""The order ``make test`` runs the tests in (tests/support/order.py): the longest modules first."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from tests.support.order import HEAVY_MODULES, heavy_first

ROOT = Path(__file__).resolve().parents[2]


def test_every_listed_heavy_module_exists():
    missing = [m for m in HEAVY_MODULES if not (ROOT / m).is_file()]
    assert not missing, f"HEAVY_MODULES names modules that are gone: {missing}"


def test_heavy_modules_move_to_the_front_and_the_rest_keep_their_order():
    first, second = HEAVY_MODULES[:2]
    ids = ["tests/a/test_x.py::t1", f"{second}::t1", "tests/a/test_x.py::t2", f"{first}::t2",
           f"{second}::t0", "tests/b/test_y.py::t1", f"{first}::t1"]
    order = [item.nodeid for item in heavy_first([SimpleNamespace(nodeid=i) for i in ids])]
    assert order == [f"{first}::t2", f"{first}::t1", f"{second}::t1", f"{second}::t0",
                     "tests/a/test_x.py::t1", "tests/a/test_x.py::t2", "tests/b/test_y.py::t1"]
