"""What a simulated muscle's fit leaves open: the PAM's undetermined directions, for `simulate` to report.

A fit writes the directions its data do not determine under ``uncertainty.undetermined`` (docs/physics.md
§6); along them the fitted moduli are one value among many that fit as well, so a force simulated from them
rests on nothing the tests measured. ``plan --confidence`` covers them over their open width and stops a
segment where they matter (exit 3); ``simulate`` gives no probability, so it reports them: a warning naming
the directions and the tests that would close them, and in its JSON the ``undetermined`` list of identify's
``uncertainty.written`` (one document per direction: ``direction``, ``scale``, ``moves``, ``test``).
"""

from __future__ import annotations

import numpy as np

from pampipe.model.pam import Pam


def open_directions(pam: Pam) -> tuple[dict, ...]:
    """The PAM's undetermined directions as documents (:meth:`ParameterUncertainty.direction_document`)."""
    u = pam.uncertainty
    return () if u is None else tuple(u.direction_document(d) for d in u.undetermined)


def open_warning(pam: Pam, what: str) -> str | None:
    """One sentence naming the PAM's undetermined directions (each by its largest weight) and the tests that
    would determine them, or None when its data determine every direction; ``what``: the simulated
    quantities (``these forces``, ``these lengths``), which rest on the fitted values."""
    u = pam.uncertainty
    if u is None or not u.undetermined:
        return None
    mostly = [u.names[int(np.argmax(np.abs(d.vector)))] for d in u.undetermined]
    tests: dict[str, int] = {}
    for d in u.undetermined:
        key = d.test or "a test that moves them"
        tests[key] = tests.get(key, 0) + 1
    closing = "; ".join(f"{test} ({count} of them)" for test, count in tests.items())
    return (f"{pam.name}: its fit leaves {len(u.undetermined)} parameter direction(s) undetermined by its "
            f"data (uncertainty.undetermined, mostly {', '.join(mostly)}): {what} rest on fitted "
            f"values the tests do not fix along them. What would determine them: {closing}. "
            "`plan --confidence` covers them over their open width and stops where they matter.")
