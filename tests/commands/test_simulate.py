"""`pampipe simulate` end to end, and every error path of the foundation issue (exit codes, messages)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import yaml

from pampipe.errors import InputError
from pampipe.io.pamfile import write_pam
from pampipe.model import braid, forces
from pampipe.model.domain import check_length, check_pipe_diameter, check_pressure
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names
from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

RADIAL = PROBLEMS / "pams" / "paper-radial-pam.yaml"
AXIAL = PROBLEMS / "pams" / "paper-axial-load-pam.yaml"


def test_simulate_json_document(axial_load_pam):
    """The issue's 'done when' command prints the docs/commands.md §2.2 document with the model's numbers."""
    out = run_cli("simulate", AXIAL, "--pipe-diameter", "3 in", "--axial-load", "1024.74 N",
                  "--pressure", "400 kPa", "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    for key in ("pipe_diameter_m", "anchored_length_m", "amplification_factor", "anchoring_pressure_Pa"):
        assert key in doc
    (point,) = doc["points"]
    assert set(point) >= {"pressure_Pa", "radial_force_N", "radial_force_per_length_N_per_m",
                          "contact_pressure_Pa", "anchored"}
    g, theta = axial_load_pam.geometry, axial_load_pam.moduli.as_vector()
    length = braid.length_at_diameter(0.0762, g)
    assert doc["pipe_diameter_m"] == pytest.approx(0.0762, rel=1e-11)
    assert doc["anchored_length_m"] == pytest.approx(288.88e-3, abs=0.005e-3)  # docs/physics.md §7
    expected = forces.radial_force(4e5, 0.0762, g, theta, 1e6, 1024.74)
    # JSON carries 12 significant digits (pampipe.io.files.JSON_DIGITS): compare to 1e-11 relative
    assert point["radial_force_N"] == pytest.approx(expected, rel=1e-11)
    # independent: F_r/(D L), F_r/L, and A(F_ax − F_a) from the unclipped force balance
    assert point["contact_pressure_Pa"] == pytest.approx(expected / (0.0762 * length), rel=1e-11)
    assert point["radial_force_per_length_N_per_m"] == pytest.approx(expected / length, rel=1e-11)
    assert point["anchored"] is True
    assert sum(point["eq14_terms_N"].values()) == pytest.approx(expected, rel=1e-9)


def test_simulate_below_anchoring_gives_zero_force():
    out = run_cli("simulate", RADIAL, "-d", "3 in", "-p", "50 kPa", "-p", "117.5 kPa", "--json")
    doc = json.loads(out.stdout)
    low, high = doc["points"]
    assert low["radial_force_N"] == 0.0 and low["anchored"] is False
    assert high["radial_force_N"] > 0 and high["anchored"] is True
    assert doc["anchoring_pressure_Pa"] == pytest.approx(117.0e3, abs=0.5e3)


def test_simulate_paper_literal_contact_pressure_is_pi_smaller():
    a = json.loads(run_cli("simulate", RADIAL, "-d", "3 in", "-p", "400 kPa", "--json").stdout)
    b = json.loads(run_cli("simulate", RADIAL, "-d", "3 in", "-p", "400 kPa", "--json",
                           "--paper-literal").stdout)
    assert a["points"][0]["contact_pressure_Pa"] == pytest.approx(
        math.pi * b["points"][0]["contact_pressure_Pa"], rel=1e-11)


def test_simulate_text_table_and_plots(tmp_path):
    out = run_cli("simulate", RADIAL, "-d", "3 in", "-d", "3.5 in", "-f", "0 N", "-f", "1024.74 N",
                  "--plots", tmp_path / "plots")
    assert out.returncode == 0, out.stderr
    assert "anchoring pressure 117.00 kPa" in out.stdout
    for name in ("radial_force.png", "free_contraction.png", "amplification.png"):
        png = (tmp_path / "plots" / name).read_bytes()
        assert png.startswith(b"\x89PNG")  # what they draw: tests/views/test_plots_style.py
    assert not list((tmp_path / "plots").glob("*.tmp"))


def _pam_file(tmp_path, mutate):
    data = yaml.safe_load(RADIAL.read_text())
    mutate(data)
    path = tmp_path / "pam.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


CONFIG_ERRORS = {
    "misspelt key": (lambda d: d["geometry"].update(initial_lenght="300 mm"),
                     ["unknown key 'geometry.initial_lenght'", "allowed keys here: initial_length"]),
    "wrong dimension": (lambda d: d["geometry"].update(initial_diameter="5 kPa"),
                        ["geometry.initial_diameter", "'5 kPa' is not a length"]),
    "negative length": (lambda d: d["geometry"].update(bladder_thickness="-1 mm"),
                        ["geometry.bladder_thickness", "must be greater than 0"]),
    "absurd length": (lambda d: d["geometry"].update(initial_length="1e30 m"),
                      ["geometry.initial_length", "must be at most 10 m"]),
    "both angles": (lambda d: d["geometry"].update(braid_angle_from_axis="24 deg"),
                    ["exactly one of braid_angle_from_transverse", "both were given"]),
    "no angle": (lambda d: d["geometry"].pop("braid_angle_from_transverse"),
                 ["exactly one of braid_angle_from_transverse", "neither was given"]),
    "extensile braid": (lambda d: d["geometry"].update(braid_angle_from_transverse="24.08 deg"),
                        ["is extensile", "never presses on a pipe wall"]),
    "missing key": (lambda d: d.pop("geometry"), ["missing required key 'geometry'"]),
    "NaN value": (lambda d: d["geometry"].update(initial_length="nan mm"), ["not a finite number"]),
    "no moduli": (lambda d: d.pop("moduli"), ["has no 'moduli:' block", "pampipe identify"]),
    "ragged moduli": (lambda d: d["moduli"]["hoop"].update(a=[1.0]), ["same length"]),
}


@pytest.mark.parametrize("case", CONFIG_ERRORS)
def test_bad_pam_file_exits_2_with_message(tmp_path, case):
    mutate, fragments = CONFIG_ERRORS[case]
    path = _pam_file(tmp_path, mutate)
    out = run_cli("simulate", path, "-d", "3 in")
    assert out.returncode == 2, out.stderr
    assert "Traceback" not in out.stderr + out.stdout
    assert str(path) in out.stderr
    for fragment in fragments:
        assert fragment in out.stderr


@pytest.mark.parametrize(("args", "fragments"), [
    (["-d", "2 in"], ["not wider than the muscle at rest", "57.15 mm"]),
    (["-d", "6 in"], ["wider than the braid can reach"]),
    (["-d", "5 kPa"], ["--pipe-diameter", "not a length"]),
    (["-d", "3 in", "-p", "-5 kPa"], ["outside the allowed gauge-pressure range"]),
    (["-d", "3 in", "-f", "3 m"], ["--axial-load", "not a force"]),
])
def test_bad_simulate_arguments_exit_2(args, fragments):
    out = run_cli("simulate", RADIAL, *args)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    for fragment in fragments:
        assert fragment in out.stderr


@pytest.mark.parametrize(("content", "fragment"), [
    (None, "not found"),
    ("", "is empty"),
    ("- a\n- b\n", "must be a YAML mapping"),
    ("name: x\nname: y\n", "duplicate key 'name'"),
    ("geometry: [1, 2\n", "invalid YAML"),
])
def test_unreadable_pam_files_exit_2(tmp_path, content, fragment):
    path = tmp_path / "pam.yaml"
    if content is not None:
        path.write_text(content)
    out = run_cli("simulate", path, "-d", "3 in")
    assert out.returncode == 2 and fragment in out.stderr and "Traceback" not in out.stderr


def test_domain_checks_raise_instead_of_nan(radial_pam):
    g = radial_pam.geometry
    with pytest.raises(InputError, match="not wider than the muscle at rest"):
        check_pipe_diameter(g, 0.05)
    with pytest.raises(InputError, match="wider than the braid can reach"):
        check_pipe_diameter(g, g.largest_diameter * 1.001)
    with pytest.raises(InputError, match=r"outside the braid's range"):
        check_length(g, g.shortest_length * 0.99)
    with pytest.raises(InputError, match=r"outside the braid's range"):
        check_length(g, g.braid_length * 1.01)
    with pytest.raises(InputError, match="gauge-pressure range"):
        check_pressure(float("nan"))
    # everything inside the checked domain evaluates to finite numbers
    theta = radial_pam.moduli.as_vector()
    diameters = np.linspace(g.initial_diameter * 1.0001, g.largest_diameter * 0.9999, 200)
    check_pipe_diameter(g, diameters)
    values = forces.radial_force(np.linspace(0, 1e7, 200), diameters, g, theta, 1e6, 1e4)
    assert np.all(np.isfinite(values))


def test_simulate_bare_zero_load_is_zero_newton(cli):
    """The README's `-f 0` (no unit) is read as 0 N: the same document as `-f '0 N'`."""
    bare = cli("simulate", RADIAL, "-d", "3 in", "-f", "0", "--json")
    newton = cli("simulate", RADIAL, "-d", "3 in", "-f", "0 N", "--json")
    assert bare.returncode == 0 and newton.returncode == 0
    assert json.loads(bare.stdout) == json.loads(newton.stdout)


