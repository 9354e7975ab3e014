"""The uncertain inputs of a confidence plan, as seeded joint draws (docs/physics.md §15).

Every source is drawn as a zero-mean deviation from the nominal value, so that a plan can add them all
(the full draw) or one at a time (the dominance table). Sources (:data:`SOURCES`):

* ``moduli``: the moduli θ and every geometry entry ``identify`` calibrated, jointly Gaussian with the
  covariance of the PAM's ``uncertainty:`` block (``Pam.uncertainty``, or the moduli-only
  ``Pam.covariance`` [Pa²] of older files): what the fit leaves open of the TESTED muscle. One fit per
  PAM file: segments that share a PAM file share this draw, in every section.
* ``geometry``: the lot spread, for a segment of ``unit: lot`` (another muscle of the tested one's lot):
  every geometry entry with a stated sd (``Pam.geometry_sd``, the ``{value, sd}`` entries), calibrated
  ones included, drawn around the fitted geometry; independent per segment (each its own muscle), the
  same in every section. A segment of ``unit: tested`` carries the tested muscle: nothing is drawn here
  (the fit absorbed the stated sds), and every tested segment of a PAM file is that one muscle.
* ``model_error``: a shift e [N] of the axial force F_ax at the anchored length, s the PAM's
  ``model_error`` (an estimate of the residual sd beyond the noise) and ν its ``model_error_dof``: the
  Student-t predictive e = s·t_ν, drawn as e = s·z/√(W/ν) with z ~ N(0, 1) and W ~ χ²_ν from a stream
  of its own (:func:`chi_scale`), so that ν → ∞ gives the normal draw e = s·z exactly; without a stated
  ν (older files) e = s·z, a normal. Per segment.
* ``bore``: a shift δ ~ N(0, sd²) [m] of the bore of each section (its ``sd``); the tolerance range is
  not drawn: the plan holds over all of it (the pipe takes every bore of its range along its length).
  One draw per bore statement (range and sd): :func:`keyed_normal`.
* ``friction``: μ ~ N(μ̂, sd²), one draw per friction statement (μ̂, sd), i.e. per wall material: a
  measured μ is one unknown number for every pipe of that wall; a draw with μ ≤ 0 cannot hold.
* ``kappa``: κ ~ N(κ̂, sd²) clipped at 0 (``Mission.kappa_sd``), one draw for the mission.
* ``prior``: along each ``undetermined`` direction v of a fit (a unit vector in scaled coordinates q,
  one unit = 1 MPa, 1 deg or 1 mm: :mod:`pampipe.model.uncertainty`), q = q̂ + t·v with t from the prior
  (``--prior-from PAM``: its moduli and covariance; the PAM's stated geometry sds) combined with the
  width the data leave open (:func:`_prior`); without a prior along v the direction is reported instead
  (exit 3).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from pampipe.errors import InputError
from pampipe.model.muscle import Muscle
from pampipe.model.uncertainty import scaled_unit

SOURCES = ("moduli", "geometry", "model_error", "bore", "friction", "kappa", "prior", "tether")
#: What each source is, for reports.
SOURCE_WORDS = {"moduli": "moduli and calibrated geometry (identify's covariance)",
                "geometry": "lot spread of the geometry (PAM file sd; unit: lot segments)",
                "model_error": "model error (axial force residual beyond noise)",
                "bore": "bore sd", "friction": "wall friction sd", "kappa": "load coupling kappa sd",
                "prior": "prior along undetermined directions",
                "tether": "tether friction sd (its tension, docs/physics.md §16)"}


@dataclass(frozen=True)
class Direction:
    """A direction of the parameter vector the data leave undetermined, and what would determine it."""

    vector: np.ndarray  # unit vector in scaled coordinates, in the muscle's layout (Structure.names())
    units: np.ndarray  # SI size of one scaled unit of each parameter (same layout)
    scale: float  # [scaled units] the width along ``vector`` the data leave open
    test: str  # the test that would determine it

    @property
    def step(self) -> np.ndarray:
        """SI change of the parameter vector for one scaled unit along the direction."""
        return self.vector * self.units


@dataclass(frozen=True)
class MuscleUncertainty:
    """One segment's muscle: nominal parameter vector and the covariances of its sources (SI)."""

    nominal: np.ndarray  # (size,)
    fit: np.ndarray  # (size, size) covariance of the fit (moduli and calibrated geometry)
    tolerance: np.ndarray  # (size,) sds of the lot spread (the stated geometry sds; zero for unit: tested)
    model_error: float  # [N]
    undetermined: tuple[Direction, ...] = ()
    prior_shift: tuple[float, ...] = ()  # per undetermined direction, vᵀ(q_prior − q̂) [scaled units]
    prior_sd: tuple[float, ...] = ()  # per undetermined direction, √(vᵀΣ_q,prior v) (0: no prior)
    fit_key: object = None  # segments with equal keys share the fit draw
    unit: str = "lot"  # "tested": the fitted muscle itself (one per fit_key); "lot": another of its lot
    model_error_dof: int | None = None  # ν of model_error² (None: not stated, the error is drawn normal)

    @property
    def unresolved(self) -> tuple[Direction, ...]:
        """Undetermined directions that no prior covers."""
        return tuple(d for d, sd in zip(self.undetermined, self.prior_sd or (0.0,) * len(self.undetermined),
                                        strict=True) if sd <= 0)


