"""The synthetic-experiment generator: protocol, exact model values, noise, files and CLI."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.cli import main
from pampipe.errors import InputError
from pampipe.identification.noise import held_length_paths
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.experiment_schema import load_experiment
from pampipe.io.pamfile import write_experiment
from pampipe.model import forces
from pampipe.model.muscle import Muscle
from pampipe.simulation.synthetic import PAPER_LOAD, PAPER_PIPES, Protocol, generate
from pampipe.specs.experiment import make_test_data


def test_protocol_shape_and_noise_free_values(radial_pam):
    tests = generate(radial_pam, Protocol(force_noise=0.0), seed=0)
    names = [spec.name for spec, _ in tests]
    assert names == ["axial", "radial-76.2mm-0N", "radial-76.2mm-1025N", "radial-88.9mm-0N",
                     "radial-88.9mm-1025N"]
    spec, axial = tests[0]
    assert axial["force"].size == 10 * 3 * 2 * 50  # pressures x cycles x legs x points
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    model = forces.axial_force(axial["pressure"], axial["length"], g, theta)
    np.testing.assert_allclose(axial["force"], model)
    # each leg spans L0 .. L_free(P); at 689 kPa the demo muscle contracts to 209.3 mm (docs/physics.md §7)
    top = axial["pressure"] == axial["pressure"].max()
    assert axial["length"][top].max() == pytest.approx(g.initial_length)
    shortest = Muscle(g, theta).free_length(Protocol().pressures[-1])[0]
    assert axial["length"][top].min() == pytest.approx(shortest, abs=1e-9)
    assert axial["length"][top].min() == pytest.approx(0.2093, abs=2e-4)
    for spec, radial in tests[1:]:
        assert spec.pipe_diameter in PAPER_PIPES and spec.axial_load in (0.0, PAPER_LOAD)
        expected = forces.radial_force(radial["pressure"], spec.pipe_diameter, g, theta, 1e6, spec.axial_load)
        np.testing.assert_allclose(radial["force"], expected)
    # below the anchoring pressure (117 kPa in the 3 in pipe without load) the force is zero
    radial = tests[1][1]
    assert np.all(radial["force"][radial["pressure"] < 117e3] == 0)
    assert np.all(radial["force"][radial["pressure"] > 118e3] > 0)


def test_noise_has_the_requested_size_and_seed(radial_pam):
    clean = generate(radial_pam, Protocol(force_noise=0.0, pressure_noise=0.0), seed=1)[0][1]
    noisy = generate(radial_pam, Protocol(force_noise=3.0, pressure_noise=1500.0), seed=1)[0][1]
    again = generate(radial_pam, Protocol(force_noise=3.0, pressure_noise=1500.0), seed=1)[0][1]
    np.testing.assert_array_equal(noisy["force"], again["force"])
    # 3000 draws: the sample standard deviation is within ±5 % (≈ 4 standard errors)
    assert np.std(noisy["force"] - clean["force"]) == pytest.approx(3.0, rel=0.05)
    assert np.std(noisy["pressure"] - clean["pressure"]) == pytest.approx(1500.0, rel=0.05)


def test_written_experiment_loads_back(tmp_path, radial_pam):
    tests = generate(radial_pam, Protocol(points_per_leg=10), seed=2)
    target = write_experiment(tmp_path, "demo", radial_pam, tests)
    data = load_experiment_data(load_experiment(target))
    generated = generate(radial_pam, Protocol(points_per_leg=10), seed=2)
    for test, (spec, columns) in zip(data.tests, generated, strict=True):
        assert test.name == spec.name and test.kind == spec.kind
        # CSV precision: 1e-4 kPa, 1e-4 N, 1e-5 mm
        np.testing.assert_allclose(test.pressure, columns["pressure"], atol=0.06)
        np.testing.assert_allclose(test.force, columns["force"], atol=6e-5)
        if test.kind == "axial":
            np.testing.assert_allclose(test.length, columns["length"], atol=6e-9)
    assert data.pam.geometry.braid_angle == pytest.approx(radial_pam.geometry.braid_angle, rel=1e-8)
    with pytest.raises(InputError, match="already exists"):
        write_experiment(tmp_path, "demo", radial_pam, tests)


def test_synth_cli(tmp_path, capsys):
    args = ["synth", str(tmp_path), "--seed", "4", "--force-noise", "0.5 N", "--points-per-leg", "5"]
    assert main(args) == 0
    assert (tmp_path / "experiment.yaml").exists()
    assert len(list((tmp_path / "data" / "experiment").glob("*.csv"))) == 5
    assert main(["synth", str(tmp_path)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert main(["synth", str(tmp_path / "x"), "--force-noise", "5 kPa"]) == 2  # a force in kPa
    assert "is not a force" in capsys.readouterr().err


def test_synth_force_noise_bare_zero_is_noise_free(tmp_path):
    """`--force-noise 0` (no unit) is read as 0 N: the same files as `--force-noise '0 N'`."""
    for name, noise in (("bare", "0"), ("newton", "0 N")):
        assert main(["synth", str(tmp_path / name), "--seed", "1", "--force-noise", noise,
                     "--points-per-leg", "5"]) == 0
    bare = sorted((tmp_path / "bare").rglob("*.csv"))
    assert bare and [p.read_bytes() for p in bare] == [
        (tmp_path / "newton" / p.relative_to(tmp_path / "bare")).read_bytes() for p in bare]


def test_a_held_length_protocol_is_a_force_map_of_the_closed_form(radial_pam):
    """``Protocol(held_lengths=N)``: N lengths L₀ − (j/N)(L₀ − L_free(689 kPa)) (L_free 209.3 mm for the
    demo muscle, docs/physics.md §7), each held while the pressure ramps up to 689 kPa and down; every row
    taut; the seeded noisy forces are the closed form F_ax(P, L) (forces.axial_force) plus 2 N noise."""
    protocol = Protocol(held_lengths=6, points_per_leg=20, cycles=2, pipes=())
    (spec, axial), = generate(radial_pam, protocol, seed=3)
    assert axial["force"].size == 6 * 2 * 2 * 20
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    lengths = np.unique(axial["length"])
    expected = g.initial_length - np.arange(6)[::-1] / 6 * (g.initial_length - 0.2093)
    np.testing.assert_allclose(lengths, expected, atol=2e-4)
    model = forces.axial_force(axial["pressure"], axial["length"], g, theta)
    miss = axial["force"] - model
    assert np.std(miss) == pytest.approx(2.0, rel=0.1) and abs(np.mean(miss)) < 4 * 2.0 / np.sqrt(miss.size)
    assert np.all(model >= 0)  # taut: a force map records tension only
    for length in lengths:
        mine = axial["length"] == length
        pressure = axial["pressure"][mine]
        assert pressure.max() == pytest.approx(Protocol().pressures[-1], rel=0.06)  # up to 689 kPa
        step = (Protocol().pressures[-1] - Protocol().pressures[0]) / 100
        below = max(pressure.min() - step, Protocol().pressures[0])  # one step lower: slack (or the least P)
        if below < pressure.min():
            assert forces.axial_force(below, length, g, theta) < 0
        order = np.argmax(pressure)  # one ramp up, then down, per cycle
        assert np.all(np.diff(pressure[:order]) > 0) and pressure[0] == pressure.min()
    clean = generate(radial_pam, dataclasses.replace(protocol, force_noise=0.0), seed=3)[0][1]
    np.testing.assert_allclose(clean["force"], model)
    again = generate(radial_pam, protocol, seed=3)[0][1]
    np.testing.assert_array_equal(again["force"], axial["force"])
    data = make_test_data(spec, axial)
    assert data.protocol == "isometric"
    assert np.unique(held_length_paths(axial["length"])).size == 6


def test_synth_held_lengths_cli(tmp_path, capsys):
    """`synth --held-lengths N` writes the force map (N held lengths, 2 × points × cycles rows each) that
    identify reads as an isometric test; more lengths than identify reads as held ones exit 2."""
    args = ["synth", str(tmp_path), "--held-lengths", "5", "--points-per-leg", "6", "--cycles", "1"]
    assert main(args) == 0
    data = load_experiment_data(load_experiment(tmp_path / "experiment.yaml"))
    axial = next(t for t in data.tests if t.kind == "axial")
    assert axial.points == 5 * 2 * 6 and axial.protocol == "isometric"
    assert np.unique(np.round(axial.length, 5)).size == 5
    assert "held at 5 lengths" in (tmp_path / "experiment.yaml").read_text()
    capsys.readouterr()
    assert main(["synth", str(tmp_path / "x"), "--held-lengths", "31"]) == 2
    assert "held_lengths: 31 is not allowed; give 0 (the paper's length cycles) to 30" in \
        capsys.readouterr().err
