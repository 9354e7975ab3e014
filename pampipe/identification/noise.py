"""A noise floor that misfit cannot inflate: the measured force's scatter about a local smooth fit per path.

The floor is model-free: it never looks at the fitted model, so a fit far off the data (a mis-stated
geometry, an effect the model lacks) cannot raise it. Along each path (a held length swept in pressure
for a test that holds its lengths, e.g. a force map; else the paths of :func:`.quality.paths`, sorted by
the swept coordinate x), every row i is predicted from its :data:`NEIGHBOURS` nearest rows on the path
(the window of NEIGHBOURS + 1 rows around it, shifted inside at the ends) by a polynomial of degree
:data:`DEGREE` in x, least squares, without row i:

  e_i = F_i − p̂_{−i}(x_i),   Var e_i = σ²(1 + h_i),   h_i = [(XᵀX)⁺]₀₀  (x centred on x_i),

so for white noise e_i²/(1 + h_i) has mean σ², while the force's smooth dependence on x up to a
quadratic is absorbed locally. Repeats (rows at one x) enter as they are: where the window's x are
equal the polynomial is their mean and e_i the scatter of repeats. σ̂² = median(e_i²/(1 + h_i)) /
median(χ²₁), robust to kinks such as the slack or anchoring point. Rows that read ≤ 0 N are left out
(the caller passes the live rows). At most :data:`CENTRES` rows per test are predicted (evenly spread).
"""

from __future__ import annotations

import math

import numpy as np

#: Neighbours of each row in its local fit, and the polynomial degree (a local quadratic).
NEIGHBOURS = 6
DEGREE = 2
#: Median of χ²₁ (σ̂² = median(e²/(1 + h)) / this).
CHI2_MEDIAN = 0.454936423119572
#: A window's XᵀX whose determinant is above this times its diagonal's product is inverted by its cofactors.
CONDITIONED = 1e-6
#: Rows predicted per test at most (the median needs far fewer; a 10⁶-row test stays fast).
CENTRES = 20_000


