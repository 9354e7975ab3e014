"""docs/api.md, the page `make docs` renders into the API reference (mkdocstrings), lists every public
function of pampipe.api (issue 42 item 6); `make docs` itself builds with --strict in its own venv."""

from __future__ import annotations

import inspect
import re

import pampipe.api as api
from tests.support.problems import ROOT


def test_the_api_page_lists_every_public_function():
    page = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\s+- (\w+)$", page, flags=re.MULTILINE))
    public = {name for name in api.__all__ if inspect.isfunction(getattr(api, name))}
    assert listed == public
    assert "::: pampipe.api" in page
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert "api.md" in config and "mkdocstrings" in config
