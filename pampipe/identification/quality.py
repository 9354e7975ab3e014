"""Is the fit as good as the data allow? The noise floor of every test, structure in the residuals,
parameters at their bounds, and the warning that names the likely cause (docs/commands.md §3.4).

**Noise floor** σ̂ of a test: the smaller of two robust estimates along paths (one per held length or
pressure level, direction and cycle; radial tests per direction; each sorted by its swept coordinate x,
pressure or length for isobaric tests). Rows that read ≤ 0 N (slack, or a pipe before anchoring) carry no
noise and are left out.

* High-pass of the residuals r = model − measured:
  e_i = r_i − (w₋ r_{i−1} + w₊ r_{i+1}),  w₋ = (x_{i+1} − x_i)/(x_{i+1} − x_{i−1}), w₊ = 1 − w₋,
  Var e_i = σ²(1 + w₋² + w₊²) for white noise, while a residual linear along the path cancels;
  σ̂² = median(e_i²/(1 + w₋² + w₊²)) / 0.4549 (the median of χ²₁). It follows sharp features of the force
  that the model shares (transients, the slack point), but a misfit curved along a sparse path inflates it.
* Model-free (:mod:`.noise`): the measured force about a local quadratic along each path (for a test that
  holds its lengths, e.g. a force map, each held length swept in pressure). No misfit can inflate it (issue
  35: on the DMSP-20-300 map fitted from a stated 30° the high-pass read 83.6 N, this one 2.27 N, the
  map's noise), while a sharp feature of the force itself can.

``rmse_over_floor`` is the largest RMSE/σ̂ over the tests.

**Structure**: along the same paths, a runs test of the residual signs: for noise about the model
each of the m pairs of neighbours changes sign with probability ½, so the number of changes is
Binomial(m, ½) and z = (changes − m/2)/√(m/4) (too few changes: z < :data:`RUNS_Z`; unlike the
Wald-Wolfowitz test it also sees a path whose residuals all have one sign), together with a lag-1
autocorrelation of at least :data:`LAG1`: a misfit that is systematic, not noise, even when small.
Below :data:`RESOLUTION` of a test's largest force neither counts: that is rounding (noise-free
data), not a misfit.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from pampipe.identification.noise import held_length_paths, local_floor
from pampipe.specs.experiment import TestData
from pampipe.specs.protocol import group_order

#: The fit is reported as above the noise when some test's RMSE exceeds this multiple of its floor.
WARN_RATIO = 3.0
#: Runs-test z below this (one-sided p ≈ 5·10⁻⁴ per test) and ...
RUNS_Z = -3.29
#: ... a lag-1 autocorrelation of the residuals along the paths of at least this: structured.
LAG1 = 0.2
#: Median of χ²₁ (σ̂² = median(e²/c)/this).
CHI2_MEDIAN = 0.454936423119572
#: Degrees of freedom of m overlapping second differences: ν ≈ m / 1.944.
OVERLAP = 1.944
#: Fewest second differences for a floor.
MIN_TERMS = 8
#: The floor is at least this fraction of the test's largest force.
RESOLUTION = 1e-6
#: Largest range of path keys ranked through a table (8 MB of flags) rather than by sorting them.
RANK_TABLE = 1 << 23


@dataclass(frozen=True)
class TestQuality:
    """The noise floor and residual structure of one test."""

    test: str
    rmse: float  # [N] over the rows that read > 0 N
    floor: float | None  # σ̂ [N] (None: too few rows along a path)
    floor_dof: float
    runs_z: float | None
    lag1: float | None
    structured: bool
    leg_gap: float | None = None  # unloading minus loading rows, measured − model, mean [N] (None: one leg)
    leg_gap_std: float | None = None  # its standard error [N]
    scale: float = 0.0  # largest |force| of the test [N]

    @property
    def legs_differ(self) -> bool:
        """The legs' mean residuals differ by more than 4 standard errors and half the floor."""
        return self.leg_gap is not None and abs(self.leg_gap) > max(4 * self.leg_gap_std,
                                                                    0.5 * (self.floor or 0.0))

    @property
    def ratio(self) -> float | None:
        """RMSE / floor, the floor taken as at least :data:`RESOLUTION` of the test's largest force (a
        misfit below that is rounding, not a misfit: noise-free data)."""
        if self.floor is None:
            return None
        return self.rmse / max(self.floor, RESOLUTION * self.scale, 1e-300)

    def as_document(self) -> dict:
        return {"test": self.test, "rmse_N": self.rmse, "floor_N": self.floor, "floor_dof": self.floor_dof,
                "rmse_over_floor": self.ratio, "runs_z": self.runs_z, "lag1_autocorrelation": self.lag1,
                "structured": self.structured, "leg_gap_N": self.leg_gap}


