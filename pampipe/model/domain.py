"""Domain checks: inputs outside the model's physical range raise :class:`InputError`, never NaN.

The braid model is valid for lengths in (B/√3, B) and for a pipe between the rest diameter D₀ and
the widest diameter the muscle can pull itself open to, D(B/√3) (docs/physics.md §2, §12).
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.errors import InputError
from pampipe.model.forces import wall_section
from pampipe.model.pam import Geometry


def check_geometry(geometry: Geometry, *, where: str = "geometry") -> None:
    """A contractile muscle with a bladder that fits inside the braid."""
    alpha_deg = math.degrees(geometry.braid_angle)
    for name, value in (("initial_length", geometry.initial_length),
                        ("initial_diameter", geometry.initial_diameter),
                        ("bladder_thickness", geometry.bladder_thickness)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{where}.{name}: {value!r} m must be a positive length.")
    if not 0 < alpha_deg < 54.7356:
        raise InputError(
            f"{where}: the braid angle from the axis is {alpha_deg:.2f} deg "
            f"({90 - alpha_deg:.2f} deg from the transverse plane); a contractile muscle needs "
            "0 < angle from axis < 54.74 deg (i.e. 35.26 deg < angle from transverse < 90 deg). "
            "Did you give the angle in the other convention?")
    if geometry.bladder_thickness >= geometry.initial_diameter / 2:
        raise InputError(
            f"{where}.bladder_thickness: {geometry.bladder_thickness * 1e3:.4g} mm must be less than "
            f"the rest radius {geometry.initial_diameter * 500:.4g} mm.")


def check_pipe_diameter(geometry: Geometry, diameter, *, where: str = "pipe_diameter") -> None:
    """D₀ < D_p < D(B/√3): wider than the muscle at rest, narrower than it can reach."""
    values = np.atleast_1d(np.asarray(diameter, dtype=float))
    if not np.all(np.isfinite(values)):
        raise InputError(f"{where}: {diameter!r} is not a finite diameter.")
    narrow = values[values <= geometry.initial_diameter]
    if narrow.size:
        raise InputError(
            f"{where}: a {narrow[0] * 1e3:.4g} mm pipe is not wider than the muscle at rest "
            f"(D0 = {geometry.initial_diameter * 1e3:.4g} mm); the muscle cannot anchor in it. "
            f"Allowed: {geometry.initial_diameter * 1e3:.4g} mm < pipe < "
            f"{geometry.largest_diameter * 1e3:.4g} mm.")
    wide = values[values >= geometry.largest_diameter]
    if wide.size:
        raise InputError(
            f"{where}: a {wide[0] * 1e3:.4g} mm pipe is wider than the braid can reach "
            f"(at most {geometry.largest_diameter * 1e3:.4g} mm, where the contractile force "
            f"vanishes at L = B/sqrt(3)). Allowed: {geometry.initial_diameter * 1e3:.4g} mm < pipe < "
            f"{geometry.largest_diameter * 1e3:.4g} mm.")


def check_length(geometry: Geometry, length, *, where: str = "length") -> None:
    """B/√3 < L < B, and the bladder still fits inside the braid (real inner radius)."""
    values = np.atleast_1d(np.asarray(length, dtype=float))
    low, high = geometry.shortest_length, geometry.braid_length
    bad = values[~((values > low) & (values < high))]
    if bad.size:
        raise InputError(
            f"{where}: {bad[0] * 1e3:.6g} mm is outside the braid's range "
            f"({low * 1e3:.5g} mm, {high * 1e3:.5g} mm) = (B/sqrt(3), B).")
    if geometry.wall == "thick":
        _, r_i, _ = wall_section(values, geometry)
        crushed = values[~np.isfinite(r_i)]
        if crushed.size:
            raise InputError(
                f"{where}: at {crushed[0] * 1e3:.6g} mm the braid is too narrow to hold the bladder "
                "(its inner radius would be imaginary); the muscle cannot be stretched that far.")


def check_pressure(pressure, *, where: str = "pressure", upper: float = 1e8) -> None:
    """0 ≤ P ≤ 100 MPa (gauge); a PAM bursts long before the upper bound."""
    values = np.atleast_1d(np.asarray(pressure, dtype=float))
    bad = values[~((values >= 0) & (values <= upper))]
    if bad.size:
        raise InputError(
            f"{where}: {bad[0]:.6g} Pa is outside the allowed gauge-pressure range 0 .. {upper:.3g} Pa.")
