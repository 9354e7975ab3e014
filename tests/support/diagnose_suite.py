"""The hidden-effect suites of `diagnose`: a TUNING set and a separate TEST set.

* ``TUNING``: the seeds and magnitudes used while choosing the thresholds of pampipe.diagnosis
  (noise-floor level, Bonferroni α, BIC and CV margins, the where-shares, the library share).
  Never used by an assertion.
* ``TEST``: different seeds and different magnitudes (scales 0.7 and 1.4 of the defaults for pairs
  and effects outside the library; the default magnitude, with new seeds, for single effects; new
  seeds for clean data). Only the tests use it, after the thresholds were fixed.

Run a whole set and print its confusion matrices (2 worker processes unless ``--workers``):

  .venv/bin/python -m tests.support.diagnose_suite test        (or tuning, round3; then groups: single,pair)
  .venv/bin/python -m tests.support.diagnose_suite round3 pair --seeds 43500-43505 --workers 1

Each case prints its wall time, the CPU time [s] of the process that ran it, the most IPOPT iterations
of a converged trial refit and the number of failed ones.
"""

from __future__ import annotations

import itertools
import sys
import time
from collections import Counter
from dataclasses import dataclass

from pampipe.diagnosis.hidden import FOREIGN, MAGNITUDES


@dataclass(frozen=True)
class Case:
    group: str  # "clean", "single", "pair", "foreign"
    effects: tuple[str, ...]
    seed: int
    scale: float = 1.0

    @property
    def label(self) -> str:
        return "+".join(self.effects) or "none"


PAIRS = tuple(itertools.combinations(MAGNITUDES, 2))


def tuning_cases() -> list[Case]:
    """TUNING set: seeds 1000-1099, default magnitudes."""
    cases = [Case("clean", (), 1000 + i) for i in range(20)]
    cases += [Case("single", (e,), 1020 + i) for i, e in enumerate(MAGNITUDES)]
    cases += [Case("pair", pair, 1030 + i) for i, pair in enumerate(PAIRS)]
    cases += [Case("foreign", (e,), 1060 + 10 * j + i) for j, e in enumerate(FOREIGN) for i in range(2)]
    return cases


def held_out_cases() -> list[Case]:
    """TEST set: seeds 5000-5999, magnitudes ×0.7 and ×1.4 (pairs, foreign), ×1 (singles)."""
    cases = [Case("clean", (), 5000 + i) for i in range(20)]
    cases += [Case("single", (e,), 5100 + i) for i, e in enumerate(MAGNITUDES)]
    cases += [Case("pair", pair, 5200 + 2 * i + k, scale) for i, pair in enumerate(PAIRS)
              for k, scale in enumerate((0.7, 1.4))]
    cases += [Case("foreign", (e,), 5300 + 10 * j + k, scale) for j, e in enumerate(FOREIGN)
              for k, scale in enumerate((0.7, 1.4, 0.7, 1.4))]
    return cases


def round3_cases() -> list[Case]:
    """The ROUND3 rerun of issue 41 (62 cases, seeds 43200-43799, none used before): 8 clean, every single
    effect on 2 seeds, every pair once (×0.7 and ×1.4 alternating), every foreign effect at ×0.7 and ×1.4."""
    cases = [Case("clean", (), 43200 + i) for i in range(8)]
    cases += [Case("single", (e,), 43300 + 10 * j + k) for j, e in enumerate(MAGNITUDES) for k in range(2)]
    cases += [Case("pair", pair, 43500 + i, (0.7, 1.4)[i % 2]) for i, pair in enumerate(PAIRS)]
    cases += [Case("foreign", (e,), 43700 + 10 * j + k, (0.7, 1.4)[k]) for j, e in enumerate(FOREIGN)
              for k in range(2)]
    return cases


