"""JSON text of many records held column-wise: the same bytes as
``json.dumps(_clean(record), sort_keys=True)`` record by record (:mod:`pampipe.io.files`), built a column at
a time.

A long route's plan has 10⁵ section records of 3 segments each, about 7·10⁶ floats: walking them as dicts and
rounding each float in Python (``float(f"{x:.12g}")``) costs more than planning them. Here each float column
is rounded to :data:`~pampipe.io.files.JSON_DIGITS` significant digits in numpy (:func:`rounded`), written
with ``float.__repr__`` (what the C JSON encoder calls), and a record is one ``%`` of a template whose
keys are sorted as ``sort_keys`` sorts them.

Every column is held :class:`Coded`: its distinct texts, each written once, and per record the index of its
text. A long route repeats its sections (the 10⁵ of ``benchmarks/bench_big_mission.py`` hold 1,260), so the
records are grouped by their columns' indices and each distinct combination is written once; a column of
mostly distinct texts (the names) is left out of the combinations and put into each record's text as the
texts are joined (:func:`joined_records`: a few thousand records per text, in one ``str.join``).

A column (a value of the ``fields`` of :func:`record_texts`) is one of:

* a 1-D numpy array of floats, bools or ints, one value per record;
* a 2-D numpy float array: one JSON list per record (its row);
* a :class:`Texts`: one JSON text per record, already encoded (a nested list, say), or a :class:`Coded`;
* a dict of columns: one nested JSON object per record;
* any other sequence of plain values (str, None, bool, int, float, dict), one per record.

A NaN or infinite float that would be written raises :class:`NotFinite`: the caller then writes those
records the slow way, whose error names the key path.
"""

from __future__ import annotations

from json.encoder import encode_basestring_ascii

import numpy as np

from pampipe.errors import SolverError
from pampipe.io.files import JSON_DIGITS, JsonText, to_json
from pampipe.runtime.alike import grouped_rows


class NotFinite(Exception):
    """A NaN or infinite float among the values to write."""


class Texts(list):
    """A column of JSON texts, already encoded, one per record."""


#: 10**k for k = 0..22, each exact (parsed from its decimal text): the scales :func:`rounded` multiplies by.
_POWERS = np.array([float(f"1e{k}") for k in range(23)])
#: Where the scaled value is this close to a half (in units of its last kept digit) the product's own
#: rounding (at most 6.2e-5 below 2^40 > 10^12) could flip the digit: those values are formatted instead.
_HALF_BAND = 1e-3


def rounded(values: np.ndarray) -> np.ndarray:
    """``float(f"{x:.12g}")`` of every element of the float array ``values`` (finite), column-wise.

    With e = ⌊log10|x|⌋ and k = 11 − e, the kept digits are M = rint(x·10^k) (half to even, as the
    formatting rounds) and the value M / 10^k, one correctly rounded division of two exact numbers: the
    float that the 12-digit text parses to. M is exact unless x·10^k lies within :data:`_HALF_BAND` of a
    half, or M has not 12 digits (e misjudged near a power of ten, or a carry to 10^12), or |k| > 22;
    those few elements are formatted one by one. Zeros (and −0.0) are kept as they are.
    """
    values = np.asarray(values, dtype=float)
    out = values.copy()
    size = np.abs(values)
    nonzero = np.flatnonzero(size)
    if not nonzero.size:
        return out
    x = values[nonzero]
    k = JSON_DIGITS - 1 - np.floor(np.log10(size[nonzero])).astype(np.int64)
    up = (k >= 0) & (k <= 22)
    down = (k < 0) & (k >= -22)
    scale = _POWERS[np.clip(np.abs(k), 0, 22)]
    with np.errstate(over="ignore"):  # beyond |k| = 22 (formatted one by one below)
        scaled = np.where(up, x * scale, x / scale)
        digits = np.rint(scaled)
        result = np.where(up, digits / scale, digits * scale)
    exact = ((up | down) & (np.abs(np.abs(scaled - np.floor(scaled)) - 0.5) > _HALF_BAND)
             & (np.abs(digits) >= 10.0 ** (JSON_DIGITS - 1)) & (np.abs(digits) < 10.0 ** JSON_DIGITS))
    out[nonzero] = result
    for i in nonzero[~exact].tolist():
        out[i] = float(f"{values[i]:.{JSON_DIGITS}g}")
    return out


def float_texts(values: np.ndarray) -> list[str]:
    """The JSON texts of the floats ``values`` as the rounding writes them; :class:`NotFinite` if any is
    NaN or infinite."""
    return _expanded(_float_codes(values))


