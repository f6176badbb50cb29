"""The library's texts: a key a caller translates, its parameters, its English."""

from collections.abc import Iterator

import pytest

from custom_components.tecoapi.pyplc.core import exceptions as plc
from custom_components.tecoapi.pyplc.core.pointmap import PointMapError, load_csv
from custom_components.tecoapi.pyplc.core.texts import TEMPLATES, Template, Text


@pytest.fixture(autouse=True)
def registry() -> Iterator[None]:
    """The library's templates as they were: a test's own leave with it."""
    kept = dict(TEMPLATES)
    yield
    TEMPLATES.clear()
    TEMPLATES.update(kept)


def test_a_text_is_its_template_s_key_and_english_filled_with_its_parameters() -> None:
    template = Template("test_reading", "{name} reads {value} at {row}")
    text = template(name="Boiler", value=21.5, row=3)

    assert isinstance(text, Text)
    assert text.key == "test_reading"
    assert dict(text.params) == {"name": "Boiler", "value": "21.5", "row": "3"}
    assert str(text) == "Boiler reads 21.5 at 3"
    assert template.params == frozenset({"name", "value", "row"})
    assert TEMPLATES["test_reading"] is template


def test_a_parameter_a_text_lacks_stays_a_placeholder() -> None:
    text = Template("test_lacking", "{name} reads {value}")(name="Boiler")
    assert str(text) == "Boiler reads {value}"
    assert text.format("{name}: {value}") == "Boiler: {value}"


def test_a_key_names_one_english_text() -> None:
    Template("test_twice", "one text")
    Template("test_twice", "one text")  # the same again: no second meaning
    with pytest.raises(ValueError, match="test_twice"):
        Template("test_twice", "another text")


def test_a_map_s_error_is_a_text_and_where_it_is() -> None:
    """What a form shows of a row (translated), and the English of a log."""
    with pytest.raises(PointMapError) as raised:
        load_csv("name,address,type\nBoiler,DT0,QWORD\n", types=("int", "real"))

    error = raised.value
    assert (error.key, dict(error.params)) == (
        "map_unknown_type",
        {"type": "'QWORD'", "known": "INT, REAL"},
    )
    assert error.where is not None
    assert (error.where.key, dict(error.where.params)) == (
        "map_at_cell",
        {"row": "2", "column": "type"},
    )
    assert str(error) == "row 2, column type: unknown type 'QWORD' (known: INT, REAL)"
    assert error.message == "unknown type 'QWORD' (known: INT, REAL)"


@pytest.mark.parametrize(
    ("error", "key", "params", "said"),
    [
        (
            plc.PlcConnectionError("Cannot talk to x: OSError"),
            "error_connection",
            {},
            "",
        ),
        (plc.PlcTlsError("untrusted"), "error_tls", {}, ""),
        (
            plc.VariableNotFoundError(
                "Variable 'x' is not found",
                path="x",
                code="400.005",
                said="400.005: Variable 'x' is not found",
            ),
            "error_not_found",
            {"path": "x"},
            "400.005: Variable 'x' is not found",
        ),
        (
            plc.OutOfRangeError("x", 120, 0, 100),
            "error_out_of_range",
            {"low": "0", "high": "100"},
            "",
        ),
        (
            plc.InvalidWriteError("x", 1, "a source's own reason"),
            "error_invalid_write",
            {},
            "",
        ),
        (plc.PlcError("anything"), "error_failed", {}, ""),
    ],
    ids=lambda value: type(value).__name__ if isinstance(value, Exception) else None,
)
def test_a_failure_says_what_happened_and_keeps_the_device_s_words(
    error: plc.PlcError, key: str, params: dict[str, str], said: str
) -> None:
    """Its class says what happened; the device's own words stay apart, untranslated."""
    text = error.text()
    assert (text.key, dict(text.params)) == (key, params)
    assert error.said == said
    assert TEMPLATES[key].params == frozenset(params)


def test_a_refused_value_says_why_where_the_source_tells() -> None:
    why = Template("test_why", "too long for {type}")(type="STRING[8]")
    told = plc.ValueRejectedError("refused", path="x", value="abc", why=why)
    untold = plc.ValueRejectedError("refused", path="x", value="abc", said="e: no")

    assert told.text() is why
    assert (untold.text().key, untold.said) == ("error_value_rejected", "e: no")


@pytest.mark.parametrize(
    ("error", "key"),
    [
        (plc.AccessDeniedError("allow-list"), "error_access_denied"),
        (plc.ServiceUnavailableError("restarting"), "error_unavailable"),
        (plc.PlcUnreachableError("ERROR:10"), "error_unreachable"),
        (plc.PlcAuthenticationError("401"), "error_auth"),
        (plc.NotAPlcError("a web page"), "error_not_the_device"),
        (plc.InvalidHostError("a path"), "error_invalid_host"),
        (plc.PlcResponseError("HTTP 500"), "error_response"),
        (plc.MalformedResponseError("broken"), "error_malformed"),
        (plc.ResponseTooLargeError("big", limit=1024), "error_too_large"),
        (plc.MissingPointError("x"), "error_not_found"),
        (plc.InvalidPathError("too long"), "error_invalid_path"),
        (plc.NoPublicVariablesError("none"), "error_no_variables"),
        (plc.VariableListTooLargeError("500.011"), "error_list_too_large"),
        (plc.VariableListUnreadableError("500.012"), "error_list_unreadable"),
        (plc.TooManyItemsError("413", allowed=256), "error_too_many_items"),
        (plc.WritesDisabledError("-1"), "error_writes_disabled"),
        (plc.ReadOnlyError("x", 1), "error_read_only"),
        (plc.DateTooEarlyError("x", "1969-12-31", "1970-01-01"), "error_too_early"),
        (plc.DurationOutOfRangeError("x", -1, "596:31:23.647"), "error_duration"),
        (plc.NotEncodableError("x", "ž", "cp1250"), "error_not_encodable"),
        (plc.NotAsciiError("x", "ž"), "error_not_ascii"),
    ],
    ids=lambda value: type(value).__name__ if isinstance(value, Exception) else None,
)
def test_each_failure_says_what_happened_in_its_own_words(
    error: plc.PlcError, key: str
) -> None:
    """Each class its text (the key of a caller's translation), its English apart."""
    text = error.text()
    assert text.key == key
    assert set(text.params) == TEMPLATES[key].params
    assert str(text) != str(error)  # the message is the source's, for logs
