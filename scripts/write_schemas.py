"""Write yaml/<file>.schema.json, the JSON Schemas of the files a user writes, from the pydantic models the
commands validate them with (docs/formats.md §5).

    python scripts/write_schemas.py           # write the schemas
    python scripts/write_schemas.py --check   # exit 1 if a schema in yaml/ is not what the models give

Each schema holds two forms of its file: values with units (a bare number only for a dimensionless value or
0), and, when the file says ``units: SI`` at its top, bare numbers as SI. An editor that reads the schema
(``# yaml-language-server: $schema=../../yaml/mission.schema.json`` on a file's first line) completes keys,
flags a misspelt one and a value without its unit while the file is written. Blocks validated by their
command (a mission's ``gait:``, an experiment's ``fit:``) are filled in from their own models.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from pampipe.identification.fit_schema import FitBlock  # noqa: E402
from pampipe.io.experiment_schema import ExperimentSchema  # noqa: E402
from pampipe.io.file_units import KEY, SI  # noqa: E402
from pampipe.io.inventory_file import InventorySchema  # noqa: E402
from pampipe.io.menu_file import MenuSchema  # noqa: E402
from pampipe.io.mission_model import MissionSchema  # noqa: E402
from pampipe.io.pam_model import PamSchema  # noqa: E402
from pampipe.pneumatics.options import GaitSchema  # noqa: E402
from pampipe.specs.schema import bare_si_schema  # noqa: E402

FOLDER = ROOT / "yaml"
#: file name → (model, what the file is, blocks {key: model} validated by a command and filled in).
FILES = {
    "mission": (MissionSchema, "a mission file (docs/formats.md §4)", {"gait": GaitSchema}),
    "pam": (PamSchema, "a PAM file (docs/formats.md §2)", {}),
    "experiment": (ExperimentSchema, "an experiment file (docs/formats.md §3)",
                   {"fit": FitBlock.model_fields["fit"].annotation}),
    "inventory": (InventorySchema, "an inventory file (docs/commands.md §8)", {}),
    "menu": (MenuSchema, "a MENU file of next-test (docs/commands.md §14)", {}),
}


def _form(model, blocks: dict, si: bool) -> tuple[dict, dict]:
    """(top-level schema, its $defs) of ``model`` with quantities in units or, with ``si``, bare SI; the
    definitions of the SI form are named ``SI.<name>``."""
    prefix = "SI." if si else ""
    with bare_si_schema(si):
        schema = model.model_json_schema(ref_template=f"#/$defs/{prefix}{{model}}")
        defs = {f"{prefix}{name}": body for name, body in schema.pop("$defs", {}).items()}
        for key, block in blocks.items():
            sub = block.model_json_schema(ref_template=f"#/$defs/{prefix}{{model}}")
            defs.update({f"{prefix}{name}": body for name, body in sub.pop("$defs", {}).items()})
            defs[f"{prefix}{block.__name__}"] = sub
            schema["properties"][key] = {"$ref": f"#/$defs/{prefix}{block.__name__}"}
    if si:
        schema["properties"] = {KEY: {"const": SI, "description": "bare numbers in this file are SI: m, Pa, "
                                      "N, kg, s, K (angles still carry their unit)"}, **schema["properties"]}
        schema["required"] = [KEY, *schema.get("required", [])]
    return schema, defs


def schema_of(name: str) -> dict:
    """The JSON Schema (draft 2020-12) of the file ``name`` (a key of :data:`FILES`)."""
    model, what, blocks = FILES[name]
    units, defs = _form(model, blocks, si=False)
    si, si_defs = _form(model, blocks, si=True)
    title = units.pop("title")
    si.pop("title")
    return {"$schema": "https://json-schema.org/draft/2020-12/schema",
            "$id": f"https://pampipe.invalid/yaml/{name}.schema.json", "title": f"pampipe {name} file",
            "description": f"{what}; generated from pampipe's {title} by scripts/write_schemas.py. "
                           f"Values carry their units ('689 kPa', '3 in'), unless the file says "
                           f"'{KEY}: {SI}' "
                           "at its top.",
            "type": "object", "if": {"required": [KEY]},
            "then": {"$ref": f"#/$defs/SI.{title}"}, "else": {"$ref": f"#/$defs/{title}"},
            "$defs": {title: units, f"SI.{title}": si, **defs, **si_defs}}


def text_of(name: str) -> str:
    return json.dumps(schema_of(name), indent=1, ensure_ascii=False, sort_keys=False) + "\n"


def main(argv: list[str]) -> int:
    check = argv == ["--check"]
    stale = []
    for name in FILES:
        path = FOLDER / f"{name}.schema.json"
        text = text_of(name)
        if check:
            if not path.is_file() or path.read_text(encoding="utf-8") != text:
                stale.append(path.relative_to(ROOT).as_posix())
        else:
            FOLDER.mkdir(exist_ok=True)
            path.write_text(text, encoding="utf-8")
            print(f"wrote {path.relative_to(ROOT)}")
    if stale:
        print(f"stale: {', '.join(stale)}; run python scripts/write_schemas.py", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
