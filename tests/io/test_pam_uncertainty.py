"""The PAM file's uncertain inputs: `{value, sd}` geometry, the joint `uncertainty:`, the maker's limits."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.io.pam_schema import load_pam
from pampipe.io.pamfile import write_pam
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names
from tests.support.problems import PROBLEMS

UNCERTAIN = PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml"


def _joint(radial_pam) -> ParameterUncertainty:
    """16 moduli, braid angle, initial length: a random PSD covariance (SI), one undetermined direction."""
    names = (*moduli_names(3), "braid_angle", "initial_length")
    rng = np.random.default_rng(5)
    sizes = np.r_[np.full(16, 0.2e6), math.radians(0.5), 0.4e-3]  # 0.2 MPa, 0.5 deg, 0.4 mm
    a = rng.normal(size=(18, 12)) * sizes[:, None]  # rank 12: six directions of zero variance
    vector = np.zeros(18)
    vector[[8, 9, 16]] = [0.6, -0.64, 0.48]  # a unit vector: hoop.a0, hoop.a1, braid_angle
    direction = UndeterminedDirection(vector, 2.5, {"radial_force_N@0.0762m": -41.5,
                                                    "anchoring_pressure_Pa@0.0762m": 1.2e4},
                                      "a radial test at 76.2 mm (3 in)")
    return ParameterUncertainty(names, a @ a.T, 3.25, (direction,))


def test_round_trip(tmp_path, radial_pam):
    """Write a PAM with every uncertain input, read it back: the same muscle (up to unit rounding)."""
    u = _joint(radial_pam)
    pam = replace(radial_pam, geometry_sd={"initial_length": 0.5e-3, "braid_angle": math.radians(1.0)},
                  max_pressure=6e5, max_contraction=0.25).with_uncertainty(u)
    target = tmp_path / "pam.yaml"
    write_pam(target, pam)
    back = load_pam(target)
    assert back.uncertainty.names == u.names
    np.testing.assert_allclose(back.uncertainty.covariance, u.covariance, rtol=1e-13, atol=0)
    np.testing.assert_allclose(back.covariance, u.covariance[:16, :16], rtol=1e-13, atol=0)
    assert back.uncertainty.model_error == pytest.approx(3.25, rel=1e-15)
    assert back.uncertainty.undetermined == u.undetermined  # exact: written as shortest round-trip floats
    assert back.geometry_sd == pytest.approx(pam.geometry_sd, rel=1e-14)
    assert back.max_pressure == pytest.approx(6e5, rel=1e-15)
    assert back.max_contraction == 0.25
    assert back.geometry.braid_angle == pytest.approx(pam.geometry.braid_angle, rel=1e-14)
    # and once more: the written file is a fixed point
    write_pam(tmp_path / "again.yaml", back)
    again = load_pam(tmp_path / "again.yaml")
    np.testing.assert_allclose(again.uncertainty.covariance, u.covariance, rtol=1e-13, atol=0)
    assert again.uncertainty.undetermined == u.undetermined


def test_old_uncertainty_block_loads_as_moduli_only():
    """``uncertainty: {unit, covariance}`` (no parameters) is the covariance of the 16 moduli, in unit²."""
    pam = load_pam(UNCERTAIN)
    u = pam.uncertainty
    assert u.names == moduli_names(3) and u.model_error == 0 and u.undetermined == ()
    assert u.covariance[0, 0] == pytest.approx((0.1e6) ** 2)  # sd 0.1 MPa on axial.a0 (the file's comment)
    assert u.covariance[8, 9] == pytest.approx(-0.6 * 0.15e6 * 0.3e6)
    np.testing.assert_array_equal(pam.covariance, u.covariance)
    assert pam.geometry_sd == {} and pam.max_pressure is None and pam.max_contraction is None


def _raw(**changes) -> dict:
    raw = {"name": "x", "geometry": {"initial_length": "314.325 mm", "initial_diameter": "57.15 mm",
                                     "braid_angle_from_transverse": "65.92 deg",
                                     "bladder_thickness": "3.175 mm"},
           "moduli": {"axial": {"a": [1.5, 0, 0, 0], "b": [0, 0, 0, 0]},
                      "hoop": {"a": [4.444, -1.615, 0, 0], "b": [0, 0, 0, 0]}}}
    for key, value in changes.items():
        raw[key] = value
    return raw


def test_value_sd_geometry_and_limits():
    """Any geometry entry may be {value, sd}; the transverse angle's sd is the same angle from the axis."""
    raw = _raw(max_pressure="6 bar", max_contraction="25 %")
    raw["geometry"] |= {"initial_diameter": {"value": "57.15 mm", "sd": "0.2 mm"},
                        "braid_angle_from_transverse": {"value": "65.92 deg", "sd": "1 deg"}}
    pam = load_pam("p.yaml", raw=raw)
    assert pam.geometry.initial_diameter == pytest.approx(57.15e-3)
    assert pam.geometry.braid_angle == pytest.approx(math.radians(90 - 65.92))
    assert pam.geometry_sd == pytest.approx({"initial_diameter": 0.2e-3, "braid_angle": math.radians(1)})
    assert pam.max_pressure == pytest.approx(6e5) and pam.max_contraction == pytest.approx(0.25)


