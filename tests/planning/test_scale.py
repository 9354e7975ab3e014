"""Long missions (issue 12, item 4): 10⁵ sections parse and plan with memory that grows linearly.

Peak memory is measured with tracemalloc (Python and numpy allocations) around reading the mission file
and planning it, after a warm-up plan so that imports and cached solvers are not counted. Linear means
peak(N₂)/peak(N₁) ≤ 1.1·N₂/N₁: 10 % above proportional covers the fixed part (the robot, the PAM
files), which only lowers the ratio; a table of Python objects per section, or an N² step, would exceed
it. The planning path builds no Section object per section (the route is columnar).
"""

from __future__ import annotations

import gc
import shutil
import tracemalloc

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.specs import mission as mission_module
from pampipe.specs.mission import Route
from tests.support.problems import PROBLEMS

BORES = ("3 in", "3.5 in", "80 mm", "{nps: 3, schedule: 40, tolerance: 1 %}", "{dn: 110, sdr: 26}")


def write_mission(folder, sections: int):
    """The demo robot on ``sections`` sections of varied lengths, bores (some with a tolerance), inclines."""
    shutil.copytree(PROBLEMS / "pams", folder / "pams", dirs_exist_ok=True)
    head = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text().split("route:")[0]
    path = folder / f"mission-{sections}.yaml"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(head.replace("../pams", "pams") + "route:\n")
        for i in range(sections):
            handle.write(f"  - {{name: s{i}, length: {1 + i % 7} m, inner_diameter: {BORES[i % 5]}, "
                         f"incline: {i % 90 - 45} deg, friction: {0.2 + 0.05 * (i % 4):g}}}\n")
    return path


def peak_memory(path) -> tuple[int, object]:
    """(traced peak [B], plan) of reading and planning the mission at ``path``."""
    gc.collect()
    tracemalloc.start()
    try:
        plan = plan_mission(load_mission(path))
        return tracemalloc.get_traced_memory()[1], plan
    finally:
        tracemalloc.stop()


def check_linear(tmp_path, small: int, large: int, monkeypatch) -> None:
    plan_mission(load_mission(write_mission(tmp_path, 10)))  # warm-up: imports, cached functions
    made = []
    original = mission_module.Section.__post_init__
    monkeypatch.setattr(mission_module.Section, "__post_init__",
                        lambda self: (made.append(1), original(self)))
    low, _ = peak_memory(write_mission(tmp_path, small))
    high, plan = peak_memory(write_mission(tmp_path, large))
    assert isinstance(plan.arrays.route, Route) and len(plan.arrays.route) == large
    assert plan.feasible and np.isfinite(plan.arrays.pressure).all()
    assert not made, f"{len(made)} Section objects built on the planning path"
    assert high / low <= 1.1 * large / small, (low, high)


def test_memory_grows_linearly_with_sections(tmp_path, monkeypatch):
    check_linear(tmp_path, 2_000, 10_000, monkeypatch)


@pytest.mark.slow
def test_a_mission_of_1e5_sections_parses_and_plans_with_linear_memory(tmp_path, monkeypatch):
    check_linear(tmp_path, 10_000, 100_000, monkeypatch)
