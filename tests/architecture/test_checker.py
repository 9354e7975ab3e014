"""The architecture checks catch what they claim to, on fabricated package sources (none of pampipe's own):
an import inside a function, under ``if TYPE_CHECKING:``, relative, through ``importlib``/``__import__``, a
string target (whole or built at run time), a circle between files and one between folders; long functions
and files, confusable twin names, an extra root module, a folder no layer holds. Each finding names the rule,
the file and the line."""

from __future__ import annotations

import textwrap

import pytest

from tests.support import architecture as arch
from tests.support.import_graph import Package

#: A small package: one module in each part the fabricated ones import.
BASE = {"pampipe/__init__.py": "", "pampipe/cli.py": "", "pampipe/api.py": "", "pampipe/errors.py": "",
        "pampipe/io/config.py": "", "pampipe/views/text.py": "", "pampipe/commands/plan.py": "",
        "pampipe/model/muscle.py": "", "pampipe/planning/law.py": "", "pampipe/bends/plan.py": ""}

SCIENCE = "the science never imports io, and of the views only a result names the view of it"


def package(sources: dict[str, str]) -> Package:
    return Package.from_sources({**BASE, **{path: textwrap.dedent(text) for path, text in sources.items()}})


def findings(sources: dict[str, str]) -> list[str]:
    built = package(sources)
    return [line for rule in arch.RULES for line in arch.rule_violations(built, rule)]


def test_a_module_that_keeps_the_rules_passes():
    """Imports of lower layers, and strings that only mention pampipe, are not findings."""
    assert findings({"pampipe/planning/fine.py": '''
        """Renders through pampipe.views.text, never imports it: prose names nothing."""
        from pampipe.errors import InputError
        from pampipe.model.muscle import Muscle
        from . import law


        def fail(name):
            raise InputError(f"pampipe.{name}: bad; see pampipe.identify(...) or pampipe.plan", Muscle, law)
        '''}) == []


def test_an_import_inside_a_function_names_the_rule_the_file_and_the_line():
    assert findings({"pampipe/planning/bad.py": '''
        """A lazy import is an import."""


        def load():
            from pampipe.io.config import load_pam
            return load_pam
        '''}) == [f"{SCIENCE}: pampipe/planning/bad.py:6 pampipe.planning.bad -> pampipe.io.config (import)"]


def test_an_import_under_type_checking_is_caught():
    found = findings({"pampipe/planning/bad.py": '''
        from typing import TYPE_CHECKING

        if TYPE_CHECKING:
            from pampipe.views.text import Table
        '''})
    assert found == [f"{SCIENCE}: pampipe/planning/bad.py:5 pampipe.planning.bad -> pampipe.views.text "
                     "(import)"]


def test_relative_imports_and_the_package_face_are_caught():
    found = findings({"pampipe/model/bad.py": '''
        from . import muscle
        from ..io import config
        from .. import __version__
        import pampipe
        '''})
    face = "the api and the package face are for users, never imported from below them: pampipe/model/bad.py"
    model = "the model imports only the errors: pampipe/model/bad.py"
    assert found == [f"{face}:4 pampipe.model.bad -> pampipe (import)",
                     f"{face}:5 pampipe.model.bad -> pampipe (import)",
                     f"{model}:3 pampipe.model.bad -> pampipe.io.config (import)",
                     f"{model}:4 pampipe.model.bad -> pampipe (import)",
                     f"{model}:5 pampipe.model.bad -> pampipe (import)"]


@pytest.mark.parametrize("line", [
    '@notebook(text="pampipe.commands.plan:result_text")',
    'TEXT = {"plan": "pampipe.commands.plan.result_text"}',
    'TEXT = f"pampipe.commands.{name}:result_text"',
    'TEXT = "pampipe.commands." + name',
    'TEXT = "pampipe." + "commands." + name',
    'TEXT = "pampipe.commands.%s:text" % name',
    'TEXT = "pampipe.commands.{}:text".format(name)',
    'TEXT = pkgutil.resolve_name("pampipe.commands.plan:result_text")',
])
def test_a_string_target_is_caught(line):
    found = findings({"pampipe/planning/bad.py": f"\n\n{line}\ndef f():\n    pass\n"})
    assert [f.split(" -> ")[1] for f in found] in (["pampipe.commands.plan (string target)"],
                                                   ["pampipe.commands (string target)"]), found
    assert found[0].startswith("only cli imports commands: pampipe/planning/bad.py:3 pampipe.planning.bad")


@pytest.mark.parametrize(("line", "target"), [
    ('importlib.import_module("pampipe.views.text")', "pampipe.views.text"),
    ('import_module(f"pampipe.views.{name}")', "pampipe.views"),
    ('__import__("pampipe.io.config")', "pampipe.io.config"),
    ('importlib.import_module(".text", "pampipe.views")', "pampipe.views.text"),
    ('importlib.import_module("..views.text", package="pampipe.planning")', "pampipe.views.text"),
])
def test_an_import_module_call_is_caught(line, target):
    source = f"import importlib\n\n\ndef load(name):\n    return {line}\n"
    found = findings({"pampipe/planning/bad.py": source})
    assert found == [f"{SCIENCE}: pampipe/planning/bad.py:5 pampipe.planning.bad -> {target} (import_module)"]


