"""The tests mirror the package: tests/<folder>/test_<topic>.py, with folders named as pampipe's (and a few
for what spans it), shared helpers in tests/support/, and no test module importing another."""

from __future__ import annotations

import ast

from tests.support.problems import ROOT

TESTS = ROOT / "tests"
#: Test folders that name no folder of pampipe/: the command line, the API, the layout, the docs, the wheel;
#: support/ holds the helpers, bad_inputs/ the corpus of broken inputs (data).
BEYOND_THE_PACKAGE = {"commands", "api", "architecture", "docs", "packaging", "support", "bad_inputs"}


def test_no_test_file_lies_flat_in_tests():
    assert sorted(p.name for p in TESTS.glob("*.py")) == ["__init__.py", "conftest.py"]


def test_every_test_folder_is_named_after_a_folder_of_the_package():
    package = {p.name for p in (ROOT / "pampipe").iterdir() if (p / "__init__.py").exists()}
    folders = {p.name for p in TESTS.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert not (stray := sorted(folders - package - BEYOND_THE_PACKAGE)), stray


def imported_test_modules(source: str) -> list[str]:
    """The test modules (and conftest) that ``source`` imports: what tests/support/ is for."""
    names = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names += [node.module, *(f"{node.module}.{a.name}" for a in node.names)]
    return [n for n in names if n.split(".")[-1].startswith("test_") or n.split(".")[-1] == "conftest"]


def test_no_test_module_imports_another():
    found = {path.relative_to(ROOT).as_posix(): names for path in sorted(TESTS.rglob("*.py"))
             if (names := imported_test_modules(path.read_text(encoding="utf-8")))}
    assert not found, found


def test_the_import_check_can_fail():
    assert imported_test_modules("from tests.planning.test_bores import scan_maximum\nimport numpy\n") == [
        "tests.planning.test_bores"]
    assert imported_test_modules("def f():\n    from tests.conftest import PROBLEMS\n") == ["tests.conftest"]
    assert imported_test_modules("from tests import test_export\n") == ["tests.test_export"]
