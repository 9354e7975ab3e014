"""What the docs quote is what their commands print (issue 42, item 5).

Convention (keep it when editing README.md or docs/workflows.md; the commands run as
tests/support/doc_commands.py says, and the checks below read what each of them printed, stdout and stderr):

* **Output blocks.** A bare ```` ``` ```` block (no language) whose nearest fenced block above is a
  ```` ```sh ```` block shows what that ```sh block printed. Every line of it must be a line its commands
  printed (runs of spaces count as one; `...` inside a line stands for any text; a line that is only `...`
  stands for lines left out). Usage lines, placeholders and other text that is not output go in a
  ```` ```text ```` block.
* **Quoted numbers.** A prose paragraph that quotes a number a command printed is followed by a marker

      <!-- printed: 196 "iterations"; 4.519 "a1,0"; 166.6 ±0.2 "run" -->

  (it may run over several lines), one item per number, separated by `;`: the number exactly as the paragraph
  writes it (it must be in the text between the marker and the previous marker or fenced block), an optional
  `±TOL` for a Monte-Carlo or solver figure, and an optional "context" that must be on the same printed line
  (runs of spaces count as one). The number must be printed by a command of the nearest ```sh block above the
  marker: some printed number p on a line with the context must round to it (|p − q| at most half a unit of
  the quoted number's last digit, or TOL when stated). Numbers a reader types (inputs, the generating values
  of synthetic data, section numbers) need no marker.

So a quoted number changed by hand, or a command whose output changes, fails tests/docs/test_docs_run.py.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

FENCE = "```"
MARKER = re.compile(r"<!--\s*printed:(?P<items>.*?)-->", re.DOTALL)
ITEM = re.compile(r'^\s*(?P<number>[−+-]?\d[\d.,]*(?:e[−+-]?\d+)?)\s*(?:±\s*(?P<tol>\d[\d.e+-]*))?\s*'
                  r'(?:"(?P<context>[^"]*)")?\s*$')
NUMBER = re.compile(r"[−+-]?(?<![\w.])\d+(?:\.\d+)?(?:e[−+-]?\d+)?")


@dataclass(frozen=True)
class Quote:
    """One checked figure: printed by the commands of the ```sh block at ``block`` (its opening line)."""
    doc: str
    line: int  # the marker's line, or the output line's
    block: int
    number: str  # the quoted number; "" for a whole output line
    tol: float | None
    context: str
    prose: str  # the paragraph the number must be in; for an output line, the line itself

    def where(self) -> str:
        return f"{self.doc}:{self.line} (output of the ```sh block at line {self.block})"


def value(text: str) -> float:
    return float(text.replace("−", "-").replace(",", ""))


def half_unit(text: str) -> float:
    """Half a unit of the last digit written: 4.519 → 0.0005, 196 → 0.5, 1.061e+04 → 5."""
    mantissa, _, exponent = text.replace("−", "-").lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def quotes(doc: str, text: str) -> list[Quote]:
    """Every output-block line and every marker item of one doc, with the ```sh block they refer to."""
    found, last_sh, previous_fence, kind, output = [], None, None, None, False
    prose, marker = [], None  # the text since the last marker or fence; a marker read over several lines
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if marker is None and stripped.startswith(FENCE):
            if kind is None:
                kind = stripped[len(FENCE):].strip()
                output, prose = kind == "" and previous_fence == "sh", []
                last_sh = number if kind == "sh" else last_sh
            else:
                kind, previous_fence = None, kind
            continue
        if kind is not None:
            if output and stripped and stripped != "...":
                found.append(Quote(doc, number, last_sh, "", None, "", line))
            continue
        if marker is None and "<!--" in line and "printed:" in line:
            start = line.index("<!--")
            prose.append(line[:start])
            marker, line = (number, ""), line[start:]
        if marker is None:
            prose.append(line)
            continue
        marker = (marker[0], marker[1] + "\n" + line)
        if "-->" in line:
            found += _items(doc, marker[0], last_sh, MARKER.search(marker[1]), "\n".join(prose))
            prose, marker = [], None
    return found


def _items(doc: str, line: int, block: int | None, match: re.Match | None, prose: str) -> list[Quote]:
    items = filter(str.strip, match.group("items").split(";")) if match else ["(no marker)"]
    out = []
    for item in items:
        parsed = ITEM.match(item)
        if parsed is None or block is None:
            out.append(Quote(doc, line, block or 0, item.strip(), None, "", ""))
            continue
        tol = parsed.group("tol")
        out.append(Quote(doc, line, block, parsed.group("number"), float(tol) if tol else None,
                         parsed.group("context") or "", prose))
    return out


def _squash(text: str) -> str:
    return " ".join(text.split())


def line_printed(expected: str, printed: list[str]) -> bool:
    pattern = re.compile(".*".join(re.escape(part) for part in _squash(expected).split("...")))
    return any(pattern.fullmatch(_squash(line)) for line in printed)


def number_printed(quote: Quote, printed: list[str]) -> bool:
    target, tol = value(quote.number), quote.tol if quote.tol is not None else half_unit(quote.number)
    for line in printed:
        if quote.context and _squash(quote.context) not in _squash(line):
            continue
        for match in NUMBER.finditer(line):
            if abs(value(match.group()) - target) <= tol * (1 + 1e-9):
                return True
    return False


def problem(quote: Quote, printed: list[str]) -> str | None:
    """Why ``quote`` is not what ``printed`` (the lines its ```sh block's commands printed) says, or None."""
    if not quote.prose:
        return f"{quote.where()}: cannot read the marker item {quote.number!r} (NUMBER [±TOL] [\"context\"])"
    if not quote.number:
        if not line_printed(quote.prose, printed):
            return f"{quote.where()}: this output line was not printed:\n  {quote.prose.strip()}"
        return None
    if quote.number not in quote.prose:
        return f"{quote.where()}: the marker names {quote.number}, which the paragraph above does not quote"
    if not number_printed(quote, printed):
        where = f' on a line with "{quote.context}"' if quote.context else ""
        tol = f"±{quote.tol}" if quote.tol is not None else "to its last digit"
        return f"{quote.where()}: {quote.number} ({tol}) was not printed{where}"
    return None
