"""The one line a lab user reads first of an ``identify`` fit (issue 42): how well it fits, how much the
model misses, and which predictions the data determine.

    fit: RMSE 2.00 N = 0.013 % of full scale 15135 N, at the noise floor 1.97 N (1.2 x); model error 0.489 N;
    determined: axial force at the tested points, in the tested ranges, above them (to 1.25 x); anchoring in
    76.2 mm, 88.9 mm / undetermined: none of these (4 of 16 coefficient combinations)

*Full scale* is the largest |force| measured in any test [N]; the RMSE is the fit's over every fitted row.
The noise floor is the tests' pooled model-free floor σ_n [N] (:mod:`.quality`, :mod:`.model_error`) and
the ratio the worst test's RMSE / floor: *at* the floor up to :data:`AT_FLOOR`, *near* it up to the warning
threshold :data:`pampipe.identification.quality.WARN_RATIO`, *ABOVE* it beyond. A prediction is determined
as :mod:`.envelope` judges it. The line is metric (N, mm); the text report localises it to ``--units``.
"""

from __future__ import annotations

from pampipe.identification.quality import WARN_RATIO

#: RMSE / noise floor up to which the fit is "at the noise floor".
AT_FLOOR = 1.5
#: Short names of the axial-force regions of :func:`pampipe.identification.envelope._regions`, by prefix.
SHORT = (("at the tested", "at the tested points"), ("in the tested ranges", "in the tested ranges"),
         ("above the tested pressures", "above them"))


def fit_verdict(result) -> str:
    """The verdict line of an :class:`~pampipe.identification.result.IdentifyResult` (module docstring)."""
    solver = "" if result.success else f"IPOPT {result.status}, NOT converged; "
    parts = [f"fit: {solver}{_accuracy(result)}"]
    if result.model_error is not None:
        parts.append(f"model error {_n(result.model_error.value)} N")
    parts.append(_determined(result))
    return "; ".join(parts)


def _accuracy(result) -> str:
    """'RMSE 2.00 N = 0.013 % of full scale 15135 N, at the noise floor 1.97 N (1.2 x)'."""
    q = result.quality
    text = f"RMSE {_n(result.rmse)} N"
    scale = max((t.scale for t in q.tests), default=0.0) if q is not None else 0.0
    if scale > 0:
        text += f" = {100 * result.rmse / scale:.2g} % of full scale {_n(scale)} N"
    ratio = None if q is None else q.rmse_over_floor
    if ratio is None:
        return text + ", noise floor unknown"
    floor = result.model_error.noise_floor if result.model_error is not None else q.noise_floor
    where = "at" if ratio <= AT_FLOOR else "near" if ratio <= WARN_RATIO else "ABOVE"
    structured = ", residuals STRUCTURED" if q.structured else ""
    return f"{text}, {where} the noise floor {_n(floor)} N ({ratio:.2g} x){structured}"


def _determined(result) -> str:
    """'determined: axial force ...; anchoring in ... / undetermined: ...' from the fit's predictions."""
    p = result.predictions
    known = [_short(r.name) for r in p.regions if r.determined]
    unknown = [_short(r.name) for r in p.regions if not r.determined]
    said, left = [], []
    if known:
        said.append("axial force " + ", ".join(known))
    if unknown:
        left.append("axial force " + ", ".join(unknown))
    bores = [(f"{q.pipe_diameter * 1e3:.4g} mm", q.determined) for q in p.pipes]
    if any(ok for _, ok in bores):
        said.append("anchoring in " + ", ".join(b for b, ok in bores if ok))
    if not all(ok for _, ok in bores):
        left.append("anchoring in " + ", ".join(b for b, ok in bores if not ok))
    u = result.uncertainty
    open_ = len(result.names) - u.rank
    combinations = f"{open_} of {len(result.names)} coefficient combinations"
    if not left:
        tail = f"none of these ({combinations})" if open_ else "nothing"
    else:
        tail = "; ".join(left) + (f" ({combinations})" if open_ else "")
    return f"determined: {'; '.join(said) or 'no prediction'} / undetermined: {tail}"


def _short(name: str) -> str:
    """A region's short name, its '(to 1.25 x)' kept: 'above them (to 1.25 x)'."""
    kept = name[name.index(" (to"):] if " (to" in name else ""
    return next((short + kept for prefix, short in SHORT if name.startswith(prefix)), name)


def _n(value: float) -> str:
    """A force to 3 significant digits, trailing zeros kept (2.00), whole above 1000 (1234)."""
    return f"{value:#.3g}".rstrip(".") if abs(value) < 1000 else f"{value:.0f}"
