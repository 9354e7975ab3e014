"""An experiment as frozen SI objects: its tests, their recorded rows and the protocol grouping.

No I/O here: :func:`pampipe.io.load_experiment` reads the experiment file and
:func:`pampipe.io.load_experiment_data` its CSV files. The grouping of rows into pressure levels,
legs and cycles (what the fit needs beyond the raw columns) is defined here.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from pampipe.errors import InputError
from pampipe.model.pam import Pam
from pampipe.specs import protocol

#: Words a ``direction``/``state`` cell may hold instead of a sign (docs/formats.md §3).
DIRECTION_WORDS = {"loading": 1, "filling": 1, "unloading": -1, "venting": -1, "held": 0}


@dataclass(frozen=True)
class DirectionCoding:
    """How a test's ``direction``/``state`` column codes the legs when it does not hold signs:
    ``direction: {column: state, loading: 1, unloading: 2}`` (``held``: optional code of held rows)."""

    column: str
    loading: float
    unloading: float
    held: float | None = None


@dataclass(frozen=True)
class TestSpec:
    """One test of an experiment: its kind, conditions and resolved CSV path (SI).

    ``set_pressures`` [Pa] are the test's pressure set points when the file names them (rows take
    the nearest one); ``protocol`` overrides the detected protocol of an axial test (``isobaric``,
    ``isometric`` or ``mixed``, see :mod:`pampipe.specs.protocol`).
    """

    name: str
    kind: str
    data: Path
    pipe_diameter: float | None
    axial_load: float
    set_pressures: tuple[float, ...] | None = None
    protocol: str | None = None
    pipe_material: str | None = None  # slip tests: the wall material the friction belongs to
    direction: DirectionCoding | None = None


@dataclass(frozen=True)
class Experiment:
    """An experiment file: its muscle, its tests (CSV paths resolved, not read) and its ``fit:`` options."""

    source: Path
    pam: Pam
    tests: tuple[TestSpec, ...]
    fit: dict[str, Any]
    pam_file: Path | None = None  # the PAM file it names (None for an inline PAM)
    prior_file: Path | None = None  # the PAM file of its prior (fit.prior.pam), if any

    @property
    def input_files(self) -> list[Path]:
        """Every file the experiment reads: itself, its PAM file and its CSV files."""
        own = [self.source] + ([self.pam_file] if self.pam_file is not None else [])
        return own + [t.data for t in self.tests]

    @property
    def validated_files(self) -> list[Path]:
        """The files its validation read: itself, its PAM file and its prior's (not the CSV data)."""
        return [self.source, *(f for f in (self.pam_file, self.prior_file) if f is not None)]


