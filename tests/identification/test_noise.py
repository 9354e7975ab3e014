"""The model-free noise floor (:mod:`pampipe.identification.noise`) against noise of known size."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.identification import noise
from pampipe.identification.noise import held_length_paths, local_floor


def test_the_floor_is_the_noise_under_a_curved_force_and_ignores_any_model():
    """Six paths of 21 pressures each, a force curved in pressure (up to 1600 N) plus white noise of sd 2.5 N:
    the floor reads the noise (the median of ~120 terms: a few % scatter), not the curvature."""
    rng = np.random.default_rng(4)
    pressure = np.tile(np.linspace(65e3, 675e3, 21), 6)
    group = np.repeat(np.arange(6), 21)
    force = 2.4e-3 * pressure * (1 + group / 6) + 1.2e-9 * pressure**2 + rng.normal(0, 2.5, pressure.size)
    floor, terms = local_floor(pressure, force, group)
    assert terms == 126 and floor == pytest.approx(2.5, rel=0.2)


def test_repeats_give_their_scatter():
    """Seven repeated readings at each of 5 pressures: where a window's pressures are all equal the local fit
    is their mean, and the floor is the repeats' scatter (sd 0.8 N) whatever the force's trend."""
    rng = np.random.default_rng(5)
    pressure = np.repeat(np.linspace(1e5, 5e5, 5), 7)
    force = 1e-2 * pressure + rng.normal(0, 0.8, pressure.size)
    floor, _ = local_floor(pressure, force, np.zeros(pressure.size, dtype=np.int64))
    assert floor == pytest.approx(0.8, rel=0.3)


def test_held_lengths_are_paths_and_sweeps_are_not():
    assert held_length_paths(np.repeat([0.237, 0.25, 0.267], 4)).tolist() == [0] * 4 + [1] * 4 + [2] * 4
    assert held_length_paths(np.linspace(0.2, 0.3, 50)) is None


def test_the_windows_are_inverted_as_numpys_pseudo_inverse_does():
    """Row 0 of the local fits' (XᵀX)⁺, from the cofactors where well conditioned, equals numpy's pinv (an SVD
    each) on windows of distinct x, of repeats only (rank 1) and of two repeated values (rank 2)."""
    rng = np.random.default_rng(6)
    x = np.sort(rng.uniform(-1, 1, (200, 6)), axis=1)
    x[:20] = 0.0
    x[20:40, :3], x[20:40, 3:] = -0.5, 0.5
    design = x[:, :, None] ** np.arange(3)[None, None, :]
    gram = np.einsum("mki,mkj->mij", design, design)
    reference = np.linalg.pinv(gram)[:, 0, :]
    row = noise._first_row_of_inverse(gram)
    assert np.allclose(row, reference, rtol=1e-10, atol=1e-10 * np.abs(reference).max())


def test_windows_of_repeats_only_are_inverted_to_the_bit_of_numpys_pseudo_inverse():
    """A window whose x all equal x_i (XᵀX = diag(a, 0, 0)) gets row 0 of pinv exactly: (1/a, 0, 0), the
    same floats: the floor of a test at held pressures is the number pinv on every window gives."""
    design = np.zeros((5, 6, 3))
    design[:, :, 0] = 1.0
    design[3, :2, 0] = 0.0  # a window with 4 rows: a = 4
    gram = np.einsum("mki,mkj->mij", design, design)
    row = noise._first_row_of_inverse(gram)
    reference = np.linalg.pinv(gram)[:, 0, :]
    assert row.tobytes() == reference.tobytes()
    assert row[3].tolist() == [0.25, 0.0, 0.0] and row[0].tolist() == [1 / 6, 0.0, 0.0]


def _held_reference(length, most=30, fewest=3):
    """held_length_paths by its definition: np.unique of the lengths to 0.1 mm, its inverse and counts."""
    values, index, counts = np.unique(np.round(length, 4), return_inverse=True, return_counts=True)
    return None if not 2 <= values.size <= most or counts.min() < fewest else index.ravel()


@pytest.mark.parametrize("kind", ["held", "sweep", "held, then a sweep after the first rows",
                                  "one held twice", "thirty held"])
def test_held_length_paths_as_numpys_unique_numbers_them(kind):
    rng = np.random.default_rng(len(kind))
    for _ in range(40):
        n = int(rng.integers(2, 12_000))
        levels = rng.uniform(0.2, 0.31, int(rng.integers(1, 40)))
        length = levels[rng.integers(0, levels.size, n)] + rng.normal(0, 1e-6, n)
        if kind == "sweep":
            length = rng.uniform(0.2, 0.31, n)
        elif kind == "thirty held":  # as many as held lengths may be, every one in the first rows
            length = np.linspace(0.2, 0.31, 30)[rng.integers(0, 30, n + 5000)]
        elif kind == "held, then a sweep after the first rows":
            length[min(5000, n - 1):] = rng.uniform(0.2, 0.31, n - min(5000, n - 1))
        elif kind == "one held twice":
            length[: n // 2] = levels[0]
            length[n // 2:] = levels[0] if n % 2 else levels[-1]
        found, expected = held_length_paths(length), _held_reference(length)
        assert (found is None) == (expected is None)
        if expected is not None:
            np.testing.assert_array_equal(found, expected)