@dataclass(frozen=True)
class Quality:
    """``fit.quality`` of the identify JSON (interfaces: rmse_over_floor, at_bounds, structured)."""

    tests: tuple[TestQuality, ...]
    at_bounds: tuple[str, ...]

    @property
    def rmse_over_floor(self) -> float | None:
        ratios = [t.ratio for t in self.tests if t.ratio is not None]
        return max(ratios) if ratios else None

    @property
    def structured(self) -> bool:
        return any(t.structured for t in self.tests)

    @property
    def noise_floor(self) -> float:
        """The tests' floors pooled, √(Σ ν_t σ_t² / Σ ν_t), ν_t their degrees of freedom [N] (0: none)."""
        known = [(t.floor, t.floor_dof) for t in self.tests if t.floor is not None and t.floor_dof > 0]
        weight = sum(v for _, v in known)
        return math.sqrt(sum(v * s**2 for s, v in known) / weight) if weight else 0.0

    @property
    def above_floor(self) -> list[TestQuality]:
        return [t for t in self.tests if t.ratio is not None and t.ratio > WARN_RATIO]

    def as_document(self) -> dict:
        return {"rmse_over_floor": self.rmse_over_floor, "at_bounds": list(self.at_bounds),
                "structured": self.structured, "warn_above": WARN_RATIO,
                "floor_method": "measured force about a local quadratic along each path (model-free)",
                "tests": [t.as_document() for t in self.tests]}


def assess(data, predictions: dict[str, np.ndarray], names, at_bound) -> Quality:
    """The quality of a fit: ``predictions`` maps each test name to the model force of its rows
    (the hinge max(0, F) applied where the fit applies it)."""
    tests = tuple(test_quality(test, predictions[test.name]) for test in data.tests)
    return Quality(tests, tuple(n for n, flag in zip(names, at_bound, strict=True) if flag))


def test_quality(test: TestData, model: np.ndarray) -> TestQuality:
    """Floor, runs test and lag-1 autocorrelation of one test (see the module docstring)."""
    residual = np.asarray(model, float) - test.force
    live = test.force > 0
    rmse = float(np.sqrt(np.mean(residual[live] ** 2))) if live.any() else 0.0
    rows, group = _paths(test, live)
    x, r = _coordinate(test)[rows], residual[rows]
    same = group[1:] == group[:-1]  # consecutive rows on one path
    inner = same[1:] & same[:-1]  # rows with a neighbour on either side
    span = x[2:] - x[:-2]
    w_minus = np.where(span > 0, (x[2:] - x[1:-1]) / np.where(span > 0, span, 1.0), 0.5)
    e = r[1:-1] - (w_minus * r[:-2] + (1 - w_minus) * r[2:])
    values = (e**2 / (1 + w_minus**2 + (1 - w_minus) ** 2))[inner]
    floors = [(math.sqrt(float(np.median(values)) / CHI2_MEDIAN), values.size)] if values.size else []
    local, terms = local_floor(*_floor_paths(test, live, (rows, group)))
    floors += [(local, terms)] if local is not None else []
    floor, terms = min(((f, n) for f, n in floors if n >= MIN_TERMS), default=(None, 0))
    changes = int(np.sum(((r[1:] >= 0) != (r[:-1] >= 0))[same]))
    pairs = int(np.sum(same))
    runs_z = (changes - pairs / 2) / math.sqrt(pairs / 4) if pairs else None
    squares = float(np.sum(r**2))
    lag1 = float(np.sum((r[1:] * r[:-1])[same])) / squares if squares > 0 else None
    scale = float(np.max(np.abs(test.force))) if test.points else 0.0
    structured = runs_z is not None and lag1 is not None and runs_z < RUNS_Z and lag1 >= LAG1 \
        and rmse > RESOLUTION * scale  # below that the residuals are rounding
    gap, gap_std = _leg_gap(test, residual, live)
    return TestQuality(test.name, rmse, floor, terms / OVERLAP, runs_z, lag1, structured, gap, gap_std,
                       scale)


