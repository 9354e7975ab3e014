"""The ``fit:`` block of an experiment file: options of the moduli identification (strict schema).

```yaml
fit:
  degree: 3                      # secant moduli cubic in strain (16 coefficients)
  mode: shared                   # shared | per_pipe | contact_increment
  objective: least_squares       # least_squares | sum_rmse (the paper's metric, smooth sqrt)
  average_legs: false            # fit the mean of loading/unloading legs per length bin (paper)
  average_bins: 30               # length bins per pressure level when averaging
  drucker: tangent               # tangent (E1t >= 0 and E2t >= 0) | sum | none
  drucker_grid: {pressures: 6, lengths: 15}
  bounds: {constant: [0 MPa, 50 MPa], other: [-50 MPa, 50 MPa], contact: [-50 MPa, 50 MPa]}
  contact_terms: constant        # contact_increment mode: constant (ΔE1, ΔE2) | full (all 4(d+1))
  prior: {sd: 2 MPa, toward: input}   # optional ridge toward input | axial | zero moduli, or a
                                 # Gaussian prior: {coefficients: {hoop.a0: {value: 4.4 MPa, sd: 0.5 MPa}}}
                                 # or {pam: pams/prior.yaml} (its moduli and uncertainty: covariance)
  contact_smoothing: 1 N         # softplus width of the contact switch
  rmse_smoothing: 1.0e-4         # ε_s [N²] in sqrt(MSE + ε_s) for sum_rmse
  max_iterations: 1000
  tolerance: 1.0e-10
  slack: unilateral              # rows with force <= 0: the model predicts max(0, F) | exclude them
  calibrate: [braid_angle, initial_length]   # geometry fitted with the moduli (also bladder_thickness)
  calibration_bounds: {braid_angle: [20 deg, 30 deg], initial_length: [300 mm, 320 mm]}
  pipe_diameters: [3 in, 3.5 in] # where the report judges the radial-force predictions
```
The schema of the block is :mod:`.fit_schema` (pydantic, imported only when a block is validated).
Bounds follow docs/physics.md §6: constant-term coefficients a_k0 ∈ [0, 50] MPa, all others ∈ [−50, 50] MPa.
Calibrated geometry stays within ``calibration_bounds`` (default: the stated braid angle ± 10°, the
stated rest length ± 5 %, the stated wall thickness × [0.25, 4]), narrowed where the braid model
would leave its domain for the tested lengths and pipes (docs/physics.md §2).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.model.uncertainty import moduli_names

#: Geometry that ``fit.calibrate`` can fit, in the order of the decision vector.
CALIBRATABLE = ("braid_angle", "initial_length", "bladder_thickness")


@dataclass(frozen=True)
class FitOptions:
    """Validated identification options (SI). See the module docstring for their meaning."""

    degree: int = 3
    mode: str = "shared"
    objective: str = "least_squares"
    average_legs: bool = False
    average_bins: int = 30
    drucker: str = "tangent"
    grid_pressures: int = 6
    grid_lengths: int = 15
    bounds_constant: tuple[float, float] = (0.0, 50e6)
    bounds_other: tuple[float, float] = (-50e6, 50e6)
    bounds_contact: tuple[float, float] = (-50e6, 50e6)
    contact_terms: str = "constant"
    prior_sd: float | None = None  # [Pa] the ridge
    prior_toward: str = "input"
    prior_mean: tuple[float, ...] | None = None  # Gaussian prior: mean of θ [Pa] ...
    prior_precision: tuple[tuple[float, ...], ...] | None = None  # ... and its precision [1/Pa²]
    prior_source: str = ""  # where the Gaussian prior came from (reported)
    contact_smoothing: float = 1.0  # [N]
    rmse_smoothing: float = 1e-4  # [N²]
    max_iterations: int = 1000
    tolerance: float = 1e-10
    slack: str = "unilateral"
    calibrate: tuple[str, ...] = ()  # in CALIBRATABLE order
    calibration_bounds: tuple[tuple[str, float, float], ...] = ()  # (name, low, high) [rad or m]
    pipe_diameters: tuple[float, ...] = ()  # [m]

    def with_overrides(self, **changes) -> FitOptions:
        """A copy with the given (non-None) fields replaced, e.g. from command-line flags."""
        return replace(self, **{k: v for k, v in changes.items() if v is not None})

    def calibrating(self, *names: str) -> FitOptions:
        """A copy that also calibrates ``names`` (the command line adds to the file)."""
        chosen = set(self.calibrate) | set(names)
        return replace(self, calibrate=tuple(n for n in CALIBRATABLE if n in chosen))


def parse_fit_options(raw: dict | None, *, source: Path | str = "experiment file",
                      rename: dict[str, str] | None = None) -> FitOptions:
    """Validate a ``fit:`` mapping; errors name ``fit.<key>`` (or ``rename[key]``) and the value."""
    from pampipe.identification.fit_schema import FitBlock  # pydantic: only when a block is validated
    from pampipe.specs.schema import validate

    schema = validate(Path(source), FitBlock, {"fit": dict(raw or {})}, rename=rename).fit
    return FitOptions(
        degree=schema.degree, mode=schema.mode, objective=schema.objective,
        average_legs=schema.average_legs, average_bins=schema.average_bins, drucker=schema.drucker,
        grid_pressures=schema.drucker_grid.pressures, grid_lengths=schema.drucker_grid.lengths,
        bounds_constant=tuple(schema.bounds.constant), bounds_other=tuple(schema.bounds.other),
        bounds_contact=tuple(schema.bounds.contact), contact_terms=schema.contact_terms,
        prior_sd=None if schema.prior is None else schema.prior.sd,
        prior_toward="input" if schema.prior is None else schema.prior.toward,
        **_gaussian_prior(schema.prior, schema.degree, source),
        contact_smoothing=schema.contact_smoothing, rmse_smoothing=schema.rmse_smoothing,
        max_iterations=schema.max_iterations, tolerance=schema.tolerance, slack=schema.slack,
        calibrate=tuple(n for n in CALIBRATABLE if n in schema.calibrate),
        calibration_bounds=tuple((n, *getattr(schema.calibration_bounds, n)) for n in CALIBRATABLE
                                 if getattr(schema.calibration_bounds, n) is not None),
        pipe_diameters=tuple(schema.pipe_diameters))


def _gaussian_prior(prior, degree: int, source) -> dict:
    """FitOptions fields of a Gaussian prior (``coefficients`` or ``mean``/``covariance``), else {}."""
    if prior is None or prior.sd is not None:
        return {}
    names = moduli_names(degree)
    n = len(names)
    if prior.coefficients is not None:
        unknown = [name for name in prior.coefficients if name not in names]
        if unknown:
            raise InputError(f"{source}: fit.prior.coefficients: unknown coefficient(s) "
                             f"{', '.join(unknown)}; with degree {degree} they are {names[0]} … {names[-1]}.")
        mean, precision = np.zeros(n), np.zeros((n, n))
        for name, c in prior.coefficients.items():
            k = names.index(name)
            mean[k], precision[k, k] = c.value, 1.0 / c.sd**2
        where = "fit.prior.coefficients: " + ", ".join(prior.coefficients)
    else:
        mean, covariance = np.asarray(prior.mean, float), np.asarray(prior.covariance, float)
        if mean.size != n or covariance.shape != (n, n):
            raise InputError(f"{source}: fit.prior: the prior's moduli have {mean.size} coefficients, the "
                             f"fit has {n} (degree {degree}); give fit.degree to match.")
        lam, vec = np.linalg.eigh(0.5 * (covariance + covariance.T))
        keep = lam > 1e-12 * max(lam.max(initial=0.0), 1e-300)  # no variance: no information either
        precision = (vec[:, keep] / lam[keep]) @ vec[:, keep].T
        where = f"fit.prior.pam: {prior.pam}" if prior.pam else "fit.prior: mean and covariance"
    return {"prior_mean": tuple(mean.tolist()), "prior_precision": tuple(map(tuple, precision.tolist())),
            "prior_source": where}


def fit_options(raw: dict | None, overrides: dict, *, calibrate: Sequence[str] = (),
                pipe_diameters: Sequence[float] = (), source: Path | str = "experiment file",
                where: str = "options", names: dict[str, str] | None = None) -> FitOptions:
    """The ``fit:`` options with ``overrides`` (command-line flags, API keywords; None = not given),
    which pass the same schema first: errors say ``where`` and the name the user wrote (``names``).
    ``calibrate`` (names of :data:`CALIBRATABLE`) and ``pipe_diameters`` [m] add to the file's lists."""
    given = {key: value for key, value in overrides.items() if value is not None}
    parse_fit_options(given, source=where,
                      rename={f"fit.{key}": (names or {}).get(key, key) for key in given})
    unknown = [name for name in calibrate if name not in CALIBRATABLE]
    if unknown:
        raise InputError(f"{where}: {(names or {}).get('calibrate', 'calibrate')} {unknown[0]!r} cannot be "
                         f"calibrated; allowed: {', '.join(CALIBRATABLE)}.")
    options = parse_fit_options({**(raw or {}), **given}, source=source).calibrating(*calibrate)
    if pipe_diameters:
        options = options.with_overrides(pipe_diameters=(*options.pipe_diameters, *pipe_diameters))
    return options
