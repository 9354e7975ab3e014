"""Writing results safely: atomic files, never over an input, deterministic JSON."""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path

from pampipe.errors import InputError, SolverError


def check_not_input(target: Path, inputs: Iterable[Path], *, option: str) -> None:
    """Refuse (exit 2) to write ``target`` if it is one of the command's input files."""
    target = Path(target)
    for source in inputs:
        source = Path(source)
        if target.exists() and source.exists() and os.path.samefile(target, source):
            raise InputError(f"{option} {target}: refusing to write over the input file {source}; "
                             "choose another output path.")
        if target.resolve() == source.resolve():
            raise InputError(f"{option} {target}: refusing to write over the input file {source}.")


def atomic_write(target: Path, write: Callable[[Path], None]) -> None:
    """Call ``write(tmp)`` on a temporary file beside ``target``, then rename it over ``target``.

    A crash or interrupt leaves either the old file or the new one, never half of one.
    """
    target = Path(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{target.parent}: cannot create the output folder ({exc.strerror}).") from None
    if target.is_dir():
        raise InputError(f"{target}: is a directory; give a file name for the output.")
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        write(tmp)
        os.replace(tmp, target)
    except OSError as exc:
        raise InputError(f"{target}: cannot write the output ({exc.strerror or exc}).") from None
    finally:
        if tmp.exists():
            tmp.unlink()


def atomic_write_text(target: Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``target`` atomically."""
    atomic_write(target, lambda tmp: tmp.write_text(text, encoding="utf-8"))


#: Significant digits of every float in JSON output: fixed, so that results are byte-identical across
#: thread counts (BLAS may reorder sums and change the last bits).
JSON_DIGITS = 12


def _clean(value, key: str = "result", timings: bool = True):
    """JSON-ready copy of ``value``; a NaN or infinite number is an error, never printed.

    With ``timings=False`` every ``*_time_s`` entry (a wall-clock measurement) is written as 0.
    """
    if isinstance(value, float):
        if not math.isfinite(value):
            raise SolverError(f"{key} came out as {value}: the computation left the model's valid "
                              "domain; please report the input that caused it", status="non_finite")
        return float(f"{value:.{JSON_DIGITS}g}")
    if isinstance(value, dict):
        return {str(k): 0.0 if not timings and str(k).endswith("_time_s")
                else _clean(v, f"{key}.{k}", timings) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v, f"{key}[{i}]", timings) for i, v in enumerate(value)]
    if hasattr(value, "item") and hasattr(value, "dtype"):  # numpy scalar
        return _clean(value.item(), key, timings)
    return value


def to_json(document: dict, *, timings: bool = True) -> str:
    """Deterministic JSON: sorted keys, 12-digit floats; NaN or inf raises SolverError (exit 3).

    ``timings=False`` writes wall-clock ``*_time_s`` entries as 0, for byte-identical output.
    """
    return json.dumps(_clean(document, timings=timings), sort_keys=True, indent=2, allow_nan=False) + "\n"
