"""JSON text of long lists of records held column-wise: the same bytes as
``json.dumps(_clean(record), sort_keys=True)`` record by record (:mod:`pampipe.io.files`), built from the
distinct records only.

A long route's plan has 10⁵ section records of 3 segments each, about 7·10⁶ floats: walking them as dicts and
rounding each float in Python (``float(f"{x:.12g}")``) costs more than planning them. A long route also
repeats its sections (the 10⁵ of ``benchmarks/bench_big_mission.py`` hold 1,260 distinct ones). So a list
(:func:`streamed_records`) is written by a :class:`ListWriter` that, for each chunk of records, groups them
by their columns' bits (:func:`~pampipe.runtime.alike.grouped_columns`: one hash and one sort per chunk,
in numpy) and writes the text of each distinct record once for the whole list: its floats rounded to
:data:`~pampipe.io.files.JSON_DIGITS` significant digits in numpy (:func:`rounded`) and written with
``float.__repr__`` (what the C JSON encoder calls), by one ``%`` of a template whose keys are sorted as
``sort_keys`` sorts them. A chunk's records are then that text per record, joined :data:`JOINED` at a
time (one ``str.join`` each). A column of mostly distinct texts (the names) is left out of the grouping: its
value is put into each record's text as the texts are joined.

A column (a value of ``fields``) is one of:

* a 1-D numpy array of floats, bools or ints, one value per record;
* a 2-D numpy float array: one JSON list per record (its row);
* a :class:`Texts`: one JSON text per record, already encoded (a nested list, say);
* a :class:`~pampipe.runtime.alike.Picked`: a few str (or None) values, one picked per record by index;
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
from pampipe.runtime.alike import Picked, grouped_columns


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
    """The JSON texts of the floats ``values`` as the rounding writes them, each distinct value rounded and
    formatted once (``float.__repr__`` costs ~1 µs; a column of all-distinct records repeats its values),
    0.0 and -0.0 apart; :class:`NotFinite` if any is NaN or infinite."""
    values = np.asarray(values, dtype=float).ravel()
    if not np.isfinite(values).all():
        raise NotFinite
    distinct, index = np.unique(values, return_inverse=True)
    texts = list(map(float.__repr__, rounded(distinct).tolist()))
    index = index.ravel()
    zeros = np.flatnonzero(values == 0.0)  # 0.0 and -0.0 are one value to np.unique
    if zeros.size:
        index[zeros] = len(texts) + np.signbit(values[zeros])
        texts += ["0.0", "-0.0"]
    return np.array(texts, dtype=object)[index].tolist()


#: Stands in a record's text for the value of a column left out of the grouping (never in JSON text: the
#: encoder escapes control characters).
_SLOT = "\0"


def _plain_ascii(text: str) -> bool:
    """``text`` is written in JSON as it is, between quotes: printable ASCII (0x20-0x7e) without ``"`` or
    ``\\``, which :func:`~json.encoder.encode_basestring_ascii` leaves as they are."""
    return text.isascii() and text.isprintable() and '"' not in text and "\\" not in text


class _Lists:
    """A column of one JSON list of nested records per record: ``width`` consecutive records of the
    columns ``fields`` for each record where ``present``, [] elsewhere."""

    __slots__ = ("fields", "present", "width")

    def __init__(self, fields: dict, width: int, present: np.ndarray) -> None:
        self.fields, self.width, self.present = fields, width, np.asarray(present, dtype=bool)


class _Column:
    """One column of a chunk: ``bits`` (1-D uint64 arrays, one value per record each) that group its
    records, and ``texts(rows)`` the JSON text of its value in each of the records ``rows``; a free column
    (``bits`` None) holds each record's text in ``values`` and takes ``slot`` in the record's template."""

    __slots__ = ("bits", "kind", "slot", "texts", "values")

    def __init__(self, kind, bits, texts=None, *, values=None, slot="%s") -> None:
        self.kind, self.bits, self.texts, self.values, self.slot = kind, bits, texts, values, slot


class _Words:
    """An id for each distinct JSON text of the plain-value columns of one list, given once."""

    def __init__(self) -> None:
        self.texts: list[str] = []
        self._of_text: dict[str, int] = {}
        self._of_value: dict = {}  # str or None → the id of its text

    def of_texts(self, distinct) -> np.ndarray:
        """The ids of the JSON texts ``distinct``."""
        ids = []
        for text in distinct:
            i = self._of_text.get(text)
            if i is None:
                i = self._of_text[text] = len(self.texts)
                self.texts.append(text)
            ids.append(i)
        return np.array(ids, dtype=np.uint64)

    def of_values(self, distinct) -> np.ndarray:
        """The ids of the texts of the str or None values ``distinct``."""
        missing = [v for v in distinct if v not in self._of_value]
        for value, i in zip(missing, self.of_texts(_value_texts(missing)).tolist(), strict=True):
            self._of_value[value] = i
        return np.array([self._of_value[v] for v in distinct], dtype=np.uint64)

    def column(self, ids: np.ndarray) -> _Column:
        """The column of the texts ``ids`` (one per record)."""
        return _Column("words", [ids], _picked(self.texts, ids))


class ListWriter:
    """The records of one JSON list (or the nested ones of one key), given a chunk of columns at a time.

    Each distinct record (the bits of its values, the free columns aside) is formatted once for the whole
    list and given an id; ``texts[id]`` is its text, with :data:`_SLOT` where a free column's value goes.
    Where the records barely repeat (more than :data:`KEPT` texts held, nested ones included), every text is
    forgotten between two chunks (:meth:`forget`), so that the memory stays that of a few chunks.
    """

    def __init__(self, *, free: bool = True, words: _Words | None = None) -> None:
        self.free = free
        self.words = _Words() if words is None else words
        self._empty()

    def forget(self) -> None:
        """Drop every text held, of this writer, its nested ones and its words (between chunks only: the
        ids of the nested records and of the words are parts of this writer's records' bits)."""
        self.words = _Words()
        self._empty()

    def _empty(self) -> None:
        """Hold no text yet (the words aside)."""
        self.texts: list[str] = []
        self._known: dict[tuple, dict[bytes, int]] = {}  # per layout of the columns: a record's bits → id
        self._inner: dict[str, ListWriter] = {}
        self._parts: dict[int, np.ndarray] = {}  # of :meth:`parts`, by their width

    def held(self) -> int:
        """The texts held: this writer's, its nested writers' and the words."""
        writers, count = [self], len(self.words.texts)
        while writers:
            writer = writers.pop()
            count += len(writer.texts)
            writers.extend(writer._inner.values())
        return count

    def coded(self, fields: dict, count: int) -> tuple[np.ndarray, np.ndarray, list[_Column]]:
        """(the ids of the chunk's distinct records, each record's place among them, the free columns) of the
        ``count`` records whose values are the columns ``fields`` (key → column)."""
        keys = sorted(fields)
        columns = [self._column(key, fields[key], count) for key in keys]
        layout = tuple((key, c.kind, c.slot) for key, c in zip(keys, columns, strict=True))
        known = self._known.setdefault(layout, {})
        kept = [c for c in columns if c.bits is not None]
        bits = [b for c in kept for b in c.bits]
        if bits and count:
            first, index = grouped_columns(bits)
            distinct = np.stack([b[first] for b in bits], axis=1)
            marks = distinct.view(np.dtype((np.void, 8 * len(bits)))).ravel().tolist()
        else:  # every record the same
            first, index = np.zeros(min(count, 1), np.intp), np.zeros(count, np.intp)
            marks = [b""] * first.size
        ids = [known.get(mark) for mark in marks]
        new = [j for j, i in enumerate(ids) if i is None]
        if new:
            template = "{" + ", ".join(encode_basestring_ascii(key).replace("%", "%%") + ": " + c.slot
                                       for key, c in zip(keys, columns, strict=True)) + "}"
            values = [c.texts(first[new]) for c in kept]
            texts = ([template % row for row in zip(*values, strict=True)] if kept
                     else [template % ()] * len(new))
            for j, text in zip(new, texts, strict=True):
                ids[j] = known[marks[j]] = len(self.texts)
                self.texts.append(text)
        return np.array(ids, dtype=np.intp), index, [c for c in columns if c.bits is None]

    def parts(self, ids: np.ndarray, width: int) -> np.ndarray:
        """(ids, ``width``) texts: each record's text split at its free columns' places, ``", "`` after
        the last."""
        table = self._parts.get(width, np.empty((0, width), dtype=object))
        if table.shape[0] < len(self.texts):  # the texts' split written since: added
            added = np.empty((len(self.texts) - table.shape[0], width), dtype=object)
            for row, text in zip(added, self.texts[table.shape[0]:], strict=True):
                split = text.split(_SLOT)
                if len(split) == width:
                    row[:] = [*split[:-1], split[-1] + ", "]
            table = self._parts[width] = np.concatenate([table, added])
        return table[ids]

    def _ids(self, fields: dict, count: int) -> np.ndarray:
        """The id of each of ``count`` records (a writer without free columns)."""
        ids, index, _ = self.coded(fields, count)
        return ids[index].astype(np.uint64)

    def _nested(self, key: str) -> ListWriter:
        if key not in self._inner:
            self._inner[key] = ListWriter(free=False, words=self.words)
        return self._inner[key]

    def _column(self, key: str, column, count: int) -> _Column:
        if isinstance(column, _Lists):
            return self._lists_column(key, column, count)
        if isinstance(column, dict):
            inner = self._nested(key)
            ids = inner._ids(column, count)
            return _Column("object", [ids], _picked(inner.texts, ids))
        if isinstance(column, Picked):
            return self.words.column(self.words.of_values(column.values)[column.index])
        if isinstance(column, np.ndarray):
            return _array_column(column)
        if isinstance(column, Texts):
            return self._words_column("texts", column, self.words.of_texts, count, lambda texts: texts)
        if set(map(type, column)) <= {str, type(None)}:  # names, labels, reasons
            return self._words_column("words", column, self.words.of_values, count, _value_texts)
        return self._words_column("texts", [_plain_text(value) for value in column], self.words.of_texts,
                                  count, lambda texts: texts)

    def _words_column(self, kind: str, values: list, ids_of, count: int, texts_of) -> _Column:
        """A column of few distinct texts, grouped by their ids; one of mostly distinct ones (more than half
        the records) free: a text put into each record's text, in quotes by the template if it needs no
        escaping."""
        distinct = dict.fromkeys(values)
        if self.free and 2 * len(distinct) > count > 1:
            if kind == "words" and None not in distinct and _plain_ascii("".join(distinct)):
                return _Column(kind, None, values=values, slot=f'"{_SLOT}"')
            return _Column(kind, None, values=texts_of(values), slot=_SLOT)
        place = dict(zip(distinct, ids_of(distinct).tolist(), strict=True))
        return self.words.column(np.fromiter(map(place.__getitem__, values), np.uint64, count=len(values)))

    def _lists_column(self, key: str, column: _Lists, count: int) -> _Column:
        """The column of a nested list per record: its records' ids (``width`` columns), and whether
        present."""
        inner, width, present = self._nested(key), column.width, column.present
        table = np.zeros((width + 1, count), dtype=np.uint64)
        table[:width, present] = inner._ids(column.fields, int(present.sum()) * width).reshape(-1, width).T
        table[width] = present

        def texts(rows):
            return ["[" + ", ".join(map(inner.texts.__getitem__, row[:width])) + "]" if row[width] else "[]"
                    for row in table[:, rows].T.tolist()]

        return _Column(("lists", width), list(table), texts)


def _picked(texts: list[str], ids: np.ndarray):
    """``texts(rows)`` of a column whose records hold the texts ``ids``."""
    return lambda rows: list(map(texts.__getitem__, ids[rows].tolist()))


def _value_texts(values: list) -> list[str]:
    """The JSON text of each str or None value."""
    return ["null" if v is None else encode_basestring_ascii(v) for v in values]


def _array_column(column: np.ndarray) -> _Column:
    """A numpy column: its values' bits, and texts as the C encoder writes the rounded values."""
    if column.dtype == bool:
        return _Column("bool", [column.astype(np.uint64)],
                       lambda rows: ["true" if v else "false" for v in column[rows].tolist()])
    if column.dtype.kind in "iu":
        return _Column("int", [column.astype(np.int64).view(np.uint64)],
                       lambda rows: list(map(int.__repr__, column[rows].tolist())))
    values = np.ascontiguousarray(column, dtype=float)
    if values.ndim == 2:
        width = values.shape[1]

        def lists(rows):
            texts = float_texts(values[rows])
            return ["[" + ", ".join(texts[k:k + width]) + "]" for k in range(0, len(texts), width)]

        return _Column(("floats", width), list(np.ascontiguousarray(values.T).view(np.uint64)), lists)
    return _Column("float", [values.view(np.uint64)], lambda rows: float_texts(values[rows]))


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


