"""pampipe/export/cgen.py piece by piece: literals and their signs, C99's 4095-byte string limit (5.2.4.1),
string and comment escaping, and straight-line statements whose answer, read back as Python, is CasADi's."""

from __future__ import annotations

import hashlib
import math
import re

import casadi as ca
import pytest

from pampipe.export import cgen


@pytest.mark.parametrize(("value", "text"), [
    (0.3, "PAMPIPE_R(0.3)"), (-1.5, "(-PAMPIPE_R(1.5))"), (0.0, "PAMPIPE_R(0.0)"),
    (-0.0, "(-PAMPIPE_R(0.0))"),
    (math.inf, "PAMPIPE_INF"), (-math.inf, "(-PAMPIPE_INF)"), (math.nan, "PAMPIPE_NAN")])
def test_a_literal_keeps_its_value_and_sign(value, text):
    assert cgen.literal(value) == text


def test_a_string_longer_than_c99_promises_is_cut_to_4095_bytes_with_a_mark():
    """C99 5.2.4.1: 4095 bytes in a string literal; longer text keeps its head and a mark naming its length
    and its SHA-256."""
    fits = "x" * 4095
    assert cgen.shortened(fits) == fits
    long = "y" * 4096
    mark = f"...[4096 chars, sha256 {hashlib.sha256(long.encode()).hexdigest()[:16]}]"
    cut = cgen.shortened(long)
    assert cut == "y" * (4095 - len(mark)) + mark
    assert len(cut.encode("utf-8")) == 4095
    wide = cgen.shortened("é" * 3000)  # 6000 bytes: the cut falls inside a character
    assert len(wide.encode("utf-8")) <= 4095 and wide.startswith("é" * 2000) and wide.endswith("]")


def test_a_c_string_escapes_and_splits():
    """Quotes, backslashes and '?' (trigraphs) escaped, non-ASCII as octal bytes, pieces of ≤ 96 characters
    that concatenate back to the text."""
    text = 'a "b" \\ ??= é' + "z" * 200
    literal = cgen.string(text, indent="")
    pieces = re.findall(r'^"(.*)"$', literal, flags=re.MULTILINE)
    assert len(pieces) == literal.count("\n") + 1 >= 3
    assert all(len(p) <= 96 for p in pieces)
    joined = "".join(pieces)
    assert joined.startswith(r'a \"b\" \\ \?\?= \303\251z')
    back = re.sub(r"\\([0-7]{3})", lambda m: chr(int(m.group(1), 8)), joined)
    back = re.sub(r'\\(["\\?])', r"\1", back)
    assert back.encode("latin-1").decode("utf-8") == text


def test_a_comment_cannot_end_itself():
    assert cgen.comment("a */ b /* c ?? d é") == "a * / b / * c ? ? d /xe9"


def test_statements_compute_what_casadi_computes():
    """f(x, y) = (max(x·y − 2, −0.5) + √y)/x, and −x²: the C statements, read as Python, give CasADi's
    answers."""
    x, y = ca.SX.sym("x"), ca.SX.sym("y")
    function = ca.Function("f", [x, y], [(ca.fmax(x * y - 2, -0.5) + ca.sqrt(y)) / x, -x**2])
    names, body = cgen.statements(function, ["in_x", "in_y"], ["out[0]", "out[1]"])
    assert names and all(n.startswith("w") for n in names)
    python = "\n".join(body).replace(";", "")
    python = re.sub(r"PAMPIPE_R\(([^)]*)\)", r"(\1)", python)
    python = python.replace("PAMPIPE_FMAX", "max").replace("PAMPIPE_SQRT", "math.sqrt")
    for vx, vy in ((1.5, 4.0), (0.5, 1.0), (-2.0, 3.0)):
        scope = {"in_x": vx, "in_y": vy, "out": [None, None], "math": math}
        exec(python, scope)  # our own generated arithmetic
        want = [float(v) for v in function(vx, vy)]
        assert scope["out"] == pytest.approx(want, rel=1e-15)
    with pytest.raises(ValueError, match="one C name per input"):
        cgen.statements(function, ["in_x"], ["out[0]", "out[1]"])


def test_a_long_comment_holds_the_label_and_the_whole_text_in_lines_of_96():
    text = "".join(chr(ord("a") + k % 26) for k in range(200))
    assert cgen.long_comment("law", text, indent="  ") == (
        f"  /* law\n   * {text[:96]}\n   * {text[96:192]}\n   * {text[192:]} */")


def test_a_c_string_line_holds_exactly_96_characters_and_escapes_delete():
    assert cgen.string("z" * 96, indent="") == '"' + "z" * 96 + '"'
    assert cgen.string("z" * 97, indent="") == '"' + "z" * 96 + '"\n"z"'
    assert cgen.string("~\x7f", indent="") == '"~\\177"'  # DEL (127) is no printable character


def test_a_comment_blanks_control_characters_and_delete():
    assert cgen.comment("a\x07b\x7fc\td~") == "a b c d~"
