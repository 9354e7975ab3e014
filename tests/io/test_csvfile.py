"""CSV loading (io.csvfile, experiment): SI conversion, precise errors, chunking, levels and legs."""

from __future__ import annotations

import re

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.io import csvfile as data_module
from pampipe.io.csvfile import read_csv
from pampipe.specs.experiment import legs_and_cycles, pressure_levels

AXIAL = ("pressure", "length", "force")


def write(tmp_path, text, name="test.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_units_in_headers_are_converted_to_si(tmp_path):
    path = write(tmp_path, "time [min],pressure [psi],length [in],force [kN]\n1,10,12,2\n2,20,11.5,3.5\n")
    columns = read_csv(path, required=AXIAL)
    # exact definitions: 1 psi = 6894.757293 Pa, 1 in = 0.0254 m, 1 kN = 1000 N, 1 min = 60 s
    np.testing.assert_allclose(columns["pressure"], [68947.57293168, 137895.14586336], rtol=1e-12)
    np.testing.assert_allclose(columns["length"], [0.3048, 0.2921], rtol=1e-12)
    np.testing.assert_allclose(columns["force"], [2000.0, 3500.0], rtol=1e-12)
    np.testing.assert_allclose(columns["time"], [60.0, 120.0], rtol=1e-12)


def test_extra_columns_and_blank_lines_are_ignored(tmp_path):
    path = write(tmp_path, "pressure [kPa], force [N], note [1]\n100,5,0\n\n200,6,1\n")
    columns = read_csv(path, required=("pressure", "force"))
    np.testing.assert_array_equal(columns["pressure"], [1e5, 2e5])
    assert set(columns) == {"pressure", "force"}


@pytest.mark.parametrize(("text", "expected"), [
    ("", "the file is empty"),
    ("pressure [kPa],length [mm],force [N]\n", "header but no data rows"),
    ("pressure [kPa],force [N]\n1,2\n", "missing column(s) length"),
    ("pressure,length [mm],force [N]\n1,2,3\n", "line 1, column 1: header 'pressure' has no unit"),
    ("pressure [kPa],length [kPa],force [N]\n1,2,3\n", "the unit [kPa] is not a length"),
    ("pressure [kPa],length [furlongz],force [N]\n1,2,3\n", "unknown unit 'furlongz'"),
    ("pressure [kPa],length [mm],force [N]\n1,2,3\n4,x,6\n", "line 3, column 2 (length): 'x' is not a"),
    ("pressure [kPa],length [mm],force [N]\n1,2,3\n4,,6\n", "line 3, column 2 (length): an empty cell"),
    ("pressure [kPa],length [mm],force [N]\n1,2,nan\n", "line 2, column 3 (force): 'nan' is not a finite"),
    ("pressure [kPa],length [mm],force [N]\n1,2,inf\n", "line 2, column 3 (force): 'inf' is not a finite"),
    ("pressure [kPa],length [mm],force [N]\n1,2,3\n4,5\n", "line 3: has 2 cells but the header has 3"),
    ("pressure [kPa],pressure [kPa],force [N]\n1,2,3\n", "appears twice"),
])
def test_malformed_csv_names_file_line_and_column(tmp_path, text, expected):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as info:
        read_csv(path, required=AXIAL)
    assert str(path) in str(info.value)
    assert expected in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="data file not found"):
        read_csv(tmp_path / "nope.csv", required=AXIAL)


