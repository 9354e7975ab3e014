"""Names reach the plots as text, never as mathtext (issue 38): a section named '$$' stopped `plan --plots`
with "internal error: ValueError", and one named 'x$^{999999999}$' was drawn as a formula."""

from __future__ import annotations

import io

import matplotlib
import yaml

from pampipe.cli import main
from pampipe.views.plots.plan import plot_plan
from pampipe.views.plots.style import PLAIN
from pampipe.views.tables import capture
from tests.support.problems import PROBLEMS

NAMES = ["$$", "x$^{999999999}$", r"$\frac{1}{0}$"]


def _mission(tmp_path):
    raw = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for name, section in zip(NAMES, raw["route"], strict=False):
        section["name"] = name
    for segment in raw["robot"]["segments"]:
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(raw))
    return path


def test_plots_and_report_of_dollar_names(tmp_path, capsys):
    mission = _mission(tmp_path)
    assert main(["plan", str(mission), "--plots", str(tmp_path / "plots"), "--report",
                 str(tmp_path / "plan.html")]) == 0, capsys.readouterr().err
    assert list((tmp_path / "plots").iterdir())


def test_every_text_is_drawn_as_written(tmp_path):
    """After drawing, no text of the figures is parsed as math: what shows is the name itself."""
    import pampipe

    plan = pampipe.plan(_mission(tmp_path))
    with capture() as figures:
        plot_plan(plan, None)
    shown = []
    for fig in figures:
        with matplotlib.rc_context(PLAIN):
            fig.savefig(io.BytesIO(), format="png")  # draws: tick labels are made now
        for text in fig.findobj(matplotlib.text.Text):
            assert text._preprocess_math(text.get_text())[1] is False, text.get_text()
            shown.append(text.get_text())
    assert any("$$" in s for s in shown) and any("x$^{999999999}$" in s for s in shown)
