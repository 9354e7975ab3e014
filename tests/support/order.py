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
