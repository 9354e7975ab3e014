"""The layout of pampipe/ keeps its architecture (docs/architecture.md), by the rules of
tests/support/architecture.py.

Every import counts, however it is made: at module level, inside functions, under ``if TYPE_CHECKING:``,
through ``importlib.import_module``/``__import__`` and as a string target such as ``"pampipe.x.y:name"``
(tests/support/import_graph.py; tests/architecture/test_checker.py shows each kind caught). A failure lists
every finding with the rule, the file and the line.
"""

from __future__ import annotations

import pytest

from tests.support import architecture as arch
from tests.support.import_graph import Package
from tests.support.problems import ROOT

PACKAGE = Package.from_folder(ROOT / "pampipe")


def report(findings: list[str]) -> str:
    return f"{len(findings)} found:\n" + "\n".join(findings)


def test_every_part_of_the_package_has_a_layer_and_every_layer_a_part():
    assert not (found := arch.layer_gaps(PACKAGE)), report(found)


@pytest.mark.parametrize("rule", arch.RULES, ids=lambda rule: rule.key)
def test_imports_keep_the_rule(rule):
    assert not (found := arch.rule_violations(PACKAGE, rule)), report(found)


def test_no_import_circle_between_files():
    assert not (found := arch.file_circles(PACKAGE)), report(found)


def test_no_import_circle_between_folders():
    assert not (found := arch.folder_circles(PACKAGE)), report(found)


def test_the_root_holds_the_face_the_entry_points_and_the_protocol_only():
    assert not (found := arch.root_violations(PACKAGE)), report(found)


def test_no_file_over_500_lines():
    assert not (found := arch.long_files(PACKAGE)), report(found)


def test_no_function_over_80_lines():
    assert not (found := arch.long_functions(PACKAGE)), report(found)


def test_no_two_modules_carry_a_confusable_name():
    assert not (found := arch.twins(PACKAGE)), report(found)
