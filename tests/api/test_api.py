"""The Python API (docs/commands.md §11.1), the bundled problems as package data, and PAM round trips.

* the API returns the same documents as the CLI's ``--json`` (byte for byte with ``--reproducible``);
* a path, a dict and unit strings give the same answers as SI numbers;
* the README's notebook example runs;
* after ``pip install .`` (no make, no checkout), ``synth`` works from any folder with its default
  muscle, and ``example`` copies a mission that plans;
* PAM names that YAML could misread survive the writer that ``identify -o`` and ``diagnose -o`` use.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest
import yaml

import pampipe
from pampipe import api
from pampipe.io.files import to_json
from pampipe.io.pam_schema import load_pam
from pampipe.io.pamfile import write_pam
from tests.support.problems import PROBLEMS, ROOT
from tests.support.processes import run_cli

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
PAM = PROBLEMS / "pams" / "paper-radial-pam.yaml"


def _cli_json(*args) -> str:
    result = run_cli(*args, "--json", "--reproducible")
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.mark.parametrize("command, call", [
    (("plan", DEMO), lambda: api.plan(DEMO)),
    (("plan", DEMO, "--payload", "3 kg", "--max-payload"),
     lambda: api.plan(DEMO, payload="3 kg", max_payload=True)),
    (("gait", DEMO, "--section", "run"), lambda: api.gait(DEMO, section="run")),
    (("simulate", PAM, "-d", "3 in", "-d", "3.5 in", "-f", "0 N", "-f", "1024.74 N", "-p", "400 kPa"),
     lambda: api.simulate(PAM, pipe_diameter=["3 in", "3.5 in"], axial_load=[0, "1024.74 N"],
                          pressure=["400 kPa"])),
], ids=["plan", "plan-payload", "gait", "simulate"])
def test_api_returns_the_cli_document(command, call):
    assert to_json(call().to_dict(), timings=False) == _cli_json(*command)


def test_identify_api_equals_cli():
    """... and its progress callback hears the fit (issue 42: it was called only while the data loaded)."""
    experiment = PROBLEMS / "experiments" / "paper-protocol.yaml"
    said: list[str] = []
    document = api.identify(experiment, degree=1, progress=said.append).to_dict()
    assert to_json(document, timings=False) == _cli_json("identify", experiment, "--degree", "1")
    assert any(line.startswith("solving the 8-parameter NLP with IPOPT") for line in said), said


def test_a_dict_and_unit_strings_give_the_same_plan(tmp_path):
    raw = yaml.safe_load(DEMO.read_text())
    from_dict = api.plan(raw, base=DEMO.parent, payload="3000 g")
    from_file = api.plan(DEMO, payload=3.0)
    assert to_json(from_dict.to_dict(), timings=False).replace("<mission dict>", "vertical-climb-3in.yaml") \
        == to_json(from_file.to_dict(), timings=False)
    with pytest.raises(pampipe.errors.InputError, match="payload"):
        api.plan(DEMO, payload="3 kPa")


def test_readme_notebook_example_runs(tmp_path):
    """The README's five-line example, run as written from the repository's root."""
    text = (ROOT / "README.md").read_text()
    block = re.search(r"<!-- notebook example -->\s*```python\n(.*?)```", text, re.S)
    assert block, "README.md lost its notebook example"
    code = block.group(1)
    assert len(code.strip().splitlines()) <= 5
    namespace: dict = {}
    cwd = os.getcwd()
    try:
        os.chdir(ROOT)
        exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    assert namespace["plan"].feasible


@pytest.mark.parametrize("name", ["pump # 2", "a: b", "it's \"quoted\"", "yes", "1234", "0o17", "1:30",
                                  "- dash", "null"])
def test_pam_names_round_trip_through_the_writer(tmp_path, radial_pam, name):
    """The writer `identify -o` and `diagnose -o` use: any name reads back as the same string."""
    import dataclasses

    pam = dataclasses.replace(radial_pam, name=name)
    write_pam(tmp_path / "pam.yaml", pam, comments=["a comment # with a hash"])
    back = load_pam(tmp_path / "pam.yaml")
    assert back.name == name
    assert back.geometry == pam.geometry
    assert back.moduli.as_vector().tolist() == pam.moduli.as_vector().tolist()  # shortest round-trip floats


def test_identify_writes_a_pam_whose_tricky_name_reads_back(tmp_path):
    experiment = yaml.safe_load((PROBLEMS / "experiments" / "paper-protocol.yaml").read_text())
    experiment["pam"]["name"] = "yes # 1: 'x'"
    for test in experiment["tests"]:
        test["data"] = str((PROBLEMS / "experiments" / test["data"]).resolve())
    (tmp_path / "exp.yaml").write_text(yaml.safe_dump(experiment))
    result = run_cli("identify", tmp_path / "exp.yaml", "--degree", "1", "-o", tmp_path / "fit.yaml")
    assert result.returncode == 0, result.stderr
    assert load_pam(tmp_path / "fit.yaml").name == "yes # 1: 'x'"


def test_the_api_names_stay_functions_after_every_module_is_imported():
    """`pampipe.plan(...)` must not turn into a subpackage once some module imported `pampipe.<name>.x`.

    A fresh interpreter imports every pampipe module first (as a long notebook session would), then
    calls ``pampipe.plan`` twice: both calls must be the API function and give the same pressures.
    """
    code = """
import importlib, pkgutil, pampipe
for info in pkgutil.walk_packages(pampipe.__path__, "pampipe."):
    if not info.name.startswith(("pampipe.examples", "pampipe.__main__")):
        importlib.import_module(info.name)
from pampipe import api
expected = {n: getattr(api, n, pampipe.Muscle) for n in pampipe.__all__ if n != "__version__"}
clashes = [n for n, value in expected.items() if getattr(pampipe, n) is not value]
assert not clashes, clashes
first = pampipe.plan("problems/missions/vertical-climb-3in.yaml").arrays.pressure
second = pampipe.plan("problems/missions/vertical-climb-3in.yaml", payload="2 kg").arrays.pressure
assert (first == second).all()
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
