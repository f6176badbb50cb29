"""What the library says, in the reader's words: its texts in Home Assistant's language.

The library tells a user what happened as a text (``pyplc.core.texts``): a
key, its parameters and its English. Each key is a text of this integration
(``exceptions.<key>.message``, beside the errors Home Assistant shows by
their own key) in each of its languages. A form's, a repair's or an error
message's ``{error}`` is filled with it in Home Assistant's language, the
language Home Assistant writes repairs and error messages in: a map's row
that cannot be read, a value that does not fit, a point the device refuses,
a failure of the device. The device's own words (its code, its message) are
not translated: they follow "the device says:".

A flow loads the texts before it fills one (:func:`async_load_texts`; it may
run before the entry is set up); an entry has them from its setup, when Home
Assistant loads the integration's texts in its language. A language not
loaded yet (just changed) gives the library's English.
"""

from typing import Final

from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import translation

from .const import DOMAIN
from .pyplc import PlcError, PointQuality
from .pyplc.core.pointmap import PointMapError
from .pyplc.core.texts import DEVICE_SAYS, Text

CATEGORY: Final = "exceptions"
"""Where the library's texts are among the integration's translations."""


async def async_load_texts(hass: HomeAssistant) -> None:
    """Load the library's texts in Home Assistant's language (kept once loaded)."""
    await translation.async_get_translations(
        hass, hass.config.language, CATEGORY, {DOMAIN}
    )


@callback
def said(hass: HomeAssistant | None, text: Text) -> str:
    """Return one of the library's texts in Home Assistant's language.

    Without Home Assistant (None: a caller outside its loop), the library's English.
    """
    if hass is None:
        return str(text)
    key = f"component.{DOMAIN}.{CATEGORY}.{text.key}.message"
    texts = translation.async_get_cached_translations(
        hass, hass.config.language, CATEGORY, DOMAIN
    )
    if not (found := texts.get(key)):
        return str(text)
    return text.format(found)


@callback
def device_says(hass: HomeAssistant | None, words: str) -> str:
    """Return the device's own words, as said to come from it."""
    return said(hass, DEVICE_SAYS(said=words))


@callback
def error_text(hass: HomeAssistant | None, err: PlcError) -> str:
    """Return what a failure says: what happened, then the device's own words."""
    text = said(hass, err.text())
    return f"{text} ({device_says(hass, err.said)})" if err.said else text


@callback
def error_detail(hass: HomeAssistant | None, err: PlcError) -> str:
    """Return the device's own words of a failure, else what happened.

    For a text that says what happened already (its key is the failure's).
    """
    return device_says(hass, err.said) if err.said else said(hass, err.text())


@callback
def quality_text(hass: HomeAssistant | None, quality: PointQuality) -> str:
    """Return why a point is not read: the source's reason, or the device's words."""
    if quality.text is not None:
        return said(hass, quality.text)
    return device_says(hass, quality.reason)


@callback
def map_error_text(hass: HomeAssistant | None, err: PointMapError) -> str:
    """Return what is wrong with a map: where in the file (its row), then what."""
    what = said(hass, err.text)
    if (where := err.where) is None:
        return what
    return f"{said(hass, where)}: {what}"