def _float_codes(values: np.ndarray) -> Coded:
    """:func:`float_texts` of ``values`` as a :class:`Coded` column: each distinct value rounded and formatted
    once (alike sections repeat theirs; ``float.__repr__`` costs ~1 µs), 0.0 and -0.0 apart."""
    values = np.asarray(values, dtype=float).ravel()
    if not np.isfinite(values).all():
        raise NotFinite
    distinct, index = np.unique(values, return_inverse=True)  # then each distinct value rounded once
    texts = list(map(float.__repr__, rounded(distinct).tolist()))
    index = index.ravel()
    zeros = np.flatnonzero(values == 0.0)  # 0.0 and -0.0 are one value to np.unique
    if zeros.size:
        index[zeros] = len(texts) + np.signbit(values[zeros])
        texts += ["0.0", "-0.0"]
    return Coded(texts, index)


class Coded:
    """A column as its distinct JSON texts and, per value, the index of its text among them."""

    __slots__ = ("codes", "texts")

    def __init__(self, texts: list[str], codes: np.ndarray) -> None:
        self.texts, self.codes = texts, codes


def _expanded(column: Coded) -> list[str]:
    """Every value's text of a coded column, in order."""
    return np.array(column.texts, dtype=object)[column.codes].tolist()


def _coded_texts(texts) -> Coded:
    """The coded column of a list of JSON texts (each distinct text kept once)."""
    return _coded_values(texts, lambda distinct: distinct)


def _coded_values(values, encode) -> Coded:
    """The coded column of a list of hashable ``values`` whose distinct ones (in order of first place)
    ``encode`` writes as their JSON texts."""
    distinct = list(dict.fromkeys(values))
    place = {value: k for k, value in enumerate(distinct)}
    codes = np.fromiter(map(place.__getitem__, values), dtype=np.intp, count=len(values))
    return Coded(encode(distinct), codes)


def coded_column(column, count: int) -> Coded:
    """The JSON text of each of the ``count`` values of ``column`` (see the module's list of columns),
    coded."""
    if isinstance(column, Coded):
        return column
    if isinstance(column, Texts):
        return _coded_texts(column)
    if isinstance(column, dict):
        return coded_records(column, count)
    if isinstance(column, np.ndarray):
        if column.dtype == bool:
            return Coded(["false", "true"], column.astype(np.intp))
        if column.dtype.kind in "iu":
            distinct, index = np.unique(column, return_inverse=True)
            return Coded(list(map(int.__repr__, distinct.tolist())), index.ravel())
        if column.ndim == 2:
            items = _float_codes(column)
            rows, inverse = _distinct_rows(items.codes.reshape(column.shape))
            return Coded(["[" + ", ".join(map(items.texts.__getitem__, row)) + "]" for row in rows], inverse)
        return _float_codes(column)
    if set(map(type, column)) <= {str, type(None)}:  # names, labels, reasons: each distinct one encoded once
        return _coded_values(column, lambda distinct: ["null" if v is None else encode_basestring_ascii(v)
                                                       for v in distinct])
    return _coded_texts([_plain_text(value) for value in column])


def _distinct_rows(codes: np.ndarray) -> tuple[list[list[int]], np.ndarray]:
    """(the distinct rows of the 2-D int array ``codes``, as lists; the distinct row of each row)."""
    table = np.ascontiguousarray(codes, dtype=np.int64)
    first, index = grouped_rows(table)
    return table[first].tolist(), index


def _plain_text(value) -> str:
    """One plain value's JSON text (strings through the C encoder's escaping)."""
    if type(value) is str:
        return encode_basestring_ascii(value)
    if value is None:
        return "null"
    try:
        return to_json(value, indent=None)[:-1]
    except SolverError:  # a NaN or infinite float
        raise NotFinite from None


def record_texts(fields: dict, count: int) -> list[str]:
    """The JSON text of each of ``count`` records whose values are the columns ``fields`` (key → column),
    keys sorted: ``json.dumps(_clean(record), sort_keys=True)`` of each."""
    return _expanded(coded_records(fields, count))


def coded_records(fields: dict, count: int) -> Coded:
    """:func:`record_texts` as a coded column (see :func:`_record_pieces`)."""
    texts, inverse, free = _record_pieces(fields, count)
    if not free:
        return Coded(texts, inverse)
    pieces = _pieces(texts, inverse, free, _SLOT)
    return Coded("".join(pieces.ravel().tolist()[:-1]).split(_SLOT), np.arange(count))


#: Records per text of :func:`joined_records`.
JOINED = 2048


