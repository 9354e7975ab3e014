"""The text of `pampipe synth`: the experiment written, its noise, and how to fit it."""

from __future__ import annotations


def synth_text(document: dict) -> str:
    """What `synth` prints, from its JSON ``document``."""
    return (f"wrote {document['experiment']} (seed {document['seed']}, force noise "
            f"{document['force_noise_N']:g} N, pressure noise {document['pressure_noise_Pa'] / 1e3:g} kPa); "
            f"fit it with\n  pampipe identify {document['experiment']} -o fitted-pam.yaml")