def record_pieces(writer: ListWriter, fields: dict, count: int) -> np.ndarray:
    """(records, 2·free + 1) texts whose concatenation row by row is each record's text followed by
    ``", "``: its distinct record's text split at the free columns' places, their values between."""
    ids, index, free = writer.coded(fields, count)
    pieces = np.empty((count, 2 * len(free) + 1), dtype=object)
    pieces[:, 0::2] = writer.parts(ids, len(free) + 1)[index]
    for k, column in enumerate(free):
        pieces[:, 2 * k + 1] = column.values
    return pieces


#: Texts a :class:`ListWriter` holds at most from one chunk to the next (a repeating route holds a few
#: thousand; one whose sections all differ would hold every record's text).
KEPT = 1 << 14

#: Records per text of :func:`joined_records`.
JOINED = 512


def joined_records(pieces: np.ndarray, *, part: int = JOINED):
    """The records of :func:`record_pieces` joined by ``", "``, :class:`~pampipe.io.files.JsonText` s of at
    most ``part`` records each (a few megabytes: the memory a text is built in is reused for the next)."""
    for start in range(0, pieces.shape[0], part):
        block = pieces[start:start + part]
        texts = block.ravel().tolist()
        texts[-1] = texts[-1][:-2]  # without the last separator
        yield JsonText("".join(texts), block.shape[0])


#: Records per pass of :func:`streamed_records`.
COLUMN_CHUNK = 1 << 14


def streamed_records(count: int, columns_of, documents_of, *, chunk: int = COLUMN_CHUNK, part: int = JOINED):
    """The ``count`` records of a long list, ``chunk`` at a time, for a
    :class:`~pampipe.io.files.Streamed` list: :class:`~pampipe.io.files.JsonText` items encoded from
    ``columns_of(start, stop)`` = (fields, {key: (the nested records' fields, records per record,
    present)}); where that gives None or a float to write is not finite, the records
    ``documents_of(start, stop)`` as dicts (whose encoding then names the key path of the bad value)."""
    writer = ListWriter()
    for start in range(0, count, chunk):
        stop = min(start + chunk, count)
        columns = columns_of(start, stop)
        try:
            if columns is None:
                raise NotFinite
            fields, nested = columns
            fields = {**fields, **{key: _Lists(*value) for key, value in nested.items()}}
            pieces = record_pieces(writer, fields, stop - start)
        except NotFinite:
            yield from documents_of(start, stop)
        else:
            yield from joined_records(pieces, part=part)
        if writer.held() > KEPT:
            writer.forget()
