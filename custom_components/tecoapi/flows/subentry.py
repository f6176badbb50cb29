"""The subentry flow: a typed device composed of the points the user chooses.

Each kind the UI offers is a subentry type (a thermostat, a blind, a light, a
button, a switch); its roles list the entry's points that fit them
(``pyplc.core.devices``).
"""

from collections.abc import Mapping
from typing import Any, Final

from homeassistant.config_entries import (
    ConfigEntry,
    ConfigEntryState,
    ConfigSubentryFlow,
    SubentryFlowResult,
)
from homeassistant.data_entry_flow import AbortFlow
from homeassistant.helpers.selector import (
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)

from ..compat import vol
from ..mapping import point_label
from ..pyplc.core.composition import (
    COMPOSITIONS,
    CompositionError,
    compose,
    fitting_points,
)
from ..pyplc.core.devices import DeviceKind

# The composed devices the UI offers (subentry types), and their kinds.
COMPOSED_KINDS: Final[dict[str, DeviceKind]] = {
    "thermostat": DeviceKind.CLIMATE,
    "blind": DeviceKind.COVER,
    "light": DeviceKind.LIGHT,
    "button": DeviceKind.BUTTON,
    "switch": DeviceKind.SWITCH,
}
CONF_KIND: Final = "kind"
CONF_ROLES: Final = "roles"
CONF_NAME: Final = "name"


class CompositionFlow(ConfigSubentryFlow):
    """Add (or change) a typed device made of points the user chooses.

    Each role lists only the points that fit it, shown by title and path; the
    choice is checked as a whole (``pyplc.core.composition.compose``) before it is
    stored. The entry shows the device at once (the other entities stay as
    they are).
    """

    async def async_step_user(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Ask for a name and the points of each role.

        Nothing is chosen for the user: the frontend would preselect the first
        point of each required role (the outside temperature as a room's).
        """
        entry = self._loaded_entry()
        composed, errors = self._composed(entry, user_input)
        if composed is not None:
            return self.async_create_entry(title=composed[0], data=composed[1])
        unchosen = {spec.role.value: "" for spec in COMPOSITIONS[self._kind].roles}
        return self.async_show_form(
            step_id="user",
            data_schema=self.add_suggested_values_to_schema(
                self._schema(entry), user_input or unchosen
            ),
            errors=errors,
        )

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Choose other points (a variable vanished with a new program) or a name."""
        entry = self._loaded_entry()
        subentry = self._get_reconfigure_subentry()
        composed, errors = self._composed(entry, user_input)
        if composed is not None:
            return self.async_update_and_abort(
                entry, subentry, title=composed[0], data=composed[1]
            )
        suggested = user_input or {
            CONF_NAME: subentry.title,
            **subentry.data[CONF_ROLES],
        }
        return self.async_show_form(
            step_id="reconfigure",
            data_schema=self.add_suggested_values_to_schema(
                self._schema(entry), suggested
            ),
            errors=errors,
        )

    @property
    def _kind(self) -> DeviceKind:
        return COMPOSED_KINDS[self._subentry_type]

    def _schema(self, entry: ConfigEntry) -> vol.Schema:
        """Return the form: a name, then a list of fitting points per role."""
        points = entry.runtime_data.data.catalogue.points
        fields: dict[Any, Any] = {vol.Required(CONF_NAME): TextSelector()}
        for spec in COMPOSITIONS[self._kind].roles:
            options = [
                SelectOptionDict(value=point.key, label=point_label(point))
                for point in fitting_points(self._kind, spec.role, points)
            ]
            key = (vol.Required if spec.required else vol.Optional)(spec.role.value)
            fields[key] = SelectSelector(
                SelectSelectorConfig(options=options, mode=SelectSelectorMode.DROPDOWN)
            )
        return vol.Schema(fields)

    def _loaded_entry(self) -> ConfigEntry:
        """Return the entry; its points are offered, so it must be loaded."""
        entry = self._get_entry()
        if entry.state is not ConfigEntryState.LOADED:
            raise AbortFlow("entry_not_loaded")
        return entry

    def _composed(
        self, entry: ConfigEntry, user_input: Mapping[str, Any] | None
    ) -> tuple[tuple[str, dict[str, Any]] | None, dict[str, str]]:
        """Return the subentry's title and data, or the form's errors.

        Neither is there before a submit; the choice is checked as a whole.
        """
        if user_input is None:
            return None, {}
        roles = {
            role: key for role, key in user_input.items() if role != CONF_NAME and key
        }
        name = user_input[CONF_NAME].strip()
        if not name:
            return None, {CONF_NAME: "name_missing"}
        try:
            compose(
                self._kind,
                roles,
                entry.runtime_data.data.catalogue.points,
                ident="check",
            )
        except CompositionError as err:
            return None, {str(err.role or "base"): err.problem.value}
        return (name, {CONF_KIND: self._kind.value, CONF_ROLES: roles}), {}
