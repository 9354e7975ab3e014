"""Slip tests (issue 24): detection, μ and κ against data generated apart from pampipe
(tests/support/slip_data.py), what one bore can and cannot say, the contact block in the PAM file and the plan
that uses it."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from pampipe.model.muscle import Muscle
from pampipe.slip import fit_slip
from pampipe.slip.detect import detect
from pampipe.slip.workflow import detect_trials
from pampipe.specs.experiment import TestSpec as Spec
from pampipe.specs.experiment import make_slip_data
from tests.support import slip_data
from tests.support.problems import PROBLEMS

MU, KAPPA = 0.3, 0.8
#: Data sets of the default run's coverage study (each ~3.4 s of CPU).
SMALL_SETS = 6
BORES = (0.0635, 0.0889)  # 2.5 in and 3.5 in: A = 0.75 and 1.20
PRESSURES = np.linspace(2.6e5, 6.0e5, 16)


def _tests(muscle, bores, *, mu=MU, kappa=KAPPA, scatter=0.01, exponent=0.0, hold=(5,), rate_gain=0.0):
    out = []
    for k, bore in enumerate(bores):
        columns = slip_data.slip_test(muscle, bore, PRESSURES, mu=mu, kappa=kappa, scatter=scatter,
                                      stick_slip=True, hold_below=hold, seed=10 + k, exponent=exponent,
                                      rate_gain=rate_gain)
        out.append(make_slip_data(Spec(f"slip-{k}", "slip", Path(f"slip-{k}.csv"), bore, 0.0), columns))
    return tuple(out)


@pytest.fixture(scope="module")
def muscle(radial_pam):
    return Muscle.from_pam(radial_pam)


@pytest.fixture(scope="module")
def two_bores(muscle):
    return fit_slip(_tests(muscle, BORES), muscle)


@pytest.fixture(scope="module")
def one_bore(muscle):
    return fit_slip(_tests(muscle, BORES[:1]), muscle)


def test_two_bores_recover_friction_and_coupling(two_bores):
    """True μ and κ inside the 95 % intervals, μ within 5 %, both determined."""
    s = two_bores
    assert s.determined == ["friction", "load_coupling"]
    assert s.friction.low <= MU <= s.friction.high
    assert s.load_coupling.low <= KAPPA <= s.load_coupling.high
    assert abs(s.friction.value / MU - 1) < 0.05
    doc = s.as_document()
    assert doc["load_coupling"]["ci95"][0] <= KAPPA <= doc["load_coupling"]["ci95"][1]


def test_censored_trials_are_kept_as_lower_bounds(two_bores, muscle):
    """The held trial (70 % of its slip load) is censored, not dropped, and its bound is below the truth."""
    held = [t for t in two_bores.trials if t.censored]
    assert len(two_bores.trials) == 2 * PRESSURES.size
    assert [(t.test, t.index) for t in held] == [("slip-0", 5), ("slip-1", 5)]
    for t in held:
        truth = slip_data.true_slip_load(muscle, PRESSURES[5], t.pipe_diameter, MU, KAPPA)
        assert t.slip_load == pytest.approx(0.7 * truth, rel=0.05)


def test_one_bore_reports_the_combination_not_kappa(one_bore, muscle):
    """One bore: κ null, μ undetermined (no value), the effective friction's interval holds the truth."""
    s = one_bore
    doc = s.as_document()
    assert doc["load_coupling"] is None and doc["friction"]["value"] is None
    assert doc["determined"] == ["effective_friction"]
    amplification, _ = slip_data.amplification(muscle.geometry, BORES[0])
    truth = MU / (1 + KAPPA * MU * math.pi * amplification)
    (bore,) = doc["combination"]["per_bore"]
    assert bore["ci95"][0] <= truth <= bore["ci95"][1]
    low, high = doc["friction"]["range_for_load_coupling_0_to_1"]
    assert low <= MU and (high is None or MU <= high)
    assert "second bore" in doc["separating_test"]
    grip = s.grip()
    assert grip.load_coupling is None and grip.friction == pytest.approx(bore["value"])


