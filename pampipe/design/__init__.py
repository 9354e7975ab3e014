"""`pampipe design`: choose the muscle geometry for a pipe inventory (docs/commands.md §7.7).

The rest length, rest diameter and braid angle are the decision variables of an NLP built once
from the symbolic :class:`~pampipe.model.muscle.Muscle` (:mod:`pampipe.design.nlp`); the bladder
material is fixed. It is solved from a Latin hypercube of starts on any executor
(:mod:`pampipe.parallel`), and with ``design.sizes: K`` up to K muscles are chosen to serve the most
pipe length (:mod:`pampipe.design.sizes`). Library API::

    from pampipe.io.inventory import load_inventory
    from pampipe.design import design_inventory

    result = design_inventory(load_inventory("inventory.yaml"))   # -> DesignResult
    result.sizes[0].pam, result.as_document()["objective"]        # SI units
"""

from pampipe.design.result import DesignResult, SizeResult
from pampipe.design.workflow import design_inventory

__all__ = ["DesignResult", "SizeResult", "design_inventory"]
