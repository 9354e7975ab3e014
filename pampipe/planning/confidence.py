"""Pressure that holds with probability C, by sampling every uncertain input (docs/physics.md §15).

Per draw k of the sources (:mod:`pampipe.planning.sources`) the least holding pressure is the closed
form the plan uses, P*_k = max over the bores D of the range (smallest, worst, largest, each + δ_k) of
    P*(D) = P_a(D, κ_kW_k) + x,   μ_kπA·(F₁x + contact increments) = SF·W_k   (docs/physics.md §8.3),
with the axial force shifted by the model error e_k (F₀ → F₀ + e_k). The condition "holds" is
P ≥ P*_k, which contains "touches the wall" (P ≥ P_a): the hinge at first contact is exact in every
draw, where a first-order propagation through it is not. The planned pressure is the empirical
C-quantile of P*_k (the least P that holds in at least a share C of the draws), its
``holding_probability`` the share of draws it holds in (Monte Carlo standard error √(p(1−p)/n)), and
``contact_probability`` the share in which the unloaded muscle touches the largest bore.

The draws are the same for every section and segment where they are in reality (one fit per PAM file,
one muscle per ``unit: lot`` segment, one for the ``unit: tested`` segments of a PAM file, one κ, one
friction draw per wall material) and keyed by the bore's statement
(:mod:`pampipe.planning.sources`). Sections alike in every input form one class, sampled once, in chunks of
bounded memory on any executor (:mod:`pampipe.planning.sampling`); the closed forms run vectorised over
draws × classes through one :class:`Muscle` whose fields are arrays (20× faster than a mapped CasADi
Function of the same expressions, equal to 3e-15). The dominance table repeats the quantile with one
source at a time (the others at their nominal values): the pressure each adds.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from pampipe.errors import InputError
from pampipe.planning.classes import Classes, Problem, section_classes
from pampipe.planning.evaluator import draws_key
from pampipe.planning.feasibility import pressure_limits
from pampipe.planning.quantiles import level_text, tail
from pampipe.planning.sampling import (
    BYTES_PER_DRAW,
    CANDIDATE_CHUNKS,
    MEMORY_BUDGET,
    by_candidates,
    chunk_classes,
    drawn_muscles,
    sample_chunk,
    segment_twins,
)
from pampipe.planning.sources import (
    SOURCE_WORDS,
    SOURCES,
    Direction,
    muscle_sources,
    muscle_uncertainty,
)
from pampipe.planning.tension import drawn_drag, section_drag
from pampipe.runtime.alike import Picked
from pampipe.runtime.executors import executor, run_all
from pampipe.runtime.memory import check_fits
from pampipe.runtime.progress import deferred

METHOD = "monte_carlo"
DEFAULT_SAMPLES = 4000
DEFAULT_SEED = 22


#: The fewest draws expected not to hold at the plan, N(1 − C): with fewer the C-quantile is one of the
#: largest few draws, and the plan and its P(hold) say more than the draws can resolve.
FAILING_DRAWS = 10


def z_value(confidence: float) -> float:
    """Check 0.5 ≤ C < 1 (InputError otherwise) and return C."""
    if not (0.5 <= confidence < 1):
        raise InputError(f"--confidence: {level_text(confidence)} must be a probability in [0.5, 1), e.g. "
                         "0.95.")
    return confidence


def check_resolution(confidence: float, samples: int) -> None:
    """InputError unless N(1 − C) ≥ :data:`FAILING_DRAWS`: the draws must resolve the C-quantile."""
    share = tail(confidence)
    expected = samples * share
    if expected < FAILING_DRAWS * (1 - 1e-12):
        need = math.ceil(FAILING_DRAWS / share * (1 - 1e-12))
        most = math.floor((1 - FAILING_DRAWS / samples) * 1e6) / 1e6
        raise InputError(
            f"--confidence {level_text(confidence)} with --samples {samples}: only {expected:.3g} of the "
            f"draws would be expected not to hold, too few to resolve the {level_text(confidence)} quantile "
            f"(the plan would be one of the largest draws and P(hold) 1); N(1 - C) must be at least "
            f"{FAILING_DRAWS}: give --samples {need} or more, or --confidence {level_text(most)} or less.")


def check_draws_fit(structures, samples: int) -> None:
    """InputError when the draws of ``samples`` would not fit in the available memory (before allocating):
    each segment's three parameter blocks and model error, and one class's chunk arrays."""
    per_draw = BYTES_PER_DRAW + sum(8 * (3 * s.size + 2) for s in structures)
    check_fits(samples * per_draw, what=f"--samples {samples}: the draws",
               advice="give fewer draws (N(1 - C) of 10 to 100 resolves the quantile; 4000 by default)")


@dataclass(frozen=True)
class Confidence:
    """The sampled plan of every element, (sections, segments) arrays, SI."""

    level: float
    samples: int
    seed: int
    pressure: np.ndarray  # [Pa], the C-quantile of P*
    holding_probability: np.ndarray
    holding_se: np.ndarray  # Monte Carlo standard error of holding_probability
    contact_probability: np.ndarray  # the unloaded muscle touches the largest bore at ``pressure``
    pressure_at: dict[str, np.ndarray]  # {"0.9": [Pa], ...}
    pressure_ci95: np.ndarray  # (S, segments, 2) [Pa], order-statistic band of the planned pressure
    shifts: dict[str, np.ndarray]  # source → C-quantile with that source alone − the certain P* [Pa]
    low_shifts: dict[str, np.ndarray]  # source → (1 − C)-quantile with that source alone − the certain P*
    certain: np.ndarray  # [Pa] P* with every source at its nominal value (max over the range's bores)
    # s → (i, d, ΔP, margin [Pa]): the first segment an undetermined direction stops there (exit 3)
    undetermined: dict[int, tuple[int, Direction, float, float]] = field(default_factory=dict)
    prior: bool = False  # some margin rests on a prior (--prior-from or stated sds)
    payload: np.ndarray | None = None  # [kg], element payload held with probability C at supply
    units: tuple[str, ...] = ()  # per segment, the muscle each probability is for: "tested" | "lot"
    open_shift: np.ndarray | None = None  # [Pa] what covering the undetermined directions adds (NaN: none)
    stopped: np.ndarray | None = None  # bool, the elements an undetermined direction stops (exit 3)

    def is_stopped(self, s: int, i: int) -> bool:
        """True where an undetermined direction stops segment i in section s: no number is given."""
        return self.stopped is not None and bool(self.stopped[s, i])

    def dominant(self) -> list[dict]:
        """Sources by the largest pressure they add alone, over the feasible elements, largest first;
        ``pressure_shift_Pa`` is None (JSON null) where no element is feasible (nothing to add to)."""
        rows = []
        for name, shift in self.shifts.items():
            finite = np.where(np.isfinite(shift), shift, np.nan)
            worst = float(np.nanmax(finite)) if np.any(np.isfinite(finite)) else None
            rows.append({"source": name, "what": SOURCE_WORDS[name], "pressure_shift_Pa": worst})
        return sorted(rows, key=lambda r: -(r["pressure_shift_Pa"] or 0.0))

    def as_document(self) -> dict:
        sources = self.dominant()
        return {"level": self.level, "method": METHOD, "samples": self.samples, "seed": self.seed,
                "dominant": [r["source"] for r in sources], "sources": sources, "prior": self.prior}

    def element_document(self, s: int, i: int) -> dict:
        """The keys one segment of one section gains (docs/commands.md §4.5): ``unit``, the muscle its
        probabilities are for; where its fit leaves directions undetermined, ``undetermined`` (stopped or
        not) and ``undetermined_shift_Pa``, what covering them adds; a stopped segment has no pressure and
        no probability: null; a pressure no draw reaches in the share asked (a quantile beyond what
        holds) is null too."""
        shift = math.nan if self.open_shift is None else float(self.open_shift[s, i])
        opened = {} if math.isnan(shift) else {"undetermined": self.is_stopped(s, i),
                                                "undetermined_shift_Pa": shift}
        if self.is_stopped(s, i):
            return {"unit": self.units[i], "pressure_Pa": None, "holding_probability": None,
                    "holding_probability_se": None, "contact_probability": None,
                    "pressure_at_Pa": dict.fromkeys(self.pressure_at), "pressure_ci95_Pa": None, **opened}
        return {"unit": self.units[i], "holding_probability": float(self.holding_probability[s, i]),
                "holding_probability_se": float(self.holding_se[s, i]),
                "contact_probability": float(self.contact_probability[s, i]),
                "pressure_at_Pa": {k: _finite(v[s, i]) for k, v in self.pressure_at.items()},
                "pressure_ci95_Pa": [_finite(x) for x in self.pressure_ci95[s, i]], **opened}

    def element_columns(self, rows: slice, complete: np.ndarray) -> dict | None:
        """The entries of :meth:`element_document` of sections ``rows`` as columns for the column-wise JSON
        writer (:mod:`pampipe.io.json_columns`): one value per segment of each complete section, sections
        first, as :meth:`pampipe.planning.result.MissionPlan.section_columns` lays out its segments. None
        where a segment there is stopped or has an undetermined shift: their entries differ from segment to
        segment (the writer then takes the documents)."""
        def flat(column: np.ndarray) -> np.ndarray:
            return column[rows][complete].ravel()

        if self.stopped is not None and flat(self.stopped).any():
            return None
        if self.open_shift is not None and not np.isnan(flat(self.open_shift)).all():
            return None
        return {"unit": Picked(self.units, np.tile(np.arange(len(self.units)), int(complete.sum()))),
                "holding_probability": flat(self.holding_probability),
                "holding_probability_se": flat(self.holding_se),
                "contact_probability": flat(self.contact_probability),
                "pressure_at_Pa": {key: flat(value) for key, value in self.pressure_at.items()},
                "pressure_ci95_Pa": self.pressure_ci95[rows][complete].reshape(-1, 2)}


def _finite(value) -> float | None:
    """A pressure [Pa] for a document: None where it is infinite (no pressure holds in that share)."""
    value = float(value)
    return value if math.isfinite(value) else None


def check_uncertainty(mission, uncertainties) -> None:
    """--confidence needs muscles without diagnosed effects and at least one source of uncertainty."""
    diagnosed = [seg.pam.name for seg in mission.segments if seg.pam.effects]
    if diagnosed:
        raise InputError(
            f"{mission.source}: --confidence does not yet propagate uncertainty through diagnosed effects; "
            f"the PAM(s) {', '.join(sorted(set(diagnosed)))} carry an 'effects:' block. Plan without "
            "--confidence, or use the PAM file written by `pampipe identify`.")
    route = mission.route
    muscle_sources = any(np.any(u.fit) or np.any(u.tolerance) or u.model_error > 0 or u.undetermined
                         for u in uncertainties)
    tether = getattr(mission, "tether", None)
    if not (muscle_sources or np.any(route.friction_sd > 0) or np.any(route.diameter_sd > 0)
            or getattr(mission, "kappa_sd", 0.0) > 0 or (tether is not None and tether.friction_sd > 0)):
        raise InputError(
            f"{mission.source}: --confidence needs an uncertainty: no PAM file has an 'uncertainty:' "
            "block (written by `pampipe identify`) or a geometry '{value, sd}', and no route section gives "
            "'friction: {value: 0.3, sd: 0.05}' or 'inner_diameter: {value: 3 in, sd: 0.5 mm}'.")


def sampling_problem(mission, muscles, elements, confidence: float, *, samples: int, seed: int, prior=None,
                     with_payload: bool = False) -> tuple[Problem, Classes, np.ndarray]:
    """(what every chunk shares, the classes of alike sections, the class of each section), checked."""
    z_value(confidence)
    if not (isinstance(samples, int) and samples >= 100):
        raise InputError(f"--samples: {samples!r} must be a whole number of at least 100 draws.")
    if not (isinstance(seed, int) and seed >= 0):
        raise InputError(f"--seed: {seed!r} must be a whole number of at least 0, e.g. 22.")
    check_resolution(confidence, samples)
    check_draws_fit([m.structure for m in muscles], samples)
    uncertainties = [muscle_uncertainty(seg, m, where=f"{mission.source}: robot.segments[{i}].pam",
                                        prior=prior)
                     for i, (seg, m) in enumerate(zip(mission.segments, muscles, strict=True))]
    check_uncertainty(mission, uncertainties)
    route = mission.route
    kappa_sd = float(getattr(mission, "kappa_sd", 0.0))
    key = draws_key(tuple(uncertainties), samples, seed, kappa_sd)
    draws = drawn_muscles(key, tuple(uncertainties), samples, seed, kappa_sd)  # the chunks reuse them
    active = muscle_sources(draws)
    active += [name for name, sd in (("bore", route.diameter_sd), ("friction", route.friction_sd))
               if np.any(np.asarray(sd) > 0)]
    drag, drag_draws = section_drag(mission), drawn_drag(mission, samples, seed)
    active += ["tether"] if drag_draws is not None else []
    problem = Problem(tuple(m.structure for m in muscles), tuple(uncertainties), samples, seed, confidence,
                      tuple(s for s in SOURCES if s in active), float(mission.kappa), kappa_sd,
                      float(mission.safety_factor),
                      float(sum(seg.mass for seg in mission.segments) + mission.payload),
                      tuple(float(seg.mass) for seg in mission.segments), float(mission.tether_drag),
                      float(mission.payload),
                      tuple(float(x) for x in pressure_limits(mission)) if with_payload else None,
                      key)
    twins = segment_twins(problem, draws, np.asarray(elements.diameter), np.asarray(elements.valid))
    classes, inverse = section_classes(route, elements, drag, drag_draws)
    limits = tuple(float(x) for x in pressure_limits(mission))
    return dataclasses.replace(problem, twins=twins, limits=limits), classes, inverse


def plan_confidence(mission, muscles, elements, confidence: float, *, samples: int = DEFAULT_SAMPLES,
                    seed: int = DEFAULT_SEED, prior=None, with_payload: bool = False,
                    workers: int | None = None, scheduler: str | None = None,
                    budget: int = MEMORY_BUDGET) -> Confidence:
    """The sampled plan of every valid element at confidence C (see the module docstring).

    ``prior`` is a :class:`~pampipe.model.pam.Pam` whose uncertainty (and moduli) serve as the prior along
    undetermined directions; ``with_payload`` adds the payload held with probability C at each segment's
    pressure limit (the supply, or its PAM's lower ``max_pressure``). The classes of alike sections are
    sampled in chunks of at most ``budget`` bytes, on ``workers`` local processes or the Dask
    ``scheduler`` (:mod:`pampipe.runtime.executors`), with the same result on each.
    """
    problem, classes, inverse = sampling_problem(mission, muscles, elements, confidence, samples=samples,
                                                 seed=seed, prior=prior, with_payload=with_payload)
    uncertainties = problem.uncertainties
    size = chunk_classes(samples, budget) * (CANDIDATE_CHUNKS if by_candidates(problem, classes) else 1)
    tasks = [(problem, classes.part(slice(start, start + size))) for start in range(0, len(classes), size)]
    # a sampling that takes more than a second says what it does; several chunks are counted as they finish
    with executor(workers=workers, scheduler=scheduler) as pool, deferred() as later:
        later(f"confidence {confidence:g}: {samples} draws of each of {len(classes)} kind(s) of section in "
              f"{len(tasks)} chunk(s) ...")
        parts = run_all(sample_chunk, tasks, pool, what="confidence chunks" if len(tasks) > 1 else None)

    def joined(get):
        return np.concatenate([get(r) for r in parts])[inverse]

    shift, stopped = joined(lambda r: r.open_shift), joined(lambda r: r.stopped)
    base, which = joined(lambda r: r.open_base), joined(lambda r: r.open_direction)
    undetermined = {}
    for s in np.flatnonzero(stopped.any(axis=1)).tolist():
        i = int(np.argmax(stopped[s]))
        margin = problem.limits[i] - base[s, i]
        direction = uncertainties[i].unresolved[int(which[s, i])]
        undetermined[s] = (i, direction, float(shift[s, i]), float(margin))
    holding = joined(lambda r: r.holding)
    used_prior = any(u.undetermined and not u.unresolved for u in uncertainties)
    return Confidence(
        confidence, samples, seed, joined(lambda r: r.pressure), holding,
        np.sqrt(holding * (1 - holding) / samples), joined(lambda r: r.contact),
        {key: joined(lambda r, key=key: r.levels[key]) for key in parts[0].levels}, joined(lambda r: r.band),
        {k: joined(lambda r, k=k: r.shifts[k]) for k in problem.active},
        {k: joined(lambda r, k=k: r.low_shifts[k]) for k in problem.active},
        joined(lambda r: r.certain), undetermined, used_prior,
        joined(lambda r: r.payload) if with_payload else None, tuple(u.unit for u in uncertainties),
        shift, stopped)