def test_detection_finds_a_known_onset():
    """Elastic to row 60 (load 600 N), then a 3 mm jump: onset at row 61, slip load 600 N, confident."""
    rng = np.random.default_rng(1)
    load = np.concatenate([np.linspace(0, 600, 61), np.linspace(590, 500, 10)])
    shift = np.concatenate([np.zeros(61), np.linspace(0.3e-3, 3e-3, 10)])
    displacement = 2e-7 * load + shift + rng.normal(0, 2e-6, load.size)
    trial = detect("t", 0, 0.0762, np.arange(load.size) * 0.1, np.full(load.size, 3e5), load, displacement)
    assert not trial.censored and trial.onset_row == 61 and trial.slip_load == pytest.approx(600)
    assert trial.confidence > 0.99
    held = detect("t", 0, 0.0762, np.arange(61) * 0.1, np.full(61, 3e5), load[:61], displacement[:61])
    assert held.censored and held.slip_load == pytest.approx(600)


def test_a_curved_elastic_trend_is_not_slip():
    """Quiet gauge, elastic displacement 6 % non-linear: the curvature (4 µm, 20 noise sd) is not a slip."""
    rng = np.random.default_rng(2)
    load = np.linspace(0, 600, 61)
    displacement = 2e-7 * load + 2e-11 * load**2 + rng.normal(0, 2e-7, load.size)
    trial = detect("t", 0, 0.0762, np.arange(load.size) * 0.1, np.full(load.size, 3e5), load, displacement)
    assert trial.censored
    jump = np.concatenate([displacement, displacement[-1] + np.linspace(0.1e-3, 1e-3, 5)])
    slipped = detect("t", 0, 0.0762, np.arange(jump.size) * 0.1, np.full(jump.size, 3e5),
                     np.concatenate([load, np.full(5, 580.0)]), jump)
    assert not slipped.censored and slipped.onset_row == 61 and slipped.slip_load == pytest.approx(600)


def test_friction_law_check(muscle, two_bores):
    """μ ∝ p^0.4 is recognised as pressure-dependent; Coulomb data are judged Coulomb. The evidence: LR's
    p-value is χ²₁'s upper tail, ΔBIC = ln N − LR (N trials, slipped or held), and the verdict is
    pressure-dependent exactly where ΔBIC < 0 and p < 0.05."""
    from scipy.stats import chi2

    assert two_bores.law.supported == "coulomb"
    dependent = fit_slip(_tests(muscle, BORES, exponent=0.4, hold=()), muscle)
    assert dependent.law.supported == "pressure_dependent"
    assert dependent.law.exponent == pytest.approx(0.4, abs=0.1)
    for law in (two_bores.law, dependent.law):
        assert law.p_value == pytest.approx(chi2.sf(law.likelihood_ratio, 1), rel=1e-9, abs=1e-300)
        assert law.delta_bic == pytest.approx(math.log(PRESSURES.size * len(BORES)) - law.likelihood_ratio,
                                              rel=1e-12, abs=1e-12)
    assert two_bores.law.likelihood_ratio >= 0 and dependent.law.delta_bic < 0 < two_bores.law.delta_bic


def test_diagnose_reports_a_rate_trend_instead_of_hiding_it(muscle, radial_pam, two_bores):
    """A grip that grows with load rate is reported as a trend; Coulomb data show none."""
    from pampipe.diagnosis.slip_residuals import SlipDiagnosis, diagnose_slip

    viscous = diagnose_slip(_tests(muscle, BORES, rate_gain=0.1), radial_pam)
    assert viscous.verdict == "trend"
    assert [t.against for t in viscous.slip.trends if t.significant] == ["load_rate_N_per_s"]
    assert "load_rate" in viscous.report() and viscous.as_document()["verdict"] == "trend"
    assert SlipDiagnosis(two_bores).verdict == "none"


