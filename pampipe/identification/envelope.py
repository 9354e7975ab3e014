"""Which predictions the fit determines, and which are extrapolations (a decision-ready verdict).

The coefficient-level view ("8 of 16 combinations identifiable") does not say whether a number a
user needs is known. This module answers for the numbers themselves:

* the **envelope** of the data: the cells of a :data:`CELLS` × :data:`CELLS` grid over the tested
  (P, L) range of the axial tests that hold measured rows;
* the axial force F_ax(P, L) grouped into regions: at the tested points themselves (a subsample of
  the measured rows), at the centres of the cells of the tested ranges that hold no data (e.g. the
  slack corner, or between held lengths: interpolation) and above the largest tested pressure (up
  to :data:`ABOVE` × P_max: extrapolation);
* at every pipe diameter of interest (the radial tests' and ``fit.pipe_diameters``): the
  anchoring pressure and the radial force at the largest tested pressure, with a flag saying
  whether the anchored length L(D_p) lies inside the envelope above the anchoring pressure (or the
  pipe was tested).

Each prediction y(x) gets its 95 % half-width 1.96·√(gᵀ Cov g), g = ∂y/∂x by central differences
(exact up to round-off for the moduli, in which F_ax is linear), and is *determined* when its
sensitivity lies in the identifiable combinations: ‖V_uᵀg̃‖ ≤ :data:`DETERMINED`·‖g̃‖
(:meth:`pampipe.identification.covariance.Uncertainty.undetermined_share`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.identification import problem
from pampipe.identification.fit_nlp import Structure
from pampipe.model import braid

#: Grid cells per axis over the tested (P, L) range.
CELLS = 12
#: Tested points (a uniform subsample of the measured rows) at which the inside is judged.
INSIDE_POINTS = 200
#: Pressures above the tested range are judged up to this multiple of the largest tested pressure.
ABOVE = 1.25
#: A prediction is determined when at most this share of its sensitivity is unidentifiable.
DETERMINED = 1e-2
Z95 = 1.959963984540054


@dataclass(frozen=True)
class Region:
    """Axial-force predictions in one region of the (P, L) plane."""

    name: str
    pressure: tuple[float, float]  # [Pa]
    length: tuple[float, float]  # [m]
    points: int
    half_width: float  # largest 95 % half-width over the region [N]
    determined: bool  # every prediction in the region

    def as_document(self) -> dict:
        return {"region": self.name, "pressure_range_Pa": list(self.pressure),
                "length_range_m": list(self.length), "points": self.points,
                "half_width_95_N": self.half_width, "determined": self.determined}


@dataclass(frozen=True)
class PipePrediction:
    pipe_diameter: float  # [m]
    anchored_length: float  # [m]
    tested: bool  # a radial test in this pipe
    inside: bool  # tested, or L(D_p) inside the axial envelope above anchoring
    anchoring_pressure: float  # [Pa]
    anchoring_half_width: float  # [Pa]
    pressure: float  # where the radial force is given [Pa]
    radial_force: float  # [N]
    radial_half_width: float  # [N]
    determined: bool

    def as_document(self) -> dict:
        return {"pipe_diameter_m": self.pipe_diameter, "anchored_length_m": self.anchored_length,
                "tested": self.tested, "inside_envelope": self.inside,
                "anchoring_pressure_Pa": self.anchoring_pressure,
                "anchoring_pressure_half_width_95_Pa": self.anchoring_half_width,
                "pressure_Pa": self.pressure, "radial_force_N": self.radial_force,
                "radial_force_half_width_95_N": self.radial_half_width, "determined": self.determined}


@dataclass(frozen=True)
class Predictions:
    pressure: tuple[float, float] | None  # tested axial range [Pa]
    length: tuple[float, float] | None  # [m]
    regions: tuple[Region, ...]
    pipes: tuple[PipePrediction, ...]

    def as_document(self) -> dict:
        return {"envelope": None if self.pressure is None else
                {"pressure_range_Pa": list(self.pressure), "length_range_m": list(self.length),
                 "grid_cells": CELLS},
                "regions": [r.as_document() for r in self.regions],
                "pipes": [p.as_document() for p in self.pipes]}


def predictions(data, structure: Structure, x, uncertainty, geometry, stated, options, stats) -> Predictions:
    """The verdict of the module docstring for the solution ``x``."""
    def muscles(xv):
        return problem.muscles_of(structure, stats, stated, xv)

    def judged(function):
        """(value, 95 % half-width, determined) of a vector-valued prediction function of x."""
        value = np.asarray(function(x), float)
        grads = np.zeros((x.size, value.size))
        for j in range(x.size):
            h = 1e-5 * max(1.0, abs(x[j]))
            up, down = x.copy(), x.copy()
            up[j] += h
            down[j] -= h
            grads[j] = (np.asarray(function(up), float) - np.asarray(function(down), float)) / (2 * h)
        var = np.einsum("ik,ij,jk->k", grads, uncertainty.covariance, grads)
        share = np.array([uncertainty.undetermined_share(grads[:, k]) for k in range(value.size)])
        return value, Z95 * np.sqrt(np.clip(var, 0, None)), share <= DETERMINED

    axial = [t for t in data.tests if t.kind == "axial"]
    regions, occupied, p_edges, l_edges = (), None, None, None
    if axial:
        pressure = np.concatenate([t.pressure[t.force > 0] for t in axial])
        length = np.concatenate([t.length[t.force > 0] for t in axial])
        p_edges = np.linspace(pressure.min(), pressure.max(), CELLS + 1)
        l_edges = np.linspace(length.min(), length.max(), CELLS + 1)
        occupied = np.zeros((CELLS, CELLS), dtype=bool)
        occupied[_bin(pressure, p_edges), _bin(length, l_edges)] = True
        every = np.linspace(0, pressure.size - 1, min(pressure.size, INSIDE_POINTS)).astype(int)
        regions = _regions(judged, muscles, occupied, p_edges, l_edges, pressure[every], length[every])
    pipes = _pipes(data, options, judged, muscles, geometry, occupied, p_edges, l_edges)
    return Predictions(None if p_edges is None else (float(p_edges[0]), float(p_edges[-1])),
                       None if l_edges is None else (float(l_edges[0]), float(l_edges[-1])), regions, pipes)


def _bin(values, edges) -> np.ndarray:
    """Index of the grid cell of every value (the last edge belongs to the last cell)."""
    span = max(edges[-1] - edges[0], 1e-300)
    return np.minimum(((values - edges[0]) / span * (edges.size - 1)).astype(np.int64), edges.size - 2)


def _regions(judged, muscles, occupied, p_edges, l_edges, tested_p, tested_l) -> tuple[Region, ...]:
    pc, lc = 0.5 * (p_edges[1:] + p_edges[:-1]), 0.5 * (l_edges[1:] + l_edges[:-1])
    pp, ll = np.meshgrid(pc, lc, indexing="ij")
    above = np.linspace(p_edges[-1], ABOVE * p_edges[-1], 4)[1:]
    ap, al = np.meshgrid(above, lc[occupied[-1]] if occupied[-1].any() else lc, indexing="ij")
    sets = [("at the tested (P, L) points", tested_p, tested_l),
            ("in the tested ranges, untested", pp[~occupied], ll[~occupied]),
            (f"above the tested pressures (to {ABOVE:g} x)", ap.ravel(), al.ravel())]
    out = []
    for name, p, length in sets:
        if p.size == 0:
            continue
        _, half, determined = judged(lambda xv, p=p, length=length: muscles(xv)[0].axial_force(p, length))
        out.append(Region(name, (float(p.min()), float(p.max())), (float(length.min()), float(length.max())),
                          int(p.size), float(half.max()), bool(determined.all())))
    return tuple(out)


def _pipes(data, options, judged, muscles, geometry, occupied, p_edges, l_edges
           ) -> tuple[PipePrediction, ...]:
    tested = {t.spec.pipe_diameter for t in data.tests if t.kind == "radial"}
    diameters = sorted(tested | set(options.pipe_diameters))
    top = max(float(t.pressure.max()) for t in data.tests)
    out = []
    for d in diameters:
        if not geometry.initial_diameter < d < geometry.largest_diameter:
            continue

        def muscle(xv, d=d):
            main, pipes = muscles(xv)
            return pipes.get(d, main)

        anchoring, a_half, a_ok = judged(lambda xv, d=d: [muscle(xv).anchoring_pressure(d)])
        force, f_half, f_ok = judged(lambda xv, d=d: [muscle(xv).radial_force(top, d)])
        length = float(braid.length_at_diameter(d, geometry))
        inside = d in tested or _inside(occupied, p_edges, l_edges, float(anchoring[0]), top, length)
        out.append(PipePrediction(d, length, d in tested, inside, float(anchoring[0]), float(a_half[0]), top,
                                  float(force[0]), float(f_half[0]), bool(a_ok[0] and f_ok[0])))
    return tuple(out)


def _inside(occupied, p_edges, l_edges, low, high, length) -> bool:
    """L(D_p) inside the envelope for most cells between the anchoring and the largest pressure."""
    if occupied is None or not l_edges[0] <= length <= l_edges[-1]:
        return False
    column = min(int(np.searchsorted(l_edges, length, side="right")) - 1, occupied.shape[1] - 1)
    rows = [k for k in range(occupied.shape[0]) if p_edges[k + 1] >= low and p_edges[k] <= high]
    return bool(rows) and float(np.mean(occupied[rows, column])) >= 0.5
