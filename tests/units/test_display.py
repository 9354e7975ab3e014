"""`--units si|metric|us` (issue 26 item 2): every command's tables, warnings and reasons in the user's units,
the JSON unchanged. Conversion factors here come from the definitions (NIST SP 811), not from pampipe."""

from __future__ import annotations

import re

import pytest

from pampipe.units.display import column, localize, shown_in
from tests.support.problems import PROBLEMS

INCH = 0.0254  # m, exact
LBF = 0.45359237 * 9.80665  # N: pound-mass times standard gravity, exact
PSI = LBF / INCH**2  # Pa
FOOT = 12 * INCH
MILE = 5280 * FOOT

#: A metric unit after a number, in a table header or in a compound unit: none may be left under --units us.
#: Names are left alone ('radial-76.2mm-0N', JSON keys such as 'pressure_Pa'), hence the digit-space and
#: word-boundary guards.
METRIC = re.compile(r"kPa|MPa|\d Pa\b|\[Pa\b|\d mm\b|\[mm|mm\]|\bmm/|\[N\]|\[N/|\d N\b|\bN/|\bN\^2|N²|\d m\b"
                    r"|\[m\]|/m\]|\d km\b|\d cm\b|\bkg\b|\b1/m\b")


def _metric_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if METRIC.search(line)]


def test_numbers_in_text_are_converted_with_their_precision():
    with shown_in("us"):
        shown = localize("planned only 4.8 kPa above first touching the largest bore (76.2 mm) at 117 kPa")
        low, bore, at = (float(v) for v in re.findall(r"[\d.]+(?= (?:psi|in))", shown))
        assert low == pytest.approx(4.8e3 / PSI, rel=5e-3) and at == pytest.approx(117e3 / PSI, rel=5e-3)
        assert bore == pytest.approx(3.0) and "kPa" not in shown and " mm" not in shown
        assert localize("after 'riser' 76.2 -> 88.9 mm: passes") == "after 'riser' 3 -> 3.5 in: passes"
        assert localize("speed 25.4 mm/s, hold 4.4482 N") == "speed 1 in/s, hold 1 lbf"
        cover = localize("60.77 of 260.2 km")
        first, total = (float(v) for v in re.findall(r"[\d.]+", cover))
        assert cover.endswith(" mi") and first == pytest.approx(60.77e3 / MILE, rel=1e-3)
        assert total == pytest.approx(260.2e3 / MILE, rel=1e-3)
        assert localize("radial-76.2mm-1025N and 5 deg") == "radial-76.2mm-1025N and 5 deg"  # names, angles
    with shown_in("si"):
        assert localize("12.5 kPa, 48 mm, 3 m") == "12500 Pa, 0.048 m, 3 m"
        assert column("P [kPa]", [121.8]) == ("P [Pa]", ["121800"])
    with shown_in("psi"):  # one pressure unit: pressures only
        assert localize("100 kPa in a 76.2 mm pipe") == f"{100e3 / PSI:.3g} psi in a 76.2 mm pipe"
    with shown_in("metric"):
        text = "12.5 kPa, 48 mm, 0.3137 MPa [0.2658, 0.3616]"
        assert localize(text) == text


def test_table_columns_convert_by_the_unit_in_their_header():
    with shown_in("us"):
        assert column("W [N]", [LBF, 2 * LBF, 1000 * LBF]) == ("W [lbf]", ["1", "2", "1000"])
        assert column("f_r [N/m]", [LBF / INCH]) == ("f_r [lbf/in]", ["1"])
        assert column("range [mm]", ["25.4-50.8"]) == ("range [in]", ["1-2"])
        assert column("length [m]", [FOOT, 1.0]) == ("length [ft]", ["1", f"{1 / FOOT:.4g}"])
        assert column("angle [deg]", [3.0]) == ("angle [deg]", [3.0])
        assert column("bore [in]", [3.0]) == ("bore [in]", [3.0])  # already in the user's unit


MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
COMMANDS = {
    "simulate": ["simulate", PROBLEMS / "pams" / "paper-radial-pam.yaml", "-d", "3 in", "-d", "3.5 in",
                 "-f", "0", "-f", "1024.74 N"],
    "simulate-extensile": ["simulate", PROBLEMS / "pams" / "extensile-steering.yaml"],
    "plan": ["plan", MISSION, "--max-payload"],
    "plan-reasons": ["plan", PROBLEMS / "missions" / "infeasible-survey.yaml"],
    "plan-bends": ["plan", PROBLEMS / "missions" / "elbows-3in.yaml"],
    "plan-confidence": ["plan", PROBLEMS / "missions" / "riser-uncertain-friction.yaml", "--confidence",
                        "0.95", "--samples", "400"],
    "gait": ["gait", MISSION],
    "design": ["design", PROBLEMS / "inventories" / "riser.yaml", "--starts", "4"],
    "export": ["export", MISSION],
    "route": ["route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "4.5 in"],
    "gait-optimal": ["gait", MISSION, "--optimal"],
    "identify": ["identify", PROBLEMS / "experiments" / "paper-protocol.yaml"],
    "identify-slip": ["identify", PROBLEMS / "experiments" / "slip-3in.yaml"],
    "synth": ["synth", "OUT", "--slip-pipe", "3 in", "--force-noise", "2 N"],
    "diagnose": ["diagnose", PROBLEMS / "experiments" / "hidden-contact-stiffening.yaml"],
}
#: The units each command's text must show under --units us.
SHOWS = {"route": ("in", "ft"), "simulate-extensile": ("psi", "in"), "design": ("psi", "in", "ft"),
         "diagnose": ("psi", "lbf", "lbf^2"), "export": ("psi", "in"), "plan": ("psi", "in", "lbf", "lb"),
         "plan-reasons": ("psi", "in", "lbf", "lb"), "plan-bends": ("psi", "in", "1/in"),
         "synth": ("psi", "lbf"), "identify": ("psi", "in", "lbf", "lbf^2"),
         "identify-slip": ("psi", "in", "lbf", "lbf/s")}


@pytest.mark.parametrize("name", COMMANDS)
def test_us_units_everywhere_and_the_json_unchanged(cli, tmp_path, name):
    """Every command that prints a quantity, on bundled problems: its text (stdout and stderr, progress lines
    included) under --units us holds no metric unit and shows the US ones; the same text under metric
    holds metric units (so the check can fail); the JSON and the files written are the same."""
    args = [tmp_path / "synth" if a == "OUT" else a for a in COMMANDS[name]]
    extra = (["-o", tmp_path / "mission.yaml", "--force"] if name == "route" else
             ["-o", tmp_path / "c", "--force"] if name == "export" else
             ["--force"] if name == "synth" else [])
    out, written = {}, {}
    for units, json in (("metric", "--json"), ("us", "--json"), ("us", None)):
        key = f"{units} {json}"
        out[key] = cli(*args, *extra, "--units", units, *([json] if json else []), "--reproducible")
        assert out[key].returncode in (0, 3), out[key].stderr
        written[key] = {p.name: p.read_text() for p in sorted(tmp_path.rglob("*")) if p.is_file()}
    metric, us, text = out["metric --json"], out["us --json"], out["us None"]
    assert metric.returncode == us.returncode == text.returncode
    assert metric.stdout.startswith("{")
    if name != "gait-optimal":  # a second optimal gait in one process starts warm: its solver block differs
        assert metric.stdout == us.stdout  # the JSON stays SI
    assert written["metric --json"] == written["us --json"]  # and so do the mission file and the robot's C
    assert _metric_lines(metric.stderr), "the check must see the metric text it forbids under us"
    assert _metric_lines(us.stderr) == []
    assert _metric_lines(text.stdout + text.stderr) == []  # the text report, progress lines and warnings
    for unit in SHOWS.get(name, ("psi", "in", "lbf")):
        assert re.search(rf"\[{re.escape(unit)}\]|\d {re.escape(unit)}\b|{re.escape(unit)}\)|per {unit}",
                         text.stdout + text.stderr), unit


def test_plan_numbers_in_us_units_match_the_json(cli):
    import json

    out = cli("plan", MISSION, "--json", "--units", "us")
    segment = json.loads(out.stdout)["sections"][0]["segments"][0]
    line = next(line for line in out.stderr.splitlines() if line.split()[:2] == ["riser", "PAM1"])
    pressure, anchor, margin, hold, capacity = (float(v) for v in line.split()[2:8] if v != "(thin)")
    assert pressure == pytest.approx(segment["pressure_Pa"] / PSI, rel=1e-3)
    assert anchor == pytest.approx(segment["largest_bore_anchoring_pressure_Pa"] / PSI, rel=1e-3)
    assert margin == pytest.approx(segment["contact_margin_Pa"] / PSI, rel=2e-3)
    assert hold == pytest.approx(segment["required_hold_N"] / LBF, rel=1e-3)
    assert capacity == pytest.approx(segment["holding_capacity_N"] / LBF, rel=1e-3)
    warning = next(line for line in out.stderr.splitlines() if line.startswith("warning: riser"))
    assert f"({0.0762 / INCH:.4g} in)" in warning  # the largest bore, as the warning states it


def test_units_is_refused_with_the_choices(cli):
    out = cli("gait", MISSION, "--units", "imperial")
    assert out.returncode == 2 and "--units" in out.stderr and "us" in out.stderr


def test_plot_axes_keep_their_data_and_show_round_ticks_of_the_display_unit():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pampipe.views.plots.display_units import localize_figure

    fig, ax = plt.subplots()
    ax.plot([0.0, 689.0], [0.0, 50.0], label="no slip 121.8 kPa")
    ax.set(xlabel="pressure [kPa]", ylabel="position [mm]", title="stride 23.85 mm")
    ax.legend()
    with shown_in("us"):
        localize_figure(fig)
    fig.canvas.draw()
    assert ax.get_xlabel() == "pressure [psi]" and ax.get_ylabel() == "position [in]"
    assert ax.get_title() == f"stride {23.85 / 25.4:.4g} in"
    assert ax.get_legend().get_texts()[0].get_text() == f"no slip {121.8e3 / PSI:.4g} psi"
    ticks = [t for t in ax.get_xticks() if 0 <= t <= 689.0]
    labels = [t.get_text() for t in ax.get_xticklabels() if 0 <= t.get_position()[0] <= 689.0]
    psi = [t * 1e3 / PSI for t in ticks]
    assert len(psi) >= 3 and all(abs(v - round(v)) < 1e-6 for v in psi)  # round psi, placed in kPa
    assert [float(label.replace("−", "-")) for label in labels] == pytest.approx(psi)
    plt.close(fig)


def test_a_reason_that_ends_the_run_is_in_the_users_units_and_the_json_error_stays_si(cli):
    import json

    args = ("gait", PROBLEMS / "missions" / "infeasible-survey.yaml", "--section", "heavy-riser")
    us, metric = cli(*args, "--units", "us", "--json"), cli(*args, "--json")
    assert us.returncode == metric.returncode == 3
    assert "kPa" in metric.stderr.splitlines()[-1] and " N " in metric.stderr.splitlines()[-1]
    last = us.stderr.splitlines()[-1]
    assert "psi" in last and "lbf" in last and not METRIC.search(last)
    assert json.loads(us.stdout) == json.loads(metric.stdout)  # the error document keeps SI-metric


def test_api_text_in_the_users_units_and_its_data_in_si(cli, tmp_path):
    """str(result) and result.to_text(units=) give the command's report in the chosen units;
    pampipe.set_units() sets the default for the process, not for a command line run; to_dict() is SI."""
    import pampipe
    from pampipe.errors import InputError

    plan = pampipe.plan(MISSION)
    document = plan.to_dict()
    metric, us = str(plan), plan.to_text(units="us")
    assert _metric_lines(metric) and _metric_lines(us) == []
    segment = document["sections"][0]["segments"][0]
    row = next(line for line in us.splitlines() if line.split()[:2] == ["riser", "PAM1"])
    assert float(row.split()[2]) == pytest.approx(segment["pressure_Pa"] / PSI, rel=1e-3)
    synth = pampipe.synth(tmp_path / "synth", force=True)
    try:
        pampipe.set_units("us")
        assert str(plan) == us and plan.to_text(units="metric") == metric
        assert plan.to_dict() == document  # the data stay SI
        assert re.search(r"\d lbf\b", str(synth)) and _metric_lines(str(synth)) == []
        simulated = str(pampipe.simulate(PROBLEMS / "pams" / "paper-radial-pam.yaml", pipe_diameter="3 in"))
        assert "in a 3 in pipe" in simulated and "[psi]" in simulated and _metric_lines(simulated) == []
        run = cli("plan", MISSION)
        assert run.returncode == 0 and "[kPa]" in run.stdout  # the command line keeps its --units
        assert str(plan) == us  # and the process default is back after the run
    finally:
        pampipe.set_units("metric")
    assert str(plan) == metric and re.search(r"\d N\b", str(synth))
    with pytest.raises(InputError, match="imperial"):
        pampipe.set_units("imperial")
