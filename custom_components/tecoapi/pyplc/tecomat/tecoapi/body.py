r"""Reading a PLC's answer: capped in size, its text decoded as UTF-8 or Windows-1250.

Size. Nothing a TecoApi PLC may legitimately send is larger than a GetObject answer
at the limits the manual documents, printed the way the PLC prints (two spaces per
level, CRLF line ends, one member per line):

- at most ``I`` = 256 items per answer (CP-2xxx; CP-1xxx 128);
- a value of at most ``V`` = 255 characters, each at most ``E`` = 6 bytes in JSON
  (``\u001f``; a character Windows-1250 knows is at most 3 bytes of UTF-8), in quotes;
- a member name of at most ``N`` = 64 characters (ASCII identifiers), in quotes;
- nesting of at most ``D`` = 32 levels (the PLC's JSON parser's limit; an array
  element takes two), so an item has at most ``D - 1`` containers above it.

One item's own line takes ``2D + (N + 2) + 2 + (E·V + 2) + 1 + 2`` bytes (indent,
name, ``": "``, value, comma, CRLF) = 1,667; each container above it at most
``3·2D + (N + 2) + 4 + 3·2`` bytes (its name line with ``:``, the ``{`` line, the
``}`` line with a comma) = 268. With no container shared between two items, the worst case:

    MAX_BODY_BYTES = I · (1,667 + (D - 1) · 268) + 6  =  2,553,606 bytes (~2.4 MiB)

(the 6: the outer braces' lines). Keys that carry indexes (``arr2[1][3]``) fit in
the slack of the escapes. GetList is bounded by the public file (at most 128 KB,
each root's name in it at least once): ``"name": {},`` and CRLF is at most 11 bytes
for each 2 bytes of that file, 704 KB. GetInfo and error answers are a few hundred
bytes. Real answers are far smaller (a full CP-2xxx answer of T_ApiObjects is about
12 KB); the cap is for a wrong device or a broken PLC answering megabytes, or without
end. It is read a chunk at a time and the request fails with
:class:`ResponseTooLargeError` at the first byte past the cap (a declared
``Content-Length`` past it fails before any byte of the body is read), so memory
stays at the cap whatever is sent, and an endless body ends there, not at the
timeout.

Text. The JSON structure of an answer is ASCII; only strings (titles, units, string
values, error messages) carry other characters. Mosaic programs are written on Czech
and Slovak Windows, so a PLC may send them as Windows-1250 bytes rather than UTF-8.
An answer that is UTF-8 is decoded as such; otherwise each string is decoded on its
own -- UTF-8 if it is, else Windows-1250 -- so one odd string never costs the rest
of the answer. Both encodings keep ``"`` and ``\`` as the ASCII bytes, and UTF-8
never uses bytes below 0x80 inside a character, so strings are found in the bytes
before decoding.
"""

import re
from typing import Final

MAX_ITEMS: Final = 256
MAX_VALUE_CHARS: Final = 255
MAX_NAME_CHARS: Final = 64
MAX_NESTING: Final = 32
ESCAPED_CHAR_BYTES: Final = 6
_INDENT: Final = 2 * MAX_NESTING
_NAME: Final = MAX_NAME_CHARS + 2
_ITEM_LINE: Final = _INDENT + _NAME + 2 + (ESCAPED_CHAR_BYTES * MAX_VALUE_CHARS + 2) + 3
_CONTAINER_LINES: Final = 3 * _INDENT + _NAME + 4 + 3 * 2
MAX_BODY_BYTES: Final = (
    MAX_ITEMS * (_ITEM_LINE + (MAX_NESTING - 1) * _CONTAINER_LINES) + 6
)
"""The most bytes of an answer the client reads (see the module docstring)."""

FALLBACK_ENCODING: Final = "cp1250"

_JSON_STRING: Final = re.compile(rb'"(?:[^"\\]|\\.)*"', re.DOTALL)


def decode_text(content: bytes) -> str:
    """Decode an answer: UTF-8, or string by string UTF-8 else Windows-1250.

    Bytes Windows-1250 does not define (0x81, 0x83, 0x88, 0x90, 0x98) and non-ASCII
    bytes outside strings become U+FFFD.
    """
    try:
        return content.decode("utf-8")
    except UnicodeDecodeError:
        pass
    return _JSON_STRING.sub(_as_utf8, content).decode("utf-8", errors="replace")


def _as_utf8(match: re.Match[bytes]) -> bytes:
    """Return a JSON string token as UTF-8: kept if it is, else from Windows-1250."""
    token = match.group()
    try:
        token.decode("utf-8")
    except UnicodeDecodeError:
        return token.decode(FALLBACK_ENCODING, errors="replace").encode("utf-8")
    return token
