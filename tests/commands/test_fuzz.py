"""Property-based fuzzing of the CLI with mutated problem files (issue 7).

PAMPIPE_FUZZ_EXAMPLES cases in all (default 120, the quick profile of `make test`; `make fuzz` runs
10⁴) are split over the commands in proportion to how cheap a case is. The property is in
:func:`tests.support.fuzzing.probe`: exit 0, 2 or 3 with a message, never a traceback.
"""

from __future__ import annotations

import functools
import os
import shutil
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.support.fuzzing import NUMBERS, QUANTITIES, mutated, probe
from tests.support.problems import PROBLEMS

# an overflow or NaN on an input that passed validation is a bug, not a warning (issue 7, item 3)
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")

TOTAL = int(os.environ.get("PAMPIPE_FUZZ_EXAMPLES", "120"))
SHARE = {"simulate": 0.45, "plan": 0.35, "gait": 0.1, "identify": 0.1, "law": 0.2, "api": 0.25, "route": 0.15}


def fuzz_settings(command: str):
    return settings(max_examples=max(1, round(TOTAL * SHARE[command])), deadline=None,
                    derandomize=not os.environ.get("PAMPIPE_FUZZ_RANDOM"), database=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _load(*parts):
    return yaml.safe_load((PROBLEMS.joinpath(*parts)).read_text())


RADIAL_PAM = _load("pams", "paper-radial-pam.yaml")
MISSION = _load("missions", "vertical-climb-3in.yaml")
EXPERIMENT = _load("experiments", "paper-protocol.yaml")


def _write(folder, name, document):
    path = folder / name
    path.write_text(yaml.safe_dump(document, allow_unicode=True))
    return path


def _mission_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz") / "missions"
    folder.mkdir()
    shutil.copytree(PROBLEMS / "pams", folder.parent / "pams")
    return folder


@fuzz_settings("simulate")
@given(document=mutated(RADIAL_PAM))
def test_simulate_survives_mutated_pam_files(tmp_path_factory, document):
    path = _write(tmp_path_factory.mktemp("fuzz"), "pam.yaml", document)
    probe(["simulate", str(path), "--pipe-diameter", "3 in", "--pressure", "300 kPa", "--json"])


@fuzz_settings("plan")
@given(document=mutated(MISSION))
def test_plan_survives_mutated_missions(tmp_path_factory, document):
    path = _write(_mission_folder(tmp_path_factory), "mission.yaml", document)
    probe(["plan", str(path), "--json"])


@fuzz_settings("gait")
@given(document=mutated(MISSION))
def test_gait_survives_mutated_missions(tmp_path_factory, document):
    path = _write(_mission_folder(tmp_path_factory), "mission.yaml", document)
    probe(["gait", str(path), "--json"])


@fuzz_settings("identify")
@given(document=mutated(EXPERIMENT))
def test_identify_survives_mutated_experiments(tmp_path_factory, document):
    folder = tmp_path_factory.mktemp("fuzz")
    data = folder / "data" / "paper-protocol"
    data.mkdir(parents=True)
    for csv in (PROBLEMS / "experiments" / "data" / "paper-protocol").glob("*.csv"):
        lines = csv.read_text().splitlines()
        data.joinpath(csv.name).write_text("\n".join(lines[:1] + lines[1::6]) + "\n")  # every 6th row
    path = _write(folder, "experiment.yaml", document)
    probe(["identify", str(path), "--json"])


# --------------------------------------------------------------- issue 27: the C law, the API, route
LAW_ROWS = int(os.environ.get("PAMPIPE_FUZZ_LAW_ROWS", "10000"))


@pytest.fixture(scope="module")
def law_drivers(tmp_path_factory):
    """mission name -> (mission, export, compiled C driver), for the C law's fuzzing."""
    from pampipe.io.mission_schema import load_mission
    from tests.support import export_c
    from tests.support.export_c import write_export

    if export_c.compiler() is None:
        pytest.skip("no host C compiler (gcc or cc) found")
    out = {}
    for name in ("vertical-climb-3in", "downhill-drain", "infeasible-survey"):
        mission = load_mission(PROBLEMS / "missions" / f"{name}.yaml")
        folder = tmp_path_factory.mktemp(f"law-{name}")
        out[name] = (mission, write_export(mission, folder), export_c.build(folder))
    return out


def _law_unsafe(law_drivers, rows) -> int:
    from tests.support import export_c, law_fuzz

    unsafe = 0
    for mission, export, exe in law_drivers.values():
        codes, pressure = export_c.run_law(exe, rows)
        unsafe += int(law_fuzz.unsafe_ok(mission, rows, codes, pressure).sum())
        twin = [int(export.law.evaluate(*row)[0]) for row in rows[:500]]
        assert twin == codes[:500].tolist()  # the Python law answers as the C one
    return unsafe


@pytest.mark.parametrize("count", [LAW_ROWS, pytest.param(100_000, marks=pytest.mark.slow)])
def test_c_law_never_answers_ok_unsafely(law_drivers, count):
    """`count` random rows per mission, inside and far outside the domain (NaN, ±inf): 0 unsafe OK."""
    from tests.support import law_fuzz

    rng = np.random.default_rng(count)
    _, export, _ = law_drivers["vertical-climb-3in"]
    assert _law_unsafe(law_drivers, law_fuzz.arguments(rng, count, export.law)) == 0


@fuzz_settings("law")
@given(rows=st.lists(st.tuples(*[st.floats(allow_nan=True, allow_infinity=True, width=64)] * 4),
                     min_size=1, max_size=200))
def test_c_law_never_answers_ok_unsafely_on_any_floats(law_drivers, rows):
    assert _law_unsafe(law_drivers, np.array(rows, dtype=float)) == 0


API_NUMBERS = st.one_of(
    NUMBERS, QUANTITIES, st.none(), st.booleans(), st.text(max_size=8),
    st.builds(np.float32, st.floats(width=32)), st.builds(np.int64, st.integers(-10**6, 10**6)),
    st.builds(np.array, st.floats()), st.builds(Decimal, st.decimals(allow_nan=True)),
    st.builds(Fraction, st.integers(-10**6, 10**6), st.integers(1, 10**6)),
    st.builds(lambda x, u: pint_units().Quantity(x, u), st.floats(-1e6, 1e6),
              st.sampled_from(["kg", "g", "lb", "m", "kPa", "percent", "deg", ""])),
    st.lists(st.floats(), max_size=3))


@functools.cache
def pint_units():
    import pint

    return pint.UnitRegistry()


@fuzz_settings("api")
@given(payload=API_NUMBERS, confidence=st.one_of(st.none(), API_NUMBERS),
       solver=st.one_of(st.sampled_from(["kkt", "ipopt"]), API_NUMBERS),
       max_payload=st.one_of(st.booleans(), API_NUMBERS))
def test_api_plan_takes_any_value(payload, confidence, solver, max_payload):
    """Any value for any option: a result or a pampipe error (InputError naming the option), nothing else."""
    import pampipe
    from pampipe.errors import PampipeError

    try:
        pampipe.plan(PROBLEMS / "missions" / "vertical-climb-3in.yaml", payload=payload,
                     confidence=confidence, solver=solver, max_payload=max_payload)
    except PampipeError:
        pass


def _net1() -> list[str]:
    from wntr.library import model_library

    return open(model_library.get_filepath("Net1"), encoding="utf-8").read().splitlines()


@fuzz_settings("route")
@given(data=st.data())
def test_route_survives_mutated_networks(tmp_path_factory, data):
    """Net1 with lines duplicated, deleted or garbled: exit 0, 2 or 3 with a message, never a traceback."""
    lines = _net1()
    for _ in range(data.draw(st.integers(1, 4))):
        k = data.draw(st.integers(0, len(lines) - 1))
        kind = data.draw(st.sampled_from(["duplicate", "delete", "garble", "number"]))
        if kind == "duplicate":
            lines.insert(k, lines[k])
        elif kind == "delete":
            del lines[k]
        elif kind == "garble":
            lines[k] = data.draw(st.text(max_size=30))
        else:
            bad = st.sampled_from(["nan", "-1", "1e400", "0", "x"])
            lines[k] = " ".join(data.draw(bad) if w[:1].isdigit() else w for w in lines[k].split())
    path = tmp_path_factory.mktemp("route") / "net.inp"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8", errors="surrogatepass")
    probe(["route", str(path), "--from", "10", "--to", "2", "--json"])
