"""What each source's forms need: the config flow builds them from its descriptor."""

from collections.abc import Iterable

from custom_components.tecoapi.const import DeviceGrouping
from custom_components.tecoapi.flows.options import MAP_MENU
from custom_components.tecoapi.flows.point_map import point_schema
from custom_components.tecoapi.options import options_schema
from custom_components.tecoapi.pyplc.core.descriptor import (
    CONF_POINT_MAP,
    Capability,
    FieldKind,
    SourceDescriptor,
)

from .common import KeyPath
from .usage import TranslationUsage


def descriptor_usage(
    usage: TranslationUsage, descriptors: Iterable[SourceDescriptor]
) -> None:
    """Add what each source's forms need: the config flow builds them from its descriptor.

    The first step's menu offers each source; its connect and reconfigure forms
    show its fields (and its form placeholders), reauthentication and a
    discovered device's confirmation its credentials; its errors are form errors
    (a push server's, the options' too), its probe's answers abort reasons. A
    form that uploads a point map shows the upload's errors, naming ``{error}``;
    the forms that check a connection show what an error rule's message names
    of its failure (``{code}``). A source whose points the user supplies has
    its forms of one point in its own words (its ``Words``' step IDs), each
    field labelled, and its error of a point its device does not read.
    """

    def need(path: KeyPath, where: str) -> None:
        usage.required.setdefault(path, where)

    def provide(path: KeyPath, names: Iterable[str], where: str) -> None:
        provided = frozenset(names)
        if path in usage.placeholders:
            known, first = usage.placeholders[path]
            usage.placeholders[path] = (known & provided, first)
        else:
            usage.placeholders[path] = (provided, where)

    by_name = {descriptor.name: descriptor for descriptor in descriptors}
    for descriptor in by_name.values():
        where = f"descriptor {descriptor.name}"
        connect, reconfigure = descriptor.connect, descriptor.reconfigure
        need(("config", "step", "user", "menu_options", connect.step_id), where)
        uploads = any(field.kind is FieldKind.POINT_MAP for field in connect.fields)
        shown = {name for rule in descriptor.errors for name in rule.placeholders}
        for form in (connect, reconfigure):
            for item in form.fields:
                need(("config", "step", form.step_id, "data", item.key), where)
            extra = shown | ({"error"} if uploads and form is connect else set())
            provide(
                ("config", "step", form.step_id), {*form.placeholders, *extra}, where
            )
        words = descriptor.words
        steps = [words.reauth_step_id] if descriptor.credentials else []
        if descriptor.probe is not None:
            steps.append("dhcp_confirm")
        for step in steps:
            for item in descriptor.credentials:
                need(("config", "step", step, "data", item.key), where)
            provide(("config", "step", step), {*connect.placeholders, "host"}, where)
        for rule in descriptor.errors:
            need(("config", "error", rule.key), where)
        if uploads:
            need(("config", "error", "point_map_invalid"), where)
            need(("config", "error", "point_map_missing"), where)
            # A new entry says how many points its file holds.
            need(("config", "create_entry", "point_map"), where)
            provide(
                ("config", "create_entry", "point_map"),
                {"points", "entities", "skipped"},
                where,
            )
        if Capability.POINT_MAP in descriptor.capabilities:
            # A newer file is checked on the device: its errors are the options'.
            # The failure's details go with its error, as in the config flow.
            for rule in descriptor.errors:
                need(("options", "error", rule.key), where)
                provide(("options", "error", rule.key), rule.placeholders, where)
            need(("options", "error", "point_map_other_device"), where)
            # Its forms of one point, in its words: every field labelled, and
            # the error of a point its device does not read (with the reason).
            words = descriptor.words
            for step, with_id, shown in (
                (words.add_point_step_id, True, {"error"}),
                (words.point_step_id, False, {"error", "point"}),
            ):
                need(("options", "step", step, "title"), where)
                for marker in point_schema(
                    descriptor.point_types, with_id=with_id
                ).schema:
                    need(("options", "step", step, "data", str(marker)), where)
                provide(("options", "step", step), shown, where)
            need(("options", "error", words.point_refused), where)
            provide(("options", "error", words.point_refused), {"error"}, where)
        for reason in descriptor.probe_reasons:
            need(("config", "abort", reason), where)
        if (companion := descriptor.companion) is not None:
            # Its push server's check: the options' errors.
            for rule in companion.errors:
                need(("options", "error", rule.key), where)
            need(("options", "error", companion.other_device), where)
        # The repair of the points its device refuses, in its own words.
        need(("issues", words.points_refused), where)
        provide(("issues", words.points_refused), {"name", "points"}, where)
        # Its abort reasons, in its own words.
        for reason in (
            words.already_configured,
            words.wrong_device,
            words.reconfigured,
        ):
            need(("config", "abort", reason), where)
        # The options form: the fields its capabilities use, on the first step
        # (or, for a source with a map, on its settings step behind its menu),
        # its device grouping's choices labelled in its words.
        step = words.options_step_id
        if Capability.POINT_MAP in descriptor.capabilities:
            for option in MAP_MENU:
                need(("options", "step", step, "menu_options", option), where)
            assert words.settings_step_id != step, where  # its own, behind the menu
            # Its upload form, in its words (an unreadable file's reason: {error}).
            upload = ("options", "step", words.upload_step_id)
            need((*upload, "title"), where)
            need((*upload, "data", CONF_POINT_MAP), where)
            provide(upload, {"error"}, where)
        step = words.settings_step_id
        need(("options", "step", step, "title"), where)
        for marker in options_schema(descriptor).schema:
            need(("options", "step", step, "data", str(marker)), where)
        for grouping in DeviceGrouping:
            need(("selector", words.devices, "options", grouping.value), where)
        if companion is not None:
            # Its push server's section, of the fields it declares.
            for item in companion.fields:
                need(
                    ("options", "step", step, "sections", "push", "data", item.key),
                    where,
                )
