"""The ``units:`` line of a user file (docs/formats.md §1): whether its bare numbers are SI.

A bare non-zero number for a dimensioned quantity (``supply_pressure: 100``) is refused in a file, naming
the key, the value and the units it could mean, unless the file says ``units: SI`` at its top level: then
bare numbers are SI (m, Pa, N, kg, s, K), as in the files pampipe writes. A dict given to the Python API
reads bare numbers as SI, as the API's arguments do. Each file read follows its own line: a mission's PAM
files are read by theirs.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from pampipe.errors import InputError
from pampipe.io.yamlfile import load_mapping
from pampipe.units.quantities import bare_numbers, show

#: The top-level key, and the one value it takes.
KEY, SI = "units", "SI"


@contextmanager
def read_units(path: Path, raw: dict | None, *, what: str) -> Iterator:
    """The mapping in the file ``path`` (or ``raw``, its content given as a dict), without its ``units:``
    key; within the block a bare number is SI when the file says ``units: SI`` or came as a dict, and is
    refused otherwise."""
    content = load_mapping(path, what=what) if raw is None else raw
    si = raw is not None
    if isinstance(content, dict) and KEY in content:
        if content[KEY] != SI:
            raise InputError(f"{path}: {KEY}: must be {SI} (bare numbers in the file are then SI: m, Pa, N, "
                             f"kg, s, K), got {show(content[KEY])}; or remove it and write every value "
                             "with its unit.")
        si, content = True, {k: v for k, v in content.items() if k != KEY}
    with bare_numbers(si):
        yield content
