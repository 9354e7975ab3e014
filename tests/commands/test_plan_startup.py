"""Start-up of `pampipe plan` (issue 25 item 2): the numeric law without CasADi, the mission cache.

The closed-form holding law is one source (:class:`~pampipe.model.muscle.Muscle`) evaluated two ways:
numerically through :mod:`pampipe.model.ops` without CasADi, and as a CasADi graph for the NLPs and the
exported code. The two must agree. A mission read before must load from the cache without reading its
YAML, give the same plan, and be validated again as soon as any file it read changes; a well-formed new
mission is validated by the quick check (pampipe.io.quick_schemas) without pydantic, a broken one by the
schema.
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from pampipe.model.muscle import Muscle
from tests.support.problems import PROBLEMS, ROOT
from tests.support.processes import in_fresh_interpreter, run_cli

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"


@pytest.mark.parametrize("contact", [False, True])
def test_numeric_law_equals_the_casadi_graph(radial_pam, contact):
    """closed_form_pressure evaluated by numpy equals the CasADi function of the symbolic muscle to 1e-12."""
    import casadi as ca

    rng = np.random.default_rng(25)
    base = Muscle.from_pam(radial_pam)
    g = base.geometry
    n = 400
    for trial in range(5):
        theta = np.asarray(base.theta) * rng.uniform(0.5, 1.5, np.size(base.theta))
        increments = theta * rng.uniform(0.0, 0.3, theta.size) if contact else None
        muscle = Muscle(g, theta, base.reference_pressure, contact=increments)
        sym = Muscle.symbolic(muscle.structure)
        d, w, kappa, mu, sf = (ca.SX.sym(name) for name in ("d", "w", "kappa", "mu", "sf"))
        law = ca.Function("law", [d, w, kappa, mu, sf, sym.p], [sym.muscle.closed_form_pressure(
            d, w, kappa=kappa, friction=mu, safety_factor=sf)])
        diameter = rng.uniform(g.initial_diameter * 1.01, g.largest_diameter * 0.99, n)
        load = rng.uniform(0.0, 200.0, n)
        friction = rng.uniform(0.05, 0.8, n)
        kappa_value, sf_value = rng.uniform(0.0, 1.0), rng.uniform(1.0, 3.0)
        numeric = muscle.closed_form_pressure(diameter, load, kappa=kappa_value, friction=friction,
                                              safety_factor=sf_value)
        graph = np.asarray(law.map(n)(diameter[None, :], load[None, :], kappa_value, friction[None, :],
                                      sf_value, muscle.parameter_vector())).ravel()
        finite = np.isfinite(graph)
        assert finite.sum() > n // 2, trial  # the comparison covers mostly planned pressures
        np.testing.assert_array_equal(np.isfinite(numeric), finite)
        np.testing.assert_allclose(numeric[finite], graph[finite], rtol=1e-12, atol=1e-12 * 1e5)


def _untimed(stdout: str) -> dict:
    """The JSON plan without the solver's wall time (the one entry that differs between equal runs)."""
    document = json.loads(stdout)
    document["solver"].pop("wall_time_s")
    return document


def _plan_in_fresh_interpreter(mission, cache, cwd=ROOT):
    """(exit code, stdout, names of casadi/pydantic/scipy/yaml modules loaded) of `pampipe plan MISSION
    --json` (SciPy's import alone costs more than the whole demo plan; yaml is loaded when a file is read)."""
    return in_fresh_interpreter(["plan", str(mission), "--json"], {"casadi", "pydantic", "scipy", "yaml"},
                                cache, cwd)


def test_demo_plan_loads_no_casadi_nor_pydantic_and_read_before_no_yaml(tmp_path):
    first = _plan_in_fresh_interpreter(DEMO, tmp_path / "cache")
    second = _plan_in_fresh_interpreter(DEMO, tmp_path / "cache")
    assert first[0] == second[0] == 0
    assert "casadi" not in first[2]  # the closed form needs no CasADi even on the first run
    assert first[2] == ["yaml"]  # the first run reads and validates the file, without pydantic
    assert second[2] == []
    assert _untimed(second[1]) == _untimed(first[1])


def test_cached_mission_is_validated_again_when_a_file_it_read_changes(tmp_path):
    """After the PAM file that a cached mission names is edited, the plan is that of the edited files
    (as planned with the cache off), and a schema error in it is explained (exit 2), never served."""
    folder = tmp_path / "work"
    shutil.copytree(PROBLEMS / "missions", folder / "missions")
    shutil.copytree(PROBLEMS / "pams", folder / "pams")
    mission = folder / "missions" / DEMO.name
    cache = tmp_path / "cache"
    code, before, _ = _plan_in_fresh_interpreter(mission, cache)
    assert code == 0
    pam = folder / "pams" / "paper-radial-pam.yaml"
    text = pam.read_text()
    assert "axial: {a: [1.5," in text
    pam.write_text(text.replace("axial: {a: [1.5,", "axial: {a: [2.5,"))  # a stiffer bladder
    code, edited, loaded = _plan_in_fresh_interpreter(mission, cache)
    assert code == 0 and loaded == ["yaml"]  # read again, well-formed: the quick check validates it
    assert _untimed(edited) != _untimed(before)
    assert _untimed(edited) == _untimed(_plan_in_fresh_interpreter(mission, "off")[1])
    pam.write_text(text.replace("reference_pressure:", "reference_pressure_was:"))
    code, _, loaded = _plan_in_fresh_interpreter(mission, cache)
    assert code == 2 and loaded == ["pydantic", "yaml"]  # broken: the schema tells what is wrong
    pam.write_text(text)
    code, again, loaded = _plan_in_fresh_interpreter(mission, cache)  # one entry per mission: kept anew
    assert code == 0 and loaded == ["yaml"] and _untimed(again) == _untimed(before)
    code, again, loaded = _plan_in_fresh_interpreter(mission, cache)
    assert code == 0 and loaded == [] and _untimed(again) == _untimed(before)


def test_mission_cache_off_validates_every_time(tmp_path):
    code, _, loaded = _plan_in_fresh_interpreter(DEMO, "off")
    assert code == 0 and loaded == ["yaml"]
    code, _, loaded = _plan_in_fresh_interpreter(DEMO, "off")
    assert loaded == ["yaml"]


def test_plan_without_json_or_report_exits_0():
    """The text-only demo (no JSON document built) plans and exits 0."""
    out = run_cli("plan", DEMO)
    assert out.returncode == 0, out.stderr
    assert "feasible" in out.stdout


def test_large_mission_files_are_not_kept(tmp_path):
    from pampipe.io.validated import LARGEST_KEPT

    shutil.copytree(PROBLEMS / "missions", tmp_path / "missions")
    shutil.copytree(PROBLEMS / "pams", tmp_path / "pams")
    mission = tmp_path / "missions" / DEMO.name
    mission.write_text(DEMO.read_text() + "#" * LARGEST_KEPT + "\n")
    for _ in range(2):
        code, _, loaded = _plan_in_fresh_interpreter(mission, tmp_path / "cache")
        assert code == 0 and loaded == ["yaml"]
