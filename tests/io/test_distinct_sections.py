"""A long route validated once per distinct section (pampipe.io.distinct_sections, issue 39) loads to the
same route, and tells the same problems, as the same file validated section by section."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.io import distinct_sections as distinct_module
from pampipe.io.distinct_sections import SHORTEST, distinct_sections
from pampipe.io.mission_schema import load_mission
from tests.support.problems import PROBLEMS

HEAD = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text().split("route:")[0].replace(
    "../pams", str(PROBLEMS / "pams"))


def mission(folder, lines: list[str]):
    path = folder / "long.yaml"
    path.write_text(HEAD + "route:\n" + "\n".join(f"  - {line}" for line in lines) + "\n")
    return path


def varied(count: int) -> list[str]:
    """``count`` sections repeating 3 lengths, 2 bores (one a mapping), 3 inclines (one a bare -0.0) and
    frictions written as 0.2, 0.20 and 1/5 (equal numbers, written differently)."""
    bores = ["3 in", "{nps: 3, schedule: 40, tolerance: 1 %}"]
    inclines = ["10 deg", "-0.0", "0.0"]
    frictions = ["0.2", "0.20", "{value: 0.2, sd: 0.01}"]
    return [f"{{name: s{i}, length: {1 + i % 3} m, inner_diameter: {bores[i % 2]}, "
            f"incline: {inclines[i % 3]}, friction: {frictions[i % 5 % 3]}}}" for i in range(count)]


def both(path, monkeypatch):
    """load_mission(path) with the distinct sections (if long enough) and section by section."""
    fast = load_mission(path)
    monkeypatch.setattr(distinct_module, "SHORTEST", 10**9)
    slow = load_mission(path)
    return fast, slow


def test_index_and_first_places():
    values = ["1 m", 1, 1.0, True, -0.0, 0.0]
    route = [{"name": f"s{i}", "length": values[i % 6]} for i in range(SHORTEST + 6)]
    found = distinct_sections(route)
    assert found.first == [0, 1, 2, 3, 4, 5]  # 1, 1.0, true, -0.0 and 0.0 are all different values
    assert found.index.tolist() == [i % 6 for i in range(SHORTEST + 6)]
    assert found.names == [f"s{i}" for i in range(SHORTEST + 6)]
    assert found.distinct(route) == route[:6]
    nested = [{"name": f"s{i}", "inner_diameter": {"nps": 3, "schedule": [40, 80][i % 2]}}
              for i in range(SHORTEST)]
    assert distinct_sections(nested).first == [0, 1]


@pytest.mark.parametrize("change", ["short", "not a mapping", "no name", "empty name", "numeric name",
                                    "bend"])
def test_section_by_section(change):
    route = [{"name": f"s{i}", "length": "1 m"} for i in range(SHORTEST)]
    if change == "short":
        route = route[:-1]
    else:
        route[100] = {"not a mapping": "1 m", "no name": {"length": "1 m"}, "empty name": {"name": ""},
                      "numeric name": {"name": 7}, "bend": {"name": "b", "bend": {"angle": "90 deg"}}}[change]
    assert distinct_sections(route) is None
    assert distinct_sections({"network": "x.inp"}) is None


def test_same_route_as_section_by_section(tmp_path, monkeypatch):
    path = mission(tmp_path, varied(SHORTEST + 44))
    fast, slow = both(path, monkeypatch)
    assert len(fast.route.name) == SHORTEST + 44
    for column in ("name", "length", "diameter", "incline", "friction", "friction_sd", "diameter_low",
                   "diameter_high", "diameter_sd", "label"):
        a, b = getattr(fast.route, column), getattr(slow.route, column)
        assert a.dtype == b.dtype and a.tolist() == b.tolist(), column
    assert np.signbit(fast.route.incline).tolist() == np.signbit(slow.route.incline).tolist()
    assert np.signbit(fast.route.incline).sum() == (SHORTEST + 44 + 1) // 3  # the -0.0 kept its sign
    assert fast.warnings == slow.warnings


@pytest.mark.parametrize("problem", ["a late bad length", "a late bad bore", "a repeated name", "a bad robot",
                                     "a late extra key"])
def test_same_message(tmp_path, monkeypatch, problem):
    lines = varied(SHORTEST + 44)
    late = SHORTEST + 20
    if problem == "a late bad length":
        lines[late] = lines[late].replace("length: ", "length: -")
    elif problem == "a late bad bore":
        lines[late] = lines[late].replace("inner_diameter: 3 in", "inner_diameter: 3 parsecs")
    elif problem == "a repeated name":
        lines[late] = lines[late].replace(f"name: s{late},", "name: s3,")
    elif problem == "a late extra key":
        lines[late] = lines[late].replace("}", ", colour: red}")
    path = mission(tmp_path, lines)
    if problem == "a bad robot":
        path.write_text(path.read_text().replace("supply_pressure:", "supply_presure:"))
    messages = []
    for shortest in (SHORTEST, 10**9):
        monkeypatch.setattr(distinct_module, "SHORTEST", shortest)
        with pytest.raises(InputError) as caught:
            load_mission(path)
        messages.append(str(caught.value))
    assert messages[0] == messages[1]
    assert problem == "a bad robot" or problem == "a repeated name" or f"route[{late}]" in messages[0]
