"""What a run may allocate: work whose arrays would not fit in the available memory is refused before it
starts, with the figure, rather than failing part way with a MemoryError (a CSV of too many rows, a
``--confidence`` plan of too many draws)."""

from __future__ import annotations

import os

from pampipe.errors import InputError


def available_memory() -> int | None:
    """Physical memory available now [B] (``SC_AVPHYS_PAGES``), None where the OS does not say."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_fits(need: float, *, what: str, advice: str) -> None:
    """InputError when ``need`` bytes exceed the available memory: "``what`` would need X GB of memory and
    Y GB are available; ``advice``." Skipped where the OS does not say how much is available."""
    available = available_memory()
    if available is not None and need > available:
        raise InputError(f"{what} would need {_gigabytes(need)} GB of memory and {_gigabytes(available)} GB "
                         f"are available; {advice}.")


def _gigabytes(size: float) -> str:
    """``size`` [B] in GB for a message: 3 significant digits, whole GB from 1000 GB on."""
    value = size / 2**30
    return f"{value:.3g}" if value < 1000 else f"{value:,.0f}"
