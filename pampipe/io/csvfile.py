"""CSV data files → SI arrays, with errors that name the file, the line and the column.

CSV format (docs/formats.md §3): one header row, every column named ``quantity [unit]``
(``pressure [kPa]``, ``length [mm]``, ``force [N]``, ``time [s]``); rows in recorded order; blank
lines are ignored. Columns with other names are allowed (they must still be numeric) and ignored.

Reading is chunked: :data:`CHUNK_ROWS` lines are parsed at a time by numpy's C parser, so a file
of 10⁷ rows needs memory for its numbers (8 bytes per cell) plus one chunk of text, never the
whole text or Python objects per cell. Only when a chunk fails does a slow line-by-line scan run,
to name the exact line, column and value.

:func:`load_experiment_data` reads every test of an experiment and groups its rows
(:func:`pampipe.experiment.make_test_data`).
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.experiment import Experiment, ExperimentData, make_test_data
from pampipe.io.files import atomic_write
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


def load_experiment_data(experiment: Experiment, *, progress: Progress | None = None) -> ExperimentData:
    """Read every test's CSV (see :func:`read_csv`) and add levels, legs and cycles."""
    tests = []
    for spec in experiment.tests:
        columns = read_csv(spec.data, required=REQUIRED[spec.kind], progress=progress)
        tests.append(make_test_data(spec, columns))
    return ExperimentData(experiment.source, experiment.pam, tuple(tests), dict(experiment.fit))


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


# ---------------------------------------------------------------------------------------- writing
def write_csv(path: Path, columns: dict[str, np.ndarray]) -> None:
    """Write SI columns as CSV in lab units (kPa, mm, N, s), atomically."""
    units = {"time": ("s", 1.0, "%.3f"), "pressure": ("kPa", 1e-3, "%.4f"),
             "length": ("mm", 1e3, "%.5f"), "force": ("N", 1.0, "%.4f")}
    order = [name for name in ("time", "pressure", "length", "force") if name in columns]
    header = ",".join(f"{name} [{units[name][0]}]" for name in order)
    table = np.column_stack([columns[name] * units[name][1] for name in order])
    fmt = [units[name][2] for name in order]
    atomic_write(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", fmt=fmt, header=header,
                                              comments=""))
