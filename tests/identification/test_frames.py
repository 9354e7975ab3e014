"""An identification's tables as DataFrames (issue 42, item 2): the tidy long table, ``coefficients()`` and
``tests_frame()`` (``tests`` is the tuple of fitted tests), each against the ``--json`` document they are read
from."""

from __future__ import annotations

import pytest

import pampipe
from tests.support.problems import PROBLEMS

pandas = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def linear():
    result = pampipe.identify(PROBLEMS / "experiments" / "paper-protocol.yaml", degree=1)
    return result, result.to_dict()


def test_the_long_table_is_one_row_per_pressure_level_of_a_test_with_the_constants_in_attrs(linear):
    result, doc = linear
    frame = result.to_frame()
    expected = [(t["name"], level["pressure_Pa"], level["rmse_N"]) for t in doc["fit"]["tests"]
                for level in t["levels"]]
    assert list(zip(frame["test_name"], frame["pressure_Pa"], frame["rmse_N"], strict=True)) == expected
    # what is the same on every row is not a column: the solver, the moduli, the test's protocol within a test
    assert "solver.iterations" not in frame.columns
    assert frame.attrs["solver.iterations"] == doc["solver"]["iterations"]
    assert frame.attrs["fit.degree"] == 1
    # a degree-1 law [a0, a1] is two coefficients, not an interval
    assert frame.attrs["moduli.axial.a.0"] == doc["moduli"]["axial"]["a"][0]
    assert frame.attrs["moduli.axial.a.1"] == doc["moduli"]["axial"]["a"][1]
    assert not any(c.startswith("moduli.") and c.endswith(("_low", "_high")) for c in frame.attrs)
    assert all(frame[c].astype(str).nunique() > 1 for c in frame.columns if c.startswith("test_"))


def test_coefficients_are_the_json_values_and_intervals_in_mpa(linear):
    result, doc = linear
    table = result.coefficients()
    u = doc["uncertainty"]
    assert list(table["coefficient"]) == u["parameters"]
    assert list(table["value_MPa"]) == u["values"]
    assert [[lo, hi] for lo, hi in zip(table["low_MPa"], table["high_MPa"], strict=True)] == u["interval_95"]
    assert list(table["determined"]) == u["determined"] == [True] * 8
    row = table.set_index("coefficient").loc["theta.hoop.a1"]
    assert (row["stress"], row["term"], row["power"]) == ("hoop", "a", 1)
    # the generating muscle's hoop a0 (4.445 MPa on these data, docs/workflows.md §1.2) lies in its interval
    hoop = table.set_index("coefficient").loc["theta.hoop.a0"]
    assert hoop["low_MPa"] < 4.445 < hoop["high_MPa"]


def test_tests_join_the_fit_and_its_quality_check(linear):
    result, doc = linear
    table = result.tests_frame().set_index("test")
    assert list(table.index) == [t["name"] for t in doc["fit"]["tests"]]
    for quality in doc["fit"]["quality"]["tests"]:
        row = table.loc[quality["test"]]
        assert row["noise_floor_N"] == quality["floor_N"]
        assert row["rmse_over_floor"] == quality["rmse_over_floor"]
    assert table.loc["axial", "points"] == 3000
    assert (table["rmse_N"] < 2.2).all() and (table["rmse_N"] > 1.8).all()  # 2 N of noise


def test_help_says_what_comes_back(linear):
    result, _ = linear
    for method in ("to_frame", "coefficients", "tests_frame", "plot", "to_text"):
        assert len(getattr(type(result), method).__doc__ or "") > 100, method
    assert "attrs" in type(result).to_frame.__doc__
