"""The 23 section kinds of the planning tests: 3–3.6 in bores, two outside the demo muscle's range (50 mm,
narrower than D₀ = 57 mm; 200 mm, wider than its braid opens), frictions 0.2–0.5 and one frictionless,
inclines within ±1.5 rad."""

from __future__ import annotations

import numpy as np

KINDS = 23


def mixed_kinds(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(bores [m], inclines [rad], frictions) of the :data:`KINDS` kinds, drawn from ``rng``."""
    bores = rng.uniform(3.0, 3.6, KINDS) * 0.0254
    bores[[3, 17]] = [0.05, 0.2]
    friction = rng.uniform(0.2, 0.5, KINDS)
    friction[9] = 0.0
    incline = rng.uniform(-1.5, 1.5, KINDS)
    return bores, incline, friction
