"""How Home Assistant words a deprecation it reports about this integration.

Plain `re` only: the smoke run on the newest release (tests/e2e/smoke.py) imports
it in an environment without the tests' dependencies.
"""

import re
from typing import Final

DEPRECATION_WORDING: Final = (
    # A deprecated entity member a class provides (2026.11: climate's temperatures).
    "provides the deprecated",
    # What every deprecation report says of its end.
    "will stop working in",
    # Deprecated constants, functions and classes.
    "is deprecated",
    "called from custom integration",
    # The request at the end of a report about a custom integration.
    "please report it to the custom integration author",
)

DEPRECATED_USE: Final = re.compile(
    # Reports through Home Assistant's frame helper name the integration.
    r"custom integration 'tecoapi'|'tecoapi' custom integration|used from tecoapi\b"
    # Any other wording counts where the integration is named: its logger, a module
    # or class of it (the 2026.11 lines name the class, `...tecoapi.climate::...`).
    r"|(?is:^(?=.*tecoapi).*(?:"
    + "|".join(re.escape(words) for words in DEPRECATION_WORDING)
    + "))"
)
"""Home Assistant's words for a deprecated call, constant or member of this integration.

Searched in a log line (with its logger's name) or a record's logger name and message.
"""
