"""Property-based fuzzing of the CLI with mutated problem files (issue 7).

PAMPIPE_FUZZ_EXAMPLES cases in all (default 120, the quick profile of `make test`; `make fuzz` runs
10⁴) are split over the commands in proportion to how cheap a case is. The property is in
:func:`tests.fuzzing.probe`: exit 0, 2 or 3 with a message, never a traceback.
"""

from __future__ import annotations

import os
import shutil

import pytest
import yaml
from hypothesis import HealthCheck, given, settings

from tests.conftest import PROBLEMS
from tests.fuzzing import mutated, probe

# an overflow or NaN on an input that passed validation is a bug, not a warning (issue 7, item 3)
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")

TOTAL = int(os.environ.get("PAMPIPE_FUZZ_EXAMPLES", "120"))
SHARE = {"simulate": 0.45, "plan": 0.35, "gait": 0.1, "identify": 0.1}


def fuzz_settings(command: str):
    return settings(max_examples=max(1, round(TOTAL * SHARE[command])), deadline=None,
                    derandomize=not os.environ.get("PAMPIPE_FUZZ_RANDOM"), database=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _load(*parts):
    return yaml.safe_load((PROBLEMS.joinpath(*parts)).read_text())


RADIAL_PAM = _load("pams", "paper-radial-pam.yaml")
MISSION = _load("missions", "vertical-climb-3in.yaml")
EXPERIMENT = _load("experiments", "paper-protocol.yaml")


def _write(folder, name, document):
    path = folder / name
    path.write_text(yaml.safe_dump(document, allow_unicode=True))
    return path


def _mission_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz") / "missions"
    folder.mkdir()
    shutil.copytree(PROBLEMS / "pams", folder.parent / "pams")
    return folder


@fuzz_settings("simulate")
@given(document=mutated(RADIAL_PAM))
def test_simulate_survives_mutated_pam_files(tmp_path_factory, document):
    path = _write(tmp_path_factory.mktemp("fuzz"), "pam.yaml", document)
    probe(["simulate", str(path), "--pipe-diameter", "3 in", "--pressure", "300 kPa", "--json"])


@fuzz_settings("plan")
@given(document=mutated(MISSION))
def test_plan_survives_mutated_missions(tmp_path_factory, document):
    path = _write(_mission_folder(tmp_path_factory), "mission.yaml", document)
    probe(["plan", str(path), "--json"])


@fuzz_settings("gait")
@given(document=mutated(MISSION))
def test_gait_survives_mutated_missions(tmp_path_factory, document):
    path = _write(_mission_folder(tmp_path_factory), "mission.yaml", document)
    probe(["gait", str(path), "--json"])


@fuzz_settings("identify")
@given(document=mutated(EXPERIMENT))
def test_identify_survives_mutated_experiments(tmp_path_factory, document):
    folder = tmp_path_factory.mktemp("fuzz")
    data = folder / "data" / "paper-protocol"
    data.mkdir(parents=True)
    for csv in (PROBLEMS / "experiments" / "data" / "paper-protocol").glob("*.csv"):
        lines = csv.read_text().splitlines()
        data.joinpath(csv.name).write_text("\n".join(lines[:1] + lines[1::6]) + "\n")  # every 6th row
    path = _write(folder, "experiment.yaml", document)
    probe(["identify", str(path), "--json"])
