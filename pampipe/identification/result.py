"""Frozen results of ``identify``: fitted moduli, fit quality, solver status, uncertainty, provenance."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from pampipe.identification.covariance import Uncertainty
from pampipe.identification.drucker import Minimum
from pampipe.identification.envelope import Predictions
from pampipe.identification.geometry import BlockedForce
from pampipe.identification.model_error import ModelError
from pampipe.identification.options import FitOptions
from pampipe.identification.predict import TestFit
from pampipe.identification.quality import Quality
from pampipe.model.pam import Geometry, Moduli, Pam
from pampipe.model.uncertainty import ParameterUncertainty
from pampipe.results import frame, notebook

if TYPE_CHECKING:  # the slip package loads only for slip tests, the calibration's search only to calibrate
    from pampipe.identification.multistart import Search
    from pampipe.slip.result import SlipResult

MPA = 1e6


@dataclass(frozen=True)
class SolverInfo:
    status: str  # IPOPT's return status, e.g. "Solve_Succeeded"
    success: bool
    iterations: int
    wall_time: float  # solve [s]
    build_time: float  # NLP build [s] (0 when taken from the cache)
    reduce_time: float  # data → sufficient statistics [s]
    objective: float  # IPOPT's scaled objective at the solution
    origin: str = "built"  # where the NLP came from: built here, or the on-disk cache ("disk")


@dataclass(frozen=True)
class Calibration:
    """The geometry of the fit: stated, fitted (= stated when nothing is calibrated), and the check."""

    stated: Geometry
    geometry: Geometry
    calibrated: tuple[str, ...]
    intervals: dict  # name -> (low, high) in deg (braid angle) or mm, None when undetermined
    stated_rmse: float | None  # RMSE of the fit at the stated geometry [N] (calibrated fits only)
    blocked_force: BlockedForce | None  # the blocked-force check of the fitted geometry
    stated_blocked_force: BlockedForce | None  # ... of the stated geometry
    blocked_force_skipped: str | None = None  # why the check could not run (None: it ran)
    search: Search | None = None  # the global calibration's starts and minima (:mod:`.multistart`)

    def as_document(self) -> dict:
        g = self.geometry
        intervals = {}
        for name, bounds in self.intervals.items():
            if bounds is None:
                continue
            if name == "braid_angle":
                intervals["braid_angle_from_axis_deg"] = list(bounds)
            else:
                intervals[f"{name}_m"] = [v * 1e-3 for v in bounds]
        doc = {"initial_length_m": g.initial_length, "braid_angle_from_axis_deg": math.degrees(g.braid_angle),
               "initial_diameter_m": g.initial_diameter, "bladder_thickness_m": g.bladder_thickness,
               "calibrated": list(self.calibrated), "intervals": intervals,
               "stated": {"initial_length_m": self.stated.initial_length,
                          "braid_angle_from_axis_deg": math.degrees(self.stated.braid_angle),
                          "bladder_thickness_m": self.stated.bladder_thickness},
               "stated_geometry_rmse_N": self.stated_rmse,
               "blocked_force_check": None if self.blocked_force is None
               else self.blocked_force.as_document(),
               "blocked_force_check_skipped": self.blocked_force_skipped,
               "multistart": None if self.search is None else self.search.as_document()}
        return doc


def _plot():
    from pampipe.views.plots.identify import plot_result

    return plot_result


def _text():
    from pampipe.views.identify_text import result_text

    return result_text


@notebook(headline=("success", "status", "sum_rmse_N"), plot=_plot, text=_text)
@dataclass(frozen=True)
class IdentifyResult:
    """The outcome of :func:`pampipe.identification.identify`.

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
    sum_rmse: float | None  # Σ over (test, pressure level) of the RMSE [N]; None without levels
    points: int
    solver: SolverInfo
    uncertainty: Uncertainty
    drucker_minimum: Minimum | None  # exact smallest Drucker quantity over the tested box (None: off)
    drucker_grid: dict = field(repr=False)  # {"pressures": [Pa], "lengths": [m], "form": str}
    warnings: tuple[str, ...]
    provenance: dict
    geometry: Geometry  # the fitted geometry (the stated one unless calibrated)
    calibration: Calibration
    predictions: Predictions
    slack_rows: tuple[int, ...] = ()  # per test
    excluded_rows: int = 0
    slip: SlipResult | None = None  # friction and load coupling from the slip tests (None: none)
    parameter_uncertainty: ParameterUncertainty | None = None  # what -o writes (identification.written)
    model_error: ModelError | None = None
    quality: Quality | None = None  # noise floor, structure, bounds (:mod:`.quality`)

    @property
    def drucker_margin(self) -> float:
        """Smallest Drucker quantity over the tested range [Pa] (≥ 0 when stable), NaN when off."""
        return float("nan") if self.drucker_minimum is None else self.drucker_minimum.value

    @property
    def verdict(self) -> str:
        """The report's first line: the fit against full scale and the noise floor, the model error, and
        which predictions the data determine (:func:`pampipe.identification.verdict.fit_verdict`)."""
        from pampipe.identification.verdict import fit_verdict

        return fit_verdict(self)

    @property
    def has_levels(self) -> bool:
        """True when every test has pressure levels (then ``sum_rmse`` is defined)."""
        return all(t.levels for t in self.tests)

    @property
    def rmse(self) -> float:
        """Root mean square residual over the rows fitted (every row but the excluded slack ones) [N]."""
        return float(np.sqrt(self.sse / max(self.points - self.excluded_rows, 1)))

    def theta_covariance(self) -> np.ndarray | None:
        """Covariance [Pa²] of the muscle's θ (the ``theta`` block), in :meth:`Moduli.as_vector` order."""
        index = [i for i, name in enumerate(self.names) if name.startswith("theta.")]
        if not index:
            return None
        return self.uncertainty.covariance[np.ix_(index, index)] * MPA**2

    def fitted_pam(self, base: Pam) -> Pam:
        """``base`` with the fitted moduli, their uncertainty, the (calibrated) geometry and the grip.

        The grip (``contact:``) comes from the slip tests, if any. The maker's limits and every stated sd
        of the geometry are kept, a calibrated entry's too: the fit's uncertainty of the tested muscle is
        in ``uncertainty``, while the stated sd is the lot's spread about it, which a ``unit: lot`` segment
        draws (docs/physics.md §15) and ``unit: tested`` does not.
        """
        grip = self.slip.grip() if self.slip is not None else None
        pam = Pam(base.name, self.geometry, self.moduli, grip=grip, geometry_sd=dict(base.geometry_sd),
                  max_pressure=base.max_pressure, max_contraction=base.max_contraction,
                  fitting_length=base.fitting_length)
        if self.parameter_uncertainty is None:
            return replace(pam, covariance=self.theta_covariance())
        return pam.with_uncertainty(self.parameter_uncertainty)

    def pam_comments(self, source) -> list[str]:
        """Header lines of the PAM file written from this fit: how it was fitted and how well."""
        u = self.uncertainty
        lines = [f"Written by `pampipe identify` from {source}",
                 f"mode {self.options.mode}, objective {self.options.objective}, "
                 f"degree {self.moduli.degree}; "
                 f"IPOPT {self.status} in {self.solver.iterations} iterations",
                 f"RMSE {self.rmse:.4g} N over {self.points} rows; "
                 + (f"sum of RMSE per (test, pressure) {self.sum_rmse:.4g} N; " if self.sum_rmse is not None
                    else "no pressure levels (sum of RMSE undefined); ")
                 + f"sigma {u.sigma:.4g} N",
                 f"identifiable parameter combinations: {u.rank} of {len(self.names)}"]
        if self.calibration.calibrated:
            stated = self.calibration.stated
            lines.append("geometry calibrated: " + ", ".join(self.calibration.calibrated)
                         + f" (stated: L0 = {stated.initial_length * 1e3:.6g} mm, braid angle "
                         f"{math.degrees(stated.braid_angle):.5g} deg from the axis)")
        if self.options.mode == "per_pipe":
            lines.append("per_pipe: these are the muscle's (axial-test) moduli; the per-pipe sets are in the "
                         "JSON output")
        return lines

    def curves(self, data):
        """The fitted curves, residuals and Drucker map over ``data`` (the experiment fitted) that the
        plots draw (:func:`pampipe.identification.curves.fit_curves`)."""
        from pampipe.identification.curves import fit_curves

        return fit_curves(data, self)

    def pam_for_pipe(self, base: Pam, pipe_diameter: float) -> Pam:
        """The muscle as used by the radial tests in ``pipe_diameter`` (per_pipe moduli if any)."""
        moduli = self.pipe_moduli.get(pipe_diameter, self.moduli)
        return Pam(base.name, self.geometry, moduli, None, fitting_length=base.fitting_length)

    def _drucker_document(self) -> dict:
        return _drucker_document(self)

    def to_dict(self) -> dict:
        """The `identify --json` document (docs/commands.md §3.2)."""
        return self.as_document()

    def coefficients(self):
        """A pandas DataFrame of the fitted moduli coefficients, one row each: ``coefficient``, ``block``,
        ``stress``, ``term``, ``power``, ``value_MPa``, ``std_MPa``, ``low_MPa``, ``high_MPa`` (the 95 %
        interval; None where the data leave it undetermined), ``determined``, ``at_bound``."""
        from pampipe.identification.frames import coefficient_rows

        return frame(coefficient_rows(self.to_dict()))

    def tests_frame(self):
        """A pandas DataFrame of the tests, one row each: ``test``, ``kind``, ``protocol``, ``points``,
        ``rmse_N``, ``slack_rows``, ``excluded_rows``, ``noise_floor_N``, ``rmse_over_floor``, ``runs_z``,
        ``lag1_autocorrelation``, ``structured``."""
        from pampipe.identification.frames import test_rows

        return frame(test_rows(self.to_dict()))

    def as_document(self) -> dict:
        """The ``identify`` JSON document (docs/commands.md §3.2), with extra keys.

        Undetermined quantities (intervals of unidentifiable coefficients, the Drucker margin
        with ``drucker: none``) are null.
        """
        u = self.uncertainty
        doc = {
            "verdict": self.verdict,
            "moduli": moduli_document(self.moduli),
            "fit": {
                "tests": [{"name": t.name, "kind": t.kind, "protocol": t.protocol, "rmse_N": t.rmse,
                           "points": t.points, "moduli": t.moduli_block, "slack_rows": t.slack,
                           "excluded_rows": t.excluded,
                           "levels": [{"pressure_Pa": lv.pressure, "points": lv.points, "rmse_N": lv.rmse}
                                      for lv in t.levels] if t.levels else None} for t in self.tests],
                "sum_rmse_N": self.sum_rmse,
                "sum_rmse_note": None if self.sum_rmse is not None else
                "undefined: test(s) " + ", ".join(t.name for t in self.tests if not t.levels)
                + " have no pressure levels (ramps)",
                "sse_N2": self.sse, "rmse_N": self.rmse,
                "points": self.points, "objective": self.options.objective, "mode": self.options.mode,
                "degree": self.options.degree, "average_legs": self.options.average_legs,
                "slack": self.options.slack, "slack_rows": int(sum(self.slack_rows)),
                "excluded_rows": self.excluded_rows,
                "prior": _prior_document(self.options),
                "quality": None if self.quality is None else self.quality.as_document(),
            },
            "geometry": self.calibration.as_document(),
            "predictions": self.predictions.as_document(),
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
                "model_error": None if self.model_error is None else self.model_error.as_document(),
                "written": None if self.parameter_uncertainty is None
                else self.parameter_uncertainty.as_document(),
            },
            "drucker": self._drucker_document(),
            "warnings": list(self.warnings),
            "provenance": self.provenance,
            "experiment": self.provenance.get("experiment"),
        }
        if self.slip is not None:
            doc["slip"] = self.slip.as_document()
        if self.options.mode == "per_pipe":
            doc["per_pipe"] = [{"pipe_diameter_m": d, "moduli": moduli_document(m)}
                               for d, m in sorted(self.pipe_moduli.items())]
        return doc


def _prior_document(options: FitOptions) -> dict | None:
    """How the fit was regularised: a ridge {sd, toward} or a Gaussian prior (where it came from)."""
    if options.prior_mean is not None:
        sd = np.sqrt(np.clip(np.diag(np.linalg.pinv(np.asarray(options.prior_precision))), 0, None))
        return {"kind": "gaussian", "source": options.prior_source, "mean_Pa": list(options.prior_mean),
                "sd_Pa": [float(v) if v > 0 else None for v in sd]}
    if options.prior_sd is not None:
        return {"kind": "ridge", "sd_Pa": options.prior_sd, "toward": options.prior_toward}
    return None


def _drucker_document(result) -> dict:
    m = result.drucker_minimum
    doc = {"form": result.drucker_grid["form"], "margin_Pa": _finite([result.drucker_margin])[0],
           "stable": None if m is None else m.stable,
           "checked": "exact minimum over the tested (P, L) box, between grid points too",
           "pressures_Pa": list(result.drucker_grid["pressures"]),
           "lengths_m": list(result.drucker_grid["lengths"])}
    if m is not None:
        doc["minimum"] = {"value_Pa": m.value, "pressure_Pa": m.pressure, "length_m": m.length,
                          "direction": m.direction}
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
