"""Elementary functions that dispatch on the argument: numpy for numbers and arrays, CasADi for symbols.

This lets one model source serve floats, whole numpy arrays (fast vectorized evaluation) and
CasADi SX/MX graphs (exact derivatives inside NLPs).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

_SYMBOLIC = (ca.SX, ca.MX, ca.DM)


def _pick(numeric, symbolic):
    def op(*args):
        if any(isinstance(a, _SYMBOLIC) for a in args):
            return symbolic(*args)
        return numeric(*args)

    op.__name__ = numeric.__name__
    return op


sqrt = _pick(np.sqrt, ca.sqrt)
cos = _pick(np.cos, ca.cos)
tan = _pick(np.tan, ca.tan)
arccos = _pick(np.arccos, ca.acos)
exp = _pick(np.exp, ca.exp)
log1p = _pick(np.log1p, ca.log1p)
fmax = _pick(np.maximum, ca.fmax)
fmin = _pick(np.minimum, ca.fmin)
sin = _pick(np.sin, ca.sin)
fabs = _pick(np.abs, ca.fabs)


def softplus(x):
    """log(1 + eˣ), written as max(x, 0) + log1p(e^−|x|) so that it never overflows."""
    return fmax(x, 0) + log1p(exp(-fabs(x)))


def if_else(condition, then, otherwise):
    """``then`` where ``condition`` holds, else ``otherwise`` (np.where / casadi.if_else)."""
    if any(isinstance(a, _SYMBOLIC) for a in (condition, then, otherwise)):
        return ca.if_else(condition, then, otherwise)
    return np.where(condition, then, otherwise)


logical_and = _pick(np.logical_and, ca.logic_and)
logical_or = _pick(np.logical_or, ca.logic_or)
