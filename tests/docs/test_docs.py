"""The repo documents itself.

Every `docs/<page>.md §<section>` citation in README.md, pampipe/, benchmarks/, tests/, docs/ and
problems/ names a page that exists and a heading of that page, links between the pages land on real
headings, and nothing points at the private reference folder users never have.

A heading's number is what starts it: `## 5. Radial expansion model` is §5, `### 5.3 Key identity` is §5.3,
`### 9d. Bladder stiffening after contact` is §9d.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

from tests.support.problems import ROOT

DOCS = ROOT / "docs"
PAGES = ("physics", "formats", "commands", "workflows")
#: Where citations are looked for, and which files there are text worth scanning.
SCANNED = ("README.md", "pampipe", "benchmarks", "tests", "docs", "problems")
SUFFIXES = {".py", ".md", ".yaml", ".yml", ".txt", ".toml"}
#: Where the private reference folder must not be mentioned (the issue's `grep` of README.md, pampipe, docs).
PUBLIC = ("README.md", "pampipe", "docs")
FORBIDDEN = ("../" + "shared", "shared" + "/spec", "shared" + "/design")

_REF = r"\d+[a-z]?(?:\.\d+)*"
#: `docs/physics.md §5.3`, `docs/physics.md (§4.4, §5.5)`, `docs/formats.md §1-§4`,
#: `docs/physics.md section 8`.
CITATION = re.compile(
    rf"docs/(?P<page>[A-Za-z0-9_-]+)\.md"
    rf"(?P<refs>\s*\(?\s*(?:§\s*|section\s+){_REF}(?:\s*(?:,|-|–|/|and)\s*§\s*{_REF})*)?")
REFERENCE = re.compile(_REF)
#: Inside docs/ a page names its siblings without the folder: `physics.md §5.3`, `[formats.md §2](...)`.
SIBLING = re.compile(CITATION.pattern.replace("docs/", r"(?<![\w.])(?:docs/)?", 1))
LOCAL = re.compile(rf"§\s*(?P<ref>{_REF})")
HEADING = re.compile(rf"^#{{1,6}}\s+(?P<number>{_REF})[.)]?\s", re.MULTILINE)
LINK = re.compile(r"\]\((?P<page>[A-Za-z0-9_./-]*?\.md)?(?:#(?P<anchor>[^)\s]+))?\)")


def headings(text: str) -> set[str]:
    """Section numbers of a Markdown page: '5', '5.3', '9d', ..."""
    return {m.group("number") for m in HEADING.finditer(text)}


def slugs(text: str) -> set[str]:
    """GitHub-style anchors of every heading of a Markdown page."""
    out = set()
    for line in text.splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*$", line)
        if m:
            title = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower())
            out.add(title.replace(" ", "-"))
    return out


def citations(text: str, *, pattern: re.Pattern = CITATION) -> list[tuple[str, list[str]]]:
    """(page, [section, ...]) for every `docs/<page>.md` mention; an empty list when it cites no section."""
    out = []
    for m in pattern.finditer(text):
        refs = REFERENCE.findall(m.group("refs") or "")
        out.append((m.group("page"), refs))
    return out


def local_references(text: str) -> list[str]:
    """Sections a docs page cites without naming a page (`see §5.3`): they refer to the page itself."""
    named = [m.span() for m in SIBLING.finditer(text)]
    return [m.group("ref") for m in LOCAL.finditer(text)
            if not any(start <= m.start() < end for start, end in named)]


def citation_problems(text: str, *, where: str, docs: Path = DOCS,
                      pattern: re.Pattern = CITATION) -> list[str]:
    """One sentence per citation in ``text`` whose page or section does not exist under ``docs``."""
    problems = []
    for page, refs in citations(text, pattern=pattern):
        path = docs / f"{page}.md"
        if not path.is_file():
            problems.append(f"{where}: docs/{page}.md does not exist")
            continue
        known = headings(path.read_text(encoding="utf-8"))
        problems += [f"{where}: docs/{page}.md has no heading numbered {ref} (cited as §{ref})"
                     for ref in refs if ref not in known]
    return problems


def _files(names) -> list[Path]:
    out = []
    for name in names:
        path = ROOT / name
        if path.is_file():
            out.append(path)
        elif path.is_dir():
            out += sorted(p for p in path.rglob("*") if p.is_file() and p.suffix in SUFFIXES
                          and "__pycache__" not in p.parts)
    return out


def _read(path: Path) -> str:
    return path.read_text(encoding="utf-8", errors="replace")


def test_the_pages_exist():
    for page in PAGES:
        assert (DOCS / f"{page}.md").is_file(), f"docs/{page}.md is missing"


def test_every_citation_points_to_an_existing_section():
    problems, found = [], 0
    for path in _files(SCANNED):
        text = _read(path)
        found += sum(len(refs) for _, refs in citations(text))
        problems += citation_problems(text, where=str(path.relative_to(ROOT)))
    assert not problems, "\n".join(problems)
    assert found > 100, f"only {found} section citations found: the scanner is broken"


_D = "docs/"  # fabricated bad citations are spelt with it, so that the repository scan does not find them


@pytest.mark.parametrize("text", [
    f"see {_D}physics.md §99",
    f"see {_D}physics.md §9z for the details",
    f"{_D}physics.md §5.3, §5.77",
    f"{_D}formats.md §1-§42",
    f"{_D}physics.md section 42",
    f"{_D}nowhere.md §1",
    f"{_D}nowhere.md",
])
def test_the_checker_catches_a_bad_citation(text):
    assert citation_problems(text, where="fabricated"), f"{text!r} was accepted"


@pytest.mark.parametrize(("text", "refs"), [
    ("docs/physics.md §5.3: the split-pipe force", ["5.3"]),
    ("(docs/physics.md §9d).", ["9d"]),
    ("docs/physics.md §7.", ["7"]),
    ("docs/physics.md (§4.4, §5.5, §7, §8), all", ["4.4", "5.5", "7", "8"]),
    ("docs/physics.md §2-§3, Eqs. 1-5", ["2", "3"]),
    ("docs/physics.md §8 / §7 for segment i", ["8", "7"]),
    ("docs/physics.md section 8). The plan", ["8"]),
    ("docs/commands.md §4.2 `plan`", ["4.2"]),
    ("the pages docs/workflows.md and docs/formats.md", []),
])
def test_the_checker_reads_every_citation_style(text, refs):
    (_page, found), = [c for c in citations(text) if c[1]] or [(None, [])]
    assert found == refs
    assert not citation_problems(text, where="fabricated")


def test_docs_pages_cite_their_own_and_each_others_sections():
    problems = []
    for path in sorted(DOCS.glob("*.md")):
        text = _read(path)
        problems += citation_problems(text, where=path.name, pattern=SIBLING)
        own = headings(text)
        problems += [f"{path.name}: §{ref} is not a heading of this page" for ref in local_references(text)
                     if ref not in own]
    assert not problems, "\n".join(problems)


def test_links_between_pages_land_on_headings():
    problems = []
    for path in [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]:
        for m in LINK.finditer(_read(path)):
            page, anchor = m.group("page"), m.group("anchor")
            if page is None and anchor is None:
                continue
            target = path if page is None else (path.parent / page)
            if not target.is_file():
                problems.append(f"{path.name}: link to missing page {page}")
            elif anchor is not None and anchor not in slugs(_read(target)):
                problems.append(f"{path.name}: link to {page or ''}#{anchor}: no such heading")
    assert not problems, "\n".join(problems)


#: `commands.md#42-json`, `docs/physics.md#62-the-slack-hinge`: an anchor into a page, in any file.
ANCHORED = re.compile(rf"(?<![\w.-])(?:docs/)?(?P<page>{'|'.join(PAGES)})\.md#(?P<anchor>[\w-]+)")


def anchor_problems(text: str, *, where: str, docs: Path = DOCS) -> list[str]:
    """One sentence per `page.md#anchor` in ``text`` that is no heading's GitHub slug on that page."""
    return [f"{where}: {m.group(0)}: no such heading" for m in ANCHORED.finditer(text)
            if m.group("anchor") not in slugs(_read(docs / f"{m.group('page')}.md"))]


