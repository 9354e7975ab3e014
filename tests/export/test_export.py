"""`pampipe export`: the exported C, compiled with the host's compiler, against `plan` and `gait`.

The reference is the planner itself (`plan_mission` on a route of random sections: the closed form
without effects, a bisection on the model with them) and `pampipe gait --json`; the C is generated
from the symbolic model, so these check the generator, the emitter and the reason logic end to end.

Test data: sections drawn with the fixed seeds below, inside each mission's envelope (bores from 5 %
below the widest rest diameter to 5 % above the narrowest braid limit, inclines over ±90°, 5 % zero
friction, payloads 0-60 kg), so that every reason code occurs. Tolerances are the issue's: 1e-9
relative in double and 1e-4 in float, relative to max(P, 1 kPa) as in plan's own cross-check
(pampipe.planning.checks.PRESSURE_FLOOR): float's absolute error is ~1e-6 of the anchoring pressure
(~10⁵ Pa), since P = P_a + x cancels, so a pressure of a few hundred pascals has no 1e-4 relative
meaning in float. Worst seen: 3.3e-14 in double; in float 1.4e-5 relative at 4.4 MPa, and 0.065 Pa at
907 Pa (7.1e-5 relative, 6.5e-5 against the floor).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import re
import subprocess

import numpy as np
import pytest
import yaml

import pampipe
from pampipe.cli import main
from pampipe.io.files import to_json
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.planning.checks import PRESSURE_FLOOR
from pampipe.specs.mission import Section
from tests.support import export_c
from tests.support.export_c import write_export
from tests.support.problems import PROBLEMS

pytestmark = pytest.mark.skipif(export_c.compiler() is None, reason="no host C compiler (gcc or cc) found")

TOLERANCE = {"double": 1e-9, "float": 1e-4}  # the issue's; see the module docstring
SEEDS = {"vertical-climb-3in": 11, "downhill-drain": 12, "infeasible-survey": 13, "diagnosed": 14,
         "thin-cubic": 15}
#: Float loses digits to cancellation far above any supply (seen: 1.9e-4 at 73 MPa on the thin-wall cubic
#: muscle near its braid limit, 4e-6 within the supply), so float compares pressures up to this [Pa].
FLOAT_RANGE = 1e7
#: 1024 random sections per mission in groups of one payload (plan with effects costs ~2 s per call)
GROUPS = {"vertical-climb-3in": (8, 128), "downhill-drain": (8, 128), "infeasible-survey": (8, 128),
          "diagnosed": (2, 512), "thin-cubic": (8, 128)}
DIAGNOSED_EFFECTS = {  # every effect the closed form carries, at non-null values (C₁ > 0: monotone capacity)
    "pressure_offset": {"offset": "12 kPa", "gain": 1.05},
    "axial_preload": {"preload": "40 N", "pulley_friction": 0.1},
    "contact_stiffening": {"axial_increment": "0.5 MPa", "hoop_increment": "0.3 MPa"},
    "wall_friction": {"lock": 0.2},
    "braid_friction": {"f0": "8 N"},
}


def diagnosed_mission(folder, effects=None, *, name="diagnosed"):
    """downhill-drain's robot and first section, with a PAM that has contact increments and ``effects``."""
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    pam["moduli"]["contact"] = {"axial": {"a": [0.5, 0, 0, 0], "b": [0, 0, 0, 0]},
                                "hoop": {"a": [0.8, 0, 0, 0], "b": [-0.05, 0, 0, 0]}}
    pam["effects"] = DIAGNOSED_EFFECTS if effects is None else effects
    (folder / f"{name}-pam.yaml").write_text(yaml.safe_dump(pam))
    mission = yaml.safe_load((PROBLEMS / "missions" / "downhill-drain.yaml").read_text())
    for segment in mission["robot"]["segments"]:
        segment["pam"] = f"{name}-pam.yaml"
    mission["route"] = mission["route"][:1]  # the gait table with effects costs seconds per section
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(mission))
    return path


def thin_cubic_mission(folder):
    """The demo climb with a thin-wall muscle whose moduli are cubic and pressure-dependent, load shared."""
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-axial-load-pam.yaml").read_text())
    pam["geometry"]["wall"] = "thin"
    pam["moduli"]["axial"]["a"] = [1.5, 0.3, -0.2, 0.1]
    pam["moduli"]["hoop"]["b"] = [0.2, -0.1, 0.05, 0.0]
    (folder / "thin-pam.yaml").write_text(yaml.safe_dump(pam))
    mission = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for segment in mission["robot"]["segments"]:
        segment["pam"] = "thin-pam.yaml"
    mission["load_path"] = "distributed"
    path = folder / "thin-cubic.yaml"
    path.write_text(yaml.safe_dump(mission))
    return path


