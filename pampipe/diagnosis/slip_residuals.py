"""`diagnose` on slip tests: is there structure in the slip residuals that μ would otherwise absorb?

The slip fit (:func:`pampipe.slip.fit_slip`) is made with the diagnosed muscle; its residual trend tests
(:mod:`pampipe.slip.trend`: against pressure and load rate) and its friction-law check (Coulomb against
μ₀(p/p_ref)^n) are the verdict: ``trend`` when any of them finds structure, else ``none``.
"""

from __future__ import annotations

from dataclasses import dataclass

from pampipe.model.muscle import Muscle
from pampipe.slip.result import SlipResult
from pampipe.slip.workflow import fit_slip


@dataclass(frozen=True)
class SlipDiagnosis:
    """The slip fit of a diagnosed muscle and what its residuals say."""

    slip: SlipResult

    @property
    def findings(self) -> list[str]:
        """Sentences naming each structure found (empty: the residuals are noise)."""
        out = [f"slip residuals trend with {t.against} (p = {t.p_value:.2g}, slope {t.slope:.3g} per unit)"
               for t in self.slip.trends if t.significant]
        law = self.slip.law
        if law is not None and law.supported == "pressure_dependent":
            out.append(f"friction depends on the contact pressure: mu = {law.friction_at_reference:.3g}"
                       f"*(p/{law.reference_pressure / 1e3:.4g} kPa)^{law.exponent:.3g} (delta BIC "
                       f"{law.delta_bic:.3g} against Coulomb)")
        return out

    @property
    def verdict(self) -> str:
        return "trend" if self.findings else "none"

    def as_document(self) -> dict:
        return {"verdict": self.verdict, "findings": self.findings,
                "residual_trends": [t.as_document() for t in self.slip.trends],
                "friction_law": None if self.slip.law is None else self.slip.law.as_document(),
                "friction": self.slip.as_document()["friction"],
                "load_coupling": self.slip.as_document()["load_coupling"],
                "trials": len(self.slip.trials)}

    def report(self) -> str:
        """The slip part of the diagnose report."""
        from pampipe.slip.trend import LEVEL

        lines = [f"\nSlip tests: {len(self.slip.trials)} trials; residual trend tests (flagged at p < "
                 f"{LEVEL / 2:g} each):"]
        lines += [f"  vs {t.against}: p = {t.p_value:.2g} ({'TREND' if t.significant else 'no trend'})"
                  for t in self.slip.trends] or ["  too few slipped trials to test"]
        if self.findings:
            lines.append("verdict: " + "; ".join(self.findings) + ". This is reported, not absorbed in mu: "
                         "test at the pressures and load rates of the mission, or model the dependence.")
        else:
            lines.append("verdict: the slip residuals show no trend with pressure or load rate, and Coulomb "
                         "friction is supported.")
        return "\n".join(lines)


def diagnose_slip(tests, pam) -> SlipDiagnosis:
    """:class:`SlipDiagnosis` of the slip tests with the muscle of ``pam`` (moduli required)."""
    return SlipDiagnosis(fit_slip(tests, Muscle.from_pam(pam)))