@dataclass(frozen=True)
class MuscleDraws:
    """n seeded draws of the sources the whole route shares, as deviations: ``params[k][i]`` is source
    k's (n, size) block of segment i's parameter vector, ``model_error[i]`` its (n,) shift [N], ``kappa``
    the (n,) deviation of κ. The per-section sources (bore, friction) are drawn by :func:`keyed_normal`."""

    n: int
    params: dict[str, list[np.ndarray]]  # "moduli", "geometry", "prior"
    model_error: list[np.ndarray]  # per segment (n,) [N]
    kappa: np.ndarray  # (n,)


def _names_index(names, structure, where: str) -> list[int]:
    layout = {name: k for k, name in enumerate(structure.names())}
    out = []
    for name in names:
        if name not in layout:
            raise InputError(f"{where}: the uncertainty names '{name}', which is not a parameter of this "
                             f"muscle; allowed: {', '.join(layout)}.")
        out.append(layout[name])
    return out


def _covariance(pam, structure, where: str) -> np.ndarray:
    """The fit covariance of ``pam`` in the muscle's layout (zeros where it says nothing)."""
    size = structure.size
    out = np.zeros((size, size))
    u = getattr(pam, "uncertainty", None)
    if u is not None and getattr(u, "covariance", None) is not None:
        index = _names_index(u.names, structure, where)
        out[np.ix_(index, index)] = np.asarray(u.covariance, dtype=float)
    elif pam.covariance is not None:
        index = list(range(5, 5 + structure.n_theta))
        out[np.ix_(index, index)] = np.asarray(pam.covariance, dtype=float)
    return out


