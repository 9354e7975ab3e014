"""The version is one number: `pampipe --version`, the package, CHANGELOG.md's newest release and
CITATION.cff."""

from __future__ import annotations

import re

import yaml

from tests.support.problems import ROOT


def test_version_agrees_everywhere(cli):
    from pampipe import __version__

    out = cli("--version")
    assert out.stdout.split()[-1] == __version__
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    released = re.findall(r"^## \[(\d+\.\d+\.\d+)\]", changelog, re.M)
    assert released and released[0] == __version__
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert citation["version"] == __version__ and citation["cff-version"] == "1.2.0"


def test_the_package_is_typed():
    assert (ROOT / "pampipe" / "py.typed").is_file()
