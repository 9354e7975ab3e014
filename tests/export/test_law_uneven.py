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
from scipy.optimize import brentq

from pampipe.export.law import Reason, mission_law
from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from tests.support import export_c
from tests.support.problems import PROBLEMS

#: (rest diameter [mm], length [mm], mass [kg], effects, max_pressure) per segment, rear to front
SEGMENTS = (("57.15 mm", "310.662 mm", "0.3 kg", None, None),
            ("63.5 mm", "260 mm", "0.9 kg", {"axial_preload": {"preload": "25 N"}}, None),
            ("57.15 mm", "310.662 mm", "0.5 kg", None, "400 kPa"))
ALPHA0 = math.radians(90 - 66.4373)  # the paper PAM's braid angle from the axis


@pytest.fixture(scope="module")
def uneven(tmp_path_factory):
    folder = tmp_path_factory.mktemp("uneven")
    base = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    mission = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for k, (diameter, length, mass, effects, rated) in enumerate(SEGMENTS):
        pam = {**base, "name": f"pam{k}", "geometry": {**base["geometry"], "initial_diameter": diameter,
                                                       "initial_length": length}}
        if effects:
            pam["effects"] = effects
        if rated:
            pam["max_pressure"] = rated
        (folder / f"pam{k}.yaml").write_text(yaml.safe_dump(pam))
        mission["robot"]["segments"][k].update(pam=f"pam{k}.yaml", mass=mass)
    path = folder / "uneven.yaml"
    path.write_text(yaml.safe_dump(mission))
    return load_mission(path)


def least_pressure(mission, i, d, incline, mu, payload):
    """Least P with μπF_r(P, D, κW) ≥ SF·W (brentq on the model), inf if none up to 100 MPa."""
    seg = mission.segments[i]
    muscle = Muscle.from_pam(seg.pam)
    total = sum(s.mass for s in mission.segments) + payload
    load = no_slip.anchor_load(total, seg.mass, incline, mu, mission.tether_drag)

    def margin(p):
        held = mu * math.pi * float(muscle.radial_force(p, d, mission.kappa * load))
        return held - mission.safety_factor * load

    start = max(float(muscle.anchoring_pressure(d, mission.kappa * load)), 0.0)
    if margin(start) >= 0:
        return start
    if margin(1e8) < 0:
        return math.inf
    return brentq(margin, start, 1e8, xtol=1e-6, rtol=1e-13)


def expected(mission, d, incline, mu, payload):
    """(reason, pressures) read segment by segment."""
    rest = [float(yaml_mm(s[0])) for s in SEGMENTS]
    braid = [math.sqrt(2 / 3) * r / math.sin(ALPHA0) for r in rest]
    limits = [mission.supply_pressure if s[4] is None else 400e3 for s in SEGMENTS]
    if any(d <= r for r in rest):
        return Reason.NARROW, None
    if any(d >= b for b in braid):
        return Reason.WIDE, None
    pressures = np.array([least_pressure(mission, i, d, incline, mu, payload) for i in range(len(SEGMENTS))])
    above = any(p > limit for p, limit in zip(pressures, limits, strict=True))
    return (Reason.ABOVE_SUPPLY if above else Reason.OK), pressures


def yaml_mm(text: str) -> float:
    return float(text.split()[0]) * 1e-3


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


def test_reasons_and_pressures_per_segment(uneven):
    law = mission_law(uneven)
    assert law.narrowest == pytest.approx(0.0635, rel=1e-12)
    assert law.widest == pytest.approx(math.sqrt(2 / 3) * 0.05715 / math.sin(ALPHA0), rel=1e-5)
    seen = set()
    for row in sections():
        reason, pressures = law.evaluate(*row)
        want, independent = expected(uneven, *row)
        assert reason == want, (row, reason, want)
        seen.add(want)
        if independent is not None:
            finite = np.isfinite(independent)
            np.testing.assert_array_equal(np.isfinite(pressures), finite)
            np.testing.assert_allclose(pressures[finite], independent[finite], rtol=1e-8)
    assert seen == {Reason.OK, Reason.NARROW, Reason.WIDE, Reason.ABOVE_SUPPLY}
    # the supply check is per segment: in the last special row only the rated segment is above its limit
    pressures = expected(uneven, 0.108, math.pi / 2, 0.3, 5.0)[1]
    np.testing.assert_array_equal(pressures > law.limits, [False, False, True])


@pytest.mark.skipif(export_c.compiler() is None, reason="no host C compiler (gcc or cc) found")
def test_the_c_law_answers_as_the_segments_do(uneven, tmp_path):
    export_c.write_export(uneven, tmp_path)
    codes, pressures = export_c.run_law(export_c.build(tmp_path), sections())
    for row, code, got in zip(sections(), codes, pressures, strict=True):
        want, independent = expected(uneven, *row)
        assert code == want, (row, code, want)
        if code == Reason.OK:
            np.testing.assert_allclose(got, independent, rtol=1e-8)
