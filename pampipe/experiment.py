"""An experiment as frozen SI objects: its tests, their recorded rows and the protocol grouping.

No I/O here: :func:`pampipe.io.load_experiment` reads the experiment file and
:func:`pampipe.io.load_experiment_data` its CSV files. The grouping of rows into pressure levels,
legs and cycles (what the fit needs beyond the raw columns) is defined here.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pampipe.model.pam import Pam


@dataclass(frozen=True)
class TestSpec:
    """One test of an experiment: its kind, conditions and resolved CSV path (SI)."""

    name: str
    kind: str
    data: Path
    pipe_diameter: float | None
    axial_load: float


@dataclass(frozen=True)
class Experiment:
    """An experiment file: its muscle, its tests (CSV paths resolved, not read) and its ``fit:`` options."""

    source: Path
    pam: Pam
    tests: tuple[TestSpec, ...]
    fit: dict[str, Any]
    pam_file: Path | None = None  # the PAM file it names (None for an inline PAM)

    @property
    def input_files(self) -> list[Path]:
        """Every file the experiment reads: itself, its PAM file and its CSV files."""
        own = [self.source] + ([self.pam_file] if self.pam_file is not None else [])
        return own + [t.data for t in self.tests]


@dataclass(frozen=True)
class TestData:
    """One test's rows in recorded order (SI), plus the grouping the fit uses.

    ``level`` indexes ``level_pressure`` (the median pressure of each level) row by row. For axial
    tests ``leg`` is +1 while the muscle lengthens and −1 while it shortens, and ``cycle`` counts
    shortening-lengthening cycles within a level; radial tests have zeros there.
    """

    spec: TestSpec
    pressure: np.ndarray  # [Pa] gauge
    force: np.ndarray  # [N] axial tension (axial) or split-pipe force (radial)
    length: np.ndarray | None  # [m] (axial tests)
    time: np.ndarray | None  # [s]
    level: np.ndarray = field(repr=False)
    level_pressure: np.ndarray = field(repr=False)
    leg: np.ndarray = field(repr=False)
    cycle: np.ndarray = field(repr=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def kind(self) -> str:
        return self.spec.kind

    @property
    def points(self) -> int:
        return int(self.force.size)


@dataclass(frozen=True)
class ExperimentData:
    """An experiment with its CSV data loaded."""

    source: Path
    pam: Pam
    tests: tuple[TestData, ...]
    fit: dict

    @property
    def points(self) -> int:
        return sum(t.points for t in self.tests)


def make_test_data(spec: TestSpec, columns: dict[str, np.ndarray]) -> TestData:
    """Wrap SI columns (``pressure``, ``force``, optional ``length``, ``time``) as :class:`TestData`."""
    pressure = np.asarray(columns["pressure"], dtype=float)
    length = columns.get("length")
    level, level_pressure = pressure_levels(pressure)
    if spec.kind == "axial" and length is not None:
        leg, cycle = legs_and_cycles(np.asarray(length, dtype=float), level)
    else:
        leg = cycle = np.zeros(pressure.size, dtype=np.int64)
    return TestData(spec, pressure, np.asarray(columns["force"], dtype=float), length, columns.get("time"),
                    level, level_pressure, leg, cycle)


def pressure_levels(pressure: np.ndarray, *, max_levels: int = 64, fallback_bins: int = 10):
    """(level index per row, median pressure per level) [-, Pa].

    Levels are clusters of the sorted pressures separated by gaps wider than 2 % of the pressure
    range (a stepped protocol with regulator noise). If that gives one level over a wide range
    (a ramp) or more than ``max_levels`` (sparse data), the rows are split into ``fallback_bins``
    equal-count pressure bins instead. Levels are numbered by increasing pressure.
    """
    n = pressure.size
    if n == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    order = np.argsort(pressure, kind="stable")
    ordered = pressure[order]
    span = ordered[-1] - ordered[0]
    breaks = np.flatnonzero(np.diff(ordered) > max(0.02 * span, 1e-9)) + 1
    ramp = breaks.size == 0 and span > 0.1 * max(abs(ordered[-1]), 1.0)
    if ramp or breaks.size + 1 > max_levels:
        bins = min(fallback_bins, n)
        breaks = np.unique((np.arange(1, bins) * n) // bins)
        breaks = breaks[(breaks > 0) & (breaks < n)]
    sorted_level = np.zeros(n, dtype=np.int64)
    sorted_level[breaks] = 1
    sorted_level = np.cumsum(sorted_level)
    level = np.empty(n, dtype=np.int64)
    level[order] = sorted_level
    bounds = np.concatenate([[0], breaks, [n]])
    medians = np.array([np.median(ordered[a:b]) for a, b in itertools.pairwise(bounds)])
    return level, medians


def legs_and_cycles(length: np.ndarray, level: np.ndarray, *, window: int = 2):
    """(leg, cycle) per row of an axial test.

    Within each level, in recorded order, the leg is the sign of the central difference
    L[i+w] − L[i−w] (w = ``window`` rows, robust to a little displacement noise); rows where it
    is zero take the previous leg. The cycle index increases by one at every switch from
    lengthening (+1) to shortening (−1).
    """
    leg = np.zeros(length.size, dtype=np.int64)
    cycle = np.zeros(length.size, dtype=np.int64)
    for lev in np.unique(level):
        rows = np.flatnonzero(level == lev)
        values = length[rows]
        if values.size < 2:
            continue
        padded = np.concatenate([np.full(window, values[0]), values, np.full(window, values[-1])])
        sign = np.sign(padded[2 * window:] - padded[:-2 * window]).astype(np.int64)
        nonzero = np.flatnonzero(sign)
        if nonzero.size == 0:
            continue
        filled = sign[nonzero[np.maximum(np.searchsorted(nonzero, np.arange(sign.size), "right") - 1, 0)]]
        leg[rows] = filled
        starts = np.concatenate([[0], (np.diff(filled) < 0).astype(np.int64)])
        cycle[rows] = np.cumsum(starts)
    return leg, cycle
