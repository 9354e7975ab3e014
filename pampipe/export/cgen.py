"""C99 text from a CasADi SX function: straight-line code in ``pampipe_real``, double or float alike.

CasADi's own code generator writes double literals, ``casadi_*`` helpers and work arrays behind a
calling convention of its own; the robot's firmware wants one plain function. So this walks the
SX function's instruction list (``Function.instruction_id`` etc.) and writes one assignment per
operation. Every literal goes through ``PAMPIPE_R(x)`` and every math call through a ``PAMPIPE_*``
macro (:data:`PRELUDE`), so that ``-DPAMPIPE_REAL_FLOAT`` turns the whole computation into float
(``1.5f``, ``sqrtf``) with no hidden promotion to double.
"""

from __future__ import annotations

import math

import casadi as ca

#: Macros the generated statements use; the .c file starts with them.
PRELUDE = """\
#ifdef PAMPIPE_REAL_FLOAT
#define PAMPIPE_R(x) x##f
#define PAMPIPE_SQRT sqrtf
#define PAMPIPE_SIN sinf
#define PAMPIPE_COS cosf
#define PAMPIPE_TAN tanf
#define PAMPIPE_ACOS acosf
#define PAMPIPE_EXP expf
#define PAMPIPE_LOG logf
#define PAMPIPE_LOG1P log1pf
#define PAMPIPE_POW powf
#define PAMPIPE_FABS fabsf
#define PAMPIPE_FMAX fmaxf
#define PAMPIPE_FMIN fminf
#else
#define PAMPIPE_R(x) x
#define PAMPIPE_SQRT sqrt
#define PAMPIPE_SIN sin
#define PAMPIPE_COS cos
#define PAMPIPE_TAN tan
#define PAMPIPE_ACOS acos
#define PAMPIPE_EXP exp
#define PAMPIPE_LOG log
#define PAMPIPE_LOG1P log1p
#define PAMPIPE_POW pow
#define PAMPIPE_FABS fabs
#define PAMPIPE_FMAX fmax
#define PAMPIPE_FMIN fmin
#endif
#define PAMPIPE_INF ((pampipe_real)INFINITY)
#define PAMPIPE_NAN ((pampipe_real)NAN)
"""

_UNARY = {ca.OP_SQRT: "PAMPIPE_SQRT({})", ca.OP_SIN: "PAMPIPE_SIN({})", ca.OP_COS: "PAMPIPE_COS({})",
          ca.OP_TAN: "PAMPIPE_TAN({})", ca.OP_ACOS: "PAMPIPE_ACOS({})", ca.OP_EXP: "PAMPIPE_EXP({})",
          ca.OP_LOG: "PAMPIPE_LOG({})", ca.OP_LOG1P: "PAMPIPE_LOG1P({})", ca.OP_FABS: "PAMPIPE_FABS({})",
          ca.OP_NEG: "-{}", ca.OP_SQ: "{0} * {0}", ca.OP_TWICE: "{0} + {0}", ca.OP_INV: "PAMPIPE_R(1.0) / {}",
          ca.OP_NOT: "(pampipe_real)!{}", ca.OP_ASSIGN: "{}"}
_BINARY = {ca.OP_ADD: "{} + {}", ca.OP_SUB: "{} - {}", ca.OP_MUL: "{} * {}", ca.OP_DIV: "{} / {}",
           ca.OP_FMAX: "PAMPIPE_FMAX({}, {})", ca.OP_FMIN: "PAMPIPE_FMIN({}, {})",
           ca.OP_POW: "PAMPIPE_POW({}, {})", ca.OP_CONSTPOW: "PAMPIPE_POW({}, {})",
           ca.OP_LT: "(pampipe_real)({} < {})", ca.OP_LE: "(pampipe_real)({} <= {})",
           ca.OP_EQ: "(pampipe_real)({} == {})", ca.OP_NE: "(pampipe_real)({} != {})",
           ca.OP_AND: "(pampipe_real)({} && {})", ca.OP_OR: "(pampipe_real)({} || {})",
           ca.OP_IF_ELSE_ZERO: "({} ? {} : PAMPIPE_R(0.0))"}


