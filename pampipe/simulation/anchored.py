"""Forward simulation of one muscle anchored in pipes (docs/physics.md §5-§7): `simulate`'s core."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.model.domain import check_pipe_diameter, check_pressure
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.results import notebook
from pampipe.simulation.open_directions import open_directions, open_warning

#: The paper's test pressures, 69…689 kPa in 69 kPa steps (10 psi steps).
PAPER_PRESSURES = tuple(68947.57 * k for k in range(1, 11))
#: Points of the curves drawn by the plots.
CURVE_POINTS = 300


@dataclass(frozen=True)
class AnchoredCase:
    """One muscle in one pipe under one axial load, evaluated at several pressures (SI)."""

    pipe_diameter: float
    axial_load: float
    anchored_length: float
    amplification_factor: float
    anchoring_pressure: float
    pressures: np.ndarray
    radial_force: np.ndarray
    force_per_length: np.ndarray
    contact_pressure: np.ndarray
    free_length: np.ndarray  # length of the muscle at each pressure (L_p once anchored)
    terms: dict[str, np.ndarray]  # Eq. 14 breakdown, before the contact clip

    @property
    def anchored(self) -> np.ndarray:
        return self.pressures > self.anchoring_pressure

    def as_document(self) -> dict:
        """The `simulate` JSON document of docs/commands.md §2.2 for this case."""
        points = []
        for i, p in enumerate(self.pressures):
            points.append({
                "pressure_Pa": float(p),
                "radial_force_N": float(self.radial_force[i]),
                "radial_force_per_length_N_per_m": float(self.force_per_length[i]),
                "contact_pressure_Pa": float(self.contact_pressure[i]),
                "total_normal_force_N": float(np.pi * self.radial_force[i]),
                "anchored": bool(self.anchored[i]),
                "length_m": float(self.free_length[i]),
                "eq14_terms_N": {k: float(v[i]) for k, v in self.terms.items()},
            })
        return {"pipe_diameter_m": self.pipe_diameter, "axial_load_N": self.axial_load,
                "anchored_length_m": self.anchored_length,
                "amplification_factor": self.amplification_factor,
                "anchoring_pressure_Pa": self.anchoring_pressure, "points": points}


@dataclass(frozen=True)
class Curves:
    """What the plots draw, computed by the same muscle as the cases (SI)."""

    pressure: np.ndarray  # grid [Pa]
    radial_force: tuple[np.ndarray, ...]  # per case, on the grid [N]
    free_length: dict[float, np.ndarray]  # per axial load [N], on the grid [m]
    diameter: np.ndarray  # D₀ … 0.98·D(B/√3) [m]
    amplification_factor: np.ndarray  # A(D) on that grid [-]


def _plot():
    from pampipe.views.plots.simulate import plot_simulation

    return plot_simulation


def _text():
    from pampipe.views.simulate_text import result_text

    return result_text


@notebook(headline=("pam", "pipe_diameter_m", "axial_load_N", "anchoring_pressure_Pa"), plot=_plot,
          text=_text)
@dataclass(frozen=True)
class SimulateResult:
    """One muscle in one or more pipes and under one or more loads; ``undetermined``: the directions its
    PAM's fit leaves open (:mod:`.open_directions`), ``warnings`` what to read before trusting the forces."""

    pam: str
    cases: tuple[AnchoredCase, ...]
    curves: Curves
    undetermined: tuple[dict, ...] = ()
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """The `simulate` JSON document: the first case's keys, ``pam``, ``cases`` when several, and
        ``undetermined`` when the PAM's fit leaves directions open."""
        document = dict(self.cases[0].as_document())
        document["pam"] = self.pam
        if len(self.cases) > 1:
            document["cases"] = [c.as_document() for c in self.cases]
        if self.undetermined:
            document["undetermined"] = list(self.undetermined)
        return document


