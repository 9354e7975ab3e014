"""`identify` of an experiment with slip tests only: μ and κ from the stated PAM's moduli.

Without axial or radial tests there is nothing to fit the moduli to, so the experiment's ``pam:`` must carry
them (a PAM written by an earlier `identify`); the result has the same document as a full fit, with the
PAM's moduli, no fitted tests and the ``slip`` block.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pampipe.errors import InputError
from pampipe.identification.options import FitOptions
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.results import notebook
from pampipe.specs.experiment import ExperimentData

if TYPE_CHECKING:  # the slip package loads only for slip tests
    from pampipe.slip.result import SlipResult


def _plot():
    from pampipe.views.plots.slip_tests import plot_grip

    return plot_grip


def _text():
    from pampipe.views.identify_text import grip_text

    return grip_text


@notebook(headline=("success", "status"), plot=_plot, text=_text)
@dataclass(frozen=True)
class GripResult:
    """The outcome of `identify` on slip tests only: the stated muscle and :class:`SlipResult`."""

    pam: Pam
    options: FitOptions
    slip: SlipResult
    wall_time: float
    source: str

    success: bool = True
    status: str = "slip_only"

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.slip.warnings

    def fitted_pam(self, base: Pam) -> Pam:
        """``base`` (its moduli kept) with the measured ``contact:`` block."""
        return Pam(base.name, base.geometry, base.moduli, base.covariance, base.effects, self.slip.grip())

    def pam_comments(self, source) -> list[str]:
        return [f"Written by `pampipe identify` from {source}: the moduli are those of the stated PAM; "
                f"contact: from {len(self.slip.trials)} slip trials"]

    def to_dict(self) -> dict:
        return self.as_document()

    def as_document(self) -> dict:
        """The `identify --json` document: the stated moduli, no moduli fit, the ``slip`` block."""
        from pampipe.identification.result import moduli_document

        return {"moduli": moduli_document(self.pam.moduli),
                "moduli_source": "stated PAM (no axial or radial test)",
                "fit": {"tests": [], "sum_rmse_N": None, "points": 0},
                "solver": {"status": self.status, "success": True, "iterations": 0,
                           "wall_time_s": self.wall_time},
                "slip": self.slip.as_document(), "warnings": list(self.warnings), "experiment": self.source}


def identify_grip(data: ExperimentData, options: FitOptions) -> GripResult:
    """μ and κ of ``data``'s slip tests with the stated PAM's moduli (InputError if it has none)."""
    if not data.slip:
        raise InputError(f"{data.source}: the experiment has no tests to fit.")
    muscle = Muscle.from_pam(data.pam, where=f"{data.source}: pam (an experiment with slip tests only takes "
                                                "its moduli from the PAM)")
    from pampipe.slip.workflow import fit_slip

    started = time.perf_counter()
    slip = fit_slip(data.slip, muscle)
    return GripResult(data.pam, options, slip, time.perf_counter() - started, str(data.source))
