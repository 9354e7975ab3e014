"""The starts and minima of a calibrated fit (pampipe/identification/multistart.py), with fake screens and
solves whose answers are set here: the screened grid (12 braid angles at the centres of 12 equal cells of the
range), the 3 lowest local minima of the profile, the seeds after them, clipping into the bounds, starts
0.5° / 0.5 mm apart dropped; solutions merged within 0.05, the runner-ups (RMSE within 1.25 × the best's,
geometry 1°, 0.5 % or 25 % away) and the report's words."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.identification import multistart

CAL = ("braid_angle", "initial_length")
LOWER, UPPER = [0.0, 140.0], [48.0, 160.0]  # the grid is (j + ½)·4° = 2°, 6°, …, 46°: exact in binary


def profile_screen(values, rest=150.0):
    """screen(x) -> the SSE given for the grid cell of the braid angle x[0] (checks x[1] is ``rest``)."""
    def screen(x):
        assert x[1] == rest
        j = (x[0] / 4.0) - 0.5
        assert j == round(j)
        return values[round(j)]
    return screen


def test_the_screened_grid_and_its_three_lowest_local_minima_come_first():
    """Local minima (ends included: the profile is padded with +inf) at 6° (3.0), 22° (2.0), 34° (1.5) and
    46° (1.0): the three lowest are 46°, 34°, 22°, in that order, then the seeds."""
    values = [5, 3.0, 4, 6, 4, 2.0, 7, 8, 1.5, 9, 9, 1.0]
    starts, screened = multistart.start_points(CAL, LOWER, UPPER, [24.0, 150.0], [("stated", [24.0, 150.0])],
                                               profile_screen(values))
    assert screened == 12
    assert [label for label, _ in starts] == ["braid angle 46 deg (screened)",
                                              "braid angle 34 deg (screened)",
                                              "braid angle 22 deg (screened)", "stated"]
    assert np.array([x for _, x in starts]).tolist() == [[46.0, 150.0], [34.0, 150.0], [22.0, 150.0],
                                                         [24.0, 150.0]]


def test_the_grid_spans_the_cells_of_the_range():
    seen = []

    def screen(x):
        seen.append(float(x[0]))
        return 1.0

    multistart.start_points(("braid_angle",), [1.0], [54.0], [24.0], [], screen)
    assert seen == pytest.approx([1.0 + (j + 0.5) * 53.0 / 12 for j in range(12)], rel=1e-14)


def test_a_flat_profile_gives_its_first_three_points_and_a_rising_one_its_first():
    """Equal neighbours are both minima (``<=``); ties keep the grid's order."""
    starts, _ = multistart.start_points(CAL, LOWER, UPPER, [24.0, 150.0], [], profile_screen([1.0] * 12))
    assert [float(x[0]) for _, x in starts] == [2.0, 6.0, 10.0]
    starts, _ = multistart.start_points(CAL, LOWER, UPPER, [24.0, 150.0], [],
                                        profile_screen([float(j) for j in range(12)]))
    assert [float(x[0]) for _, x in starts] == [2.0]
    starts, _ = multistart.start_points(CAL, LOWER, UPPER, [24.0, 150.0], [],
                                        profile_screen([float(-j) for j in range(12)]))
    assert [float(x[0]) for _, x in starts] == [46.0]


def test_seeds_are_clipped_into_the_bounds_and_a_missing_seed_is_skipped():
    """Clipped 1e-6 of the range inside each bound; the stated rest length 170 mm (beyond 160) too."""
    starts, _ = multistart.start_points(CAL, LOWER, UPPER, [24.0, 170.0],
                                        [("blocked force", None), ("slopes", [60.0, 130.0])],
                                        profile_screen([float(j) for j in range(12)], 160.0 - 20e-6))
    assert [label for label, _ in starts] == ["braid angle 2 deg (screened)", "slopes"]
    assert starts[0][1].tolist() == [2.0, 160.0 - 20e-6]
    assert starts[1][1] == pytest.approx([48.0 - 48e-6, 140.0 + 20e-6], rel=1e-15)
    assert starts[1][1][0] < 48.0 and starts[1][1][1] > 140.0


