"""Benchmark: `diagnose` on the bundled hidden-effect example, time per candidate.

Goal (issue 5): the bundled example finishes in under 60 s on a 2-core machine. Baseline in the
same run: one `identify` (shared moduli) on the same experiment, i.e. the cost of the baseline fit
alone; the ratio says how many baseline fits the whole diagnosis costs.

Run: .venv/bin/python benchmarks/bench_diagnose.py
"""

from __future__ import annotations

import time
from pathlib import Path

from pampipe.diagnose.workflow import diagnose
from pampipe.identify import identify, parse_fit_options
from pampipe.io.config import load_experiment
from pampipe.io.csvfile import load_experiment_data
from pampipe.report import table

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "problems" / "experiments" / "hidden-contact-stiffening.yaml"


def main() -> None:
    data = load_experiment_data(load_experiment(EXAMPLE))
    started = time.perf_counter()
    identify(data, parse_fit_options(data.fit).with_overrides(mode="shared"))
    baseline = time.perf_counter() - started

    started = time.perf_counter()
    result = diagnose(data)
    total = time.perf_counter() - started
    rows = [(c.effect, c.wall_time, c.iterations, "yes" if c.cv_rmse is not None else "no")
            for c in (result.baseline, *result.candidates)]
    print(f"{EXAMPLE.name}: {data.points} rows, selected {result.selected}")
    print(table(["candidate", "fit + CV time [s]", "IPOPT iterations", "cross-validated"], rows))
    print(table(["what", "time [s]"], [("identify (shared), the baseline alone", baseline),
                                       ("diagnose, all 7 candidates", total),
                                       ("ratio diagnose / identify", total / baseline)]))
    print(f"goal: < 60 s on 2 cores -> {'met' if total < 60 else 'NOT met'} ({total:.1f} s)")


if __name__ == "__main__":
    main()
