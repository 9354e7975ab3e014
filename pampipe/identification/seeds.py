"""Geometry seeds from the data: the braid angle α₀ and rest length L₀ that the force slopes give
(docs/physics.md §6.1), used as starts of the global calibration (:mod:`.multistart`).

At a held length L the muscle's tension is F_ax(P, L) = P·area(L) + bladder terms (Eq. 9), and with
pressure-independent moduli the bladder terms do not depend on P: the slope dF/dP at a length is
area(L), a function of the geometry alone. In the thin-wall (Gaylord) form

  area(L) = (3L² − B²)/(4πN²) = c₂L² − c₀,   c₂ = 3/(4πN²),  c₀ = B²/(4πN²),

linear in L², so slopes at two or more lengths fix c₂ and c₀ by (weighted) linear least squares, and

  B = √(3c₀/c₂)  (√3 × the ideal free-contraction length, where area = 0),
  N = √(3/(4πc₂)),  sin α₀ = πD₀N/B,  L₀ = B cos α₀.

The thick-wall area differs by the wall; the thin-wall values start a two-parameter least squares of
the slopes against the exact area of the muscle's wall (:func:`pampipe.model.forces.axial_levers`).
Slopes: the measured rows (force > 0) grouped by length (each held length, or equal-count length
bins), F = a + s·P + c·(L − L̄) fitted in each group that spans at least three pressures over 20 % of
the largest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from pampipe.model import forces
from pampipe.model.pam import Geometry

#: Length groups: distinct held lengths (rounded to 0.1 mm) if at most this many, else equal-count bins.
MAX_GROUPS = 40
#: Fewest rows in a group.
MIN_ROWS = 3


@dataclass(frozen=True)
class Slope:
    length: float  # mean length of the group [m]
    slope: float  # dF/dP [N/Pa]
    std: float  # its standard error [N/Pa]


@dataclass(frozen=True)
class Seed:
    """α₀ [rad] and L₀ [m] from the force slopes, and the slopes they come from."""

    braid_angle: float
    initial_length: float
    slopes: tuple[Slope, ...]

    def as_document(self) -> dict:
        return {"braid_angle_from_axis_deg": math.degrees(self.braid_angle),
                "initial_length_m": self.initial_length, "slopes": len(self.slopes),
                "lengths_m": [s.length for s in self.slopes]}


def slopes(data) -> list[Slope]:
    """dF/dP in every length group of the axial tests (see the module docstring)."""
    parts = [(t.pressure[t.force > 0], t.length[t.force > 0], t.force[t.force > 0])
             for t in data.tests if t.kind == "axial"]
    if not parts:
        return []
    pressure, length, force = (np.concatenate(p) for p in zip(*parts, strict=True))
    distinct = np.unique(np.round(length, 4))
    if distinct.size <= MAX_GROUPS:
        group = np.searchsorted(distinct, np.round(length, 4))
    else:
        edges = np.quantile(length, np.linspace(0, 1, MAX_GROUPS // 2 + 1)[1:-1])
        group = np.searchsorted(edges, length)
    top = float(np.max(np.abs(pressure))) if pressure.size else 0.0
    out = []
    for g in np.unique(group):
        rows = group == g
        p, ell, f = pressure[rows], length[rows], force[rows]
        if p.size < MIN_ROWS or np.unique(np.round(p / max(top, 1.0), 2)).size < 3 or np.ptp(p) < 0.2 * top:
            continue
        columns = [np.ones_like(p), p] + ([ell - ell.mean()] if np.ptp(ell) > 0 else [])
        design = np.column_stack(columns)
        coef, *_ = np.linalg.lstsq(design, f, rcond=None)
        residual = f - design @ coef
        dof = max(p.size - len(columns), 1)
        cov = float(residual @ residual) / dof * np.linalg.pinv(design.T @ design)
        out.append(Slope(float(ell.mean()), float(coef[1]), float(math.sqrt(max(cov[1, 1], 0.0)))))
    return out


def seed(data, geometry: Geometry, rest_range: tuple[float, float] | None = None) -> Seed | None:
    """α₀ and L₀ from the force slopes (None: fewer than two lengths with a slope, lengths spanning
    less than 2 % of L₀, or slopes that no braid explains). ``rest_range`` [m]: where L₀ may be
    (None: L₀ is the stated one, only α₀ is sought)."""
    found = slopes(data)
    if len(found) < 2:
        return None
    ell = np.array([s.length for s in found])
    if np.ptp(ell) < 0.02 * geometry.initial_length:
        return None
    s = np.array([s.slope for s in found])
    w = 1 / np.maximum(np.array([s.std for s in found]), 1e-3 * np.abs(s).max() + 1e-12)
    if geometry.wall == "thin" and rest_range is not None:
        start = _gaylord(geometry, ell, s, w)
    else:
        start = _grid(geometry, ell, s, w, rest_range)
    if start is None:
        return None
    alpha, rest = _refine(geometry, ell, s, w, *start, rest_range)
    if not math.radians(1) < alpha < math.radians(54):
        return None
    return Seed(alpha, rest, tuple(found))


def _gaylord(geometry: Geometry, ell, s, w) -> tuple[float, float] | None:
    """(α₀, L₀) of the thin-wall closed form of the module docstring."""
    (c2, c0), *_ = np.linalg.lstsq(np.column_stack([ell**2, -np.ones_like(ell)]) * w[:, None], s * w,
                                   rcond=None)
    if not (c2 > 0 and c0 > 0):
        return None
    braid = math.sqrt(3 * c0 / c2)
    sine = math.pi * geometry.initial_diameter * math.sqrt(3 / (4 * math.pi * c2)) / braid
    if not 0 < sine < 1:
        return None
    return math.asin(sine), braid * math.sqrt(1 - sine**2)


def _misfit(geometry: Geometry, ell, s, w, alpha: float, rest: float) -> np.ndarray | None:
    """Weighted slope residuals of the exact area at (α₀, L₀), None outside the braid's domain."""
    g = replace(geometry, braid_angle=alpha, initial_length=rest)
    if float(ell.max()) >= g.braid_length or float(ell.min()) <= g.shortest_length:
        return None
    with np.errstate(invalid="ignore"):
        area = np.array([float(forces.axial_levers(v, g)[0]) for v in ell])
    return (area - s) * w if np.all(np.isfinite(area)) else None


