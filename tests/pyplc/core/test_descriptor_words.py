"""A source's words: its options open on a menu, its settings on a step of their own."""

from dataclasses import replace

import pytest

from custom_components.tecoapi.pyplc.core.descriptor import Words
from custom_components.tecoapi.pyplc.core.registry import sources


def test_every_source_s_settings_have_a_step_of_their_own() -> None:
    for descriptor in sources():
        words = descriptor.words
        assert words.settings_step_id != words.options_step_id, descriptor.name


def test_a_source_whose_settings_share_its_menu_s_step_is_refused() -> None:
    """Every source's options open on a menu: its settings cannot share its step."""
    tekon = next(item for item in sources() if item.name == "tekon")

    with pytest.raises(ValueError, match="steps of their own"):
        replace(tekon, words=Words(options_step_id="tekon"))