def run_case(case: Case) -> dict:
    """Diagnose one case; the outcome as a plain dict (picklable)."""
    from pampipe.diagnosis.hidden import hidden_experiment
    from pampipe.diagnosis.workflow import diagnose
    from pampipe.io.pam_schema import load_pam
    from tests.support.problems import PROBLEMS

    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    started, cpu = time.perf_counter(), time.process_time()
    result = diagnose(hidden_experiment(pam, case.effects or None, seed=case.seed, scale=case.scale))
    trials = [t for s in result.steps for t in s.trials]
    return {"case": case, "verdict": result.verdict.verdict, "named": result.selected_effects,
            "confounded": tuple(c["with"] for c in result.confounded),
            "groups": tuple(result.verdict.indistinguishable),
            "rmse_after": [t.rmse for t in result.chosen.tests], "time": time.perf_counter() - started,
            "iterations": max((t.model.fit.iterations for t in trials if t.model), default=0),
            "failed": sum(t.model is None for t in trials),
            "cpu": time.process_time() - cpu}


def outcome_class(outcome: dict) -> str:
    """How a case came out, in the words of issue 13's acceptance criteria."""
    case, verdict, named = outcome["case"], outcome["verdict"], set(outcome["named"])
    truth = set(case.effects)
    if case.group == "clean":
        return "none" if verdict == "none" else f"{verdict}: {'+'.join(sorted(named)) or '-'}"
    if case.group == "foreign":
        if verdict == "explained":
            return "confident wrong name"
        return verdict
    if truth <= named:
        return "all named" + (" (+extra)" if named - truth else "")
    grouped = {name for group in outcome.get("groups", ()) for name in group}
    flagged = named | set(outcome["confounded"]) | grouped
    if truth <= flagged:  # a true effect in a group the tests cannot separate (or flagged as confounded)
        return "all named or flagged"
    if named & truth:
        return "one named"
    return "none named"


def confusion(outcomes: list[dict]) -> str:
    """Tables: true effect(s) × verdict, and true effect(s) × named set."""
    lines = []
    for group in ("clean", "single", "pair", "foreign"):
        rows = [o for o in outcomes if o["case"].group == group]
        if not rows:
            continue
        lines.append(f"\n## {group} ({len(rows)} cases)")
        lines.append("| true | verdict | named | outcome |")
        lines.append("|---|---|---|---|")
        for o in rows:
            c = o["case"]
            lines.append(f"| {c.label} ×{c.scale:g} (seed {c.seed}) | {o['verdict']} | "
                         f"{'+'.join(o['named']) or '-'} | {outcome_class(o)} |")
        counts = Counter(outcome_class(o) for o in rows)
        lines.append("summary: " + ", ".join(f"{k}: {v}/{len(rows)}" for k, v in sorted(counts.items())))
    return "\n".join(lines)


def main(argv: list[str]) -> None:
    import argparse
    from multiprocessing import get_context

    parser = argparse.ArgumentParser(prog="python -m tests.support.diagnose_suite")
    parser.add_argument("which", nargs="?", default="tuning", choices=("tuning", "test", "round3"))
    parser.add_argument("groups", nargs="?", help="comma-separated groups (clean,single,pair,foreign)")
    parser.add_argument("--seeds", help="an inclusive seed range FIRST-LAST")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    cases = {"tuning": tuning_cases, "test": held_out_cases, "round3": round3_cases}[args.which]()
    groups = args.groups.split(",") if args.groups else None
    first, last = map(int, args.seeds.split("-")) if args.seeds else (0, 10**9)
    cases = [c for c in cases if (groups is None or c.group in groups) and first <= c.seed <= last]
    started = time.perf_counter()
    with get_context("spawn").Pool(args.workers) as pool:
        outcomes = []
        for outcome in pool.imap(run_case, cases):
            outcomes.append(outcome)
            print(f"{outcome['case'].label} ×{outcome['case'].scale:g} seed {outcome['case'].seed}: "
                  f"{outcome['verdict']} {outcome['named']} groups {outcome['groups']} "
                  f"({outcome['time']:.1f} s, CPU {outcome['cpu']:.1f} s; trial refits: at most "
                  f"{outcome['iterations']} iterations, {outcome['failed']} failed)", flush=True)
    print(confusion(outcomes))
    print(f"\n{len(cases)} cases in {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
