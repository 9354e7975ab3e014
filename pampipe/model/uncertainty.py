"""What a fit leaves uncertain about a muscle: joint covariance, model error, undetermined directions.

No I/O here: :mod:`pampipe.io.pam_schema` reads the PAM file's ``uncertainty:`` block into a
:class:`ParameterUncertainty`, :mod:`pampipe.io.pamfile` writes it, ``identify`` builds it.

Parameters are named ``axial.a0 … axial.a3, axial.b0 … axial.b3, hoop.a0 … hoop.b3`` (the moduli θ in the
order of :meth:`pampipe.model.pam.Moduli.as_vector`), then any calibrated geometry entries ``braid_angle``
(α₀ from the axis), ``initial_length``, ``initial_diameter``, ``bladder_thickness``. Everything is SI
(Pa, rad, m). An undetermined direction is written in *scaled coordinates*, one scaled unit being
:data:`SCALED_UNITS` of the parameter (1 MPa for a modulus coefficient, 1 deg for the braid angle, 1 mm for a
length), so that its weights are comparable; :meth:`ParameterUncertainty.step` turns it back into SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: Geometry entries a fit may calibrate, in the order they follow the moduli.
GEOMETRY_NAMES = ("braid_angle", "initial_length", "initial_diameter", "bladder_thickness")
#: SI size of one scaled unit of each parameter kind: 1 MPa, 1 deg, 1 mm.
SCALED_UNITS = {"moduli": 1e6, "braid_angle": math.pi / 180, "initial_length": 1e-3, "initial_diameter": 1e-3,
                "bladder_thickness": 1e-3}


def moduli_names(degree: int = 3) -> tuple[str, ...]:
    """``axial.a0 … hoop.b<degree>``: the names of θ (:meth:`Moduli.as_vector` order)."""
    return tuple(f"{law}.{part}{j}" for law in ("axial", "hoop") for part in ("a", "b")
                 for j in range(degree + 1))


def scaled_unit(name: str) -> float:
    """SI size of one scaled unit of parameter ``name`` (:data:`SCALED_UNITS`)."""
    return SCALED_UNITS.get(name, SCALED_UNITS["moduli"])


#: Tolerance of :func:`check_covariance` on the correlation-scaled matrix (rounding of written files).
PSD_TOLERANCE = 1e-6


def check_covariance(cov: np.ndarray) -> None:
    """ValueError unless ``cov`` is finite, symmetric and positive semi-definite.

    Checked on the correlation-scaled matrix C/(s sᵀ), s = √diag C, so that rows in Pa² and in rad² weigh
    alike; symmetry and the least eigenvalue are allowed :data:`PSD_TOLERANCE` of rounding.
    """
    if not np.all(np.isfinite(cov)):
        raise ValueError("covariance has entries that are not finite numbers")
    diag = np.diag(cov)
    if np.any(diag < 0):
        i = int(np.argmin(diag))
        raise ValueError(f"covariance: the variance [{i}][{i}] is negative ({diag[i]:.6g} in SI units); a "
                         "variance is a squared standard deviation, at least 0")
    s = np.sqrt(diag)
    s[s == 0] = 1.0
    scaled = cov / np.outer(s, s)
    if np.max(np.abs(scaled - scaled.T), initial=0.0) > PSD_TOLERANCE:
        raise ValueError("covariance is not symmetric")
    if cov.size and np.linalg.eigvalsh(0.5 * (scaled + scaled.T))[0] < -PSD_TOLERANCE:
        raise ValueError("covariance is not positive semi-definite (a variance of some combination would be "
                         "negative)")


@dataclass(frozen=True)
class UndeterminedDirection:
    """A direction of the parameters that the data do not fix.

    Moving the parameters by ``t · scale · vector`` (scaled coordinates, :data:`SCALED_UNITS`) changes
    the fit's residuals by (next to) nothing for |t| ≤ 1; ``scale`` is the width along the direction
    that the data leave open, i.e. the prior sd one would need to pin it. ``moves`` maps predictions
    (``radial_force_N@0.0762m``, ``anchoring_pressure_Pa@0.0762m``: SI, unit-suffixed, at a bore) to
    their change per unit of ``scale`` along ``vector`` (t = 1). ``test`` names the test that would
    determine it (``a radial test at 76.2 mm (3 in)``).
    """

    vector: np.ndarray  # unit vector over ParameterUncertainty.names, scaled coordinates
    scale: float  # [scaled units]
    moves: dict[str, float] = field(default_factory=dict, hash=False)
    test: str = ""

    def __eq__(self, other) -> bool:
        if not isinstance(other, UndeterminedDirection):
            return NotImplemented
        return (self.scale == other.scale and self.moves == other.moves and self.test == other.test
                and np.array_equal(self.vector, other.vector))


@dataclass(frozen=True)
class ParameterUncertainty:
    """Joint uncertainty of a muscle's moduli and calibrated geometry, SI.

    ``covariance`` [Pa², rad², m², cross terms in their SI products] is over ``names``, positive
    semi-definite on the determined subspace (zero along the ``undetermined`` directions: they are
    listed, not given a variance). ``model_error`` [N] is the residual spread beyond the noise floor
    that no parameter value removes (0 when the model fits to the noise). ``prior_determined`` lists
    the directions that only a prior (``fit.prior``) determines: their variance is the prior's, so a
    plan that depends on them rests on the prior (``scale`` is then that sd along the direction).
    """

    names: tuple[str, ...]
    covariance: np.ndarray
    model_error: float = 0.0
    undetermined: tuple[UndeterminedDirection, ...] = ()
    prior_determined: tuple[UndeterminedDirection, ...] = ()
    model_error_dof: int | None = None  # degrees of freedom of model_error² (None: not stated)

    def __post_init__(self):
        cov = np.asarray(self.covariance, dtype=float)
        if cov.shape != (len(self.names),) * 2:
            raise ValueError(f"covariance is {cov.shape}, expected {len(self.names)}x{len(self.names)} "
                             f"(one row per name: {', '.join(self.names)})")
        check_covariance(cov)
        if not (math.isfinite(self.model_error) and self.model_error >= 0):
            raise ValueError(f"model_error {self.model_error!r} N must be a finite number ≥ 0")
        for d in (*self.undetermined, *self.prior_determined):
            if np.shape(d.vector) != (len(self.names),):
                raise ValueError(f"an undetermined direction has {np.size(d.vector)} weights, expected "
                                 f"{len(self.names)}")
        object.__setattr__(self, "covariance", cov)

    def __eq__(self, other) -> bool:
        if not isinstance(other, ParameterUncertainty):
            return NotImplemented
        return (self.names == other.names and self.model_error == other.model_error
                and self.model_error_dof == other.model_error_dof
                and self.undetermined == other.undetermined
                and self.prior_determined == other.prior_determined
                and np.array_equal(self.covariance, other.covariance))

    @property
    def moduli_count(self) -> int:
        """How many of ``names`` are moduli coefficients (they come first)."""
        return sum(1 for name in self.names if name not in GEOMETRY_NAMES)

    @property
    def geometry_names(self) -> tuple[str, ...]:
        """The calibrated geometry entries among ``names``."""
        return tuple(name for name in self.names if name in GEOMETRY_NAMES)

    def moduli_covariance(self) -> np.ndarray:
        """The moduli block of ``covariance`` [Pa²] (what ``Pam.covariance`` holds)."""
        n = self.moduli_count
        return self.covariance[:n, :n]

    def moduli_part(self) -> ParameterUncertainty:
        """The uncertainty of the moduli alone (geometry rows dropped), for a muscle of another geometry:
        directions keep their moduli part (renormalised, same step) and lose their moves (other bores)."""
        n = self.moduli_count

        def cut(d: UndeterminedDirection) -> UndeterminedDirection | None:
            norm = float(np.linalg.norm(d.vector[:n]))
            if norm < 1e-12:
                return None
            return UndeterminedDirection(d.vector[:n] / norm, d.scale * norm, {}, d.test)

        def kept(directions):
            return tuple(c for c in map(cut, directions) if c is not None)

        return ParameterUncertainty(self.names[:n], self.covariance[:n, :n], self.model_error,
                                    kept(self.undetermined), kept(self.prior_determined),
                                    self.model_error_dof)

    def scaled_units(self) -> np.ndarray:
        """SI size of one scaled unit for each of ``names``."""
        return np.array([scaled_unit(name) for name in self.names])

    def step(self, direction: UndeterminedDirection) -> np.ndarray:
        """SI parameter change of one ``scale`` along ``direction``: scale·vector·units, over ``names``."""
        return direction.scale * np.asarray(direction.vector, dtype=float) * self.scaled_units()

    def as_document(self) -> dict:
        """JSON form (SI): parameters, covariance, model error, undetermined directions (scaled units)."""
        return {"parameters": list(self.names), "covariance_SI": self.covariance.tolist(),
                "model_error_N": self.model_error, "model_error_dof": self.model_error_dof,
                "scaled_units_SI": {name: scaled_unit(name) for name in self.names},
                "undetermined": [self.direction_document(d) for d in self.undetermined],
                "prior_determined": [self.direction_document(d) for d in self.prior_determined]}

    def direction_document(self, d: UndeterminedDirection) -> dict:
        """JSON form of a direction over ``names``: its non-zero weights, ``scale``, ``moves``, ``test``."""
        return {"direction": {n: float(w) for n, w in zip(self.names, d.vector, strict=True) if w != 0},
                "scale": d.scale, "moves": dict(d.moves), "test": d.test}

    @classmethod
    def moduli_only(cls, covariance, *, degree: int | None = None) -> ParameterUncertainty:
        """The uncertainty of the moduli alone (the old ``uncertainty: {unit, covariance}`` block) [Pa²]."""
        cov = np.asarray(covariance, dtype=float)
        degree = cov.shape[0] // 4 - 1 if degree is None else degree
        return cls(moduli_names(degree), cov)
