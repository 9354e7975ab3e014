"""The search's progress on stderr (issue 41): every cross-validation says which model it refits, from the
second on with an estimate at the mean so far, and a model is cross-validated once."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pampipe.diagnosis.search import Search


def test_each_cross_validation_is_announced_once_with_an_estimate_after_the_first():
    said, folds = [], []
    cells = SimpleNamespace(test=np.array([0, 1]), size=2)
    search = Search(cells, refit=None, assess=None, cross_validate=lambda fit: folds.append(fit) or 1.5,
                    say=said.append)
    first = SimpleNamespace(effects=(), fit="baseline fit")
    second = SimpleNamespace(effects=("braid_friction", "prestrain"), fit="pair fit")
    assert search.cv(first) == 1.5
    assert search.cv(first) == 1.5  # cached: neither refitted nor announced again
    search.cv(second)
    assert folds == ["baseline fit", "pair fit"]
    assert said[0] == "cross-validating baseline (fold refits)"
    assert said[1].startswith("cross-validating braid_friction + prestrain (fold refits, about ")
    assert said[1].endswith(" s at the mean so far)")
    assert len(said) == 2
