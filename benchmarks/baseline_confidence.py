"""The plain numpy Monte Carlo a skilled user would write for `plan --confidence` (docs/physics.md §15).

Per section and segment, n draws of what pampipe draws, and per draw the closed-form least holding pressure

    P*_k = max over the range's bores D (smallest, the segment's worst, largest; each + δ_k) of
           W_k·κ_k/F₁ + (W_k/μ_k)·SF/(πAF₁) − (F₀ + e_k)/F₁,    W_k = μ_k·g·cos φ·(M − m) + g·M·|sin φ| + drag

(F₀ [N], F₁ [N/Pa], A [-] the muscle's coefficients at its anchored length in bore D, from the drawn
parameters), floored at 0 and cut (inf) beyond 100 MPa or where F₁ ≤ 0 or μ ≤ 0; the plan is its
C-quantile (the inverted-CDF rank ⌈nC⌉ − 1, by ``np.partition``). Drawn, as the docs state it:

* the fit's posterior: the PAM's ``uncertainty:`` covariance (moduli and calibrated geometry), one draw per
  PAM file shared by every section;
* for a ``unit: lot`` segment the stated geometry sds (``{value, sd}``), per segment;
* the model error e = s·t_ν (s·z where no ν is written), per segment;
* the friction μ ~ N(μ̂, sd²), one draw per friction statement (a wall material), moving the anchor's load;
* the bore δ ~ N(0, sd²), one draw per bore statement; κ ~ N(κ̂, sd²) clipped at 0, one per mission.

Its own random streams (not pampipe's): it agrees with pampipe within Monte Carlo error
(tests/planning/test_confidence_baseline.py), and shares with it only the mission reader
(``pampipe.load_mission``, its cache of a file read before included), the worst bore of a range (the
deterministic plan's search) and the muscle's coefficients F₀, F₁, A (``Muscle.affine_coefficients`` over
draws × distinct bores, 10⁴ × a few: not the costly part). Segments with the same PAM file, mass and unit have
the same distribution: each is sampled once. Sections are grouped by their bores and sampled in chunks of
``chunk`` values per array. Not covered: undetermined directions, tethers, effects, contact increments
(ValueError).

    .venv/bin/python benchmarks/baseline_confidence.py MISSION [--confidence 0.95] [--samples 10000]
"""

from __future__ import annotations

import argparse
import math
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from pampipe.api import load_mission
from pampipe.model.muscle import PRESSURE_LIMIT, Muscle
from pampipe.model.no_slip import STANDARD_GRAVITY
from pampipe.model.pam import Geometry
from pampipe.planning.problem import build_elements, mission_muscles

#: Values per (sections × draws) array of a chunk: 2¹⁶ doubles, 512 kB, within the L2 cache (the fastest
#: of 10⁴ to 2²² at 10⁴ draws).
CHUNK = 1 << 16


def _gaussian(rng, cov: np.ndarray, n: int) -> np.ndarray:
    """(n, size) zero-mean normal draws of ``cov``, through the eigen-decomposition of its correlation
    matrix (entries in Pa² and rad² differ by 10²⁰)."""
    out = np.zeros((n, cov.shape[0]))
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    live = np.flatnonzero(sd > 0)
    if live.size:
        values, vectors = np.linalg.eigh(cov[np.ix_(live, live)] / np.outer(sd[live], sd[live]))
        out[:, live] = rng.standard_normal((n, live.size)) @ (vectors * np.sqrt(np.clip(values, 0, None))).T
        out[:, live] *= sd[live]
    return out


def muscle_draws(segment, muscle: Muscle, n: int, rng, fits: dict) -> tuple[np.ndarray, np.ndarray]:
    """(parameter vectors (n, size), model error e (n,) [N]) of one segment's muscle."""
    if segment.pam.effects or muscle.structure.contact:
        raise ValueError("the baseline covers muscles without effects or contact increments")
    names = muscle.structure.names()
    u = segment.pam.uncertainty
    if u is not None and u.undetermined:
        raise ValueError("the baseline does not cover undetermined directions")
    key = segment.pam_file
    if key not in fits:
        cov = np.zeros((len(names), len(names)))
        if u is not None and u.covariance is not None:
            index = [names.index(name) for name in u.names]
            cov[np.ix_(index, index)] = u.covariance
        fits[key] = _gaussian(rng, cov, n)
    p = muscle.parameter_vector() + fits[key]
    if segment.unit == "lot":
        for name, sd in (segment.pam.geometry_sd or {}).items():
            p[:, names.index(name)] += sd * rng.standard_normal(n)
    s = float(getattr(u, "model_error", 0.0) or 0.0)
    dof = getattr(u, "model_error_dof", None)
    e = s * rng.standard_normal(n)
    if dof is not None:
        e /= np.sqrt(rng.chisquare(dof, n) / dof)
    return p, e


