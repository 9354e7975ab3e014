"""Standard pipe bores (docs/commands.md §4.3) against published values typed here, not from fluids."""

from __future__ import annotations

import pytest

from pampipe.errors import InputError
from pampipe.specs.pipes import SCHEDULES, bore

INCH = 0.0254

# ASME B36.10M / B36.19M inch columns: (NPS, schedule, outside diameter [in], wall [in], bore [in]).
# Each row is also in the usual schedule charts (e.g. NPS 4 Sch 40: OD 4.500 in, wall 0.237 in, bore
# 4.026 in); the test checks OD - 2 wall = bore too, so a typo in one column shows.
PUBLISHED = [
    ("1/2", 40, 0.840, 0.109, 0.622),
    (1, 40, 1.315, 0.133, 1.049),
    ("1 1/4", 40, 1.660, 0.140, 1.380),
    (2, 80, 2.375, 0.218, 1.939),
    (2, "XXS", 2.375, 0.436, 1.503),
    (3, 40, 3.500, 0.216, 3.068),
    (3, 160, 3.500, 0.438, 2.624),
    (4, 40, 4.500, 0.237, 4.026),
    (6, 40, 6.625, 0.280, 6.065),
    (8, 40, 8.625, 0.322, 7.981),
    (10, 80, 10.750, 0.594, 9.562),
    (10, "80S", 10.750, 0.500, 9.750),    # B36.19M: thinner than B36.10M Sch 80 above NPS 8
    (12, 40, 12.750, 0.406, 11.938),
    (12, "STD", 12.750, 0.375, 12.000),   # STD and Sch 40 part at NPS 12
    (12, "40S", 12.750, 0.375, 12.000),
]
# fluids stores the standards' metric columns: OD rounded to 0.1 mm (<= 0.05 mm) and wall to 0.01 mm
# (<= 0.005 mm, twice), so up to NPS 12 a bore may differ from the inch column by 0.06 mm; 1e-9 m for
# float noise.
METRIC_ROUNDING = 0.06e-3 + 1e-9


@pytest.mark.parametrize(("nps", "schedule", "outside", "wall", "inner"), PUBLISHED)
def test_steel_bores_equal_the_published_inch_columns(nps, schedule, outside, wall, inner):
    assert outside - 2 * wall == pytest.approx(inner, abs=1e-9)  # the typed row is consistent
    size = bore({"nps": nps, "schedule": schedule})
    assert size.nominal == pytest.approx(inner * INCH, abs=METRIC_ROUNDING)
    assert size.low == size.high == size.nominal


def test_nps_3_sch_40_is_the_issue_bore():
    # 3.068 in = 77.927 mm; fluids' metric column: 88.9 mm - 2 x 5.49 mm = 77.92 mm.
    assert bore({"nps": 3, "schedule": 40}).nominal == pytest.approx(77.92e-3, abs=1e-12)


def test_large_sizes_use_the_metric_outside_diameter_rounded_to_a_millimetre():
    # NPS 24 Sch 40: OD 24.000 in, wall 0.688 in, bore 22.624 in = 574.65 mm; the metric column has
    # 610 mm - 2 x 17.48 mm = 575.04 mm (OD rounded 0.4 mm up). Documented in pampipe.specs.pipes.
    assert bore({"nps": 24, "schedule": 40}).nominal == pytest.approx(22.624 * INCH, abs=0.4e-3 + 1e-9)


def test_pe_bore_is_outside_diameter_less_two_walls():
    # ISO 4427 / EN 12201: PE 110 SDR 11 has a 10.0 mm wall, so a 90.0 mm bore.
    size = bore({"dn": 110, "sdr": 11})
    assert size.nominal == pytest.approx(90.0e-3, abs=1e-12)
    assert size.label == "DN 110 SDR 11"
    # SDR 17: 110 / 17 mm wall, exactly (the formula; tables round the wall up, see pampipe.specs.pipes)
    assert bore({"dn": 110, "sdr": 17}).nominal == pytest.approx((110 - 2 * 110 / 17) * 1e-3, rel=1e-12)


