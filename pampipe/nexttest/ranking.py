"""The linearised ranking of a menu's tests by what they take off the mission's plan (docs/commands.md,
next-test).

For each test (and, with ``pairs``, each pair: their informations add) the muscle's posterior Σ₁
(:mod:`.posterior`) replaces the PAM's uncertainty in every segment that carries it, and plan's own sampled
C-quantile (:func:`pampipe.planning.confidence.plan_confidence`, the same seeded draws for every
candidate: common random numbers) gives the planned pressures P_C of every section and segment. The
criterion (c-optimal on the plan's quantity, through the hinge of first contact, the worst bore and the
quantile) is J = max P_C over the valid elements (``objective="pressure"``) or the air-weighted mean
Σ V·P_C / Σ V, V the enclosed volume at the anchored length (``objective="air"``). The open undetermined
directions are drawn over their posterior width (the plan "on the prior"), so J exists where plan would
stop; whether it still stops (exit 3) is a second plan with them listed. Candidates are ranked by the
predicted drop J₀ − J₁ per unit cost (a drop from an infinite J₀ is infinite: then by J₁, then cost). Beside
it, the D-optimal pick: the largest log det(I + Σ₀F) per unit cost (:func:`.posterior.information_gain`).
"""

from __future__ import annotations

import copy
import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np

from pampipe.errors import InputError
from pampipe.model.muscle import Muscle
from pampipe.nexttest.information import fisher
from pampipe.nexttest.posterior import extended, information_gain, planned_uncertainty, posterior
from pampipe.planning.confidence import DEFAULT_SEED, plan_confidence
from pampipe.planning.problem import build_elements, mission_muscles

OBJECTIVES = ("pressure", "air")
DEFAULT_DRAWS = 10_000


@dataclass(frozen=True)
class Outcome:
    """What a plan would be after a candidate (or today, with no test)."""

    tests: tuple  # the menu tests (one, or two with ``pairs``)
    cost: float  # [s]
    pressure: float  # [Pa] J after the test(s), on the prior along the directions left open
    pressure_sd: float  # [Pa] its Monte Carlo spread (order-statistic band) or, checked, over the truths
    closes: int  # undetermined directions it closes
    left_open: int  # undetermined directions still open
    stops: bool  # an open direction still stops the plan (exit 3)
    information_gain: float  # [nats] log det(I + Σ₀F)


@dataclass(frozen=True)
class Ranking:
    """Today's plan and every candidate's outcome, best first, and the D-optimal pick."""

    current: Outcome
    ranked: tuple[Outcome, ...]
    d_optimal: Outcome
    objective: str
    confidence: float
    samples: int
    seed: int


def drop(before: float, after: float) -> float:
    """J₀ − J₁ [Pa] (inf from an infinite J₀ to a finite J₁, 0 between two infinite ones)."""
    if math.isinf(before) and math.isinf(after):
        return 0.0
    return before - after


def order_key(current: Outcome, outcome: Outcome) -> tuple:
    """Largest drop per unit cost first, then the lower J₁, then the cheaper."""
    gain = drop(current.pressure, outcome.pressure)
    per_cost = gain / outcome.cost if outcome.cost > 0 else (math.inf if gain > 0 else 0.0)
    return (-per_cost, outcome.pressure, outcome.cost, tuple(t.entry for t in outcome.tests))


