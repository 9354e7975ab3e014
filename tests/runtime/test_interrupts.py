"""An interrupted run exits 128 + the signal (SIGINT 130, SIGTERM 143) with one line and leaves no output
file (issues 7, 14, 26)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest

from tests.support.problems import PROBLEMS, ROOT


@pytest.fixture(scope="module")
def big_experiment(tmp_path_factory):
    """An axial experiment of 10⁶ rows (the bundled test tiled), slow enough to interrupt mid-read."""
    folder = tmp_path_factory.mktemp("big")
    source = PROBLEMS / "experiments" / "data" / "paper-protocol" / "axial.csv"
    header, *rows = source.read_text().splitlines()
    body = "\n".join(rows)
    repeats = 10**6 // len(rows) + 1
    (folder / "axial.csv").write_text(header + "\n" + "\n".join([body] * repeats) + "\n")
    pam = (PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text().split("moduli:")[0]
    (folder / "pam.yaml").write_text(pam)
    (folder / "experiment.yaml").write_text(
        "pam: pam.yaml\ntests:\n  - {name: axial, kind: axial, data: axial.csv}\n")
    return folder


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_interrupt_leaves_no_partial_output(big_experiment, signum, tmp_path):
    target = tmp_path / "fit.yaml"
    process = subprocess.Popen([sys.executable, "-m", "pampipe", "identify",
                                str(big_experiment / "experiment.yaml"), "-o", str(target)],
                               stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True, cwd=ROOT)
    first = process.stderr.readline()  # the first progress line: the run is under way
    assert "reading axial.csv" in first
    process.send_signal(signum)
    _, rest = process.communicate(timeout=600)  # a guard against a hang, not a measurement
    assert process.returncode == 128 + signum  # 130 for SIGINT, 143 for SIGTERM
    assert rest.strip().splitlines() == ["pampipe identify: interrupted; no partial output was written."]
    assert "Traceback" not in rest
    assert not target.exists()
    assert not list(tmp_path.iterdir())  # no temporary file left behind either


#: diagnose with IPOPT's iteration log on stdout (unbuffered, no NLP cache that could hold quiet solvers),
#: so the test sees when IPOPT is iterating instead of guessing it from a delay.
IPOPT_VISIBLE = ("import sys, pampipe.runtime.ipopt as nlp; nlp.IPOPT_DEFAULTS['print_level'] = 5; "
                 "from pampipe.cli import main; sys.exit(main(sys.argv[1:]))")


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_interrupt_inside_ipopt_exits_130(signum):
    """diagnose spends these moments in IPOPT refits; CasADi swallows the KeyboardInterrupt there and
    IPOPT stops with a failure status (before issue 14: exit 3 "did not converge", or ignored). The
    signal goes when IPOPT prints the first iteration header of the first refit (after "refit 1 of"),
    i.e. while IPOPT iterates, however busy the machine is."""
    process = subprocess.Popen([sys.executable, "-u", "-c", IPOPT_VISIBLE, "diagnose",
                                str(PROBLEMS / "experiments" / "hidden-contact-stiffening.yaml")],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT,
                               env={**os.environ, "PAMPIPE_NLP_CACHE": "off"})
    seen, refitting = [], False
    while not (refitting and seen[-1].startswith("iter ")):  # IPOPT iterates in a refit
        seen.append(process.stdout.readline())
        assert seen[-1], seen[-20:]  # the run ended before any refit iterated
        refitting = refitting or "diagnose: refit " in seen[-1]  # "refit 1 of 9 of this step: …"
    process.send_signal(signum)
    rest, _ = process.communicate(timeout=600)  # a guard against a hang, not a measurement
    assert process.returncode == 128 + signum, rest[-2000:]
    assert rest.strip().splitlines()[-1] == "pampipe diagnose: interrupted; no partial output was written."
    assert "Traceback" not in rest


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_gait_stops_inside_ipopt_on_either_signal(signum, tmp_path):
    """`gait --optimal` (issue 42): SIGTERM takes Ctrl-C's path out of IPOPT's minimum-time solve: 128 + the
    signal, one line, no traceback, no plot folder. The signal goes when IPOPT prints its first iteration
    header (a condition, not a delay)."""
    plots = tmp_path / "plots"
    process = subprocess.Popen([sys.executable, "-u", "-c", IPOPT_VISIBLE, "gait",
                                str(PROBLEMS / "missions" / "vertical-climb-3in.yaml"), "--optimal",
                                "--plots", str(plots)],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT,
                               env={**os.environ, "PAMPIPE_NLP_CACHE": "off"})
    seen = [""]
    while not seen[-1].startswith("iter "):  # IPOPT iterates
        seen.append(process.stdout.readline())
        assert seen[-1], seen[-20:]  # the run ended before IPOPT iterated
    process.send_signal(signum)
    rest, _ = process.communicate(timeout=600)  # a guard against a hang, not a measurement
    assert process.returncode == 128 + signum, rest[-2000:]
    assert rest.strip().splitlines()[-1] == "pampipe gait: interrupted; no partial output was written."
    assert "Traceback" not in rest
    assert not list(tmp_path.iterdir())
