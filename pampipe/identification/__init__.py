"""Moduli identification (docs/physics.md §6): `identify(data, options) -> IdentifyResult`.

Modules: :mod:`.options` (the ``fit:`` block), :mod:`.statistics` (data → sufficient statistics),
:mod:`.fit_nlp` (the cached IPOPT problem), :mod:`.covariance`, :mod:`.predict` (model forces and
residuals for recorded rows), :mod:`.result` (frozen results), :mod:`.fit` (the orchestration).
"""

from pampipe.identification.fit import identify
from pampipe.identification.options import FitOptions, parse_fit_options
from pampipe.identification.predict import predict, residuals
from pampipe.identification.result import IdentifyResult

__all__ = ["FitOptions", "IdentifyResult", "identify", "parse_fit_options", "predict", "residuals"]
