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
one muscle per segment, one κ) and independent per section for bore and friction. The closed forms run
vectorised over draws × sections through one :class:`Muscle` whose fields are arrays (20× faster than a
mapped CasADi Function of the same expressions, equal to 3e-15). The dominance table repeats the
quantile with one source at a time (the others at their nominal values): the pressure each adds.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from pampipe.errors import InputError
from pampipe.model.muscle import Muscle, Structure
from pampipe.model.pam import Geometry
from pampipe.model.slip import STANDARD_GRAVITY, incline_load
from pampipe.planning.feasibility import pressure_limits
from pampipe.planning.sources import SOURCE_WORDS, Direction, draw, muscle_uncertainty

METHOD = "monte_carlo"
LEVELS = (0.9, 0.99, 0.999)  # the pressures every confidence plan reports
DEFAULT_SAMPLES = 4000
DEFAULT_SEED = 22
#: Draws × sections evaluated per vectorised call (bounds memory for long routes).
BATCH = 1 << 17
#: An undetermined direction "moves" a hold when ± its open width moves P* by more than this [Pa] (1 kPa).
MOVES = 1e3


def draw_values(structure: Structure, p: np.ndarray, d, w, kappa, mu, sf: float, e, pressure: float):
    """(P* [Pa], P_a(D, 0) [Pa], W_max(P) [N]) for columns of parameter vectors ``p`` (size, N) and
    arrays (N,) of bore D [m], load W [N], κ, μ and model error ``e`` [N] (a shift of F_ax at the anchored
    length), at ``pressure`` P [Pa] for W_max.

    One :class:`Muscle` whose fields are the N columns, so the closed forms the plan uses
    (:meth:`Muscle.closed_form_pressure`, inf where it does not hold) run vectorised over every draw.
    """
    n = structure.n_theta
    geometry = Geometry(p[0], p[1], p[2], p[3], structure.wall)
    muscle = Muscle(geometry, p[5:5 + n], p[4], contact=p[5 + n:5 + 2 * n] if structure.contact else None)
    with np.errstate(all="ignore"):
        c = muscle.affine_coefficients(d)
        c = dataclasses.replace(c, at_zero=c.at_zero + e)
        least = muscle.closed_form_pressure(d, w, kappa=kappa, friction=mu, safety_factor=sf, anchored=c)
        touch = -c.at_zero / c.slope
        stiffening = 1 + (c.contact_at_zero + c.contact_slope * pressure) / (p[4] * c.slope)
        grip = mu * math.pi * c.amplification * stiffening
        largest = grip * (c.at_zero + c.slope * pressure) / (sf + kappa * grip)
    return [np.asarray(v, dtype=float) * np.ones(np.shape(d)) for v in (least, touch, largest)]


def z_value(confidence: float) -> float:
    """Check 0.5 ≤ C < 1 (InputError otherwise) and return C."""
    if not (0.5 <= confidence < 1):
        raise InputError(f"--confidence: {confidence!r} must be a probability in [0.5, 1), e.g. 0.95.")
    return confidence


def upper_quantile(values: np.ndarray, level: float, axis: int = 0) -> np.ndarray:
    """Least x with a share ≥ level of ``values`` ≤ x (the empirical, inverted-CDF quantile)."""
    n = values.shape[axis]
    k = max(math.ceil(level * n - 1e-9) - 1, 0)
    return np.take(np.sort(values, axis=axis), k, axis=axis)


def lower_quantile(values: np.ndarray, level: float, axis: int = 0) -> np.ndarray:
    """Largest x with a share ≥ level of ``values`` ≥ x."""
    n = values.shape[axis]
    k = min(math.floor((1 - level) * n + 1e-9), n - 1)
    return np.take(np.sort(values, axis=axis), k, axis=axis)


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
    undetermined: dict[int, tuple[int, Direction, float]] = field(default_factory=dict)  # s → (i, d, ΔP)
    prior: bool = False  # some margin rests on a prior (--prior-from or stated sds)
    payload: np.ndarray | None = None  # [kg], element payload held with probability C at supply

    def dominant(self) -> list[dict]:
        """Sources by the largest pressure they add alone, over the feasible elements, largest first."""
        rows = []
        for name, shift in self.shifts.items():
            finite = np.where(np.isfinite(shift), shift, np.nan)
            worst = float(np.nanmax(finite)) if np.any(np.isfinite(finite)) else math.inf
            rows.append({"source": name, "what": SOURCE_WORDS[name], "pressure_shift_Pa": worst})
        return sorted(rows, key=lambda r: -r["pressure_shift_Pa"])

    def as_document(self) -> dict:
        return {"level": self.level, "method": METHOD, "samples": self.samples, "seed": self.seed,
                "dominant": [r["source"] for r in self.dominant()], "sources": self.dominant(),
                "prior": self.prior}

    def element_document(self, s: int, i: int) -> dict:
        """The keys one segment of one section gains (docs/commands.md §4.5); where an undetermined
        direction moves the section's hold there is no probability: null, and ``undetermined`` true."""
        if s in self.undetermined:
            return {"holding_probability": None, "holding_probability_se": None,
                    "contact_probability": None, "pressure_at_Pa": dict.fromkeys(self.pressure_at),
                    "pressure_ci95_Pa": None, "undetermined": True}
        return {"holding_probability": float(self.holding_probability[s, i]),
                "holding_probability_se": float(self.holding_se[s, i]),
                "contact_probability": float(self.contact_probability[s, i]),
                "pressure_at_Pa": {k: float(v[s, i]) for k, v in self.pressure_at.items()},
                "pressure_ci95_Pa": [float(x) for x in self.pressure_ci95[s, i]]}


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
    if not (muscle_sources or np.any(route.friction_sd > 0) or np.any(route.diameter_sd > 0)
            or getattr(mission, "kappa_sd", 0.0) > 0):
        raise InputError(
            f"{mission.source}: --confidence needs an uncertainty: no PAM file has an 'uncertainty:' "
            "block (written by `pampipe identify`) or a geometry '{value, sd}', and no route section gives "
            "'friction: {value: 0.3, sd: 0.05}' or 'inner_diameter: {value: 3 in, sd: 0.5 mm}'.")


