"""The muscle's uncertainty after a test: prior, posterior covariance, closed directions (docs/commands.md,
next-test).

In scaled coordinates q over the PAM's ``uncertainty:`` names, what the fit knows is the Gaussian

    Σ₀ = Σ_q + Σ_j s_j² v_j v_jᵀ,

Σ_q the written covariance and, along each undetermined direction v_j, the width s_j the data leave open
(its ``scale``) as a prior sd: the plan "on the prior". A test of information F (:mod:`.information`) gives
the linearised posterior Σ₁ = (Σ₀⁻¹ + F)⁻¹ = (I + Σ₀F)⁻¹Σ₀. Within the span V of the undetermined
directions the ratio of posterior to prior variance is an eigenvalue r of W₀^{-1/2} W₁ W₀^{-1/2},
W = VᵀΣV; a direction stays open unless its 95 % half-width falls below the tenth of its prior width that
identify asks of an identifiable combination (Z95·√r < IDENTIFIABLE,
:mod:`pampipe.identification.covariance`).
A test of rank k changes at most k of these ratios.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from pampipe.identification.covariance import IDENTIFIABLE, Z95
from pampipe.model.pam import Moduli
from pampipe.model.uncertainty import (
    GEOMETRY_NAMES,
    ParameterUncertainty,
    UndeterminedDirection,
    moduli_names,
)


@dataclass(frozen=True)
class Posterior:
    """Σ₁ [scaled units²], the directions still open (unit vectors, widths) and how many closed."""

    covariance: np.ndarray
    open_vectors: tuple[np.ndarray, ...]
    open_widths: tuple[float, ...]
    closed: int


def scaled_covariance(u: ParameterUncertainty) -> np.ndarray:
    """Σ_q = Σ / (units unitsᵀ) [scaled units²]."""
    units = u.scaled_units()
    return u.covariance / np.outer(units, units)


def prior_covariance(u: ParameterUncertainty) -> np.ndarray:
    """Σ₀ (module docstring) [scaled units²]."""
    out = scaled_covariance(u)
    for d in u.undetermined:
        v = np.asarray(d.vector, dtype=float)
        out = out + d.scale**2 * np.outer(v, v)
    return 0.5 * (out + out.T)


def posterior(u: ParameterUncertainty, information: np.ndarray) -> Posterior:
    """Σ₁ and the undetermined directions left open after adding ``information`` F (module docstring)."""
    prior = prior_covariance(u)
    cov = np.linalg.solve(np.eye(prior.shape[0]) + prior @ information, prior)
    cov = 0.5 * (cov + cov.T)
    if not u.undetermined:
        return Posterior(cov, (), (), 0)
    v = np.array([d.vector for d in u.undetermined], dtype=float).T  # (m, k)
    before, after = v.T @ prior @ v, v.T @ cov @ v
    values, vectors = np.linalg.eigh(before)
    root = vectors / np.sqrt(values)  # W₀^{-1/2} (in W₀'s eigenbasis)
    ratios, mixes = np.linalg.eigh(root.T @ after @ root)
    still = Z95 * np.sqrt(np.clip(ratios, 0.0, None)) >= IDENTIFIABLE
    opened, spans = [], []
    for e in (root @ mixes)[:, still].T:
        direction = v @ e
        unit = direction / float(np.linalg.norm(direction))
        opened.append(unit if unit[np.argmax(np.abs(unit))] > 0 else -unit)
        spans.append(float(math.sqrt(max(unit @ cov @ unit, 0.0))))
    return Posterior(cov, tuple(opened), tuple(spans), int(len(u.undetermined) - still.sum()))


def planned_uncertainty(u: ParameterUncertainty, post: Posterior, *, on_prior: bool) -> ParameterUncertainty:
    """The ``uncertainty:`` a plan samples after the test (SI): with ``on_prior`` all of Σ₁ as the covariance
    (the open directions drawn over their posterior width, as a prior would); without, Σ₁ off the open
    directions as the covariance and the open directions listed as undetermined (a plan stops on them where
    they matter: exit 3)."""
    units = u.scaled_units()
    cov = post.covariance
    directions = ()
    if not on_prior and post.open_vectors:
        basis = np.array(post.open_vectors).T
        keep = np.eye(cov.shape[0]) - basis @ np.linalg.pinv(basis)
        cov = keep @ cov @ keep.T
        directions = tuple(UndeterminedDirection(vec, width, {}, "") for vec, width in
                           zip(post.open_vectors, post.open_widths, strict=True))
    si = 0.5 * (cov + cov.T) * np.outer(units, units)
    return ParameterUncertainty(u.names, si, u.model_error, directions, model_error_dof=u.model_error_dof)


def information_gain(u: ParameterUncertainty, information: np.ndarray) -> float:
    """log det(I + Σ₀F) = log det Σ₀ − log det Σ₁: the D-optimal criterion [nats]."""
    prior = prior_covariance(u)
    return float(np.linalg.slogdet(np.eye(prior.shape[0]) + prior @ information)[1])


def extended(pam, tested: bool) -> ParameterUncertainty:
    """The PAM's ``uncertainty:`` with, for a tested muscle (every segment that carries it ``unit: tested``),
    each geometry entry the PAM states with an sd (``{value, sd}``) that its fit did not calibrate, as a
    further parameter of variance sd² and no correlation: the fit did not measure it, so this muscle's own
    value is known only to its tolerance (a ``unit: lot`` plan draws it as the lot spread already)."""
    u = pam.uncertainty
    stated = pam.geometry_sd or {}
    extra = [n for n in GEOMETRY_NAMES if tested and n not in u.names and stated.get(n, 0.0) > 0]
    if not extra:
        return u
    size = len(u.names) + len(extra)
    cov = np.zeros((size, size))
    cov[:len(u.names), :len(u.names)] = u.covariance
    cov[len(u.names):, len(u.names):] = np.diag([stated[n] ** 2 for n in extra])

    def padded(directions):
        return tuple(dataclasses.replace(d, vector=np.r_[d.vector, np.zeros(len(extra))]) for d in directions)

    return ParameterUncertainty((*u.names, *extra), cov, u.model_error, padded(u.undetermined),
                                padded(u.prior_determined), u.model_error_dof)


def shifted(pam, u, q):
    """The PAM moved by ``q`` [scaled units] along the names of ``u``: its moduli and the geometry entries."""
    step = dict(zip(u.names, np.asarray(q, dtype=float) * u.scaled_units(), strict=True))
    names = moduli_names(pam.moduli.degree)
    theta = pam.moduli.as_vector() + np.array([step.get(n, 0.0) for n in names])
    moduli = Moduli.from_vector(theta, reference_pressure=pam.moduli.reference_pressure)
    geometry = pam.geometry
    for name in GEOMETRY_NAMES:
        if name in step:
            geometry = dataclasses.replace(geometry, **{name: getattr(geometry, name) + step[name]})
    return dataclasses.replace(pam, moduli=moduli, geometry=geometry)
