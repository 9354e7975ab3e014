"""Experiment data: CSV files → SI arrays, with errors that name the file, the line and the column.

CSV format (docs/formats.md §3): one header row, every column named ``quantity [unit]``
(``pressure [kPa]``, ``length [mm]``, ``force [N]``, ``time [s]``); rows in recorded order; blank
lines are ignored. Columns with other names are allowed (they must still be numeric) and ignored.

Reading is chunked: :data:`CHUNK_ROWS` lines are parsed at a time by numpy's C parser, so a file
of 10⁷ rows needs memory for its numbers (8 bytes per cell) plus one chunk of text, never the
whole text or Python objects per cell. Only when a chunk fails does a slow line-by-line scan run,
to name the exact line, column and value.

:func:`load_experiment_data` adds what the fit needs beyond the raw columns: the pressure level of
every row (axial tests are isobaric; radial tests step or ramp the pressure) and, for axial tests,
the leg (+1 lengthening, −1 shortening) and the cycle index.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pampipe.config import Experiment, TestSpec
from pampipe.errors import InputError
from pampipe.model.pam import Pam
from pampipe.units import column_factor

#: Lines parsed per chunk: bounds the text held in memory (≈ 10 MB for 3-column files).
CHUNK_ROWS = 262_144
#: Rows one file may hold. identify keeps the numbers in memory (≈ 170 bytes a row at its peak,
#: measured: 1.7 GB for 10⁷ rows), so this cap keeps a run under ≈ 5 GB on a 24 GB machine.
MAX_ROWS = 30_000_000
#: Known column names and their dimensions.
DIMENSIONS = {"pressure": "pressure", "length": "length", "force": "force", "time": "time"}
#: Columns each test kind needs.
REQUIRED = {"axial": ("pressure", "length", "force"), "radial": ("pressure", "force")}

_HEADER = re.compile(r"^\s*([^\[\]]+?)\s*\[([^\[\]]*)\]\s*$")

Progress = Callable[[str], None]


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


def load_experiment_data(experiment: Experiment, *, progress: Progress | None = None) -> ExperimentData:
    """Read every test's CSV (see :func:`read_csv`) and add levels, legs and cycles."""
    tests = []
    for spec in experiment.tests:
        columns = read_csv(spec.data, required=REQUIRED[spec.kind], progress=progress)
        tests.append(make_test_data(spec, columns))
    return ExperimentData(experiment.source, experiment.pam, tuple(tests), dict(experiment.fit))


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


# ------------------------------------------------------------------------------------------ CSV
def read_csv(path: Path, *, required: tuple[str, ...], progress: Progress | None = None
             ) -> dict[str, np.ndarray]:
    """Read a CSV file into SI columns keyed by quantity name (``pressure``, ``length``, ...).

    Raises :class:`InputError` naming the file, the line and the column for: a missing or
    unreadable file, an empty file, a header without data, a header cell without a ``[unit]``,
    an unknown unit or one of the wrong dimension, a missing required column, a duplicate column,
    a row with the wrong number of cells, a non-numeric cell, NaN or infinity.
    """
    path = Path(path)
    try:
        handle = open(path, encoding="utf-8", newline="")  # closed by the with below
    except FileNotFoundError:
        raise InputError(f"{path}: data file not found.") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected a CSV data file.") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the data file ({exc.strerror or exc}).") from None
    try:
        with handle:
            return _read_open(path, handle, required, progress)
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: is not UTF-8 text (byte {exc.start} of a chunk).") from None


def _read_open(path, handle, required, progress) -> dict[str, np.ndarray]:
    header_line = handle.readline()
    if not header_line.strip():
        raise InputError(f"{path}: the file is empty; expected a header row such as "
                         f"'{', '.join(_example_header(required))}' followed by data rows.")
    names, factors, ncols = _parse_header(path, header_line, required)
    chunks = []
    first_line = 2  # file line number of the chunk's first line (the header is line 1)
    rows = 0
    while True:
        lines = list(itertools.islice(handle, CHUNK_ROWS))
        if not lines:
            break
        try:
            block = np.loadtxt(lines, delimiter=",", ndmin=2, dtype=float)
        except ValueError:
            block = None
        if block is None or (block.size and (block.shape[1] != ncols or not np.all(np.isfinite(block)))):
            _scan(path, lines, first_line, names, ncols)  # raises, naming the line and column
        if block.size:
            chunks.append(block)
            rows += block.shape[0]
        if rows > MAX_ROWS:
            raise InputError(f"{path}: more than {MAX_ROWS:,} data rows; pampipe holds the data in memory "
                             "(about 170 bytes a row), so thin the file out (every k-th row keeps the "
                             "statistics) or split it into several tests.")
        first_line += len(lines)
        if progress is not None and rows >= CHUNK_ROWS:
            progress(f"reading {path.name}: {rows:,} rows")
    if rows == 0:
        raise InputError(f"{path}: the file has a header but no data rows.")
    table = np.concatenate(chunks) if len(chunks) > 1 else chunks[0]
    return {name: table[:, col] * factors[name] for name, col in names.items()}


def _parse_header(path, line, required):
    cells = [c.strip() for c in line.rstrip("\r\n").split(",")]
    names, factors = {}, {}
    for col, cell in enumerate(cells, start=1):
        match = _HEADER.match(cell)
        if not match:
            raise InputError(f"{path}: line 1, column {col}: header {cell!r} has no unit in square "
                             "brackets; write it as 'quantity [unit]', e.g. 'pressure [kPa]'.")
        name, unit = match.group(1).strip().lower(), match.group(2).strip()
        if name in names:
            raise InputError(f"{path}: line 1, column {col}: the column {name!r} appears twice.")
        where = f"{path}: line 1, column {col} ({name})"
        if name in DIMENSIONS:
            factors[name] = column_factor(unit, DIMENSIONS[name], where=where)
        names[name] = col - 1
    missing = [r for r in required if r not in names]
    if missing:
        raise InputError(f"{path}: line 1: missing column(s) {', '.join(missing)}; this test needs "
                         f"{', '.join(_example_header(required))} (found: {', '.join(cells)}).")
    return {n: c for n, c in names.items() if n in DIMENSIONS}, factors, len(cells)


def _scan(path, lines, first_line, names, ncols) -> None:
    """Find and report the first malformed line of a chunk (slow path, only on error)."""
    labels = {c: n for n, c in names.items()}
    for offset, raw in enumerate(lines):
        text = raw.strip()
        if not text:
            continue
        cells = [c.strip() for c in text.split(",")]
        where = f"{path}: line {first_line + offset}"
        if len(cells) != ncols:
            raise InputError(f"{where}: has {len(cells)} cells but the header has {ncols} columns.")
        for col, cell in enumerate(cells):
            label = labels.get(col, f"column {col + 1}")
            try:
                value = float(cell)
            except ValueError:
                shown = "an empty cell" if not cell else f"{cell!r}"
                raise InputError(f"{where}, column {col + 1} ({label}): {shown} is not a number.") from None
            if not math.isfinite(value):
                raise InputError(f"{where}, column {col + 1} ({label}): {cell!r} is not a finite number "
                                 "(NaN and infinity are not allowed; remove or fix the row).")
    raise InputError(f"{path}: lines {first_line}-{first_line + len(lines) - 1}: malformed CSV.")


def _example_header(required) -> list[str]:
    units = {"pressure": "kPa", "length": "mm", "force": "N", "time": "s"}
    return [f"{name} [{units[name]}]" for name in required]