def coefficients(structure, p: np.ndarray, bore: np.ndarray) -> tuple[np.ndarray, ...]:
    """(F₀ [N], F₁ [N/Pa], A [-]) (n,) of the muscles ``p`` (n, size) in bores ``bore`` (n,) [m]."""
    t = structure.n_theta
    muscle = Muscle(Geometry(*p[:, :4].T, structure.wall), p[:, 5:5 + t].T, p[:, 4])
    with np.errstate(all="ignore"):
        c = muscle.affine_coefficients(bore)
    return c.at_zero, c.slope, c.amplification


def plain_monte_carlo(mission, confidence: float, samples: int, seed: int, chunk: int = CHUNK) -> np.ndarray:
    """The C-quantile of P* [Pa] of every (section, segment), (S, segments); inf where nothing holds."""
    if getattr(mission, "tether", None) is not None:
        raise ValueError("the baseline does not cover tethers")
    n, rng = samples, np.random.default_rng(seed)
    muscles = mission_muscles(mission)
    elements = build_elements(mission, muscles)
    route = mission.route
    low, high = np.asarray(route.diameter_low), np.asarray(route.diameter_high)
    bore_sd, mu_hat, mu_sd = (np.asarray(v, dtype=float) for v in (route.diameter_sd, route.friction,
                                                                   route.friction_sd))
    rise, run = np.abs(np.sin(route.incline)), np.cos(route.incline)
    total = sum(seg.mass for seg in mission.segments) + mission.payload
    rank = max(math.ceil(confidence * n - 1e-9) - 1, 0)
    # one draw per statement: friction (μ̂, sd), bore (range, sd); κ per mission
    friction_rows, friction_of = np.unique(np.stack([mu_hat, mu_sd]), axis=1, return_inverse=True)
    friction_of = friction_of.ravel()
    xi = rng.standard_normal((friction_rows.shape[1], n))
    bore_rows, bore_of = np.unique(np.stack([low, high, bore_sd]), axis=1, return_inverse=True)
    bore_of = bore_of.ravel()
    delta = rng.standard_normal((bore_rows.shape[1], n)) * bore_rows[2][:, None]
    kappa = np.maximum(mission.kappa + mission.kappa_sd * rng.standard_normal(n), 0.0)
    out = np.full((len(route), len(muscles)), np.inf)
    fits, done = {}, {}
    for i, (seg, muscle) in enumerate(zip(mission.segments, muscles, strict=True)):
        same = (seg.pam_file, seg.mass, seg.unit)
        if same in done:
            out[:, i] = out[:, done[same]]
            continue
        done[same] = i
        p, e = muscle_draws(seg, muscle, n, rng, fits)
        slope = STANDARD_GRAVITY * run * (total - seg.mass)
        at_zero = STANDARD_GRAVITY * total * rise + mission.tether_drag
        worst = np.asarray(elements.diameter[:, i])
        valid = np.asarray(elements.valid[:, i])
        groups, group_of = np.unique(np.stack([bore_of, worst]), axis=1, return_inverse=True)
        for g in range(groups.shape[1]):
            b, d_worst = int(groups[0, g]), groups[1, g]
            terms = []  # (κ/F₁, SF/(πAF₁), (F₀ + e)/F₁) per distinct bore of the range
            for d in sorted({bore_rows[0, b], d_worst, bore_rows[1, b]}):
                f0, f1, a = coefficients(muscle.structure, p, d + delta[b])
                f1 = np.where(f1 > 0, f1, np.nan)
                terms.append((kappa / f1, mission.safety_factor / (math.pi * a * f1), (f0 + e) / f1))
            rows = np.flatnonzero((group_of.ravel() == g) & valid)
            for part in np.array_split(rows, max(1, math.ceil(rows.size * n / chunk))):
                mu = mu_hat[part, None] + mu_sd[part, None] * xi[friction_of[part]]
                w = mu * slope[part, None] + at_zero[part, None]
                per_mu = np.where(mu > 0, w / mu, np.nan)
                least = None
                for k, r, f in terms:
                    value = w * k
                    value += per_mu * r
                    value -= f
                    least = value if least is None else np.maximum(least, value, out=least)  # NaN stays
                planned = np.partition(least, rank, axis=1)[:, rank]  # NaN sorts last: does not hold
                out[part, i] = np.where(planned <= PRESSURE_LIMIT, np.maximum(planned, 0.0), np.inf)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission")
    parser.add_argument("--confidence", type=float, default=0.95)
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--chunk", type=int, default=CHUNK, help="values per chunk array")
    args = parser.parse_args()
    started = time.process_time()
    mission = load_mission(args.mission)
    read = time.process_time() - started
    planned = plain_monte_carlo(mission, args.confidence, args.samples, args.seed, args.chunk)
    total = time.process_time() - started
    usage = resource.getrusage(resource.RUSAGE_SELF)
    print(f"read {read:.3f} s, Monte Carlo {total - read:.3f} s CPU, peak {usage.ru_maxrss / 1024:.0f} MB; "
          f"median plan {np.median(planned[np.isfinite(planned)]) / 1e3:.3f} kPa")


if __name__ == "__main__":
    main()
