"""The exported law of a robot that is not uniform (issue 40): two muscle sizes, unequal masses, a PAM with
an effect (axial preload) beside two without, one rated below the supply. Judged per segment against an
independent computation: the least pressure that holds SF·W by brentq on the full model's radial force,
the rest diameter D₀ and the braid limit D(B/√3) = √(2/3)·D₀/sin α₀ from the PAM file's own numbers, and the
reason a segment-by-segment reading gives (too narrow for ANY muscle, too wide for ANY braid, ANY segment
above its own limit). The C function must give the same answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from pampipe.errors import InputError
from pampipe.export.law import Reason, mission_law
from pampipe.io.mission_schema import load_mission
from tests.support import export_c
from tests.support.problems import PROBLEMS
from tests.support.uneven import (
    RATED,
    SEGMENTS,
    braid_limits,
    least_holding_pressure,
    rest_diameters,
    uneven_mission,
)


@pytest.fixture(scope="module")
def uneven(tmp_path_factory):
    return uneven_mission(tmp_path_factory.mktemp("uneven"))


def expected(mission, d, incline, mu, payload):
    """(reason, pressures) read segment by segment."""
    rest, braid = rest_diameters(), braid_limits()
    limits = [mission.supply_pressure if s[4] is None else RATED for s in SEGMENTS]
    if any(d <= r for r in rest):
        return Reason.NARROW, None
    if any(d >= b for b in braid):
        return Reason.WIDE, None
    pressures = np.array([least_holding_pressure(mission, i, d, incline, mu, payload)
                          for i in range(len(SEGMENTS))])
    above = any(p > limit for p, limit in zip(pressures, limits, strict=True))
    return (Reason.ABOVE_SUPPLY if above else Reason.OK), pressures


def sections():
    """(D, φ, μ, m) rows: between the two rest diameters, between the two braid limits, one segment above
    its limit and the others not, and random sections inside the envelope."""
    rng = np.random.default_rng(40)
    rows = [(0.060, 1.2, 0.3, 2.0), (0.0620, 0.0, 0.5, 0.0),  # wider than 57 mm, not than 63.5 mm
            (0.120, 0.3, 0.4, 1.0), (0.125, 0.0, 0.3, 0.0),  # beyond 116.7 mm, within 129.7 mm
            (0.0762, math.pi / 2, 0.3, 2.0), (0.0889, 0.0, 0.3, 2.0), (0.0762, math.pi / 2, 0.3, 12.0),
            (0.108, math.pi / 2, 0.3, 5.0)]  # only the segment rated 400 kPa is above its limit
    for _ in range(25):
        rows.append((rng.uniform(0.064, 0.116), rng.uniform(-math.pi / 2, math.pi / 2), rng.uniform(0.1, 0.6),
                     rng.uniform(0, 30)))
    return rows


@pytest.fixture(scope="module")
def answers(uneven):
    """``sections()`` with their independent (reason, pressures), worked out once for both laws."""
    return [(row, *expected(uneven, *row)) for row in sections()]


def test_reasons_and_pressures_per_segment(uneven, answers):
    law = mission_law(uneven)
    assert law.narrowest == pytest.approx(0.0635, rel=1e-12)
    assert law.widest == pytest.approx(min(braid_limits()), rel=1e-5)
    seen = set()
    for row, want, independent in answers:
        reason, pressures = law.evaluate(*row)
        assert reason == want, (row, reason, want)
        seen.add(want)
        if independent is not None:
            finite = np.isfinite(independent)
            np.testing.assert_array_equal(np.isfinite(pressures), finite)
            np.testing.assert_allclose(pressures[finite], independent[finite], rtol=1e-8)
    assert seen == {Reason.OK, Reason.NARROW, Reason.WIDE, Reason.ABOVE_SUPPLY}
    # the supply check is per segment: in the last special row only the rated segment is above its limit
    pressures = next(p for row, _, p in answers if row == (0.108, math.pi / 2, 0.3, 5.0))
    np.testing.assert_array_equal(pressures > law.limits, [False, False, True])


@pytest.mark.skipif(export_c.compiler() is None, reason="no host C compiler (gcc or cc) found")
def test_the_c_law_answers_as_the_segments_do(uneven, answers, tmp_path):
    export_c.write_export(uneven, tmp_path)
    codes, pressures = export_c.run_law(export_c.build(tmp_path), [row for row, _, _ in answers])
    for (row, want, independent), code, got in zip(answers, codes, pressures, strict=True):
        assert code == want, (row, code, want)
        if code == Reason.OK:
            np.testing.assert_allclose(got, independent, rtol=1e-8)


def test_confidence_law_covers_plan_at_c_in_every_section():
    """`export --confidence C` adds per segment the largest P_C − P_nominal of `plan --confidence C` over the
    sections (issue 40): the law then asks at least P_C in every section, exactly P_C where that gap is
    largest, and the nominal law plus that margin elsewhere (the riser's friction sd 0.05, the run's 0.03:
    the gaps differ)."""
    from pampipe.export.law import confidence_margins
    from pampipe.io.mission_schema import load_mission
    from pampipe.planning import plan_mission
    from tests.support.problems import PROBLEMS

    mission = load_mission(PROBLEMS / "missions" / "riser-uncertain-friction.yaml")
    margins = confidence_margins(mission, 0.9, samples=400, seed=3)
    law, nominal = mission_law(mission, confidence=0.9, margins=margins), mission_law(mission)
    planned = plan_mission(mission, confidence=0.9, samples=400, seed=3).arrays
    gaps = planned.pressure - planned.nominal_pressure
    assert len(margins) == len(mission.segments) and np.ptp(gaps[:, 0]) > 1.0
    for s, sec in enumerate(mission.route):
        row = (sec.diameter, sec.incline, sec.friction, mission.payload)
        reason, pressures = law.evaluate(*row)
        assert reason == Reason.OK
        np.testing.assert_allclose(pressures, nominal.evaluate(*row)[1] + np.max(gaps, axis=0), rtol=1e-12)
        assert np.all(pressures >= planned.pressure[s] * (1 - 1e-9))
    assert np.allclose(margins, np.max(gaps, axis=0), rtol=1e-12)


#: effects without a closed form, with values (tests/export/test_export.py's)
REFUSED = {"end_effects": {"volume_taper": 0.3, "end_length": 0.5},
           "braid_extensibility": {"compliance": "2 1/MN"}}


@pytest.mark.parametrize("effects", [(None, "braid_extensibility", "end_effects"),
                                     (None, None, "end_effects"),
                                     ("end_effects", None, "braid_extensibility")],
                         ids=["middle-and-front", "front-only", "rear-and-front"])
def test_the_refusal_names_the_first_segment_that_cannot_be_exported(tmp_path, effects):
    """Segments rear to front, each with its own PAM file (``effects``: the one effect without a closed form
    on each, or none): the export's refusal names the rearmost segment whose PAM has one, that PAM and that
    effect, read from the files written here, and no other segment's."""
    base = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    mission = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for k, effect in enumerate(effects):
        pam = {**base, "name": f"pam{k}", **({"effects": {effect: REFUSED[effect]}} if effect else {})}
        (tmp_path / f"pam{k}.yaml").write_text(yaml.safe_dump(pam))
        mission["robot"]["segments"][k]["pam"] = f"pam{k}.yaml"
    (tmp_path / "m.yaml").write_text(yaml.safe_dump(mission))
    first = next(k for k, e in enumerate(effects) if e)
    names = [s["name"] for s in mission["robot"]["segments"]]
    with pytest.raises(InputError) as refusal:
        mission_law(load_mission(tmp_path / "m.yaml"))
    text = str(refusal.value)
    assert f"robot segment {names[first]} (PAM 'pam{first}')" in text
    assert f"the effect '{effects[first]}' cannot be exported to C" in text
    assert all(f"robot segment {n} " not in text for k, n in enumerate(names) if k != first)