def test_no_slip_at_all_claims_no_friction(muscle):
    """Every trial held: friction has no upper limit, so no contact block, and a warning says why."""
    held = fit_slip(_tests(muscle, BORES[:1], hold=tuple(range(PRESSURES.size))), muscle)
    assert all(t.censored for t in held.trials)
    assert held.grip() is None
    assert any("no trial slipped" in w for w in held.warnings)


def test_too_few_slips_claim_nothing(muscle):
    """Two slipped trials cannot estimate the scatter: no friction, no contact block, valid JSON."""
    few = fit_slip(_tests(muscle, BORES[:1], hold=tuple(range(2, PRESSURES.size))), muscle)
    assert sum(not t.censored for t in few.trials) == 2
    assert few.grip() is None and few.friction is None
    doc = few.as_document()
    json.dumps(doc, allow_nan=False)
    assert doc["combination"]["per_bore"][0]["value"] is None
    assert any("only 2 trial(s) slipped" in w for w in few.warnings)


# ------------------------------------------------------------------------------------------------ CLI
def _experiment(folder: Path, muscle, bores, **kwargs) -> Path:
    (folder / "data").mkdir(parents=True, exist_ok=True)
    tests = []
    for k, bore in enumerate(bores):
        columns = slip_data.slip_test(muscle, bore, PRESSURES[::2], mu=MU, kappa=KAPPA, seed=k, **kwargs)
        slip_data.write(folder / "data" / f"slip-{k}.csv", columns)
        tests.append({"name": f"slip-{k}", "kind": "slip", "pipe_diameter": f"{bore * 1e3} mm",
                      "pipe_material": "steel", "data": f"data/slip-{k}.csv"})
    path = folder / "slip.yaml"
    path.write_text(yaml.safe_dump({"pam": str(PROBLEMS / "pams" / "paper-radial-pam.yaml"), "tests": tests}))
    return path


@pytest.fixture(scope="module")
def gripped_pam(tmp_path_factory, muscle):
    """identify -o on two bores: the PAM file with the measured contact: block."""
    from pampipe.cli import main

    folder = tmp_path_factory.mktemp("grip")
    out = folder / "gripped.yaml"
    assert main(["identify", str(_experiment(folder, muscle, BORES)), "-o", str(out)]) == 0
    return out


def test_identify_writes_the_contact_block(gripped_pam):
    from pampipe.io.pam_schema import load_pam

    doc = yaml.safe_load(gripped_pam.read_text())
    assert set(doc["contact"]) >= {"friction", "load_coupling", "pipe_material"}
    assert doc["contact"]["pipe_material"] == "steel"
    pam = load_pam(gripped_pam)
    assert pam.grip.friction == doc["contact"]["friction"]["value"] and pam.grip.friction_sd > 0
    assert pam.grip.load_coupling == doc["contact"]["load_coupling"]["value"]


def test_identify_json_has_the_slip_block(cli, tmp_path, muscle):
    out = cli("identify", _experiment(tmp_path, muscle, BORES[:1]), "--json")
    assert out.returncode == 0, out.stderr
    slip = json.loads(out.stdout)["slip"]
    assert slip["load_coupling"] is None and slip["determined"] == ["effective_friction"]
    assert {"pressure_Pa", "slip_load_N", "censored", "test"} <= set(slip["trials"][0])


def _mission(folder: Path, pam: Path, friction=None, **extra) -> Path:
    section = {"name": "riser", "length": "3 m", "inner_diameter": "3 in", "incline": "90 deg", **extra}
    if friction is not None:
        section["friction"] = friction
    segments = [{"name": f"PAM{i}", "pam": str(pam), "mass": "0.4 kg"} for i in (1, 2, 3)]
    path = folder / f"mission-{len(list(folder.iterdir()))}.yaml"
    path.write_text(yaml.safe_dump({"robot": {"segments": segments, "payload": "2 kg"},
                                    "supply_pressure": "689 kPa", "safety_factor": 1.5, "route": [section],
                                    "load_path": "through_anchor"}))
    return path


