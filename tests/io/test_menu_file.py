"""The MENU file of `next-test`: kinds, costs, pressure levels, bores the muscle reaches, clear errors."""

from __future__ import annotations

import math

import pytest

from pampipe.errors import InputError
from pampipe.io.menu_file import load_menu
from pampipe.io.pam_schema import load_pam
from tests.support.problems import PROBLEMS

UNCERTAIN = PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml"


def _menu(tmp_path, text: str, pam=None):
    path = tmp_path / "menu.yaml"
    path.write_text(text)
    return load_menu(path, pam or load_pam(UNCERTAIN))


def test_every_kind_in_si(tmp_path):
    menu = _menu(tmp_path, """
tests:
  - {kind: radial, pipe_diameter: 2.5 in, axial_load: 0 N, cost: 1 h}
  - {kind: radial, pipe_diameter: 3 in, axial_load: 1024.74 N, cost: 1.5 h}
  - {kind: isometric, length: 250 mm, cost: 0.5 h}
  - {kind: slip, pipe_diameter: 3 in, trials: 3, cost: 2 h}
  - {kind: axial, pressures: [100 kPa, 800 kPa], cost: 1 h}
pressures: 69 kPa .. 689 kPa in 69 kPa steps
""")
    radial, loaded, isometric, slip, axial = menu.tests
    assert radial.pipe_diameter == pytest.approx(0.0635) and radial.cost == 3600
    assert loaded.axial_load == pytest.approx(1024.74) and loaded.cost == 5400
    assert isometric.length == pytest.approx(0.25) and isometric.pipe_diameter is None
    assert slip.trials == 3 and slip.axial_load == 0
    assert axial.pressures == (1e5, 8e5)
    levels = radial.pressures  # 69, 138, …, 621 kPa, then 689 kPa (the paper's 10 psi steps)
    assert len(levels) == 10 and levels[0] == pytest.approx(69e3) and levels[-1] == pytest.approx(689e3)
    assert levels[8] == pytest.approx(9 * 69e3)
    assert radial.as_document() == {"kind": "radial", "pipe_diameter_m": pytest.approx(0.0635),
                                     "axial_load_N": 0.0, "pressures_Pa": list(levels)}


def test_default_pressures(tmp_path):
    menu = _menu(tmp_path, "tests:\n  - {kind: radial, pipe_diameter: 3 in, cost: 1 h}\n")
    assert menu.tests[0].pressures[-1] == pytest.approx(689e3) and len(menu.tests[0].pressures) == 10


@pytest.mark.parametrize(("entry", "words"), [
    ("{kind: twist, cost: 1 h}", ["tests[0]", "twist", "radial, axial, isometric, slip"]),
    ("{kind: radial, pipe_diameter: 3 in, cost: -1 h}", ["tests[0]", "cost", "at least 0"]),
    ("{kind: radial, pipe_diameter: 2 in, cost: 1 h}", ["tests[0]", "narrower than the muscle at rest"]),
    ("{kind: radial, pipe_diameter: 6 in, cost: 1 h}", ["tests[0]", "wider than the muscle can reach"]),
    ("{kind: isometric, length: 400 mm, cost: 1 h}", ["tests[0]", "length 400 mm"]),
    ("{kind: radial, pipe_diameter: 3 in, cost: 1 kPa}", ["tests[0]", "cost"]),
    ("{kind: axial, cost: 1 h, pressures: 1 kPa to 9 kPa}", ["tests[0].pressures", "LOW .. HIGH"]),
])
def test_bad_entries_name_the_entry(tmp_path, entry, words):
    with pytest.raises(InputError) as info:
        _menu(tmp_path, f"tests:\n  - {entry}\n")
    for word in words:
        assert word in str(info.value)


def test_pam_without_uncertainty(tmp_path):
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    with pytest.raises(InputError, match="no 'uncertainty:' block"):
        _menu(tmp_path, "tests:\n  - {kind: radial, pipe_diameter: 3 in, cost: 1 h}\n", pam)


def test_reach_is_the_braid_limit(tmp_path):
    """The widest bore is D(B/√3) = B√(2/3)/(Nπ), from B = L₀/cos α₀ and N = L₀ tan α₀/(πD₀)."""
    pam = load_pam(UNCERTAIN)
    g = pam.geometry
    alpha = math.radians(90 - 66.4373)
    b = g.initial_length / math.cos(alpha)
    n = g.initial_length * math.tan(alpha) / (math.pi * g.initial_diameter)
    reach = b * math.sqrt(2 / 3) / (n * math.pi)
    entry = "units: SI\ntests:\n  - {{kind: radial, pipe_diameter: {}, cost: 1}}\n"
    ok = _menu(tmp_path, entry.format(reach * 0.999))
    assert ok.tests[0].pipe_diameter < reach
    with pytest.raises(InputError, match="wider than"):
        _menu(tmp_path, entry.format(reach * 1.001))