def test_chunked_reading_matches_and_keeps_line_numbers(tmp_path, monkeypatch):
    rows = [f"{i},{i * 0.5},{i * 2}" for i in range(1, 101)]
    path = write(tmp_path, "pressure [Pa],length [m],force [N]\n" + "\n".join(rows) + "\n")
    whole = read_csv(path, required=AXIAL)
    monkeypatch.setattr(data_module, "BLOCK_BYTES", 50)  # about 4 rows a block, the last one short
    chunked = read_csv(path, required=AXIAL)
    for name in AXIAL:
        np.testing.assert_array_equal(whole[name], chunked[name])
    np.testing.assert_array_equal(chunked["pressure"], np.arange(1, 101))
    rows[57] = "58,oops,116"  # data row 58 is file line 59, in a later block
    write(tmp_path, "pressure [Pa],length [m],force [N]\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputError, match=r"line 59, column 2 \(length\): 'oops'"):
        read_csv(path, required=AXIAL)


def test_pressure_levels_of_a_stepped_protocol_with_noise():
    rng = np.random.default_rng(3)
    steps = np.array([69e3, 138e3, 207e3, 276e3])
    truth = np.repeat(np.arange(4), 250)
    rng.shuffle(truth)
    pressure = steps[truth] + 2e3 * rng.standard_normal(truth.size)  # 2 kPa noise, 69 kPa steps
    level, medians = pressure_levels(pressure)
    np.testing.assert_array_equal(level, truth)
    np.testing.assert_allclose(medians, steps, atol=1e3)  # median of 250 draws: SE ≈ 0.16 kPa


def test_a_pressure_ramp_falls_back_to_equal_count_bins():
    pressure = np.linspace(0, 7e5, 1000)
    level, medians = pressure_levels(pressure)
    assert medians.size == 10
    np.testing.assert_array_equal(np.bincount(level), np.full(10, 100))
    assert np.all(np.diff(medians) > 0)


def test_legs_and_cycles_of_a_triangle_wave():
    one_cycle = np.concatenate([np.linspace(0.31, 0.25, 20, endpoint=False),
                                np.linspace(0.25, 0.31, 20, endpoint=False)])
    length = np.tile(one_cycle, 3)
    leg, cycle = legs_and_cycles(length, np.zeros(length.size, dtype=int))
    # shortening first (-1), then lengthening (+1); the central difference (window 2) shifts the
    # switch by at most one row at each turning point
    assert np.all(leg[1:19] == -1) and np.all(leg[21:39] == 1)
    assert set(np.unique(cycle)) == {0, 1, 2}
    assert np.all(cycle[:19] == 0) and np.all(cycle[-15:] == 2)


def test_a_file_that_would_not_fit_in_memory_is_refused_before_it_is_read(tmp_path, monkeypatch):
    """The row count is estimated from the file size; a file whose rows need more than the available
    memory is refused with a clear message (the available memory is lowered for the test)."""
    monkeypatch.setattr(data_module.os, "sysconf", lambda name: {"SC_AVPHYS_PAGES": 10,
                                                                 "SC_PAGE_SIZE": 4096}[name])
    path = tmp_path / "big.csv"
    path.write_text("pressure [kPa], force [N]\n" + "100, 5\n" * 1300)
    with pytest.raises(InputError, match=r"would need .* GB of memory"):
        read_csv(path, required=("pressure", "force"))


@pytest.mark.parametrize("text", ["1,2,3\n4,5,6\n", "1,2,3\n\n4,5,6\n", "1.5,-2e3,3\n4,5,6\n"])
def test_the_fast_reader_gives_the_chunked_readers_numbers(tmp_path, monkeypatch, text):
    path = write(tmp_path, "pressure [Pa],length [m],force [N]\n" + text * 50)
    chunked = read_csv(path, required=AXIAL)
    monkeypatch.setattr(data_module, "FAST_BYTES", 0)
    fast = read_csv(path, required=AXIAL)
    for name in AXIAL:
        np.testing.assert_array_equal(fast[name], chunked[name])


@pytest.mark.parametrize(("text", "expected"), [
    ("1,2,3\n4,x,6\n", "line 3, column 2 (length): 'x' is not a"),
    ("1,2,3\n4,5\n", "line 3: has 2 cells but the header has 3"),
    ("1,2,nan\n", "line 2, column 3 (force): 'nan' is not a finite"),
])
def test_the_fast_reader_still_names_the_bad_line(tmp_path, monkeypatch, text, expected):
    monkeypatch.setattr(data_module, "FAST_BYTES", 0)
    path = write(tmp_path, "pressure [kPa],length [mm],force [N]\n" + text)
    with pytest.raises(InputError, match=re.escape(expected)):
        read_csv(path, required=AXIAL)


def test_fill_and_group_order_equal_their_searching_and_merging_forms():
    """protocol._fill (a running maximum) equals the search per row it replaced, and group_order (a radix
    sort where the groups fit in uint16) equals the stable argsort, with few groups and with more."""
    from pampipe.specs.protocol import _fill, group_order

    rng = np.random.default_rng(5)
    for size in (0, 1, 7, 50_000):
        signs = rng.choice(np.array([-1, 0, 0, 1], dtype=np.int8), size)
        nonzero = np.flatnonzero(signs)
        at = np.maximum(np.searchsorted(nonzero, np.arange(size), side="right") - 1, 0)
        expected = signs[nonzero[at]] if nonzero.size else signs
        assert np.array_equal(_fill(signs), expected)
        for groups in (rng.integers(0, 11, size), rng.integers(0, 2**17, size)):
            assert np.array_equal(group_order(groups), np.argsort(groups, kind="stable"))


def test_median_above_equals_the_median_compared():
    """rate_sign's lag test counts the values above the threshold instead of taking their median: the
    same answer for odd and even sizes, thresholds at, between and beside the middle values, and ties."""
    from pampipe.specs.protocol import _median_above

    rng = np.random.default_rng(6)
    for size in (1, 2, 3, 4, 5, 10, 11, 1000, 1001):
        for values in (rng.uniform(0, 1, size), np.round(rng.uniform(0, 1, size), 1)):
            middle = np.sort(values)[[(size - 1) // 2, size // 2]]
            for threshold in (*middle, middle.mean(), np.nextafter(middle.mean(), 0), -1.0, 2.0, 0.5):
                assert _median_above(values, threshold) == (np.median(values) > threshold), (size, threshold)
