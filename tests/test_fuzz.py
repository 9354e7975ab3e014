"""Property-based fuzzing of the CLI with mutated problem files (issue 7).

The quick profile runs in `make test`; `make fuzz` sets PAMPIPE_FUZZ_EXAMPLES=10000 (spread over the
commands) and prints how many cases ran and how they ended.
"""

from __future__ import annotations

import os

import yaml
from hypothesis import HealthCheck, given, settings

from tests.conftest import PROBLEMS
from tests.fuzzing import mutated, probe

EXAMPLES = int(os.environ.get("PAMPIPE_FUZZ_EXAMPLES", "40"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=not os.environ.get("PAMPIPE_FUZZ_RANDOM"),
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
                database=None)

RADIAL_PAM = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())


@FUZZ
@given(document=mutated(RADIAL_PAM))
def test_simulate_survives_mutated_pam_files(tmp_path_factory, document):
    folder = tmp_path_factory.mktemp("fuzz")
    path = folder / "pam.yaml"
    path.write_text(yaml.safe_dump(document, allow_unicode=True))
    probe(["simulate", str(path), "--pipe-diameter", "3 in", "--pressure", "300 kPa", "--json"])
