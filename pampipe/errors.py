"""Exception hierarchy. The library raises these; only ``cli`` maps them to exit codes.

* :class:`InputError` (exit 2): a user mistake: unreadable file, schema, unit or CSV error,
  or a value outside the physical domain of the model.
* :class:`InfeasibleError` (exit 3): the inputs are valid but no solution exists.
* :class:`SolverError` (exit 3): a numerical solver failed; carries the solver status.
"""

from __future__ import annotations


class PampipeError(Exception):
    """Base class of every error pampipe raises on purpose."""

    exit_code = 1


class InputError(PampipeError, ValueError):
    """Bad input: the message names the file, key or line, the value and what is allowed."""

    exit_code = 2


class InfeasibleError(PampipeError):
    """Valid input, but the problem has no solution (the reasons are in the message)."""

    exit_code = 3


class SolverError(PampipeError, RuntimeError):
    """A solver failed; ``status`` is the solver's own status word (e.g. IPOPT's)."""

    exit_code = 3

    def __init__(self, message: str, status: str = "unknown") -> None:
        super().__init__(message)
        self.status = status


class StreamError(PampipeError):
    """stdout or stderr cannot be written (a full disk, a closed stream, a broken pipe): exit 2.

    ``stream`` is "stdout" or "stderr"; the environment is at fault, not the input or the solver.
    """

    exit_code = 2

    def __init__(self, message: str, stream: str) -> None:
        super().__init__(message)
        self.stream = stream
