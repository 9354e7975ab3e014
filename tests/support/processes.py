"""pampipe in another process: as a user runs it, or in a fresh interpreter that reports what it loaded."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.support.problems import ROOT


def in_fresh_interpreter(argv: list[str], watched: set[str], cache, cwd=ROOT):
    """(exit code, stdout, which of the top-level modules ``watched`` were loaded) of `pampipe ARGV` run in a
    fresh interpreter with the cache folder ``cache`` (or ``off``)."""
    code = ("import sys\nfrom pampipe.cli import main\n"
            f"code = main({argv!r})\n"
            f"loaded = sorted({{m.split('.')[0] for m in sys.modules}} & {set(watched)!r})\n"
            "print('LOADED', *loaded, file=sys.stderr)\nsys.exit(code)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=cwd,
                         env={**os.environ, "PAMPIPE_NLP_CACHE": str(cache)}, timeout=300)
    loaded = next(line for line in out.stderr.splitlines() if line.startswith("LOADED")).split()[1:]
    return out.returncode, out.stdout, loaded


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run ``python -m pampipe ARGS`` in a subprocess, as a user would."""
    return subprocess.run([sys.executable, "-m", "pampipe", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=timeout)