def test_plan_from_pam_equals_plan_by_hand(tmp_path, gripped_pam):
    """friction: from_pam (and absent) gives the plan of the same μ written by hand, to 1e-9."""
    import pampipe

    mu = yaml.safe_load(gripped_pam.read_text())["contact"]["friction"]["value"]
    by_hand = pampipe.plan(_mission(tmp_path, gripped_pam, friction=mu)).to_dict()
    for friction in ("from_pam", None):
        measured = pampipe.plan(_mission(tmp_path, gripped_pam, friction=friction)).to_dict()
        for a, b in zip(measured["sections"][0]["segments"], by_hand["sections"][0]["segments"], strict=True):
            assert a["pressure_Pa"] == pytest.approx(b["pressure_Pa"], rel=1e-9, abs=1e-9)


def test_plan_takes_kappa_from_the_pam_without_load_path(tmp_path, gripped_pam):
    from pampipe.io.mission_schema import load_mission

    path = _mission(tmp_path, gripped_pam)
    raw = yaml.safe_load(path.read_text())
    raw.pop("load_path")
    mission = load_mission(path, raw=raw)
    kappa = yaml.safe_load(gripped_pam.read_text())["contact"]["load_coupling"]
    assert mission.load_path == "from_pam" and mission.kappa == kappa["value"]
    assert mission.kappa_sd == kappa["sd"] and mission.route.friction_sd[0] > 0
    with_path = load_mission(path)
    assert with_path.kappa == 1.0


def test_plan_warns_about_another_pipe_material(cli, tmp_path, gripped_pam):
    out = cli("plan", _mission(tmp_path, gripped_pam, pipe_material="PVC"))
    assert out.returncode == 0
    assert "PVC" in out.stderr and "steel" in out.stderr


def test_plan_from_pam_needs_segments_that_agree(cli, tmp_path, gripped_pam):
    """Segments whose PAM files measured different friction: exit 2 naming them."""
    other = yaml.safe_load(gripped_pam.read_text())
    other["contact"]["friction"]["value"] *= 1.5
    (tmp_path / "other.yaml").write_text(yaml.safe_dump(other))
    path = _mission(tmp_path, gripped_pam)
    raw = yaml.safe_load(path.read_text())
    raw["robot"]["segments"][2]["pam"] = str(tmp_path / "other.yaml")
    path.write_text(yaml.safe_dump(raw))
    out = cli("plan", path)
    assert out.returncode == 2
    assert "PAM1" in out.stderr and "PAM3" in out.stderr and "route[0].friction" in out.stderr


def test_plan_from_pam_needs_a_contact_block(cli, tmp_path):
    out = cli("plan", _mission(tmp_path, PROBLEMS / "pams" / "paper-radial-pam.yaml"))
    assert out.returncode == 2
    assert "route[0].friction" in out.stderr and "contact:" in out.stderr


# ------------------------------------------------------------------------------------------- bad data
def _bad(tmp_path: Path, header: str, rows: list[str]) -> Path:
    (tmp_path / "bad.csv").write_text("\n".join([header, *rows]) + "\n")
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump({"pam": str(PROBLEMS / "pams" / "paper-radial-pam.yaml"),
                                    "tests": [{"name": "s", "kind": "slip", "pipe_diameter": "3 in",
                                               "data": "bad.csv"}]}))
    return path


def _ramp(pressure="300", n=30):
    return [f"{i * 0.1:.1f},{pressure},{i * 10.0},{i * 0.001}" for i in range(n)]


