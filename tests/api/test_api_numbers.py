"""The Python API takes every kind of number, and checks its options as the CLI does (issue 27).

Before: np.int64(2), np.float32, Decimal, Fraction and pint quantities gave "TypeError: ... is not
iterable", and solver="bogus", confidence="0.95", sketch_name="../evil" raised bare ValueError or
TypeError. The reference is the same call with a plain float in SI.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pint
import pytest

import pampipe
from pampipe.errors import InputError
from tests.support.problems import PROBLEMS

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
PAM = PROBLEMS / "pams" / "paper-radial-pam.yaml"
UNITS = pint.UnitRegistry()


@pytest.fixture(scope="module")
def reference():
    return pampipe.plan(MISSION, payload=2.0).to_dict()["sections"]


@pytest.mark.parametrize("payload", [np.int64(2), np.float32(2.0), np.array(2.0), Decimal("2"),
                                     Fraction(4, 2), UNITS.Quantity(2, "kg"), UNITS.Quantity(2000, "g"),
                                     UNITS.Quantity(Decimal("4.40924524"), "lb")], ids=repr)
def test_plan_takes_every_number(payload, reference):
    got = pampipe.plan(MISSION, payload=payload).to_dict()["sections"]
    want = [s["segments"][0]["pressure_Pa"] for s in reference]
    assert [s["segments"][0]["pressure_Pa"] for s in got] == pytest.approx(want, rel=1e-8)


def test_simulate_takes_arrays_and_quantities():
    plain = pampipe.simulate(PAM, pipe_diameter=[0.0762, 0.0889], pressure=[2e5, 3e5]).to_dict()
    for diameter, pressure in ((np.array([0.0762, 0.0889]), np.array([2e5, 3e5])),
                               (UNITS.Quantity(np.array([3.0, 3.5]), "inch"), [UNITS.Quantity(200, "kPa"),
                                                                              Fraction(3 * 10**5)])):
        got = pampipe.simulate(PAM, pipe_diameter=diameter, pressure=pressure).to_dict()
        assert got["pipe_diameter_m"] == pytest.approx(plain["pipe_diameter_m"], rel=1e-12)
        assert got["anchoring_pressure_Pa"] == pytest.approx(plain["anchoring_pressure_Pa"], rel=1e-12)


@pytest.mark.parametrize(("call", "option", "value"), [
    (pampipe.plan, "solver", "bogus"), (pampipe.plan, "confidence", "0.95"),
    (pampipe.plan, "confidence", 1.5),
    (pampipe.plan, "payload", "3 m"), (pampipe.plan, "payload", UNITS.Quantity(3, "m")),
    (pampipe.plan, "payload", 1 + 2j), (pampipe.plan, "payload", np.nan), (pampipe.plan, "payload", 10**400),
    (pampipe.plan, "payload", [1, 2]), (pampipe.plan, "max_payload", "yes"), (pampipe.gait, "section", 3),
    (pampipe.gait, "optimal", "no"), (pampipe.export_mission, "sketch_name", "../evil"),
    (pampipe.export_mission, "sketch_name", 5),
    # issue 38: raw ValueError, TypeError
    (pampipe.plan, "solver", None), (pampipe.plan, "prior", 3),
    (pampipe.export_mission, "confidence", "0.95"), (pampipe.export_mission, "samples", 10.5),
    (pampipe.export_mission, "seed", -1)], ids=lambda v: getattr(v, "__name__", None) or repr(v))
def test_bad_option_values_are_input_errors_naming_the_option(call, option, value):
    with pytest.raises(InputError) as error:
        call(MISSION, **{option: value})
    assert option in str(error.value)


@pytest.mark.parametrize(("option", "value"), [("folds", "3"), ("folds", 2.5), ("folds", 1)])
def test_diagnose_options(option, value):
    with pytest.raises(InputError) as error:
        pampipe.diagnose(PROBLEMS / "experiments" / "paper-protocol.yaml", **{option: value})
    assert option in str(error.value)


@pytest.mark.parametrize("value", [np.ma.masked, np.ma.array(2.0, mask=True)])
def test_masked_value_is_refused(value):
    """Issue 38: pampipe.plan(M, payload=np.ma.masked) planned 0 kg (numpy reads a masked value as 0)."""
    with pytest.raises(InputError, match="payload: the value is masked"):
        pampipe.plan(MISSION, payload=value)


def test_masked_entry_of_a_list_is_refused():
    with pytest.raises(InputError, match=r"pipe_diameter\[1\]: the value is masked"):
        pampipe.simulate(PAM, pipe_diameter=np.ma.array([0.08, 0.09], mask=[False, True]))


def test_unmasked_masked_array_is_its_number(reference):
    assert pampipe.plan(MISSION, payload=np.ma.array(2.0)).to_dict()["sections"] == reference


def test_empty_pipe_diameter_list_names_the_option():
    """Issue 38: pipe_diameter=[] was "ValueError: max() arg is an empty sequence"."""
    with pytest.raises(InputError, match="pipe_diameter: an empty list"):
        pampipe.simulate(PAM, pipe_diameter=[])


@pytest.mark.parametrize(("section", "segment", "name"), [(9, 0, "section"), (0, 9, "segment"),
                                                          (-1, 0, "section"), (0, 1.0, "segment")])
def test_capacity_curve_index_out_of_range(section, segment, name):
    """Issue 38: capacity_curve(9, 9, [1e5]) was an IndexError."""
    plan = pampipe.plan(MISSION)
    with pytest.raises(InputError, match=f"capacity_curve: {name}"):
        plan.capacity_curve(section, segment, [1e5])
    assert plan.capacity_curve(np.int64(0), 0, [4e5])[0] > 0


def test_muscle_from_something_that_is_no_pam():
    """Issue 38: Muscle.from_pam(None) was "AttributeError: 'NoneType' object has no attribute 'moduli'"."""
    from pampipe.model.muscle import Muscle

    with pytest.raises(InputError, match="pam: a NoneType is not a PAM"):
        Muscle.from_pam(None)
