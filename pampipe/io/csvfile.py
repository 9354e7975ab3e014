"""CSV data files → SI arrays, with errors that name the file, the line and the column.

CSV format (docs/formats.md §3): one header row, every column named ``quantity [unit]``
(``pressure [kPa]``, ``length [mm]``, ``force [N]``, ``time [s]``); rows in recorded order; blank
lines are ignored. Optional columns: ``set_pressure [kPa]`` (the set point of every row) and
``direction [-]`` or ``state [-]`` (+1, −1 or 0: the sign of the swept variable's rate, see
:mod:`pampipe.specs.protocol`). Columns with other names are allowed (they must still be numeric) and
ignored.

A cell is a plain decimal number (:data:`pampipe.units.quantities.NUMBER`), nothing else: no comments
(``1#514.46`` is an error, not 1), no NaN or infinity, no underscores or hexadecimal.

Reading is chunked: blocks of :data:`BLOCK_BYTES` whole lines are parsed by numpy's C parser, or by
pandas' when the experiment's files exceed :data:`FAST_BYTES` (2-3× faster, measured: 0.39 s against
0.88 s for 1.8·10⁶ rows, but 0.5 s to import, so small experiments do not use it). A file of 10⁷
rows needs memory for its numbers (8 bytes per cell) plus one block of text, never the whole text or
Python objects per cell; a file whose rows would not fit in the available memory is refused before
it is read (:func:`check_memory`). Only when a block holds a character that cannot be part of a
number, or fails to parse, does a slow line-by-line scan run, to name the exact line, column and value.
Only regular files are read (a FIFO or ``/dev/zero`` is refused before reading).

:func:`load_experiment_data` reads every test of an experiment and groups its rows
(:func:`pampipe.specs.experiment.make_test_data`).
"""

from __future__ import annotations

import io
import itertools
import math
import os
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.io.files import atomic_write
from pampipe.io.paths import open_input
from pampipe.runtime.memory import check_fits
from pampipe.specs.experiment import (
    DIRECTION_WORDS,
    Experiment,
    ExperimentData,
    make_slip_data,
    make_test_data,
)
from pampipe.units.quantities import NUMBER, column_factor, show

#: Bytes read per block, in whole lines: bounds the text held in memory (a block holds ≈ 2·10⁵ rows
#: of a 3-column file, and no line may be longer).
BLOCK_BYTES = 8 * 2**20
#: Experiments whose files hold more bytes than this are parsed by pandas (when installed).
FAST_BYTES = 32 * 2**20
#: Memory a data row needs while identify runs [bytes] (measured peak: ≈ 80 B a row at 3·10⁶ rows, see
#: benchmarks/bench_identify.py; 120 leaves a margin).
BYTES_PER_ROW = 120
#: Files with more rows than this report their reading progress.
PROGRESS_ROWS = 262_144
#: Known column names and their dimensions.
DIMENSIONS = {"pressure": "pressure", "length": "length", "force": "force", "time": "time",
              "set_pressure": "pressure", "axial_load": "force", "displacement": "length"}
#: Direction columns (docs/formats.md §3): the sign of the swept variable's rate, unit ``-`` or ``1``.
SIGNS = ("direction", "state")
#: Columns each test kind needs.
REQUIRED = {"axial": ("pressure", "length", "force"), "radial": ("pressure", "force"),
            "slip": ("time", "pressure", "axial_load", "displacement")}

_HEADER = re.compile(r"^\s*([^\[\]]+?)\s*\[([^\[\]]*)\]\s*$")

Progress = Callable[[str], None]


