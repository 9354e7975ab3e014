"""Human-readable output: aligned text tables, and plot helpers (matplotlib imported lazily)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pampipe.io.files import atomic_write


def table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A plain aligned text table; floats are shown with 4 significant digits."""
    cells = [[_fmt(v) for v in row] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h)
              for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))
    rule = "  ".join("-" * w for w in widths)
    body = ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in cells]
    return "\n".join([line, rule, *body])


def _fmt(value: object) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) < 1e6 else f"{value:.4e}"
    return str(value)


def new_figure(*args, **kwargs):
    """A matplotlib figure on the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(*args, **kwargs)


def save_figure(fig, folder: Path, name: str) -> Path:
    """Save ``fig`` as ``folder/name`` (PNG) atomically, close it and return the path."""
    import matplotlib.pyplot as plt

    target = Path(folder) / name
    fig.tight_layout()
    atomic_write(target, lambda tmp: fig.savefig(tmp, format="png", dpi=120), create_folder=True)
    plt.close(fig)
    return target
