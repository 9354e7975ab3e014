"""check_length judges the bladder's fit from the shortest and longest lengths (the room R_o² − V_b/(πL)
is concave in L): it refuses exactly the arrays where some length has an imaginary inner radius row by
row, naming the same first such length."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.model.domain import check_length
from pampipe.model.forces import wall_section
from pampipe.model.pam import Geometry


def _first_crushed(geometry, lengths):
    with np.errstate(invalid="ignore"):
        _, r_i, _ = wall_section(lengths, geometry)
    crushed = lengths[~np.isfinite(r_i)]
    return crushed[0] if crushed.size else None


@pytest.mark.parametrize("seed", range(6))
def test_refuses_exactly_the_lengths_whose_bladder_does_not_fit(seed):
    rng = np.random.default_rng(seed)
    geometry = Geometry(0.3, 0.03, math.radians(rng.uniform(15, 35)), rng.uniform(0.5e-3, 6e-3))
    low, high = geometry.shortest_length, geometry.braid_length
    for _ in range(40):
        a, b = np.sort(rng.uniform(low, high, 2))
        lengths = rng.permutation(np.concatenate([[a, b], rng.uniform(a, b, 500)]))
        expected = _first_crushed(geometry, lengths)
        if expected is None:
            check_length(geometry, lengths)
        else:
            with pytest.raises(InputError, match=f"at {expected * 1e3:.6g} mm the braid is too narrow"):
                check_length(geometry, lengths)