def _floor_paths(test: TestData, live: np.ndarray, paths: tuple[np.ndarray, np.ndarray]
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, measured force, path) of the live rows sorted by path then x, for the noise floor: each held
    length swept in pressure for a test that holds its lengths (a force map), else ``paths`` (:func:`_paths`
    of the live rows, which the caller has)."""
    rows = np.flatnonzero(live)
    held = held_length_paths(test.length[rows]) if test.kind == "axial" and rows.size > 1 else None
    if held is None:
        rows, group = paths
        return _coordinate(test)[rows], test.force[rows], group
    order = np.lexsort((test.pressure[rows], held))
    return test.pressure[rows][order], test.force[rows][order], held[order]


def _leg_gap(test: TestData, residual: np.ndarray, live: np.ndarray) -> tuple[float | None, float | None]:
    """(how far the unloading rows read above the loading rows, relative to the model, on average; its
    standard error) [N]: a gap is what hysteresis or friction leaves in a model without them."""
    sweeps_length = test.kind == "axial" and test.protocol in ("isobaric", "mixed")
    leg = test.leg if sweeps_length else test.pressure_leg
    if leg is None:
        return None, None
    up, down = residual[live & (leg > 0)], residual[live & (leg < 0)]
    if up.size < 3 or down.size < 3:
        return None, None
    std = math.sqrt(np.var(up, ddof=1) / up.size + np.var(down, ddof=1) / down.size)
    return float(up.mean() - down.mean()), std  # residual = model − measured


def _coordinate(test: TestData) -> np.ndarray:
    """The swept coordinate: length for isobaric tests, pressure otherwise."""
    return test.length if test.kind == "axial" and test.protocol == "isobaric" else test.pressure


def _paths(test: TestData, live: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(live rows sorted by path, then by the swept coordinate; the path index of each)."""
    zeros = np.zeros(test.points, dtype=np.int64)
    pressure_leg = test.pressure_leg if test.pressure_leg is not None else zeros
    if test.kind == "axial" and test.protocol == "isobaric":
        keys = (test.level, test.leg, test.cycle)
    elif test.kind == "axial" and test.protocol == "isometric":
        keys = (test.held_length if test.held_length is not None else zeros, pressure_leg, test.cycle)
    elif test.kind == "axial":  # mixed: per direction of the length and of the pressure
        keys = (test.leg, pressure_leg, zeros)
    else:
        keys = (zeros, pressure_leg, zeros)
    rows = np.flatnonzero(live)
    if not rows.size:
        return rows, np.zeros(0, dtype=np.int64)
    group = _row_groups([np.asarray(k, dtype=np.int64)[rows] for k in keys])
    order = _path_order(_coordinate(test)[rows], group)
    return rows[order], group[order]


def _path_order(x: np.ndarray, group: np.ndarray) -> np.ndarray:
    """``np.lexsort((x, group))`` (by group, then x; ties in recorded order): the rows by group (a radix sort,
    :func:`~pampipe.specs.protocol.group_order`), then each group's by x (a stable sort); a path is one sweep,
    so its x come in one run that the stable sort takes as it is (2.5x faster at 1.8·10⁶ rows than one
    sort of every x). With more than :data:`SORTED_PATHS` paths, one stable sort by x, then the radix sort."""
    by_group = group_order(group)
    grouped = group[by_group]
    bounds = np.flatnonzero(grouped[1:] != grouped[:-1]) + 1
    if bounds.size >= SORTED_PATHS:
        order = np.argsort(x, kind="stable")
        return order[group_order(group[order])]
    for a, b in itertools.pairwise([0, *bounds.tolist(), group.size]):
        rows = by_group[a:b]
        by_group[a:b] = rows[np.argsort(x[rows], kind="stable")]
    return by_group


#: Paths above which :func:`_path_order` sorts every row at once (a loop over them would cost more).
SORTED_PATHS = 4096


