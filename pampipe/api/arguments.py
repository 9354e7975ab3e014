"""The arguments of the Python API checked and converted as the command line converts its options: physical
values (unit strings, real numbers, pint quantities) to SI floats, whole numbers, flags, choices and names;
each refusal an :class:`~pampipe.errors.InputError` that names the argument and what it takes."""

from __future__ import annotations

import inspect
import math
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

from pampipe.errors import InputError
from pampipe.units.quantities import real_number, show, to_si

Source = str | os.PathLike | Mapping  # a file, or its content as a dict (or the loaded object itself)


def source_file(source: Source, kind: str, base, *, name: str | None = None) -> tuple[Path, dict | None]:
    """(path, raw): a path to read, or a stand-in path beside ``base`` for a dict's content; InputError
    naming the option ``name`` (else ``kind``) for anything else."""
    if isinstance(source, Mapping):
        return Path(base or Path.cwd()) / f"<{kind} dict>", dict(source)
    if not isinstance(source, str | os.PathLike):
        raise InputError(f"{name or kind}: {show(source)} is not allowed; give the path of a {kind} file or "
                         "its content as a dict.")
    return Path(source), None


def si(value, dimension: str, name: str):
    """SI float(s) of one value or a sequence of them (None stays None).

    A value is anything :func:`pampipe.units.quantities.to_si` reads: a unit string, any real number (int,
    float, Decimal, Fraction, numpy scalars and 0-d arrays) or a pint Quantity; a sequence is a list,
    a tuple or a 1-d array (numpy, or a pint Quantity of one).
    """
    if value is None:
        return None
    if isinstance(value, list | tuple) or getattr(value, "ndim", 0) == 1:
        if len(value) == 0:
            raise InputError(f"{name}: an empty list; give one value or a list of at least one.")
        return [to_si(v, dimension, where=f"{name}[{i}]") for i, v in enumerate(value)]
    return to_si(value, dimension, where=name)


def as_list(value) -> list:
    """``value`` as a list (a list or tuple itself, anything else the one item)."""
    return list(value) if isinstance(value, list | tuple) else [value]


def number(value, name: str, allowed: str) -> float:
    """A real number of any kind (:func:`pampipe.units.quantities.real_number`), else InputError naming
    ``name``."""
    found = real_number(value, where=name)
    if found is None:
        raise InputError(f"{name}: {show(value)} is not a number; {allowed}.")
    return found


def whole(value, name: str, *, least: int | None = None):
    """A whole number (None stays None): any real number with no fraction, at least ``least``."""
    if value is None:
        return None
    allowed = "give a whole number" + (f" of at least {least}" if least is not None else "")
    found = number(value, name, allowed)
    if not (math.isfinite(found) and found == int(found)) or (least is not None and found < least):
        raise InputError(f"{name}: {show(value)} is not allowed; {allowed}.")
    return int(found)


def flag(value, name: str) -> bool:
    """True or False (a numpy bool too), else InputError."""
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return bool(value)
    raise InputError(f"{name}: {show(value)} is not allowed; give True or False.")


def choice(value, name: str, allowed: Sequence[str], *, optional: bool = True):
    """One of ``allowed`` (None stays None where ``optional``), else InputError listing them."""
    if (value is None and optional) or (isinstance(value, str) and value in allowed):
        return value
    raise InputError(f"{name}: {show(value)} is not one of {', '.join(repr(a) for a in allowed)}.")


def probability(value, name: str = "confidence") -> float | None:
    """A confidence level C as a real number (None stays None; text is refused: '0.95' is not 0.95); its
    range [0.5, 1) is checked where it is used."""
    if value is None:
        return None
    if isinstance(value, str):
        raise InputError(f"{name}: {show(value)} is text; give a probability in [0.5, 1) as a number, e.g. "
                         "0.95.")
    return number(value, name, "give a probability in [0.5, 1), e.g. 0.95")


def names(value, name: str):
    """A list of strings from one string or a sequence of them (None stays None)."""
    if value is None or isinstance(value, str):
        return None if value is None else [value]
    if isinstance(value, list | tuple) and all(isinstance(v, str) for v in value):
        return list(value)
    raise InputError(f"{name}: {show(value)} is not allowed; give a name or a list of names.")


def path(value, name: str) -> Path | None:
    """A file or folder path (None stays None): a string or a path-like object."""
    if value is None:
        return None
    if isinstance(value, str | os.PathLike):
        return Path(value)
    raise InputError(f"{name}: {show(value)} is not allowed; give a path.")


def where(workers, scheduler) -> tuple[int | None, str | None]:
    """Checked ``workers`` (a whole number ≥ 1) and ``scheduler`` (an address) for
    :func:`pampipe.runtime.executors.executor`."""
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError(f"scheduler: {show(scheduler)} is not allowed; give an address such as "
                         "'tcp://host:8786'.")
    return whole(workers, "workers", least=1), scheduler


def objective(name: str, kind):
    """The member of the enum ``kind`` whose value is ``name``, else InputError listing them."""
    try:
        return kind(name)
    except ValueError:
        raise InputError(f"objective: {name!r} is not one of {', '.join(k.value for k in kind)}.") from None


def no_other(function: Callable, unexpected: Mapping) -> None:
    """A TypeError naming the first of ``unexpected`` keyword options and those ``function`` takes."""
    if unexpected:
        allowed = [p.name for p in inspect.signature(function).parameters.values()
                   if p.kind is inspect.Parameter.KEYWORD_ONLY]
        raise TypeError(f"pampipe.{function.__name__}() got an unexpected option {next(iter(unexpected))!r}; "
                        f"allowed: {', '.join(sorted(allowed))}")
