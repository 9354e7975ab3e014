"""The shortcut for one-line route entries (pampipe.io.yamlfile._flow_lines, issue 25) changes no plan:
the text report and the JSON of a long generated route and of bundled missions are byte for byte those of the
same files parsed event by event."""

from __future__ import annotations

from unittest import mock

import pytest

from pampipe.io import yamlfile
from tests.support.problems import PROBLEMS

BORES = ["3 in", "3.5 in", "80 mm", "{nps: 3, schedule: 40, tolerance: 1 %}", "{dn: 110, sdr: 26}"]


def long_route(folder, sections: int = 300):
    """The demo robot on ``sections`` varied sections, one flow mapping per line (as the benchmark writes)."""
    head = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text().split("route:")[0]
    head = head.replace("../pams", str(PROBLEMS / "pams"))
    lines = [f"  - {{name: s{i}, length: {1 + i % 7} m, inner_diameter: {BORES[i % 5]}, "
             f"incline: {i % 90 - 45} deg, friction: {0.2 + 0.05 * (i % 4):g}}}" for i in range(sections)]
    path = folder / "long.yaml"
    path.write_text(head + "route:\n" + "\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("mission", ["long", "vertical-climb-3in.yaml", "elbows-3in.yaml",
                                     "steel-pipe-sizes.yaml"])
def test_flow_lines_change_no_plan(cli, tmp_path, monkeypatch, mission):
    monkeypatch.setenv("PAMPIPE_NLP_CACHE", "off")  # no kept mission: every run parses the file
    path = long_route(tmp_path) if mission == "long" else PROBLEMS / "missions" / mission
    read = sum(len(mappings) for mappings, _, _ in yamlfile._flow_lines(path.read_text())[0].values())
    assert mission != "long" or read >= 300  # and the segments
    runs = {}
    for shortcut in (True, False):
        reader = yamlfile._flow_lines if shortcut else (lambda text: ({}, text))
        with mock.patch.object(yamlfile, "_flow_lines", reader):
            runs[shortcut] = [cli("plan", path, "--reproducible", *extra) for extra in ((), ("--json",))]
    for fast, slow in zip(runs[True], runs[False], strict=True):
        assert (fast.returncode, fast.stdout, fast.stderr) == (slow.returncode, slow.stdout, slow.stderr)
    assert runs[True][1].stdout.startswith("{")
