"""The model error of a fit: the prediction error beyond the noise, cross-validated over protocol blocks.

**Noise floor** σ_n [N]: the pooled model-free floor of the tests (:mod:`.noise`, :mod:`.quality`).

**Cross-validation over blocks of the protocol** (issue 35): the blocks are :data:`BANDS` bands of
pressure (quantiles of the tested pressures, over every test) and, for an axial test that holds its
lengths (a force map's columns: :func:`.noise.held_length_paths`), each held length. Each block is
withheld in turn, the fit is solved again on the rest (``refit``: the same NLP structure, cached, fed
the remaining rows through its parameters; a calibrated geometry is held at the full fit's; with least
squares from the full fit θ̂ by active-set steps, the first θ̂ − H₋ᵦ⁻¹g₋ᵦ with H₋ᵦ [N²/MPa²] and g₋ᵦ [N²/MPa]
the rest's Hessian and gradient at θ̂, :mod:`.held_out`, else by IPOPT) and the withheld rows are
predicted. With B blocks of
held-out RMSE e_b the written model error is what the user meets beyond the noise,

    s_cv² = (1/B) Σ_b e_b²,    model_error = √max(0, s_cv² − (1/B) Σ_b σ_b²),   with B − 1 degrees of freedom,

each block weighing the same (a block is one untested condition: a length or a pressure range). With
fewer than two blocks (one pressure, no held lengths) there is nothing to hold out: the in-sample RMSE
over the noise floor is used instead (``method = "in_sample"``, rows − 1 degrees of freedom).

**In the unit of what a plan draws** (docs/physics.md §15): a plan draws the model error as a shift e of
the axial force F_ax at the anchored length L_p. An axial row's miss is a miss of F_ax; a radial row
measures F_r = A(D_p)(F_ax(P, L_p) − F_a) (§5.3), so its miss δ is a miss δ/A of F_ax at L_p (A the
refit's amplification factor at the test's bore, 1.0–1.6 for the bench's 88.9 mm test of a 57 mm muscle).
Every e_b is taken over those F_ax misses [N], and the noise it carries is σ_b² = σ_n²·mean(w) over the
block's rows, w = 1 on an axial row and 1/A² on a radial one (σ_n the measured force's floor). On data
without radial tests this is the plain held-out RMSE. Measured on tuning trials of
``benchmarks/bench_coverage.py`` (seed 2, trials 1–15, held protocol, a radial test in each; z the truth's
miss of F_ax at the riser's L_p, a bore no test used, over s), the alternatives of issue 35 were rejected:
the radial rows' own pressure-band blocks give an s 2–6× below that miss (z RMS 3.1: unsafe); the radial
test withheld as a bore block has the scale (z RMS 1.2) but one radial bore gives it ν = 0; held lengths
weighted by closeness to L_p (a Gaussian kernel one length step wide, Kish's effective count for ν) give
a larger s (the lengths near L_p miss more than the mean), a median 1.06–1.11× from the model error alone
against 1.03×. The pooled blocks give z RMS 1.04 (docs/physics.md §15).

**Large experiments:** above :data:`CV_ROWS` rows the blocks are held out of, and refitted on, an evenly
spaced subset of each test's rows in recorded order (:func:`thinned`, about :data:`CV_ROWS` in all; the full
fit keeps every row), so the cost stops growing with the rows. A held-out block is predicted by
extrapolation, so the refit's parameter scatter adds to s_cv² a term that falls as 1/rows: the estimate is
that of a fit to :data:`CV_ROWS` rows, larger (the safe side) than one on every row by that term. On the
paper protocol with 2 N noise (tests/identification/test_model_error.py) the term is ≈ 1.3 N² at 3·10³
rows, so ≈ 0.13 N² at 3·10⁴.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from pampipe.errors import PampipeError
from pampipe.identification.noise import evenly_spaced, held_length_paths

#: Pressure bands held out in turn.
BANDS = 4
#: Rows above which the cross-validation runs on an evenly spaced subset of each test (:func:`thinned`).
CV_ROWS = 30_000


@dataclass(frozen=True)
class Block:
    """One block of the protocol held out: a pressure band [Pa] or a held length [m], and its miss."""

    kind: str  # "pressure" or "length"
    low: float  # [Pa] or [m]
    high: float
    rows: int
    rmse: float  # held-out RMSE of F_ax [N] (a radial row's miss over A(D_p): the module docstring)

    def as_document(self) -> dict:
        unit = "Pa" if self.kind == "pressure" else "m"
        return {"kind": self.kind, f"{self.kind}_range_{unit}": [self.low, self.high], "rows": self.rows,
                "held_out_rmse_N": self.rmse}


@dataclass(frozen=True)
class ModelError:
    """The model-error term of a fit and how it was found (see the module docstring)."""

    value: float  # model_error [N]: the held-out prediction error beyond the noise, 0 within it
    noise_floor: float  # pooled σ_n [N]
    cv_rmse: float  # RMS over the held-out blocks of their RMSE [N] (in-sample RMSE for "in_sample")
    method: str  # "held_blocks" or "in_sample"
    blocks: tuple[Block, ...]  # the blocks held out in turn
    dof: int = 1  # degrees of freedom of value²: blocks − 1 (rows − 1 in sample)

    @property
    def bands(self) -> tuple[Block, ...]:
        """The pressure bands among the blocks."""
        return tuple(b for b in self.blocks if b.kind == "pressure")

    def as_document(self) -> dict:
        return {"model_error_N": self.value, "model_error_dof": self.dof, "noise_floor_N": self.noise_floor,
                "cross_validated_rmse_N": self.cv_rmse,
                "method": self.method, "blocks": [b.as_document() for b in self.blocks]}


@dataclass(frozen=True)
class RowSample:
    """The rows used for cross-validation: their test, pressure, measured force and weight."""

    test: np.ndarray  # index into data.tests
    rows: np.ndarray  # row index within the test
    pressure: np.ndarray  # [Pa]
    force: np.ndarray  # [N]
    weight: np.ndarray  # rows each stands for


def sample_rows(data, slack: str, *, limit: int | None = None) -> RowSample:
    """A uniform subsample of every test's fitted rows, in recorded order (at most ``limit`` per test)."""
    parts = []
    for t, test in enumerate(data.tests):
        used = np.arange(test.points)
        if slack == "exclude" and test.kind == "axial":
            used = used[~test.slack]
        if used.size == 0:
            continue
        if limit is None or used.size <= limit:  # every row (linspace(0, n − 1, n) is 0, 1, …, n − 1)
            pick = used
        else:
            pick = used[evenly_spaced(used.size, limit)]
        parts.append((np.full(pick.size, t), pick, test.pressure[pick], test.force[pick],
                      np.full(pick.size, used.size / pick.size)))
    return RowSample(*(np.concatenate([p[k] for p in parts]) for k in range(5)))


