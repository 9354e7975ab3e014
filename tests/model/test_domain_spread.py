"""A stated geometry sd against the physical domain (issue 38): the share of its normal outside, computed
here by statistics.NormalDist, must be at most 1e-6; an sd just inside that passes, one just outside not."""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.model.domain import OUTSIDE_SHARE, OUTSIDE_Z, check_spread, outside_domain
from pampipe.model.pam import Geometry

GEOMETRY = Geometry(0.310662, 0.05715, math.radians(90 - 66.4373), 0.003175, "thick")


def test_outside_z_is_the_one_sided_quantile():
    assert NormalDist().cdf(-OUTSIDE_Z) == pytest.approx(OUTSIDE_SHARE, rel=1e-5)


def test_length_sd_share_outside_is_named():
    share = NormalDist(0.310662, 1.0).cdf(0.0)  # 0.378
    with pytest.raises(InputError, match=f"sd 1000 mm puts {share:.3g} of the draws outside"):
        check_spread(GEOMETRY, "initial_length", 1.0, where="geometry.initial_length")


@pytest.mark.parametrize(("name", "distance"), [
    ("initial_length", 0.310662), ("initial_diameter", 0.05715 - 2 * 0.003175),
    ("bladder_thickness", 0.003175)])
def test_sd_at_the_bound_passes_and_beyond_it_is_refused(name, distance):
    check_spread(GEOMETRY, name, distance / OUTSIDE_Z * 0.999, where=name)
    with pytest.raises(InputError, match=name):
        check_spread(GEOMETRY, name, distance / OUTSIDE_Z * 1.01, where=name)


def test_braid_angle_both_sides_shown_in_the_files_convention():
    """66.4373 deg from the transverse: the contractile side is 35.26 to 90 deg; the nearer edge is 90 deg."""
    with pytest.raises(InputError, match=r"between 35\.26 and 90 deg") as caught:
        check_spread(GEOMETRY, "braid_angle", math.radians(5.7), where="x", transverse=True)
    share = NormalDist(66.4373, 5.7).cdf(35.26439) + 1 - NormalDist(66.4373, 5.7).cdf(90)
    assert f"puts {share:.3g} of the draws" in str(caught.value)


def test_outside_domain_rows():
    nominal = np.array([0.31, 0.057, 0.41, 0.003])
    rows = np.array([nominal, [-0.1, 0.057, 0.41, 0.003], [0.31, 0.005, 0.41, 0.003],
                     [0.31, 0.057, 1.0, 0.003], [0.31, 0.057, 0.41, 0.0], [np.nan, 0.057, 0.41, 0.003]])
    assert outside_domain(rows, nominal).tolist() == [False, True, True, True, True, True]
