"""`--report FILE.pdf` (issue 42): the report as an A4 PDF drawn by matplotlib alone: it is a PDF, it opens
with the verdict, holds the text report and a page per figure, and its text can be searched."""

from __future__ import annotations

import subprocess
import sys

from pampipe._version import __version__
from pampipe.views.pdf_report import MONO, PAGE, lines, write_pdf
from tests.support.pdf_text import pdf_lines
from tests.support.problems import PROBLEMS, ROOT


def test_plan_report_pdf_opens_with_the_verdict_and_holds_text_and_plots(tmp_path):
    target = tmp_path / "plan.pdf"
    mission = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
    out = subprocess.run([sys.executable, "-m", "pampipe", "plan", str(mission), "--report", str(target),
                          "--quiet"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    data = target.read_bytes()
    assert data.startswith(b"%PDF-") and data.rstrip().endswith(b"%%EOF")
    text = pdf_lines(data)
    verdict = "feasible: every segment holds in every section, over each bore's range, within the supply."
    assert verdict in text and text.index(verdict) < text.index("Inputs") < text.index("Report")
    assert any(line.startswith("largest pressure: 166.5 kPa (PAM1 in run)") for line in text)
    assert sum(line.startswith("Fit per") or "Segments" in line or "PAM1" in line for line in text) > 0
    assert data.count(b"/Type /Page\n") + data.count(b"/Type /Page ") >= 3  # text page(s) and plots
    assert not list(tmp_path.glob(".*"))  # written atomically: no temporary file left


def test_the_pdf_says_when_it_was_written_in_utc(tmp_path):
    """As the HTML report does (issue 42): the second line names the version, the command and the UTC minute
    it was written, read back from the PDF and compared with the clock before and after."""
    from datetime import datetime, timedelta, timezone

    before = datetime.now(timezone.utc).replace(second=0, microsecond=0)
    target = write_pdf(tmp_path / "r.pdf", "plan", title="t", inputs=[], text="feasible: yes", document={})
    after = datetime.now(timezone.utc)
    minutes = [before + timedelta(minutes=k) for k in range(int((after - before).total_seconds() // 60) + 1)]
    second = pdf_lines(target.read_bytes())[1]
    assert second in [f"pampipe {__version__}, pampipe plan, {m:%Y-%m-%d %H:%M} UTC" for m in minutes], second


def test_long_lines_wrap_and_pages_break(tmp_path):
    """A 300-character line of the text report wraps at the monospace width; 400 lines take several pages;
    every character is kept."""
    text = "fit: RMSE 2.00 N = 1.2 % of full scale\n" + "x" * 300 + "\n" + "\n".join(f"row {k}" for k in
                                                                                range(400))
    rows = lines("identify", title="t", inputs=[], text=text, document={})
    mono = [line for line, style in rows if style is MONO]
    assert max(map(len, mono)) <= MONO.columns and "".join(mono).count("x") == 300
    target = write_pdf(tmp_path / "r.pdf", "identify", title="t", inputs=[], text=text, document={},
                       warnings=["w $a_b$"])
    shown = pdf_lines(target.read_bytes())
    assert shown[2] == "fit: RMSE 2.00 N = 1.2 % of full scale"  # the verdict, after title and version
    assert "row 399" in shown and "w $a_b$" in shown  # text as written, no mathtext
    per_page = (PAGE[1] - 2 * 12 / 25.4) / MONO.height
    assert target.read_bytes().count(b"/Type /Page") - 1 >= 400 / per_page
