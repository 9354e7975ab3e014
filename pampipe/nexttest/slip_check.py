"""The preposterior check of a slip test (docs/commands.md §14.4): the truth's slip trials, a refit of the
moduli from them, the muscle that refit leaves.

``identify`` fits μ and κ to slip tests with the moduli held (:mod:`pampipe.slip.workflow`); what the
linearised criterion credits a slip test with is what its slip loads say about the moduli, ln μ a nuisance
(:mod:`.information`). The check refits exactly that:

1. the truth's trials (:func:`pampipe.slip.synthetic_trials.generate_slip`, `synth`'s generator: one trial
   per pressure level and trial, slip load W = μπF_r(P, D, κW) scattered by exp(N(0, s²)), s = 3 %, traces
   with sensor noise) and their slip loads as pampipe's detector finds them;
2. the MAP estimate over the scaled parameters q (1 MPa, 1 deg, 1 mm) and ln μ,

       min  qᵀΣ₀⁻¹q + Σ_i (ln W_i − ln W(P_i; θ̂ + q, μ, κ))² / s²,

   Σ₀ the prior (:func:`.posterior.prior_covariance`: the check's truths are drawn from it), W the plan's
   slip model (:meth:`pampipe.model.muscle.Muscle.largest_load`, SF = 1), κ known as the linearised criterion
   takes it (the PAM's ``contact:`` coupling, else :data:`KAPPA`), by scipy's ``least_squares``;
3. the refitted muscle's uncertainty: the Gauss-Newton posterior (Σ₀⁻¹ + F)⁻¹ at the estimate, F the slip
   rows' information with ln μ marginalised (its Schur complement), and the undetermined directions it
   leaves open (:func:`.posterior.posterior`).

The plan's friction is the mission's: the μ fitted here is a nuisance, as in the linearised criterion.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from pampipe.model.muscle import Muscle
from pampipe.nexttest.posterior import planned_uncertainty, posterior, prior_covariance, shifted
from pampipe.slip.synthetic_trials import SlipProtocol, generate_slip
from pampipe.slip.workflow import detect_trials
from pampipe.specs.experiment import make_slip_data

#: The load coupling κ of the trials when the PAM carries none (through the anchor: the conservative end).
KAPPA = 1.0
#: [N] The slip load below which the model's ln W is floored (a muscle that does not grip at a trial's P).
FLOOR = 1e-3


def grip(pam) -> tuple[float, float]:
    """(μ, κ) of the truth's trials: the PAM's measured ``contact:``, else synth's μ and :data:`KAPPA`."""
    measured = pam.grip
    if measured is None:
        return SlipProtocol(pipes=()).friction, KAPPA
    return measured.friction, KAPPA if measured.load_coupling is None else measured.load_coupling


def trials(truth_pam, test, seed: int, friction: float, kappa: float) -> tuple[np.ndarray, np.ndarray]:
    """(P [Pa], W [N]) of the detected slips of ``test`` (``trials`` per pressure level) on ``truth_pam``."""
    pressures = tuple(float(p) for p in np.repeat(test.pressures, test.trials))
    protocol = SlipProtocol(pipes=(test.pipe_diameter,), friction=friction, load_coupling=kappa,
                            pressures=pressures)
    made = generate_slip(Muscle.from_pam(truth_pam), protocol, np.random.default_rng(seed))
    found = [t for t in detect_trials(tuple(make_slip_data(spec, columns) for spec, columns in made))
             if not t.censored and t.slip_load > 0]
    return np.array([t.pressure for t in found]), np.array([t.slip_load for t in found])


def refit_slip(pam, u, diameter: float, pressure, load, friction: float, kappa: float):
    """The PAM refitted to slip loads ``load`` at ``pressure`` in bore ``diameter`` with prior N(θ̂, Σ₀) over
    ``u``'s names (module docstring, steps 2 and 3); its ``uncertainty`` the posterior.

    The search runs in whitened coordinates z, q = Bz with BBᵀ = Σ₀ (B over the range of Σ₀: what the plan
    takes as known stays), so the prior term is |z|²; the slip rows' information in q is B⁺ᵀF_zB⁺."""
    scatter = SlipProtocol(pipes=()).scatter
    values, vectors = np.linalg.eigh(prior_covariance(u))
    keep = values > 1e-12 * values.max()
    basis = vectors[:, keep] * np.sqrt(values[keep])  # B
    inverse = (vectors[:, keep] / np.sqrt(values[keep])).T  # B⁺

    def residuals(x):
        muscle = Muscle.from_pam(shifted(pam, u, basis @ x[:-1]))
        modelled = muscle.largest_load(pressure, diameter, kappa=kappa, friction=np.exp(x[-1]),
                                       safety_factor=1.0)
        slips = (np.log(load) - np.log(np.maximum(modelled, FLOOR))) / scatter
        return np.concatenate([slips, x[:-1]])

    found = least_squares(residuals, np.r_[np.zeros(basis.shape[1]), np.log(friction)], method="trf")
    slips = found.jac[:pressure.size]
    info = slips.T @ slips
    tail = info[-1, -1]
    schur = np.outer(info[:-1, -1], info[-1, :-1]) / tail if tail > 0 else 0.0
    post = posterior(u, inverse.T @ (info[:-1, :-1] - schur) @ inverse)
    moved = shifted(pam, u, basis @ found.x[:-1])
    return moved.with_uncertainty(planned_uncertainty(u, post, on_prior=False))
