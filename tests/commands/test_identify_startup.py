"""Start-up of `pampipe identify` (issue 25 item 1): an experiment read before loads from the cache of
validated files (:mod:`pampipe.io.validated`, the one `plan` uses) without pydantic or PyYAML, gives the
same document, and is validated again as soon as a file its validation read changes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from importlib.metadata import version

from pampipe import __version__
from tests.support.problems import PROBLEMS, ROOT
from tests.support.processes import in_fresh_interpreter

PRIOR = "pams/paper-radial-pam-uncertain.yaml"


def _identify_in_fresh_interpreter(experiment, cache, *flags):
    """(exit code, stdout, names of pydantic/yaml modules loaded) of `pampipe identify EXPERIMENT --json
    --reproducible FLAGS`."""
    return in_fresh_interpreter(["identify", str(experiment), "--json", "--reproducible", *flags],
                                {"pydantic", "yaml"}, cache)


def _with_prior(folder):
    """The bundled paper-protocol experiment in ``folder``, with a PAM file as its prior (fit.prior.pam)."""
    shutil.copytree(PROBLEMS / "experiments" / "data", folder / "data")
    shutil.copytree(PROBLEMS / "pams", folder / "pams")
    experiment = folder / "experiment.yaml"
    text = (PROBLEMS / "experiments" / "paper-protocol.yaml").read_text()
    assert "\n  prior:" not in text and text.endswith("\n") and text.splitlines()[-1].startswith("  ")
    experiment.write_text(text + f"  prior: {{pam: {PRIOR}}}\n")  # into its fit: block, the last
    return experiment


def test_an_experiment_read_before_loads_neither_pydantic_nor_yaml_and_fits_the_same(tmp_path):
    experiment = _with_prior(tmp_path / "work")
    first = _identify_in_fresh_interpreter(experiment, tmp_path / "cache")
    second = _identify_in_fresh_interpreter(experiment, tmp_path / "cache")
    assert first[0] == second[0] == 0
    assert first[2] == ["pydantic", "yaml"] and second[2] == []
    assert second[1] == first[1]  # byte-identical (--reproducible)
    assert json.loads(first[1])["fit"]["prior"]["kind"] == "gaussian"


def test_a_kept_experiment_is_validated_again_when_its_prior_file_changes(tmp_path):
    """Editing the prior's PAM file (read by the validation, not named by the experiment's own keys)
    refits with the edited prior, as with the cache off; a schema error in it is explained (exit 2)."""
    experiment = _with_prior(tmp_path / "work")
    cache = tmp_path / "cache"
    code, before, _ = _identify_in_fresh_interpreter(experiment, cache)
    assert code == 0
    prior = experiment.parent / PRIOR
    text = prior.read_text()
    assert "hoop:  {a: [4.443711," in text
    prior.write_text(text.replace("hoop:  {a: [4.443711,", "hoop:  {a: [3.9,"))
    code, edited, loaded = _identify_in_fresh_interpreter(experiment, cache)
    assert code == 0 and loaded == ["pydantic", "yaml"]
    assert edited != before
    assert edited == _identify_in_fresh_interpreter(experiment, "off")[1]
    prior.write_text(text.replace("reference_pressure:", "reference_pressure_was:"))
    code, _, loaded = _identify_in_fresh_interpreter(experiment, cache)
    assert code == 2 and loaded == ["pydantic", "yaml"]


def test_flags_pass_the_schema_with_the_experiment_kept(tmp_path):
    """A kept experiment skips the fit: block's validation, never that of the command line's flags."""
    experiment = _with_prior(tmp_path / "work")
    assert _identify_in_fresh_interpreter(experiment, tmp_path / "cache")[0] == 0
    code, _, loaded = _identify_in_fresh_interpreter(experiment, tmp_path / "cache", "--max-iterations", "0")
    assert code == 2 and loaded == ["pydantic"]


def test_the_version_in_the_provenance_is_the_installed_one():
    """identify's provenance gives pampipe.__version__, which must be the installed package's version."""
    assert __version__ == version("pampipe")


def test_identify_keeps_freed_memory_for_reuse(tmp_path):
    """The command asks glibc to reuse freed blocks (pampipe.runtime.heap: at 3·10⁶ rows 1.5·10⁵ page faults
    become 6·10⁴) before it reads the data."""
    experiment = PROBLEMS / "experiments" / "paper-protocol.yaml"
    code = ("import sys\nfrom pampipe.cli import main\nfrom pampipe.runtime.heap import retain_freed_memory\n"
            f"code = main(['identify', {str(experiment)!r}, '--json'])\n"
            "print('ASKED', retain_freed_memory.cache_info().currsize, file=sys.stderr)\nsys.exit(code)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "PAMPIPE_NLP_CACHE": str(tmp_path / "cache")}, timeout=300)
    assert out.returncode == 0 and "ASKED 1" in out.stderr


def test_an_experiment_without_slip_tests_does_not_load_the_slip_package(tmp_path):
    """pampipe.slip (μ and κ from slip tests, ~20 ms of imports) loads only for experiments with them."""
    code = ("import sys\nfrom pampipe.cli import main\n"
            "codes = [main(['identify', sys.argv[1], '--json', '--reproducible'])]\n"
            "before = any(m.startswith('pampipe.slip') for m in sys.modules)\n"
            "codes.append(main(['identify', sys.argv[2], '--json', '--reproducible']))\n"
            "after = any(m.startswith('pampipe.slip') for m in sys.modules)\n"
            "print('SLIP', codes, before, after, file=sys.stderr)\n")
    experiments = [str(PROBLEMS / "experiments" / name) for name in ("paper-protocol.yaml", "slip-3in.yaml")]
    out = subprocess.run([sys.executable, "-c", code, *experiments], capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "PAMPIPE_NLP_CACHE": str(tmp_path / "cache")}, timeout=300)
    line = next(line for line in out.stderr.splitlines() if line.startswith("SLIP"))
    assert line == "SLIP [0, 0] False True", out.stderr[-2000:]
