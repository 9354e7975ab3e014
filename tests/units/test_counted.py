"""Counts read as English: '1 pipe', '2 pipes' (issue 42, item 8)."""

from __future__ import annotations

from pampipe.units.display import counted


def test_one_is_singular_and_every_other_count_plural():
    assert counted(1, "pipe") == "1 pipe"
    assert [counted(n, "test") for n in (0, 2, 1000)] == ["0 tests", "2 tests", "1000 tests"]
