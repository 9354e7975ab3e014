"""`rehearse --confidence C`: the chance that the robot gets through, and where it first slips
(docs/physics.md §16.4).

The robot walks at the pressures of `plan --confidence C` (the table a controller would be given). Each of the
n seeded draws of `plan --confidence` (the same draws: every source it samples, the tether's friction sd among
them, physics.md §15 and §16.1) gives every element its least holding pressure P*_k; in that draw the robot
slips in the first walked section where some segment's P*_k exceeds its planned pressure, and stops there. The
completion probability is the share of draws with no slip along the whole route (0 when the walk itself stops
short of the route's end); each section gets the share of draws whose first slip is there; the time and air of
a draw are those of the walk up to the entry of the section where it slips (the whole walk if none), and their
C-quantiles (the least value not exceeded in a share C of the draws) are reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements
from pampipe.planning.sampling import class_deviations, muscle_draws


@dataclass(frozen=True)
class Completion:
    """The Monte Carlo of a rehearsal at confidence ``level``."""

    level: float
    samples: int
    seed: int
    probability: float  # share of the draws that complete the route
    first_slip: np.ndarray  # (S,) share of the draws whose first slip is in each section
    time: float  # [s] C-quantile of the time walked
    free_air: float  # [m³] normal, C-quantile of the air used
    sources: tuple[str, ...]  # what was sampled

    @property
    def standard_error(self) -> float:
        """√(p(1 − p)/n) of the completion probability."""
        return math.sqrt(self.probability * (1 - self.probability) / self.samples)

    def as_document(self, route, entry: np.ndarray) -> dict:
        slips = [{"section": str(route.name[s]), "distance_m": float(entry[s]),
                  "probability": float(self.first_slip[s])} for s in np.flatnonzero(self.first_slip > 0)]
        return {"level": self.level, "samples": self.samples, "seed": self.seed,
                "sources": list(self.sources), "completion_probability_se": self.standard_error,
                "first_slip": slips,
                "time_s": self.time, "free_air_m3": self.free_air}


def completion(mission, plan, walk, *, level: float, samples: int, seed: int) -> Completion:
    """The draws of ``plan`` (a `plan --confidence` plan of ``mission``) against its pressures, over
    ``walk``."""
    muscles = plan.muscles
    elements = build_elements(mission, muscles)
    problem, classes, inverse = sampling_problem(mission, muscles, elements, level, samples=samples,
                                                 seed=seed)
    draws = muscle_draws(problem)
    bore, friction = class_deviations(problem, classes)
    walked = np.flatnonzero(walk.walked > 0)
    slips = np.zeros((samples, walked.size), dtype=bool)
    needed = np.unique(inverse[walked])
    for i in range(len(muscles)):
        rows = needed[classes.valid[needed, i]]
        if rows.size == 0:
            continue
        column = np.full(len(classes), -1)
        column[rows] = np.arange(rows.size)
        least = Evaluator(problem, draws, classes, i, rows, bore[rows].T, friction[rows].T).evaluate(
            problem.active)[0]
        picked = column[inverse[walked]]
        held = picked >= 0
        slips[:, held] |= least[:, picked[held]] > plan.arrays.pressure[walked[held], i][None, :]
    slipped = slips.any(axis=1)
    first = np.where(slipped, walked[np.argmax(slips, axis=1)], -1)
    share = np.bincount(first[slipped], minlength=len(mission.route)) / samples
    route_done = bool(np.all(walk.walked == mission.route.length))
    elapsed = np.concatenate([[0.0], np.cumsum(walk.time)])
    used = np.concatenate([[0.0], np.cumsum(walk.free_air)])
    stop = np.where(slipped, first, len(mission.route))
    time = float(np.quantile(elapsed[stop], level, method="inverted_cdf"))
    air = float(np.quantile(used[stop], level, method="inverted_cdf"))
    probability = float(np.mean(~slipped)) if route_done else 0.0
    return Completion(level, samples, seed, probability, share, time, air, problem.active)
