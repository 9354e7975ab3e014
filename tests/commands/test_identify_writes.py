"""`identify -o` writes the PAM of every fit that reaches the data; `plan` decides where the rest matters.

Issue 35, build 3: what the data do not determine goes into the PAM's ``uncertainty: undetermined:``
(interfaces §8.1) instead of a refusal; only a failed solve writes nothing (test_identify.py checks that).
"""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

from pampipe.cli import main
from pampipe.io.pam_schema import load_pam
from pampipe.model.pam import Pam
from pampipe.simulation.synthetic import Protocol, generate
from tests.support.lab_data import write_lab
from tests.support.problems import PROBLEMS

FESTO = PROBLEMS / "experiments" / "festo-dmsp20-300.yaml"
CLIMB = PROBLEMS / "missions" / "vertical-climb-3in.yaml"


def cli(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def mission_with(tmp_path, pam_path, bore: str):
    """The bundled climb with every segment carrying ``pam_path`` and every section of bore ``bore``."""
    text = CLIMB.read_text().replace("../pams/paper-radial-pam.yaml", str(pam_path))
    text = text.replace("inner_diameter: 3 in", f"inner_diameter: {bore}")
    text = text.replace("inner_diameter: 3.5 in", f"inner_diameter: {bore}")
    path = tmp_path / f"climb-{bore.replace(' ', '')}.yaml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def festo_pam(tmp_path_factory):
    out = tmp_path_factory.mktemp("festo") / "fit.yaml"
    code = main(["identify", str(FESTO), "-o", str(out), "--json"])
    return code, out


def test_the_measured_map_writes_its_pam_at_the_default_degree(festo_pam):
    code, out = festo_pam
    assert code == 0 and out.exists()
    pam = load_pam(out)
    assert pam.moduli.degree == 3 and pam.uncertainty is not None
    # the map (one held-length grid, no radial test) leaves directions open: listed, not refused
    assert pam.uncertainty.undetermined
    assert all(d.test for d in pam.uncertainty.undetermined)


@pytest.mark.parametrize("bore", ["1.25 in", "3 in"])
def test_plan_reads_the_written_pam_and_decides(festo_pam, tmp_path, capsys, bore):
    """1.25 in (31.75 mm): the muscle anchors, the open directions move it little: a plan (0), or a stop with
    its reason (3). 3 in: wider than this braid opens (at most ~43 mm): no solution, with the reason (3)."""
    _, fit = festo_pam
    code, out, err = cli(capsys, "plan", mission_with(tmp_path, fit, bore), "--confidence", "0.95",
                         "--samples", "1000", "--json")
    assert code in (0, 3), err
    doc = json.loads(out)
    reasons = [sec.get("reason") for sec in doc["sections"] if sec.get("reason")] + doc.get("reasons", [])
    if bore == "3 in":
        assert code == 3 and not doc["feasible"] and "wider than the braid" in reasons[0]
        assert doc["confidence"]["sources"][0]["pressure_shift_Pa"] is None  # nothing feasible to add to
    elif code == 3:
        assert reasons, doc
    else:
        assert doc["feasible"]
        assert all(s["pressure_Pa"] > 0 for sec in doc["sections"] for s in sec["segments"])


def test_a_fit_with_loose_tolerances_writes_too(tmp_path, capsys):
    """Axial data only, from a muscle stated with loose tolerances: most coefficients are undetermined,
    and the fit still writes its PAM with them listed."""
    stated = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    loose = {"initial_length": 5e-3, "initial_diameter": 2e-3, "braid_angle": math.radians(3.0),
             "bladder_thickness": 0.5e-3}
    base = Pam(stated.name, stated.geometry, None, geometry_sd=loose, fitting_length=stated.fitting_length)
    tests = [(spec, cols, None) for spec, cols in generate(stated, Protocol(pipes=(), cycles=1), seed=3)]
    lab = write_lab(tmp_path, base, tests)
    out = tmp_path / "fit.yaml"
    code, _, err = cli(capsys, "identify", lab, "-o", out)
    assert code == 0, err
    pam = load_pam(out)
    assert pam.uncertainty.undetermined
    assert pam.geometry_sd["braid_angle"] == pytest.approx(loose["braid_angle"])


def test_one_row_per_test_writes_a_pam_that_lists_what_is_open(tmp_path, capsys):
    """Issue 27's case (one row per test): a PAM is written, and nearly every direction is listed open."""
    folder = tmp_path / "exp"
    shutil.copytree(PROBLEMS / "experiments", folder)
    for csv in (folder / "data" / "paper-protocol").glob("*.csv"):
        lines = csv.read_text().splitlines()
        csv.write_text("\n".join(lines[:2]) + "\n")
    out = tmp_path / "fit.yaml"
    code, _, err = cli(capsys, "identify", folder / "paper-protocol.yaml", "-o", out)
    assert code == 0, err
    assert len(load_pam(out).uncertainty.undetermined) >= 10  # of 16 coefficients: 5 rows fix a few


def test_a_stated_angle_only_seeds_the_calibration(tmp_path, capsys):
    """Build 7: catalogue angles 15-45 deg (45 deg puts the map's 237 mm below the stated braid's B/sqrt(3) =
    245 mm) each calibrate to the one geometry of the map and write their PAM; each calibrated fit reaches
    the map's floor and is not warned about (build 5, below: the same fit uncalibrated misses by far)."""
    shutil.copytree(FESTO.parent / "data" / "festo-dmsp20-300", tmp_path / "data" / "festo-dmsp20-300")
    text = FESTO.read_text()
    found = []
    for angle in ("15", "20", "30", "39.6", "45"):
        stated = tmp_path / f"stated-{angle}.yaml"
        stated.write_text(text.replace("braid_angle_from_axis: 26.07 deg",
                                       f"braid_angle_from_axis: {angle} deg"))
        out = tmp_path / f"fit-{angle}.yaml"
        code, stdout, err = cli(capsys, "identify", stated, "--calibrate", "braid_angle", "--calibrate",
                                "initial_length", "-o", out, "--json")
        assert code == 0 and out.exists(), err
        assert "misses the data" not in err and json.loads(stdout)["fit"]["quality"]["rmse_over_floor"] < 3
        geometry = json.loads(stdout)["geometry"]
        found.append((geometry["braid_angle_from_axis_deg"], geometry["initial_length_m"]))
        written = load_pam(out).geometry
        assert math.degrees(written.braid_angle) == pytest.approx(found[-1][0], abs=1e-3)
    angles, lengths = np.array(found).T
    # one minimum from every seed (the multi-start merges minima within 0.05 deg and 0.05 mm)
    assert np.ptp(angles) < 0.05 and np.ptp(lengths) < 0.05e-3
    assert 20 < angles[0] < 30  # not a seed's value: the map's (blocked-force slope: 26.07 deg)


@pytest.fixture
def stated_30(tmp_path):
    """The measured map stated at a catalogue 30 deg (its braid is 26.1 deg), beside a copy of its data."""
    shutil.copytree(FESTO.parent / "data" / "festo-dmsp20-300", tmp_path / "data" / "festo-dmsp20-300")
    path = tmp_path / "stated-30.yaml"
    path.write_text(FESTO.read_text().replace("braid_angle_from_axis: 26.07 deg",
                                              "braid_angle_from_axis: 30 deg"))
    return path


def test_a_bad_fit_of_the_measured_map_is_not_silent(stated_30, capsys):
    """Build 5: from a stated 30 deg without calibration the fit misses by 113 N. The model-free floor stays
    at the map's noise (2.27 N, as for the right geometry), so the fit is warned about with the next step.
    Calibrated, the same map fits to its floor and is not warned about: test_a_stated_angle_only_seeds_the_
    calibration checks it for this and four other stated angles (one fit less here)."""
    _, out, err = cli(capsys, "identify", stated_30, "--json")
    doc = json.loads(out)
    floor = doc["fit"]["quality"]["tests"][0]["floor_N"]
    assert floor == pytest.approx(2.27, abs=0.05) and doc["fit"]["quality"]["rmse_over_floor"] > 30
    assert "misses the data by far more than the noise" in err and "--calibrate braid_angle" in err


def test_a_pam_fitted_with_radial_data_plans_without_a_stop(tmp_path, capsys):
    """Build 4 on radial data: the bundled protocol (axial and radial tests) writes a PAM whose open
    directions move the demo climb's C = 0.95 plan by < 1 kPa (measured 0.6-0.9 Pa): far below a tenth of
    its margin to the 689 kPa supply, so no segment stops (before: 1-4.6 kPa directions stopped 14 of 44)."""
    from pampipe.planning.sampling import OPEN_SHARE

    fit = tmp_path / "fit.yaml"
    code, _, err = cli(capsys, "identify", PROBLEMS / "experiments" / "paper-protocol.yaml", "-o", fit)
    assert code == 0 and load_pam(fit).uncertainty.undetermined, err  # directions are open: plan decides
    mission = tmp_path / "climb.yaml"
    mission.write_text(CLIMB.read_text().replace("../pams/paper-radial-pam.yaml", str(fit)))
    code, out, err = cli(capsys, "plan", mission, "--confidence", "0.95", "--samples", "1000", "--json")
    assert code == 0, err
    doc = json.loads(out)
    supply = 689e3  # the climb's supply_pressure [Pa]
    for segment in (s for section in doc["sections"] for s in section["segments"]):
        assert segment["undetermined"] is False and segment["pressure_Pa"] > 0
        assert 0 <= segment["undetermined_shift_Pa"] < 1e3
        assert segment["undetermined_shift_Pa"] < OPEN_SHARE * (supply - segment["pressure_Pa"])
