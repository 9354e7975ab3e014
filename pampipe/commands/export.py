"""`pampipe export`: the mission's anchoring law and gait schedule as C (docs/commands.md §9)."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from pampipe.commands.common import add_confidence_options, add_output_options, add_units_option, emit
from pampipe.errors import InputError
from pampipe.io.files import atomic_write_set, check_not_input
from pampipe.runtime.progress import note

NAME = "export"
HELP = ("write the mission's anchoring law and gait schedule as plain C99 (pampipe_plan.h/.c) and an "
        "Arduino example sketch")

EPILOG = """\
DIR receives pampipe_plan.h, pampipe_plan.c and DIR_NAME.ino (pampipe_example.ino when the folder's name
is not a valid Arduino sketch name), so DIR opens as a sketch in the Arduino IDE. The function

  int pampipe_required_pressure(inner_diameter_m, incline_rad, friction, payload_kg, pressure_Pa[])

gives the numbers `pampipe plan` gives for any section, or a reason code; compile with -DPAMPIPE_REAL_FLOAT
for float. Effects of a diagnosed PAM are exported when the closed form carries them, else refused (exit 2).

examples:
  pampipe export problems/missions/vertical-climb-3in.yaml -o firmware
  gcc -std=c99 -c firmware/pampipe_plan.c

exit codes: 0 written; 2 bad input, an effect without a closed form, or outputs that exist (use --force)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4)")
    parser.add_argument("-o", "--output", type=Path, metavar="DIR", required=True,
                        help="folder to write the files into (created if missing)")
    parser.add_argument("--force", action="store_true", help="overwrite output files that already exist")
    add_confidence_options(parser, confidence="export a law that plans at confidence C: each segment's "
                           "pressure gains the margin `pampipe plan --confidence C` needs over the mission's "
                           "sections, stated in the header",
                           samples="draws of the uncertain inputs for --confidence (default 4000, as "
                           "`plan`); N(1 - C) must be at least 10", seed=None)
    add_output_options(parser, plots=False)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe.api import export_mission, load_mission
    from pampipe.export import DEFAULT_SKETCH, HEADER, SOURCE, is_sketch_name
    from pampipe.views.export_text import written_text

    if args.samples is not None and args.confidence is None:
        raise InputError("--samples only applies with --confidence C.")
    mission = load_mission(args.mission)
    inputs = list(dict.fromkeys(Path(p) for p in mission.input_files))
    folder = args.output
    if os.path.lexists(folder) and not folder.is_dir():
        raise InputError(f"-o {folder}: exists and is not a folder; give a folder for the C files.")
    sketch = folder.resolve().name if is_sketch_name(folder.resolve().name) else DEFAULT_SKETCH
    targets = [folder / name for name in (HEADER, SOURCE, f"{sketch}.ino")]
    for target in targets:
        check_not_input(target, inputs, option="-o")
    existing = [str(t) for t in targets if t.exists()]
    if existing and not args.force:
        raise InputError(f"-o {folder}: {', '.join(existing)} already exist(s); pass --force to overwrite, "
                         "or choose another folder.")
    export = export_mission(mission, sketch_name=sketch, confidence=args.confidence,
                            samples=args.samples, progress=note)  # quiet under --json and --quiet
    atomic_write_set(folder, export.files)  # the old set or the new one, never a mix
    emit(args, export.to_dict(), written_text(export, folder))
    return 0