def muscle_uncertainty(segment, muscle: Muscle, *, where: str, prior=None) -> MuscleUncertainty:
    """The sources of one segment's muscle, from its PAM (and the ``prior`` PAM, if any) and its ``unit``:
    ``lot`` draws every stated geometry sd as the lot spread, ``tested`` none (docs/physics.md §15)."""
    pam, structure = segment.pam, muscle.structure
    fit = _covariance(pam, structure, where)
    stated = np.zeros(structure.size)  # every stated geometry sd, the prior of undetermined directions
    given = getattr(pam, "geometry_sd", None) or {}
    for name, k in zip(given, _names_index(given, structure, where), strict=True):
        stated[k] = float(given[name])
    u = getattr(pam, "uncertainty", None)
    unit = getattr(segment, "unit", "lot")
    if unit == "tested" and u is None and pam.covariance is None:
        raise InputError(f"{where}: 'unit: tested' says the segment carries the very muscle the PAM file was "
                         f"fitted to, but the PAM '{pam.name}' has no 'uncertainty:' block (written by "
                         "`pampipe identify -o`): nothing describes that muscle's fit. Say 'unit: lot' (the "
                         "stated geometry sds are then drawn as the lot spread), or give the PAM written by "
                         "identify.")
    tolerance = np.zeros(structure.size) if unit == "tested" else stated
    error = float(getattr(u, "model_error", 0.0) or 0.0)
    dof = getattr(u, "model_error_dof", None)
    units = np.array([scaled_unit(name) for name in structure.names()])
    directions = []
    for d in getattr(u, "undetermined", None) or ():
        vector = np.zeros(structure.size)
        vector[_names_index(u.names, structure, where)] = np.asarray(d.vector, dtype=float)
        norm = np.linalg.norm(vector)
        if norm > 0:
            directions.append(Direction(vector / norm, units, float(getattr(d, "scale", 1.0) or 1.0),
                                        str(getattr(d, "test", "") or "")))
    shift, sds = _prior(directions, muscle, stated, prior, where)
    key = segment.pam_file if segment.pam_file is not None else id(pam)
    return MuscleUncertainty(muscle.parameter_vector(), fit, tolerance, error, tuple(directions),
                             shift, sds, key, unit, None if dof is None else int(dof))


def _prior(directions, muscle: Muscle, stated: np.ndarray, prior, where: str):
    """(mean, sd) of t along each undetermined direction v [scaled units], from the prior and the data.

    In scaled coordinates q, the prior (the stated geometry sds, plus ``prior``'s covariance and moduli)
    has precision Λ = Σ_q⁺ (an entry without variance carries no information), so along v its precision
    is λ = vᵀΛv and its mean m = vᵀΛ(q_prior − q̂)/λ. The data leave v open over its ``scale`` s, so
    t ~ N(m·λ/(λ + s⁻²), 1/(λ + s⁻²)). λ = 0 (no prior on v): sd 0, the direction stays unresolved.
    """
    if not directions:
        return (), ()
    structure = muscle.structure
    cov = np.diag(stated**2)
    base = muscle.parameter_vector()
    mean = base.copy()
    if prior is not None:
        cov = cov + _covariance(prior, structure, f"--prior-from {where}")
        if prior.moduli is not None:
            other = Muscle.from_pam(prior)
            if other.structure != structure:
                raise InputError(f"--prior-from: the PAM '{prior.name}' has moduli of another structure "
                                 f"({other.structure}) than the planned muscle ({structure}).")
            mean[5:] = other.parameter_vector()[5:]  # its moduli; the geometry stays the stated one
    units = directions[0].units
    precision = np.linalg.pinv(cov / np.outer(units, units), rcond=1e-12, hermitian=True)
    shift, sds = [], []
    for d in directions:
        weight = float(d.vector @ precision @ d.vector)
        if weight <= 1e-12:
            shift.append(0.0)
            sds.append(0.0)
            continue
        total = weight + d.scale**-2
        shift.append(float(d.vector @ precision @ ((mean - base) / units)) / total)
        sds.append(float(total**-0.5))
    return tuple(shift), tuple(sds)


def _gaussian(rng, cov: np.ndarray, n: int) -> np.ndarray:
    """(n, size) zero-mean draws of a (possibly singular) covariance, through the eigen-decomposition of
    its correlation matrix on the entries with a variance: entries in Pa² and in rad² differ by 10²⁰, and
    an eigen-decomposition of the raw matrix would leak its round-off (~1 Pa, i.e. ~1 m or 1 rad) into
    entries of zero variance."""
    out = np.zeros((n, cov.shape[0]))
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    live = np.flatnonzero(sd > 0)
    if live.size == 0:
        return out
    s = sd[live]
    values, vectors = np.linalg.eigh(cov[np.ix_(live, live)] / np.outer(s, s))
    root = vectors * np.sqrt(np.clip(values, 0.0, None))
    out[:, live] = (rng.standard_normal((n, live.size)) @ root.T) * s
    return out


