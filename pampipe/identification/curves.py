"""What the `identify` plots draw, computed once from the fitted muscle (the plots only draw).

* the fitted F_ax(L) at every pressure level of every isobaric test, F_ax(P) at every held length of
  every isometric test (both with the fitted geometry; slack rows are drawn as max(0, F));
* the fitted F_r(P) of every radial test (its pipe's moduli in ``per_pipe`` mode);
* the residual (model − measured) of every row;
* the Drucker margin min(E₁ᵗ, E₂ᵗ) on a fine (P, L) map over the constraint grid's range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.identification.predict import predict
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam

CURVE_POINTS = 300
DRUCKER_MAP = (80, 120)  # pressures × lengths


@dataclass(frozen=True)
class AxialCurve:
    test: str
    level: int
    pressure: float  # [Pa]
    length: np.ndarray  # [m]
    force: np.ndarray  # [N]


@dataclass(frozen=True)
class IsometricCurve:
    test: str
    held: int
    length: float  # [m]
    pressure: np.ndarray  # [Pa]
    force: np.ndarray  # [N]


@dataclass(frozen=True)
class RadialCurve:
    test: str
    pressure: np.ndarray  # [Pa]
    force: np.ndarray  # [N]


@dataclass(frozen=True)
class DruckerMap:
    pressure: np.ndarray  # (n_p,) [Pa]
    length: np.ndarray  # (n_l,) [m]
    margin: np.ndarray  # (n_p, n_l) min(E₁ᵗ, E₂ᵗ) [Pa]
    minimum: object  # the exact minimum of the result (drawn as a marker, named in the title)


@dataclass(frozen=True)
class FitCurves:
    axial: tuple[AxialCurve, ...]
    isometric: tuple[IsometricCurve, ...]
    radial: tuple[RadialCurve, ...]
    residuals: dict[str, np.ndarray]  # per test, row by row [N] (NaN for excluded slack rows)
    drucker: DruckerMap | None


def fit_curves(data, result) -> FitCurves:
    """The curves of ``result`` (an :class:`IdentifyResult`) over the data of ``data``."""
    base = data.pam
    fitted = Muscle(result.geometry, result.moduli.as_vector(), result.moduli.reference_pressure)
    axial, isometric, radial, residuals = [], [], [], {}
    for test in data.tests:
        pam = result.pam_for_pipe(base, test.spec.pipe_diameter) if test.kind == "radial" else \
            Pam(base.name, result.geometry, result.moduli)
        model = predict(pam, test)
        if test.kind == "axial":
            slack = test.slack
            model = np.where(slack, np.maximum(model, 0.0), model)
            if result.options.slack == "exclude":
                model = np.where(slack, np.nan, model)
        residuals[test.name] = model - test.force
        if test.kind == "axial" and test.protocol == "isometric":
            for held, length in enumerate(test.level_length):
                mine = test.held_length == held
                grid = np.linspace(test.pressure[mine].min(), test.pressure[mine].max(), 100)
                force = np.maximum(np.asarray(fitted.axial_force(grid, length), float), 0.0)
                isometric.append(IsometricCurve(test.name, held, float(length), grid, force))
        elif test.kind == "axial":
            for lev, pressure in enumerate(test.level_pressure):
                mine = test.level == lev
                if not mine.any():
                    continue
                lengths = np.linspace(test.length[mine].min(), test.length[mine].max(), 100)
                axial.append(AxialCurve(test.name, lev, float(pressure), lengths,
                                        np.asarray(fitted.axial_force(pressure, lengths), dtype=float)))
        else:
            grid = np.linspace(min(0.0, test.pressure.min()), test.pressure.max(), CURVE_POINTS)
            force = Muscle.from_pam(pam).radial_force(grid, test.spec.pipe_diameter, test.spec.axial_load)
            radial.append(RadialCurve(test.name, grid, np.asarray(force, dtype=float) * np.ones_like(grid)))
    drucker = None
    if result.options.drucker != "none":
        g = result.drucker_grid
        pressures = np.linspace(min(g["pressures"]), max(g["pressures"]), DRUCKER_MAP[0])
        lengths = np.linspace(min(g["lengths"]), max(g["lengths"]), DRUCKER_MAP[1])
        pp, ll = np.meshgrid(pressures, lengths, indexing="ij")
        e1, e2 = fitted.drucker_tangent_moduli(pp, ll)
        drucker = DruckerMap(pressures, lengths, np.minimum(e1, e2), result.drucker_minimum)
    return FitCurves(tuple(axial), tuple(isometric), tuple(radial), residuals, drucker)
