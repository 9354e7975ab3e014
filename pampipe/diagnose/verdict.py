"""The verdict (docs/commands.md §7.5): none, explained, partly_explained or unexplained.

With M the tests the baseline leaves off the noise (:mod:`.structure`) and S the selected effects:

* ``none``: M is empty, the baseline fits to the noise;
* ``unexplained``: S is empty (no effect clears the margins of :mod:`.search`), or S removes less
  than :data:`LIBRARY_SHARE` of what the generic probes remove from the baseline on M (the library
  leaves the tests that held the residual largely unchanged): nothing is named;
* ``explained``: S brings every test to the noise;
* ``partly_explained``: S helps, but some test keeps structured residual (reported with where).
"""

from __future__ import annotations

from dataclasses import dataclass

from pampipe.diagnose.structure import Assessment, Where

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


def decide(names: list[str], baseline: Assessment, final: Assessment, effects: tuple[str, ...]) -> Verdict:
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