def load_experiment_data(experiment: Experiment, *, progress: Progress | None = None) -> ExperimentData:
    """Read every test's CSV (see :func:`read_csv`) and add levels, legs and cycles."""
    tests, slip = [], []
    sizes = [spec.data.stat().st_size if spec.data.is_file() else 0 for spec in experiment.tests]
    fast = sum(sizes) > FAST_BYTES  # pandas pays its import once for the whole experiment
    for spec in experiment.tests:
        columns = read_csv(spec.data, required=REQUIRED[spec.kind], progress=progress, fast=fast)
        if spec.kind == "slip":
            slip.append(make_slip_data(spec, columns))
        else:
            tests.append(make_test_data(spec, columns))
    if tests and not any(np.any(t.force) for t in tests):
        raise InputError(f"{experiment.source}: every force in every test is 0 N: nothing to fit; "
                         "check the force columns and their units.")
    return ExperimentData(experiment.source, experiment.pam, tuple(tests), dict(experiment.fit), tuple(slip))


# ------------------------------------------------------------------------------------------ CSV
def read_csv(path: Path, *, required: tuple[str, ...], progress: Progress | None = None,
             fast: bool | None = None) -> dict[str, np.ndarray]:
    """Read a CSV file into SI columns keyed by quantity name (``pressure``, ``length``, ...).

    ``fast`` chooses pandas' parser (default: for a file above :data:`FAST_BYTES`). Raises
    :class:`InputError` naming the file, the line and the column for: a missing or unreadable file,
    an empty file, a header without data, a header cell without a ``[unit]``, an unknown unit or one
    of the wrong dimension, a missing required column, a duplicate column, a row with the wrong
    number of cells, a non-numeric cell, NaN or infinity, or rows that would not fit in memory.
    """
    path = Path(path)
    with open_input(path, what="data file") as handle:
        size = os.fstat(handle.fileno()).st_size
        parse = _pandas_parser() if (size > FAST_BYTES if fast is None else fast) else None
        return _read_open(path, _blocks(path, handle), required, progress, size, parse or _numpy_block)


def check_memory(path: Path, size: int, line_bytes: int) -> None:
    """Refuse a file whose rows (estimated from its size and its first line's length) would need more
    than the available memory (:data:`BYTES_PER_ROW` a row)."""
    check_rows(size / max(line_bytes, 8), where=f"{path}: about", advice="thin the file out (every k-th "
               "row keeps the statistics) or split it into several tests")


def check_rows(rows: float, *, where: str, advice: str) -> None:
    """InputError when ``rows`` data rows would need more than the available memory
    (:data:`BYTES_PER_ROW` a row); skipped where the OS does not say how much is available."""
    check_fits(rows * BYTES_PER_ROW, what=f"{where} {rows:,.0f} data rows", advice=advice)


def _numpy_block(chunk: bytes) -> np.ndarray:
    return np.loadtxt(chunk.decode("ascii").split("\n"), delimiter=",", ndmin=2, dtype=float,
                      comments=None)


def _pandas_parser():
    """A block parser by pandas' C reader (the same numbers as numpy's), or None without pandas."""
    try:
        import pandas as pd
    except ImportError:
        return None

    def parse(chunk: bytes) -> np.ndarray:
        try:
            return pd.read_csv(io.BytesIO(chunk), header=None, dtype=np.float64, engine="c",
                               skip_blank_lines=True, na_filter=False).to_numpy()
        except Exception:  # malformed: numpy's reader and the scan name the line
            raise ValueError("pandas could not parse the block") from None

    return parse


def _blocks(path: Path, handle):
    """(file line number of the block's first line, bytes) for consecutive blocks of whole lines."""
    carry, line = b"", 1
    while True:
        try:
            block = handle.read(BLOCK_BYTES)
        except OSError as exc:
            raise InputError(f"{path}: cannot read the data file ({exc.strerror or exc}).") from None
        data = carry + block
        cut = len(data) if not block else data.rfind(b"\n") + 1
        if block and cut == 0:
            if len(data) > BLOCK_BYTES:
                raise InputError(f"{path}: line {line} is longer than {BLOCK_BYTES // 2**20} MB; "
                                 "is this a CSV file?")
            carry = data
            continue
        carry = data[cut:]
        if cut:
            yield line, data[:cut]
            line += data.count(b"\n", 0, cut)
        if not block:
            return


#: The bytes of rows of plain decimal numbers (a block with any other byte goes to the slow scan).
_NUMERIC = b"0123456789eE+-.,\r\n\t\f\v "
_CELL = re.compile(NUMBER)