def test_a_start_within_half_a_degree_and_half_a_millimetre_of_an_earlier_one_is_dropped():
    """Both entries must be close (``all``); 0.5 exactly is close."""
    seeds = [("a", [10.5, 150.0]), ("b", [10.5, 150.6]), ("c", [11.0, 150.0]), ("d", [10.0, 149.5]),
             ("e", [10.75, 150.25]), ("f", [9.497, 150.0])]
    values = [9.5, 9.0, 1.0] + [9.0 + j for j in range(9)]  # one screened start: 10°
    starts, _ = multistart.start_points(CAL, LOWER, UPPER, [24.0, 150.0], seeds, profile_screen(values))
    assert [label for label, _ in starts] == ["braid angle 10 deg (screened)", "b", "c", "f"]


def test_without_a_calibrated_braid_angle_nothing_is_screened():
    def screen(x):
        raise AssertionError("no screening without the braid angle")

    starts, screened = multistart.start_points(("initial_length",), [140.0], [160.0], [150.0],
                                               [("stated", [150.0]), ("slopes", [150.4]), ("past", [150.503]),
                                                ("far", [151.2])], screen)
    assert screened == 0 and [label for label, _ in starts] == ["stated", "past", "far"]


def fake(answers: dict):
    """run(x) -> (payload, sse, fitted) from ``answers`` keyed by the start's braid angle; None fails."""
    def run(x):
        answer = answers[float(x[0])]
        if answer is None:
            raise SolverError(f"start {x[0]:g} failed", status="Error_In_Step_Computation")
        sse, fitted = answer
        return f"payload {x[0]:g}", sse, np.array(fitted, float)
    return run


STARTS = [(name, np.array([angle, 150.0])) for name, angle in
          [("A", 1.0), ("B", 2.0), ("C", 3.0), ("D", 4.0), ("E", 5.0), ("F", 6.0)]]
ANSWERS = {1.0: (8.0, [20.0, 150.0]), 2.0: (7.9, [20.04, 150.03]), 3.0: (9.0, [30.0, 150.0]),
           4.0: (8.5, [20.5, 150.0]), 5.0: (20.0, [40.0, 150.0]), 6.0: None}


def test_solutions_are_merged_sorted_and_runner_ups_named():
    """A and B end 0.04°, 0.03 mm apart (one minimum, B's lower cost first); D ends 0.46° from it (another
    minimum, but not far); C 10° away with an RMSE √(9/7.9) = 1.07 × the best's (a runner-up); E's RMSE is
    √(20/7.9) = 1.59 × (not one); F fails."""
    report, payload = multistart.search(fake(ANSWERS), STARTS, CAL, rows=4, screened=12)
    assert payload == "payload 2"
    assert [(m.starts, m.geometry, m.sse) for m in report.minima] == [
        (("B", "A"), (20.04, 150.03), 7.9), (("D",), (20.5, 150.0), 8.5), (("C",), (30.0, 150.0), 9.0),
        (("E",), (40.0, 150.0), 20.0)]
    assert report.best.rmse == pytest.approx(math.sqrt(7.9 / 4), rel=1e-15) and report.reached_best == 2
    assert report.failed == ("F",) and [m.starts for m in report.runner_ups()] == [("C",)]
    assert report.describe() == [
        "global calibration: 6 starts (after screening 12 braid angles), 2 reached the best (RMSE 1.405 N at "
        "braid_angle 20.04 deg, initial_length 150.03 mm), 1 failed; 3 other local minima",
        "runner-up minima close in cost but far in geometry: RMSE 1.5 N at braid_angle 30 deg, "
        "initial_length 150 mm (1 starts)"]
    doc = report.as_document()
    assert {k: doc[k] for k in ("starts", "reached_best", "failed", "screened", "close_rmse_factor")} == {
        "starts": 6, "reached_best": 2, "failed": 1, "screened": 12, "close_rmse_factor": 1.25}
    assert doc["best"] == {"rmse_N": report.best.rmse, "sse_N2": 7.9, "starts": 2, "from": ["B", "A"],
                           "braid_angle_from_axis_deg": 20.04, "initial_length_m": pytest.approx(0.15003)}
    assert [m["from"] for m in doc["runner_up_minima"]] == [["C"]] and len(doc["minima"]) == 4
    assert doc["start_points"][0] == {"from": "A", "braid_angle": 1.0, "initial_length": 150.0}
    assert doc["seed_from_force_slopes"] is None


