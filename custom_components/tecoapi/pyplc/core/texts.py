"""What the library tells a user, in any language: a key, its parameters, its English.

A message a user reads (why a map's row is refused, why a value cannot be
written, why a point is not read) is a :class:`Text`: a :class:`Template`'s
key, which a caller with translations looks up in its user's language, the
parameters that fill it, and the library's own English (``str(text)``, for
logs and for a caller without translations). Every template registers itself
by its key (:data:`TEMPLATES`), so a caller can check that its translations
have each one, with the same parameters. A parameter is data (a row's number,
a type's name, a value the user typed), never a sentence.

Nothing here does I/O.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
from string import Formatter
from types import MappingProxyType
from typing import Final

TEMPLATES: Final[dict[str, "Template"]] = {}
"""Every template by its key (filled as the library's modules are imported)."""


@dataclass(frozen=True, slots=True)
class Template:
    """A message with a key: its English, with ``{name}`` for each parameter."""

    key: str
    english: str

    def __post_init__(self) -> None:
        """Register the template; a key names one English text only."""
        known = TEMPLATES.setdefault(self.key, self)
        if known.english != self.english:
            msg = f"two texts have the key {self.key!r}"
            raise ValueError(msg)

    @property
    def params(self) -> frozenset[str]:
        """The names of the parameters its text takes."""
        return frozenset(
            name for _, name, _, _ in Formatter().parse(self.english) if name
        )

    def __call__(self, **params: object) -> "Text":
        """Return the text with its parameters (each as text)."""
        return Text(self, MappingProxyType({k: str(v) for k, v in params.items()}))


@dataclass(frozen=True, slots=True)
class Text:
    """A message for a user: its template and the parameters that fill it."""

    template: Template
    params: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def key(self) -> str:
        """The key a caller's translations know it by."""
        return self.template.key

    def __str__(self) -> str:
        """Return the message in the library's English."""
        return self.format(self.template.english)

    def format(self, message: str) -> str:
        """Return a message of this text (its English, a translation) filled in.

        A placeholder the parameters lack stays as it is (``{name}``).
        """
        return message.format_map(_Filled(self.params))


class _Filled(dict[str, str]):
    """Parameters that leave a placeholder they lack as it is."""

    def __missing__(self, key: str) -> str:
        return f"{{{key}}}"


DEVICE_SAYS: Final = Template("device_says", "the device says: {said}")
"""The device's own words (its code, its message), as it says them."""
