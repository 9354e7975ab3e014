"""The reference of the bore-range tests: a dense brute-force scan of the least holding pressure over a
range of bores (tests/planning/test_bores.py explains why 20 001 points meet the 1e-6 tolerance)."""

from __future__ import annotations

import numpy as np

from pampipe.model.muscle import Muscle

SCAN = 20_001  # points of the brute-force scan of each range


def scan_maximum(muscle: Muscle, low: float, high: float, load: float, *, kappa, friction, safety_factor,
                 points: int = SCAN):
    """(max P*, argmax D) over ``points`` evenly spaced bores of [low, high]."""
    bores = np.linspace(low, high, points)
    pressure = muscle.least_holding_pressure(bores, load, kappa=kappa, friction=friction,
                                             safety_factor=safety_factor)
    k = int(np.argmax(pressure))
    return float(pressure[k]), float(bores[k])