def plan_codes(plan) -> np.ndarray:
    """The reason code of each planned section, read from plan's sentence (docs/physics.md §8.4 order)."""
    codes = []
    for section in plan.sections:
        reason = section.reason or ""
        codes.append(0 if section.feasible else 3 if "wall friction is zero" in reason
                     else 1 if "is not wider than" in reason
                     else 2 if "wider than the braid" in reason else 4)
    return np.array(codes)


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    """name -> (mission path, mission, Export, C folder), each exported once for the whole module."""
    cache = {}

    def get(name):
        if name not in cache:
            folder = tmp_path_factory.mktemp(name)
            made = {"diagnosed": diagnosed_mission, "thin-cubic": thin_cubic_mission}
            path = made[name](folder) if name in made else PROBLEMS / "missions" / f"{name}.yaml"
            mission = load_mission(path)
            cache[name] = (path, mission, write_export(mission, folder / "c"), folder / "c")
        return cache[name]

    return get


@pytest.fixture(scope="module", params=list(SEEDS))
def case(request, exports):
    """One mission: its export, random sections, and plan's answers for them."""
    _, mission, export, folder = exports(request.param)
    rng = np.random.default_rng(SEEDS[request.param])
    low, high = export.law.narrowest, export.law.widest
    rows, codes, pressure = [], [], []
    groups, per_group = GROUPS[request.param]
    for k in range(groups):
        payload = 0.0 if k == 0 else float(rng.uniform(0.0, 60.0))
        d = rng.uniform(0.95 * low, 1.05 * high, per_group)
        incline = rng.uniform(-math.pi / 2, math.pi / 2, per_group)
        friction = np.where(rng.random(per_group) < 0.05, 0.0, rng.uniform(0.02, 1.0, per_group))
        route = tuple(Section(f"s{i}", 1.0, d[i], incline[i], friction[i], 0.0) for i in range(per_group))
        plan = plan_mission(dataclasses.replace(mission, route=route), payload=payload)
        codes.append(plan_codes(plan))
        pressure.append(plan.arrays.pressure)
        rows += [(d[i], incline[i], friction[i], payload) for i in range(per_group)]
    return {"name": request.param, "export": export, "folder": folder, "rows": np.array(rows),
            "codes": np.concatenate(codes), "pressure": np.concatenate(pressure)}


@pytest.mark.parametrize("real", ["double", "float"])
def test_exported_function_agrees_with_plan(case, real):
    exe = export_c.build(case["folder"], real=real)
    codes, pressure = export_c.run_law(exe, case["rows"])
    want_codes, want = case["codes"], case["pressure"]
    tol = TOLERANCE[real]
    assert set(want_codes) == {0, 1, 2, 3, 4}, "the sample must exercise every reason"
    law, rows = case["export"].law, case["rows"]
    # a code may differ only where the input lies within the tolerance of a threshold (rounding to float)
    near = (np.isclose(rows[:, 0], law.narrowest, rtol=tol, atol=0)
            | np.isclose(rows[:, 0], law.widest, rtol=tol, atol=0)
            | np.any(np.isclose(want, law.supply_pressure, rtol=tol, atol=0), axis=1))
    differ = codes != want_codes
    assert not np.any(differ & ~near), list(zip(rows[differ], want_codes[differ], codes[differ], strict=True))
    filled = np.isin(want_codes, (0, 4)) & np.isin(codes, (0, 4))
    assert np.array_equal(np.isinf(pressure[filled]), np.isinf(want[filled]))
    finite = np.isfinite(want[filled]) & (want[filled] <= (FLOAT_RANGE if real == "float" else math.inf))
    got, want = pressure[filled][finite], want[filled][finite]
    error = np.abs(got - want) / np.maximum(np.abs(want), PRESSURE_FLOOR)
    assert np.all(error <= tol), error.max()
    assert np.all(np.isnan(pressure[~filled]))  # no number where the pipe itself refuses
    if real == "double":  # the Python twin that fills the gait table's reasons answers alike
        twin = [law.evaluate(*row) for row in rows[:200]]
        assert [int(code) for code, _ in twin] == codes[:200].tolist()
        np.testing.assert_allclose(np.array([p for _, p in twin]), pressure[:200], rtol=1e-12)