def draw_muscles(muscles: list[MuscleUncertainty], n: int, seed: int, kappa_sd: float) -> MuscleDraws:
    """``n`` joint draws of the muscles' sources (one stream seeded by ``seed``, in segment order) and of κ
    (its own keyed stream): equal seeds give equal draws, in any process. The tested segments of one PAM
    file are one muscle: they take the first one's draws (prior, model error; no lot spread)."""
    rng = np.random.default_rng(seed)
    fits, params = {}, {"moduli": [], "geometry": [], "prior": []}
    errors = []
    tested: dict = {}  # fit key → the first tested segment of that PAM file
    for i, m in enumerate(muscles):
        if m.fit_key not in fits:
            fits[m.fit_key] = _gaussian(rng, m.fit, n)
        params["moduli"].append(fits[m.fit_key])
        params["geometry"].append(rng.standard_normal((n, m.tolerance.size)) * m.tolerance)
        prior = np.zeros((n, m.nominal.size))
        for d, shift, sd in zip(m.undetermined, m.prior_shift, m.prior_sd, strict=True):
            prior += np.outer(shift + sd * rng.standard_normal(n), d.step)
        params["prior"].append(prior)
        errors.append(rng.standard_normal(n) * m.model_error * chi_scale(seed, i, m.model_error_dof, n))
        if m.unit == "tested":  # the stream is drawn as for any segment: the others' draws do not move
            first = tested.setdefault(m.fit_key, i)
            for key in params:
                params[key][i] = params[key][first]
            errors[i] = errors[first]
    kappa = keyed_normal(seed, "kappa", (), n) * kappa_sd if kappa_sd > 0 else np.zeros(n)
    return MuscleDraws(n, params, errors, kappa)


#: Stream tags of the keyed draws (a stream is the seed, a tag and the statement's numbers).
_TAGS = {"bore": 1, "friction": 2, "kappa": 3, "tether": 4, "model_error": 5}


def chi_scale(seed: int, segment: int, dof: int | None, n: int) -> np.ndarray:
    """(n,) factors 1/√(W/ν), W ~ χ²_ν, that turn segment ``segment``'s normal model-error draws z into
    Student-t draws z/√(W/ν) ~ t_ν (``dof`` = ν); ones without ``dof``. Their own stream, keyed by the seed
    and the segment, so that the normal draws, and every other source's, do not move with ν."""
    if dof is None:
        return np.ones(n)
    sequence = np.random.SeedSequence(seed, spawn_key=(_TAGS["model_error"], segment))
    return np.sqrt(dof / np.random.default_rng(sequence).chisquare(dof, n))


def keyed_normal(seed: int, tag: str, statement, n: int) -> np.ndarray:
    """(n,) standard normal draws (read-only) of the stream keyed by ``seed``, the source ``tag`` and the
    numbers of the ``statement`` it is drawn for (a bore's range and sd, a friction's value and sd): every
    section that states the same bore (friction) gets the same draw, in whichever chunk or process it is
    sampled. The last few streams are kept (a route states few bores and frictions)."""
    return _keyed(seed, tag, tuple(float(x) for x in statement), n)


@functools.lru_cache(maxsize=64)
def _keyed(seed: int, tag: str, statement: tuple[float, ...], n: int) -> np.ndarray:
    words = np.asarray(statement, dtype="<f8").view("<u4").tolist()
    sequence = np.random.SeedSequence(seed, spawn_key=(_TAGS[tag], *words))
    out = np.random.default_rng(sequence).standard_normal(n)
    out.flags.writeable = False
    return out


def muscle_sources(draws: MuscleDraws) -> list[str]:
    """The muscle-wide sources with a non-zero spread, in :data:`SOURCES` order."""
    active = [k for k in ("moduli", "geometry", "prior") if any(np.any(b) for b in draws.params[k])]
    active += ["model_error"] if any(np.any(e) for e in draws.model_error) else []
    return active + (["kappa"] if np.any(draws.kappa) else [])
