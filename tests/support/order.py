"""The order the tests run in: ``PAMPIPE_TEST_SHUFFLE=SEED`` (tests/conftest.py) draws one from SEED."""

from __future__ import annotations

import random


def shuffled(items: list, seed: int) -> list:
    """``items`` grouped by module (the part of a pytest node id before ``::``, groups in first-seen order),
    then the groups, and each group's items, shuffled by ``random.Random(seed)``: the same seed gives the same
    order in every process."""
    draw = random.Random(seed)
    groups: dict[str, list] = {}
    for item in items:
        groups.setdefault(item.nodeid.split("::")[0], []).append(item)
    order = list(groups.values())
    draw.shuffle(order)
    for group in order:
        draw.shuffle(group)
    return [item for group in order for item in group]


#: The test modules that take longest (each over about 20 s on a quiet machine; `pytest --durations`), started
#: first so that the two workers of ``make test`` do not end with one of them alone on a long module.
HEAVY_MODULES = (
    "tests/docs/test_docs_run.py",
    "tests/units/test_display.py",
    "tests/diagnosis/test_diagnose.py",
    "tests/identification/test_lab_protocols.py",
    "tests/commands/test_identify_writes.py",
    "tests/identification/test_uncertainty.py",
    "tests/commands/test_design.py",
    "tests/views/test_html_report.py",
    "tests/diagnosis/test_blame.py",
    "tests/commands/test_identify_startup.py",
)


def heavy_first(items: list) -> list:
    """``items`` with the tests of :data:`HEAVY_MODULES` moved to the front, in that order; every other test,
    and the tests within each module, keep their order (a stable sort on the module's rank)."""
    rank = {module: i for i, module in enumerate(HEAVY_MODULES)}
    return sorted(items, key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))
