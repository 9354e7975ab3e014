"""pytest plugin of scripts/mutate.py (``--select``): which lines of one module each test runs.

``MUTATE_TRACE`` names the module's file, ``MUTATE_TRACE_OUT`` the JSON file written at the end:
{test id: [line, ...]}, and under "" the lines run outside any test (imports, collection, fixtures of a
wider scope than the test). In-process only (sys.settrace and threading.settrace): a line run in a
subprocess or a worker process is not seen.
"""

from __future__ import annotations

import json
import os
import sys
import threading

import pytest

TARGET = os.path.realpath(os.environ.get("MUTATE_TRACE", ""))
_lines: dict[str, set[int]] = {"": set()}
_current = _lines[""]
_files: dict[str, bool] = {}


def _ours(filename: str) -> bool:
    if filename not in _files:
        _files[filename] = os.path.realpath(filename) == TARGET
    return _files[filename]


def _local(frame, event, arg):
    if event == "line":
        _current.add(frame.f_lineno)
    return _local


def _global(frame, event, arg):
    if _ours(frame.f_code.co_filename):
        _current.add(frame.f_lineno)
        return _local
    return None


def pytest_configure(config):
    sys.settrace(_global)
    threading.settrace(_global)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    global _current
    _current = _lines.setdefault(item.nodeid, set())
    yield
    _current = _lines[""]


def pytest_unconfigure(config):
    sys.settrace(None)
    threading.settrace(None)
    with open(os.environ["MUTATE_TRACE_OUT"], "w", encoding="utf-8") as out:
        json.dump({k: sorted(v) for k, v in _lines.items()}, out)