def row_forces(data, sample: RowSample, muscles, slack: str) -> np.ndarray:
    """Model force [N] at every sampled row for ``muscles`` = (muscle, {pipe: muscle})."""
    main, pipes = muscles
    out = np.empty(sample.rows.size)
    for t, test in enumerate(data.tests):
        mine = sample.test == t
        if not mine.any():
            continue
        rows = sample.rows[mine]
        if test.kind == "axial":
            pressure_leg = 0.0 if test.pressure_leg is None else test.pressure_leg[rows]
            force = main.axial_force(test.pressure[rows], test.length[rows], leg=test.leg[rows],
                                     pressure_leg=pressure_leg)
            if slack == "unilateral":
                force = np.where(test.slack_at(rows), np.maximum(force, 0.0), force)
        else:
            muscle = pipes.get(test.spec.pipe_diameter, main)
            force = muscle.radial_force(test.pressure[rows], test.spec.pipe_diameter, test.spec.axial_load)
        out[mine] = force
    return out


def estimate(data, muscles_at, x, refit, *, slack: str, noise: float) -> ModelError:
    """Model error of the fit ``x`` (module docstring); ``muscles_at(x)`` is (muscle, {pipe: muscle}),
    ``refit(data)`` the same for the fit to ``data`` (a block withheld; it may raise a
    :class:`~pampipe.errors.PampipeError`: that block is skipped); ``noise``: the pooled noise floor σ_n [N]
    (:attr:`.quality.Quality.noise_floor`, model-free)."""
    data = thinned(data, CV_ROWS)
    every = sample_rows(data, slack, limit=None)
    sigma_n = noise
    found, noise = [], []
    for kind, low, high, held in blocks(data, every):
        try:
            muscles = refit(withheld(data, every, held))
        except PampipeError:
            continue
        part = RowSample(*(getattr(every, f)[held] for f in RowSample.__dataclass_fields__))
        scale = axial_scale(data, part, muscles)
        miss = (row_forces(data, part, muscles, slack) - part.force) / scale
        found.append(Block(kind, low, high, int(held.sum()), float(np.sqrt(np.mean(miss**2)))))
        noise.append(sigma_n**2 * float(np.mean(scale**-2.0)))
    if len(found) < 2:
        muscles = muscles_at(x)
        scale = axial_scale(data, every, muscles)
        r = (row_forces(data, every, muscles, slack) - every.force) / scale
        mse = float(np.mean(r**2))
        floor = sigma_n**2 * float(np.mean(scale**-2.0))
        return ModelError(float(np.sqrt(max(mse - floor, 0.0))), sigma_n, float(np.sqrt(mse)),
                          "in_sample", (), max(int(r.size) - 1, 1))
    cv = float(np.sqrt(np.mean([b.rmse**2 for b in found])))
    return ModelError(float(np.sqrt(max(cv**2 - float(np.mean(noise)), 0.0))), sigma_n, cv, "held_blocks",
                      tuple(found), len(found) - 1)