class _Evaluator:
    """P*, first contact and W_max of one segment over draws × sections, for any subset of sources."""

    def __init__(self, mission, muscle: Muscle, i: int, elements, draws, sections: np.ndarray):
        self.structure, self.draws, self.i, self.s = muscle.structure, draws, i, sections
        self.nominal = muscle.parameter_vector()
        r = mission.route
        self.bores = [np.asarray(b, dtype=float)[sections] for b in
                      (r.diameter_low, elements.diameter[:, i], r.diameter_high)]
        if np.array_equal(self.bores[0], self.bores[2]):  # no tolerance range: one bore (3× fewer calls)
            self.bores = self.bores[2:]
        self.mu = np.asarray(r.friction, dtype=float)[sections]
        self.rise, self.run = np.abs(np.sin(r.incline[sections])), np.cos(r.incline[sections])
        self.total = sum(seg.mass for seg in mission.segments) + mission.payload
        self.mass, self.tether = mission.segments[i].mass, mission.tether_drag
        self.kappa, self.sf = mission.kappa, mission.safety_factor
        self.payload = mission.payload

    def inputs(self, sources, nominal=None) -> tuple:
        """(p (n, size), δ (n, S), μ (n, S), κ (n,), e (n,)) with only ``sources`` drawn around
        ``nominal`` (default: the muscle's parameter vector)."""
        d, i, n = self.draws, self.i, self.draws.n
        nominal = self.nominal if nominal is None else nominal
        p = np.broadcast_to(nominal, (n, nominal.size)).copy()
        for key in ("moduli", "geometry", "prior"):
            if key in sources:
                p += d.params[key][i]
        zero = np.zeros((n, self.s.size))
        bore = d.bore[:, self.s] if "bore" in sources else zero
        mu = self.mu + (d.friction[:, self.s] if "friction" in sources else zero)
        kappa = np.maximum(self.kappa + (d.kappa if "kappa" in sources else 0.0), 0.0)
        error = d.model_error[i] if "model_error" in sources else np.zeros(n)
        return p, bore, mu, kappa * np.ones(n), error

    def evaluate(self, sources, pressure=None, *, nominal=None):
        """(P* (n, S) [Pa], touch at the largest bore (n, S) [Pa], payload at ``pressure`` (n, S) [kg])."""
        p, bore, mu, kappa, error = self.inputs(sources, nominal)
        load = incline_load(self.total, self.mass, self.rise, self.run, mu, self.tether)
        n, count = mu.shape
        columns = n * count

        def flat(a):
            return np.broadcast_to(a, (n, count)).reshape(-1)

        at = 0.0 if pressure is None else float(pressure)
        results = []
        for bore_nominal in self.bores:
            values = _call(self.structure, columns, np.repeat(p, count, axis=0).T, flat(bore_nominal + bore),
                           flat(load), flat(kappa[:, None]), flat(mu), self.sf, flat(error[:, None]), at)
            results.append([v.reshape(n, count) for v in values])
        least = np.max([r[0] for r in results], axis=0)
        least = np.where(np.isnan(least), np.inf, least)
        touch = results[-1][1]  # the largest bore
        payload = None
        if pressure is not None:
            held = np.min([r[2] for r in results], axis=0)
            per_kg = STANDARD_GRAVITY * (self.rise + mu * self.run)
            payload = self.payload + (held - load) / np.where(per_kg > 0, per_kg, np.nan)
            payload = np.where((held >= 0) & (touch <= pressure) & (mu > 0) & np.isfinite(payload),
                               payload, -np.inf)
        return least, touch, payload


