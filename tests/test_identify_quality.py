"""identify, round 2 of real muscles (issue 23): documented keys work, direction columns are read as
they are coded, no silent bad fit, the slack hinge in the fit, a global calibration."""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.optimize import least_squares

from pampipe.errors import InputError
from pampipe.identification import FitOptions, identify
from pampipe.identification.options import parse_fit_options
from pampipe.io.config import load_experiment
from pampipe.io.csvfile import load_experiment_data
from pampipe.model.effects import LIBRARY
from pampipe.model.muscle import Muscle
from tests import lab_data as lab

ROOT = Path(__file__).resolve().parents[1]


def _formats_fit_block() -> dict:
    """The ``fit:`` example of docs/formats.md, parsed as YAML exactly as printed."""
    text = (ROOT / "docs" / "formats.md").read_text()
    blocks = re.findall(r"```yaml\n(fit:\n.*?)```", text, flags=re.DOTALL)
    assert blocks, "docs/formats.md has no fit: example"
    return yaml.safe_load(blocks[0])["fit"]


def test_calibration_bounds_as_the_docs_write_them():
    raw = _formats_fit_block()
    assert "calibration_bounds" in raw
    options = parse_fit_options({**raw, "calibrate": ["braid_angle", "initial_length"]})
    bounds = {name: (low, high) for name, low, high in options.calibration_bounds}
    assert bounds["braid_angle"] == pytest.approx((math.radians(20), math.radians(30)))
    assert bounds["initial_length"] == pytest.approx((0.300, 0.320))


@pytest.mark.parametrize("value, words", [("[30 deg, 20 deg]", "lower bound"),
                                          ("[20 deg, 25 deg, 30 deg]", "braid_angle"),
                                          ("[20 mm, 30 mm]", "braid_angle")])
def test_bad_calibration_bounds_name_the_key(value, words):
    raw = yaml.safe_load(f"calibration_bounds: {{braid_angle: {value}}}")
    with pytest.raises(InputError) as error:
        parse_fit_options(raw, source="lab.yaml")
    assert "lab.yaml" in str(error.value) and "calibration_bounds" in str(error.value)
    assert words in str(error.value)


# ------------------------------------------------------------------------------ direction columns
def _ramps_with_state(pam, *, shuffle, hysteresis=(6.0, 10e-6), seed=23):
    """Isometric ramps (3 held lengths, hysteresis band, transients after each reversal) with a lab's
    state column coded 1 = filling, 2 = venting; shuffled without a time column when ``shuffle``, so
    that only the state column says which leg a row is on."""
    muscle = lab.truth(pam)
    cols = lab.isometric_ramps(muscle, [0.27, 0.29, pam.geometry.initial_length], hysteresis=hysteresis,
                               noise=1.0, transient=(2.0, 0.3), points=60, rng=np.random.default_rng(seed))
    cols = lab.state_coded(cols)
    if shuffle:
        order = np.random.default_rng(seed + 1).permutation(cols["force"].size)
        cols = {k: v[order] for k, v in cols.items() if k != "time"}
    return cols


def test_a_state_column_coded_1_2_is_refused_naming_file_column_and_values(radial_pam, tmp_path, cli):
    cols = _ramps_with_state(radial_pam, shuffle=False)
    path = lab.write_lab(tmp_path, radial_pam, [(lab.axial("ramps"), cols, None)])
    out = cli("identify", path, "--degree", "1")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "ramps.csv" in out.stderr and "'state'" in out.stderr and "1, 2" in out.stderr
    assert "direction: {column: state, loading: 1, unloading: 2}" in out.stderr  # the way out


@pytest.mark.parametrize("mapping, words", [({"column": "state", "loading": 1, "unloading": 2}, None),
                                             (None, ("filling", "venting")),
                                             (None, ("Loading", "UNLOADING"))])
def test_a_mapped_or_worded_state_column_gives_the_generated_legs(radial_pam, tmp_path, mapping, words):
    """Rows shuffled, no time column: the legs come from the state column alone, and they are the
    generated ones, row by row."""
    cols = _ramps_with_state(radial_pam, shuffle=True)
    text_state = None
    if words:
        text_state = np.where(cols["filling"] > 0, words[0], words[1])
        cols = {**cols, "state": np.zeros(cols["force"].size)}
    path = lab.write_lab(tmp_path, radial_pam, [(lab.axial("ramps"), cols,
                                                 {"direction": mapping} if mapping else None)])
    if text_state is not None:  # a lab's words in place of the codes
        csv = tmp_path / "ramps.csv"
        lines = csv.read_text().splitlines()
        lines[1:] = [",".join([*line.split(",")[:-1], w]) for line, w in zip(lines[1:], text_state,
                                                                             strict=True)]
        csv.write_text("\n".join(lines) + "\n")
    data = load_experiment_data(load_experiment(path))
    test = data.tests[0]
    assert test.direction_source == "column" and test.protocol == "isometric"
    np.testing.assert_array_equal(test.pressure_leg, cols["filling"])