def simulate_anchored(muscle: Muscle, *, pipe_diameter: float, axial_load: float = 0.0,
                      pressures=PAPER_PRESSURES, paper_literal: bool = False) -> AnchoredCase:
    """Anchoring pressure, anchored length, A, and F_r, f_r, p_c at each pressure (docs/physics.md §5)."""
    check_pipe_diameter(muscle.geometry, pipe_diameter)
    pressures = np.asarray(pressures, dtype=float)
    check_pressure(pressures)
    length = float(muscle.anchored_length(pipe_diameter))
    anchoring = float(muscle.anchoring_pressure(pipe_diameter, axial_load))
    radial = np.asarray(muscle.radial_force(pressures, pipe_diameter, axial_load), dtype=float)
    radial = radial * np.ones_like(pressures)
    lengths = np.maximum(muscle.free_length(pressures, axial_load=axial_load, braid_limit=True), length)
    terms = {k: np.asarray(v, dtype=float) * np.ones_like(pressures)
             for k, v in muscle.radial_force_terms(pressures, pipe_diameter, axial_load).items()}
    return AnchoredCase(
        pipe_diameter=float(pipe_diameter), axial_load=float(axial_load), anchored_length=length,
        amplification_factor=float(muscle.amplification_factor(pipe_diameter)),
        anchoring_pressure=anchoring, pressures=pressures, radial_force=radial,
        force_per_length=radial / length,
        contact_pressure=muscle.contact_pressure(radial, pipe_diameter, paper_literal=paper_literal),
        free_length=lengths, terms=terms)


def simulate(pam: Pam, *, pipe_diameters, axial_loads=(0.0,), pressures=PAPER_PRESSURES,
             paper_literal: bool = False) -> SimulateResult:
    """Every (pipe, load) case of one muscle, and the curves its plots draw."""
    muscle = Muscle.from_pam(pam)
    cases = tuple(simulate_anchored(muscle, pipe_diameter=d, axial_load=f, pressures=pressures,
                                    paper_literal=paper_literal)
                  for d in pipe_diameters for f in axial_loads)
    top = max(max(c.pressures.max() for c in cases),
              1.2 * max(c.anchoring_pressure for c in cases if np.isfinite(c.anchoring_pressure)))
    grid = np.linspace(0.0, top, CURVE_POINTS)
    g = muscle.geometry
    diameters = np.linspace(g.initial_diameter, 0.98 * g.largest_diameter, CURVE_POINTS)
    radial = tuple(np.asarray(muscle.radial_force(grid, c.pipe_diameter, c.axial_load), dtype=float)
                   * np.ones_like(grid) for c in cases)
    curves = Curves(grid, radial,
                    {load: muscle.free_length(grid, axial_load=load, braid_limit=True)
                     for load in sorted(set(axial_loads))},
                    diameters, np.asarray(muscle.amplification_factor(diameters), dtype=float))
    warning = open_warning(pam, "these forces")
    return SimulateResult(pam.name, cases, curves, open_directions(pam),
                          () if warning is None else (warning,))


@dataclass(frozen=True)
class ExtensionResult:
    """An extensile muscle's free length against pressure at zero axial load (docs/physics.md §14.4), SI.

    ``limit`` is B/√3, where the braid stops extending; ``diameter`` D(L) at each free length;
    ``undetermined`` and ``warnings`` as in :class:`SimulateResult` (the lengths rest on the same moduli).
    """

    pam: str
    initial_length: float  # [m] L₀
    limit: float  # [m] B/√3
    pressures: np.ndarray  # [Pa]
    free_length: np.ndarray  # [m]
    diameter: np.ndarray  # [m]
    curve_pressure: np.ndarray  # [Pa] for the plot
    curve_length: np.ndarray  # [m]
    undetermined: tuple[dict, ...] = ()
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        """The `simulate --json` document of an extensile PAM, with ``undetermined`` when the PAM's fit
        leaves directions open."""
        l0 = self.initial_length
        document = {"pam": self.pam, "kind": "extensile", "initial_length_m": l0,
                "braid_limit_length_m": self.limit,
                "points": [{"pressure_Pa": float(p), "free_length_m": float(length),
                            "extension": float(length / l0 - 1), "diameter_m": float(d)}
                           for p, length, d in zip(self.pressures, self.free_length, self.diameter,
                                                   strict=True)]}
        if self.undetermined:
            document["undetermined"] = list(self.undetermined)
        return document


def extension(pam: Pam, *, pressures) -> ExtensionResult:
    """Free length L(P) of an extensile muscle at zero axial load, at ``pressures`` [Pa] and on a curve."""
    from pampipe.model.braid import diameter_at_length

    pressures = np.asarray(pressures, dtype=float)
    check_pressure(pressures)
    muscle = Muscle.from_pam(pam)
    g = pam.geometry
    lengths = muscle.free_length(pressures)
    grid = np.linspace(0.0, max(float(pressures.max()), 1.0), CURVE_POINTS)
    warning = open_warning(pam, "these lengths")
    return ExtensionResult(pam.name, g.initial_length, g.shortest_length, pressures, lengths,
                           diameter_at_length(lengths, g), grid, muscle.free_length(grid),
                           open_directions(pam), () if warning is None else (warning,))