def axial_scale(data, sample: RowSample, muscles) -> np.ndarray:
    """What a miss of each sampled row is per newton of F_ax at the anchored length [-]: 1 on an axial row,
    A(D_p) on a radial one (F_r = A(F_ax(P, L_p) − F_a), docs/physics.md §5.3), for ``muscles`` =
    (muscle, {pipe: muscle})."""
    main, pipes = muscles
    out = np.ones(sample.rows.size)
    for t, test in enumerate(data.tests):
        mine = sample.test == t
        if test.kind != "axial" and mine.any():
            pipe = test.spec.pipe_diameter
            out[mine] = float(pipes.get(pipe, main).amplification_factor(pipe))
    return out


#: Degrees of freedom at and below which the t the plans draw is far wider than a normal (warned).
FEW_DOF = 2


def few_blocks_warning(error: ModelError) -> str | None:
    """A warning when a positive model error rests on ν ≤ :data:`FEW_DOF` degrees of freedom, else None.

    Plans draw it as s·t_ν (docs/physics.md §15): the one-sided 95 % quantile of t_ν is 6.31 for ν = 1 and
    2.92 for ν = 2 against 1.64 for the normal and 2.35 for ν = 3, so one more block moves a plan by
    several model errors. More blocks are more pressure levels (up to :data:`BANDS` bands) or more held
    lengths (each held length of a force map is a block)."""
    if error.dof > FEW_DOF or not error.value > 0:
        return None
    from scipy.special import stdtrit

    quantile = float(stdtrit(error.dof, 0.95))
    held = "rows (nothing to hold out)" if error.method == "in_sample" else "held-out blocks of the protocol"
    return (f"the model error {error.value:.3g} N rests on {error.dof + 1} {held} "
            f"(model_error_dof = {error.dof}): plans draw it as a Student-t on {error.dof} degree(s) of "
            f"freedom, whose 95 % quantile is {quantile:.3g} model errors against 1.64 for a normal "
            f"(docs/physics.md §15). More blocks narrow it (2.35 at 3 dof): test at {BANDS} or more "
            "distinct pressure levels, or hold the length at several values in an axial test (each held "
            "length is a block)")


def blocks(data, rows: RowSample) -> list[tuple[str, float, float, np.ndarray]]:
    """(kind, low, high, mask over ``rows``) of every block: the pressure bands [Pa], then the held
    lengths [m] of each axial test that holds its lengths (module docstring)."""
    edges = _band_edges(rows.pressure)
    band = np.clip(np.searchsorted(edges, rows.pressure, side="right") - 1, 0, edges.size - 2)
    out = [("pressure", float(edges[g]), float(edges[g + 1]), band == g) for g in range(edges.size - 1)]
    for t, test in enumerate(data.tests):
        mine = rows.test == t
        if test.kind != "axial" or not mine.any():
            continue
        lengths = held_length_paths(test.length[rows.rows[mine]])
        if lengths is None:
            continue
        where = np.flatnonzero(mine)
        for index in range(int(lengths.max()) + 1):
            held = np.zeros(rows.rows.size, dtype=bool)
            held[where[lengths == index]] = True
            value = float(np.round(test.length[rows.rows[where[lengths == index][0]]], 4))
            out.append(("length", value, value, held))
    return [(kind, low, high, held) for kind, low, high, held in out if held.any() and not held.all()]


def thinned(data, limit: int):
    """``data`` with each test cut to an evenly spaced subset of its rows in recorded order, about
    ``limit`` rows in all (the same share of every test); ``data`` itself when it has at most ``limit``."""
    if data.points <= limit:
        return data
    share = limit / data.points
    tests = []
    for test in data.tests:
        keep = np.zeros(test.points, dtype=bool)
        keep[evenly_spaced(test.points, max(int(np.ceil(share * test.points)), 2))] = True
        tests.append(test.subset(keep) if not keep.all() else test)
    return replace(data, tests=tuple(tests))


def withheld(data, rows: RowSample, held: np.ndarray):
    """``data`` without the ``held`` rows (a test left with none is dropped)."""
    tests = []
    for t, test in enumerate(data.tests):
        drop = rows.rows[(rows.test == t) & held]
        keep = np.ones(test.points, dtype=bool)
        keep[drop] = False
        if keep.all():
            tests.append(test)
        elif keep.any():
            tests.append(test.subset(keep))
    return replace(data, tests=tuple(tests), slip=())


def _band_edges(pressure: np.ndarray) -> np.ndarray:
    """Edges of up to :data:`BANDS` pressure bands holding distinct tested pressures (quantiles)."""
    distinct = np.unique(np.round(pressure, -2))  # 100 Pa: a regulated level counts once
    if distinct.size < 2:
        return np.array([pressure.min(), pressure.max()])
    count = min(BANDS, distinct.size)
    cuts = np.quantile(distinct, np.linspace(0, 1, count + 1)[1:-1], method="nearest")
    middles = [0.5 * (distinct[max(np.searchsorted(distinct, c) - 1, 0)] + c) for c in cuts]
    return np.unique(np.concatenate([[pressure.min() - 1.0], middles, [pressure.max() + 1.0]]))