def test_a_word_that_is_no_direction_names_its_line(radial_pam, tmp_path, cli):
    cols = _ramps_with_state(radial_pam, shuffle=False)
    path = lab.write_lab(tmp_path, radial_pam, [(lab.axial("ramps"), cols, None)])
    csv = tmp_path / "ramps.csv"
    lines = csv.read_text().splitlines()
    lines[5] = ",".join([*lines[5].split(",")[:-1], "fill"])
    csv.write_text("\n".join(lines) + "\n")
    out = cli("identify", path, "--degree", "1")
    assert out.returncode == 2 and "line 6" in out.stderr and "'fill'" in out.stderr


@pytest.mark.parametrize("mapping, key", [({"column": "state", "loading": 1, "unloading": 1}, "distinct"),
                                          ({"column": "phase", "loading": 1, "unloading": 2}, "column"),
                                          ({"column": "direction", "loading": 1, "unloading": 2},
                                           "direction")])
def test_a_bad_direction_mapping_is_an_input_error(radial_pam, tmp_path, cli, mapping, key):
    cols = _ramps_with_state(radial_pam, shuffle=False)
    path = lab.write_lab(tmp_path, radial_pam, [(lab.axial("ramps"), cols, {"direction": mapping})])
    out = cli("identify", path, "--degree", "1")
    assert out.returncode == 2 and "Traceback" not in out.stderr and key in out.stderr


def _hysteresis_refit(pam, test, theta0, with_band: bool):
    """Least squares through Muscle (scipy, row by row; independent of identify and diagnose) of the
    moduli, with or without the pressure_hysteresis band, on the measured rows off the turning points."""
    live = (test.force > 0) & (test.pressure_leg != 0)
    params = LIBRARY["pressure_hysteresis"].parameters if with_band else ()

    def residual(z):
        effects = {"pressure_hysteresis": {p.name: z[8 + i] * p.scale for i, p in enumerate(params)}} \
            if with_band else None
        m = Muscle(pam.geometry, z[:8] * 1e6, 1e6, effects=effects)
        model = m.axial_force(test.pressure, test.length, leg=test.leg, pressure_leg=test.pressure_leg)
        return np.asarray(model, float)[live] - test.force[live]

    z0 = np.concatenate([theta0, [p.null / p.scale for p in params]])
    lower = np.concatenate([np.full(8, -60.0), [p.lower / p.scale for p in params]])
    upper = np.concatenate([np.full(8, 60.0), [p.upper / p.scale for p in params]])
    fit = least_squares(residual, np.clip(z0, lower + 1e-9, upper - 1e-9), bounds=(lower, upper),
                        x_scale="jac")
    return float(np.sqrt(np.mean(fit.fun ** 2))), fit.x[8:]


def test_with_the_mapping_the_pressure_hysteresis_is_found(radial_pam, tmp_path):
    """Ramps with a hidden band F = F_ax − sgn(Ṗ)(h₀ + h₁P), h₀ = 6 N, h₁ = 10 N/MPa, state coded 1/2,
    rows shuffled: read through the mapping, the band fits the data to about the noise (σ = 1 N plus
    the 2 N transients) and is recovered; read as 'every row filling' (the old misreading) it cannot
    be fitted at all."""
    cols = _ramps_with_state(radial_pam, shuffle=True)
    mapping = {"column": "state", "loading": 1, "unloading": 2}
    path = lab.write_lab(tmp_path, radial_pam, [(lab.axial("ramps"), cols, {"direction": mapping})])
    test = load_experiment_data(load_experiment(path)).tests[0]
    theta0 = np.array([1.5, 0, 0, 0, 4.4, -1.6, 0, 0])
    baseline, _ = _hysteresis_refit(radial_pam, test, theta0, False)
    banded, (h0, h1) = _hysteresis_refit(radial_pam, test, theta0, True)
    assert baseline > 5.0 and banded < 1.3
    assert h0 == pytest.approx(6.0, abs=0.6) and h1 == pytest.approx(10.0, abs=2.0)
    misread = replace(test, pressure_leg=np.ones_like(test.pressure_leg))
    assert _hysteresis_refit(radial_pam, misread, theta0, True)[0] > 5.0


