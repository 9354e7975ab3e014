"""Forward simulation of one muscle anchored in a pipe (docs/physics.md §5-§7): `simulate`'s core."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.errors import InputError
from pampipe.model import braid, effects, forces
from pampipe.model.domain import check_pipe_diameter, check_pressure
from pampipe.model.functions import free_length
from pampipe.model.pam import Pam

#: The paper's test pressures, 69…689 kPa in 69 kPa steps (10 psi steps).
PAPER_PRESSURES = tuple(68947.57 * k for k in range(1, 11))


@dataclass(frozen=True)
class AnchoredCase:
    """One muscle in one pipe under one axial load, evaluated at several pressures (SI)."""

    pipe_diameter: float
    axial_load: float
    anchored_length: float
    amplification_factor: float
    anchoring_pressure: float
    pressures: np.ndarray
    radial_force: np.ndarray
    force_per_length: np.ndarray
    contact_pressure: np.ndarray
    free_length: np.ndarray  # length of the muscle at each pressure (L_p once anchored)
    terms: dict[str, np.ndarray]  # Eq. 14 breakdown, before the contact clip

    @property
    def anchored(self) -> np.ndarray:
        return self.pressures > self.anchoring_pressure

    def as_document(self) -> dict:
        """The `simulate` JSON document of docs/commands.md §6."""
        points = []
        for i, p in enumerate(self.pressures):
            points.append({
                "pressure_Pa": float(p),
                "radial_force_N": float(self.radial_force[i]),
                "radial_force_per_length_N_per_m": float(self.force_per_length[i]),
                "contact_pressure_Pa": float(self.contact_pressure[i]),
                "total_normal_force_N": float(np.pi * self.radial_force[i]),
                "anchored": bool(self.anchored[i]),
                "length_m": float(self.free_length[i]),
                "eq14_terms_N": {k: float(v[i]) for k, v in self.terms.items()},
            })
        return {"pipe_diameter_m": self.pipe_diameter, "axial_load_N": self.axial_load,
                "anchored_length_m": self.anchored_length,
                "amplification_factor": self.amplification_factor,
                "anchoring_pressure_Pa": self.anchoring_pressure, "points": points}


def require_moduli(pam: Pam, *, source: str = "PAM file") -> None:
    """A muscle without identified moduli cannot be simulated or planned."""
    if pam.moduli is None:
        raise InputError(f"{source}: the PAM '{pam.name}' has no 'moduli:' block; run "
                         "`pampipe identify EXPERIMENT.yaml -o PAM.yaml` first, or add the block by hand.")


def simulate_anchored(pam: Pam, *, pipe_diameter: float, axial_load: float = 0.0,
                      pressures=PAPER_PRESSURES, paper_literal: bool = False) -> AnchoredCase:
    """Anchoring pressure, anchored length, A, and F_r, f_r, p_c at each pressure (docs/physics.md §5)."""
    require_moduli(pam)
    geometry, theta = pam.geometry, pam.moduli.as_vector()
    pref, contact = pam.moduli.reference_pressure, pam.moduli.contact_vector()
    check_pipe_diameter(geometry, pipe_diameter)
    pressures = np.asarray(pressures, dtype=float)
    check_pressure(pressures)
    length = float(braid.length_at_diameter(pipe_diameter, geometry))
    amp = float(braid.amplification_factor(pipe_diameter, geometry))
    contact = contact if np.any(contact) else None
    if pam.effects:  # docs/physics.md §9 effects written by `diagnose`
        anchoring = float(effects.anchoring_pressure_with_effects(pipe_diameter, geometry, theta, pref,
                                                                  axial_load, contact, pam.effects))
        radial = effects.radial_force_with_effects(pressures, pipe_diameter, geometry, theta, pref,
                                                   axial_load, contact, pam.effects)
    else:
        anchoring = float(forces.anchoring_pressure(pipe_diameter, geometry, theta, pref, axial_load))
        radial = forces.radial_force(pressures, pipe_diameter, geometry, theta, pref, axial_load, contact)
    radial = np.asarray(radial, dtype=float) * np.ones_like(pressures)
    lengths = np.maximum(free_length(pressures, geometry, theta, pref, axial_load=axial_load), length)
    terms = forces.radial_force_terms(pressures, pipe_diameter, geometry, theta, pref, axial_load)
    terms = {k: np.asarray(v, dtype=float) * np.ones_like(pressures) for k, v in terms.items()}
    return AnchoredCase(
        pipe_diameter=float(pipe_diameter), axial_load=float(axial_load), anchored_length=length,
        amplification_factor=amp, anchoring_pressure=anchoring, pressures=pressures,
        radial_force=radial, force_per_length=forces.force_per_length(radial, length),
        contact_pressure=forces.contact_pressure(radial, pipe_diameter, length, paper_literal),
        free_length=lengths, terms=terms)
