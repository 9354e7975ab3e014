"""identify's verdict line (issue 42): fit against full scale and the noise floor, model error, and which
predictions the data determine, on hand-made fits whose numbers are known."""

from __future__ import annotations

from types import SimpleNamespace as NS

import pytest

from pampipe.identification.verdict import fit_verdict


def _fit(rmse=2.0, scale=1000.0, ratio=1.2, floor=1.8, structured=False, regions=(True, True, True),
         pipes=(True,), rank=12, success=True, model_error=6.9):
    names = ("at the tested (P, L) points", "in the tested ranges, untested",
             "above the tested pressures (to 1.25 x)")
    quality = NS(tests=(NS(scale=scale / 2), NS(scale=scale)), rmse_over_floor=ratio, structured=structured,
                 noise_floor=floor)
    return NS(success=success, status="Maximum_Iterations_Exceeded", rmse=rmse, quality=quality,
              model_error=None if model_error is None else NS(value=model_error, noise_floor=floor),
              predictions=NS(regions=[NS(name=n, determined=d) for n, d in zip(names, regions, strict=True)],
                             pipes=[NS(pipe_diameter=0.0762 + 0.0127 * k, determined=d)
                                    for k, d in enumerate(pipes)]),
              uncertainty=NS(rank=rank), names=tuple(range(16)))


def test_a_fit_at_the_floor_says_so_with_its_share_of_full_scale():
    line = fit_verdict(_fit(rmse=12.0, scale=1000.0))  # 12 N of 1000 N: 1.2 %
    assert line == ("fit: RMSE 12.0 N = 1.2 % of full scale 1000 N, at the noise floor 1.80 N (1.2 x); "
                    "model error 6.90 N; determined: axial force at the tested points, in the tested ranges, "
                    "above them (to 1.25 x); anchoring in 76.2 mm / undetermined: none of these (4 of 16 "
                    "coefficient combinations)")


@pytest.mark.parametrize(("ratio", "word"), [(1.5, "at"), (2.0, "near"), (3.0, "near"), (3.1, "ABOVE")])
def test_the_floor_word_follows_the_ratio(ratio, word):
    assert f", {word} the noise floor 1.80 N" in fit_verdict(_fit(ratio=ratio))


def test_what_is_undetermined_is_named():
    line = fit_verdict(_fit(regions=(True, True, False), pipes=(True, False), structured=True, ratio=35))
    assert "ABOVE the noise floor 1.80 N (35 x), residuals STRUCTURED" in line
    assert line.endswith("determined: axial force at the tested points, in the tested ranges; anchoring in "
                         "76.2 mm / undetermined: axial force above them (to 1.25 x); anchoring in 88.9 mm "
                         "(4 of 16 coefficient combinations)")


def test_a_full_rank_fit_without_model_error_or_floor_and_a_failed_solve():
    fit = _fit(rank=16, model_error=None, success=False)
    fit.quality.rmse_over_floor = None
    line = fit_verdict(fit)
    assert line.startswith("fit: IPOPT Maximum_Iterations_Exceeded, NOT converged; RMSE 2.00 N = 0.2 % of "
                           "full scale 1000 N, noise floor unknown; determined:")
    assert "model error" not in line and line.endswith("/ undetermined: nothing")