def _open_and_closed(tmp_path, pam):
    """``pam`` written twice to ``tmp_path``: open.yaml, whose fit leaves hoop.a0 and an axial.b1/b2
    combination undetermined, and closed.yaml, the same uncertainty with no open direction."""
    names = moduli_names(3)
    hoop, axial = np.zeros(16), np.zeros(16)
    hoop[names.index("hoop.a0")] = 1.0
    axial[[names.index("axial.b1"), names.index("axial.b2")]] = [0.8, -0.6]
    test = "a radial test at 76.2 mm (3 in)"
    open_ = (UndeterminedDirection(hoop, 2.0, {"radial_force_N@0.0762m": 30.0}, test),
             UndeterminedDirection(axial, 5.0, {}, test))
    u = ParameterUncertainty(names, np.diag(np.r_[np.full(8, 0.05e6), np.zeros(8)] ** 2), 0.0, open_)
    pam = dataclasses.replace(pam, name="axial-only").with_uncertainty(u)
    write_pam(tmp_path / "open.yaml", pam)
    write_pam(tmp_path / "closed.yaml", pam.with_uncertainty(dataclasses.replace(u, undetermined=())))
    return tmp_path / "open.yaml", tmp_path / "closed.yaml"


def _check_open_directions(opened, closed, quantity: str) -> None:
    """Exit 0 both; one stderr line naming each direction (by its largest weight), what rests on them and the
    tests that would close them; the PAM's ``undetermined`` list (as identify writes it) in the JSON, which
    otherwise equals the closed PAM's; the closed PAM: no warning, no key."""
    assert opened.returncode == 0 and closed.returncode == 0, opened.stderr + closed.stderr
    (line,) = [x for x in opened.stderr.splitlines() if x.startswith("warning:")]
    assert "2 parameter direction(s) undetermined" in line and "hoop.a0, axial.b1" in line
    assert f"{quantity} rest on fitted values" in line
    assert "a radial test at 76.2 mm (3 in) (2 of them)" in line
    assert not [x for x in closed.stderr.splitlines() if x.startswith("warning:")]
    doc, plain = json.loads(opened.stdout), json.loads(closed.stdout)
    assert doc.pop("undetermined") == [
        {"direction": {"hoop.a0": 1.0}, "scale": 2.0, "moves": {"radial_force_N@0.0762m": 30.0},
         "test": "a radial test at 76.2 mm (3 in)"},
        {"direction": {"axial.b1": 0.8, "axial.b2": -0.6}, "scale": 5.0, "moves": {},
         "test": "a radial test at 76.2 mm (3 in)"}]
    assert "undetermined" not in plain and doc == plain


def test_open_directions_warn_in_one_line_and_list_in_json(tmp_path, radial_pam):
    """A PAM whose fit leaves directions open, simulated in a pipe: exit 0 and the same forces as without
    them, one warning line and the ``undetermined`` list (:func:`_check_open_directions`)."""
    files = _open_and_closed(tmp_path, radial_pam)
    args = ("-d", "3 in", "-p", "400 kPa", "--json")
    _check_open_directions(*(run_cli("simulate", f, *args) for f in files), "these forces")


def test_open_directions_warn_without_a_pipe(tmp_path):
    """An extensile PAM simulated free (no pipe) whose fit leaves directions open warns and lists them as
    in a pipe (issue 35): its lengths rest on the same fitted moduli."""
    from pampipe.io.pam_schema import load_pam

    files = _open_and_closed(tmp_path, load_pam(PROBLEMS / "pams" / "extensile-steering.yaml"))
    args = ("-p", "100 kPa", "-p", "200 kPa", "--json")
    _check_open_directions(*(run_cli("simulate", f, *args) for f in files), "these lengths")
