"""Tecomat programs for the typed-device tests: T_ApiObjects, GTSAP1 families, discovery."""

from collections.abc import Mapping
from typing import Any

from custom_components.tecoapi.pyplc import Point
from custom_components.tecoapi.pyplc.core.devices import (
    DeviceCatalogue,
    TypedDevice,
    find_devices,
)
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS
from custom_components.tecoapi.pyplc.tecomat.tecoapi.catalogue import build_catalogue

ATTR = {
    "enable": True,
    "visibility": True,
    "readOnly": False,
    "title": "",
    "minValue": 0.0,
    "maxValue": 0.0,
    "units": "",
}


def api(value: Any, **attr: Any) -> dict[str, Any]:
    """A T_ApiObject as GetObject answers it (writable, no range unless told)."""
    return {"value": value, "attr": ATTR | attr}


def family(base: str, family_type: str, **properties: Any) -> dict[str, Any]:
    """The top-level variables of one GTSAP1 family."""
    return {
        f"{base}_GTSAP1_{family_type}_{prop}": value
        for prop, value in properties.items()
    }


def discover(tree: Mapping[str, Any]) -> tuple[DeviceCatalogue, dict[str, Point]]:
    """Devices of a GetObject tree, through the real catalogue walker and Tecomat's
    recognisers."""
    catalogue = build_catalogue(list(tree), tree)
    found = find_devices(catalogue.points, catalogue.values, RECOGNISERS)
    return found, dict(catalogue.points)


def only(found: DeviceCatalogue) -> TypedDevice:
    assert len(found.devices) == 1, found.skipped
    return next(iter(found.devices.values()))