def test_one_start_one_minimum_in_the_singular():
    report, _ = multistart.search(fake({1.0: (4.0, [20.0, 150.0])}), STARTS[:1], CAL, rows=0)
    assert report.best.rmse == 2.0  # rows 0 counts as 1
    assert report.describe() == ["global calibration: 1 start, 1 reached the best (RMSE 2 N at braid_angle "
                                 "20 deg, initial_length 150 mm)",
                                 "runner-up minima close in cost but far in geometry: none"]
    report, _ = multistart.search(fake({1.0: (4.0, [20.0, 150.0]), 2.0: (5.0, [20.5, 150.0])}), STARTS[:2],
                                  CAL, rows=1)
    assert report.describe()[0].endswith("; 1 other local minimum")
    report, _ = multistart.search(fake({1.0: (4.0, [20.0, 150.0]), 2.0: (5.0, [20.5, 150.0]),
                                        3.0: (6.0, [21.0, 150.0])}), STARTS[:3], CAL, rows=1)
    assert report.describe()[0].endswith("; 2 other local minima")
    unscreened = multistart.Search(CAL, report.starts, report.minima, (), None)
    assert unscreened.screened == 0 and unscreened.describe()[0].startswith("global calibration: 3 starts, ")


def test_minima_are_one_within_0_05_in_each_entry():
    answers = {1.0: (1.0, [0.0, 0.0]), 2.0: (2.0, [0.05, 0.05]), 3.0: (3.0, [0.0, 0.0500001]),
               4.0: (4.0, [0.0500001, 0.0])}
    report, _ = multistart.search(fake(answers), STARTS[:4], CAL, rows=1)
    assert [m.starts for m in report.minima] == [("A", "B"), ("C",), ("D",)]


@pytest.mark.parametrize(("other", "far"), [
    ((21.0, 200.0, 4.0), False), ((21.000001, 200.0, 4.0), True), ((19.0, 200.0, 4.0), False),
    ((18.999999, 200.0, 4.0), True), ((20.0, 201.0, 4.0), False), ((20.0, 201.000001, 4.0), True),
    ((20.0, 199.0, 4.0), False), ((20.0, 200.0, 5.0), False), ((20.0, 200.0, 5.000001, ), True),
    ((20.0, 200.0, 2.999999), True)])
def test_far_is_1_degree_half_a_percent_of_the_rest_length_or_a_quarter_of_the_wall(other, far):
    """Relative to the best's rest length (200 mm) and wall (4 mm); an RMSE exactly 1.25 × the best's is
    close."""
    names = ("braid_angle", "initial_length", "bladder_thickness")
    run = fake({1.0: (16.0, [20.0, 200.0, 4.0]), 2.0: (25.0, list(other))})
    starts = [("best", np.array([1.0, 0, 0])), ("other", np.array([2.0, 0, 0]))]
    report, _ = multistart.search(run, starts, names, rows=1)
    assert report.minima[1].rmse == 1.25 * report.best.rmse
    assert len(report.runner_ups()) == (1 if far else 0)


def test_an_rmse_beyond_1_25_times_the_best_is_no_runner_up():
    run = fake({1.0: (16.0, [20.0, 150.0]), 2.0: (25.0 + 1e-9, [30.0, 150.0])})
    report, _ = multistart.search(run, STARTS[:2], CAL, rows=1)
    assert report.runner_ups() == []


def test_every_start_failing_without_a_fallback_raises_the_first_failure():
    with pytest.raises(SolverError, match="start 1 failed"):
        multistart.search(fake({1.0: None, 2.0: None}), STARTS[:2], CAL, rows=1)


def test_wall_thicknesses_are_one_start_within_0_05_mm_and_one_minimum_within_0_01_mm():
    """1.05 − 1.0 is a hair above 0.05 in floating point (0.05000000000000004): a start of its own."""
    starts, _ = multistart.start_points(("bladder_thickness",), [0.5], [2.0], [1.0],
                                        [("stated", [1.0]), ("thicker", [1.05]), ("near", [1.04])], None)
    assert [label for label, _ in starts] == ["stated", "thicker"]
    ends = {1.0: (1.0, 1.0), 2.0: (2.0, 1.01), 3.0: (3.0, 1.009)}  # start -> (SSE, fitted thickness)

    def run(x):
        sse, fitted = ends[float(x[0])]
        return "payload", sse, np.array([fitted])

    starts = [(name, np.array([key])) for name, key in (("A", 1.0), ("B", 2.0), ("C", 3.0))]
    report, _ = multistart.search(run, starts, ("bladder_thickness",), rows=1)
    assert [m.starts for m in report.minima] == [("A", "C"), ("B",)]
