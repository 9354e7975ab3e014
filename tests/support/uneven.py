"""A robot that is not uniform (issue 40), written as mission and PAM files: two muscle sizes, unequal
masses, a PAM with an effect (axial preload) beside two without, one rated below the supply."""

from __future__ import annotations

import math
from pathlib import Path

import yaml
from scipy.optimize import brentq

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from tests.support.problems import PROBLEMS

#: (rest diameter, length, mass, effects, max_pressure) per segment, rear to front
SEGMENTS = (("57.15 mm", "310.662 mm", "0.3 kg", None, None),
            ("63.5 mm", "260 mm", "0.9 kg", {"axial_preload": {"preload": "25 N"}}, None),
            ("57.15 mm", "310.662 mm", "0.5 kg", None, "400 kPa"))
#: the paper PAM's braid angle from the axis, which every segment keeps [rad]
ALPHA0 = math.radians(90 - 66.4373)
RATED = 400e3  # [Pa] the third segment's max_pressure


def rest_diameters() -> list[float]:
    """D₀ per segment [m], read from :data:`SEGMENTS`."""
    return [float(s[0].split()[0]) * 1e-3 for s in SEGMENTS]


def braid_limits() -> list[float]:
    """D(B/√3) = √(2/3)·D₀/sin α₀ per segment [m]: the widest bore each braid can fill."""
    return [math.sqrt(2 / 3) * d / math.sin(ALPHA0) for d in rest_diameters()]


def uneven_mission(folder: Path, route: list[dict] | None = None):
    """The demo climb with the :data:`SEGMENTS` robot (files in ``folder``), loaded; ``route``: its route."""
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
    if route is not None:
        mission["route"] = route
    path = folder / "uneven.yaml"
    path.write_text(yaml.safe_dump(mission))
    return load_mission(path)


def least_holding_pressure(mission, i: int, d: float, incline: float, mu: float, payload: float) -> float:
    """Least P [Pa] with μπF_r(P, D, κW) ≥ SF·W for segment i (brentq on the full model's radial force,
    from the anchoring pressure up); inf if none up to 100 MPa, or where the bore is not wider than the
    segment's muscle at rest or not narrower than its braid limit (:func:`rest_diameters`,
    :func:`braid_limits`)."""
    if not rest_diameters()[i] < d < braid_limits()[i]:
        return math.inf
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
    if not margin(1e8) >= 0:
        return math.inf
    return brentq(margin, start, 1e8, xtol=1e-6, rtol=1e-13)
