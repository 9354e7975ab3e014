"""pampipe: pressures for pneumatic-muscle pipe crawlers, from a symbolic CasADi model of the muscle.

The Python API (:mod:`pampipe.api`, docs/commands.md §11.1) — each command as a function that takes
a file path or a dict and unit strings, and returns a result with ``.to_dict()``::

    import pampipe
    plan = pampipe.plan("mission.yaml", payload="3 kg")

Also: :class:`Muscle` (the one door to the model), ``load_pam``, ``load_mission``,
``load_experiment``. Names are imported on first use, so ``import pampipe`` stays light.
"""

from pampipe._version import __version__

_API = ("simulate", "identify", "plan", "gait", "diagnose", "design_inventory", "export_mission", "load_pam",
        "load_mission", "load_experiment", "load_inventory", "extension", "save_pam", "route", "synth",
        "example", "set_units", "rehearse", "next_test")
__all__ = [*_API, "Muscle", "__version__"]


def __getattr__(name: str):
    if name in _API:
        from pampipe import api

        return getattr(api, name)
    if name == "Muscle":
        from pampipe.model.muscle import Muscle

        return Muscle
    raise AttributeError(f"module 'pampipe' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
