"""`pampipe completion bash|zsh` (issue 42, item 8): a script the shell parses that completes commands,
options and option choices, built from the parser."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from tests.support.processes import run_cli


@pytest.fixture(scope="module")
def bash_script() -> str:
    done = run_cli("completion", "bash")
    assert done.returncode == 0, done.stderr
    return done.stdout


def _complete(script: str, line: str) -> list[str]:
    """What bash offers for the last word of ``line`` (``COMPREPLY`` of the script's function)."""
    words = line.split(" ")
    program = (f"{script}\nCOMP_WORDS=({' '.join(repr(w) for w in words)}); COMP_CWORD={len(words) - 1}\n"
               "_pampipe; printf '%s\\n' \"${COMPREPLY[@]}\"")
    done = subprocess.run(["bash", "-c", program], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


@pytest.mark.skipif(shutil.which("bash") is None, reason="no bash")
def test_bash_parses_the_script(bash_script, tmp_path):
    path = tmp_path / "pampipe.bash"
    path.write_text(bash_script)
    assert subprocess.run(["bash", "-n", str(path)], capture_output=True, timeout=60).returncode == 0
    assert "complete -o filenames -o bashdefault -F _pampipe pampipe" in bash_script


@pytest.mark.skipif(shutil.which("bash") is None, reason="no bash")
@pytest.mark.parametrize(("line", "expected"), [
    ("pampipe pl", ["plan"]),
    ("pampipe re", ["rehearse"]),
    ("pampipe plan --confi", ["--confidence"]),
    ("pampipe plan x.yaml --units p", ["psi"]),
    ("pampipe identify e.yaml --mode contact", ["contact_increment"]),
    ("pampipe completion z", ["zsh"]),
])
def test_bash_completes_commands_options_and_choices(bash_script, line, expected):
    assert _complete(bash_script, line) == expected


@pytest.mark.skipif(shutil.which("zsh") is None, reason="no zsh")
def test_zsh_parses_the_script(tmp_path):
    done = run_cli("completion", "zsh")
    path = tmp_path / "_pampipe.zsh"
    path.write_text(done.stdout)
    assert done.stdout.startswith("autoload -U +X bashcompinit && bashcompinit\n")
    assert subprocess.run(["zsh", "-n", str(path)], capture_output=True, timeout=60).returncode == 0


def test_an_unknown_shell_is_exit_2():
    done = run_cli("completion", "fish")
    assert done.returncode == 2
    assert "invalid choice: 'fish'" in done.stderr
