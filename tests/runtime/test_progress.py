"""Progress on stderr: a live bar on a terminal, plain lines otherwise, nothing when not shown (issue 26)."""

from __future__ import annotations

import io
import subprocess
import sys

from pampipe.runtime import progress
from pampipe.runtime.executors import SerialExecutor, run_all
from tests.support.problems import PROBLEMS, ROOT


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_plain_lines_off_a_terminal():
    stream = io.StringIO()
    with progress.shown(stream=stream):
        assert run_all(lambda x: x * x, [1, 2, 3], SerialExecutor(), what="squares") == [1, 4, 9]
        progress.note("done squaring")
    assert stream.getvalue().splitlines() == ["squares: 1/3 done", "squares: 2/3 done", "squares: 3/3 done",
                                              "done squaring"]


def test_stages_inside_overall_count_as_one_total():
    """design's starts (issue 42): stages of 3 and 4 planned as 7 count 1/7 ... 7/7, not 1/3 ... 1/4; a stage
    nobody planned extends the total; another kind of step and the count after the block keep their own."""
    stream = io.StringIO()
    with progress.shown(stream=stream):
        with progress.overall("starts", planned=7):
            run_all(lambda x: x, range(3), SerialExecutor(), what="starts")
            run_all(lambda x: x, range(2), SerialExecutor(), what="squares")
            run_all(lambda x: x, range(4), SerialExecutor(), what="starts")
            run_all(lambda x: x, range(2), SerialExecutor(), what="starts")
        run_all(lambda x: x, range(1), SerialExecutor(), what="starts")
    assert stream.getvalue().splitlines() == [
        *(f"starts: {k}/7 done" for k in range(1, 4)), "squares: 1/2 done", "squares: 2/2 done",
        *(f"starts: {k}/7 done" for k in range(4, 8)), "starts: 8/9 done", "starts: 9/9 done",
        "starts: 1/1 done"]


def test_live_bar_on_a_terminal_rewrites_one_line():
    stream = Terminal()
    with progress.shown(stream=stream):
        progress.count("starts", 1, 4)
        progress.note("a step")  # ends the bar's line first
        progress.count("starts", 4, 4)
    text = stream.getvalue()
    assert text.startswith("\r[" + "#" * 6 + "." * 18 + "] 1/4 starts\n")
    assert "a step\n" in text and text.endswith("] 4/4 starts\n")


def test_a_deferred_step_is_noted_only_when_its_wait_runs_out():
    """identify's steps below 10⁵ rows: a line only for a step still running after a second. The waits
    are joined, not timed: 0 s runs out at once, an hour never within the test."""
    stream = io.StringIO()
    with progress.shown(stream=stream):
        with progress.deferred(after=0.0) as later:
            later("a slow step")
            later.timer.join()
        with progress.deferred(after=3600.0) as later:
            later("a step the next one ends")
            first = later.timer
            later("a step the block ends")
            second = later.timer
        first.join()
        second.join()  # cancelled: both end at once, and say nothing
    with progress.deferred(after=0.0) as later:  # not shown (a notebook, --json): no wait at all
        later("unseen")
        assert later.timer is None
    assert stream.getvalue() == "a slow step\n"


def test_silent_unless_shown_and_when_disabled():
    stream = io.StringIO()
    progress.count("starts", 1, 2)  # no reporter: nothing happens, nothing fails
    with progress.shown(enabled=False, stream=stream):
        progress.count("starts", 1, 2)
        progress.note("step")
    assert stream.getvalue() == ""


def test_quiet_and_json_silence_the_command_line():
    """Two starts instead of the riser's 16: a line per start is what is silenced, and two show it."""
    inventory = str(PROBLEMS / "inventories" / "riser.yaml")
    for extra in ([], ["--quiet"], ["--json"]):
        out = subprocess.run([sys.executable, "-m", "pampipe", "design", inventory, "--starts", "2", *extra],
                             capture_output=True, text=True, cwd=ROOT, timeout=300)
        assert out.returncode == 0, out.stderr
        counted = [line for line in out.stderr.splitlines() if line.startswith("design starts:")]
        assert bool(counted) == (extra == []), (extra, out.stderr)


def test_to_frame_names_the_extra_without_pandas(monkeypatch):
    import pytest

    from pampipe.results import frame

    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match=r"pampipe\[frames\]"):
        frame([{"a": 1}])