@pytest.mark.parametrize(("header", "rows", "named"), [
    ("time [s],pressure [kPa],axial_load [N]", [r.rsplit(",", 1)[0] for r in _ramp()], "displacement"),
    ("time [s],pressure [kPa],axial_load [N],displacement [mm]",
     [f"{i * 0.1:.1f},300,50,{i * 0.001}" for i in range(30)], "axial_load"),
    ("time [s],pressure [kPa],axial_load [N],displacement [mm]", _ramp("-20"), "pressure"),
    ("time [s],pressure [kPa],axial_load [N],displacement [mm]", [*_ramp()[:5], "0.5,300,nan,0.1"],
     "axial_load"),
])
def test_bad_slip_data_exit_2_naming_file_and_column(cli, tmp_path, header, rows, named):
    out = cli("identify", _bad(tmp_path, header, rows))
    assert out.returncode == 2
    assert "bad.csv" in out.stderr and named in out.stderr and "Traceback" not in out.stderr


def test_identify_fits_moduli_and_grip_together(tmp_path, muscle):
    """Axial and radial tests beside a slip test: the moduli are fitted, then the grip with the fitted muscle;
    the API returns both (``result.slip``, ``to_dict()["slip"]``)."""
    import pampipe

    experiment = yaml.safe_load((PROBLEMS / "experiments" / "paper-protocol.yaml").read_text())
    for test in experiment["tests"]:
        test["data"] = str(PROBLEMS / "experiments" / test["data"])
    (tmp_path / "data").mkdir()
    columns = slip_data.slip_test(muscle, BORES[1], PRESSURES[::2], mu=MU, kappa=KAPPA, seed=3)
    slip_data.write(tmp_path / "data" / "slip.csv", columns)
    experiment["tests"].append({"name": "slip", "kind": "slip", "pipe_diameter": "3.5 in",
                                "data": "data/slip.csv"})
    result = pampipe.identify(experiment, base=tmp_path, degree=1)
    assert result.slip is not None and result.tests and len(result.slip.trials) == 8
    doc = result.to_dict()
    assert doc["moduli"]["hoop"]["a"] and doc["slip"]["determined"] == ["effective_friction"]
    amplification, _ = slip_data.amplification(muscle.geometry, BORES[1])
    truth = MU / (1 + KAPPA * MU * math.pi * amplification)
    low, high = doc["slip"]["combination"]["per_bore"][0]["ci95"]
    assert low <= truth <= high
    written = result.fitted_pam(load_bundled_pam())
    assert written.grip.friction == pytest.approx(doc["slip"]["combination"]["per_bore"][0]["value"])
    assert written.grip.load_coupling is None and written.moduli == result.moduli


def load_bundled_pam():
    from pampipe.io.pam_schema import load_pam

    return load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")


