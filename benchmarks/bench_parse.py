"""Benchmark of reading big missions: 10⁴ and 10⁵ route sections (issue 14, item 6).

Each reader runs twice in a fresh process on the same file: once for its time (imports excluded) and
its peak resident size, once under tracemalloc for its peak of Python allocations (tracemalloc slows
the run several times, so it is not timed):

* ``pampipe``: :func:`pampipe.io.mission_schema.load_mission`: YAML 1.2 core, units, schema, SI objects;
* ``yaml.safe_load``: PyYAML's pure-Python safe loader, the baseline (parsing only, no units);
* ``yaml CSafeLoader``: PyYAML with libyaml, the strongest plain reader (parsing only, YAML 1.1).

Goal: pampipe under 10 s at 10⁵ sections, memory linear in the sections.

    .venv/bin/python benchmarks/bench_parse.py [--sizes 10000 100000]
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
READERS = ("pampipe", "yaml.safe_load", "yaml CSafeLoader")


def write_mission(folder: Path, sections: int) -> Path:
    """The demo robot on a route of ``sections`` sections with varied lengths, bores and inclines."""
    shutil.copytree(ROOT / "problems" / "pams", folder / "pams", dirs_exist_ok=True)
    head = (ROOT / "problems" / "missions" / "vertical-climb-3in.yaml").read_text().split("route:")[0]
    bores = ("3 in", "3.5 in", "80 mm")
    path = folder / f"mission-{sections}.yaml"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(head.replace("../pams", "pams") + "route:\n")
        for i in range(sections):
            handle.write(f"  - {{name: s{i}, length: {1 + i % 7} m, inner_diameter: {bores[i % 3]}, "
                         f"incline: {i % 90} deg, friction: 0.3}}\n")
    return path


def child(reader: str, path: str, trace: bool) -> None:
    """Read ``path`` with ``reader`` in this process; print {seconds, traced_MB, rss_MB} as JSON."""
    import resource
    import time
    import tracemalloc

    import yaml

    from pampipe.io.mission_schema import load_mission

    text_readers = {"yaml.safe_load": yaml.safe_load,
                    "yaml CSafeLoader": lambda text: yaml.load(text, Loader=yaml.CSafeLoader)}
    if trace:
        tracemalloc.start()
    started = time.perf_counter()
    if reader == "pampipe":
        count = len(load_mission(path).route)
    else:
        count = len(text_readers[reader](Path(path).read_text())["route"])
    seconds = time.perf_counter() - started
    traced = tracemalloc.get_traced_memory()[1] if trace else 0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: kB
    print(json.dumps({"seconds": seconds, "traced_MB": traced / 1e6, "rss_MB": rss / 1e6, "sections": count}))


def measure(reader: str, path: Path) -> dict:
    """Time and peak RSS from a plain run, the traced peak from a second run under tracemalloc."""
    runs = [json.loads(subprocess.run([sys.executable, __file__, "--child", reader, str(path), *flag],
                                      capture_output=True, text=True, check=True, cwd=ROOT).stdout)
            for flag in ([], ["--trace"])]
    return {**runs[0], "traced_MB": runs[1]["traced_MB"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    parser.add_argument("--child", nargs=2, metavar=("READER", "PATH"), help=argparse.SUPPRESS)
    parser.add_argument("--trace", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(*args.child, trace=args.trace)
        return
    print(f"{'sections':>9}  {'reader':<18}{'time [s]':>10}{'x safe_load':>13}{'traced peak [MB]':>18}"
          f"{'peak RSS [MB]':>15}{'kB/section':>12}")
    with tempfile.TemporaryDirectory() as tmp:
        for sections in args.sizes:
            path = write_mission(Path(tmp), sections)
            rows = {reader: measure(reader, path) for reader in READERS}
            base = rows["yaml.safe_load"]["seconds"]
            for reader, r in rows.items():
                assert r["sections"] == sections
                print(f"{sections:>9}  {reader:<18}{r['seconds']:>10.2f}{r['seconds'] / base:>13.3f}"
                      f"{r['traced_MB']:>18.1f}{r['rss_MB']:>15.1f}{r['traced_MB'] * 1e3 / sections:>12.2f}")


if __name__ == "__main__":
    main()
