"""descriptor_usage: a source's forms are built from its descriptor."""

from scripts.checks.common import dotted
from scripts.checks.descriptors import descriptor_usage
from scripts.checks.usage import TranslationUsage
from tests.fake_source import MEMORY


def test_checker_reads_what_a_descriptor_s_forms_need() -> None:
    """A source's forms are built from its descriptor: the checker asks for their keys."""
    usage = TranslationUsage()
    descriptor_usage(usage, [MEMORY])
    needed = {dotted(path) for path in usage.required}
    assert {
        "config.step.user.menu_options.memory",
        "config.step.memory.data.host",
        "config.step.memory.data.point_map",
        "config.step.reconfigure_memory.data.host",
        "config.error.cannot_connect",
        "config.error.point_map_invalid",
        "options.step.settings.data.scan_interval",
    } <= needed
    assert "options.step.settings.data.attribute_interval" not in needed
    assert usage.placeholders[("config", "step", "memory")][0] == {"error"}
