"""Which systems' catalogues Tecomat's typed-device conventions are searched in."""

from custom_components.tecoapi.pyplc.core import registry
from custom_components.tecoapi.pyplc.tecomat.conventions import RECOGNISERS
from custom_components.tecoapi.pyplc.tecomat.gtsap1 import GTSAP1
from custom_components.tecoapi.pyplc.tecomat.structs import STRUCTS


def test_gtsap1_families_come_before_structs() -> None:
    assert RECOGNISERS == (GTSAP1, STRUCTS)
    assert [recogniser.name for recogniser in RECOGNISERS] == ["gtsap1", "struct"]


def test_every_built_in_system_registers_them() -> None:
    """Every catalogue was searched for both before systems registered their own:
    a Mervis function block's members follow the struct convention, and a map's
    or a gateway's names may follow either. Their devices stay."""
    builtin = {
        descriptor.name: descriptor.recognisers
        for descriptor in registry.sources()
        if descriptor.name in {"tecoapi", "plccoms", "mervis", "fpi4c", "tekon"}
    }
    assert builtin == dict.fromkeys(
        ("tecoapi", "plccoms", "mervis", "fpi4c", "tekon"), RECOGNISERS
    )
