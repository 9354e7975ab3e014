"""Geometry in the fit: calibration bounds, the calibrated geometry, and the blocked-force check.

**Blocked-force check** (docs/physics.md §4.3): at the rest length L₀ both strains vanish, so the
bladder carries no stress and F_ax(P, L₀) = P·area(L₀) with area = R_iL²/(2πN²R_o) − πR_i² (thick wall;
(3L² − B²)/(4πN²) thin): the slope dF/dP at the longest tested length, when that length is L₀ (within
:data:`AT_REST`), depends on the geometry alone. The measured slope (a straight-line fit of F on P over
the measured rows within :data:`NEAR` of the longest tested length) is compared with the stated
geometry's; when they differ by more than three standard errors and :data:`MISMATCH` of the slope, the
braid angle that would give the measured slope (at the stated L₀) is named. A positive intercept
pressure P_th = −c/s of that line is a muscle that needs a threshold pressure before it pulls at its
longest length (a rest length stated too long, or bladder prestrain, docs/physics.md §9j).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from pampipe.errors import InputError
from pampipe.identification.fit_nlp import GEOMETRY
from pampipe.identification.options import FitOptions
from pampipe.model import forces
from pampipe.model.pam import Geometry

#: Default calibration ranges: braid angle over the braid's whole range (1° to 54°, below the
#: neutral 54.7° where a muscle stops contracting; the multi-start of :mod:`.multistart` searches it),
#: rest length ± 5 %, wall thickness × [1/4, 4].
ANGLE_RANGE = (1.0, 54.0)  # [deg]
LENGTH_RANGE = 0.05
THICKNESS_RANGE = 4.0
#: Keep this relative margin from the edges of the braid model's domain (B/√3 < L < B).
DOMAIN_MARGIN = 0.005
#: Rows within this fraction of L₀ below the longest tested length count as "at the longest length".
NEAR = 0.002
#: The check needs the longest tested length within this relative distance of the stated L₀: away
#: from L₀ the bladder strains are not zero, and pressure-dependent moduli (b_kj) add to dF/dP, so a
#: fit can trade the braid angle for them (measured: isometric ramps at 0.93 L₀ with α₀ stated 3° off
#: were fitted as well at 16.6° as at the true 23.6°). 1 % covers a rest length stated a few mm off.
AT_REST = 0.01
#: A slope mismatch is reported above this relative size (and above 3 standard errors).
MISMATCH = 0.02
Z95 = 1.959963984540054


def stated_x(geometry: Geometry, calibrate) -> np.ndarray:
    """The stated values of the calibrated entries, in x units (deg, mm)."""
    vector = geometry.as_vector()
    return np.array([vector[GEOMETRY[name][0]] / GEOMETRY[name][1] for name in calibrate])


def from_x(geometry: Geometry, calibrate, values) -> Geometry:
    """``geometry`` with the calibrated entries taken from x (deg, mm)."""
    vector = geometry.as_vector()
    for name, value in zip(calibrate, values, strict=True):
        index, unit = GEOMETRY[name]
        vector[index] = float(value) * unit
    return Geometry(*(float(v) for v in vector), geometry.wall)


def bounds(data, options: FitOptions, pipes) -> dict[str, tuple[float, float]]:
    """{name: (low, high)} in x units: the user's or default ranges, narrowed to the model's domain.

    Domain (docs/physics.md §2): every tested length in (B/√3, B) and every pipe below the widest
    diameter D(B/√3) = √(2/3)·D₀/sin α₀, for every rest length in its range.
    """
    g = data.pam.geometry
    given = {name: (low, high) for name, low, high in options.calibration_bounds}
    out = {"braid_angle": given.get("braid_angle", tuple(math.radians(v) for v in ANGLE_RANGE)),
           "initial_length": given.get("initial_length", (g.initial_length * (1 - LENGTH_RANGE),
                                                          g.initial_length * (1 + LENGTH_RANGE))),
           "bladder_thickness": given.get("bladder_thickness",
                                          (g.bladder_thickness / THICKNESS_RANGE,
                                           min(g.bladder_thickness * THICKNESS_RANGE,
                                               0.45 * g.initial_diameter)))}
    lengths = [t.length for t in data.tests if t.kind == "axial"]
    rest_low, rest_high = out["initial_length"] if "initial_length" in options.calibrate else \
        (g.initial_length, g.initial_length)
    low, high = out["braid_angle"]
    if lengths:
        longest = max(float(v.max()) for v in lengths) * (1 + DOMAIN_MARGIN)
        shortest = min(float(v.min()) for v in lengths) * (1 - DOMAIN_MARGIN)
        low = max(low, math.acos(min(1.0, rest_low / longest)))  # B = L₀/cos α₀ > longest
        high = min(high, math.acos(min(1.0, rest_high / (math.sqrt(3) * shortest))))  # B/√3 < shortest
    if pipes:
        high = min(high, math.asin(min(1.0, math.sqrt(2 / 3) * g.initial_diameter / max(pipes)
                                       / (1 + DOMAIN_MARGIN))))
    if "braid_angle" in options.calibrate and not low < high:
        raise InputError(
            f"{data.source}: no braid angle in the calibration range keeps the braid model in its domain for "
            "these tests (every axial length below B = L0/cos(alpha0) and above B/sqrt(3), every pipe "
            f"narrower than D(B/sqrt(3))): it would need at least {math.degrees(low):.3g} deg and at most "
            f"{math.degrees(high):.3g} deg; check the tested lengths, the pipe diameters and the stated D0 "
            "and L0.")
    out["braid_angle"] = (low, high)
    return {name: (out[name][0] / GEOMETRY[name][1], out[name][1] / GEOMETRY[name][1])
            for name in options.calibrate}


@dataclass(frozen=True)
class BlockedForce:
    """The blocked-force slope at the longest tested length, measured and from the geometry."""

    length: float  # mean length of the rows used [m]
    rows: int
    slope: float  # measured dF/dP [N/Pa]
    slope_std: float  # its standard error [N/Pa]
    geometry_slope: float  # area(L) of the geometry checked [N/Pa]
    threshold: float  # P_th = −intercept/slope [Pa]
    threshold_std: float  # [Pa]
    fitting_angle: float | None  # α₀ [rad] that gives the measured slope at the stated L₀ (None: none)

    @property
    def consistent(self) -> bool:
        gap = abs(self.slope - self.geometry_slope)
        return gap <= max(3 * self.slope_std, MISMATCH * abs(self.geometry_slope))

    @property
    def has_threshold(self) -> bool:
        """A threshold pressure clearly above zero (3 standard errors and 5 kPa)."""
        return self.threshold > max(3 * self.threshold_std, 5e3)

    def as_document(self) -> dict:
        return {"length_m": self.length, "rows": self.rows, "slope_N_per_Pa": self.slope,
                "slope_interval_N_per_Pa": [self.slope - Z95 * self.slope_std,
                                            self.slope + Z95 * self.slope_std],
                "geometry_slope_N_per_Pa": self.geometry_slope, "consistent": self.consistent,
                "threshold_pressure_Pa": self.threshold,
                "fitting_braid_angle_from_axis_deg": None if self.fitting_angle is None
                else math.degrees(self.fitting_angle)}


def blocked_force(data, geometry: Geometry) -> BlockedForce | None:
    """The check of the module docstring, or None when the data cannot make it
    (:func:`blocked_force_skipped` says why)."""
    rows = _rows_at_rest(data, geometry)
    if isinstance(rows, str):
        return None
    pressure, force, length = rows
    design = np.column_stack([np.ones_like(pressure), pressure])
    coef, *_ = np.linalg.lstsq(design, force, rcond=None)
    residual = force - design @ coef
    sigma2 = float(residual @ residual) / max(pressure.size - 2, 1)
    cov = sigma2 * np.linalg.inv(design.T @ design)
    intercept, slope = coef
    mean_length = float(length.mean())
    area = float(forces.axial_levers(mean_length, geometry)[0])
    grad = np.array([-1 / slope, intercept / slope**2])  # of P_th = −intercept/slope
    return BlockedForce(mean_length, int(pressure.size), float(slope), float(math.sqrt(cov[1, 1])), area,
                        float(-intercept / slope), float(math.sqrt(max(grad @ cov @ grad, 0.0))),
                        _angle_for_slope(geometry, mean_length, float(slope)))


def blocked_force_skipped(data, geometry: Geometry) -> str | None:
    """Why the blocked-force check cannot run on these data (None: it can)."""
    rows = _rows_at_rest(data, geometry)
    return rows if isinstance(rows, str) else None


def _rows_at_rest(data, geometry: Geometry):
    """(P, F, L) of the measured rows at the longest tested length, or the reason there are none
    usable: no axial test, the longest tested length farther than :data:`AT_REST` from the stated
    L₀, fewer than three distinct pressures there, or a pressure span below 20 % of the largest."""
    rows = [t for t in data.tests if t.kind == "axial"]
    if not rows:
        return "no axial test"
    longest = max(float(t.length.max()) for t in rows)
    gap = longest / geometry.initial_length - 1.0
    if abs(gap) > AT_REST:
        return (f"the longest tested length {longest * 1e3:.5g} mm is {abs(gap) * 100:.2g} % "
                f"{'below' if gap < 0 else 'above'} the rest length L0 = "
                f"{geometry.initial_length * 1e3:.5g} mm "
                f"(the check needs rows within {AT_REST * 100:g} % of L0, where the force depends on the "
                "geometry alone); a pressure ramp at L0 would make it")
    near = longest - NEAR * geometry.initial_length
    pressure = np.concatenate([t.pressure[(t.length >= near) & (t.force > 0)] for t in rows])
    force = np.concatenate([t.force[(t.length >= near) & (t.force > 0)] for t in rows])
    length = np.concatenate([t.length[(t.length >= near) & (t.force > 0)] for t in rows])
    top = float(np.max(np.abs(pressure))) if pressure.size else 0.0
    distinct = np.unique(np.round(pressure / max(top, 1.0), 2)).size if pressure.size else 0
    if pressure.size < 3 or distinct < 3:
        return (f"{distinct} distinct pressure(s) with tension at the longest tested length "
                f"{longest * 1e3:.5g} mm (the check needs 3)")
    if np.ptp(pressure) < 0.2 * top:
        return (f"the pressures at the longest tested length span {np.ptp(pressure) / 1e3:.3g} kPa, "
                f"below 20 % of the largest ({top / 1e3:.4g} kPa)")
    return pressure, force, length


def _angle_for_slope(geometry: Geometry, length: float, slope: float) -> float | None:
    """α₀ with area(L; α₀) = slope at the stated L₀ (bisection on [1°, 54°]; area falls with α₀)."""
    def area(alpha):
        g = replace(geometry, braid_angle=alpha)
        if length >= g.braid_length:
            return math.inf
        return float(forces.axial_levers(length, g)[0])

    low, high = math.radians(1.0), math.radians(54.0)
    if not area(high) <= slope <= area(low):
        return None
    for _ in range(60):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if area(mid) > slope else (low, mid)
    return 0.5 * (low + high)
