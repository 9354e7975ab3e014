"""`pampipe next-test` end to end: the docs' example, the JSON keys of interfaces §9.4, the Python API."""

from __future__ import annotations

import json

import pampipe
from pampipe.cli import main
from tests.support.problems import PROBLEMS

PAM = PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml"
MISSION = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
MENU = PROBLEMS / "menus" / "radial-menu.yaml"


def test_json_keys_and_order(capsys):
    code = main(["next-test", str(PAM), str(MISSION), "--menu", str(MENU), "--samples", "1000", "--check",
                 "0",
                 "--json", "--reproducible"])
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["current"]["pressure_Pa"] > 0
    assert len(doc["ranked"]) == 7
    for row in doc["ranked"]:
        assert set(row["test"]) <= {"kind", "pipe_diameter_m", "axial_load_N", "length_m", "trials",
                                    "pressures_Pa"}
        assert row["cost_s"] > 0
        assert {"pressure_Pa", "pressure_sd_Pa", "closes_undetermined"} <= set(row["predicted"])
    per_hour = [r["predicted"]["drop_per_hour_Pa"] for r in doc["ranked"]]
    assert per_hour == sorted(per_hour, reverse=True)
    radial = next(r for r in doc["ranked"] if r["label"] == "radial 76.2 mm, 1024.74 N")
    assert radial["test"] == {"kind": "radial", "pipe_diameter_m": 0.0762, "axial_load_N": 1024.74,
                              "pressures_Pa": [69000.0 * k for k in range(1, 10)] + [689000.0]}
    assert {"test", "predicted"} <= set(doc["d_optimal"])
    assert doc["wall_time_s"] == 0


def test_text_and_api():
    result = pampipe.next_test(PAM, MISSION, menu=MENU, samples=1000, pairs=True)
    assert len(result.ranking.ranked) == 7 + 21
    text = str(result)
    assert "D-optimal pick" in text and "rank" in text
    assert repr(result).startswith("<NextTest ")


def test_skeleton_identify_reads_once_filled(tmp_path, capsys):
    """-o DIR: the best test as an experiment; its rows filled with the true muscle's forces (and 2 N noise),
    identify reads it, with the old fit as its prior."""
    import numpy as np

    from pampipe.io.pam_schema import load_pam
    from pampipe.model.muscle import Muscle

    out = tmp_path / "next"
    assert main(["next-test", str(PAM), str(MISSION), "--menu", str(MENU), "--samples", "500", "--check", "0",
                 "-o", str(out)]) == 0
    capsys.readouterr()
    experiment = out / "next-test.yaml"
    assert (out / "pam.yaml").is_file() and experiment.is_file()
    csv = next((out / "data").glob("*.csv"))
    header, *rows = csv.read_text().splitlines()
    # isometric 250 mm is ranked first
    assert header == "pressure [kPa],length [mm],force [N]" and len(rows) == 10
    truth = Muscle.from_pam(load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml"))
    rng = np.random.default_rng(2)
    filled = [header]
    for row in rows:
        pressure, length, force = row.split(",")
        assert force == "" and float(length) == 250
        for _ in range(20):
            f = float(truth.axial_force(float(pressure) * 1e3, 0.25)) + 2 * rng.standard_normal()
            filled.append(f"{pressure},{length},{f:.4f}")
    csv.write_text("\n".join(filled) + "\n")
    assert main(["identify", str(experiment), "-o", str(tmp_path / "refit.yaml")]) == 0
    refit = load_pam(tmp_path / "refit.yaml")
    assert refit.uncertainty is not None and refit.moduli is not None
