"""Frozen results of ``identify``: fitted moduli, fit quality, solver status, uncertainty, provenance."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pampipe.identify.options import FitOptions
from pampipe.identify.uncertainty import Uncertainty
from pampipe.model.pam import Moduli, Pam

MPA = 1e6


@dataclass(frozen=True)
class LevelFit:
    pressure: float  # level pressure [Pa]
    points: int
    rmse: float  # [N]


@dataclass(frozen=True)
class TestFit:
    """Fit quality of one test, from the exact (unsmoothed) model on every row."""

    name: str
    kind: str
    points: int
    rmse: float  # [N]
    levels: tuple[LevelFit, ...]
    moduli_block: str  # which fitted moduli the test used (theta, pipe<k>)


@dataclass(frozen=True)
class SolverInfo:
    status: str  # IPOPT's return status, e.g. "Solve_Succeeded"
    success: bool
    iterations: int
    wall_time: float  # solve [s]
    build_time: float  # NLP build [s] (0 when taken from the cache)
    reduce_time: float  # data → sufficient statistics [s]
    objective: float  # IPOPT's scaled objective at the solution


@dataclass(frozen=True)
class IdentifyResult:
    """The outcome of :func:`pampipe.identify.identify`.

    ``moduli`` is the muscle's moduli set (the one written to the PAM file); ``pipe_moduli`` maps
    each pipe diameter [m] to the moduli its radial tests used (``per_pipe`` mode: separate sets).
    ``x``/``names`` is the raw decision vector in MPa, ``uncertainty`` refers to it.
    """

    success: bool
    status: str
    options: FitOptions
    moduli: Moduli
    pipe_moduli: dict[float, Moduli]
    x: np.ndarray
    names: tuple[str, ...]
    tests: tuple[TestFit, ...]
    sse: float  # Σ residual² over all rows [N²]
    sum_rmse: float  # Σ over (test, pressure level) of the RMSE [N] (the paper's metric)
    points: int
    solver: SolverInfo
    uncertainty: Uncertainty
    drucker_margin: float  # smallest Drucker quantity on the grid [Pa] (≥ 0 when stable)
    drucker_grid: dict = field(repr=False)  # {"pressures": [Pa], "lengths": [m], "form": str}
    warnings: tuple[str, ...]
    provenance: dict

    @property
    def rmse(self) -> float:
        """Root mean square residual over every row [N]."""
        return float(np.sqrt(self.sse / max(self.points, 1)))

    def theta_covariance(self) -> np.ndarray | None:
        """Covariance [Pa²] of the muscle's θ (the ``theta`` block), in :meth:`Moduli.as_vector` order."""
        index = [i for i, name in enumerate(self.names) if name.startswith("theta.")]
        if not index:
            return None
        return self.uncertainty.covariance[np.ix_(index, index)] * MPA**2

    def fitted_pam(self, base: Pam) -> Pam:
        """``base`` with the fitted moduli and the θ covariance."""
        return Pam(base.name, base.geometry, self.moduli, self.theta_covariance())

    def pam_comments(self, source) -> list[str]:
        """Header lines of the PAM file written from this fit: how it was fitted and how well."""
        u = self.uncertainty
        lines = [f"Written by `pampipe identify` from {source}",
                 f"mode {self.options.mode}, objective {self.options.objective}, "
                 f"degree {self.moduli.degree}; "
                 f"IPOPT {self.status} in {self.solver.iterations} iterations",
                 f"RMSE {self.rmse:.4g} N over {self.points} rows; sum of RMSE per (test, pressure) "
                 f"{self.sum_rmse:.4g} N; sigma {u.sigma:.4g} N",
                 f"identifiable parameter combinations: {u.rank} of {len(self.names)}"]
        if self.options.mode == "per_pipe":
            lines.append("per_pipe: these are the muscle's (axial-test) moduli; the per-pipe sets are in the "
                         "JSON output")
        return lines

    def pam_for_pipe(self, base: Pam, pipe_diameter: float) -> Pam:
        """The muscle as used by the radial tests in ``pipe_diameter`` (per_pipe moduli if any)."""
        moduli = self.pipe_moduli.get(pipe_diameter, self.moduli)
        return Pam(base.name, base.geometry, moduli, None)

    def to_dict(self) -> dict:
        """The `identify --json` document (docs/commands.md §6)."""
        return self.as_document()

    def as_document(self) -> dict:
        """The ``identify`` JSON document (docs/commands.md §6), with extra keys.

        Undetermined quantities (intervals of unidentifiable coefficients, the Drucker margin
        with ``drucker: none``) are null.
        """
        u = self.uncertainty
        doc = {
            "moduli": moduli_document(self.moduli),
            "fit": {
                "tests": [{"name": t.name, "kind": t.kind, "rmse_N": t.rmse, "points": t.points,
                           "moduli": t.moduli_block,
                           "levels": [{"pressure_Pa": lv.pressure, "points": lv.points, "rmse_N": lv.rmse}
                                      for lv in t.levels]} for t in self.tests],
                "sum_rmse_N": self.sum_rmse, "sse_N2": self.sse, "rmse_N": self.rmse,
                "points": self.points, "objective": self.options.objective, "mode": self.options.mode,
                "degree": self.options.degree, "average_legs": self.options.average_legs,
            },
            "solver": {"status": self.solver.status, "success": self.solver.success,
                       "iterations": self.solver.iterations, "wall_time_s": self.solver.wall_time,
                       "build_wall_time_s": self.solver.build_time,
                       "reduce_wall_time_s": self.solver.reduce_time,
                       "objective": self.solver.objective},
            "uncertainty": {
                "unit": "MPa", "parameters": list(self.names), "values": self.x.tolist(),
                "sigma_N": u.sigma, "dof": u.dof, "rank": u.rank, "rank_deficient": u.rank_deficient,
                "std": _finite(u.std), "interval_95": [_finite([lo, hi]) for lo, hi in zip(u.lower, u.upper,
                                                                                            strict=True)],
                "at_bound": u.at_bound.tolist(), "determined": u.determined.tolist(),
                "correlation": [_finite(row) for row in u.correlation], "covariance": u.covariance.tolist(),
                "combinations": [{"weights_N_per_MPa": c.weights.tolist(), "value_N": c.value,
                                  "std_N": _finite([c.std])[0], "interval_95_N": _finite(c.interval),
                                  "singular_value": c.singular_value, "identifiable": c.identifiable}
                                 for c in u.combinations],
            },
            "drucker": {"form": self.drucker_grid["form"], "margin_Pa": _finite([self.drucker_margin])[0],
                        "pressures_Pa": list(self.drucker_grid["pressures"]),
                        "lengths_m": list(self.drucker_grid["lengths"])},
            "warnings": list(self.warnings),
            "provenance": self.provenance,
            "experiment": self.provenance.get("experiment"),
        }
        if self.options.mode == "per_pipe":
            doc["per_pipe"] = [{"pipe_diameter_m": d, "moduli": moduli_document(m)}
                               for d, m in sorted(self.pipe_moduli.items())]
        return doc


def _finite(values) -> list:
    """Numbers as a list, with NaN/inf (undetermined quantities) as None (JSON null)."""
    return [float(v) if np.isfinite(v) else None for v in values]


def moduli_document(moduli: Moduli, unit: float = MPA) -> dict:
    """The ``moduli`` mapping of the JSON document (coefficients in MPa)."""
    def law(a, b):
        return {"a": [v / unit for v in a], "b": [v / unit for v in b]}

    doc = {"unit": "MPa", "reference_pressure_Pa": moduli.reference_pressure,
           "axial": law(moduli.axial_a, moduli.axial_b), "hoop": law(moduli.hoop_a, moduli.hoop_b)}
    if moduli.contact is not None:
        c = np.asarray(moduli.contact) / unit
        k = moduli.degree + 1
        doc["contact"] = {"axial": {"a": c[:k].tolist(), "b": c[k:2 * k].tolist()},
                          "hoop": {"a": c[2 * k:3 * k].tolist(), "b": c[3 * k:].tolist()}}
    return doc
