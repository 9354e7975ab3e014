"""The planning problem of one mission, as per-element arrays (docs/physics.md §5, §7, §8).

An *element* is one (section s, segment i) pair. The gait of docs/physics.md §8 anchors, in steps
I…VII, the segments {2}, {1,2}, {1}, {1,3}, {3}, {2,3}, {2}: every segment is the only anchor in
some step, so in every section each segment must hold the section's whole load alone.

* Load on the single anchor i in section s (incline φ, wall friction μ, M = segment masses + payload):
  W = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + tether_drag  [N]  (:func:`pampipe.model.slip.anchor_load`).
* At the anchored length L_p = L(D_s) the free-muscle force is affine in P (docs/physics.md §7):
  F_ax(P, L_p) = F₀ + F₁·P, and the contact increment of docs/physics.md §9d is
  ΔF = ((P − P_a)₊/P_ref)·(C₀ + C₁·P), with P_a = (κW − F₀)/F₁ the anchoring pressure under the load.
* No slip: g(P) = μπA·(F₀ + F₁P + ΔF(P) − κW) − SF·W ≥ 0 (holding capacity ≥ SF × required hold).

The coefficients are evaluated once per element from the model functions (vectorised numpy); the NLP
of :mod:`pampipe.plan.solve` takes them as parameters, so a new route or payload is a new call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.model import braid, forces
from pampipe.model.slip import STANDARD_GRAVITY, anchor_load

#: Largest gauge pressure the model accepts [Pa] (pampipe.model.domain.check_pressure).
PRESSURE_LIMIT = 1e8


@dataclass(frozen=True)
class Elements:
    """Per-element arrays of shape (sections, 3), SI units. Invalid elements hold finite placeholders."""

    diameter: np.ndarray  # D_s [m]
    length: np.ndarray  # anchored length L_p = L(D_s) [m]
    amplification: np.ndarray  # A(D_s) [-]
    volume: np.ndarray  # V(L_p) = πD²L/4 [m³], the air the segment takes per pascal
    at_zero: np.ndarray  # F₀ = F_ax(0, L_p) [N]
    slope: np.ndarray  # F₁ = ∂F_ax/∂P [N/Pa]
    contact_at_zero: np.ndarray  # C₀ [N] (contact increments, docs/physics.md §9d)
    contact_slope: np.ndarray  # C₁ [N/Pa]
    reference_pressure: np.ndarray  # P_ref [Pa]
    load: np.ndarray  # W [N], required hold
    load_per_payload: np.ndarray  # ∂W/∂payload = g(|sin φ| + μ cos φ) [N/kg]
    friction: np.ndarray  # μ [-]
    kappa: float  # κ of the load path
    safety_factor: float  # SF
    valid: np.ndarray  # inside the model's domain: D₀ < D < D(B/√3) and μ > 0

    @property
    def grip(self) -> np.ndarray:
        """μπA [-]: holding capacity per newton of F_ax − κW."""
        return self.friction * math.pi * self.amplification

    @property
    def anchoring(self) -> np.ndarray:
        """P_a(κW) = (κW − F₀)/F₁ [Pa]: the pressure at which the loaded muscle reaches the wall."""
        return (self.kappa * self.load - self.at_zero) / self.slope

    @property
    def free_anchoring(self) -> np.ndarray:
        """P_a(0) = −F₀/F₁ [Pa]: the pressure at which the unloaded muscle reaches the wall."""
        return -self.at_zero / self.slope

    @property
    def lower_bound(self) -> np.ndarray:
        """Contact constraint as a bound: P ≥ max(P_a(κW), 0) [Pa]."""
        return np.maximum(self.anchoring, 0.0)


def holding_force(pressure, at_zero, slope, contact_at_zero, contact_slope, reference_pressure,
                  anchoring, axial_load):
    """F_ax + ΔF − κW [N] at pressure P ≥ P_a(κW), the contact switch being closed (floats or CasADi)."""
    engaged = (pressure - anchoring) / reference_pressure
    return (at_zero + slope * pressure + engaged * (contact_at_zero + contact_slope * pressure)
            - axial_load)


def slip_margin(pressure, elements: Elements):
    """g(P) = μπA(F_ax + ΔF − κW) − SF·W [N] for every element (numpy; P broadcast to (S, 3))."""
    e = elements
    hold = holding_force(pressure, e.at_zero, e.slope, e.contact_at_zero, e.contact_slope,
                         e.reference_pressure, e.anchoring, e.kappa * e.load)
    return e.grip * hold - e.safety_factor * e.load


def slip_margin_slope(pressure, elements: Elements):
    """∂g/∂P [N/Pa] = μπA(F₁ + (C₀ + C₁P)/P_ref + C₁(P − P_a)/P_ref)."""
    e = elements
    return e.grip * (e.slope + (e.contact_at_zero + e.contact_slope * pressure) / e.reference_pressure
                     + e.contact_slope * (pressure - e.anchoring) / e.reference_pressure)


def build_elements(mission, *, payload: float | None = None) -> Elements:
    """Evaluate the model once per element for ``mission`` (payload [kg] overrides the mission's)."""
    payload = mission.payload if payload is None else float(payload)
    route = mission.route
    diameter = np.array([s.diameter for s in route], dtype=float)
    incline = np.array([s.incline for s in route], dtype=float)
    friction = np.array([s.friction for s in route], dtype=float)
    total_mass = sum(seg.mass for seg in mission.segments) + payload
    columns = []
    for seg in mission.segments:
        g = seg.pam.geometry
        theta, pref = seg.pam.moduli.as_vector(), seg.pam.moduli.reference_pressure
        contact = seg.pam.moduli.contact_vector()
        valid = (diameter > g.initial_diameter) & (diameter < g.largest_diameter) & (friction > 0)
        safe = np.where(valid, diameter, 0.5 * (g.initial_diameter + g.largest_diameter))
        length = braid.length_at_diameter(safe, g)
        at_zero, slope = forces.axial_force_affine(length, g, theta, pref)
        if np.any(contact):
            c0 = forces.bladder_force(0.0, length, g, contact, pref)
            c1 = (forces.bladder_force(pref, length, g, contact, pref) - c0) / pref
        else:
            c0 = c1 = np.zeros_like(length)
        load = anchor_load(total_mass, seg.mass, incline, friction, mission.tether_drag)
        columns.append({
            "diameter": diameter, "length": length, "amplification": braid.amplification_factor(safe, g),
            "volume": braid.enclosed_volume(length, g), "at_zero": at_zero, "slope": slope,
            "contact_at_zero": c0, "contact_slope": c1, "reference_pressure": np.full_like(length, pref),
            "load": load,
            "load_per_payload": STANDARD_GRAVITY * (np.abs(np.sin(incline)) + friction * np.cos(incline)),
            "friction": friction, "valid": valid})
    stacked = {key: np.stack([np.broadcast_to(c[key], diameter.shape) for c in columns], axis=1)
               for key in columns[0]}
    return Elements(**stacked, kappa=mission.kappa, safety_factor=mission.safety_factor)


def largest_load(pressure, elements: Elements) -> np.ndarray:
    """W_max [N] each element holds at pressure P: the W with capacity(P, W) = SF·W.

    Above anchoring, P − P_a(κW) = (F_ax(P) − κW)/F₁, so the contact increment scales the holding
    force by k = 1 + (C₀ + C₁P)/(P_ref F₁), and μπA·k·(F_ax(P) − κW) = SF·W gives
    W_max = μπA·k·F_ax(P) / (SF + κ·μπA·k)   (docs/physics.md §8 with k = 1 without contact increments).
    Negative where the unloaded muscle does not reach the wall at P.
    """
    e = elements
    stiffening = 1 + (e.contact_at_zero + e.contact_slope * pressure) / (e.reference_pressure * e.slope)
    grip = e.grip * stiffening
    return grip * (e.at_zero + e.slope * pressure) / (e.safety_factor + e.kappa * grip)
