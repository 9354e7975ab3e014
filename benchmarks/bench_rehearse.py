"""Benchmark of `pampipe rehearse` on long routes (issue 37, item 5): the 9 km ky4 route and a synthetic 10 km
route of 10³ sections, with a tether, a 10 mm supply hose and a compressor.

1. **ky4**: ``pampipe route ky4 --from J-315 --to J-897 --max-bore "4.5 in" --template T -o r.yaml`` (T: the
   demo robot with a tether, its hose and compressor, elbows of 10 D so that every bend passes), then
   ``pampipe rehearse r.yaml --json`` in a fresh interpreter: its wall time (the issue's goal: ≤ 60 s on this
   machine), then the same in-process, split into the plan and the walk.
2. **Baseline**: the per-section loop a user of `pampipe gait` would write, the simulated sequential gait of
   each walked section (``sequential_gait(mission, index, mission_plan=plan)``, what ``gait --section NAME``
   does), against the batched gait table of the walk: the time and the largest relative difference of the
   gait's own cycle times and strides.
3. **Synthetic**: 10³ sections of 10 m in 4 kinds (inclines 0°, 5°, −5°, 30°), a 30° bend every 100 sections:
   the in-process rehearsal.

Wall and CPU seconds are printed (on a shared machine wall time also counts the other processes); nothing is
asserted.

    .venv/bin/python benchmarks/bench_rehearse.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parent.parent
PAM = str(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")
TETHER = {"weight": "0.3 N/m", "friction": 0.1, "back_tension": "5 N", "length": "12 km",
          "hose": {"inner_diameter": "10 mm"}, "compressor": {"free_air_delivery": "200 L/min"}}
TEMPLATE = {"robot": {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
                      "payload": "2 kg"},
            "supply_pressure": "689 kPa", "safety_factor": 1.5, "elbow_radius": "10 D", "tether": TETHER,
            "route": [{"name": "x", "length": "1 m", "inner_diameter": "3 in", "friction": 0.3}]}


def timed(call):
    """(result, wall [s], CPU [s]) of ``call()``."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = call()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def pampipe(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "pampipe", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def ky4(folder: Path) -> Path:
    template = folder / "template.yaml"
    template.write_text(yaml.safe_dump(TEMPLATE))
    out = pampipe("route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "4.5 in", "--template",
                  str(template), "-o", "r.yaml", "--force", cwd=folder)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return folder / "r.yaml"


def baseline(mission, result) -> tuple[float, float, float]:
    """(wall [s], CPU [s], largest relative difference) of the per-section loop of the simulated gait."""
    from pampipe.locomotion import gait_options, sequential_gait

    options = gait_options(mission.gait, source=mission.source)
    walked = np.flatnonzero(result.walk.walked > 0)

    def loop():
        return [sequential_gait(mission, int(s), options=options, mission_plan=result.plan) for s in walked]

    gaits, wall, cpu = timed(loop)
    cycle = np.array([g.cycle_time for g in gaits]) / result.walk.gait_cycle_time[walked] - 1
    stride = np.array([g.stride for g in gaits]) / result.walk.stride[walked] - 1
    return wall, cpu, float(max(np.abs(cycle).max(), np.abs(stride).max()))


def in_process(name: str, mission) -> None:
    from pampipe.planning import plan_mission
    from pampipe.rehearsal import rehearse_mission

    result, wall, cpu = timed(lambda: rehearse_mission(mission))
    _, plan_wall, plan_cpu = timed(lambda: plan_mission(mission))
    route = mission.route
    print(f"{name}: {len(route)} sections, {route.length.sum() / 1e3:.4g} km, walked "
          f"{result.walk.walked.sum() / 1e3:.4g} km in {result.time / 3600:.4g} h, {result.free_air:.4g} m³; "
          f"rehearse in-process {wall:.2f} s wall ({cpu:.2f} s CPU), of which the plan {plan_wall:.2f} s "
          f"({plan_cpu:.2f} s CPU)")
    loop_wall, loop_cpu, worst = baseline(mission, result)
    print(f"  baseline, the simulated gait section by section: {loop_wall:.2f} s wall ({loop_cpu:.2f} s CPU) "
          f"for the gait alone; batched gait table agrees to {worst:.2e} (cycle time and stride)")


def synthetic():
    from pampipe.api import load_mission

    inclines = ("0 deg", "5 deg", "-5 deg", "30 deg")
    route = []
    for k in range(1000):
        section = {"name": f"s{k}", "length": "10 m", "inner_diameter": "3 in", "incline": inclines[k % 4],
                   "friction": 0.3}
        if k % 100 == 99 and k < 999:
            section["bend"] = {"angle": "30 deg"}
        route.append(section)
    return load_mission({**TEMPLATE, "route": route})


def main() -> int:
    from pampipe.api import load_mission

    with tempfile.TemporaryDirectory() as work:
        folder = Path(work)
        path = ky4(folder)
        _, wall, _ = timed(lambda: pampipe("rehearse", str(path), "--json", cwd=folder))
        print(f"ky4 J-315 -> J-897: `pampipe rehearse r.yaml --json` in a fresh interpreter: {wall:.2f} s "
              "wall (goal: <= 60 s)")
        in_process("ky4 route", load_mission(path))
    in_process("synthetic route", synthetic())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
