"""`next_test`: rank a menu's tests for a mission's plan (docs/commands.md, next-test)."""

from __future__ import annotations

from pampipe.nexttest.ranking import DEFAULT_DRAWS, Planner, rank_menu
from pampipe.nexttest.result import NextTest
from pampipe.planning.confidence import DEFAULT_SEED, z_value


def next_test(mission, pam, pam_file, menu, *, confidence: float = 0.95, objective: str = "pressure",
              pairs: bool = False, samples: int = DEFAULT_DRAWS, seed: int = DEFAULT_SEED, workers=None,
              scheduler=None) -> NextTest:
    """The linearised ranking of ``menu``'s tests (:mod:`pampipe.nexttest.ranking`) for ``mission`` planned at
    ``confidence`` with the muscle ``pam`` (read from ``pam_file``)."""
    z_value(confidence)
    planner = Planner(mission, pam, pam_file, confidence, objective=objective, samples=samples, seed=seed,
                      workers=workers, scheduler=scheduler)
    ranking = rank_menu(planner, menu.tests, pairs=pairs)
    return NextTest(str(pam_file or pam.name), str(mission.source), str(menu.source), ranking)
