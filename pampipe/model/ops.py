"""Elementary functions that dispatch on the argument: numpy for numbers and arrays, CasADi for symbols.

This lets one model source serve floats, whole numpy arrays (fast vectorized evaluation) and
CasADi SX/MX graphs (exact derivatives inside NLPs). CasADi is never imported here: an argument can
only be a CasADi symbol once the caller has imported CasADi, so numeric work (``pampipe plan``'s
closed form) runs without loading it.
"""

from __future__ import annotations

import sys

import numpy as np


def is_symbolic(*args) -> bool:
    """True when any argument is a CasADi SX, MX or DM (False, without importing CasADi, when not loaded)."""
    ca = sys.modules.get("casadi")
    return ca is not None and any(isinstance(a, (ca.SX, ca.MX, ca.DM)) for a in args)


def _pick(numeric, symbolic: str):
    def op(*args):
        if is_symbolic(*args):
            return getattr(sys.modules["casadi"], symbolic)(*args)
        return numeric(*args)

    op.__name__ = numeric.__name__
    return op


sqrt = _pick(np.sqrt, "sqrt")
cos = _pick(np.cos, "cos")
tan = _pick(np.tan, "tan")
arccos = _pick(np.arccos, "acos")
exp = _pick(np.exp, "exp")
log1p = _pick(np.log1p, "log1p")
fmax = _pick(np.maximum, "fmax")
fmin = _pick(np.minimum, "fmin")
sin = _pick(np.sin, "sin")
fabs = _pick(np.abs, "fabs")


def softplus(x):
    """log(1 + eˣ), written as max(x, 0) + log1p(e^−|x|) so that it never overflows."""
    return fmax(x, 0) + log1p(exp(-fabs(x)))


def if_else(condition, then, otherwise):
    """``then`` where ``condition`` holds, else ``otherwise`` (np.where / casadi.if_else)."""
    if is_symbolic(condition, then, otherwise):
        return sys.modules["casadi"].if_else(condition, then, otherwise)
    return np.where(condition, then, otherwise)


logical_and = _pick(np.logical_and, "logic_and")
logical_or = _pick(np.logical_or, "logic_or")


def column(entries, *, like):
    """A column of ``entries`` of the same kind as ``like``: casadi.vertcat when an entry or ``like`` is an
    SX or MX symbol (CasADi is loaded then), else a numpy array of floats."""
    ca = sys.modules.get("casadi")
    if ca is not None and any(isinstance(e, ca.SX | ca.MX) for e in (*entries, like)):
        return ca.vertcat(*entries)
    return np.array([float(e) for e in entries])