def _decode(path: Path, chunk: bytes, line: int) -> str:
    try:
        return chunk.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad = line + chunk.count(b"\n", 0, exc.start)
        raise InputError(f"{path}: line {bad}: is not UTF-8 text.") from None


def _read_open(path, blocks, required, progress, size, parse) -> dict[str, np.ndarray]:
    first, chunk = next(blocks, (1, b""))
    _decode(path, chunk, first)  # a binary file fails here, before its "header" is judged
    header, _, rest = chunk.partition(b"\n")
    header = header.decode("utf-8").removeprefix("\ufeff")  # a byte-order mark, as spreadsheets write
    if not header.strip():
        raise InputError(f"{path}: the file is empty; expected a header row such as "
                         f"'{', '.join(_example_header(required))}' followed by data rows.")
    names, factors, ncols = _parse_header(path, header, required)
    check_memory(path, size, len(header) + 1)
    chunks = []
    rows = 0
    for start, chunk in itertools.chain([(first + 1, rest)], blocks):
        if not chunk or chunk.isspace():  # = not chunk.strip(), without copying the block
            continue
        block = None
        signs = next((names[n] for n in SIGNS if n in names), None)
        if signs is not None and chunk.translate(None, _NUMERIC):
            chunk = _direction_words(path, chunk, start, signs, ncols)
        if not chunk.translate(None, _NUMERIC):
            try:
                block = parse(chunk)
            except ValueError:
                block = None
        if block is None or (block.size and (block.shape[1] != ncols or not np.all(np.isfinite(block)))):
            lines = _decode(path, chunk, start).split("\n")
            _scan(path, lines, start, names, ncols)  # raises, naming the line and column
            # no bad line: the block failed on whitespace-only lines, which are ignored
            block = np.loadtxt([t for t in lines if t.strip()], delimiter=",", ndmin=2, dtype=float,
                               comments=None)
        chunks.append(block)
        rows += block.shape[0]
        if progress is not None and rows >= PROGRESS_ROWS:
            progress(f"reading {path.name}: {rows:,} rows")
    if rows == 0:
        raise InputError(f"{path}: the file has a header but no data rows.")
    return {name: _column(chunks, col, factors[name]) for name, col in names.items()}


def _column(blocks: list[np.ndarray], col: int, factor: float) -> np.ndarray:
    """Column ``col`` of the stacked blocks times ``factor`` (column by column: pandas' blocks are
    column-major, so no row-major table of every column is built)."""
    if len(blocks) == 1:
        return blocks[0][:, col] * factor
    out = np.concatenate([block[:, col] for block in blocks])
    out *= factor
    return out


#: Separators other than the comma that spreadsheets write, by name.
_OTHER_SEPARATORS = {";": "semicolons (';')", "\t": "tabs"}


def _separator_problem(text: str) -> str | None:
    """Why ``text`` (a row) is not comma-separated plain CSV, or None: other separators, quoted cells."""
    if "," not in text:
        for separator, name in _OTHER_SEPARATORS.items():
            if separator in text:
                return (f"the row is separated by {name}; pampipe reads comma-separated values: "
                        "save the file as CSV with ',' between cells")
    if any(c.strip()[:1] in ('"', "'") for c in text.split(",")):
        return ("its cells are quoted; pampipe reads plain CSV: save it without quotes, e.g. "
                "'time [s],pressure [kPa]' and '0.0,101.3'")
    return None


def _parse_header(path, line, required):
    problem = _separator_problem(line.strip())
    if problem:
        raise InputError(f"{path}: line 1: {problem}.")
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
        elif name in SIGNS:
            if unit not in ("", "-", "1"):
                raise InputError(f"{where}: a {name} column holds signs (+1, -1, 0) and takes the unit "
                                 f"[-] or [1], not [{unit}].")
            factors[name] = 1.0
        names[name] = col - 1
    missing = [r for r in required if r not in names]
    if missing:
        raise InputError(f"{path}: line 1: missing column(s) {', '.join(missing)}; this test needs "
                         f"{', '.join(_example_header(required))} (found: {', '.join(cells)}).")
    if "direction" in names and "state" in names:
        raise InputError(f"{path}: line 1: give either a direction or a state column, not both.")
    return {n: c for n, c in names.items() if n in factors}, factors, len(cells)


