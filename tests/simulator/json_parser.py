"""The PLC's JSON parser for PutObject bodies, with the limits of manual chapter 3.6.

Only ASCII in strings, no scientific notation (`1.5E3`), item names of at most 64
characters (400.008), item values of at most 255 characters, nesting of at most 32
levels where an array uses two. Syntax errors answer 400.009 with a description;
the manual names `JSON stack overflow`, `Expected character '{'`, `Expected
character ':'`, `Expected character '"'` and `JSON stack underflow`, which are used
for those cases; other cases use `Unexpected character 'X'`, `Unexpected end of
data`, `Non-ASCII character` and `Value is too long`.
"""

from typing import Any, Final

from . import errors
from .errors import TecoError
from .program import MAX_NAME_LENGTH

MAX_VALUE_LENGTH: Final = 255
MAX_NESTING: Final = 32
_WHITESPACE: Final = " \t\r\n"
_ESCAPES: Final = {
    '"': '"',
    "\\": "\\",
    "/": "/",
    "b": "\b",
    "f": "\f",
    "n": "\n",
    "r": "\r",
    "t": "\t",
}


def parse_put_body(body: bytes) -> dict[str, Any]:
    """The top-level object of a PutObject body, or a TecoError (400.008/400.009)."""
    return _Parser(body.decode("latin-1")).document()


class _Parser:
    """A recursive-descent reader over the body text (one character per byte)."""

    def __init__(self, text: str) -> None:
        self._text = text
        self._at = 0
        self._depth = 0

    def document(self) -> dict[str, Any]:
        self._skip_space()
        if self._peek() != "{":
            raise _syntax("Expected character '{'")
        value = self._object()
        self._skip_space()
        if self._at < len(self._text):
            if self._peek() in "}]":
                raise _syntax("JSON stack underflow")
            raise self._unexpected()
        return value

    def _peek(self) -> str:
        return self._text[self._at] if self._at < len(self._text) else ""

    def _skip_space(self) -> None:
        while self._at < len(self._text) and self._text[self._at] in _WHITESPACE:
            self._at += 1

    def _unexpected(self) -> TecoError:
        character = self._peek()
        if not character:
            return _syntax("Unexpected end of data")
        if not character.isascii():
            return _syntax("Non-ASCII character")
        return _syntax(f"Unexpected character '{character}'")

    def _enter(self, levels: int) -> None:
        self._depth += levels
        if self._depth > MAX_NESTING:
            raise _syntax("JSON stack overflow")

    def _object(self) -> dict[str, Any]:
        self._at += 1
        self._enter(1)
        result: dict[str, Any] = {}
        self._skip_space()
        if self._peek() == "}":
            self._at += 1
            self._depth -= 1
            return result
        while True:
            self._skip_space()
            if self._peek() != '"':
                raise _syntax("Expected character '\"'")
            key = self._string()
            if len(key) > MAX_NAME_LENGTH:
                raise errors.item_name_too_long(key)
            self._skip_space()
            if self._peek() != ":":
                raise _syntax("Expected character ':'")
            self._at += 1
            result[key] = self._value()
            self._skip_space()
            if self._peek() == ",":
                self._at += 1
                continue
            if self._peek() == "}":
                self._at += 1
                self._depth -= 1
                return result
            raise self._unexpected()

    def _array(self) -> list[Any]:
        self._at += 1
        self._enter(2)
        result: list[Any] = []
        self._skip_space()
        if self._peek() == "]":
            self._at += 1
            self._depth -= 2
            return result
        while True:
            result.append(self._value())
            self._skip_space()
            if self._peek() == ",":
                self._at += 1
                continue
            if self._peek() == "]":
                self._at += 1
                self._depth -= 2
                return result
            raise self._unexpected()

    def _value(self) -> Any:
        self._skip_space()
        character = self._peek()
        if character == "{":
            return self._object()
        if character == "[":
            return self._array()
        if character == '"':
            return self._string()
        if character == "-" or _is_digit(character):
            return self._number()
        for literal, value in (("true", True), ("false", False), ("null", None)):
            if self._text.startswith(literal, self._at):
                self._at += len(literal)
                return value
        raise self._unexpected()

    def _string(self) -> str:
        self._at += 1
        characters: list[str] = []
        while True:
            character = self._peek()
            if not character:
                raise self._unexpected()
            self._at += 1
            if character == '"':
                break
            if not character.isascii():
                self._at -= 1
                raise self._unexpected()
            if character == "\\":
                character = self._escape()
            characters.append(character)
            if len(characters) > MAX_VALUE_LENGTH:
                raise _syntax("Value is too long")
        return "".join(characters)

    def _escape(self) -> str:
        code = self._peek()
        self._at += 1
        if code in _ESCAPES:
            return _ESCAPES[code]
        if code == "u":
            digits = self._text[self._at : self._at + 4]
            if len(digits) == 4 and all(c in "0123456789abcdefABCDEF" for c in digits):
                self._at += 4
                if int(digits, 16) > 0x7F:
                    raise _syntax("Non-ASCII character")
                return chr(int(digits, 16))
        self._at -= 1
        raise self._unexpected()

    def _number(self) -> int | float:
        start = self._at
        if self._peek() == "-":
            self._at += 1
        if not _is_digit(self._peek()):
            raise self._unexpected()
        while _is_digit(self._peek()):
            self._at += 1
        is_real = self._peek() == "."
        if is_real:
            self._at += 1
            if not _is_digit(self._peek()):
                raise self._unexpected()
            while _is_digit(self._peek()):
                self._at += 1
        text = self._text[start : self._at]
        if len(text) > MAX_VALUE_LENGTH:
            raise _syntax("Value is too long")
        # A following 'e'/'E' (scientific notation) is rejected by the caller
        # as an unexpected character.
        return float(text) if is_real else int(text)


def _is_digit(character: str) -> bool:
    return len(character) == 1 and "0" <= character <= "9"


def _syntax(description: str) -> TecoError:
    return errors.json_syntax(description)
