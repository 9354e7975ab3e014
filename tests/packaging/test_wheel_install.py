"""A plain `pip install` of the wheel is complete: every command works outside the repository (issue 21).

The wheel is built offline from a copy of the sources (`pip wheel --no-build-isolation`, with the setuptools
of the test extra) and installed without its dependencies into a fresh venv; that venv sees the project venv's
dependencies through a `.pth` line, but not its editable pampipe (whose finder is never run). The commands run
in a scratch folder with no `problems/` in reach, so what they read must come from the installed package.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path
from types import SimpleNamespace

import pytest

from tests.support.problems import ROOT

SOURCES = ("pampipe", "problems", "yaml", "setup.py", "pyproject.toml", "README.md", "LICENSE")


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A venv holding only the pampipe wheel (dependencies borrowed from this one), and a scratch folder."""
    base = tmp_path_factory.mktemp("wheel")
    source = base / "source"
    for name in SOURCES:
        copy = shutil.copytree if (ROOT / name).is_dir() else shutil.copy
        copy(ROOT / name, source / name, **({"ignore": shutil.ignore_patterns("__pycache__")}
                                            if (ROOT / name).is_dir() else {}))
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-qq"]
    subprocess.run([*pip, "wheel", "--no-deps", "--no-build-isolation", "-w", base / "dist", source],
                   check=True, capture_output=True, text=True)
    wheel = next((base / "dist").glob("pampipe-*.whl"))
    target = base / "venv"
    venv.create(target, with_pip=False)
    python = target / "bin" / "python"
    subprocess.run([*pip, "--python", python, "install", "--no-deps", wheel], check=True, capture_output=True)
    site = Path(subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               check=True, capture_output=True, text=True).stdout.strip())
    borrowed = dict.fromkeys([sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])
    (site / "zz-borrowed-dependencies.pth").write_text("".join(f"{p}\n" for p in borrowed))
    scratch = base / "scratch"
    scratch.mkdir()
    return SimpleNamespace(bin=target / "bin", site=site, scratch=scratch, wheel=wheel)


def run(installed, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PATH": f"{installed.bin}{os.pathsep}{os.environ['PATH']}", "MPLBACKEND": "Agg"}
    env.pop("PYTHONPATH", None)
    return subprocess.run(["pampipe", *args], capture_output=True, text=True, cwd=installed.scratch, env=env)


def test_the_wheel_carries_the_bundled_problems(installed):
    import zipfile

    names = zipfile.ZipFile(installed.wheel).namelist()
    shipped = {Path(n).relative_to("pampipe/examples").as_posix() for n in names
               if n.startswith("pampipe/examples/")}
    expected = {p.relative_to(ROOT / "problems").as_posix() for p in (ROOT / "problems").rglob("*")
                if p.is_file() and p.suffix in (".yaml", ".csv")}
    assert expected and expected <= shipped


def test_the_wheel_carries_the_schemas(installed):
    """Issue 42: `yaml/`'s JSON Schemas ship as pampipe/schemas, for `example` to copy beside its files."""
    import zipfile

    names = set(zipfile.ZipFile(installed.wheel).namelist())
    expected = {f"pampipe/schemas/{p.name}" for p in (ROOT / "yaml").glob("*.schema.json")}
    assert len(expected) >= 4 and expected <= names


def test_pampipe_is_the_installed_wheel(installed):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # a caller's tree must not shadow it
    out = subprocess.run([installed.bin / "python", "-c", "import pampipe; print(pampipe.__file__)"],
                         capture_output=True, text=True, cwd=installed.scratch, check=True, env=env)
    assert Path(out.stdout.strip()).is_relative_to(installed.site)


@pytest.mark.parametrize("name", ["ky4-route", "ky4-network", "vertical-climb-3in", "paper-protocol",
                                  "riser"])
def test_example_copies_outside_the_repository(installed, name):
    out = run(installed, "example", name, f"ex-{name}", "--json")
    assert out.returncode == 0, out.stderr
    files = [Path(f) for f in json.loads(out.stdout)["files"]]
    assert files and all((installed.scratch / f).is_file() for f in files)
    assert all((installed.scratch / f).resolve().is_relative_to(installed.scratch) for f in files)
    for path in (installed.scratch / f for f in files if f.suffix == ".yaml"):  # its schema line resolves
        schema = path.read_text().splitlines()[0].split("$schema=")[1]
        assert (path.parent / schema).resolve() == (installed.scratch / f"ex-{name}" / "yaml" /
                                                    Path(schema).name).resolve()
        assert (path.parent / schema).read_bytes() == (ROOT / "yaml" / Path(schema).name).read_bytes()


def test_route_default_template_comes_from_the_installed_package(installed):
    out = run(installed, "route", "ky4", "--from", "J-315", "--to", "J-897", "-o", "r.yaml", "--json")
    assert out.returncode == 0, out.stderr
    assert Path(json.loads(out.stdout)["template"]).is_relative_to(installed.site)
    planned = run(installed, "plan", "r.yaml", "--json")  # its PAM paths lead into the installed package
    assert planned.returncode in (0, 3), planned.stderr
    assert "Traceback" not in planned.stderr and json.loads(planned.stdout)


def test_copied_examples_plan_synth_identify_and_simulate(installed):
    mission = "demo/missions/vertical-climb-3in.yaml"
    for args in (["example", "vertical-climb-3in", "demo"], ["plan", mission], ["gait", mission],
                 ["synth", "exp", "--seed", "1", "--points-per-leg", "5"],
                 ["identify", "exp/experiment.yaml"],
                 ["simulate", "demo/pams/paper-radial-pam.yaml", "-d", "3 in", "-f", "0"]):
        out = run(installed, *args)
        assert out.returncode == 0, (args, out.stderr)


@pytest.mark.slow
def test_every_readme_command_runs_with_the_wheel(installed, tmp_path):
    """The README's commands (the convention of tests/support/doc_commands.py) with the wheel's `pampipe`
    (≈ 60 s)."""
    from tests.support.doc_commands import commands, run_docs

    run_docs(installed.bin, tmp_path, commands(["README.md"]))
