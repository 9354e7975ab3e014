"""The text a PDF written by matplotlib shows, read without a PDF library: each content stream inflated
(zlib), each text object (BT … ET) its string literals joined. matplotlib writes a monospace line as one
literal per character (kerned), so the join gives the line back."""

from __future__ import annotations

import re
import zlib

_STREAM = re.compile(rb"stream\r?\n(.*?)\r?\nendstream", re.S)
_TEXT = re.compile(rb"BT(.*?)ET", re.S)
_LITERAL = re.compile(rb"\(((?:\\.|[^\\)])*)\)", re.S)
_ESCAPE = re.compile(rb"\\([()\\])")


def pdf_lines(data: bytes) -> list[str]:
    """Every text object's text, in the order written."""
    out = []
    for match in _STREAM.finditer(data):
        try:
            content = zlib.decompress(match.group(1))
        except zlib.error:  # an uncompressed stream (pdf.compression 0), or binary data
            content = match.group(1)
        for block in _TEXT.finditer(content):
            pieces = [_ESCAPE.sub(rb"\1", m.group(1)) for m in _LITERAL.finditer(block.group(1))]
            if pieces:
                out.append(b"".join(pieces).decode("latin-1"))
    return out