class Planner:
    """The mission with the tested PAM's uncertainty replaced, planned at C on fixed seeded draws."""

    def __init__(self, mission, pam, pam_file, confidence: float, *, objective: str = "pressure",
                 samples: int = DEFAULT_DRAWS, seed: int = DEFAULT_SEED):
        if objective not in OBJECTIVES:
            raise InputError(f"--objective: {objective!r} is not one of {', '.join(OBJECTIVES)}.")
        self.carriers = [i for i, seg in enumerate(mission.segments) if _same(seg, pam, pam_file)]
        if not self.carriers:
            raise InputError(f"{mission.source}: no segment of the mission carries the PAM "
                             f"'{pam.name}'{f' ({pam_file})' if pam_file else ''}: next-test ranks tests of "
                             "the muscle the mission plans with; give a PAM file one of its segments names.")
        self.mission, self.pam, self.confidence = mission, pam, confidence
        self.objective, self.samples, self.seed = objective, samples, seed
        self.muscles = mission_muscles(mission)
        self.elements = build_elements(mission, self.muscles)
        self.muscle = Muscle.from_pam(pam)
        self.tested = all(mission.segments[i].unit == "tested" for i in self.carriers)
        self.uncertainty = extended(pam, self.tested)

    def carrying(self, pam):
        """The mission with the carriers' PAM replaced by ``pam``."""
        segments = tuple(dataclasses.replace(seg, pam=pam) if i in self.carriers else seg
                         for i, seg in enumerate(self.mission.segments))
        return dataclasses.replace(self.mission, segments=segments)

    def plan(self, uncertainty):
        """plan_confidence (serial: each plan is short) with the carriers' PAM holding ``uncertainty``."""
        mission = self.carrying(self.pam.with_uncertainty(uncertainty))
        return plan_confidence(mission, self.muscles, self.elements, self.confidence, samples=self.samples,
                               seed=self.seed)

    def refitted(self, pam) -> tuple[float, bool]:
        """(J [Pa], plan stops) with the carriers' muscle refitted to ``pam`` (its nominal moved too): J on
        the prior along the directions its fit leaves open, as :meth:`outcome`."""
        other = copy.copy(self)
        other.pam, other.mission = pam, self.carrying(pam)
        other.muscles = mission_muscles(other.mission)
        other.elements = build_elements(other.mission, other.muscles)
        other.uncertainty = u = extended(pam, self.tested)
        value = other.value(other.plan(planned_uncertainty(u, posterior(u, np.zeros((len(u.names),) * 2)),
                                                           on_prior=True)))[0]
        return value, _stops(other.plan(pam.uncertainty))

    def value(self, sampled) -> tuple[float, float]:
        """(J [Pa], its Monte Carlo sd [Pa]) of a sampled plan (module docstring)."""
        valid = np.asarray(self.elements.valid)
        pressure = np.where(valid, sampled.pressure, np.nan)
        band = sampled.pressure_ci95
        sd = (band[..., 1] - band[..., 0]) / (2 * 1.959964)
        if not valid.any():
            return math.nan, math.nan
        if self.objective == "air":
            volume = np.where(valid, np.asarray(self.elements.volume), 0.0)
            total = float(volume.sum())
            return (float(np.nansum(volume * pressure) / total),
                    float(math.sqrt(np.nansum((volume * np.where(valid, sd, 0.0)) ** 2)) / total))
        k = np.unravel_index(int(np.nanargmax(np.where(valid, pressure, -np.inf))), pressure.shape)
        return float(pressure[k]), float(sd[k])

    def outcome(self, tests: tuple, stopped_now: bool) -> Outcome:
        """A candidate's predicted plan (module docstring); no tests: today's, on the prior."""
        u = self.uncertainty
        information = sum((fisher(self.muscle, u, t) for t in tests), np.zeros((len(u.names),) * 2))
        post = posterior(u, information)
        value, sd = self.value(self.plan(planned_uncertainty(u, post, on_prior=True)))
        stops = stopped_now and bool(post.open_vectors) and _stops(self.plan(
            planned_uncertainty(u, post, on_prior=False)))
        return Outcome(tests, float(sum(t.cost for t in tests)), value, sd, post.closed,
                       len(post.open_vectors), stops, information_gain(u, information))


def rank_menu(planner: Planner, tests, *, pairs: bool = False) -> Ranking:
    """Today's plan, every candidate ranked (module docstring) and the D-optimal pick."""
    stopped_now = _stops(planner.plan(planner.pam.uncertainty))
    current = dataclasses.replace(planner.outcome((), False), stops=stopped_now)
    candidates = [(t,) for t in tests]
    if pairs:
        candidates += list(itertools.combinations(tests, 2))
    outcomes = [planner.outcome(c, stopped_now) for c in candidates]
    ranked = tuple(sorted(outcomes, key=lambda o: order_key(current, o)))
    d_optimal = max(outcomes, key=lambda o: (o.information_gain / o.cost if o.cost > 0 else math.inf,
                                             -o.cost, -o.tests[0].entry))
    return Ranking(current, ranked, d_optimal, planner.objective, planner.confidence, planner.samples,
                   planner.seed)


def _stops(sampled) -> bool:
    return sampled.stopped is not None and bool(np.any(sampled.stopped))


def _same(segment, pam, pam_file) -> bool:
    """The segment carries the tested PAM: the same file, or (inline or no file named) the same muscle."""
    if pam_file is not None and segment.pam_file is not None:
        return segment.pam_file.resolve() == pam_file.resolve()
    return segment.pam == pam
