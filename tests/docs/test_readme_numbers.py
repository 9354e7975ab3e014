"""Every performance figure in docs/performance.md (and README.md's summary of it) comes from a script in
benchmarks/ that still prints it (issues 25, 39).

A row of the performance tables names its script (`bench_x.py`) and quotes, in double quotes, the label
that script prints next to the figure; every paragraph of the section names a script and quotes a label
likewise. The check is that the script exists and that the quoted label is still in its source: the
README follows the scripts' current output format (the timing values themselves change run to run and
are not checked).
"""

from __future__ import annotations

import re

import pytest

from tests.support.problems import ROOT

BENCHMARKS = ROOT / "benchmarks"
SCRIPT = re.compile(r"`(bench_\w+\.py)`")
QUOTE = re.compile(r'"([^"]{6,})"')


def performance_section(text: str) -> str:
    return text.split("\n## Performance\n", 1)[1].split("\n## ", 1)[0]


def claims(section: str) -> list[str]:
    """Table rows (not the header or the rule) and paragraphs that state figures."""
    blocks, paragraph = [], []
    for line in section.splitlines():
        if line.startswith("|"):
            if not line.startswith("|---") and not line.startswith("| task"):
                blocks.append(line)
        elif line.strip():
            paragraph.append(line)
        elif paragraph:
            blocks.append(" ".join(paragraph))
            paragraph = []
    if paragraph:
        blocks.append(" ".join(paragraph))
    return [b for b in blocks if re.search(r"\d+(\.\d+)?\s*(s|ms|MB|kB|×)\b", b)]


def problems(section: str) -> list[str]:
    """What is wrong with the section's claims: no script, a missing script, a label no script prints."""
    found = []
    for claim in claims(section):
        scripts, quotes = SCRIPT.findall(claim), QUOTE.findall(claim)
        if not scripts or not quotes:
            found.append(f"names no script or quotes no printed label: {claim[:80]}")
            continue
        sources = []
        for name in scripts:
            path = BENCHMARKS / name
            if not path.exists():
                found.append(f"benchmarks/{name} does not exist: {claim[:80]}")
            else:
                sources.append(path.read_text(encoding="utf-8"))
        found += [f'"{q}" is printed by none of {scripts}' for q in quotes
                  if not any(q in source for source in sources)]
    return found


def test_every_performance_figure_quotes_a_script_that_prints_it():
    page = (ROOT / "docs" / "performance.md").read_text(encoding="utf-8")
    assert len(claims(page)) >= 4
    assert problems(page) == []


def test_the_readme_summarises_and_links_the_performance_page():
    section = performance_section((ROOT / "README.md").read_text(encoding="utf-8"))
    assert "(docs/performance.md)" in section
    assert problems(section) == []


@pytest.mark.parametrize("row", [
    '| warm gait | 0.1 s | x | 1× |',  # no script named
    '| warm gait (`bench_gait.py`: "a label it never prints") | 0.1 s | x | 1× |',
    '| warm gait (`bench_nothing.py`: "warm pampipe.gait(optimal=True)") | 0.1 s | x | 1× |',
])
def test_the_check_catches_an_unsourced_figure(row):
    assert problems(f"| task | a | b | c |\n|---|---|---|---|\n{row}\n")