# ------------------------------------------------------------------------------- no silent bad fit
@pytest.fixture(scope="module")
def muscle(radial_pam):
    return lab.truth(radial_pam)


def _misfit_warnings(result):
    return [w for w in result.warnings if "noise floor" in w or "structured" in w]


def test_a_wrong_angle_without_calibration_warns_naming_the_geometry(radial_pam, muscle):
    """A lab's force map (3 pressures, longest length 1.3 % short of L₀, σ = 1 N) fitted at a braid
    angle stated 4° off and no calibration: the RMSE is tens of times the noise; the report says so,
    connects the moduli at their bounds to it, names the geometry and the next step, and says the
    true reason the blocked-force check could not run."""
    cols = lab.short_force_map(muscle, rng=np.random.default_rng(31))
    data = lab.experiment(radial_pam, [(lab.axial("map"), cols)],
                          stated=lab.off_by(radial_pam.geometry, angle_deg=4))
    result = identify(data, FitOptions(degree=1))
    q = result.as_document()["fit"]["quality"]
    assert q["rmse_over_floor"] > 5 and set(q) >= {"rmse_over_floor", "at_bounds", "structured"}
    (warning,) = _misfit_warnings(result)
    assert "geometry" in warning and "--calibrate braid_angle" in warning and "map" in warning
    for name in q["at_bounds"]:
        assert name in warning  # moduli at their bounds are tied to the misfit
    reason = result.calibration.blocked_force_skipped
    assert "1.3 %" in reason and "below the rest length" in reason
    assert result.as_document()["geometry"]["blocked_force_check_skipped"] == reason


def test_clean_data_reach_their_floor_without_a_misfit_warning(radial_pam, muscle):
    """Data from the stated muscle (σ = 1 N): RMSE/floor near 1, no structure, no misfit warning;
    the floor itself estimates the generated σ."""
    rng = np.random.default_rng(32)
    g = radial_pam.geometry
    data = lab.experiment(radial_pam, [
        (lab.axial("ramps"), lab.isometric_ramps(muscle, [0.27, 0.29, g.initial_length], points=80, rng=rng)),
        (lab.radial("pipe-3in", 0.0762), lab.split_pipe(muscle, 0.0762, rng=rng))])
    result = identify(data, FitOptions(degree=1))
    q = result.quality
    assert q.rmse_over_floor < 1.5 and not q.structured and not _misfit_warnings(result)
    for test in q.tests:  # 400-480 live rows: σ̂ within ±25 % of σ = 1 N
        assert 0.75 < test.floor < 1.25


def test_a_small_systematic_misfit_is_called_structured(radial_pam, muscle):
    """A hysteresis band of ±1.5 N (well inside 3x the noise in RMSE) left unmodelled: the residual
    keeps one sign along each leg, so the runs test and the autocorrelation call it structured, and
    the report warns although the RMSE is under 3x the floor."""
    g = radial_pam.geometry
    cols = lab.isometric_ramps(muscle, [0.27, 0.29, g.initial_length], points=80, hysteresis=(1.5, 0.0),
                               rng=np.random.default_rng(33))
    result = identify(lab.experiment(radial_pam, [(lab.axial("ramps"), cols)]), FitOptions(degree=1))
    q = result.quality
    assert q.rmse_over_floor < 3 and q.structured
    (warning,) = _misfit_warnings(result)
    assert "structured" in warning and "ramps" in warning
    assert "hysteresis" in warning and "diagnose" in warning  # the legs differ by the band, 2 x 1.5 N
    assert q.tests[0].leg_gap == pytest.approx(3.0, abs=0.3)


def test_the_report_prints_the_quality_and_the_true_skip_reason(radial_pam, muscle, tmp_path, cli):
    cols = lab.short_force_map(muscle, rng=np.random.default_rng(34))
    path = lab.write_lab(tmp_path, lab.Pam(radial_pam.name, lab.off_by(radial_pam.geometry, angle_deg=4)),
                         [(lab.axial("map"), cols, None)])
    out = cli("identify", path, "--degree", "1")
    assert out.returncode == 0
    assert "RMSE / noise floor" in out.stdout and "warning: the fit misses the data" in out.stdout
    assert "fewer than 3" not in out.stdout and "1.3 % below the rest length" in out.stdout
    out = cli("identify", path, "--degree", "1", "--json")
    quality = json.loads(out.stdout)["fit"]["quality"]
    assert quality["rmse_over_floor"] > 5 and isinstance(quality["structured"], bool)
