"""Domain checks: inputs outside the model's physical range raise :class:`InputError`, never NaN.

The braid model is valid for lengths in (B/√3, B) (an extensile braid: (0, B/√3)), and for a pipe between
the rest diameter D₀ and the widest diameter the muscle can pull itself open to, D(B/√3) (docs/physics.md §2,
§12).
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.errors import InputError
from pampipe.model.braid import diameter_at_length
from pampipe.model.forces import bladder_volume, inner_room, wall_section
from pampipe.model.pam import Geometry

#: The neutral braid angle from the axis [deg], atan √2: contractile below it, extensile above it.
NEUTRAL_ANGLE_DEG = math.degrees(math.atan(math.sqrt(2.0)))


def check_geometry(geometry: Geometry, *, where: str = "geometry") -> None:
    """A contractile or extensile muscle (not at the neutral angle) whose bladder fits inside the braid."""
    alpha_deg = math.degrees(geometry.braid_angle)
    for name, value in (("initial_length", geometry.initial_length),
                        ("initial_diameter", geometry.initial_diameter),
                        ("bladder_thickness", geometry.bladder_thickness)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{where}.{name}: {value!r} m must be a positive length.")
    if not 0 < alpha_deg < 90 or abs(alpha_deg - NEUTRAL_ANGLE_DEG) < 0.01:
        raise InputError(
            f"{where}: the braid angle from the axis is {alpha_deg:.2f} deg "
            f"({90 - alpha_deg:.2f} deg from the transverse plane); a contractile muscle needs "
            "0 < angle from axis < 54.74 deg (i.e. 35.26 deg < angle from transverse < 90 deg), an "
            "extensile one 54.74 deg < angle from axis < 90 deg; at 54.74 deg the braid neither contracts "
            "nor extends. Did you give the angle in the other convention?")
    if geometry.bladder_thickness >= geometry.initial_diameter / 2:
        raise InputError(
            f"{where}.bladder_thickness: {geometry.bladder_thickness * 1e3:.4g} mm must be less than "
            f"the rest radius {geometry.initial_diameter * 500:.4g} mm.")


#: The largest share of a stated geometry sd's normal that may fall outside the physical domain.
OUTSIDE_SHARE = 1e-6
#: The z of :data:`OUTSIDE_SHARE` on one side: an sd may be at most (distance to the edge)/this.
OUTSIDE_Z = 4.753424


def entry_domain(geometry: Geometry, name: str) -> tuple[float, float]:
    """(low, high) of one geometry entry with the others at their values [m or rad]: L₀ > 0, D₀ > 2t,
    0 < t < D₀/2, and the braid angle from the axis on its side of the neutral angle (contractile or
    extensile)."""
    neutral = math.radians(NEUTRAL_ANGLE_DEG)
    return {"initial_length": (0.0, math.inf),
            "initial_diameter": (2 * geometry.bladder_thickness, math.inf),
            "bladder_thickness": (0.0, geometry.initial_diameter / 2),
            "braid_angle": (neutral, math.pi / 2) if geometry.extensile else (0.0, neutral)}[name]


def check_spread(geometry: Geometry, name: str, sd: float, *, where: str, transverse: bool = False) -> None:
    """InputError when a normal of sd ``sd`` [m or rad] around the entry ``name`` (an attribute of
    :class:`Geometry`) puts more than :data:`OUTSIDE_SHARE` of its draws outside :func:`entry_domain` (a
    draw there is no muscle). ``where`` names the entry; an angle is shown from the transverse plane where
    ``transverse`` (the file's convention), lengths in mm."""
    if not sd > 0:
        return
    value = float(getattr(geometry, name))
    low, high = entry_domain(geometry, name)
    root2 = sd * math.sqrt(2)
    share = 0.5 * (math.erfc((value - low) / root2) + math.erfc((high - value) / root2))
    if share <= OUTSIDE_SHARE:
        return
    largest = min(value - low, high - value) / OUTSIDE_Z
    if name == "braid_angle":
        unit, scale = "deg", math.degrees(1)
        shown = sorted(90 - math.degrees(x) if transverse else math.degrees(x) for x in (low, high))
        domain, value = f"between {shown[0]:.4g} and {shown[1]:.4g} deg", math.degrees(value)
        value = 90 - value if transverse else value
    else:
        unit, scale = "mm", 1e3
        domain = (f"above {low * 1e3:.4g} mm" if math.isinf(high)
                  else f"between {low * 1e3:.4g} and {high * 1e3:.4g} mm")
        value *= 1e3
    raise InputError(
        f"{where}: sd {sd * scale:.4g} {unit} puts {share:.3g} of the draws outside what a muscle can be "
        f"(its value {value:.6g} {unit} must stay {domain}); an sd may put at most {OUTSIDE_SHARE:g} "
        f"outside: give an sd of at most {largest * scale:.3g} {unit}.")


def outside_domain(p: np.ndarray, nominal: np.ndarray) -> np.ndarray:
    """Rows of parameter draws ``p`` (n, size; L₀, D₀, α, t first) that are no muscle: outside
    :func:`entry_domain` in any entry (NaN included), the braid angle on the side of ``nominal``'s."""
    length, diameter, angle, thickness = (p[:, k] for k in range(4))
    neutral = math.radians(NEUTRAL_ANGLE_DEG)
    extensile = nominal[2] > neutral
    side = (angle > neutral) & (angle < math.pi / 2) if extensile else (angle > 0) & (angle < neutral)
    return ~((length > 0) & (thickness > 0) & (diameter > 2 * thickness) & side)


def check_kind(geometry: Geometry, *, extensile: bool, where: str, role: str) -> None:
    """The muscle is of the kind its role needs: contractile to anchor, extensile to steer."""
    if geometry.extensile == extensile:
        return
    alpha_deg = math.degrees(geometry.braid_angle)
    need = (f"an extensile muscle, braid angle from the axis above {NEUTRAL_ANGLE_DEG:.2f} deg (below "
            f"{90 - NEUTRAL_ANGLE_DEG:.2f} deg from the transverse)" if extensile else
            f"a contractile muscle, braid angle from the axis below {NEUTRAL_ANGLE_DEG:.2f} deg (above "
            f"{90 - NEUTRAL_ANGLE_DEG:.2f} deg from the transverse)")
    raise InputError(f"{where}: {role} needs {need}; this one's is {alpha_deg:.2f} deg from the axis "
                     f"({90 - alpha_deg:.2f} deg from the transverse).")


def check_pipe_diameter(geometry: Geometry, diameter, *, where: str = "pipe_diameter") -> None:
    """D₀ < D_p < D(B/√3): wider than the muscle at rest, narrower than it can reach."""
    values = np.atleast_1d(np.asarray(diameter, dtype=float))
    if not np.all(np.isfinite(values)):
        raise InputError(f"{where}: {diameter!r} is not a finite diameter.")
    if geometry.extensile:
        raise InputError(
            f"{where}: this muscle is extensile (braid angle from the axis "
            f"{math.degrees(geometry.braid_angle):.2f} deg > {NEUTRAL_ANGLE_DEG:.2f} deg): inflated it "
            f"lengthens and narrows from {geometry.initial_diameter * 1e3:.4g} mm toward "
            f"{geometry.largest_diameter * 1e3:.4g} mm, so it never presses on a pipe wall. It steers "
            "(robot.steering in a mission); without --pipe-diameter, simulate shows its extension.")
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
    shown = "(B/sqrt(3), B)"
    if geometry.extensile:  # it lengthens from L0 toward B/sqrt(3)
        low, high, shown = 0.0, geometry.shortest_length, "(0, B/sqrt(3))"
    bad = values[~((values > low) & (values < high))]
    if bad.size:
        raise InputError(
            f"{where}: {bad[0] * 1e3:.6g} mm is outside the braid's range "
            f"({low * 1e3:.5g} mm, {high * 1e3:.5g} mm) = {shown}.")
    if geometry.wall == "thick" and not _bladder_fits(values, geometry):
        with np.errstate(invalid="ignore"):  # NaN marks a crushed row: the error names it, no warning
            _, r_i, _ = wall_section(values, geometry)
        crushed = values[~np.isfinite(r_i)]
        if crushed.size:
            raise InputError(
                f"{where}: at {crushed[0] * 1e3:.6g} mm the braid is too narrow to hold the bladder "
                "(its inner radius would be imaginary); the muscle cannot be stretched that far.")


def _bladder_fits(lengths: np.ndarray, geometry: Geometry) -> bool:
    """R_o² − V_b/(πL) > 10⁻⁹R_o² (a real inner radius, with room for rounding) at every length, judged
    at the shortest and the longest: (B² − L²)/(4π²N²) − V_b/(πL) is concave in L > 0, so its minimum
    over [L_min, L_max] is at an end (no pass over every row; False: check them one by one)."""
    if not lengths.size:
        return True
    ends = np.array([lengths.min(), lengths.max()])
    r_o = diameter_at_length(ends, geometry) / 2
    return bool(np.all(inner_room(ends, r_o, bladder_volume(geometry)) > 1e-9 * r_o**2))


def check_pressure(pressure, *, where: str = "pressure", upper: float = 1e8) -> None:
    """0 ≤ P ≤ 100 MPa (gauge); a PAM bursts long before the upper bound."""
    values = np.atleast_1d(np.asarray(pressure, dtype=float))
    bad = values[~((values >= 0) & (values <= upper))]
    if bad.size:
        raise InputError(
            f"{where}: {bad[0]:.6g} Pa is outside the allowed gauge-pressure range 0 .. {upper:.3g} Pa.")
