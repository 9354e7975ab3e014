"""The verdict (docs/commands.md §7.5): none, explained, partly_explained or unexplained.

With M the tests the baseline leaves off the noise (:mod:`.structure`) and S the selected effects:

* ``none``: M is empty, the baseline fits to the noise;
* ``unexplained``: S is empty (no effect clears the margins of :mod:`.search`), or S removes less
  than :data:`LIBRARY_SHARE` of what the generic probes remove from the baseline on M (the library
  leaves the tests that held the residual largely unchanged), or the baseline plus one family of
  generic probes (linearised refit, :mod:`.structure`) has a BIC lower than the baseline + S by
  more than the search's BIC margin (a generic term is the better explanation): nothing is named;
* ``explained``: S brings every test to the noise;
* ``partly_explained``: S helps, but some test keeps structured residual (reported with where).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pampipe.diagnosis.search import BIC_MARGIN
from pampipe.diagnosis.structure import Assessment, Where

VERDICTS = ("none", "explained", "partly_explained", "unexplained")
#: The library must remove at least this share of what the probes remove on the misfit tests.
LIBRARY_SHARE = 0.5


@dataclass(frozen=True)
class Verdict:
    verdict: str
    effects: tuple[str, ...]  # named effects (empty unless explained or partly_explained)
    reason: str
    library_removed: float  # [N²] on the baseline's misfit tests
    probes_removed: float  # [N²] by the probes from the baseline, same tests
    remaining: tuple[Where, ...]  # where structured residual remains (partly_explained, unexplained)


@dataclass(frozen=True)
class Scores:
    """What the BIC comparison of library and probes needs: rows, and (SSE [N²], parameters) of the
    baseline and of the final model."""

    rows: int
    baseline_sse: float
    baseline_k: int
    final_sse: float
    final_k: int

    def bic(self, sse: float, k: int) -> float:
        return self.rows * math.log(max(sse, 1e-300) / self.rows) + k * math.log(self.rows)


def decide(names: list[str], baseline: Assessment, final: Assessment, effects: tuple[str, ...],
           scores: Scores | None = None) -> Verdict:
    """The verdict from the baseline's and the final model's assessments (``names``: test names)."""
    misfit = baseline.misfit
    if not misfit:
        return Verdict("none", (), "the baseline fits to the noise: every test passes the lack-of-fit, "
                       "serial-correlation and structure tests", 0.0, 0.0, ())
    held = ", ".join(names[i] for i in misfit)
    probes = baseline.ss(misfit) - sum(baseline.probe_ss[i] for i in misfit)
    library = baseline.ss(misfit) - final.ss(misfit) if effects else 0.0
    if not effects:
        return Verdict("unexplained", (), f"structured residual in {held}, and no library effect clears the "
                       "margins (BIC, cross-validation, and a clear reduction where the residual is)",
                       0.0, probes, _remaining(baseline))
    if library < LIBRARY_SHARE * probes:
        share = library / probes
        return Verdict("unexplained", (), f"{' + '.join(effects)} would remove only {share:.0%} of what "
                       f"generic terms remove from {held}: the library does not explain the residual there",
                       library, probes, _remaining(final))
    if scores is not None:
        final_bic = scores.bic(scores.final_sse, scores.final_k)
        name, (removed, k) = min(baseline.probe_families.items(), key=lambda item: scores.bic(
            scores.baseline_sse - item[1][0], scores.baseline_k + item[1][1]))
        probe_bic = scores.bic(scores.baseline_sse - removed, scores.baseline_k + k)
        if probe_bic < final_bic - BIC_MARGIN:
            return Verdict("unexplained", (), f"a generic {name} term ({k} coefficients) explains the data "
                           f"better than {' + '.join(effects)} (BIC {final_bic - probe_bic:.0f} lower): the "
                           "library does not explain the residual", library, probes, _remaining(final))
    if final.at_noise:
        verb = "brings" if len(effects) == 1 else "bring"
        return Verdict("explained", effects, f"{' + '.join(effects)} {verb} every test to the noise",
                       library, probes, ())
    left = ", ".join(names[i] for i in final.misfit)
    share = library / baseline.ss(misfit)
    verb = "removes" if len(effects) == 1 else "remove"
    return Verdict("partly_explained", effects, f"{' + '.join(effects)} {verb} {share:.0%} of the residual "
                   f"sum of squares of {held}, but structured residual remains in {left}",
                   library, probes, _remaining(final))


def _remaining(assessment: Assessment) -> tuple[Where, ...]:
    return tuple(t.where for t in assessment.tests if t.where is not None)
