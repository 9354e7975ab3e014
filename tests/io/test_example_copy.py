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
    schemas = [str(tmp_path / "yaml" / f"{kind}.schema.json") for kind in ("mission", "pam")]
    assert sorted(second.to_dict()["unchanged"]) == sorted([pam, *schemas])
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


@pytest.mark.parametrize("name", ["vertical-climb-3in", "paper-protocol", "riser", "paper-radial-pam"])
def test_copied_files_name_a_schema_that_is_there(tmp_path, name):
    """Issue 42: the bundled files' `$schema=../../yaml/...` pointed outside the folder copied into. The
    schemas they name are copied into DIR/yaml/ and each line points there; the rest of each file is the
    bundled bytes, and the copy validates against the schema its line names (jsonschema)."""
    import json
    import re

    import jsonschema

    from pampipe.io import bundled
    from pampipe.io.yamlfile import load_mapping
    from tests.support.problems import PROBLEMS, ROOT

    files = [tmp_path / f for f in api.example(name, tmp_path / "copy").to_dict()["files"]]
    copied = [f for f in files if f.suffix == ".yaml"]
    assert copied
    for path in copied:
        first, rest = path.read_bytes().split(b"\n", 1)
        found = re.fullmatch(rb"# yaml-language-server: \$schema=(\S+)", first)
        assert found, first
        schema = (path.parent / found.group(1).decode()).resolve()
        assert schema.parent == (tmp_path / "copy" / "yaml").resolve()
        assert schema in [f.resolve() for f in files]
        assert schema.read_bytes() == (ROOT / "yaml" / schema.name).read_bytes()
        source = PROBLEMS / path.relative_to(tmp_path / "copy")
        assert rest == source.read_bytes().split(b"\n", 1)[1]
        validator = jsonschema.Draft202012Validator(json.loads(schema.read_text()))
        assert list(validator.iter_errors(load_mapping(path))) == []
    assert bundled.schemas().samefile(ROOT / "yaml")  # a checkout reads yaml/ itself
