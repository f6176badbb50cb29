"""The sources a caller may offer: the built-in systems', and any registered.

Each system's subpackage declares its descriptors in a module of its own
(``DESCRIPTORS``); this module imports the built-in ones by name when it is
imported (not later: an import inside an event loop blocks it), so a caller
imports this module and nothing of any system. A source
written elsewhere (a test's, another vendor's) is :func:`register`-ed and is
then offered like the built-in ones.
"""

from collections.abc import Callable
import importlib
from typing import Final

from .descriptor import SourceDescriptor

BUILTIN: Final = (
    "..tecomat.descriptor",
    "..mervis.descriptor",
    "..panasonic.descriptor",
    "..tekon.descriptor",
)
"""The modules whose ``DESCRIPTORS`` are the built-in sources, in menu order."""

_registered: dict[str, SourceDescriptor] = {}
_builtin: dict[str, SourceDescriptor] = {}


def _load_builtin() -> dict[str, SourceDescriptor]:
    """Import the built-in systems' descriptors (once)."""
    if not _builtin:
        for module_name in BUILTIN:
            module = importlib.import_module(module_name, __package__)
            descriptors: tuple[SourceDescriptor, ...] = module.DESCRIPTORS
            _builtin.update((item.name, item) for item in descriptors)
    return _builtin


def sources() -> tuple[SourceDescriptor, ...]:
    """Every source, the built-in ones first."""
    return (*_load_builtin().values(), *_registered.values())


def source(name: str) -> SourceDescriptor:
    """Return the descriptor of a name; KeyError when there is none."""
    if (found := _load_builtin().get(name) or _registered.get(name)) is None:
        raise KeyError(name)
    return found


def find(name: str) -> SourceDescriptor | None:
    """Return the descriptor of a name, or None."""
    return _load_builtin().get(name) or _registered.get(name)


def register(descriptor: SourceDescriptor) -> Callable[[], None]:
    """Offer another source; returns the function that takes it back.

    A name is one source's forever: a built-in name, or one registered already,
    is refused (ValueError).
    """
    name = descriptor.name
    if name in _load_builtin() or name in _registered:
        raise ValueError(f"a source named {name!r} exists")

    def unregister() -> None:
        if _registered.get(name) is descriptor:
            del _registered[name]

    _registered[name] = descriptor
    return unregister


_load_builtin()
