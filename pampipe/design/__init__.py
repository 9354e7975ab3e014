"""`pampipe design`: choose the muscle geometry for a pipe inventory (docs/commands.md §8).

The rest length, rest diameter and braid angle are the decision variables of an NLP built once
from the symbolic :class:`~pampipe.model.muscle.Muscle` (:mod:`pampipe.design.design_nlp`); the bladder
material is fixed. It is solved from a Latin hypercube of starts on any executor
(:mod:`pampipe.runtime.executors`), and with ``design.sizes: K`` up to K muscles are chosen to serve the most
pipe length (:mod:`pampipe.design.sizes`). Library API::

    import pampipe
    result = pampipe.design_inventory("inventory.yaml", sizes=2)  # -> DesignResult (pampipe.api)
    result.sizes[0].pam, result.to_dict()["objective"]            # SI units

    from pampipe.design import solve_inventory                    # on a loaded Inventory and an executor
    result = solve_inventory(pampipe.load_inventory("inventory.yaml"), pool=None)
"""

from pampipe.design.result import DesignResult, SizeResult
from pampipe.design.workflow import solve_inventory

__all__ = ["DesignResult", "SizeResult", "solve_inventory"]
