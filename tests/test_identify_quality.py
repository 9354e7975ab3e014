"""identify, round 2 of real muscles (issue 23): documented keys work, direction columns are read as
they are coded, no silent bad fit, the slack hinge in the fit, a global calibration."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
import yaml

from pampipe.errors import InputError
from pampipe.identification.options import parse_fit_options

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