@pytest.mark.parametrize(("tolerance", "half_width"), [
    ("1 mm", 1e-3), (0.001, 1e-3), ("0.04 in", 0.04 * INCH), ("2 %", 0.02 * 90e-3), ("2%", 0.02 * 90e-3),
])
def test_tolerance_gives_a_symmetric_range(tolerance, half_width):
    size = bore({"dn": 110, "sdr": 11, "tolerance": tolerance})
    assert size.nominal == pytest.approx(90e-3, abs=1e-12)
    assert size.low == pytest.approx(90e-3 - half_width, abs=1e-12)
    assert size.high == pytest.approx(90e-3 + half_width, abs=1e-12)


def test_length_forms_and_sd():
    assert bore("3 in").nominal == pytest.approx(3 * INCH, rel=1e-12)
    assert bore(0.0762).label == "76.2 mm"
    size = bore({"value": "76.2 mm", "tolerance": "1 mm", "sd": "1 %"})
    assert (size.low, size.high, size.sd) == pytest.approx((75.2e-3, 77.2e-3, 0.762e-3), abs=1e-12)
    assert size.label == "76.2 mm ± 1 mm, sd 1 %"
    assert size.as_document()["inner_diameter_range_m"] == [size.low, size.high]


@pytest.mark.parametrize(("nps", "schedule", "label"), [
    ("1/8", "sch 40", "NPS 1/8 Sch 40 (ASME B36.10M)"),
    ("1-1/2", "xs", "NPS 1 1/2 Sch XS (ASME B36.10M)"),
    (0.75, "10S", "NPS 3/4 Sch 10S (ASME B36.19M)"),
    (36, 10, "NPS 36 Sch 10 (ASME B36.10M)"),
])
def test_sizes_and_schedules_are_read_as_engineers_write_them(nps, schedule, label):
    assert bore({"nps": nps, "schedule": schedule}).label == label


def test_every_schedule_of_the_spec_is_offered():
    # docs/commands.md §4.3: schedules 5 to 160, STD, XS, XXS, 5S to 80S; NPS 1/8 to 36
    for schedule in ("5", "10", "20", "30", "40", "60", "80", "100", "120", "140", "160", "STD", "XS", "XXS",
                     "5S", "10S", "40S", "80S"):
        assert schedule in SCHEDULES
    assert bore({"nps": "1/8", "schedule": 40}).nominal > 0
    assert bore({"nps": 36, "schedule": "STD"}).nominal > 0


@pytest.mark.parametrize(("spec", "words"), [
    ({"nps": 3, "schedule": 20}, ["NPS 3 has no schedule 20", "5, 10, 30, 40, 80, 160, STD, XS, XXS"]),
    ({"nps": 7, "schedule": 40}, ["nps: 7 is not a standard pipe size", "1/8, 1/4", "6, 8"]),
    ({"nps": 3, "schedule": "41"}, ["schedule: '41' is not an ASME schedule", "STD, XS, XXS, 5S"]),
    ({"nps": "three", "schedule": 40}, ["'three' is not a nominal pipe size", "1 1/4"]),
    ({"nps": 3}, ["also needs schedule"]),
    ({"nps": 3, "schedule": 40, "dn": 80}, ["exactly one of", "nps, schedule, dn"]),
    ({"nps": 3, "schedule": 40, "tol": "1 mm"}, ["unknown key tol", "tolerance, sd"]),
    ({"dn": 110, "sdr": 2}, ["sdr: 2 leaves no bore", "11, 13.6"]),
    ({"dn": "110 mm", "sdr": 11}, ["dn: expected a number", "outside diameter in mm"]),
    ({"value": "3 in", "tolerance": "100 %"}, ["not smaller than the bore"]),
    ({"value": "3 in", "tolerance": "-1 mm"}, ["'-1 mm' is negative"]),
    ({"value": "3 in", "tolerance": "+2 %"}, ["cannot read '+2 %' as a percentage"]),
    ({"value": "5 kPa"}, ["inner_diameter.value", "is not a length"]),
    (-0.05, ["is not a pipe bore", "between 0 and 10 m"]),
])
def test_bad_sizes_name_the_value_and_what_is_allowed(spec, words):
    with pytest.raises(InputError) as info:
        bore(spec, where="route[2].inner_diameter")
    message = str(info.value)
    assert message.startswith("route[2].inner_diameter")
    for word in words:
        assert word in message