def test_every_anchor_into_a_page_is_a_heading():
    """Code docstrings and YAML comments too, not only Markdown links (docs/commands.md was renumbered)."""
    problems, found = [], 0
    for path in _files(SCANNED):
        text = _read(path)
        found += len(ANCHORED.findall(text))
        problems += anchor_problems(text, where=str(path.relative_to(ROOT)))
    assert not problems, "\n".join(problems)
    assert found > 20, f"only {found} anchors found: the scanner is broken"


_H = "#"  # fabricated bad anchors are spelt with it, so that the repository scan does not find them


@pytest.mark.parametrize("text", [
    f"[x](commands.md{_H}75-diagnose-verdict)", f"see docs/commands.md{_H}5-commands",
    f"[y](physics.md{_H}no-such-heading)"])
def test_the_anchor_check_can_fail(text):
    assert anchor_problems(text, where="fabricated")


def private_mentions(text: str) -> list[str]:
    """The forbidden paths that ``text`` mentions."""
    return [word for word in FORBIDDEN if word in text]


DOTTED = re.compile(r"(?<![\w.])pampipe(?:\.[A-Za-z_]\w*)+")
REPO_PATH = re.compile(r"(?<![\w./-])(?:pampipe|problems|tests|benchmarks)/[\w./-]*\w/?")


