"""Typed devices of programs discovered over real HTTP from the simulator."""

from typing import Any

import aiohttp

from custom_components.tecoapi.pyplc import Catalogue
from custom_components.tecoapi.pyplc.core.devices import (
    ClimateSupport,
    CoverClass,
    DeviceCatalogue,
    DeviceKind,
    LightMode,
    Measurement,
    Role,
    TypedDevice,
    find_devices,
    kelvin_range,
    setpoint_range,
)
from custom_components.tecoapi.pyplc.tecomat import TecoApiClient
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS
from tests.pyplc.conftest import StartSimulator, make_client
from tests.simulator import Program, Simulator

# The demo's typed devices: key -> (kind, name, feature).
DEMO_DEVICES: dict[str, tuple[DeviceKind, str, object]] = {
    "gtsap1:light:obyvak_strop": (
        DeviceKind.LIGHT,
        "Obývák strop",
        LightMode.BRIGHTNESS,
    ),
    "gtsap1:light:kuchyne_linka": (DeviceKind.LIGHT, "Kuchyňská linka", LightMode.RGB),
    "gtsap1:light:loznice": (DeviceKind.LIGHT, "Ložnice", LightMode.COLOR_TEMP),
    "gtsap1:light:chodba": (DeviceKind.LIGHT, "Chodba", LightMode.ONOFF),
    "gtsap1:socket:terasa": (DeviceKind.SWITCH, "Zásuvka terasa", None),
    "gtsap1:relay:zavlaha": (DeviceKind.SWITCH, "Závlaha zahrady", None),
    "gtsap1:contact:vstup": (DeviceKind.CONTACT, "Vstupní dveře", None),
    "gtsap1:display:obyvak": (DeviceKind.DISPLAY, "Obývák CO2", Measurement.CO2),
    "gtsap1:button:dvere_tlacitko": (DeviceKind.BUTTON, "Tlačítko u dveří", None),
    "gtsap1:opener:stineni.obyvak_zaluzie": (
        DeviceKind.COVER,
        "Obývák žaluzie",
        CoverClass.SHUTTER,
    ),
    "gtsap1:opener:stineni.loznice_roleta": (
        DeviceKind.COVER,
        "Ložnice roleta",
        CoverClass.SHUTTER,
    ),
    "gtsap1:opener:stineni.vjezd": (
        DeviceKind.COVER,
        "Vjezdová brána",
        CoverClass.GATE,
    ),
    "gtsap1:opener:stineni.garaz_vrata": (
        DeviceKind.COVER,
        "Garážová vrata",
        CoverClass.GATE,
    ),
    "gtsap1:thermostat:termostaty.obyvak": (
        DeviceKind.CLIMATE,
        "Obývák",
        ClimateSupport.BOTH,
    ),
    "gtsap1:thermostat:termostaty.loznice": (
        DeviceKind.CLIMATE,
        "Ložnice",
        ClimateSupport.HEATING,
    ),
    "gtsap1:thermostat:termostaty.pracovna": (
        DeviceKind.CLIMATE,
        "Pracovna",
        ClimateSupport.COOLING,
    ),
    "struct:climate:detskypokoj.thermostat": (
        DeviceKind.CLIMATE,
        "Thermostat",
        ClimateSupport.HEATING,
    ),
    "struct:cover:detskypokoj.blind": (DeviceKind.COVER, "Blind", CoverClass.SHUTTER),
    "struct:light:detskypokoj.light": (DeviceKind.LIGHT, "Light", LightMode.BRIGHTNESS),
    "struct:light:podkrovi.satnasvetlo": (
        DeviceKind.LIGHT,
        "Satna svetlo",
        LightMode.COLOR_TEMP,
    ),
    "struct:cover:podkrovi.stresniokno": (
        DeviceKind.COVER,
        "Stresni okno",
        CoverClass.SHUTTER,
    ),
}


def feature(device: TypedDevice) -> object:
    return (
        device.light_mode or device.cover_class or device.climate or device.measurement
    )


async def devices_of(client: TecoApiClient) -> tuple[DeviceCatalogue, Catalogue]:
    catalogue = await client.discover()
    return find_devices(catalogue.points, catalogue.values, RECOGNISERS), catalogue


async def test_the_demo_programs_devices(client: TecoApiClient) -> None:
    found, catalogue = await devices_of(client)

    assert {
        key: (device.kind, device.name, feature(device))
        for key, device in found.devices.items()
    } == DEMO_DEVICES
    assert found.skipped == {}
    # Every GTSAP1 variable and every member of the typed structs is consumed;
    # nothing else is.
    typed_structs = ("detskypokoj.", "podkrovi.")
    expected = {
        key
        for key in catalogue.points
        if "gtsap1_" in key or key.startswith(typed_structs)
    }
    assert found.consumed == expected
    # Attributes and values keep doing their job.
    values = catalogue.values
    points = catalogue.points
    devices = found.devices
    living = devices["gtsap1:thermostat:termostaty.obyvak"]
    assert setpoint_range(living, points, values) == (16.0, 28.0)
    kids = devices["struct:climate:detskypokoj.thermostat"]
    assert setpoint_range(kids, points, values) == (16.0, 26.0)
    bedroom = devices["gtsap1:light:loznice"]
    assert kelvin_range(bedroom, points, values) == (2200, 5000)
    wardrobe = devices["struct:light:podkrovi.satnasvetlo"]
    assert kelvin_range(wardrobe, points, values) == (2700, 6500)
    kitchen = devices["gtsap1:light:kuchyne_linka"]
    assert values[kitchen.roles[Role.RGB]] == 255 + 128 * 256
    ceiling = devices["gtsap1:light:obyvak_strop"]
    assert ceiling.roles[Role.TARGET_LEVEL] == "obyvak_strop_gtsap1_light_tgtlevel"
    roof = devices["struct:cover:podkrovi.stresniokno"]
    assert roof.roles[Role.TARGET] == "podkrovi.stresniokno.position"