def test_synth_slip_tests_are_read_back(cli, tmp_path):
    """synth --slip-pipe writes slip tests that identify reads: 8 trials per bore, the held one censored, the
    true effective friction inside its interval, and --plots draws every test."""
    out = cli("synth", tmp_path, "--name", "grip", "--slip-pipe", "3 in", "--slip-only", "--held-trial", "2",
              "--friction", "0.25", "--load-coupling", "0.5", "--stick-slip", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["slip"]["friction"] == 0.25
    out = cli("identify", tmp_path / "grip.yaml", "--json", "--plots", tmp_path / "plots")
    assert out.returncode == 0, out.stderr
    slip = json.loads(out.stdout)["slip"]
    assert [t["censored"] for t in slip["trials"]] == [False, True] + [False] * 6
    amplification, _ = slip_data.amplification(load_bundled_pam().geometry, 0.0762)
    truth = 0.25 / (1 + 0.5 * 0.25 * math.pi * amplification)
    low, high = slip["combination"]["per_bore"][0]["ci95"]
    assert low <= truth <= high
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == ["slip_fit.png", "slip_slip-76.2mm.png"]


def test_synth_refuses_bad_slip_values(cli, tmp_path):
    out = cli("synth", tmp_path, "--slip-pipe", "3 in", "--friction", "0")
    assert out.returncode == 2 and "--friction" in out.stderr
    out = cli("synth", tmp_path, "--slip-only")
    assert out.returncode == 2 and "--slip-pipe" in out.stderr


def test_the_shipped_slip_example(cli):
    """problems/experiments/slip-3in.yaml: one bore, so the combination and not kappa; trial 3 held."""
    out = cli("identify", PROBLEMS / "experiments" / "slip-3in.yaml", "--json")
    assert out.returncode == 0, out.stderr
    slip = json.loads(out.stdout)["slip"]
    assert slip["load_coupling"] is None and slip["trials"][2]["censored"]
    low, high = slip["friction"]["range_for_load_coupling_0_to_1"]
    assert low <= 0.3 <= high  # the generating friction (kappa = 1)


def _coverage(muscle, seeds, *, stick_slip: bool, scatter=0.03):
    """Hits and counts of the 95 % intervals of μ, κ and each bore's μ_eff = μ/(1 + κμπA) over data sets of
    4–12 trials per bore (3 and 3.5 in, 3 % scatter, μ = 0.3, κ = 1), each drawn with its own seed."""
    hits, counts = np.zeros(3, dtype=int), np.zeros(3, dtype=int)
    for seed in seeds:
        n = int(np.random.default_rng(seed).integers(4, 13))
        pressures = np.linspace(2.5e5, 6e5, n)
        tests = tuple(make_slip_data(Spec(f"s{k}", "slip", Path("s.csv"), bore, 0.0),
                                     slip_data.slip_test(muscle, bore, pressures, mu=0.3, kappa=1.0,
                                                         scatter=scatter, stick_slip=stick_slip,
                                                         seed=1000 * seed + k))
                      for k, bore in enumerate((0.0762, 0.0889)))
        result = fit_slip(tests, muscle)
        if result.friction is not None:
            hits[:2] += [result.friction.low <= 0.3 <= result.friction.high,
                         result.load_coupling.low <= 1.0 <= result.load_coupling.high]
            counts[:2] += 1
        for e in result.effective:
            if e.estimate.closed:
                truth = 0.3 / (1 + 1.0 * 0.3 * math.pi * e.amplification)
                hits[2] += e.estimate.low <= truth <= e.estimate.high
                counts[2] += 1
    return hits, counts


def _honest_least(count: int) -> int:
    """The fewest hits of ``count`` 95 % intervals that a true coverage of 93 % gives in 99 % of studies
    (the binomial's 1 % quantile): a study of a few sets can only catch a coverage far below that."""
    from scipy.stats import binom

    return int(binom.ppf(0.01, count, 0.93))


def test_interval_coverage_small(muscle):
    """The default run's coverage study (issue 35): SMALL_SETS data sets of 4–12 stick-slip trials per bore.
    Its threshold is what so few sets can say (:func:`_honest_least`: 4 of 6, 9 of 12): it catches a
    coverage of 70 % in about a quarter (6 intervals) to half (12) of such studies; the slow study below is
    the one that checks 93 %."""
    hits, counts = _coverage(muscle, range(SMALL_SETS), stick_slip=True)
    assert np.all(counts == [SMALL_SETS, SMALL_SETS, 2 * SMALL_SETS]), counts
    assert all(h >= _honest_least(c) for h, c in zip(hits, counts, strict=True)), (hits, counts)


def test_stick_slip_onsets_give_the_generated_slip_loads(muscle, monkeypatch):
    """The detection error of three-jump (stick-slip) onsets is no source of the intervals' scatter: over 8
    data sets of the coverage study (4–12 trials per bore, every other one stick-slip), each detected slip
    load is the generated one within 0.2 % (measured over 120 sets: sd 0.02 %, largest 0.13 %, none
    censored) against the 3 % scatter of the slip loads; the clean trials alike."""
    made = []
    rows = slip_data.trial_rows

    def recorded(rng, slip_load, pressure, **options):
        made.append(slip_load)
        return rows(rng, slip_load, pressure, **options)

    monkeypatch.setattr(slip_data, "trial_rows", recorded)
    errors = []
    for seed in range(8):
        pressures = np.linspace(2.5e5, 6e5, int(np.random.default_rng(seed).integers(4, 13)))
        for k, bore in enumerate((0.0762, 0.0889)):
            made.clear()
            columns = slip_data.slip_test(muscle, bore, pressures, mu=0.3, kappa=1.0, scatter=0.03,
                                          stick_slip=True, seed=1000 * seed + k)
            trials = detect_trials((make_slip_data(Spec("s", "slip", Path("s.csv"), bore, 0.0), columns),))
            assert len(trials) == len(made) and not any(t.censored for t in trials)
            errors += [t.slip_load / load - 1 for t, load in zip(trials, made, strict=True)]
    assert np.max(np.abs(errors)) < 2e-3


@pytest.mark.slow
def test_interval_coverage_over_seeds(muscle):
    """96 data sets of 4–12 stick-slip trials per bore (slip in three jumps): the 95 % intervals hold the
    truth in ≥ 93 % for each of μ, κ and μ_eff. Measured: μ 92/96 (Wilson 95 % [0.898, 0.984]), κ 91/96
    ([0.884, 0.978]), μ_eff 183/192 ([0.913, 0.975]). Before, the chosen noise model's intervals held μ in
    90/96 and κ in 89/96 (0.927; 5 of the 7 misses under absolute scatter, 3 with 4 trials per bore); every
    interval now spans both noise models' (:func:`pampipe.slip.workflow.spanning`), at a median 1.16× (μ)
    and 1.18× (κ) the chosen model's width (docs/physics.md §13.3)."""
    hits, counts = _coverage(muscle, range(96), stick_slip=True)
    assert np.all(counts == [96, 96, 192]), counts  # μ and κ determined in every set
    assert np.all(hits >= 0.93 * counts), (hits, counts)


@pytest.mark.parametrize("n", [4, 6, 12])
def test_profile_interval_of_a_mean_is_the_exact_t_interval(n):
    """For n normal loads about an unknown mean (absolute noise, σ estimated), the profile-likelihood
    interval with the small-sample threshold is exactly x̄ ± t₀.₉₇₅,ₙ₋₁·s/√n (s the n − 1 sd): the
    textbook interval, computed here without pampipe. With χ²₁ it was narrower (4 loads: 1.96·s·√(4/3)/√4
    against 3.18·s/√4)."""
    from scipy import stats

    from pampipe.slip.fit import FRICTION_BOUNDS, Likelihood, maximise, profile_interval

    loads = 1.0 + 0.05 * np.random.default_rng(n).standard_normal(n)
    like = Likelihood(loads, np.zeros(n, bool), lambda mu, kappa: np.full(n, mu), "absolute")
    best = maximise(like, kappa=0.0)
    interval = profile_interval(like, best, "friction", FRICTION_BOUNDS, kappa_fixed=0.0)
    half = stats.t.ppf(0.975, n - 1) * loads.std(ddof=1) / math.sqrt(n)
    assert interval.low == pytest.approx(loads.mean() - half, abs=2e-5)
    assert interval.high == pytest.approx(loads.mean() + half, abs=2e-5)


def test_interval_threshold_limits():
    """n·ln(1 + t²/(n − p)) → χ²₁ = 3.841 for many trials; 5.90 at n = 4, p = 1; open with no degree of
    freedom; χ²₁ with σ held."""
    from pampipe.slip.fit import CHI2_95, interval_threshold

    assert interval_threshold(10**6, 1, False) == pytest.approx(CHI2_95, rel=1e-5)
    t3 = 3.182446305284263  # t₀.₉₇₅ on 3 degrees of freedom (tables)
    assert interval_threshold(4, 1, False) == pytest.approx(4 * math.log1p(t3**2 / 3), rel=1e-9)
    assert interval_threshold(2, 2, False) == math.inf
    assert interval_threshold(4, 1, True) == CHI2_95
