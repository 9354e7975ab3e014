"""What identify computes once and reuses gives the numbers of computing it again, bit for bit: the
hinge's refits reuse the first reduction (statistics.Memo); the model error's noise floor uses the model
forces the per-test scoring evaluated."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.identification import FitOptions, identify, statistics
from pampipe.identification.statistics import Memo, reduce_experiment
from pampipe.io.csvfile import load_experiment_data
from pampipe.io.experiment_schema import load_experiment
from pampipe.model.pam import Pam
from pampipe.simulation.synthetic import Protocol, generate
from pampipe.specs.experiment import ExperimentData, make_test_data
from tests.support.problems import PROBLEMS


@pytest.fixture(scope="module")
def data(radial_pam):
    tests = [make_test_data(spec, cols) for spec, cols in
             generate(radial_pam, Protocol(points_per_leg=60, radial_points=20), seed=3)]
    pam = Pam(radial_pam.name, radial_pam.geometry)
    return ExperimentData(PROBLEMS / "generated.yaml", pam, tuple(tests), {})


def _same(a, b):
    for name in ("r", "z", "rest", "points", "pressure", "test"):
        assert np.array_equal(getattr(a.axial, name), getattr(b.axial, name)), name
    assert np.array_equal(a.cells.moments, b.cells.moments)
    for x, y in zip(a.radial, b.radial, strict=True):
        assert np.array_equal(x.moments, y.moments)


def _reduce(data, hinge, memo=None):
    return reduce_experiment(data, degree=3, hinge=hinge, memo=memo)


@pytest.mark.parametrize("where", ["late", "early"])
def test_a_refit_with_hinged_rows_equals_a_fresh_reduction(data, monkeypatch, where):
    """Chunks of 256 rows: rows hinged late keep most chunks from the memo, rows hinged in the
    first chunk keep none; either way R, z, rest, cells and radial bins equal a reduction from scratch."""
    monkeypatch.setattr(statistics, "CHUNK", 256)
    axial = next(i for i, t in enumerate(data.tests) if t.kind == "axial")
    measured = np.flatnonzero(data.tests[axial].force > 0)
    assert measured.size > 8 * 256
    rows = measured[[-300, -40]] if where == "late" else measured[[5, -40]]
    computed = []
    augmented = statistics._augmented
    monkeypatch.setattr(statistics, "_augmented", lambda *a: computed.append(a[0].size) or augmented(*a))
    memo = Memo()
    first = _reduce(data, {}, memo)
    full = sum(computed)
    computed.clear()
    again = _reduce(data, {axial: rows}, memo)
    reused = sum(computed)
    computed.clear()
    fresh = _reduce(data, {axial: rows})
    _same(again, fresh)
    assert not np.array_equal(first.axial.r, again.axial.r)  # the hinged rows left the QR groups
    assert full == measured.size
    assert reused < 300 + 256 if where == "late" else reused == measured.size - rows.size


@pytest.mark.parametrize(("mode", "slack"), [("shared", "unilateral"), ("contact_increment", "exclude")])
def test_the_model_error_uses_the_fit_quality_floor(mode, slack):
    """The model error's σ_n is the fit quality's pooled model-free floor (one floor per fit, issue 35),
    and the 2 N noise of the bundled data is what it reads."""
    data = load_experiment_data(load_experiment(PROBLEMS / "experiments" / "paper-protocol.yaml"))
    result = identify(data, FitOptions(mode=mode, slack=slack))
    assert result.model_error.noise_floor == result.quality.noise_floor
    assert result.model_error.noise_floor == pytest.approx(2.0, rel=0.15)


def test_the_parameters_packed_once_evaluate_as_the_numpy_ones(data, monkeypatch):
    """Layout.pack converts p to CasADi once per solve instead of at every call: the functions give the
    numbers of the numpy p, bit for bit."""
    from pampipe.identification import exact

    seen = []
    polish = exact.polish
    monkeypatch.setattr(exact, "polish", lambda nlp, p, x, *rest: seen.append((nlp, p, x))
                        or polish(nlp, p, x, *rest))
    identify(data, FitOptions())
    nlp, p, x = seen[-1]
    plain = np.asarray(p, dtype=float).ravel()
    assert plain.size == nlp.layout.size and not isinstance(p, np.ndarray)
    for function in (nlp.sse, nlp.hessian, nlp.constraints, nlp.gradient):
        for packed, unpacked in zip(function.call([x, p]), function.call([x, plain]), strict=True):
            assert np.array_equal(np.asarray(packed), np.asarray(unpacked))


def test_empty_cells_leave_the_fit_unchanged_bit_for_bit(data, monkeypatch):
    """The cell capacity's headroom (so that the hinge's refits keep one NLP) pads the cells with empty
    ones: the fit with four times the capacity is the same, bit for bit."""
    from pampipe.identification import moment_cells as cells
    from pampipe.identification import problem

    base = identify(data, FitOptions())
    sizes = []
    monkeypatch.setattr(problem, "capacity",
                        lambda count, **kw: sizes.append(count) or 4 * cells.capacity(count, **kw))
    padded = identify(data, FitOptions())
    assert sizes and padded.provenance["parameters"] == base.provenance["parameters"]
    assert np.array_equal(padded.x, base.x) and padded.sse == base.sse
    assert padded.solver.iterations == base.solver.iterations
    for name in ("lower", "upper", "at_bound"):
        assert np.array_equal(getattr(padded.uncertainty, name), getattr(base.uncertainty, name),
                              equal_nan=True), name
    assert repr(padded.model_error) == repr(base.model_error) and repr(padded.quality) == repr(base.quality)


def test_the_tsqr_equals_stacking_each_chunks_level_rows_under_r_bit_for_bit(data, monkeypatch):
    """A chunk of one level's rows gets its R written above them in place; a chunk that spans levels is
    split: either way R, z and rest equal a QR of [R; the level's rows of the chunk] chunk after chunk."""
    monkeypatch.setattr(statistics, "CHUNK", 256)
    got = _reduce(data, {}).axial
    index = next(i for i, t in enumerate(data.tests) if t.kind == "axial")
    test, p = data.tests[index], 16
    rows = np.flatnonzero(test.force > 0)
    r = np.zeros((test.level_pressure.size, p + 1, p + 1))
    spans = 0
    for start in range(0, rows.size, 256):
        chunk = rows[start:start + 256]
        offset, phi = statistics.regressors(test.pressure[chunk], test.length[chunk], data.pam.geometry, 3)
        block = np.column_stack([phi, test.force[chunk] - offset])
        levels = np.unique(test.level[chunk])
        spans += levels.size > 1
        for lev in levels:
            stacked = np.asfortranarray(np.vstack([r[lev], block[test.level[chunk] == lev]]))
            r[lev] = np.linalg.qr(stacked, mode="r")[:p + 1]
    assert spans and spans < rows.size // 256  # both kinds of chunk
    mine = got.test == index
    expected = r[np.unique(test.level[rows])]
    assert np.array_equal(got.r[mine], expected[:, :p, :p])
    assert np.array_equal(got.z[mine], expected[:, :p, p])
    assert np.array_equal(got.rest[mine], expected[:, p, p] ** 2)


def test_a_refit_with_fewer_cells_takes_the_held_nlp_of_the_next_larger_capacity(monkeypatch):
    """The model error's refits on a subset hold fewer slack cells than the fit: they take the NLP the
    process holds that differs only by a larger capacity (the smallest such; the fit is the same, as
    above), and nothing else: another structure, or no cells, keeps its own."""
    from dataclasses import replace

    from pampipe.identification import fit_nlp

    base = fit_nlp.Structure("shared", "least_squares", 16, 1, True, 64, ((11, 0),), 1, 256, 0, "constant",
                             "none", (), "thick", 1000, 1e-10)
    held = [replace(base, cells=512), replace(base, cells=128), replace(base, cells=128, grid_rows=128)]
    monkeypatch.setattr(fit_nlp, "_HELD", held)
    assert fit_nlp.with_held_room(base) == replace(base, cells=128)
    assert fit_nlp.with_held_room(replace(base, cells=256)) == replace(base, cells=512)
    assert fit_nlp.with_held_room(replace(base, cells=1024)) == replace(base, cells=1024)
    assert fit_nlp.with_held_room(replace(base, grid_rows=64)) == replace(base, grid_rows=64)
    assert fit_nlp.with_held_room(replace(base, cells=0)) == replace(base, cells=0)
