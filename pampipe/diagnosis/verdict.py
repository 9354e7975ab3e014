"""The verdict (docs/commands.md §6.3): none, explained, partly_explained or unexplained.

With M the tests the baseline leaves off the noise (:mod:`.structure`) and S the selected effects:

* ``none``: M is empty, the baseline fits to the noise;
* ``unexplained``: S is empty (no effect clears the margins of :mod:`.search`), or S removes less
  than :data:`LIBRARY_SHARE` of what the generic probes remove from the baseline on M (the library
  leaves the tests that held the residual largely unchanged), or the baseline plus one family of
  generic probes (linearised refit, :mod:`.structure`) has a BIC lower than the baseline + S by
  more than the search's BIC margin (a generic term is the better explanation): nothing is named;
* ``explained``: S brings every test to the noise;
* ``partly_explained``: S helps, but some test keeps structured residual (reported with where).

Then :func:`qualify` keeps the verdict from claiming more than the data show (the four values stay;
``judged``, ``indistinguishable``, ``undetermined`` and ``cautions`` say why a verdict was lowered):

* a floor that was *assumed* (no repeats, too few neighbours: σ = the test's own RMSE) cannot show
  a fit at the noise: ``none`` becomes ``unexplained`` with ``judged = false`` and the reason
  "cannot judge: …", ``explained`` becomes ``partly_explained``;
* a test that scatters :data:`pampipe.diagnosis.noise.NOISY` times more than its twins is named in
  ``cautions``; its floor judges nothing, so ``none`` becomes ``unexplained`` and ``explained``
  ``partly_explained``;
* effects that tie with an alternative (within the search's BIC margin, :mod:`.search`) are
  reported as one group in ``indistinguishable`` and not named on their own;
* an effect with a parameter the data do not pin inside its allowed range is ``undetermined``, not
  named, by one rule: its 95 % interval covers :data:`SPAN` or more of the range, or the fit stops at a
  bound that is not the parameter's null value (the data would push it further); a verdict whose fitted
  set holds one is not ``explained``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from pampipe.diagnosis.search import BIC_MARGIN
from pampipe.diagnosis.structure import Assessment, Where

VERDICTS = ("none", "explained", "partly_explained", "unexplained")
#: The library must remove at least this share of what the probes remove on the misfit tests.
LIBRARY_SHARE = 0.5
#: An effect parameter whose 95 % interval covers this share of its allowed range is undetermined.
SPAN = 0.5
#: A fitted value within this share of its allowed range from a bound (not its null value) is at the bound.
AT_BOUND = 1e-3


@dataclass(frozen=True)
class Verdict:
    verdict: str
    effects: tuple[str, ...]  # named effects (empty unless explained or partly_explained)
    reason: str
    library_removed: float  # [N²] on the baseline's misfit tests
    probes_removed: float  # [N²] by the probes from the baseline, same tests
    remaining: tuple[Where, ...]  # where structured residual remains (partly_explained, unexplained)
    fitted: tuple[str, ...] = ()  # the set refitted (named, tied and undetermined effects)
    indistinguishable: tuple[tuple[str, ...], ...] = ()  # groups these tests cannot separate
    undetermined: tuple[str, ...] = ()  # fitted effects whose interval spans its allowed range
    judged: bool = True  # False: an assumed noise floor, the fit cannot be judged against the noise
    cautions: tuple[str, ...] = ()


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


def qualify(verdict: Verdict, *, groups, undetermined, floors, noisy) -> Verdict:
    """The verdict lowered where the data cannot support it (see the module docstring).

    ``groups``: tie groups (each holds one fitted effect); ``undetermined``: {effect: parameter};
    ``floors``: the noise floors; ``noisy``: [(test, ratio, its σ, the twins' σ)].
    """
    fitted = verdict.effects
    tied = {name for group in groups for name in group}
    named = tuple(e for e in fitted if e not in tied and e not in undetermined)
    reason = verdict.reason
    for group in groups:  # the verdict names the group, never one of its members on its own
        for name in group:
            if name in fitted:
                reason = reason.replace(name, f"({' or '.join(group)})")
    value, reasons, cautions = verdict.verdict, [reason], []
    assumed = [f.test for f in floors if f.method == "assumed"]
    judged = not assumed
    for test, ratio, sigma, twins in noisy:
        cautions.append(f"{test} scatters {ratio:.1f}x more than its twins ({sigma:.3g} N against "
                        f"{twins:.3g} N): noise the other tests do not have (an oscillating pressure, a "
                        "loose fixture?); its floor cannot judge the fit")
    if not judged:
        reasons = [f"cannot judge: the noise floor of {', '.join(assumed)} was assumed, not measured (no "
                   "repeated set points and too few neighbouring points), so no fit can be shown to reach "
                   "the noise; record repeats of some set points"]
        if value == "explained":
            reasons.append(reason)
    if noisy:
        reasons.append("; ".join(cautions))
    for group in groups:
        reasons.append(f"{' or '.join(group)}: these tests cannot tell them apart (indistinguishable)")
    for name, parameter in undetermined.items():
        reasons.append(f"{name} is undetermined: the data do not pin {parameter} inside its allowed range "
                       "(its 95 % interval spans it, or the fit stops at a bound)")
    if value == "none" and (not judged or noisy):
        value = "unexplained"
    elif value == "explained" and (not judged or noisy or undetermined):
        value = "partly_explained" if named or groups else "unexplained"
    elif value == "partly_explained" and not named and not groups:
        value = "unexplained"
    return replace(verdict, verdict=value, effects=named if value != "unexplained" else (),
                   reason="; ".join(reasons), fitted=fitted, indistinguishable=tuple(groups),
                   undetermined=tuple(undetermined), judged=judged, cautions=tuple(cautions))


def tie_groups(steps, fitted: tuple[str, ...]) -> list[tuple[str, ...]]:
    """Groups of effects that tie: each fitted effect with the alternatives confounded with it at the
    step that added it (alternatives that are fitted too are not ties), overlapping groups merged."""
    from pampipe.diagnosis.refit import canonical

    groups: list[set[str]] = []
    for step in steps:
        if step.action != "add" or step.effect not in fitted:
            continue
        members = {step.effect, *(e for e in step.confounded if e not in fitted)}
        if len(members) < 2:
            continue
        for group in [g for g in groups if g & members]:
            members |= group
            groups.remove(group)
        groups.append(members)
    return [canonical(g) for g in groups]


def undetermined_effects(summary, bounds) -> dict[str, str]:
    """{effect: parameter} of the fitted effects with a parameter the data do not pin inside its allowed
    range ``bounds[effect][parameter] = (low, high)`` (SI): its 95 % interval covers :data:`SPAN` of the
    range, or its value (``summary.parameters``) lies within :data:`AT_BOUND` of the range from a bound
    that is not its null value."""
    from pampipe.diagnosis.candidates import candidate

    values = getattr(summary, "parameters", {})
    out = {}
    for name, parameters in summary.intervals.items():
        nulls = {p.name: p.null for p in candidate(name).parameters}
        for parameter, (low, high) in parameters.items():
            lower, upper = bounds[name][parameter]
            width = upper - lower
            value = values.get(name, {}).get(parameter)
            at_bound = value is not None and width > 0 and any(
                abs(value - edge) <= AT_BOUND * width and abs(edge - nulls[parameter]) > AT_BOUND * width
                for edge in (lower, upper))
            if width > 0 and ((high - low) >= SPAN * width or at_bound):
                out[name] = parameter
                break
    return out