@dataclass(frozen=True)
class TestData:
    """One test's rows in recorded order (SI), plus the grouping the fit uses (:mod:`pampipe.specs.protocol`).

    ``level`` indexes ``level_pressure`` row by row: the pressure levels (set points or clusters)
    when ``level_source`` is ``set_points`` or ``clusters``; for a test without levels
    (``none``: ramps) equal-count pressure bins, used only inside the fit. ``leg`` is the sign of
    dL/dt (+1 lengthening, −1 shortening) and ``pressure_leg`` the sign of dP/dt (+1 filling,
    −1 venting), 0 where held or unknown; ``cycle`` counts cycles of the swept variable within a
    level. ``protocol``: ``isobaric``, ``isometric``, ``mixed`` (axial tests) or ``radial``;
    ``held_length`` indexes ``level_length``, the held lengths of an isometric test (else zeros).
    ``direction_source`` says where the directions came from: ``column``, ``time``, ``row order``
    or ``unknown`` (rows not in time order: no legs).
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
    pressure_leg: np.ndarray | None = field(default=None, repr=False)
    level_source: str = "clusters"
    protocol: str = "isobaric"
    held_length: np.ndarray | None = field(default=None, repr=False)
    level_length: np.ndarray | None = field(default=None, repr=False)
    direction_source: str = "row order"

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def kind(self) -> str:
        return self.spec.kind

    @property
    def points(self) -> int:
        return int(self.force.size)

    @property
    def has_levels(self) -> bool:
        """True when the rows are grouped into pressure levels (set points or clusters)."""
        return self.level_source != "none"

    @property
    def slack(self) -> np.ndarray:
        """Rows where the muscle is slack (recorded force ≤ 0), docs/commands.md §3.3."""
        return self.slack_at(slice(None))

    def slack_at(self, rows) -> np.ndarray:
        """:attr:`slack` of ``rows`` only (no pass over every row)."""
        return self.force[rows] <= 0

    def subset(self, keep: np.ndarray) -> TestData:
        """This test with the rows ``keep`` (bool mask) only, each keeping its level, leg and cycle (a block
        of the protocol withheld: :mod:`pampipe.identification.model_error`)."""
        rows = {name: value[keep] for name in ROW_FIELDS if (value := getattr(self, name)) is not None}
        return replace(self, **rows)


#: The fields of :class:`TestData` with one entry per row.
ROW_FIELDS = ("pressure", "force", "length", "time", "level", "leg", "cycle", "pressure_leg", "held_length")


@dataclass(frozen=True)
class ExperimentData:
    """An experiment with its CSV data loaded."""

    source: Path
    pam: Pam
    tests: tuple[TestData, ...]
    fit: dict
    slip: tuple[SlipData, ...] = ()  # slip tests (kind: slip), kept apart from the moduli fit

    @property
    def points(self) -> int:
        """Rows of the moduli fit (axial and radial tests; slip tests are not counted)."""
        return sum(t.points for t in self.tests)


@dataclass(frozen=True)
class SlipData:
    """One slip test's rows in time order (SI) and its trials (docs/formats.md, slip tests).

    A trial is a rise of the axial load from rest, ended where the load drops back
    (:func:`split_trials`); ``trials`` holds (first row, end row) pairs, the end exclusive, and
    ``row`` each row's 0-based data row in the file (its order before sorting by time).
    """

    spec: TestSpec
    time: np.ndarray  # [s]
    pressure: np.ndarray  # [Pa] gauge
    axial_load: np.ndarray  # [N]
    displacement: np.ndarray  # [m] of the muscle along the pipe
    trials: tuple[tuple[int, int], ...]
    row: np.ndarray = field(repr=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def points(self) -> int:
        return int(self.time.size)


#: A trial ends where the load falls back below its start plus this fraction of its rise.
RETURN_FRACTION = 0.1
#: Fewest rows a trial needs for its elastic trend and onset.
MIN_TRIAL_ROWS = 8


def make_slip_data(spec: TestSpec, columns: dict[str, np.ndarray]) -> SlipData:
    """Validate a slip test's SI columns and split them into trials (InputError names file and column).

    Columns ``time``, ``pressure``, ``axial_load``, ``displacement``. Refused: a negative gauge
    pressure, an axial load of the wrong sign (further below 0 than above it), one that never rises above
    its noise, a trial with fewer than
    :data:`MIN_TRIAL_ROWS` rows, time that is not increasing.
    """
    where = f"{spec.data}"
    time = np.asarray(columns["time"], dtype=float)
    order = np.argsort(time, kind="stable")
    time, pressure, load, displacement = (np.asarray(columns[k], dtype=float)[order]
                                          for k in ("time", "pressure", "axial_load", "displacement"))
    if np.any(np.diff(time) <= 0):
        i = int(order[1:][np.diff(time) <= 0][0])
        raise InputError(f"{where}: column 'time', data row {i + 1}: the time repeats; a slip test records "
                         "one row per instant, time strictly increasing.")
    negative = np.flatnonzero(pressure < 0)
    if negative.size:
        i = int(order[negative[0]])
        raise InputError(f"{where}: column 'pressure', data row {i + 1}: "
                         f"{pressure[negative[0]] / 1e3:.6g} kPa is negative; a slip test holds the muscle "
                         "at a gauge pressure >= 0 (the anchoring pressure or above).")
    if load.size and -load.min() > max(load.max(), 0.0):
        i = int(order[int(np.argmin(load))])
        raise InputError(f"{where}: column 'axial_load', data row {i + 1}: the load reaches "
                         f"{load.min():.6g} N and at most {max(load.max(), 0.0):.6g} N; a slip test pulls "
                         "the muscle along the pipe with a positive load (tension, in N). Was the load "
                         "cell's sign reversed? Negate the column.")
    trials = split_trials(load)
    if not trials:
        raise InputError(f"{where}: column 'axial_load': the load never rises (it spans "
                         f"{np.ptp(load):.4g} N, within its noise); a slip test raises the axial load from "
                         "rest until the muscle slips, then lets it drop back, once per trial.")
    for first, end in trials:
        if end - first < MIN_TRIAL_ROWS:
            raise InputError(f"{where}: column 'axial_load', data rows {int(order[first]) + 1}-"
                             f"{int(order[end - 1]) + 1}: a trial of only {end - first} rows; each trial "
                             f"needs at least {MIN_TRIAL_ROWS} rows (sample the rise more often).")
    return SlipData(spec, time, pressure, load, displacement, tuple(trials), order)


def split_trials(load: np.ndarray) -> list[tuple[int, int]]:
    """(first row, end row) of every trial: a rise of the load by more than its noise, ended where the
    load falls back below start + :data:`RETURN_FRACTION` of the rise (or at the last row).

    The noise is σ = 1.4826·median|Δ²F|/√6 (second differences: a steady ramp does not count); a rise
    must exceed max(10σ, 10⁻³·span).
    """
    load = np.asarray(load, dtype=float)
    if load.size < 3:
        return []
    noise = 1.4826 * float(np.median(np.abs(np.diff(load, 2)))) / np.sqrt(6.0)
    least = max(10 * noise, 1e-3 * float(np.ptp(load)), 1e-9)
    trials, first, low, peak = [], 0, load[0], load[0]
    for i, value in enumerate(load):
        if value > peak:
            peak = value
        if peak - low <= least:
            if value < low:  # still at rest: the trial starts at the lowest point
                first, low, peak = i, value, value
            continue
        if value <= low + RETURN_FRACTION * (peak - low):
            trials.append((first, i + 1))
            first, low, peak = i, value, value
    if peak - low > least:
        trials.append((first, load.size))
    return trials


def make_test_data(spec: TestSpec, columns: dict[str, np.ndarray]) -> TestData:
    """Wrap SI columns as :class:`TestData`: levels, protocol and the direction of every row.

    Columns: ``pressure``, ``force``, ``length`` (axial), optional ``time`` (puts the rows in time
    order for the rates), ``set_pressure`` (the set point of every row) and ``direction`` or
    ``state`` (the sign of the swept variable's rate: length for isobaric and mixed tests,
    pressure for isometric and radial ones; 0 held).
    """
    pressure = np.asarray(columns["pressure"], dtype=float)
    force = np.asarray(columns["force"], dtype=float)
    length = columns.get("length")
    length = None if length is None else np.asarray(length, dtype=float)
    time = columns.get("time")
    order = None if time is None else np.argsort(np.asarray(time, dtype=float), kind="stable")
    if columns.get("set_pressure") is not None:
        levels = protocol.find_levels(pressure, columns["set_pressure"], per_row=True)
    else:
        levels = protocol.find_levels(pressure, spec.set_pressures)
    n = pressure.size
    zeros = np.zeros(n, dtype=np.int8)
    held, kind = None, "radial"
    if spec.kind == "axial" and length is not None:
        kind, held = protocol.classify(levels, length, order)
        kind = spec.protocol or kind
        if kind == "isometric" and held is None:
            held = protocol.cluster_levels(length) or protocol.equal_count_bins(length)
    leg, pressure_leg = zeros, zeros
    given = direction_signs(spec, columns)
    groups = {"isobaric": levels.index, "isometric": None if held is None else held.index}.get(kind)
    grouped = protocol.segments(groups, order, n)  # the rows of each level (held length) in time order
    if kind == "isobaric":
        leg = _given_or(given, lambda: protocol.directions(length, grouped))
    elif kind == "isometric":
        pressure_leg = _given_or(given, lambda: protocol.directions(pressure, grouped))
    elif kind == "mixed":
        leg = _given_or(given, lambda: protocol.directions(length, grouped))
        pressure_leg = protocol.directions(pressure, grouped)
    else:
        pressure_leg = _given_or(given, lambda: protocol.directions(pressure, grouped))
    swept = leg if kind in ("isobaric", "mixed") else pressure_leg
    if given is not None:
        source = "column"
    elif order is not None:
        source = "time"
    else:
        source = "row order" if np.any(swept) else "unknown"
    cycle = protocol.cycles(swept, grouped)
    return TestData(spec, pressure, force, length, time, levels.index, levels.values, leg, cycle,
                    pressure_leg, levels.source, kind,
                    None if held is None else held.index, None if held is None else held.values, source)


def _given_or(given, compute) -> np.ndarray:
    """The signs of a ``direction``/``state`` column if the file has one, else the computed signs."""
    return given if given is not None else compute()


def direction_signs(spec: TestSpec, columns: dict[str, np.ndarray]) -> np.ndarray | None:
    """The legs (+1 loading/filling/lengthening, −1 unloading/venting/shortening, 0 held) that the
    file's ``direction`` or ``state`` column codes, or None without one.

    The column holds +1, −1 or 0 (words were turned into these when read), or the codes of the
    test's mapping (:class:`DirectionCoding`); any other value is an :class:`InputError` naming the
    file, the column and the values found: a column coded 1/2 is never read as "all filling".
    """
    name = next((n for n in ("direction", "state") if columns.get(n) is not None), None)
    coding = spec.direction
    if name is None:
        if coding is not None:
            raise InputError(f"{spec.data}: test {spec.name!r} maps its direction column "
                             f"(direction.column: {coding.column}) but the file has no {coding.column} "
                             "column.")
        return None
    if coding is not None and coding.column != name:
        raise InputError(f"{spec.data}: test {spec.name!r}: direction.column is {coding.column!r} but the "
                         f"file's direction column is {name!r}.")
    raw = np.asarray(columns[name], dtype=float)
    codes = {1.0: 1, -1.0: -1, 0.0: 0} if coding is None else \
        {coding.loading: 1, coding.unloading: -1, **({} if coding.held is None else {coding.held: 0})}
    known = np.isin(raw, list(codes))
    if not np.all(known):
        found = np.unique(raw)
        shown = ", ".join(f"{v:g}" for v in found[:8]) + (", ..." if found.size > 8 else "")
        if coding is None:
            raise InputError(
                f"{spec.data}: column {name!r} holds {shown}; a {name} column holds +1 (loading, "
                f"filling, lengthening), -1 (unloading, venting, shortening) or 0 (held), or those words. "
                f"If it codes the legs otherwise, map the codes in the test, e.g. "
                f"direction: {{column: {name}, loading: {found[0]:g}, unloading: {found[-1]:g}}} "
                "(docs/formats.md §3).")
        allowed = ", ".join(f"{v:g}" for v in codes)
        raise InputError(f"{spec.data}: column {name!r} holds {shown}, and test {spec.name!r} maps only "
                         f"{allowed} (direction: loading, unloading, held); map every code the file uses.")
    out = np.zeros(raw.size, dtype=np.int8)
    for code, sign in codes.items():
        out[raw == code] = sign
    return out


def pressure_levels(pressure: np.ndarray, *, max_levels: int = protocol.MAX_LEVELS,
                    fallback_bins: int = protocol.FALLBACK_BINS):
    """(level index per row, median pressure per level) [-, Pa], see :mod:`pampipe.specs.protocol`.

    Levels are clusters of the pressures; a ramp (no levels) is split into ``fallback_bins``
    equal-count pressure bins instead. Levels are numbered by increasing pressure.
    """
    pressure = np.asarray(pressure, dtype=float)
    levels = protocol.cluster_levels(pressure, max_levels=max_levels) \
        or protocol.equal_count_bins(pressure, fallback_bins)
    return levels.index, levels.values


def legs_and_cycles(length: np.ndarray, level: np.ndarray):
    """(leg, cycle) per row of an isobaric test in recorded order: the sign of dL/dt within each
    level (:func:`pampipe.specs.protocol.rate_sign`) and the shortening-lengthening cycle count."""
    length = np.asarray(length, dtype=float)
    grouped = protocol.segments(np.asarray(level), None, length.size)
    leg = protocol.directions(length, grouped)
    return leg, protocol.cycles(leg, grouped)