def joined_records(fields: dict, count: int, *, part: int = JOINED):
    """The texts of :func:`record_texts` joined by ``", "``, :class:`~pampipe.io.files.JsonText` s of at
    most ``part`` records each (a few megabytes: the memory a text is built in is reused for the next)."""
    pieces = _pieces(*_record_pieces(fields, count), ", ")
    for start in range(0, count, part):
        block = pieces[start:start + part]
        text = JsonText("".join(block.ravel().tolist()[:-1]))  # without the last separator
        text.items = block.shape[0]
        yield text


#: Stands in a record's text for the value of a column left out of the combinations (never in JSON text:
#: the encoder escapes control characters).
_SLOT = "\0"


def _record_pieces(fields: dict, count: int) -> tuple[list[str], np.ndarray, list[Coded]]:
    """(the text of each distinct combination of the columns' texts, each record's combination, the columns
    left out): each combination is written once, by one ``%`` of a template. A column with more distinct
    texts than half the records (a name) is left out of the combinations: :data:`_SLOT` stands in the
    combination's text for its value."""
    keys = sorted(fields)
    columns = [coded_column(fields[k], count) for k in keys]
    free = [j for j, c in enumerate(columns) if 2 * len(c.texts) > count > 1]
    kept = [j for j in range(len(keys)) if j not in free]
    template = "{" + ", ".join(encode_basestring_ascii(k).replace("%", "%%") + ": " + ("%s" if j in kept
                               else _SLOT) for j, k in enumerate(keys)) + "}"
    rows, inverse = _distinct_rows(np.stack([columns[j].codes for j in kept], axis=1) if kept
                                   else np.empty((count, 0), dtype=np.int64))
    texts = [columns[j].texts for j in kept]
    combined = [template % tuple(t[c] for t, c in zip(texts, row, strict=True)) for row in rows]
    return combined, inverse, [columns[j] for j in free]


def _pieces(combined: list[str], inverse: np.ndarray, free: list[Coded], separator: str) -> np.ndarray:
    """(records, 2·free + 2) texts whose concatenation row by row is each record's text and ``separator``:
    its combination's text split at its :data:`_SLOT` places, with the free columns' texts between."""
    parts = np.array([text.split(_SLOT) for text in combined], dtype=object)  # (combinations, free + 1)
    pieces = np.empty((inverse.size, 2 * len(free) + 2), dtype=object)
    pieces[:, 0::2] = parts[inverse]  # the pieces around the free columns' places
    for k, column in enumerate(free):
        pieces[:, 2 * k + 1] = np.array(column.texts, dtype=object)[column.codes]
    pieces[:, -1] = separator
    return pieces


def grouped(texts: list[str], width: int, present: np.ndarray) -> Texts:
    """One JSON list per record: ``width`` consecutive ``texts`` where ``present``, [] elsewhere
    (``texts`` holds the present records' items only, in order)."""
    return Texts(_expanded(_grouped(_coded_texts(texts), width, present)))


def _grouped(items: Coded, width: int, present: np.ndarray) -> Coded:
    """:func:`grouped` of coded items, coded: each distinct list written once."""
    rows, inverse = _distinct_rows(items.codes.reshape(-1, width))
    texts = ["[" + ", ".join(map(items.texts.__getitem__, row)) + "]" for row in rows] + ["[]"]
    codes = np.full(present.size, len(texts) - 1, dtype=np.intp)
    codes[present] = inverse
    return Coded(texts, codes)


#: Records per pass of :func:`streamed_records`: alike records within a pass are written once.
COLUMN_CHUNK = 1 << 14


def streamed_records(count: int, columns_of, documents_of, *, chunk: int = COLUMN_CHUNK):
    """The ``count`` records of a long list, ``chunk`` at a time, for a
    :class:`~pampipe.io.files.Streamed` list: :class:`~pampipe.io.files.JsonText` items encoded from
    ``columns_of(start, stop)`` = (fields, {key: (the nested records' fields, records per record,
    present)}); where that gives None or a float to write is not finite, the records
    ``documents_of(start, stop)`` as dicts (whose encoding then names the key path of the bad value)."""
    for start in range(0, count, chunk):
        stop = min(start + chunk, count)
        columns = columns_of(start, stop)
        try:
            if columns is None:
                raise NotFinite
            fields, nested = columns
            fields = dict(fields)
            for key, (inner, width, present) in nested.items():
                fields[key] = _grouped(coded_records(inner, int(present.sum()) * width), width, present)
            yield from joined_records(fields, stop - start)
        except NotFinite:
            yield from documents_of(start, stop)
