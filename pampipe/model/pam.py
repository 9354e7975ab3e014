"""Frozen SI descriptions of a PAM: its braid/bladder geometry and its bladder moduli.

No I/O here: :mod:`pampipe.io.pam_schema` builds these from YAML files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from pampipe.model import braid
from pampipe.model.uncertainty import ParameterUncertainty

Wall = Literal["thick", "thin"]
#: The key of a PAM file's ``effects:`` block naming effects the data could not tell apart (``Pam.ties``,
#: written by ``diagnose -o`` after a tie; none of them is applied): {"a or b": the test that would separate}.
TIES = "indistinguishable"


@dataclass(frozen=True)
class Geometry:
    """Rest geometry of a contractile McKibben muscle (docs/physics.md §1-§2), SI units.

    ``braid_angle`` is α₀, measured from the PAM axis (the paper quotes β₀ = 90° − α₀).
    """

    initial_length: float  # L0 [m], active length between end fittings
    initial_diameter: float  # D0 [m], braid = bladder outer diameter
    braid_angle: float  # alpha0 [rad], from the axis
    bladder_thickness: float  # t0 [m]
    wall: Wall = "thick"

    @classmethod
    def from_transverse_angle(cls, *, initial_length, initial_diameter, braid_angle_from_transverse,
                              bladder_thickness, wall: Wall = "thick") -> Geometry:
        """Build from the paper's angle convention β₀ (from the transverse plane): α₀ = π/2 − β₀."""
        return cls(initial_length, initial_diameter, math.pi / 2 - braid_angle_from_transverse,
                   bladder_thickness, wall)

    @property
    def braid_length(self) -> float:
        """B = L₀ / cos α₀ [m] (Eq. 1)."""
        return braid.braid_length(self)

    @property
    def turns(self) -> float:
        """N = L₀ tan α₀ / (π D₀) [-] (Eq. 2)."""
        return braid.turns(self)

    @property
    def shortest_length(self) -> float:
        """B/√3 [m]: the length at which the Gaylord force vanishes (α = 54.74°)."""
        return self.braid_length / math.sqrt(3.0)

    @property
    def extensile(self) -> bool:
        """True for a braid wound beyond the neutral angle (α₀ > 54.74° from the axis): it lengthens when
        inflated, toward B/√3, instead of contracting."""
        return self.braid_angle > math.atan(math.sqrt(2.0))

    @property
    def largest_diameter(self) -> float:
        """D(B/√3) = B√(2/3)/(Nπ) [m]: the widest the muscle can pull itself open."""
        return self.braid_length * math.sqrt(2.0 / 3.0) / (self.turns * math.pi)

    def as_vector(self) -> np.ndarray:
        """[L₀, D₀, α₀, t₀]: the geometry parameter vector of the prebuilt CasADi functions."""
        return np.array([self.initial_length, self.initial_diameter, self.braid_angle,
                         self.bladder_thickness])


@dataclass(frozen=True)
class Moduli:
    """Secant-moduli law E_k = Σ_j (a_kj + b_kj P/P_ref) ε_k^j, coefficients in Pa (docs/physics.md §4.2).

    ``contact`` holds optional increments applied once the muscle is anchored (docs/physics.md §9d),
    in the same order as :meth:`as_vector`; ``None`` means zero.
    """

    axial_a: tuple[float, ...]
    axial_b: tuple[float, ...]
    hoop_a: tuple[float, ...]
    hoop_b: tuple[float, ...]
    reference_pressure: float = 1e6  # P_ref [Pa]
    contact: tuple[float, ...] | None = None

    @property
    def degree(self) -> int:
        """Polynomial degree of the secant moduli in strain (3 = cubic, 16 coefficients)."""
        return len(self.axial_a) - 1

    def as_vector(self) -> np.ndarray:
        """θ = [a₁, b₁, a₂, b₂] [Pa], the ordering of docs/physics.md §6."""
        return np.concatenate([self.axial_a, self.axial_b, self.hoop_a, self.hoop_b]).astype(float)

    def contact_vector(self) -> np.ndarray:
        """Contact increments Δθ [Pa] in the order of :meth:`as_vector` (zeros when absent)."""
        if self.contact is None:
            return np.zeros(4 * (self.degree + 1))
        return np.asarray(self.contact, dtype=float)

    @classmethod
    def from_vector(cls, theta, *, reference_pressure: float = 1e6, contact=None) -> Moduli:
        """Inverse of :meth:`as_vector`."""
        theta = [float(v) for v in np.asarray(theta).ravel()]
        n = len(theta) // 4
        parts = [tuple(theta[i * n:(i + 1) * n]) for i in range(4)]
        contact_t = None if contact is None else tuple(float(v) for v in np.asarray(contact).ravel())
        return cls(*parts, reference_pressure=reference_pressure, contact=contact_t)