def test_every_rule_catches_a_breach():
    """For each rule, a module of a part it applies to imports a part it forbids."""
    for rule in arch.RULES:
        source = sorted(rule.applies_to)[0]
        target = sorted(rule.may_not_import - {source})[0]
        path = "pampipe/__init__.py" if source == arch.FACE else (
            f"pampipe/{source}.py" if source in arch.ROOT_MODULES else f"pampipe/{source}/bad.py")
        module = "pampipe" if target == arch.FACE else f"pampipe.{target}"
        # the target defines a result class: the views rule forbids importing exactly such modules
        result = "from pampipe.results import notebook\n\n\n@notebook()\nclass Result:\n    pass\n"
        where = f"pampipe/{target}.py" if target in arch.ROOT_MODULES else f"pampipe/{target}/__init__.py"
        extra = {} if target == arch.FACE else {where: result}
        built = package({**extra, path: f"import {module}\n"})
        found = arch.rule_violations(built, rule)
        assert any(line.startswith(f"{rule.name}: {path}:1 ") for line in found), rule


def test_a_circle_between_files_is_caught_whatever_closes_it():
    lazy = {"pampipe/planning/a.py": "from pampipe.planning.b import g\n",
            "pampipe/planning/b.py": "def g():\n    from pampipe.planning.a import f\n"}
    (found,) = arch.file_circles(package(lazy))
    assert found == ("2 files in a circle (pampipe.planning.a, pampipe.planning.b), e.g. "
                     "pampipe.planning.a (pampipe/planning/a.py:1, import) -> "
                     "pampipe.planning.b (pampipe/planning/b.py:2, import) -> pampipe.planning.a")
    by_string = {"pampipe/planning/a.py": 'TEXT = "pampipe.planning.b:text"\n',
                 "pampipe/planning/b.py": "import pampipe.planning.a\n"}
    assert "(pampipe/planning/a.py:1, string target)" in arch.file_circles(package(by_string))[0]
    through_init = {"pampipe/planning/__init__.py": "from pampipe.planning.law import plan\n",
                    "pampipe/planning/law.py": "def plan():\n    from pampipe.planning import settle\n"}
    assert arch.file_circles(package(through_init))[0].startswith(
        "2 files in a circle (pampipe.planning, pampipe.planning.law)")
    no_circle = {"pampipe/planning/a.py": "from pampipe.planning.law import plan\n"}
    assert arch.file_circles(package(no_circle)) == []


def test_a_circle_between_folders_is_caught_without_one_between_files():
    sources = {"pampipe/planning/a.py": "from pampipe.bends.plan import bend\n",
               "pampipe/bends/plan.py": "def bend():\n    from pampipe.planning.law import plan\n"}
    assert arch.file_circles(package(sources)) == []
    assert arch.folder_circles(package(sources)) == [
        "bends, planning in a circle, e.g. bends (pampipe/bends/plan.py:2, import) -> planning "
        "(pampipe/planning/a.py:1, import) -> bends"]


def test_long_functions_and_files_are_caught_template_text_aside():
    body = "".join(f"    x{i} = {i}\n" for i in range(79))
    at_limit = f"def f():\n{body}"  # 80 lines
    template = 'def c_source():\n    return f"""\n' + "int x;\n" * 100 + '"""\n'
    sources = {"pampipe/planning/ok.py": at_limit, "pampipe/export/template.py": template,
               "pampipe/planning/long.py": at_limit + "    return x0\n"}
    assert arch.long_functions(package(sources)) == ["pampipe/planning/long.py:1 f: 81 lines (at most 80)"]
    files = {"pampipe/io/big.py": "x = 1\n" * 501, "pampipe/io/ok.py": "x = 1\n" * 500}
    assert arch.long_files(package(files)) == ["pampipe/io/big.py: 501 lines (at most 500)"]


def test_confusable_twins_an_extra_root_module_and_an_unplaced_folder_are_caught():
    built = package({"pampipe/runtime/nlp.py": "", "pampipe/identification/_nlp.py": "",
                     "pampipe/slip/fit.py": "", "pampipe/synth/__init__.py": "", "pampipe/heap.py": ""})
    assert arch.twins(built) == ["nlp: pampipe/identification/_nlp.py, pampipe/runtime/nlp.py"]
    assert arch.root_violations(built) == [
        "pampipe/heap.py: a root module beyond ['__init__', '__main__', '_version', 'api', 'cli', 'errors', "
        "'results']"]
    assert "synth: a part of the package in no layer of LAYERS" in arch.layer_gaps(built)


def test_a_result_names_its_view_and_no_view_imports_a_result():
    """python-control's shape: a module defining a result class may import the view that draws it, any other
    science module may not, and a view may not import the result module; the folder circle that the
    result -> view edge closes is not counted, another is."""
    result = """
        from pampipe.results import notebook


        def _text():
            from pampipe.views.text import render
            return render


        @notebook(text=_text)
        class PlanResult:
            pass
        """
    protocol = {"pampipe/results.py": "def notebook(**views):\n    return lambda cls: cls\n"}
    assert findings({**protocol, "pampipe/planning/result.py": result,
                     "pampipe/views/text.py": "def render(r): ...\n"}) == []
    helper = findings({"pampipe/planning/helper.py": "from pampipe.views.text import render\n",
                       "pampipe/views/text.py": "def render(r): ...\n"})
    assert [line.split(":")[0] for line in helper] == [SCIENCE]
    view = findings({**protocol, "pampipe/planning/result.py": result,
                     "pampipe/views/text.py": "from pampipe.planning.result import PlanResult\n"})
    assert [line.split(":")[0] for line in view] == [
        "no view imports a module that defines a result (results sit above their views)"]
    words = {**protocol, "pampipe/planning/result.py": result,
             "pampipe/views/text.py": "from pampipe.planning.words import WORDS\n",
             "pampipe/planning/words.py": "WORDS = {}\n"}
    assert arch.folder_circles(package(words)) == []
    words["pampipe/planning/words.py"] = "from pampipe.views.other import X\nWORDS = {}\n"
    words["pampipe/views/other.py"] = "X = 1\n"
    assert len(arch.folder_circles(package(words))) == 1