def resolves(dotted: str) -> bool:
    """Whether ``pampipe.a.b.c`` names an importable module or an attribute of one."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            target = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if not hasattr(target, name):
                return False
            target = getattr(target, name)
        return True
    return False


def test_code_the_docs_name_exists():
    """Every `pampipe.module.function` and every repository path the pages mention is still there."""
    problems = []
    for path in [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]:
        text = _read(path)
        problems += [f"{path.name}: {name} does not resolve" for name in sorted(set(DOTTED.findall(text)))
                     if not resolves(name)]
        problems += [f"{path.name}: {name} does not exist" for name in sorted(set(REPO_PATH.findall(text)))
                     if not (ROOT / name).exists()]
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name", ["pampipe.model.braid.no_such_function", "pampipe.no_such_module.thing"])
def test_a_stale_code_name_is_caught(name):
    assert not resolves(name)


def test_nothing_points_at_the_private_reference():
    hits = [f"{path.relative_to(ROOT)}: {word}" for path in _files(PUBLIC)
            for word in private_mentions(_read(path))]
    assert not hits, "\n".join(hits)


@pytest.mark.parametrize("text", ["see " + "../" + "shared/spec/physics.md §5",
                                  "the design notes (" + "shared" + "/design.md)"])
def test_the_private_reference_check_can_fail(text):
    assert private_mentions(text)


def test_license_matches_pyproject():
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    assert re.search(r'^license\s*=\s*"MIT"', pyproject, re.MULTILINE)
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "the pampipe developers" in text


# ------------------------------------------------------------------ the formats page keeps up with the code
def section(text: str, number: str) -> str:
    """The text of the section numbered ``number`` (a `## ` heading) up to the next `## ` heading."""
    match = re.search(rf"^## {re.escape(number)}\. .*?(?=^## |\Z)", text, re.MULTILINE | re.DOTALL)
    assert match, f"no section {number}"
    return match.group(0)


def schema_keys(model, prefix: str = "") -> set[str]:
    """Every key a pydantic model accepts; a nested mapping's as dotted leaves (`drucker_grid.pressures`)."""
    from pampipe.specs.schema import _model_in

    keys = set()
    for name, field in model.model_fields.items():
        key = prefix + (field.alias or name)
        inner = _model_in(field.annotation)
        keys |= {key} if inner is None else schema_keys(inner, key + ".")
    return keys


