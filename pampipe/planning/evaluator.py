"""P* over draws × classes for any subset of the drawn sources: the costly part of a confidence plan
(docs/physics.md §15).

:class:`Evaluator` evaluates one segment over a chunk's classes. The muscle's coefficients F₀, F₁, A, C₀, C₁
at its anchored length (:func:`anchored_at`) depend on the muscle and the bore only: they are computed once
per draw and distinct drawn bore and kept per process (:data:`SHARED`), then the load-dependent closed form
P* = (κW − F₀ − e)/F₁ + SF·W/(μπAF₁) runs vectorised over classes × draws, and the worst of a range's bores is
kept: in its affine form W·k + (W/μ)·r − f (:mod:`pampipe.planning.law`, the per-draw k, r, f kept per process
too), or with contact increments or effects :meth:`Muscle.closed_form_pressure` (:func:`holding_law`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import math
import pickle
from typing import TYPE_CHECKING

import numpy as np

from pampipe.model.domain import outside_domain
from pampipe.model.muscle import Anchored, Muscle, Structure
from pampipe.model.no_slip import STANDARD_GRAVITY, incline_load_affine
from pampipe.model.pam import Geometry
from pampipe.planning.law import Terms, per_class, per_draw, raw_least, settle
from pampipe.planning.memo import Memo
from pampipe.planning.quantiles import order_statistics
from pampipe.runtime.alike import unique_rows

if TYPE_CHECKING:
    from pampipe.planning.classes import Classes, Problem
    from pampipe.planning.sources import MuscleDraws

#: Columns (draws × bores) per vectorised call of :func:`anchored_at`.
BATCH = 1 << 16
#: Bytes each process keeps across chunks (:data:`SHARED`): 80 coefficient columns of 10⁴ draws.
SHARED_BUDGET = 32 << 20
#: The coefficients of :class:`Anchored` the closed forms use (after ``length``, which they do not).
USED = ("amplification", "at_zero", "slope", "contact_at_zero", "contact_slope")
#: Per process, a segment's parameter draws and their coefficients in each drawn bore (:class:`Evaluator`).
SHARED = Memo(SHARED_BUDGET)


def draws_key(uncertainties: tuple, samples: int, seed: int, kappa_sd: float) -> str:
    """What names the route's draws: the muscles' sources, the draws, the seed (the bores' seed too)."""
    what = (tuple(uncertainties), samples, seed, kappa_sd)
    return hashlib.sha256(pickle.dumps(what, protocol=5)).hexdigest()


def _muscle(structure: Structure, p: np.ndarray) -> Muscle:
    """One :class:`Muscle` whose fields are the columns of ``p`` (size, ...): the numpy path of the one
    model (:mod:`pampipe.model.ops`), vectorised over every column."""
    n = structure.n_theta
    geometry = Geometry(p[0], p[1], p[2], p[3], structure.wall)
    return Muscle(geometry, p[5:5 + n], p[4], contact=p[5 + n:5 + 2 * n] if structure.contact else None)


def anchored_at(structure: Structure, p: np.ndarray, d) -> Anchored:
    """The muscle's coefficients F₀, F₁, A, C₀, C₁ at the anchored length in bore ``d`` [m] (the costly,
    load-free part of the law), for columns ``p`` (size, N) and ``d`` (N,)."""
    with np.errstate(all="ignore"):
        return _muscle(structure, p).affine_coefficients(d)


def holding_law(structure: Structure, p: np.ndarray, c: Anchored, w, kappa, mu, sf: float, e,
                pressure: float | None = None):
    """(P* [Pa], P_a(D, 0) [Pa], W_max(P) [N] or None without ``pressure``) from the coefficients ``c``
    (:func:`anchored_at`): the closed forms the plan uses (:meth:`Muscle.closed_form_pressure`, inf where
    it does not hold; without contact increments or effects its affine form, :mod:`pampipe.planning.law`),
    with F₀ shifted by the model error ``e`` [N]; every argument broadcasts against ``c``'s fields (``p``
    (size, ...) too) and ``w``, ``mu`` against each other."""
    muscle = _muscle(structure, p)
    largest = None
    with np.errstate(all="ignore"):
        c = dataclasses.replace(c, at_zero=c.at_zero + e)
        if structure.contact or structure.effects:
            least = muscle.closed_form_pressure(None, w, kappa=kappa, friction=mu, safety_factor=sf,
                                                anchored=c)
        else:
            t = per_draw(c, kappa, 0.0, sf)
            shape = np.broadcast_shapes(*(np.shape(v) for v in (w, mu, t.k, t.r, t.f)))
            least = settle(raw_least(*per_class(w, mu), t, np.empty(shape), np.empty(shape)))
        touch = -c.at_zero / c.slope
        if pressure is not None:
            stiffening = 1 + (c.contact_at_zero + c.contact_slope * pressure) / (p[4] * c.slope)
            grip = mu * math.pi * c.amplification * stiffening
            largest = grip * (c.at_zero + c.slope * pressure) / (sf + kappa * grip)
    values = [v for v in (least, touch, largest) if v is not None]
    shape = np.broadcast_shapes(*(np.shape(v) for v in values))
    out = [v if np.shape(v) == shape else np.broadcast_to(np.asarray(v, dtype=float), shape) for v in values]
    return out if largest is not None else [*out, None]


class Evaluator:
    """P*, first contact and W_max of segment i over draws × classes, for any subset of the sources."""

    def __init__(self, problem: Problem, draws: MuscleDraws, classes: Classes, i: int, rows: np.ndarray,
                 bore: np.ndarray, friction: np.ndarray):
        self.problem, self.draws, self.i = problem, draws, i
        self.key = problem.key
        self.structure = problem.structures[i]
        self.nominal = problem.uncertainties[i].nominal
        self.bore, self.friction = bore, friction  # (n, rows) deviations
        low, worst, high = classes.low[rows], classes.worst[rows, i], classes.high[rows]
        # each distinct bore of the ranges once, the largest last: one without a range, two where the worst
        # bore is an end of its range (commonly the largest), three only where it lies inside
        self.bores = [high]
        if not (np.array_equal(worst, low) or np.array_equal(worst, high)):
            self.bores.insert(0, worst)
        if not np.array_equal(low, high):
            self.bores.insert(0, low)
        self.mu, self.mu_sd = classes.mu[rows], classes.mu_sd[rows]
        statement = (low, high, classes.bore_sd[rows])  # keys the bore draw
        self.groups = [_groups(b, statement) for b in self.bores]
        incline = classes.incline[rows]
        self.rise, self.run = np.abs(np.sin(incline)), np.cos(incline)
        self.drag = None if classes.drag is None else classes.drag[rows]  # a tether (docs/physics.md §16)
        self.drag_draws = None if classes.drag_draws is None else classes.drag_draws[rows]
        self.affine = not (self.structure.contact or self.structure.effects)  # :mod:`law`'s affine form
        self._loads: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        self._per_class: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}

    def inputs(self, sources, nominal=None, drawn_scalar=None) -> tuple:
        """(p (R, size), δ (C, R), μ (C, R), κ (R,), e (R,)) with only ``sources`` drawn around ``nominal``
        (default: the muscle's parameter vector); R = n for what is drawn, 1 for what is not (the
        evaluation runs over classes × draws: a class's draws are contiguous).
        ``drawn_scalar``: the values of the one drawn source κ or e (its deviations) instead of its draws."""
        p, bore, kappa, error = self._muscle_inputs(sources, nominal, drawn_scalar)
        return p, bore, self.friction_load("friction" in sources)[0], kappa, error

    def _muscle_inputs(self, sources, nominal, drawn_scalar) -> tuple:
        """:meth:`inputs` but μ: (p, δ, κ, e), what the per-draw terms (:func:`law.per_draw`) depend on."""
        d, i = self.draws, self.i
        drawn = tuple(key for key in ("moduli", "geometry", "prior") if key in sources)
        if nominal is None:  # the same in every chunk: kept per process
            p = SHARED.get((self.key, i, drawn), lambda: self._parameters(self.nominal, drawn))
        else:
            p = self._parameters(nominal, drawn)
        bore = self.bore.T if "bore" in sources else np.zeros((self.mu.size, 1))
        kappa, error = d.kappa, d.model_error[i]
        if drawn_scalar is not None:
            kappa, error = drawn_scalar, drawn_scalar
        kappa = np.maximum(self.problem.kappa + (kappa if "kappa" in sources else np.zeros(1)), 0.0)
        error = error if "model_error" in sources else np.zeros(1)
        return p, bore, kappa, error

    def _parameters(self, nominal: np.ndarray, drawn: tuple[str, ...]) -> np.ndarray:
        """The parameter vectors (n, size) with the ``drawn`` sources added to ``nominal`` ((1, size) with
        none), read-only."""
        d = self.draws
        p = np.broadcast_to(nominal, (d.n if drawn else 1, nominal.size)).copy()
        for key in drawn:
            p += d.params[key][self.i]
        if drawn:  # a draw outside the physical domain is no muscle: it does not hold (NaN → P* = inf)
            p[outside_domain(p, nominal)] = np.nan
        p.flags.writeable = False
        return p

    def friction_load(self, drawn: bool, tether: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """(μ (C, n or 1), the anchor's load W(μ) [N] (C, n or 1)) with or without the friction draw, once
        per evaluator (the full draw and friction alone share them), by its affine form in μ
        (:func:`pampipe.model.no_slip.incline_load_affine`); with a tether its tension per class, in each
        draw of its friction where ``tether``."""
        key = (drawn, tether and self.drag_draws is not None)
        if key not in self._loads:
            mu = self.mu[:, None] + (self.friction.T if drawn else np.zeros((1, 1)))
            slope, at_zero = self.load_affine()
            load = np.multiply(mu, slope[:, None])
            load += at_zero[:, None]
            if self.drag is not None:
                load = load + (self.drag_draws if key[1] else self.drag[:, None])
            self._loads[key] = mu, load
        return self._loads[key]

    def load_affine(self) -> tuple[np.ndarray, np.ndarray]:
        """(∂W/∂μ [N], W at μ = 0 [N]) (C,) of each class's anchor load without the tether's tension
        (:func:`pampipe.model.no_slip.incline_load_affine`; the mission's ``tether_drag`` where it has no
        tether)."""
        pr = self.problem
        return incline_load_affine(pr.total_mass, pr.masses[self.i], self.rise, self.run,
                                   pr.tether_drag if self.drag is None else 0.0)

    def per_class(self, drawn: bool, tether: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """:func:`law.per_class` (W, W/μ [N]) of :meth:`friction_load`, once per evaluator."""
        if (drawn, tether) not in self._per_class:
            mu, load = self.friction_load(drawn, tether)
            self._per_class[drawn, tether] = per_class(load, mu)
        return self._per_class[drawn, tether]

    def monotone(self, name: str) -> int:
        """+1 (−1) where P* is non-decreasing (non-increasing) in the one drawn source ``name``, in floating
        point too, else 0 (docs/physics.md §15, *Breakdown*). Without contact increments
        P* = W·k + (W/μ)·r − f, k = κ/F₁, f = (F₀ + e)/F₁ (:mod:`law`) at the nominal muscle, μ and bore:
        falling in e (F₁ > 0; else inf for every draw), rising in κ = max(κ̂ + δ, 0) where W ≥ 0; each
        rounded step (sum with a constant, quotient by F₁ > 0, product by W ≥ 0, difference from a constant)
        keeps the order, and so do the floor at 0, the inf beyond 100 MPa and the max over the range's
        bores. Contact increments make P* a sum of a rising and a falling term (exact math rises, rounding
        need not): 0, as for every other source."""
        if not self.affine:
            return 0
        if name == "model_error":
            return -1
        if name == "kappa" and np.all(self.friction_load(False)[1] >= 0):
            return 1
        return 0

    def alone(self, name: str, ranks) -> np.ndarray:
        """The order statistics ``ranks`` (R, C) of P* with only source ``name`` drawn. Where P* is monotone
        in it (:meth:`monotone`), P* maps the source's order statistics onto its own: R evaluations, not n."""
        sign = self.monotone(name)
        if sign == 0:
            return order_statistics(self.evaluate((name,), raw=True)[0], ranks, overwrite=True, settle=settle)
        draws = self.draws.kappa if name == "kappa" else self.draws.model_error[self.i]
        n = draws.size
        at = order_statistics(draws[:, None], [k if sign > 0 else n - 1 - k for k in ranks])[:, 0]
        return self.evaluate((name,), drawn_scalar=at)[0]

    def evaluate(self, sources, pressure=None, *, nominal=None, drawn_scalar=None, raw=False):
        """(P* (n, C) [Pa], touch at the largest bore (n, C) [Pa], payload at ``pressure`` (n, C) [kg]);
        ``nominal``, ``drawn_scalar``: as :meth:`inputs` (then R rows, not n); ``raw``: P* may be the raw
        value of :mod:`pampipe.planning.law` (to :func:`law.settle` after the order statistics).

        The coefficients (:func:`anchored_at`) depend on the muscle and the bore only: they are computed
        once per draw and distinct drawn bore (classes sharing a bore statement share its draws) and kept
        per process (:data:`SHARED`: the next chunk in that bore reuses them), then the
        load-dependent closed form runs over classes × draws by broadcasting (the arrays returned are
        transposed views of those)."""
        if self.affine and pressure is None:
            least, touch = self._affine(sources, nominal, drawn_scalar)
            return (least if raw else settle(least)).T, touch.T, None
        pr = self.problem
        p, bore, mu, kappa, error = self.inputs(sources, nominal, drawn_scalar)
        load = self.friction_load("friction" in sources, "tether" in sources)[1]
        columns = p.T[:, None, :]  # (size, 1, n or 1)
        least = held = touch = None
        for group, c in self._in_bores(p, bore, sources, nominal):
            pick = group if c.slope.shape[0] > 1 else slice(0, 1)  # one bore for all: broadcast, no copy
            c = Anchored(None, *(getattr(c, name)[pick] if np.ndim(getattr(c, name)) else getattr(c, name)
                                 for name in USED))  # per class; the anchored length is not used
            values = holding_law(self.structure, columns, c, load, kappa[None, :], mu, pr.safety_factor,
                                 error[None, :], pressure)
            least = values[0] if least is None else np.maximum(least, values[0])  # never NaN: inf instead
            if pressure is not None:
                held = values[2] if held is None else np.minimum(held, values[2])
            touch = values[1]  # the largest bore is the last
        shape = np.broadcast_shapes(least.shape, mu.shape, (1, p.shape[0]))
        least = least if least.shape == shape else np.broadcast_to(least, shape)
        touch = np.broadcast_to(touch, shape)
        payload = None
        if pressure is not None:
            per_kg = STANDARD_GRAVITY * (self.rise[:, None] + mu * self.run[:, None])
            payload = pr.payload + (held - load) / np.where(per_kg > 0, per_kg, np.nan)
            payload = np.where((held >= 0) & (touch <= pressure) & (mu > 0) & np.isfinite(payload),
                               payload, -np.inf)
            payload = np.broadcast_to(payload, shape).T
        return least.T, touch.T, payload

    def _affine(self, sources, nominal, drawn_scalar) -> tuple[np.ndarray, np.ndarray]:
        """(raw P* (C, R) [Pa], touch at the largest bore (C, R) [Pa]) of :meth:`evaluate` by the affine form
        (:func:`law.raw_least`, four passes per bore), run by run of classes in one bore (the classes come
        sorted by bore), with each bore's :class:`law.Terms` kept per process (:meth:`_terms`)."""
        w, per_mu = self.per_class("friction" in sources, "tether" in sources)
        shape, spare, least = None, None, None
        for group, terms in self.bore_terms(sources, nominal, drawn_scalar):
            if shape is None:
                shape = np.broadcast_shapes(w.shape, *((1, np.size(v)) for v in vars(terms[0]).values()))
                spare = np.empty(shape)
            out = np.empty(shape)
            for g, run in _runs(group):
                raw_least(w[run], per_mu[run], terms[g], out[run], spare[run])
            least = out if least is None else np.maximum(least, out, out=least)  # NaN stays NaN: inf
        if len(terms) == 1:  # the largest bore is the last
            return least, np.broadcast_to(-terms[0].f, shape)
        touch = np.empty(shape)
        for g, run in _runs(group):
            touch[run] = -terms[g].f
        return least, touch

    def touch_share(self, sources, pressure: np.ndarray) -> np.ndarray:
        """The share of draws (C,) in which the unloaded muscle touches the largest bore at ``pressure`` (C,)
        [Pa], P_a(D_high + δ, 0) = −f ≤ P, with ``sources`` drawn (as quantiles.share_at_most of
        :meth:`evaluate`'s touch, sorted once per drawn bore)."""
        group, terms = self.bore_terms(sources)[-1]
        out = np.empty(pressure.shape)
        for g, t in enumerate(terms):
            rows = group == g
            touch = np.sort(-t.f)
            out[rows] = np.searchsorted(touch, pressure[rows], side="right") / touch.size
        return out

    def bore_terms(self, sources, nominal=None, drawn_scalar=None) -> list[tuple[np.ndarray, list[Terms]]]:
        """Per bore of the ranges, the largest last: (each class's group (C,), the :class:`law.Terms` (R,)
        of each group's drawn bore) with only ``sources`` drawn (``nominal``, ``drawn_scalar``: as
        :meth:`inputs`), kept per process where they are the draws' (:meth:`_terms`)."""
        p, bore, kappa, error = self._muscle_inputs(sources, nominal, drawn_scalar)
        return [(group, [self._terms(p, bore_nominal[first[g]] + bore[first[g]], sources, kappa, error,
                                     None if nominal is not None else tuple(bores[:, g].tolist()),
                                     drawn_scalar is None) for g in range(first.size)])
                for bore_nominal, (bores, group, first) in zip(self.bores, self.groups, strict=True)]

    def _terms(self, p: np.ndarray, d: np.ndarray, sources, kappa, error, bore: tuple | None,
               keep: bool) -> Terms:
        """:func:`law.per_draw` of draws ``p`` (n or 1, size) in the drawn bore ``d`` (n or 1,) [m], ``bore``
        its statement (None: ``p`` is not the muscle's: not kept); ``keep``: κ and e are the draws', and
        the terms are kept in :data:`SHARED` (the next chunk in that bore reuses them)."""
        key = None if bore is None else (*self._shared(sources), *bore)

        def column() -> Anchored:
            return self._column(p, d) if key is None else SHARED.get(key, lambda: self._column(p, d))

        def terms() -> Terms:
            return per_draw(column(), kappa, error, self.problem.safety_factor)

        if key is None or not keep:
            return terms()
        drawn = ("kappa" in sources, "model_error" in sources, self.problem.kappa, self.problem.safety_factor)
        return SHARED.get((*key, "terms", *drawn), terms)

    def _shared(self, sources) -> tuple:
        """What names the coefficients of the muscle draws with ``sources`` drawn, before the bore."""
        drawn_p = tuple(k for k in ("moduli", "geometry", "prior") if k in sources)
        return self.key, self.i, self.structure, drawn_p, "bore" in sources

    def _in_bores(self, p: np.ndarray, bore: np.ndarray, sources, nominal):
        """(each class's group (C,), :meth:`_anchored` (G, R) in the groups' drawn bores) for each bore of
        the ranges, the largest last; kept in :data:`SHARED` unless ``nominal`` is given."""
        shared = self._shared(sources)
        for bore_nominal, (bores, group, first) in zip(self.bores, self.groups, strict=True):
            drawn = bore_nominal[first][:, None] + bore[first]  # (G, n or 1)
            keys = None if nominal is not None else [(*shared, *b) for b in bores.T.tolist()]
            yield group, self._anchored(p, drawn, keys)

    def _anchored(self, p: np.ndarray, d: np.ndarray, keys) -> Anchored:
        """:func:`anchored_at` of draws ``p`` (n or 1, size) in bores ``d`` (G, n or 1): (G, R) fields, each
        bore's kept in :data:`SHARED` under its key in ``keys`` (None: computed, not kept)."""
        columns = [self._column(p, d[g]) if keys is None else
                   SHARED.get(keys[g], lambda g=g: self._column(p, d[g])) for g in range(d.shape[0])]
        rows = max(p.shape[0], d.shape[1])
        joined = (_joined([getattr(c, name) for c in columns], [rows] * len(columns)) for name in USED)
        return Anchored(None, *(v if np.ndim(v) == 0 else v.reshape(-1, rows) for v in joined))

    def _column(self, p: np.ndarray, d: np.ndarray) -> Anchored:
        """:func:`anchored_at` of draws ``p`` (n or 1, size) in bores ``d`` (n or 1,): (R,) fields (or one
        number), in batches of at most :data:`BATCH` columns (bounded memory)."""
        rows = max(p.shape[0], d.shape[0])
        d = np.broadcast_to(d, (rows,))
        parts, sizes = [], []
        for start in range(0, rows, BATCH):
            k = np.arange(start, min(start + BATCH, rows))
            parts.append(anchored_at(self.structure, p[np.minimum(k, p.shape[0] - 1)].T, d[k]))
            sizes.append(k.size)
        return Anchored(None, *(_joined([getattr(c, name) for c in parts], sizes) for name in USED))


def _groups(bore: np.ndarray, statement: tuple) -> tuple:
    """(the distinct (bore, its statement) columns (4, G), each class's group (C,), each group's first
    class (G,)): classes of one group share the drawn bore and so its coefficients."""
    bores, first, group = unique_rows(np.stack([bore, *statement], axis=1))
    return bores.T, group, first


def _runs(group: np.ndarray) -> list[tuple[int, slice]]:
    """(group, rows) of each run of consecutive classes in one group (``group`` (C,))."""
    cuts = [0, *(np.flatnonzero(np.diff(group)) + 1).tolist(), group.size]
    return [(int(group[a]), slice(a, b)) for a, b in itertools.pairwise(cuts)]


def _joined(values: list, sizes: list[int]):
    """One coefficient of several parts (each a number or (size,) values): one number where it is the same
    number in every part (C₀, C₁ = 0 without contact increments), else the parts' values end to end."""
    if all(np.ndim(v) == 0 for v in values) and len({float(v) for v in values}) == 1:
        return float(values[0])
    return np.concatenate([np.broadcast_to(v, (size,)) for v, size in zip(values, sizes, strict=True)])
