"""The repository and its bundled problem files, as every test finds them."""

from __future__ import annotations

from pathlib import Path

#: The repository's root (the folder holding pampipe/, problems/ and tests/).
ROOT = Path(__file__).resolve().parents[2]
#: The bundled problems: pams/, missions/, experiments/, inventories/, networks/.
PROBLEMS = ROOT / "problems"
#: The corpus of broken inputs, one folder per case with its case.yaml (tests/commands/test_bad_inputs.py).
BAD_INPUTS = ROOT / "tests" / "bad_inputs"
