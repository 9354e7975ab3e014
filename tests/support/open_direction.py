"""A PAM whose fit leaves hoop.a0 open over ±2 MPa (axial data only), and a demo mission that uses it: plan
stops there (exit 3) and next-test names the test that closes it (tests/nexttest)."""

from __future__ import annotations

import dataclasses

import numpy as np

from pampipe.io.pamfile import write_pam
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names
from tests.support.problems import PROBLEMS


def open_direction_files(tmp_path, radial_pam):
    """(the PAM, its file, the mission file) in ``tmp_path``."""
    vector = np.zeros(16)
    vector[8] = 1.0  # hoop.a0
    u = ParameterUncertainty(moduli_names(3), np.diag(np.r_[np.full(8, 0.05e6), np.zeros(8)] ** 2), 0.0,
                             (UndeterminedDirection(vector, 2.0, {}, "a radial test"),))
    pam = dataclasses.replace(radial_pam, name="axial-only").with_uncertainty(u)
    write_pam(tmp_path / "axial-only.yaml", pam)
    text = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text()
    (tmp_path / "mission.yaml").write_text(text.replace("../pams/paper-radial-pam.yaml", "axial-only.yaml"))
    return pam, tmp_path / "axial-only.yaml", tmp_path / "mission.yaml"