def _call(structure, columns: int, p, *args):
    """:func:`draw_values` over ``columns`` columns, in batches of at most :data:`BATCH` (bounded memory)."""
    out = [[], [], []]
    for start in range(0, columns, BATCH):
        part = slice(start, min(start + BATCH, columns))
        cut = [a[part] if np.ndim(a) == 1 and a.size == columns else a for a in args]
        for k, v in enumerate(draw_values(structure, p[:, part], *cut)):
            out[k].append(v)
    return [np.concatenate(o) for o in out]


def plan_confidence(mission, muscles, elements, confidence: float, *, samples: int = DEFAULT_SAMPLES,
                    seed: int = DEFAULT_SEED, prior=None, with_payload: bool = False) -> Confidence:
    """The sampled plan of every valid element at confidence C (see the module docstring).

    ``prior`` is a :class:`~pampipe.model.pam.Pam` whose uncertainty (and moduli) serve as the prior along
    undetermined directions; ``with_payload`` adds the payload held with probability C at each segment's
    pressure limit (the supply, or its PAM's lower ``max_pressure``).
    """
    z_value(confidence)
    if not (isinstance(samples, int) and samples >= 100):
        raise InputError(f"--samples: {samples!r} must be a whole number of at least 100 draws.")
    uncertainties = [muscle_uncertainty(seg, m, where=f"{mission.source}: robot.segments[{i}].pam",
                                        prior=prior)
                     for i, (seg, m) in enumerate(zip(mission.segments, muscles, strict=True))]
    check_uncertainty(mission, uncertainties)
    draws = draw(mission, uncertainties, samples, seed)
    shape = elements.load.shape
    pressure = np.full(shape, np.inf)
    holding, contact = np.zeros(shape), np.zeros(shape)
    levels = {f"{c:g}": np.full(shape, np.inf) for c in LEVELS}
    band = np.full((*shape, 2), np.inf)
    shifts = {name: np.full(shape, np.nan) for name in draws.active}
    low_shifts = {name: np.full(shape, np.nan) for name in draws.active}
    certain_all = np.full(shape, np.nan)
    payload = np.full(shape, -np.inf) if with_payload else None
    undetermined = {}
    limits = pressure_limits(mission)  # the supply, or a PAM's lower rated pressure
    n = samples
    half = 1.959964 * math.sqrt(n * confidence * (1 - confidence))
    ranks = (max(math.floor(n * confidence - half) - 1, 0), min(math.ceil(n * confidence + half) - 1, n - 1))
    for i, muscle in enumerate(muscles):
        rows = np.flatnonzero(elements.valid[:, i])
        if rows.size == 0:
            continue
        ev = _Evaluator(mission, muscle, i, elements, draws, rows)
        supply = limits[i] if with_payload else None
        least, touch, held = ev.evaluate(draws.active, supply)
        planned = upper_quantile(least, confidence)
        pressure[rows, i] = planned
        holding[rows, i] = np.mean(least <= planned, axis=0)
        contact[rows, i] = np.mean(touch <= planned, axis=0)
        ordered = np.sort(least, axis=0)
        band[rows, i] = ordered[list(ranks)].T
        for key, level in zip(levels, LEVELS, strict=True):
            levels[key][rows, i] = upper_quantile(least, level)
        if held is not None:
            payload[rows, i] = lower_quantile(held, confidence)
        certain = ev.evaluate(())[0][0]
        certain_all[rows, i] = certain
        for name in draws.active:
            alone = ev.evaluate((name,))[0]
            shifts[name][rows, i] = upper_quantile(alone, confidence) - certain
            low_shifts[name][rows, i] = upper_quantile(alone, 1 - confidence) - certain
        for d in uncertainties[i].unresolved:
            moved = _moves(ev, d)
            for k, s in enumerate(rows.tolist()):
                if abs(moved[k]) > MOVES and s not in undetermined:
                    undetermined[s] = (i, d, float(moved[k]))
    se = np.sqrt(holding * (1 - holding) / n)
    used_prior = any(u.undetermined and not u.unresolved for u in uncertainties)
    return Confidence(confidence, n, seed, pressure, holding, se, contact, levels, band, shifts, low_shifts,
                      certain_all, undetermined, used_prior, payload)


def _moves(ev: _Evaluator, direction: Direction) -> np.ndarray:
    """Change of the certain P* [Pa] per section across ± the width the data leave open along
    ``direction`` (inf where P* stops existing on either side)."""
    step = direction.scale * direction.step
    out = [ev.evaluate((), nominal=ev.nominal + sign * step)[0][0] for sign in (1.0, -1.0)]
    with np.errstate(invalid="ignore"):
        delta = out[0] - out[1]
    return np.where(np.isfinite(delta), delta, np.inf)
