"""The result of `pampipe next-test` and its JSON document (docs/commands.md, next-test; interfaces §9.4)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from pampipe.nexttest.ranking import Outcome, Ranking, drop
from pampipe.results import notebook


def _text():
    from pampipe.views.nexttest_text import result_text

    return result_text


def _plot():
    from pampipe.views.plots.nexttest import plot_next_test

    return plot_next_test


def finite(value: float) -> float | None:
    """JSON has no inf: None stands for "no pressure holds" (or no number)."""
    return float(value) if math.isfinite(value) else None


def predicted_document(current: Outcome, o: Outcome) -> dict:
    """``predicted`` of one candidate: the plan after it, its spread, the drop, the directions it closes."""
    gain = drop(current.pressure, o.pressure)
    return {"pressure_Pa": finite(o.pressure), "pressure_sd_Pa": finite(o.pressure_sd),
            "drop_Pa": finite(gain), "drop_per_hour_Pa": finite(gain / o.cost * 3600) if o.cost > 0 else None,
            "closes_undetermined": o.closes, "undetermined_left": o.left_open, "exit_3": o.stops,
            "information_gain": o.information_gain}


def candidate_document(current: Outcome, o: Outcome, checked=None) -> dict:
    """One ranked candidate: ``test`` (the first of a pair; ``tests`` lists both), ``cost_s``, ``predicted``
    and, for the top few, ``checked`` (the preposterior check)."""
    doc = {"test": o.tests[0].as_document(), "tests": [t.as_document() for t in o.tests],
           "entries": [t.entry for t in o.tests], "label": " + ".join(t.describe() for t in o.tests),
           "cost_s": o.cost, "predicted": predicted_document(current, o)}
    if checked is not None:
        doc["checked"] = checked
    return doc


@notebook(headline=("pam", "mission", "confidence", "best", "current_pressure_Pa"), text=_text, plot=_plot)
@dataclass(frozen=True)
class NextTest:
    """Today's plan at C, the menu's tests ranked by predicted drop per unit cost, the D-optimal pick."""

    pam: str
    mission: str
    menu: str
    ranking: Ranking = field(repr=False)
    checks: dict = field(default_factory=dict, repr=False)  # rank index → the preposterior check document
    command: str = ""  # the command line that would rank the tests again
    wall_time: float = 0.0

    def timed(self, wall_time: float) -> NextTest:
        return replace(self, wall_time=wall_time)

    @property
    def best(self) -> Outcome:
        return self.ranking.ranked[0]

    def to_dict(self) -> dict:
        r = self.ranking
        current = r.current
        return {"pam": self.pam, "mission": self.mission, "menu": self.menu, "confidence": r.confidence,
                "objective": r.objective, "samples": r.samples, "seed": r.seed,
                "best": " + ".join(t.describe() for t in self.best.tests),
                "current_pressure_Pa": finite(current.pressure),
                "current": {"pressure_Pa": finite(current.pressure),
                            "pressure_sd_Pa": finite(current.pressure_sd),
                            "undetermined": current.left_open, "exit_3": current.stops},
                "ranked": [candidate_document(current, o, self.checks.get(k))
                           for k, o in enumerate(r.ranked)],
                "d_optimal": candidate_document(current, r.d_optimal),
                "wall_time_s": self.wall_time}