def test_hand_written_direction_is_normalised_keeping_its_step():
    """A direction {hoop.a0: 2} with scale 1 is the unit vector with scale 2: the same SI step, 2 MPa."""
    raw = _raw(uncertainty={"covariance": np.zeros((16, 16)).tolist(),
                            "undetermined": [{"direction": {"hoop.a0": 2}, "test": "a radial test at 3 in"}]})
    u = load_pam("p.yaml", raw=raw).uncertainty
    d = u.undetermined[0]
    assert d.scale == 2 and d.vector[8] == 1 and np.count_nonzero(d.vector) == 1
    assert u.step(d)[8] == pytest.approx(2e6)


def _not_psd() -> np.ndarray:
    """Unit variances, correlations 0.9 (a0, a1) and -0.9 (a1, a2): eigenvalue 1 - 0.9·√2 < 0."""
    cov = np.eye(16)
    cov[0, 1] = cov[1, 0] = 0.9
    cov[1, 2] = cov[2, 1] = -0.9
    return cov


@pytest.mark.parametrize(("change", "named"), [
    ({"uncertainty": {"covariance": [[1, 2], [2, 1]], "parameters": ["axial.a0", "braid_angle"]}},
     "uncertainty.parameters"),
    ({"uncertainty": {"covariance": (-np.eye(16)).tolist()}}, "uncertainty: covariance"),
    ({"uncertainty": {"covariance": _not_psd().tolist()}}, "positive semi-definite"),
    ({"uncertainty": {"covariance": np.ones((15, 15)).tolist()}}, "uncertainty.covariance"),
    ({"uncertainty": {"covariance": np.zeros((16, 16)).tolist(),
                      "undetermined": [{"direction": {"hoop.c0": 1}}]}},
     "uncertainty.undetermined[0].direction"),
    ({"uncertainty": {"covariance": np.zeros((16, 16)).tolist(), "model_error": "-1 N"}}, "model_error"),
    ({"max_contraction": "120 %"}, "max_contraction"),
    ({"max_pressure": "6 mm"}, "max_pressure"),
])
def test_bad_uncertain_inputs_name_the_key(change, named):
    with pytest.raises(InputError) as err:
        load_pam("p.yaml", raw=_raw(**change))
    assert "p.yaml" in str(err.value) and named in str(err.value)


def test_negative_or_unitless_geometry_sd_is_refused():
    for bad in ({"value": "57.15 mm", "sd": "-1 mm"}, {"value": "57.15 mm", "sd": "1 kPa"}):
        raw = _raw()
        raw["geometry"]["initial_diameter"] = bad
        with pytest.raises(InputError, match="initial_diameter"):
            load_pam("p.yaml", raw=raw)


def test_uncertainty_without_moduli_is_refused():
    raw = _raw(uncertainty={"covariance": np.zeros((16, 16)).tolist()})
    del raw["moduli"]
    with pytest.raises(InputError, match="moduli"):
        load_pam("p.yaml", raw=raw)
