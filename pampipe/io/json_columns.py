"""JSON text of many records held column-wise: the same bytes as
``json.dumps(_clean(record), sort_keys=True)`` record by record (:mod:`pampipe.io.files`), built a column at
a time.

A long route's plan has 10⁵ section records of 3 segments each, about 7·10⁶ floats: walking them as dicts and
rounding each float in Python (``float(f"{x:.12g}")``) costs more than planning them. Here each float column
is rounded to :data:`~pampipe.io.files.JSON_DIGITS` significant digits in numpy (:func:`rounded`), written
with ``float.__repr__`` (what the C JSON encoder calls), and every record is one ``%`` of a template whose
keys are sorted as ``sort_keys`` sorts them.

A column (a value of the ``fields`` of :func:`record_texts`) is one of:

* a 1-D numpy array of floats, bools or ints, one value per record;
* a 2-D numpy float array: one JSON list per record (its row);
* a :class:`Texts`: one JSON text per record, already encoded (a nested list, say);
* a dict of columns: one nested JSON object per record;
* any other sequence of plain values (str, None, bool, int, float, dict), one per record.

A NaN or infinite float that would be written raises :class:`NotFinite`: the caller then writes those
records the slow way, whose error names the key path.
"""

from __future__ import annotations

from json.encoder import encode_basestring_ascii

import numpy as np

from pampipe.errors import SolverError
from pampipe.io.files import JSON_DIGITS, STREAM_CHUNK, JsonText, to_json


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
    values = np.asarray(values, dtype=float)
    if not np.isfinite(values).all():
        raise NotFinite
    # each distinct value formatted once (alike sections repeat theirs; float.__repr__ costs ~1 µs)
    distinct, index = np.unique(rounded(values), return_inverse=True)
    texts = np.array(list(map(float.__repr__, distinct.tolist())), dtype=object)[index.ravel()]
    zeros = np.flatnonzero(values == 0.0)  # 0.0 and -0.0 are one value to np.unique
    texts[zeros] = np.where(np.signbit(values[zeros]), "-0.0", "0.0")
    return texts.tolist()


def column_texts(column, count: int) -> list[str]:
    """The JSON text of each of the ``count`` values of ``column`` (see the module's list of columns)."""
    if isinstance(column, Texts):
        return column
    if isinstance(column, dict):
        return record_texts(column, count)
    if isinstance(column, np.ndarray):
        if column.dtype == bool:
            return ["true" if v else "false" for v in column.tolist()]
        if column.dtype.kind in "iu":
            return list(map(int.__repr__, column.tolist()))
        if column.ndim == 2:
            rows = np.asarray(float_texts(column.ravel()), dtype=object).reshape(column.shape)
            return ["[" + ", ".join(row) + "]" for row in rows.tolist()]
        return float_texts(column)
    if set(map(type, column)) <= {str, type(None)}:  # names, labels, reasons: each distinct one encoded once
        texts = {value: _plain_text(value) for value in set(column)}
        return list(map(texts.__getitem__, column))
    return [_plain_text(value) for value in column]


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
    keys = sorted(fields)
    if not keys:
        return ["{}"] * count
    template = "{" + ", ".join(encode_basestring_ascii(k).replace("%", "%%") + ": %s" for k in keys) + "}"
    columns = [column_texts(fields[k], count) for k in keys]
    return [template % row for row in zip(*columns, strict=True)]


def grouped(texts: list[str], width: int, present: np.ndarray) -> Texts:
    """One JSON list per record: ``width`` consecutive ``texts`` where ``present``, [] elsewhere
    (``texts`` holds the present records' items only, in order)."""
    out, start = Texts(), 0
    for here in present.tolist():
        if here:
            out.append("[" + ", ".join(texts[start:start + width]) + "]")
            start += width
        else:
            out.append("[]")
    return out


def streamed_records(count: int, columns_of, documents_of, *, chunk: int = STREAM_CHUNK):
    """The ``count`` records of a long list, :data:`STREAM_CHUNK` at a time, for a
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
                fields[key] = grouped(record_texts(inner, int(present.sum()) * width), width, present)
            yield from map(JsonText, record_texts(fields, stop - start))
        except NotFinite:
            yield from documents_of(start, stop)
