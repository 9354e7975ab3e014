"""`pampipe example` into a folder that holds byte-identical files needs no --force (issue 42, item 8)."""

from __future__ import annotations

import pytest

from pampipe import api
from pampipe.errors import InputError


def test_a_second_example_sharing_a_pam_needs_no_force(tmp_path):
    first = api.example("vertical-climb-3in", tmp_path).to_dict()
    pam = str(tmp_path / "pams" / "paper-radial-pam.yaml")
    assert pam in first["files"] and first["unchanged"] == []
    second = api.example("elbows-3in", tmp_path)
    assert second.to_dict()["unchanged"] == [pam]
    assert f"unchanged (already there) {pam}" in second.render()
    again = api.example("vertical-climb-3in", tmp_path).to_dict()  # the same example twice: nothing to write
    assert sorted(again["unchanged"]) == sorted(again["files"])


def test_a_file_with_other_content_is_still_refused(tmp_path):
    api.example("vertical-climb-3in", tmp_path)
    pam = tmp_path / "pams" / "paper-radial-pam.yaml"
    pam.write_text(pam.read_text() + "# my edit\n")
    with pytest.raises(InputError, match="already exists"):
        api.example("elbows-3in", tmp_path)
    assert pam.read_text().endswith("# my edit\n")  # nothing replaced
    api.example("elbows-3in", tmp_path, force=True)
    assert not pam.read_text().endswith("# my edit\n")
