"""The calibration geometry (pampipe/identification/geometry.py) against answers written again here: the
blocked-force slope P·area(L₀) of docs/physics.md §4.3 (thick and thin wall) on synthetic rows of a known
geometry, its straight line fitted with numpy.polyfit, the braid angle of a measured slope by brentq, the
threshold-pressure intercept, the mismatch and threshold boundaries, the AT_REST / NEAR windows, and the
calibration bounds against the braid domain B/√3 < L < B (docs/physics.md §2)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.stats import norm

from pampipe.errors import InputError
from pampipe.identification import geometry as geo
from pampipe.identification.options import FitOptions
from pampipe.model.pam import Geometry

L0, D0, T0 = 0.15, 0.02, 0.0015  # [m]
STATED = math.radians(24.0)


def area(length, alpha, wall="thick", rest=L0):
    """P·area of Eq. 9 at the given length, docs/physics.md §2 and §4.3, written from the spec alone [m²]."""
    b = rest / math.cos(alpha)
    n = rest * math.tan(alpha) / (math.pi * D0)
    if wall == "thin":
        return (3 * length**2 - b**2) / (4 * math.pi * n**2)
    r_o = math.sqrt(b**2 - length**2) / (n * math.pi) / 2
    v_b = math.pi * ((D0 / 2) ** 2 - (D0 / 2 - T0) ** 2) * rest
    r_i = math.sqrt(r_o**2 - v_b / (math.pi * length))
    return r_i * length**2 / (2 * math.pi * n**2 * r_o) - math.pi * r_i**2


def geometry(alpha=STATED, wall="thick"):
    return Geometry(L0, D0, alpha, T0, wall)


def axial(length, pressure, force):
    return SimpleNamespace(kind="axial", length=np.asarray(length, float),
                           pressure=np.asarray(pressure, float), force=np.asarray(force, float))


def data(*tests, g=None):
    return SimpleNamespace(tests=tests, pam=SimpleNamespace(geometry=g or geometry()), source="lab/exp.yaml")


def ramp(pressures, slope, threshold=0.0, length=L0):
    """An isometric ramp at ``length``: F = slope·(P − threshold), no noise."""
    p = np.asarray(pressures, float)
    return axial(np.full(p.size, length), p, slope * (p - threshold))


def textbook_line(p, f):
    """Slope, its standard error, the intercept pressure −c/s and its delta-method standard error from the
    textbook formulas of a least-squares line (independent of the module's matrix algebra)."""
    slope, intercept = np.polyfit(p, f, 1)
    n = p.size
    sxx = float(np.sum((p - p.mean()) ** 2))
    sigma2 = float(np.sum((f - (slope * p + intercept)) ** 2)) / (n - 2)
    var_s, var_c, cov_cs = sigma2 / sxx, sigma2 * (1 / n + p.mean() ** 2 / sxx), -p.mean() * sigma2 / sxx
    p_th = -intercept / slope
    var_th = (var_c + p_th**2 * var_s + 2 * p_th * cov_cs) / slope**2
    return slope, math.sqrt(var_s), p_th, math.sqrt(var_th)


@pytest.mark.parametrize("wall", ["thick", "thin"])
def test_the_blocked_force_line_is_the_rows_at_the_longest_length_fitted_straight(wall):
    """Rows at L₀, rows 0.15 % shorter (inside NEAR = 0.2 %) and a slack row count; rows 0.3 % shorter, a
    row at zero force and one below zero do not. The line, its standard error and the intercept pressure
    are polyfit's and the textbook's; the geometry's slope is area(mean length) of Eq. 9."""
    rng = np.random.default_rng(4)
    s = area(L0, STATED, wall)
    p1 = np.linspace(100e3, 600e3, 8)
    p2 = np.array([150e3, 350e3, 550e3, 500e3])
    p3 = np.array([200e3, 400e3])
    at_rest = axial(np.full(11, L0), np.r_[p1, 0.0, 20e3, 5e3],
                    np.r_[s * (p1 - 40e3) + rng.normal(0, 3.0, 8), 0.0, -5.0, 0.0])
    near = axial(np.full(4, L0 * (1 - 0.0015)), p2, s * (p2 - 40e3) + rng.normal(0, 3.0, 4))
    far = axial(np.full(2, L0 * (1 - 0.003)), p3, 2 * s * p3)  # would change the line if it counted
    radial = SimpleNamespace(kind="radial", length=None, pressure=p3, force=p3 * 1e-3)
    check = geo.blocked_force(data(at_rest, radial, near, far, g=geometry(wall=wall)), geometry(wall=wall))
    p = np.r_[p1, p2]
    f = np.r_[at_rest.force[:8], near.force]
    lengths = np.r_[np.full(8, L0), near.length]
    slope, slope_se, p_th, p_th_se = textbook_line(p, f)
    assert check.rows == 12
    assert check.length == pytest.approx(lengths.mean(), rel=1e-15)
    assert check.slope == pytest.approx(slope, rel=1e-9)
    assert check.slope_std == pytest.approx(slope_se, rel=1e-6)
    assert check.threshold == pytest.approx(p_th, rel=1e-6) and p_th == pytest.approx(40e3, abs=3e3)
    assert check.threshold_std == pytest.approx(p_th_se, rel=1e-6)
    assert check.geometry_slope == pytest.approx(area(lengths.mean(), STATED, wall), rel=1e-12)
    assert check.consistent and check.fitting_angle == pytest.approx(STATED, abs=math.radians(0.5))
    assert geo.blocked_force_skipped(data(at_rest, near, far), geometry(wall=wall)) is None


@pytest.mark.parametrize("wall", ["thick", "thin"])
def test_a_slope_of_another_braid_angle_names_that_angle(wall):
    """Rows of α₀ = 30° checked against a stated 24°: inconsistent, and the angle named is the root of
    area(L₀; α) = slope found by brentq (area falls with α, so 30° gives the smaller slope)."""
    truth = math.radians(30.0)
    slope = area(L0, truth, wall)
    check = geo.blocked_force(data(ramp([100e3, 250e3, 400e3, 600e3], slope)), geometry(wall=wall))
    root = brentq(lambda a: area(L0, a, wall) - check.slope, math.radians(1.0), math.radians(54.0),
                  xtol=1e-14)
    assert check.slope == pytest.approx(slope, rel=1e-10) and check.slope < area(L0, STATED, wall)
    assert not check.consistent
    assert check.fitting_angle == pytest.approx(root, abs=1e-9) and root == pytest.approx(truth, abs=1e-8)
    assert check.threshold == pytest.approx(0.0, abs=1e-6) and not check.has_threshold


@pytest.mark.parametrize(("degrees", "named"), [(1.005, True), (0.99, False), (53.9, True), (54.2, False)])
def test_the_named_angle_is_searched_between_1_and_54_degrees(degrees, named):
    slope = area(L0, math.radians(degrees))
    angle = geo._angle_for_slope(geometry(), L0, slope)
    if named:
        assert angle == pytest.approx(math.radians(degrees), abs=1e-10)
    else:
        assert angle is None


def test_the_search_ends_include_1_and_54_degrees():
    """A slope equal to the model's area at 54° (or at 1°) exactly still names that end (``<=``)."""
    from pampipe.model import forces

    for end in (1.0, 54.0):
        slope = float(forces.axial_levers(L0, geometry(math.radians(end)))[0])
        assert geo._angle_for_slope(geometry(), L0, slope) == pytest.approx(math.radians(end), abs=1e-10)


def test_a_length_beyond_the_braid_of_small_angles_still_names_the_angle():
    """At L = 1.005 L₀ a braid of α₀ below arccos(1/1.005) = 5.7° is shorter than L: its area is taken as
    infinite (no such muscle reaches L), so the bisection moves up, to the angle whose area matches."""
    length = L0 * 1.005
    slope = area(length, math.radians(20.0))
    angle = geo._angle_for_slope(geometry(), length, slope)
    assert angle == pytest.approx(math.radians(20.0), abs=1e-10)


def test_a_threshold_pressure_is_the_intercept_of_the_line():
    s = area(L0, STATED)
    check = geo.blocked_force(data(ramp([100e3, 200e3, 300e3, 500e3], s, threshold=60e3)), geometry())
    assert check.threshold == pytest.approx(60e3, rel=1e-9) and check.has_threshold and check.consistent
    assert check.slope_std < 1e-12 * check.slope and check.threshold_std < 1e-3  # a perfect line: no spread


def _check(slope=51.0, slope_std=1e-9, geometry_slope=50.0, threshold=0.0, threshold_std=0.0):
    return geo.BlockedForce(L0, 5, slope, slope_std, geometry_slope, threshold, threshold_std, None)


def test_the_mismatch_boundary_is_2_percent_on_both_sides():
    """|s − s_g| ≤ max(3 SE, 2 % s_g): with s_g = 50 the 2 % is 1.0 exactly in floating point."""
    assert _check(51.0).consistent and _check(49.0).consistent
    assert not _check(51.0 + 1e-9).consistent and not _check(49.0 - 1e-9).consistent
    assert _check(-51.0, geometry_slope=-50.0).consistent  # |s_g|
    assert not _check(-51.0 - 1e-9, geometry_slope=-50.0).consistent


def test_the_mismatch_boundary_is_three_standard_errors_where_they_are_wider():
    assert _check(51.5, slope_std=0.5).consistent and _check(48.5, slope_std=0.5).consistent
    assert not _check(51.5 + 1e-9, slope_std=0.5).consistent
    assert not _check(48.5 - 1e-9, slope_std=0.5).consistent
    assert not _check(51.5, slope_std=0.4).consistent


def test_a_threshold_is_clear_above_three_standard_errors_and_5_kPa():
    assert not _check(threshold=5e3).has_threshold and _check(threshold=5e3 + 1e-6).has_threshold
    assert _check(threshold=5.02e3).has_threshold
    assert not _check(threshold=12e3, threshold_std=4e3).has_threshold
    assert _check(threshold=12e3 + 1e-6, threshold_std=4e3).has_threshold
    assert not _check(threshold=-20e3, threshold_std=1.0).has_threshold


def test_the_document_gives_the_95_percent_interval_and_the_angle_in_degrees():
    check = geo.BlockedForce(0.149, 7, 2e-3, 1e-5, 2.1e-3, 3e4, 2e3, math.radians(27.5))
    z = norm.ppf(0.975)
    doc = check.as_document()
    assert doc.pop("slope_interval_N_per_Pa") == pytest.approx([2e-3 - z * 1e-5, 2e-3 + z * 1e-5], rel=1e-12)
    assert doc == pytest.approx(
        {"length_m": 0.149, "rows": 7, "slope_N_per_Pa": 2e-3, "geometry_slope_N_per_Pa": 2.1e-3,
         "consistent": False, "threshold_pressure_Pa": 3e4, "fitting_braid_angle_from_axis_deg": 27.5},
        rel=1e-12)
    assert _check().as_document()["fitting_braid_angle_from_axis_deg"] is None


@pytest.mark.parametrize(("ratio", "why"), [(1 - 0.012, "1.2 % below"), (1 + 0.012, "1.2 % above"),
                                            (1 - 0.0104, "1 % below")])
def test_the_check_needs_the_longest_length_within_1_percent_of_l0(ratio, why):
    rows = ramp([100e3, 300e3, 500e3], area(L0, STATED), length=L0 * ratio)
    reason = geo.blocked_force_skipped(data(rows), geometry())
    assert reason == (f"the longest tested length {L0 * ratio * 1e3:.5g} mm is {why} the rest length "
                      "L0 = 150 mm (the check needs rows within 1 % of L0, where the force depends on the "
                      "geometry alone); a pressure ramp at L0 would make it")
    assert geo.blocked_force(data(rows), geometry()) is None


@pytest.mark.parametrize("ratio", [1 - 0.0099, 1 + 0.0099])
def test_rows_within_1_percent_of_l0_are_checked(ratio):
    rows = ramp([100e3, 300e3, 500e3], 2e-3, length=L0 * ratio)
    assert geo.blocked_force_skipped(data(rows), geometry()) is None
    assert geo.blocked_force(data(rows), geometry()).length == pytest.approx(L0 * ratio, rel=1e-15)


def test_a_row_exactly_near_below_the_longest_length_counts():
    longest = L0 * 1.004
    edge = longest - 0.002 * L0
    rows = axial([longest, longest, longest, edge, np.nextafter(edge, 0.0)],
                 [100e3, 300e3, 500e3, 200e3, 400e3], [0.2e3, 0.6e3, 1.0e3, 0.5e3, 0.9e3])
    check = geo.blocked_force(data(rows), geometry())
    assert check.rows == 4 and check.length == pytest.approx((3 * longest + edge) / 4, rel=1e-14)


def test_no_axial_test_no_check():
    radial = SimpleNamespace(kind="radial", length=None, pressure=np.array([1e5, 2e5, 3e5]),
                             force=np.array([1.0, 2.0, 3.0]))
    assert geo.blocked_force_skipped(data(radial), geometry()) == "no axial test"
    assert geo.blocked_force(data(radial), geometry()) is None


@pytest.mark.parametrize(("pressures", "forces", "reason"), [
    ([100e3, 100e3, 500e3, 500e3], [1.0, 1.0, 2.0, 2.0],
     "2 distinct pressure(s) with tension at the longest tested length 150 mm (the check needs 3)"),
    ([100e3, 300e3, 500e3], [0.0, -1.0, -2.0], "0 distinct pressure(s) with tension at the longest"),
    ([300e3, 600e3, 601e3], [1.0, 2.0, 2.1], "2 distinct pressure(s)"),  # 601 and 600 kPa round to one level
    ([100e3, 300e3], [1.0, 2.0], "2 distinct pressure(s)"),
    ([0.0, 100e3, 300e3, 500e3], [0.0, -1.0, 2.0, 3.0], "2 distinct pressure(s)"),  # slack rows do not count
    ([500e3, 550e3, 600e3], [1.0, 2.0, 3.0], "span 100 kPa, below 20 % of the largest (600 kPa)")])
def test_too_few_or_too_close_pressures_at_the_longest_length(pressures, forces, reason):
    rows = axial(np.full(len(pressures), L0), pressures, forces)
    assert reason in geo.blocked_force_skipped(data(rows), geometry())
    assert geo.blocked_force(data(rows), geometry()) is None


def test_three_distinct_pressures_spanning_exactly_20_percent_are_enough():
    rows = axial(np.full(3, L0), [400e3, 450e3, 500e3], [0.8e3, 0.9e3, 1.0e3])
    assert geo.blocked_force_skipped(data(rows), geometry()) is None
    assert geo.blocked_force(data(rows), geometry()).slope == pytest.approx(2e-3, rel=1e-9)


def test_three_noisy_rows_have_one_degree_of_freedom():
    p = np.array([200e3, 400e3, 600e3])
    f = np.array([0.41e3, 0.79e3, 1.22e3])
    check = geo.blocked_force(data(axial(np.full(3, L0), p, f)), geometry())
    slope, slope_se, p_th, p_th_se = textbook_line(p, f)
    assert (check.slope, check.threshold) == pytest.approx((slope, p_th), rel=1e-9)
    assert (check.slope_std, check.threshold_std) == pytest.approx((slope_se, p_th_se), rel=1e-9)


def test_levels_one_percent_apart_are_distinct():
    rows = axial(np.full(3, L0), [300e3, 594e3, 600e3], [0.6e3, 1.188e3, 1.2e3])
    assert geo.blocked_force(data(rows), geometry()).rows == 3


def test_stated_and_calibrated_entries_in_degrees_and_millimetres():
    names = ("braid_angle", "initial_length", "bladder_thickness")
    g = geometry(wall="thin")
    assert geo.stated_x(g, names) == pytest.approx([24.0, 150.0, 1.5], rel=1e-12)
    assert geo.stated_x(g, ("bladder_thickness",)) == pytest.approx([1.5], rel=1e-12)
    moved = geo.from_x(g, names, [30.0, 152.0, 2.0])
    assert moved == Geometry(0.152, D0, moved.braid_angle, 0.002, "thin")
    assert moved.braid_angle == pytest.approx(math.radians(30.0), rel=1e-15)
    assert geo.from_x(g, ("initial_length",), [149.0]) == Geometry(0.149, D0, STATED, T0, "thin")


def flat(ranges: dict) -> dict:
    """{name: (low, high)} as {name low: low, name high: high} (pytest.approx compares flat mappings)."""
    return {f"{name} {end}": value for name, pair in ranges.items()
            for end, value in zip(("low", "high"), pair, strict=True)}


def options(*calibrate, given=(), pipes=()):
    return FitOptions(calibrate=calibrate, calibration_bounds=given, pipe_diameters=pipes)


ALL = ("braid_angle", "initial_length", "bladder_thickness")


def test_the_default_ranges_without_tests_or_pipes():
    rows = data(SimpleNamespace(kind="radial", length=None, pressure=np.ones(3), force=np.ones(3)))
    assert flat(geo.bounds(rows, options(*ALL), ())) == pytest.approx(flat(
        {"braid_angle": (1.0, 54.0), "initial_length": (142.5, 157.5), "bladder_thickness": (0.375, 6.0)}),
        rel=1e-12)
    thick = data(g=Geometry(L0, D0, STATED, 0.003))  # 4 t₀ = 12 mm is beyond 0.45 D₀ = 9 mm
    assert flat(geo.bounds(thick, options("bladder_thickness"), ())) == pytest.approx(
        flat({"bladder_thickness": (0.75, 9.0)}), rel=1e-12)


def test_given_ranges_replace_the_defaults():
    given = (("braid_angle", math.radians(10.0), math.radians(40.0)), ("initial_length", 0.148, 0.151),
             ("bladder_thickness", 0.001, 0.002))
    assert flat(geo.bounds(data(), options(*ALL, given=given), ())) == pytest.approx(flat(
        {"braid_angle": (10.0, 40.0), "initial_length": (148.0, 151.0), "bladder_thickness": (1.0, 2.0)}),
        rel=1e-12)


def _braid(alpha, rest):
    return Geometry(rest, D0, math.radians(alpha), T0)


@pytest.mark.parametrize("calibrate", [("braid_angle",), ("braid_angle", "initial_length")])
def test_the_braid_angle_range_keeps_every_tested_length_inside_the_braid(calibrate):
    """At the lowest angle the braid B = L₀/cos α₀ of the shortest rest length is 0.5 % longer than the
    longest tested length; at the highest, B/√3 of the longest rest length is 0.5 % below the shortest
    tested length. The rest lengths are the stated L₀, or its ±5 % range when it is calibrated too."""
    longest, shortest = 0.152, 0.105
    rows = data(axial([0.12, longest], [1e5, 2e5], [1.0, 2.0]),
                axial([shortest, 0.13], [1e5, 2e5], [1.0, 2.0]))
    low, high = geo.bounds(rows, options(*calibrate), ())["braid_angle"]
    rest_low, rest_high = (L0 * 0.95, L0 * 1.05) if "initial_length" in calibrate else (L0, L0)
    assert _braid(low, rest_low).braid_length == pytest.approx(longest * 1.005, rel=1e-12)
    assert _braid(high, rest_high).shortest_length == pytest.approx(shortest * 0.995, rel=1e-12)
    assert 1.0 < low < high < 54.0


def test_tested_lengths_below_the_rest_length_leave_the_lowest_angle_at_1_degree():
    rows = data(axial([0.12, 0.14], [1e5, 2e5], [1.0, 2.0]))
    assert geo.bounds(rows, options("braid_angle"), ())["braid_angle"][0] == pytest.approx(1.0, rel=1e-12)


def test_the_widest_pipe_caps_the_braid_angle():
    """D(B/√3) = √(2/3)·D₀/sin α₀ must stay 0.5 % above the widest pipe; pipes narrower than √(2/3)·D₀ cap
    nothing."""
    rows = data(axial([0.149, 0.15], [1e5, 2e5], [1.0, 2.0]))
    high = geo.bounds(rows, options("braid_angle"), (0.03, 0.04))["braid_angle"][1]
    assert _braid(high, L0).largest_diameter == pytest.approx(0.04 * 1.005, rel=1e-12)
    narrow = geo.bounds(rows, options("braid_angle"), (0.015,))["braid_angle"]
    assert narrow[1] == pytest.approx(54.0, rel=1e-12)
    low, high = geo.bounds(data(), options("braid_angle"), (0.03,))["braid_angle"]
    assert low == pytest.approx(1.0, rel=1e-12)
    assert _braid(high, L0).largest_diameter == pytest.approx(0.03 * 1.005, rel=1e-12)


def test_a_braid_angle_range_of_one_point_is_refused():
    given = (("braid_angle", math.radians(20.0), math.radians(20.0)),)
    with pytest.raises(InputError, match="at least 20 deg and at most 20 deg"):
        geo.bounds(data(), options("braid_angle", given=given), ())


def test_no_braid_angle_in_the_domain_is_an_input_error_naming_the_file_and_the_limits():
    rows = data(axial([0.08, 0.16], [1e5, 2e5], [1.0, 2.0]))  # needs B > 0.1608 m and B/√3 < 0.0796 m
    with pytest.raises(InputError, match=r"^lab/exp\.yaml: no braid angle .* at least 21\.1 deg and at most "
                                         r"0 deg"):
        geo.bounds(rows, options("braid_angle"), ())
    assert flat(geo.bounds(rows, options("bladder_thickness"), ())) == pytest.approx(
        flat({"bladder_thickness": (0.375, 6.0)}), rel=1e-12)  # the angle is not calibrated: no error
