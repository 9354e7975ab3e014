"""Every command's ``--json --reproducible`` output on the bundled problems, written to one folder.

Run it before and after a change that must not change behaviour (a regrouping, a rename), then compare:

    python scripts/snapshot_outputs.py /tmp/before      # on the old tree
    python scripts/snapshot_outputs.py /tmp/after       # on the new tree
    diff -r /tmp/before /tmp/after && echo identical

Each output is ``<command>-<problem>.json`` (stdout) plus ``.rc`` (the exit code); ``export`` writes its C
files
beside it as ``<name>.<file>``. Wall-clock entries are 0 under ``--reproducible``, so the files compare to
the byte.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROBLEMS = ROOT / "problems"
MISSIONS, EXPERIMENTS, INVENTORIES, PAMS = (
    sorted(p.relative_to(ROOT) for p in (PROBLEMS / kind).glob("*.yaml"))
    for kind in ("missions", "experiments", "inventories", "pams"))


def runs() -> list[tuple[str, list[str]]]:
    """(name, pampipe arguments) of every output compared."""
    out = []
    for m in MISSIONS:
        out.append((f"plan-{m.stem}", ["plan", str(m), "--json", "--max-payload"]))
        out.append((f"gait-{m.stem}", ["gait", str(m), "--json"]))
        out.append((f"export-{m.stem}", ["export", str(m), "-o", "{dir}"]))
    for name in ("riser-uncertain-friction", "steel-pipe-sizes"):
        out.append((f"plan-confidence-{name}",
                    ["plan", f"problems/missions/{name}.yaml", "--json", "--confidence", "0.9"]))
    out.append(("gait-optimal-vertical-climb-3in",
                ["gait", "problems/missions/vertical-climb-3in.yaml", "--json", "--optimal"]))
    for e in EXPERIMENTS:
        out.append((f"identify-{e.stem}", ["identify", str(e), "--json"]))
        out.append((f"diagnose-{e.stem}", ["diagnose", str(e), "--json"]))
    for inv in INVENTORIES:
        out.append((f"design-{inv.stem}", ["design", str(inv), "--json", "--starts", "4"]))
    for p in PAMS:
        out.append((f"simulate-{p.stem}", ["simulate", str(p), "-d", "3 in", "-d", "3.5 in",
                                           "-f", "0 N", "-f", "1024.74 N", "--json"]))
    out.append(("route-ky4", ["route", "ky4", "--from", "J-315", "--to", "J-897", "--json"]))
    return out


def main(folder: str, only: str = "") -> int:
    target = Path(folder)
    target.mkdir(parents=True, exist_ok=True)
    for name, args in runs():
        if only and only not in name:
            continue
        with tempfile.TemporaryDirectory() as work:
            args = [a.replace("{dir}", str(Path(work) / "c")) for a in args]
            done = subprocess.run([sys.executable, "-m", "pampipe", *args, "--reproducible"],
                                  capture_output=True, cwd=ROOT, timeout=1800)
            if (Path(work) / "c").is_dir():  # export: the C files, not the temporary path
                for f in sorted((Path(work) / "c").iterdir()):
                    (target / f"{name}.{f.name}").write_bytes(f.read_bytes())
        (target / f"{name}.json").write_bytes(done.stdout.replace(work.encode(), b"{tmp}"))
        (target / f"{name}.rc").write_text(f"{done.returncode}\n")
        print(f"{name}: exit {done.returncode}, {len(done.stdout)} bytes", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