def _direction_words(path, chunk: bytes, first_line: int, col: int, ncols: int) -> bytes:
    """The block with the words of its direction column (:data:`pampipe.specs.experiment.DIRECTION_WORDS`:
    loading, filling → +1; unloading, venting → −1; held → 0) written as signs; a word that is not one
    of them is an error naming the line. Other cells are left for the number check."""
    lines = _decode(path, chunk, first_line).split("\n")
    for offset, line in enumerate(lines):
        cells = line.split(",")
        if len(cells) != ncols:
            continue  # blank, or malformed: the scan names it
        word = cells[col].strip().lower()
        if word in DIRECTION_WORDS:
            cells[col] = str(DIRECTION_WORDS[word])
            lines[offset] = ",".join(cells)
        elif word.isalpha():
            shown = show(cells[col].strip())
            raise InputError(f"{path}: line {first_line + offset}, column {col + 1}: {shown} is not a "
                             f"direction; allowed: +1, -1, 0 or {', '.join(DIRECTION_WORDS)} "
                             "(docs/formats.md §3).")
    return "\n".join(lines).encode("utf-8")


def _scan(path, lines, first_line, names, ncols) -> None:
    """Raise for the first malformed line of a block, naming it (slow path, only on error)."""
    labels = {c: n for n, c in names.items()}
    for offset, raw in enumerate(lines):
        text = raw.strip()
        if not text:
            continue
        cells = [c.strip() for c in text.split(",")]
        where = f"{path}: line {first_line + offset}"
        problem = _separator_problem(text)
        if problem:
            raise InputError(f"{where}: {problem}.")
        if len(cells) != ncols:
            raise InputError(f"{where}: has {len(cells)} cells but the header has {ncols} columns.")
        for col, cell in enumerate(cells):
            label = labels.get(col, f"column {col + 1}")
            if cell.lower().lstrip("+-") in ("nan", "inf", "infinity"):
                raise InputError(f"{where}, column {col + 1} ({label}): {cell!r} is not a finite number "
                                 "(NaN and infinity are not allowed; remove or fix the row).")
            if not _CELL.fullmatch(cell):
                shown = "an empty cell" if not cell else show(cell)
                raise InputError(f"{where}, column {col + 1} ({label}): {shown} is not a number "
                                 "(a cell holds one plain decimal number).")
            if not math.isfinite(float(cell)):
                raise InputError(f"{where}, column {col + 1} ({label}): {cell!r} is not a finite number "
                                 "(NaN and infinity are not allowed; remove or fix the row).")


def _example_header(required) -> list[str]:
    units = {"pressure": "kPa", "length": "mm", "force": "N", "time": "s", "axial_load": "N",
             "displacement": "mm"}
    return [f"{name} [{units[name]}]" for name in required]


# ---------------------------------------------------------------------------------------- writing
def write_csv(path: Path, columns: dict[str, np.ndarray]) -> None:
    """Write SI columns as CSV in lab units (kPa, mm, N, s), atomically."""
    units = {"time": ("s", 1.0, "%.3f"), "pressure": ("kPa", 1e-3, "%.4f"),
             "length": ("mm", 1e3, "%.5f"), "force": ("N", 1.0, "%.4f"), "axial_load": ("N", 1.0, "%.4f"),
             "displacement": ("mm", 1e3, "%.5f")}
    order = [name for name in ("time", "pressure", "length", "force", "axial_load", "displacement")
             if name in columns]
    header = ",".join(f"{name} [{units[name][0]}]" for name in order)
    table = np.column_stack([columns[name] * units[name][1] for name in order])
    fmt = [units[name][2] for name in order]
    atomic_write(path, lambda tmp: np.savetxt(tmp, table, delimiter=",", fmt=fmt, header=header,
                                              comments=""), create_folder=True)
