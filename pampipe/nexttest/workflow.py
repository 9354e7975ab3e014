"""`next_test`: rank a menu's tests for a mission's plan and check the top ones (docs/commands.md §14)."""

from __future__ import annotations

from pampipe.nexttest.preposterior import DEFAULT_TRUTHS, check
from pampipe.nexttest.ranking import DEFAULT_DRAWS, Planner, rank_menu
from pampipe.nexttest.result import NextTest
from pampipe.planning.confidence import DEFAULT_SEED, z_value


def next_test(mission, pam, pam_file, menu, *, confidence: float = 0.95, objective: str = "pressure",
              pairs: bool = False, samples: int = DEFAULT_DRAWS, seed: int = DEFAULT_SEED, checks: int = 0,
              truths: int = DEFAULT_TRUTHS, workers=None, scheduler=None) -> NextTest:
    """The linearised ranking of ``menu``'s tests (:mod:`pampipe.nexttest.ranking`) for ``mission`` planned at
    ``confidence`` with the muscle ``pam`` (read from ``pam_file``), and the preposterior check
    (:mod:`pampipe.nexttest.preposterior`) of the top ``checks`` over ``truths`` truths on ``workers``
    processes or the Dask ``scheduler``."""
    z_value(confidence)
    planner = Planner(mission, pam, pam_file, confidence, objective=objective, samples=samples, seed=seed)
    ranking = rank_menu(planner, menu.tests, pairs=pairs)
    top = [o.tests for o in ranking.ranked[:checks]]
    documents = check(planner, top, truths=truths, seed=seed, workers=workers, scheduler=scheduler) \
        if top else []
    return NextTest(str(pam_file or pam.name), str(mission.source), str(menu.source), ranking,
                    {k: d for k, d in enumerate(documents) if d is not None})