def local_floor(x: np.ndarray, force: np.ndarray, group: np.ndarray) -> tuple[float | None, int]:
    """(σ̂ [N], terms) from rows sorted by path ``group`` then ``x`` (module docstring); σ̂ is None when
    no path has NEIGHBOURS + 1 rows (the caller decides how many terms make a floor)."""
    x, force, group = (np.asarray(v) for v in (x, force, group))
    window = NEIGHBOURS + 1
    starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]]) if group.size else np.zeros(0, np.int64)
    lengths = np.diff(np.r_[starts, group.size])
    long_enough = lengths >= window
    if not long_enough.any():
        return None, 0
    first = np.repeat(starts[long_enough], lengths[long_enough])
    size = np.repeat(lengths[long_enough], lengths[long_enough])
    centre = np.concatenate([np.arange(s, s + n) for s, n in zip(starts[long_enough], lengths[long_enough],
                                                                 strict=True)])
    if centre.size > CENTRES:
        pick = evenly_spaced(centre.size, CENTRES)
        centre, first, size = centre[pick], first[pick], size[pick]
    low = first + np.clip(centre - first - NEIGHBOURS // 2, 0, size - window)
    rows = low[:, None] + np.arange(window)[None, :]
    rows = np.where(rows < centre[:, None], rows, rows + 1)[:, :NEIGHBOURS]  # skip the centre row
    dx = x[rows] - x[centre][:, None]
    scale = np.ptp(dx, axis=1)
    dx /= np.where(scale > 0, scale, 1.0)[:, None]
    # X = [1, dx, dx²] per window: XᵀX and Xᵀy from the sums of the window's powers of dx (and times F)
    square, near = dx * dx, force[rows]
    sums = [np.full(dx.shape[0], float(NEIGHBOURS)), *(v.sum(axis=1) for v in (dx, square, dx * square,
                                                                                 square * square))]
    gram = np.stack([sums[i:i + DEGREE + 1] for i in range(DEGREE + 1)], axis=1).transpose(2, 0, 1)
    first_row = _first_row_of_inverse(gram)
    intercept = (first_row[:, 0] * near.sum(axis=1) + first_row[:, 1] * (dx * near).sum(axis=1)
                 + first_row[:, 2] * (square * near).sum(axis=1))
    error = force[centre] - intercept
    values = error**2 / (1 + first_row[:, 0])
    return math.sqrt(float(np.median(values)) / CHI2_MEDIAN), int(values.size)


def _first_row_of_inverse(gram: np.ndarray) -> np.ndarray:
    """Row 0 of (XᵀX)⁺ of every window (m × 3 × 3 → m × 3): all the floor needs (the intercept
    p̂(x_i) = row₀·Xᵀy and h_i = [(XᵀX)⁺]₀₀). Where XᵀX = [[a, b, c], [b, d, e], [c, e, f]] is well
    conditioned (its determinant above :data:`CONDITIONED` times adf; x is scaled to a unit span, so the
    entries are O(1)) it is the cofactors' row (df − e², ce − bf, be − cd) / det, elementwise over the
    windows; where every x of the window is x_i (repeats only: XᵀX = diag(a, 0, 0), a the rows) it is
    (1/a, 0, 0), what pinv gives to the bit; numpy's pinv (an SVD each) where other repeats make XᵀX singular
    or nearly (on a radial test of 3·10⁴ rows 99.7 % of the windows are repeats only). The cofactors and pinv
    agree to ~1e-12 where both apply."""
    a, b, c = gram[:, 0, 0], gram[:, 0, 1], gram[:, 0, 2]
    d, e, f = gram[:, 1, 1], gram[:, 1, 2], gram[:, 2, 2]
    cofactors = np.stack([d * f - e * e, c * e - b * f, b * e - c * d], axis=1)
    determinant = a * cofactors[:, 0] + b * cofactors[:, 1] + c * cofactors[:, 2]
    regular = np.abs(determinant) > CONDITIONED * np.abs(a * d * f)
    repeats = ~regular & (a > 0) & (gram.reshape(-1, 9)[:, 1:] == 0).all(axis=1)
    out = np.empty((gram.shape[0], 3))
    out[regular] = cofactors[regular] / determinant[regular, None]
    out[repeats] = 0.0
    out[repeats, 0] = 1.0 / a[repeats]
    rest = ~regular & ~repeats
    out[rest] = np.linalg.pinv(gram[rest])[:, 0, :]
    return out


def evenly_spaced(size: int, count: int) -> np.ndarray:
    """Indices of ``count`` rows evenly spaced over 0 … size − 1, in order (fewer where two round to one):
    the linspace truncated is non-decreasing, so its distinct values are those unlike their predecessor."""
    spaced = np.linspace(0, size - 1, count).astype(np.int64)
    return spaced[np.r_[True, spaced[1:] != spaced[:-1]]] if spaced.size else spaced


#: More distinct lengths than this in an axial test is a sweep, not held lengths (:func:`held_length_paths`).
MOST_HELD_LENGTHS = 30
#: The first rows :func:`held_length_paths` looks at before it sorts every row (a sweep shows itself there).
PROBE = 4096


def held_length_paths(length: np.ndarray, *, most: int = MOST_HELD_LENGTHS, fewest: int = 3
                      ) -> np.ndarray | None:
    """The held length of each row as a path index, for a test whose rows sit at 2..``most`` distinct
    lengths (to 0.1 mm), each held for at least ``fewest`` rows; None for a test that sweeps its length."""
    held = np.round(np.asarray(length, float), 4)
    if np.unique(held[:PROBE]).size > most:  # a sweep: its first rows already hold more lengths (no sort of
        return None  # every row, ≈ 0.2 s at 1.8·10⁶ rows)
    values = np.unique(held)  # numpy's vectorised sort, not the merge sort of return_inverse
    if not 2 <= values.size <= most:
        return None
    index = np.searchsorted(values, held)  # the rank among the distinct lengths: np.unique's inverse
    if np.bincount(index, minlength=values.size).min() < fewest:
        return None
    return index