def _row_groups(columns: list[np.ndarray]) -> np.ndarray:
    """The index of each row's distinct (c₀, c₁, c₂) in lexicographic order, as ``np.unique(axis=0)``
    numbers them: from one mixed-radix int64 key where the ranges allow, ranked by a table of the keys
    present when it has at most :data:`RANK_TABLE` entries (no sort), else by a 1-D unique."""
    key, spans = np.zeros(columns[0].size, dtype=np.int64), 1
    for column in columns:
        low, span = int(column.min()), int(column.max()) - int(column.min()) + 1
        spans *= span
        if spans >= 2**62:
            _, group = np.unique(np.column_stack(columns), axis=0, return_inverse=True)
            return group.ravel()
        key = key * span + (column - low)
    if spans > RANK_TABLE:
        return np.unique(key, return_inverse=True)[1].ravel()
    present = np.zeros(spans, dtype=bool)
    present[key] = True
    return (np.cumsum(present) - 1)[key]


def warnings(quality: Quality, calibration, calibrate: tuple[str, ...]) -> list[str]:
    """The warnings of a fit that is not as good as its data: each names the tests, by how much, the
    likely cause and the next step. ``calibration`` is the fit's :class:`.result.Calibration`."""
    out = []
    bad = quality.above_floor
    structured = [t for t in quality.tests if t.structured and t not in bad]
    moduli = [n for n in quality.at_bounds if not n.startswith("geometry.")]
    geometry = [n for n in quality.at_bounds if n.startswith("geometry.")]
    if not bad and not structured:
        return out
    if bad:
        shown = "; ".join(f"{t.test} {t.rmse:.3g} N = {t.ratio:.3g}x its noise floor {t.floor:.3g} N"
                          for t in bad)
        what = f"the fit misses the data by far more than the noise ({shown})"
    else:
        shown = "; ".join(f"{t.test}: runs z = {t.runs_z:.3g}, lag-1 autocorrelation {t.lag1:.2f}"
                          for t in structured)
        what = f"the residuals are structured, not noise ({shown})"
    if moduli:
        what += (f"; the moduli {', '.join(moduli)} sit at their bounds: they are stretched to absorb a "
                 "misfit they cannot represent")
    cause = _cause(quality, calibration, calibrate, geometry, bad or structured)
    out.append(f"{what}. Likely cause: {cause}.")
    return out


def _cause(quality, calibration, calibrate, geometry, flagged) -> str:
    """The likely cause of a misfit and the next step, from what the fit already knows."""
    stated = calibration.stated_blocked_force
    if geometry:
        return (f"the calibrated geometry stopped at its bound ({', '.join(geometry)}); next: widen "
                "fit.calibration_bounds (docs/formats.md §3) or check the stated geometry")
    if stated is not None and not stated.consistent and not calibrate:
        return ("the stated geometry: the blocked-force slope disagrees with it (above); next: identify "
                "--calibrate braid_angle --calibrate initial_length")
    legs = [t for t in flagged if t.legs_differ]
    if legs:
        gaps = ", ".join(f"{t.test} {abs(t.leg_gap):.3g} N" for t in legs)
        return (f"hysteresis or friction: the loading and unloading legs differ by {gaps} on average, which "
                "the baseline model cannot show; next: pampipe diagnose on this experiment (it names the "
                "effect), or fit.average_legs for isobaric tests")
    if 2 * len(flagged) <= len(quality.tests):  # a minority of the tests
        names = ", ".join(t.test for t in flagged)
        return (f"something only test(s) {names} see (their units, a sensor offset or gain, a different "
                "muscle state), since the other tests fit; next: plot them (--plots) and run pampipe "
                "diagnose")
    if stated is not None and stated.consistent:
        return ("an effect the baseline model lacks (contact stiffening, friction, prestrain, a sensor "
                "error): the blocked-force check finds the stated geometry consistent; next: pampipe "
                "diagnose on this experiment")
    if not calibrate:
        return ("the stated geometry (braid angle, rest length), which the moduli cannot make up for, or an "
                "effect the baseline model lacks; next: identify --calibrate braid_angle --calibrate "
                "initial_length, then pampipe diagnose if the misfit stays")
    return ("an effect the baseline model lacks (hysteresis, friction, prestrain, a sensor error); next: "
            "pampipe diagnose on this experiment")
