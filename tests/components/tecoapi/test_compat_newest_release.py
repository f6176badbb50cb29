"""What Home Assistant 2026.11 expects of the integration, checked on every release.

The test environments run 2026.10 and 2026.2, which neither warn nor fail where
2026.11 does; these tests hold the integration to 2026.11's rules directly, and
the smoke run (scripts/smoke) runs it on the newest release itself.
"""

import importlib

from homeassistant.exceptions import ConfigEntryError
from homeassistant.helpers.entity import Entity
import pytest

from custom_components.tecoapi import PLATFORMS, compat
from custom_components.tecoapi.climate import PlcClimate

# ClimateEntity's members 2026.11 deprecates, each with the names that replace it
# (homeassistant/components/climate/entity.py there). A class that provides one
# without a replacement, or below the class that provides the replacement, is warned
# about at import ("... provides the deprecated ..., this will stop working in Home
# Assistant 2027.11"; homeassistant.helpers.deprecation.migrate_deprecated_entity_members).
_TEMPERATURES = (
    "temperature_unit",
    "current_temperature",
    "target_temperature",
    "target_temperature_high",
    "target_temperature_low",
)
CLIMATE_RENAMED: dict[str, frozenset[str]] = {
    **{
        name: frozenset({f"native_{name}", f"_attr_native_{name}"})
        for name in _TEMPERATURES
    },
    **{f"_attr_{name}": frozenset({f"_attr_native_{name}"}) for name in _TEMPERATURES},
}
# What an entity that changes its entity ID in place must not extend without also
# taking the change (homeassistant.helpers.entity._ADD_REMOVE_METHODS, 2026.11).
ADD_REMOVE_METHODS = (
    "async_prepare_to_add_to_hass",
    "async_added_to_hass",
    "async_will_remove_from_hass",
)


def _ours(cls: type) -> bool:
    return not cls.__module__.startswith("homeassistant.")


@pytest.mark.parametrize("name", sorted(CLIMATE_RENAMED))
def test_the_thermostat_gives_every_temperature_its_native_name(name: str) -> None:
    """The class that gives a temperature by its old name gives the native one too."""
    replacements = CLIMATE_RENAMED[name]
    provider = next(
        cls
        for cls in PlcClimate.__mro__
        if name in vars(cls) or not replacements.isdisjoint(vars(cls))
    )
    assert not _ours(provider) or not replacements.isdisjoint(vars(provider))


def _entity_classes() -> set[type[Entity]]:
    """Every entity class of the integration (its platforms imported)."""
    for platform in PLATFORMS:
        importlib.import_module(f"custom_components.tecoapi.{platform}")
    found: set[type[Entity]] = set()
    pending: list[type[Entity]] = [Entity]
    while pending:
        for subclass in pending.pop().__subclasses__():
            if subclass not in found:
                found.add(subclass)
                pending.append(subclass)
    return {cls for cls in found if cls.__module__.startswith("custom_components.")}


def test_every_entity_takes_a_new_entity_id_in_place() -> None:
    """No entity class extends adding or removal without taking an entity ID change.

    2026.11 renames such an entity in place; others it removes and adds again, a way
    it drops in 2027.11 (homeassistant.helpers.entity._entity_class_requires_readd).
    """
    classes = _entity_classes()
    assert PlcClimate in classes

    def readds(entity_class: type[Entity]) -> bool:
        ours = [cls for cls in entity_class.__mro__ if _ours(cls)]
        takers = [cls for cls in ours if "async_entity_id_changed" in vars(cls)]
        return any(
            any(method in vars(cls) for method in ADD_REMOVE_METHODS)
            and not any(issubclass(taker, cls) for taker in takers)
            for cls in ours
        )

    assert sorted(cls.__qualname__ for cls in classes if readds(cls)) == []


@pytest.mark.parametrize("returns_none", [False, True])
def test_an_entry_method_returns_what_the_release_expects(
    monkeypatch: pytest.MonkeyPatch, returns_none: bool
) -> None:
    """2026.11: None, a failure raises; before: whether it succeeded."""
    monkeypatch.setattr(compat, "ENTRY_RESULT_NONE", returns_none)
    if returns_none:
        assert compat.entry_result(True) is None
        with pytest.raises(ConfigEntryError) as raised:
            compat.entry_result(False)
        assert raised.value.translation_key == "unload_platforms_failed"
    else:
        assert compat.entry_result(True) is True
        assert compat.entry_result(False) is False


def test_the_release_is_told_by_what_it_has() -> None:
    """2026.11 brought async_unload_platforms_or_raise with the None results."""
    from homeassistant.const import MAJOR_VERSION, MINOR_VERSION

    assert compat.ENTRY_RESULT_NONE is ((MAJOR_VERSION, MINOR_VERSION) >= (2026, 11))