def literal(value: float) -> str:
    """A ``pampipe_real`` constant: ``PAMPIPE_R(0.3)``, ``(-PAMPIPE_R(1.5))``, ``PAMPIPE_INF``."""
    value = float(value)
    if math.isnan(value):
        return "PAMPIPE_NAN"
    if math.isinf(value):
        return "PAMPIPE_INF" if value > 0 else "(-PAMPIPE_INF)"
    text = f"PAMPIPE_R({abs(value)!r})"
    return f"(-{text})" if math.copysign(1.0, value) < 0 else text


def statements(function: ca.Function, inputs: list[str], outputs: list[str], *,
               prefix: str = "w") -> tuple[list[str], list[str]]:
    """(declared variable names, C statements) evaluating ``function`` (scalar SX inputs and outputs).

    Input ``k`` is read from the C expression ``inputs[k]`` and output ``k`` assigned to ``outputs[k]``.
    Constants and inputs are written in place; each other operation becomes ``wN = ...;`` on the
    work slot CasADi assigned it (slots are reused once dead, so few variables are needed).
    """
    if function.n_in() != len(inputs) or function.n_out() != len(outputs):
        raise ValueError("one C name per input and per output is needed")
    value: dict[int, str] = {}
    declared: set[int] = set()
    body = []
    for k in range(function.n_instructions()):
        op = function.instruction_id(k)
        args = function.instruction_input(k)
        out = function.instruction_output(k)
        if op == ca.OP_CONST:
            value[out[0]] = literal(function.instruction_constant(k))
        elif op == ca.OP_INPUT:
            value[out[0]] = inputs[args[0]]
        elif op == ca.OP_OUTPUT:
            body.append(f"{outputs[out[0]]} = {value[args[0]]};")
        elif op in _UNARY or op in _BINARY:
            form = _UNARY.get(op) or _BINARY[op]
            expression = form.format(*(value[a] for a in args))
            declared.add(out[0])
            body.append(f"{prefix}{out[0]} = {expression};")
            value[out[0]] = f"{prefix}{out[0]}"
        else:
            raise NotImplementedError(f"CasADi operation {op} has no C form in pampipe.export.cgen")
    return [f"{prefix}{i}" for i in sorted(declared)], body


#: The longest string literal C99 promises to translate (5.2.4.1), in bytes; gcc's -Woverlength-strings.
MAX_STRING = 4095
#: Source characters per line of a long literal (split into concatenated pieces) or comment.
LINE = 96


def shortened(text: str, limit: int = MAX_STRING) -> str:
    """``text`` if its UTF-8 fits in ``limit`` bytes, else its head and a mark naming length and hash.

    The mark keeps two long names that share their head apart: '…[10000 chars, sha256 1f2e…]'.
    """
    data = text.encode("utf-8")
    if len(data) <= limit:
        return text
    import hashlib

    mark = f"...[{len(text)} chars, sha256 {hashlib.sha256(data).hexdigest()[:16]}]"
    return data[:limit - len(mark)].decode("utf-8", "ignore") + mark


def string(text: str, *, indent: str = "        ") -> str:
    """A C string literal of ``text`` (UTF-8; quotes, backslashes, '?' and non-ASCII escaped).

    Longer than :data:`MAX_STRING` bytes, the text is :func:`shortened`; a literal longer than
    :data:`LINE` characters is split into concatenated pieces, one per line, each ``indent``ed.
    """
    pieces = []
    for byte in shortened(text).encode("utf-8"):
        char = chr(byte)
        if char in '"\\?':
            pieces.append("\\" + char)
        elif 32 <= byte < 127:
            pieces.append(char)
        else:
            pieces.append(f"\\{byte:03o}")
    lines, line = [], ""
    for piece in pieces:
        if len(line) + len(piece) > LINE:
            lines.append(line)
            line = ""
        line += piece
    lines.append(line)
    return f"\n{indent}".join(f'"{line}"' for line in lines)


def long_comment(label: str, text: str, indent: str = "    ") -> str:
    """A /* */ comment holding ``label`` and the whole ``text`` made safe, in lines of :data:`LINE`."""
    safe = comment(text)
    rows = [comment(label)] + [safe[k:k + LINE] for k in range(0, len(safe), LINE)]
    return f"{indent}/* " + f"\n{indent} * ".join(rows) + " */"


def comment(text: str) -> str:
    """``text`` made safe inside a /* */ comment: ASCII, no comment start or end, trigraph or splice."""
    safe = text.encode("ascii", "backslashreplace").decode("ascii").replace("\\", "/")
    safe = "".join(c if 32 <= ord(c) < 127 else " " for c in safe)
    return safe.replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")
