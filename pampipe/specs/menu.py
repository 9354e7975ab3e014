"""The tests a lab can run, each with its cost: the menu of `pampipe next-test` (docs/commands.md, next-test).

No I/O here: :func:`pampipe.io.menu_file.load_menu` reads the MENU file into a :class:`Menu`. Everything is SI
(m, N, Pa, s). A test is one of :data:`KINDS`:

* ``radial``: the muscle inflated inside a split pipe of bore ``pipe_diameter`` under ``axial_load``, the
  radial force F_r(P) recorded at each of ``pressures``;
* ``axial``: isobaric force-length cycles F_ax(P, L) at each of ``pressures``, L from the rest length to
  the free length at P;
* ``isometric``: the length held at ``length``, F_ax(P, length) at each of ``pressures``;
* ``slip``: ``trials`` slip trials in a pipe of bore ``pipe_diameter``, F_slip = μπF_r(P) at each pressure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

KINDS = ("radial", "axial", "isometric", "slip")
#: The protocol's pressure levels unless a test says otherwise: 69 kPa .. 689 kPa in 69 kPa steps [Pa].
DEFAULT_LEVELS = (69e3, 689e3, 69e3)


def pressure_levels(low: float, high: float, step: float) -> tuple[float, ...]:
    """``low .. high in step steps`` [Pa]: low + k·step for k = 0, 1, … while within half a step of ``high``,
    the last one ``high`` itself (69 .. 689 in 69: 69, 138, …, 621, 689 kPa, the paper's 10 psi steps)."""
    count = math.floor((high - low) / step + 0.5) + 1
    levels = [low + k * step for k in range(count)]
    levels[-1] = high if count > 1 else low
    return tuple(levels)


@dataclass(frozen=True)
class MenuTest:
    """One test of the menu (SI); the fields a kind does not use are None."""

    kind: str
    cost: float  # [s]
    pressures: tuple[float, ...]  # [Pa]
    pipe_diameter: float | None = None  # [m] radial, slip
    axial_load: float | None = None  # [N] radial, slip
    length: float | None = None  # [m] isometric
    trials: int | None = None  # slip
    entry: int = 0  # its index in the file's ``tests:``

    def describe(self) -> str:
        """A short label: ``radial 76.2 mm, 0 N``."""
        if self.kind in ("radial", "slip"):
            what = f"{self.kind} {self.pipe_diameter * 1e3:.4g} mm, {self.axial_load:.6g} N"
            return what + (f", {self.trials} trials" if self.kind == "slip" else "")
        if self.kind == "isometric":
            return f"isometric {self.length * 1e3:.4g} mm"
        return f"axial {min(self.pressures) / 1e3:.4g}..{max(self.pressures) / 1e3:.4g} kPa"

    def as_document(self) -> dict:
        """JSON form (interfaces §9.4): ``kind`` and the fields of that kind, SI with unit suffixes."""
        out: dict = {"kind": self.kind}
        if self.pipe_diameter is not None:
            out["pipe_diameter_m"] = self.pipe_diameter
        if self.axial_load is not None:
            out["axial_load_N"] = self.axial_load
        if self.length is not None:
            out["length_m"] = self.length
        if self.trials is not None:
            out["trials"] = self.trials
        out["pressures_Pa"] = list(self.pressures)
        return out


@dataclass(frozen=True)
class Menu:
    """The tests of a MENU file, in file order."""

    source: Path
    tests: tuple[MenuTest, ...]
