"""docs/architecture.md keeps up with the package: every path it names exists (relative to pampipe/ or to the
repository), and it says what every folder of pampipe/ owns."""

from __future__ import annotations

import re

from tests.support.problems import ROOT

PAGE = ROOT / "docs" / "architecture.md"
#: A path in backticks: `planning/law.py`, `model/effects/`, `cli.py`, `tests/support/`. Upper-case parts are
#: placeholders (`commands/NAME.py`) and are not checked.
PATH = re.compile(r"`((?:[\w.]+/)*[\w.]+(?:\.py|/))`")


def missing_paths(text: str) -> list[str]:
    """The paths ``text`` names that are neither under pampipe/ nor under the repository's root."""
    return [path for path in dict.fromkeys(PATH.findall(text)) if not re.search(r"[A-Z]", path)
            and not (ROOT / "pampipe" / path).exists() and not (ROOT / path).exists()]


def test_every_path_the_page_names_exists():
    assert not (found := missing_paths(PAGE.read_text(encoding="utf-8"))), found


def test_the_path_check_can_fail():
    assert missing_paths("`planning/law.py`, `model/no_such_effect.py` and `commands/NAME.py`") == [
        "model/no_such_effect.py"]


def test_the_page_says_what_every_folder_owns():
    text = PAGE.read_text(encoding="utf-8")
    owners = text[text.index("## 1."):text.index("## 2.")]
    folders = sorted(p.name for p in (ROOT / "pampipe").iterdir() if (p / "__init__.py").exists())
    assert not (missing := [f for f in folders if f"`{f}/" not in owners]), missing