def _grid(geometry: Geometry, ell, s, w, rest_range) -> tuple[float, float] | None:
    """The best (α₀, L₀) of a grid: α₀ every 1° in [1°, 54°], L₀ at 11 points of its range."""
    rests = [geometry.initial_length] if rest_range is None else np.linspace(*rest_range, 11)
    best, where = math.inf, None
    for rest in rests:
        for alpha in np.radians(np.arange(1.0, 54.0, 1.0)):
            r = _misfit(geometry, ell, s, w, float(alpha), float(rest))
            if r is not None and float(r @ r) < best:
                best, where = float(r @ r), (float(alpha), float(rest))
    return where


def _refine(geometry: Geometry, ell, s, w, alpha, rest, rest_range) -> tuple[float, float]:
    """Least squares of the slopes against the exact area (of the muscle's wall) from (α₀, L₀)."""
    free_rest = rest_range is not None
    start = [alpha, rest] if free_rest else [alpha]

    def residual(z):
        r = _misfit(geometry, ell, s, w, z[0], z[1] if free_rest else geometry.initial_length)
        return np.full(ell.size, 1e6) if r is None else r

    if residual(start)[0] == 1e6:
        return alpha, rest if free_rest else geometry.initial_length
    lower = [math.radians(1)] + ([rest_range[0]] if free_rest else [])
    upper = [math.radians(54)] + ([rest_range[1]] if free_rest else [])
    start = np.clip(start, np.array(lower) + 1e-9, np.array(upper) - 1e-9)
    from scipy.optimize import least_squares  # here: importing it costs a plain identify 0.3 s

    fit = least_squares(residual, start, bounds=(lower, upper), max_nfev=100,
                        x_scale=[0.01] + ([0.01 * rest] if free_rest else []))
    if np.any(np.abs(fit.fun) >= 1e6):
        return alpha, rest if free_rest else geometry.initial_length
    return float(fit.x[0]), float(fit.x[1]) if free_rest else geometry.initial_length
