"""Benchmark of `pampipe gait --optimal` on the demo mission.

Times the optimal-control problem cold (build + solve, from the sequential schedule) and warm
(re-solve of a changed mission with the same structure), against the baseline of the same run:
the sequential schedule's own computation. Prints the speed gain of the optimal gait.
Goals: cold < 5 s, warm < 1 s.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

from pampipe.gait import optimal_gait, sequential_gait
from pampipe.gait.optimal import _problem
from pampipe.io.config import load_mission

DEMO = Path(__file__).resolve().parent.parent / "problems" / "missions" / "vertical-climb-3in.yaml"


def main() -> None:
    mission = load_mission(DEMO)
    _problem.cache_clear()
    start = time.perf_counter()
    sequential = sequential_gait(mission)
    t_seq = time.perf_counter() - start
    cold = optimal_gait(mission, baseline=sequential)
    rows = [("cold (build + solve)", cold)]
    for payload in (2.5, 3.0):
        changed = dataclasses.replace(mission, payload=payload)
        warm = optimal_gait(changed, warm_start=rows[-1][1].warm_start)
        rows.append((f"warm (payload {payload:g} kg)", warm))
    print(f"demo mission, section {sequential.section!r}: sequential schedule computed in {t_seq:.3f} s")
    print(f"{'OCP solve':<24}{'build [s]':>10}{'solve [s]':>10}{'iter':>6}{'cycle [s]':>11}"
          f"{'speed [mm/s]':>14}{'vs sequential':>15}")
    for label, result in rows:
        s = result.solver
        print(f"{label:<24}{s['build_time_s']:>10.3f}{s['solve_time_s']:>10.3f}{s['iterations']:>6d}"
              f"{result.cycle_time:>11.3f}{result.speed * 1e3:>14.4g}"
              f"{(s['build_time_s'] + s['solve_time_s']) / t_seq:>14.1f}x")
    gain = sequential.cycle_time / cold.cycle_time - 1
    total = cold.solver["build_time_s"] + cold.solver["solve_time_s"]
    warm = max(r.solver["solve_time_s"] for _, r in rows[1:])
    print(f"speed: sequential {sequential.speed * 1e3:.4g} mm/s, optimal {cold.speed * 1e3:.4g} mm/s, "
          f"gain {100 * gain:+.1f} %")
    print(f"goals: cold {total:.2f} s < 5 s: {'met' if total < 5 else 'MISSED'}; "
          f"warm {warm:.2f} s < 1 s: {'met' if warm < 1 else 'MISSED'}")


if __name__ == "__main__":
    main()