def subsection(text: str, heading: str) -> str:
    """The text from the line ``heading`` to the next heading."""
    start = text.index("\n" + heading) + 1
    end = text.find("\n#", start + 1)
    return text[start:] if end < 0 else text[start:end]


def table_keys(text: str) -> set[str]:
    """The `key`s that open a row of a Markdown table (`| `slack` | string | ...`)."""
    return set(re.findall(r"^\| `([\w.\[\]]+)` \|", text, re.MULTILINE))


def effect_rows(text: str) -> set[tuple[str, str, str, str]]:
    """(effect, parameter, display unit, null) of every row of the `effects:` table of formats.md §2."""
    rows, effect = set(), None
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if not line.startswith("|") or len(cells) != 6:
            continue
        named = re.match(r"`(\w+)`", cells[0])
        if named:
            effect = named.group(1)
        elif cells[0]:
            effect = None
        param = re.fullmatch(r"`(\w+)`", cells[1])
        if effect and param:
            rows.add((effect, param.group(1), cells[3], cells[5]))
    return rows


def undocumented(text: str) -> list[str]:
    """What the code accepts and ``text`` (formats.md) does not document, one line each."""
    from pampipe.identification.fit_schema import FitSchema
    from pampipe.io.csvfile import DIMENSIONS, REQUIRED, SIGNS
    from pampipe.io.experiment_schema import TestSchema
    from pampipe.model.effects import LIBRARY

    experiment = section(text, "3")
    fit = table_keys(subsection(experiment, "### `fit:`"))
    problems = [f"fit.{key}: no row in the formats.md §3 fit: table" for key in sorted(schema_keys(FitSchema))
                if key not in fit]
    tests = table_keys(subsection(experiment, "### `tests[]`"))
    problems += [f"tests[].{key}: no row in the formats.md §3 tests[] table" for key in sorted(
        schema_keys(TestSchema)) if key not in tests]
    columns = table_keys(subsection(experiment, "### CSV data"))
    required = {name for names in REQUIRED.values() for name in names}
    problems += [f"CSV column {name}: no row in the formats.md §3 optional-column table" for name in sorted(
        set(DIMENSIONS) | set(SIGNS)) if name not in required and name not in columns]
    documented = effect_rows(section(text, "2"))
    wanted = {(e.name, p.name, "–" if p.unit == "-" else p.unit, f"{p.null:g}")
              for e in LIBRARY.values() for p in e.parameters}
    problems += [f"effect {e}.{p} [{unit}], null {null}: not (or not so) in the formats.md §2 effects table"
                 for e, p, unit, null in sorted(wanted - documented)]
    problems += [f"formats.md §2 documents {e}.{p}, which the effect library does not have"
                 for e, p, _, _ in sorted(documented - wanted)]
    return problems


def test_formats_documents_every_fit_key_csv_column_and_effect_parameter():
    """Derived from the schemas and the effect registry: a key added to the code fails until documented."""
    assert not undocumented(_read(DOCS / "formats.md")), "\n".join(undocumented(_read(DOCS / "formats.md")))


@pytest.mark.parametrize("row", ["| `calibration_bounds.initial_length` |", "| `slack` |",
                                 "| `pipe_diameters` |", "| `set_pressure` |", "| `state` |",
                                 "| `protocol` |", "| | `h1` |",
                                 "| `prestrain` (physics.md §9j) | `axial_prestrain` |"])
def test_the_formats_check_fails_when_a_row_is_missing(row):
    text = _read(DOCS / "formats.md")
    assert text.count(row) == 1
    start = text.index(row)
    end = text.index("\n", start)
    assert undocumented(text[:start] + text[end + 1:]), f"deleting {row} went unnoticed"