def changed_demo(simulator: Simulator) -> Program:
    """The demo downloaded again with typed devices added, removed and changed."""
    source = simulator.program.to_mapping()
    variables: dict[str, Any] = source["variables"]
    # Removed: the hall light's family, and the kids room blind's position (its
    # struct is no blind any more: its target and moving flag become raw).
    for prop in ("onoff", "type", "name"):
        del variables[f"CHODBA_GTSAP1_LIGHT_{prop}"]
    del source["types"]["TBlind"]["position"]
    del variables["detskyPokoj"]["value"]["blind"]["position"]
    # Added: a study light.
    variables["PRACOVNA_GTSAP1_LIGHT_onoff"] = {"type": "BOOL", "value": True}
    # Changed: the kitchen strip is brightness only now, the study thermostat
    # heats too, the blind is renamed; a family is spelled in other letter case
    # and moved to the end of the program.
    variables["KUCHYNE_LINKA_GTSAP1_LIGHT_dimtype"]["value"] = 0
    thermostats = variables["Termostaty"]["variables"]
    thermostats["PRACOVNA_GTSAP1_THERMOSTAT_type"]["value"] = 3
    shading = variables["Stineni"]["variables"]
    shading["OBYVAK_ZALUZIE_GTSAP1_OPENER_name"]["value"] = "Velká žaluzie"
    for prop in ("CLICKCNT", "PRESSCNT", "name"):
        spec = variables.pop(f"DVERE_TLACITKO_GTSAP1_BUTTON_{prop}")
        variables[f"Dvere_Tlacitko_gtsap1_button_{prop}"] = spec
    return Program.from_mapping(source)


async def test_program_downloads_keep_keys_of_the_same_variables(
    simulator: Simulator, client: TecoApiClient
) -> None:
    before, _ = await devices_of(client)

    simulator.load_program(changed_demo(simulator))
    after, catalogue = await devices_of(client)

    assert set(before.devices) - set(after.devices) == {
        "gtsap1:light:chodba",
        "struct:cover:detskypokoj.blind",
    }
    assert set(after.devices) - set(before.devices) == {"gtsap1:light:pracovna"}
    for key in set(before.devices) & set(after.devices):
        old, new = before.devices[key], after.devices[key]
        assert (new.kind, new.source, new.base.lower()) == (
            old.kind,
            old.source,
            old.base.lower(),
        )
    devices = after.devices
    assert devices["gtsap1:light:kuchyne_linka"].light_mode is LightMode.BRIGHTNESS
    study = devices["gtsap1:thermostat:termostaty.pracovna"]
    assert study.climate is ClimateSupport.BOTH
    assert devices["gtsap1:opener:stineni.obyvak_zaluzie"].name == "Velká žaluzie"
    button = devices["gtsap1:button:dvere_tlacitko"]
    assert button.base == "Dvere_Tlacitko"
    assert button.roles == {
        Role.CLICK_COUNT: "dvere_tlacitko_gtsap1_button_clickcnt",
        Role.PRESS_COUNT: "dvere_tlacitko_gtsap1_button_presscnt",
        Role.NAME: "dvere_tlacitko_gtsap1_button_name",
    }
    # The vanished blind's remaining members are raw points again.
    assert "detskypokoj.blind.target" in catalogue.points
    assert "detskypokoj.blind.target" not in after.consumed

    simulator.load_program("demo")
    again, _ = await devices_of(client)
    assert again.devices == before.devices


async def test_gtsap1_text_values_over_http(
    start_simulator: StartSimulator, session: aiohttp.ClientSession
) -> None:
    """A program keeping its GTSAP1 values as text with a decimal comma."""
    source = {
        "plc": {
            "family": "Fx2",
            "type": "CP-2080",
            "serialNumber": "SD 0001",
            "version": "Fx2 CP2080I v1.1",
            "mac": "00-0A-14-00-00-01",
        },
        "program": {"name": "TEXTY", "compiled": "2026-01-01T00:00:00.000Z"},
        "variables": {
            "Main": {
                "program": "prgMain",
                "variables": {
                    "KOUPELNA_GTSAP1_THERMOSTAT_meastemp": {
                        "type": "STRING[16]",
                        "value": "23,4",
                    },
                    "KOUPELNA_GTSAP1_THERMOSTAT_setpoint": {
                        "type": "STRING[16]",
                        "value": "24,0",
                    },
                    "KOUPELNA_GTSAP1_THERMOSTAT_heatmode": {"type": "INT", "value": 1},
                    "KOUPELNA_GTSAP1_THERMOSTAT_type": {
                        "type": "STRING[4]",
                        "value": "2",
                    },
                },
            }
        },
    }
    sim = await start_simulator(Program.from_mapping(source))
    found, catalogue = await devices_of(make_client(session, sim))

    climate = found.devices["gtsap1:thermostat:main.koupelna"]
    assert climate.climate is ClimateSupport.HEATING
    assert climate.name == "Koupelna"
    assert set(climate.roles) == {Role.TEMPERATURE, Role.SETPOINT, Role.HEAT_MODE}
    temperature = catalogue.values[climate.roles[Role.TEMPERATURE]]
    assert climate.readings.number(temperature) == 23.4
    assert len(found.consumed) == 4
