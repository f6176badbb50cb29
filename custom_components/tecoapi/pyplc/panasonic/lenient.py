"""JSON as the FP-I4C's documentation prints it: strict first, tolerant second.

The manual's examples are not JSON: arrays and objects end with a comma
(``[1, 2,]``, ``"err_code": 0,}``), a bit address goes unquoted (``"start":
f``) and an ANY read's ``hex`` words are bare (``000A``). Nobody knows what a
real gateway sends, so an answer is read strictly (``json.loads``) and, when
that fails, by :func:`loads_lenient`, which takes those forms and nothing
else looser: a trailing comma before ``]`` or ``}``, and a bare word (letters,
digits, ``_ . + -``) that is not a JSON number, ``true``, ``false`` or
``null`` as the text it spells; and the no-break spaces the manual's pages
indent with as white space. A bare word that is a JSON number is that
number; one with leading zeros (``0001``) is text, as a hex word is.

The text is bounded (:data:`MAX_TEXT`) and so is nesting (:data:`MAX_DEPTH`),
so a broken or hostile answer costs bounded memory and time: the parser walks
the text once.
"""

import json
import re
from typing import Any, Final

MAX_TEXT: Final = 512 * 1024
"""The longest text either parser reads (characters)."""
MAX_DEPTH: Final = 32
"""The deepest nesting the tolerant parser takes (an answer has three levels)."""

_WHITESPACE: Final = re.compile(r"[ \t\r\n\u00a0]*")
_STRING: Final = re.compile(r'"(?:[^"\\\x00-\x1f]|\\["\\/bfnrt]|\\u[0-9a-fA-F]{4})*"')
_BARE: Final = re.compile(r"[A-Za-z0-9_.+\-]+")
_NUMBER: Final = re.compile(r"-?(?:0|[1-9][0-9]*)(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?")
_LITERALS: Final = {"true": True, "false": False, "null": None}


class LenientJsonError(ValueError):
    """Text that is not JSON, even as the documentation prints it."""

    def __init__(self, message: str, position: int) -> None:
        """Say what is wrong and where (a character's index)."""
        super().__init__(f"{message} at character {position}")
        self.position = position


def loads(text: str) -> tuple[Any, bool]:
    """Return the value of a JSON text, and whether it took the tolerant parser."""
    if len(text) > MAX_TEXT:
        raise LenientJsonError(f"longer than {MAX_TEXT} characters", MAX_TEXT)
    try:
        return json.loads(text), False
    except (ValueError, RecursionError):
        return loads_lenient(text), True


def loads_lenient(text: str) -> Any:
    """Return the value of JSON as the documentation prints it (see the module)."""
    if len(text) > MAX_TEXT:
        raise LenientJsonError(f"longer than {MAX_TEXT} characters", MAX_TEXT)
    return _Parser(text).parse()


class _Parser:
    """A recursive descent over one text, at most :data:`MAX_DEPTH` deep."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.position = 0

    def parse(self) -> Any:
        value = self.value(0)
        self.skip()
        if self.position != len(self.text):
            raise LenientJsonError("text after the value", self.position)
        return value

    def skip(self) -> None:
        found = _WHITESPACE.match(self.text, self.position)
        assert found is not None
        self.position = found.end()

    def peek(self) -> str:
        """Return the next character after white space."""
        self.skip()
        if self.position >= len(self.text):
            raise LenientJsonError("unexpected end", self.position)
        return self.text[self.position]

    def value(self, depth: int) -> Any:
        char = self.peek()
        if char in "[{":
            if depth >= MAX_DEPTH:
                raise LenientJsonError("nested too deep", self.position)
            self.position += 1
            return self.array(depth + 1) if char == "[" else self.object(depth + 1)
        return self.scalar()

    def array(self, depth: int) -> list[Any]:
        items: list[Any] = []
        while self.peek() != "]":
            items.append(self.value(depth))
            if not self.separated("]"):
                break
        self.position += 1
        return items

    def object(self, depth: int) -> dict[str, Any]:
        members: dict[str, Any] = {}
        while self.peek() != "}":
            found = _STRING.match(self.text, self.position)
            if found is None:
                raise LenientJsonError("expected a key", self.position)
            self.position = found.end()
            if self.peek() != ":":
                raise LenientJsonError("expected ':'", self.position)
            self.position += 1
            members[json.loads(found.group())] = self.value(depth)
            if not self.separated("}"):
                break
        self.position += 1
        return members

    def separated(self, end: str) -> bool:
        """Take a comma (True: more may follow) or see the end (False)."""
        char = self.peek()
        if char == ",":
            self.position += 1
            return True
        if char != end:
            raise LenientJsonError(f"expected ',' or {end!r}", self.position)
        return False

    def scalar(self) -> Any:
        """Read a string, a number, a literal or a bare word."""
        text, position = self.text, self.position
        if text[position] == '"':
            if (found := _STRING.match(text, position)) is None:
                raise LenientJsonError("broken string", position)
            self.position = found.end()
            return json.loads(found.group())
        if (found := _BARE.match(text, position)) is None:
            raise LenientJsonError(f"unexpected {text[position]!r}", position)
        self.position = found.end()
        word = found.group()
        if word in _LITERALS:
            return _LITERALS[word]
        if _NUMBER.fullmatch(word):
            return float(word) if any(char in word for char in ".eE") else int(word)
        return word