def test_argument_checks_and_reason_order(tmp_path):
    """NaN, infinity, a negative payload or friction: refused (5); zero friction before a narrow pipe."""
    export = write_export(load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml"), tmp_path)
    exe = export_c.build(tmp_path)
    rows = [(math.nan, 0.0, 0.3, 2.0), (0.0762, math.inf, 0.3, 2.0), (0.0762, 0.0, 0.3, -1.0),
            (0.01, 0.0, 0.0, 2.0), (0.01, 0.0, 0.3, 2.0), (1.0, 0.0, 0.3, 2.0), (0.0762, 0.0, -0.1, 2.0),
            (0.0762, math.pi / 2, 0.3, 2.0)]
    codes, pressure = export_c.run_law(exe, rows)
    assert codes.tolist() == [5, 5, 5, 3, 1, 2, 5, 0]
    assert np.all(np.isnan(pressure[:-1]))
    plan = plan_mission(load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml"))
    riser = [s.pressure for s in plan.sections[0].segments]  # 3 in, 90°, μ 0.3, 2 kg
    assert pressure[-1] == pytest.approx(riser, rel=1e-12)  # same inputs, same closed form
    assert export.law.evaluate(0.0762, math.pi / 2, 0.3, 2.0)[1] == pytest.approx(riser, rel=1e-12)


def gait_cli(capsys, mission, section):
    capsys.readouterr()
    code = main(["gait", str(mission), "--section", section, "--json"])
    out = capsys.readouterr().out
    return code, (json.loads(out) if code == 0 else None)


@pytest.mark.parametrize("name", ["downhill-drain", "infeasible-survey"])
def test_gait_table_equals_gait_json(exports, capsys, name):
    path, mission, _, folder = exports(name)
    table, names = export_c.run_table(export_c.build(folder))
    assert names == [s.name for s in mission.segments]
    assert [t["name"] for t in table] == [s.name for s in mission.route]
    for row, section in zip(table, mission.route, strict=True):
        assert (row["inner_diameter_m"], row["incline_rad"], row["friction"], row["length_m"]) == (
            section.diameter, section.incline, section.friction, section.length)
        code, document = gait_cli(capsys, path, section.name)
        if row["reason"] != 0:  # gait refuses the section too, and the table holds zeros
            assert code == 3
            assert row["cycle_time_s"] == 0 and all(s["duration_s"] == 0 for s in row["steps"])
            continue
        assert code == 0
        # the CLI's JSON has 12 significant digits (docs/commands.md §1.2): 1e-11 relative
        assert row["cycle_time_s"] == pytest.approx(document["cycle_time_s"], rel=1e-11)
        assert row["stride_m"] == pytest.approx(document["stride_m"], rel=1e-11)
        for step, want in zip(row["steps"], document["steps"], strict=True):
            assert step["step"] == want["step"]
            words = [f"inflate {n}" for n, v in zip(names, step["valves"], strict=True) if v == 1]
            words += [f"vent {n}" for n, v in zip(names, step["valves"], strict=True) if v == -1]
            assert ", ".join(words) == ("" if want["step"] == "I" else want["valve_action"])
            assert [n for n, a in zip(names, step["anchored"], strict=True) if a] == want["anchored"]
            assert step["duration_s"] == pytest.approx(want["duration_s"], rel=1e-11, abs=1e-300)
            # the table holds the levels the schedule fills or vents to (the plan's pressure or the vented
            # one, tests/locomotion/test_gait_table.py); gait simulates them, to CVODES' ~1e-10 (and 1e-5 Pa
            # at 500 Pa)
            assert step["pressures_Pa"] == pytest.approx([want["pressures_Pa"][n] for n in names], rel=1e-9,
                                                         abs=1e-4)
            planned = [s["planned_pressure_Pa"] for s in document["segments"]]
            for got, plan_pressure in zip(step["pressures_Pa"], planned, strict=True):
                assert got == pytest.approx(plan_pressure, rel=1e-11) or got == 500.0  # the default vented


def test_c_is_self_contained(tmp_path):
    """<math.h> only, no allocation, no writable globals: every symbol is code or read-only data."""
    write_export(load_mission(PROBLEMS / "missions" / "downhill-drain.yaml"), tmp_path)
    source = (tmp_path / "pampipe_plan.c").read_text()
    header = (tmp_path / "pampipe_plan.h").read_text()
    includes = [line for line in (source + header).splitlines() if line.startswith("#include")]
    assert includes == ["#include <math.h>", '#include "pampipe_plan.h"']
    for real, extra in (("double", []), ("float", export_c.FLOAT_FLAGS)):
        obj = tmp_path / f"plan_{real}.o"
        subprocess.run([export_c.compiler(), *export_c.FLAGS, *extra, "-fno-pic", "-c", "-o", str(obj),
                        str(tmp_path / "pampipe_plan.c")], check=True, capture_output=True)
        symbols = subprocess.run(["nm", str(obj)], check=True, capture_output=True, text=True).stdout
        entries = [line.split()[-2:] for line in symbols.splitlines() if line.strip()]
        assert not {kind for kind, _ in entries} & set("BbDdCGgSs"), symbols  # nothing writable
        math_names = {"sqrt", "sin", "cos", "tan", "fabs", "fmax", "fmin", "pow", "exp", "log", "log1p",
                      "acos"}
        allowed = math_names | {f"{n}f" for n in math_names}
        assert {name for kind, name in entries if kind == "U"} <= allowed, symbols  # libm only


def test_names_are_escaped(tmp_path):
    """Quotes, backslashes, trigraphs, comment ends and UTF-8 in names survive C strings and comments."""
    mission = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    odd = ['say "hi"', "back\\slash ??= */ /*", "Steigleitung-\u00e9\u00e8 \u2191"]
    for segment, name in zip(mission["robot"]["segments"], odd, strict=True):
        segment["name"] = name
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    mission["route"][0]["name"] = odd[1]
    mission["route"][1]["name"] = odd[2]
    path = tmp_path / "odd.yaml"
    path.write_text(yaml.safe_dump(mission, allow_unicode=True), encoding="utf-8")
    write_export(load_mission(path), tmp_path / "c")
    table, names = export_c.run_table(export_c.build(tmp_path / "c", real="float"))
    assert names == odd
    assert [t["name"] for t in table] == odd[1:]


def test_export_command(tmp_path, capsys):
    mission = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
    out = tmp_path / "riser_bot"
    capsys.readouterr()
    assert main(["export", str(mission), "-o", str(out), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert sorted(p.name for p in out.iterdir()) == ["pampipe_plan.c", "pampipe_plan.h", "riser_bot.ino"]
    assert document["files"] == ["pampipe_plan.c", "pampipe_plan.h", "riser_bot.ino"]
    assert document["reason_codes"] == {"ok": 0, "narrow": 1, "wide": 2, "no_friction": 3, "above_supply": 4,
                                        "bad_argument": 5}
    assert [s["reason_code"] for s in document["sections"]] == [0, 0]
    header = (out / "pampipe_plan.h").read_text()
    assert hashlib.sha256(mission.read_bytes()).hexdigest() in header
    assert "Mission: vertical-climb-3in.yaml" in header and "pampipe 0.1.0" in header
    assert str(PROBLEMS) not in header  # inputs are named relative to the mission's folder
    assert "#define PAMPIPE_SEGMENTS 3" in header
    assert ("int pampipe_required_pressure(pampipe_real inner_diameter_m, pampipe_real incline_rad, "
            "pampipe_real friction,\n                              pampipe_real payload_kg, "
            "pampipe_real pressure_Pa[PAMPIPE_SEGMENTS]);") in header
    before = (out / "pampipe_plan.c").read_text()
    (out / "pampipe_plan.c").write_text("edited")
    assert main(["export", str(mission), "-o", str(out)]) == 2  # outputs exist
    assert "--force" in capsys.readouterr().err
    assert (out / "pampipe_plan.c").read_text() == "edited"
    assert main(["export", str(mission), "-o", str(out), "--force"]) == 0
    assert (out / "pampipe_plan.c").read_text() == before  # deterministic
    # the exported law's pressures are plan's, section by section (compiled with the driver in a copy)
    import shutil

    built = tmp_path / "built"
    shutil.copytree(out, built)
    loaded = load_mission(mission)
    rows = [(s.diameter, s.incline, s.friction, loaded.payload) for s in loaded.route]
    codes, pressures = export_c.run_law(export_c.build(built), rows)
    assert codes.tolist() == [0, 0]
    np.testing.assert_allclose(pressures, plan_mission(loaded).arrays.pressure, rtol=1e-9)
    odd = tmp_path / "my firmware"
    assert main(["export", str(mission), "-o", str(odd)]) == 0
    assert (odd / "pampipe_example.ino").exists()
    assert "folder named pampipe_example" in capsys.readouterr().out


def test_header_is_the_same_wherever_the_mission_lies(tmp_path, capsys):
    """The same mission exported from two absolute folders: byte-identical files, mission hash included;
    the inputs named relative to the mission's folder with the SHA-256 of their bytes."""
    import shutil

    texts = []
    for place in ("a", "deeper/b"):
        problems = shutil.copytree(PROBLEMS, tmp_path / place / "problems")
        out = tmp_path / place / "out"
        assert main(["export", str(problems / "missions" / "vertical-climb-3in.yaml"), "-o", str(out)]) == 0
        texts.append({p.name: p.read_bytes() for p in out.iterdir()})
    assert texts[0] == texts[1]
    header = texts[0]["pampipe_plan.h"].decode()
    for name in ("missions/vertical-climb-3in.yaml", "pams/paper-radial-pam.yaml"):
        digest = hashlib.sha256((PROBLEMS / name).read_bytes()).hexdigest()
        shown = name.split("/")[1] if name.startswith("missions/") else f"../{name}"
        assert f"  {digest}  {shown}\n" in header
    assert str(tmp_path) not in header


def test_api_returns_the_command_document(tmp_path, capsys):
    """pampipe.export_mission on a path and on a dict: the CLI's --json document, and the same files."""
    mission = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
    capsys.readouterr()
    assert main(["export", str(mission), "-o", str(tmp_path / "pampipe_example"), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    export = pampipe.export_mission(str(mission))
    assert json.loads(to_json(export.to_dict())) == printed
    assert all((tmp_path / "pampipe_example" / n).read_text() == t for n, t in export.files.items())
    raw = yaml.safe_load(mission.read_text())
    from_dict = pampipe.export_mission(raw, base=mission.parent)
    def body(text):  # after the provenance comment, which the mission hash covers too
        return re.sub(r"0x[0-9a-f]{15}", "HASH", text.split("*/", 1)[1])

    assert body(from_dict.files["pampipe_plan.c"]) == body(export.files["pampipe_plan.c"])
    assert from_dict.provenance.inputs[0][0].endswith("paper-radial-pam.yaml")  # a dict has no bytes to hash


def test_export_never_writes_over_an_input(tmp_path, capsys):
    mission = tmp_path / "pampipe_plan.h"
    mission.write_text((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text().replace(
        "../pams/", f"{PROBLEMS}/pams/"))
    before = mission.read_text()
    assert main(["export", str(mission), "-o", str(tmp_path), "--force"]) == 2
    assert "input file" in capsys.readouterr().err
    assert mission.read_text() == before


@pytest.mark.parametrize("effect", ["end_effects", "braid_extensibility"])
def test_effects_without_closed_form_are_refused(tmp_path, capsys, effect):
    values = {"end_effects": {"volume_taper": 0.3, "end_length": 0.5},
              "braid_extensibility": {"compliance": "2 1/MN"}}[effect]
    path = diagnosed_mission(tmp_path, {"axial_preload": {"preload": "10 N"}, effect: values})
    assert main(["export", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"the effect '{effect}' cannot be exported to C" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_plan_reason_past_the_third_section(tmp_path):
    """Regression: the payload in the supply reason of section s ≥ 3 (it indexed the row again)."""
    mission = yaml.safe_load((PROBLEMS / "missions" / "infeasible-survey.yaml").read_text())
    for segment in mission["robot"]["segments"]:
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    sections = {s["name"]: s for s in mission["route"]}
    runs = [{**sections["ok-run"], "name": f"run{k}"} for k in range(3)]
    mission["route"] = [*runs, sections["heavy-riser"]]
    path = tmp_path / "four.yaml"
    path.write_text(yaml.safe_dump(mission))
    plan = plan_mission(load_mission(path), with_max_payload=True)
    assert [s.feasible for s in plan.sections] == [True, True, True, False]
    limit = plan.max_payload.sections[3].payload
    assert plan.sections[3].reason.endswith(f"at most {limit:.3g} kg of payload here.")