@dataclass(frozen=True)
class Grip:
    """Wall friction μ and load coupling κ from slip tests (docs/physics.md §13): the PAM's ``contact:``.

    ``load_coupling`` is None when the tests did not determine κ (one bore): ``friction`` is then the
    effective friction μ/(1 + κμπA) at ``tested_diameters[0]``, exact there with κ = 0 and conservative
    everywhere with κ = 1 (docs/physics.md §13.3). ``pipe_material``: the wall it was measured on.
    """

    friction: float
    friction_sd: float = 0.0
    load_coupling: float | None = None
    load_coupling_sd: float = 0.0
    pipe_material: str | None = None
    tested_diameters: tuple[float, ...] = ()  # [m]


@dataclass(frozen=True)
class Pam:
    """A named muscle: geometry, optional moduli, their uncertainty, effects and the maker's limits.

    ``covariance`` is the covariance of :meth:`Moduli.as_vector` [Pa²], written by ``identify``: the
    moduli block of ``uncertainty.covariance`` (kept for the code that reads the moduli alone; a PAM
    built by hand with an ``uncertainty`` should pass both, see :meth:`with_uncertainty`).
    ``effects`` maps effect names of :mod:`pampipe.model.effects` to their parameters (SI), e.g.
    ``{"braid_friction": {"f0": 12.0, "f1": 3e-5}}``, written by ``diagnose``; None: the baseline.
    ``uncertainty`` is the joint uncertainty of the moduli and calibrated geometry written by
    ``identify`` (:class:`~pampipe.model.uncertainty.ParameterUncertainty`); None: none stated.
    ``geometry_sd`` maps geometry entries (``initial_length``, ``initial_diameter``, ``braid_angle``,
    ``bladder_thickness``) to a stated standard deviation (SI: m, rad), from ``{value, sd}`` entries of
    the PAM file; empty when none. ``max_pressure`` [Pa] is the maker's rated pressure and
    ``max_contraction`` [-] the largest contraction 1 − L/L₀ the maker allows; None: not stated.
    ``fitting_length`` [m] is what the end fittings add to the rigid length of the deflated muscle.
    ``ties`` maps each group of effects the data could not tell apart (``"prestrain or sensor_offset"``) to
    the test that would separate them, written by ``diagnose`` after a tie: none of them is in ``effects``.
    """

    name: str
    geometry: Geometry
    moduli: Moduli | None = None
    covariance: np.ndarray | None = field(default=None, compare=False)
    effects: dict[str, dict[str, float]] | None = field(default=None, hash=False)
    grip: Grip | None = None  # measured wall friction and load coupling (the top-level ``contact:``)
    uncertainty: ParameterUncertainty | None = field(default=None, hash=False)
    geometry_sd: dict[str, float] = field(default_factory=dict, hash=False)
    max_pressure: float | None = None
    max_contraction: float | None = None

    def with_uncertainty(self, uncertainty: ParameterUncertainty | None) -> Pam:
        """This PAM with ``uncertainty`` and, consistently, its moduli block as ``covariance``."""
        covariance = None if uncertainty is None else uncertainty.moduli_covariance()
        return replace(self, uncertainty=uncertainty, covariance=covariance)
    fitting_length: float = 0.0  # [m]
    ties: dict[str, str] | None = field(default=None, hash=False)

    @property
    def rigid_length(self) -> float:
        """L₀ + fitting length [m]: the deflated segment as a rigid cylinder (docs/physics.md §14)."""
        return self.geometry.initial_length + self.fitting_length
