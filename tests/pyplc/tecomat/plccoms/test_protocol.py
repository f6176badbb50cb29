"""PLCComS lines and values, without a socket: the framer, the parsers, the formats."""

from datetime import UTC, date, datetime, time, timedelta
from decimal import Decimal
import math
import struct
from typing import Any

from hypothesis import example, given, strategies as st
import pytest

from custom_components.tecoapi.pyplc.core.exceptions import InvalidValueError
from custom_components.tecoapi.pyplc.core.models import ValueKind
from custom_components.tecoapi.pyplc.tecomat.plccoms.formatting import (
    format_value,
    plain_number,
)
from custom_components.tecoapi.pyplc.tecomat.plccoms.protocol import (
    DOUBLE_BITS_FROM,
    MAX_TIME_MS,
    MAX_TOD_MS,
    DateForm,
    LineFramer,
    ServerError,
    date_form,
    kind_of_type,
    learn_date_form,
    parse_server_error,
    parse_value,
    parse_variable,
    split_answer,
    split_line,
    split_list_entry,
)


@pytest.mark.parametrize(
    ("type_name", "kind"),
    [
        ("BOOL", ValueKind.BOOL),
        ("usint", ValueKind.INTEGER),
        ("LINT", ValueKind.INTEGER),
        ("DWORD", ValueKind.INTEGER),
        ("REAL", ValueKind.REAL),
        ("LREAL", ValueKind.REAL),
        ("STRING", ValueKind.STRING),
        ("STRING[32]", ValueKind.STRING),
        ("string(16)", ValueKind.STRING),
        ("WSTRING", ValueKind.STRING),
        ("TIME", ValueKind.TIME),
        ("TOD", ValueKind.TIME),
        ("TIME_OF_DAY", ValueKind.TIME),
        ("DATE", ValueKind.DATE),
        ("DT", ValueKind.DATETIME),
        (" DATE_AND_TIME ", ValueKind.DATETIME),
        ("ARRAY OF BYTE", None),
        ("", None),
    ],
)
def test_kind_of_type(type_name: str, kind: ValueKind | None) -> None:
    assert kind_of_type(type_name) is kind


# --- the framer ----------------------------------------------------------------------------


def test_framer_takes_lf_and_crlf_and_keeps_partial_lines() -> None:
    framer = LineFramer()

    assert framer.feed(b"GET:a,1\r\nDIFF:b,2\nDIFF:c") == [b"GET:a,1", b"DIFF:b,2"]
    assert framer.buffered == len(b"DIFF:c")
    assert framer.feed(b",3\r") == []
    assert framer.feed(b"\n\n") == [b"DIFF:c,3", b""]
    assert framer.buffered == 0


def test_framer_fed_one_byte_at_a_time() -> None:
    framer = LineFramer()
    data = b"LIST:a,BOOL\r\nLIST:\r\nDIFF:x,1,5\n"

    lines = [line for byte in data for line in framer.feed(bytes([byte]))]

    assert lines == [b"LIST:a,BOOL", b"LIST:", b"DIFF:x,1,5"]


def test_framer_discards_an_over_long_line_in_one_piece() -> None:
    framer = LineFramer(max_length=8)

    lines = framer.feed(b"12345678\n123456789\nok\n")

    assert lines == [b"12345678", b"ok"]
    assert framer.discarded == 1


def test_framer_discards_an_over_long_line_arriving_in_pieces() -> None:
    framer = LineFramer(max_length=8)

    assert framer.feed(b"12345") == []
    assert framer.feed(b"67890") == []  # over the cap: dropped as it streams
    assert framer.buffered == 0
    assert framer.feed(b"more and more without end") == []
    assert framer.buffered == 0
    assert framer.feed(b"tail\nnext\n") == [b"next"]
    assert framer.discarded == 1


def test_framer_memory_stays_bounded_whatever_is_sent() -> None:
    framer = LineFramer(max_length=100)

    for _ in range(100):
        framer.feed(b"x" * 10_000)
        assert framer.buffered <= 101

    assert framer.discarded == 1


def test_framer_counts_a_crlf_line_by_its_text() -> None:
    framer = LineFramer(max_length=4)

    assert framer.feed(b"1234\r\n12345\r\n") == [b"1234"]
    assert framer.feed(b"123") == []
    assert framer.feed(b"45\r\n") == []
    assert framer.discarded == 2


def test_framer_needs_a_positive_cap() -> None:
    with pytest.raises(ValueError, match="max_length"):
        LineFramer(max_length=0)


# --- lines ---------------------------------------------------------------------------------


def test_split_line() -> None:
    assert split_line("diff:a,1") == ("DIFF", "a,1")
    assert split_line(" List :") == ("LIST", "")
    assert split_line("no colon") is None
    assert split_line(":x") is None


def test_split_answer_keeps_commas_in_the_value() -> None:
    assert split_answer("T_ZONES_SET[0].TOPIT_TC,1") == ("T_ZONES_SET[0].TOPIT_TC", "1")
    assert split_answer("temp,21,5") == ("temp", "21,5")
    assert split_answer('text, "a, b" ') == ("text", '"a, b"')
    assert split_answer("noValue") is None
    assert split_answer(",1") is None


def test_split_list_entry_cuts_the_flags() -> None:
    assert split_list_entry("Temp*~,REAL") == ("Temp", "*~", "REAL")
    assert split_list_entry("Temp,REAL") == ("Temp", "", "REAL")
    assert split_list_entry("*~,BOOL") is None
    assert split_list_entry("") is None


def test_split_list_entry_cuts_the_flags_after_the_type() -> None:
    # The changelog (1.5): a disabled variable is LIST:svetlo_kuchyn,BOOL*.
    assert split_list_entry("svetlo_kuchyn,BOOL*") == ("svetlo_kuchyn", "*", "BOOL")
    assert split_list_entry("Temp,REAL~*") == ("Temp", "*~", "REAL")
    assert split_list_entry("Temp~,REAL*") == ("Temp", "*~", "REAL")
    # The manual's example prints no type.
    assert split_list_entry("test_btn_up*~") == ("test_btn_up", "*~", "")
    assert split_list_entry("Temp,") == ("Temp", "", "")


def test_parse_server_error() -> None:
    assert parse_server_error("ERROR", "2 Variable 'x' not found") == ServerError(
        "ERROR", "2", "Variable 'x' not found"
    )
    assert parse_server_error("WARNING", " flood of DIFF ") == ServerError(
        "WARNING", "", "flood of DIFF"
    )
    assert parse_server_error("ERROR", "41") == ServerError("ERROR", "41", "")


def test_parse_server_error_of_the_manual() -> None:
    error = parse_server_error(
        "ERROR", "33 Unknown variable name in request: 'GET:test'"
    )

    assert (error.number, error.request, error.variable) == (33, "GET:test", "test")
    assert error.message == "Unknown variable name in request: 'GET:test'"
    delta = parse_server_error(
        "ERROR", "35 Wrong parameter value in request: 'EN:test_1 a'"
    )
    assert (delta.number, delta.variable) == (35, "test_1")
    assert parse_server_error("ERROR", "35 x: 'SET:a.b,5'").variable == "a.b"
    assert parse_server_error("ERROR", "10 Unable to connect to PLC.").request == ""
    warning = parse_server_error(
        "WARNING", "252 Changed active variables in public file: '[10/1648]'"
    )
    assert (warning.number, warning.variable) == (252, "")
    assert parse_server_error("ERROR", "30 x: 'GET:'").variable == ""
    assert parse_server_error("ERROR", "no code").number is None


# --- values in -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kind", "text", "value"),
    [
        (ValueKind.BOOL, "1", True),
        (ValueKind.BOOL, "0", False),
        (ValueKind.BOOL, "TRUE", True),
        (ValueKind.BOOL, "false", False),
        (ValueKind.BOOL, "2", None),
        (ValueKind.INTEGER, "-42", -42),
        (ValueKind.INTEGER, "+7", 7),
        (ValueKind.INTEGER, "5.0", 5),
        (ValueKind.INTEGER, "5,5", None),
        (ValueKind.INTEGER, "x", None),
        (ValueKind.REAL, "21.5", 21.5),
        (ValueKind.REAL, "21,5", 21.5),
        (ValueKind.REAL, "-0,125", -0.125),
        (ValueKind.REAL, ".5", 0.5),
        (ValueKind.REAL, "3", 3.0),
        (ValueKind.REAL, "2.150000e+01", 21.5),
        (ValueKind.REAL, "2,15E1", 21.5),
        (ValueKind.REAL, "2.15 e+001", 21.5),
        (ValueKind.REAL, "1e400", None),
        (ValueKind.REAL, "nan", None),
        (ValueKind.REAL, "", None),
        (ValueKind.STRING, '"Dobrý den"', "Dobrý den"),
        (ValueKind.STRING, '""', ""),
        (ValueKind.STRING, "bare", "bare"),
        (ValueKind.STRING, '"', '"'),
        (
            ValueKind.TIME,
            "3723450",
            timedelta(hours=1, minutes=2, seconds=3, milliseconds=450),
        ),
        (ValueKind.TIME, "-1", None),
        (
            ValueKind.TIME,
            "01:02:03.45",
            timedelta(hours=1, minutes=2, seconds=3, milliseconds=450),
        ),
        (ValueKind.TIME, "120:00:00", timedelta(hours=120)),
        (
            ValueKind.TIME,
            "T#1h2m3s450ms",
            timedelta(hours=1, minutes=2, seconds=3, milliseconds=450),
        ),
        (ValueKind.TIME, "time#1d_2h", timedelta(hours=26)),
        (ValueKind.TIME, "T#1.5s", timedelta(seconds=1, milliseconds=500)),
        (ValueKind.TIME, "T#-5s", None),
        (ValueKind.TIME, "T#5x", None),
        (ValueKind.TIME, "T#1hx2m", None),
        (ValueKind.TIME, "T#", None),
        (ValueKind.TIME, "TOD#06:30:00", timedelta(hours=6, minutes=30)),
        (ValueKind.TIME, "1500.4", timedelta(seconds=1, milliseconds=500)),
        (ValueKind.TIME, "soon", None),
        (ValueKind.DATE, "1434499200", date(2015, 6, 17)),
        (ValueKind.DATE, "1434499200.0", date(2015, 6, 17)),
        (ValueKind.DATE, "2015-06-17", date(2015, 6, 17)),
        (ValueKind.DATE, "D#2015-06-17", date(2015, 6, 17)),
        (ValueKind.DATE, "2015-02-30", None),
        (ValueKind.DATE, "1e300", None),
        (ValueKind.DATE, "x", None),
        (
            ValueKind.DATETIME,
            "1526037753",
            datetime(2018, 5, 11, 11, 22, 33, tzinfo=UTC),
        ),
        (
            ValueKind.DATETIME,
            "1526037753,5",
            datetime(2018, 5, 11, 11, 22, 33, 500000, tzinfo=UTC),
        ),
        (
            ValueKind.DATETIME,
            "2018-05-11T11:22:33.456Z",
            datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC),
        ),
        (
            ValueKind.DATETIME,
            "DT#2018-05-11-11:22:33",
            datetime(2018, 5, 11, 11, 22, 33, tzinfo=UTC),
        ),
        (ValueKind.DATETIME, "2018-05-11 25:00:00", None),
        (ValueKind.DATETIME, "now", None),
        (None, '"text"', "text"),
        (None, "TRUE", True),
        (None, "12", 12),
        (None, "1,5", 1.5),
        (None, "on", "on"),
    ],
)
def test_parse_value(kind: ValueKind | None, text: str, value: Any) -> None:
    parsed = parse_value(kind, text)

    assert parsed == value
    assert type(parsed) is type(value)


# --- values out ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kind", "value", "text"),
    [
        (ValueKind.BOOL, True, "1"),
        (ValueKind.BOOL, 0, "0"),
        (ValueKind.INTEGER, -5, "-5"),
        (ValueKind.INTEGER, 7.0, "7"),
        (ValueKind.REAL, 21.5, "21.5"),
        (ValueKind.REAL, 3, "3"),
        (ValueKind.REAL, 1e-7, "0.0000001"),
        (ValueKind.REAL, 1.5e16, "15000000000000000"),
        (ValueKind.REAL, 1e300, "1" + "0" * 300),
        (ValueKind.STRING, "Dobrý den", '"Dobrý den"'),
        (ValueKind.TIME, timedelta(hours=1, milliseconds=5), "3600005"),
        (ValueKind.TIME, time(6, 30, 0, 250000), "23400250"),
        (ValueKind.TIME, "01:02:03.450", "3723450"),
        (ValueKind.TIME, 1500, "1500"),
        (None, False, "0"),
        (None, 12, "12"),
        (None, 2.5, "2.5"),
        (None, "x", '"x"'),
    ],
)
def test_format_value(kind: ValueKind | None, value: Any, text: str) -> None:
    assert format_value(kind, value, name="v") == text


def double_bits(seconds: float) -> str:
    """The manual's DATE/DT integer: a double's 8 bytes as an unsigned integer."""
    return str(int.from_bytes(struct.pack("<d", seconds), "little"))


@pytest.mark.parametrize(
    ("form", "text"),
    [
        (DateForm.DOUBLE_BITS, double_bits(1526037753.9)),
        (DateForm.DECIMAL, "1526037753.9"),
        (DateForm.SECONDS, "1526037753"),
    ],
)
def test_dates_are_written_in_the_server_s_form(form: DateForm, text: str) -> None:
    moment = datetime(2018, 5, 11, 11, 22, 33, 900000, tzinfo=UTC)

    assert format_value(ValueKind.DATETIME, moment, name="v", dates=form) == text
    # A naive datetime is taken as UTC.
    naive = moment.replace(tzinfo=None)
    assert format_value(ValueKind.DATETIME, naive, name="v", dates=form) == text
    local = datetime.fromisoformat("2018-05-11T13:22:33.9+02:00")
    assert format_value(ValueKind.DATETIME, local, name="v", dates=form) == text
    midnight = {
        DateForm.DOUBLE_BITS: double_bits(1434499200),
        DateForm.DECIMAL: "1434499200",
        DateForm.SECONDS: "1434499200",
    }[form]
    assert format_value(ValueKind.DATE, date(2015, 6, 17), name="v", dates=form) == (
        midnight
    )


def test_the_default_date_form_is_the_manual_s() -> None:
    moment = datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC)

    text = format_value(ValueKind.DATETIME, moment, name="v")

    assert text == double_bits(1526037753.456)
    assert int(text) >= DOUBLE_BITS_FROM


@pytest.mark.parametrize(
    ("type_name", "text", "value"),
    [
        # DATE_TIME_DECIMAL = No (the default): the double's bytes as an integer.
        (
            "DT",
            double_bits(1526037753.456),
            datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC),
        ),
        ("DATE", double_bits(1434499200), date(2015, 6, 17)),
        # DATE_TIME_DECIMAL = Yes.
        (
            "DT",
            "1526037753.4560000896",
            datetime(2018, 5, 11, 11, 22, 33, 456000, tzinfo=UTC),
        ),
        ("DATE", "1434499200.0000000000", date(2015, 6, 17)),
        # A plain count of seconds (what was assumed before the manual).
        ("DT", "1526037753", datetime(2018, 5, 11, 11, 22, 33, tzinfo=UTC)),
        # Outside the type's range: no date at all, never the year 50,000.
        ("DT", double_bits(1.6e12), None),
        ("DT", double_bits(-1.0), None),
        ("DT", double_bits(float("nan")), None),
        ("DT", double_bits(float("inf")), None),
        ("DT", str(2**64), None),
        ("DT", "1600000000000", None),
        ("DATE", double_bits(1e300), None),
        ("DT", "-5", None),
        # TIME a 32-bit count of milliseconds, TOD one below a day.
        ("TIME", str(2**32 - 1), timedelta(milliseconds=2**32 - 1)),
        ("TIME", str(2**32), None),
        ("TOD", "86399999", timedelta(milliseconds=86_399_999)),
        ("TOD", "86400000", None),
        ("TIME_OF_DAY", "TOD#25:00:00", None),
        ("TIME", "86400000", timedelta(days=1)),
        ("REAL", "1,5", 1.5),
        ("MYSTRUCT", "12", 12),
        (None, "12", 12),
    ],
)
def test_parse_variable_within_its_type(
    type_name: str | None, text: str, value: Any
) -> None:
    assert parse_variable(type_name, text) == value


# The last millisecond a DT holds, 9999-12-31T23:59:59.999, in seconds since 1970.
LAST_SECOND = 253402300799.999


def number_texts(number: float) -> list[str]:
    """Every way a server may print a number: plain, repr, scientific, comma."""
    texts = [
        repr(number),
        f"{number:.6e}",
        str(int(number)) if number.is_integer() else "",
    ]
    if math.isfinite(number):
        plain = format(Decimal(repr(number)), "f")
        texts += [plain, plain.replace(".", ",")]
    return [text for text in texts if text]


_SECONDS = st.floats() | st.floats(LAST_SECOND - 1, LAST_SECOND + 1)
_MILLIS = st.floats() | st.floats(MAX_TIME_MS - 1, MAX_TIME_MS + 1)


@given(
    type_name=st.sampled_from(["DT", "DATE", "TIME", "TOD"]),
    number=_SECONDS | _MILLIS,
    integer=st.integers(-(2**70), 2**70) | st.integers(0, 2**64 - 1),
)
@example(type_name="DT", number=253402300799.9995, integer=0)
@example(type_name="DATE", number=253402300799.9995, integer=0)
@example(type_name="TIME", number=float(2**32), integer=2**32)
def test_a_date_or_time_of_any_number_is_a_value_or_none(
    type_name: str, number: float, integer: int
) -> None:
    """A date or time the server sends never raises: a value in range, or None."""
    texts = [*number_texts(number), str(integer), f"T#{integer}ms", f"{integer}:00:00"]
    if not math.isnan(number):
        texts.append(double_bits(number))
    for text in texts:
        value = parse_variable(type_name, text)
        if value is None:
            continue
        if type_name == "DT":
            assert isinstance(value, datetime)
            assert value >= datetime(1970, 1, 1, tzinfo=UTC)
        elif type_name == "DATE":
            assert isinstance(value, date)
            assert value >= date(1970, 1, 1)
        else:
            limit = MAX_TIME_MS if type_name == "TIME" else MAX_TOD_MS
            assert timedelta(0) <= value <= timedelta(milliseconds=limit)


@pytest.mark.parametrize(
    ("type_name", "text", "value"),
    [
        ("DT", "253402300799.999", datetime(9999, 12, 31, 23, 59, 59, 999000, UTC)),
        ("DT", "253402300799.9994", datetime(9999, 12, 31, 23, 59, 59, 999000, UTC)),
        ("DT", "253402300799.9995", None),  # 10000-01-01 once rounded
        ("DT", double_bits(253402300799.9995), None),
        ("DATE", "253402300799.9995", None),
        ("DATE", double_bits(253402300799.9995), None),
        pytest.param("DT", "9" * 5000, None, id="DT-5000-digits"),
        ("TIME", str(MAX_TIME_MS), timedelta(milliseconds=MAX_TIME_MS)),
        ("TIME", "T#49d17h2m47s295ms", timedelta(milliseconds=MAX_TIME_MS)),
        ("TIME", "T#49d17h2m47s296ms", None),  # beyond 32 bits, however written
        ("TIME", "1193:02:47.296", None),
        ("TIME", f"T#{'9' * 400}d", None),
        ("TIME", f"{'9' * 20}:00:00", None),
        pytest.param("INT", "9" * 5000, None, id="INT-5000-digits"),
        pytest.param(None, "9" * 5000, None, id="untyped-5000-digits"),
    ],
)
def test_a_value_beyond_its_type_is_none(
    type_name: str | None, text: str, value: Any
) -> None:
    assert parse_variable(type_name, text) == value


def test_date_form_tells_the_server_s_form() -> None:
    assert date_form(double_bits(1526037753.0)) is DateForm.DOUBLE_BITS
    assert date_form("1526037753.4560000896") is DateForm.DECIMAL
    assert date_form("1526037753,5") is DateForm.DECIMAL
    assert date_form("1.526038e+09") is DateForm.DECIMAL
    assert date_form("0.0") is DateForm.DECIMAL
    assert date_form("1526037753") is DateForm.SECONDS
    assert date_form("2018-05-11T11:22:33Z") is None


@pytest.mark.parametrize("text", ["0", " 0 ", "000", "-5", "x", "", "9" * 5000])
def test_a_zero_proves_no_date_form(text: str) -> None:
    """0 (also 0.0's bytes, the manual's default for a DT never set) is every form."""
    assert date_form(text) is None
    for known in (None, *DateForm):
        assert learn_date_form(known, text) is known


@pytest.mark.parametrize(
    ("known", "text", "learnt"),
    [
        (None, double_bits(1526037753.0), DateForm.DOUBLE_BITS),
        (None, "1526037753.5", DateForm.DECIMAL),
        (None, "1526037753", DateForm.SECONDS),
        # A proof replaces what was known (a restarted server may differ).
        (DateForm.SECONDS, double_bits(1526037753.0), DateForm.DOUBLE_BITS),
        (DateForm.DOUBLE_BITS, "1526037753.5", DateForm.DECIMAL),
        (DateForm.DECIMAL, double_bits(1526037753.0), DateForm.DOUBLE_BITS),
        # A plain integer is also a decimal server's with no decimals: it only
        # fills a form not known yet.
        (DateForm.DECIMAL, "1526037753", DateForm.DECIMAL),
        (DateForm.DOUBLE_BITS, "1526037753", DateForm.DOUBLE_BITS),
    ],
)
def test_learn_date_form(known: DateForm | None, text: str, learnt: DateForm) -> None:
    assert learn_date_form(known, text) is learnt


@pytest.mark.parametrize(
    ("kind", "value"),
    [
        (ValueKind.BOOL, 2),
        (ValueKind.BOOL, "true"),
        (ValueKind.INTEGER, True),
        (ValueKind.INTEGER, 1.5),
        (ValueKind.REAL, "1"),
        (ValueKind.REAL, float("inf")),
        (ValueKind.REAL, False),
        (ValueKind.STRING, 5),
        (ValueKind.STRING, 'a "quote"'),
        (ValueKind.STRING, "two\nlines"),
        (ValueKind.STRING, "Ж"),
        (ValueKind.TIME, timedelta(seconds=-1)),
        (ValueKind.TIME, -5),
        (ValueKind.TIME, "5 minutes"),
        (ValueKind.TIME, 1.5),
        (ValueKind.TIME, 2**32),
        (ValueKind.TIME, timedelta(days=50)),
        (ValueKind.DATE, date(1969, 12, 31)),
        (ValueKind.DATETIME, datetime(1969, 12, 31, 23, 59, 59, tzinfo=UTC)),
        (ValueKind.DATE, datetime(2020, 1, 1, tzinfo=UTC)),
        (ValueKind.DATETIME, date(2020, 1, 1)),
        (None, None),
        (None, [1]),
    ],
)
def test_format_value_refuses_what_the_kind_cannot_take(
    kind: ValueKind | None, value: Any
) -> None:
    with pytest.raises(InvalidValueError) as caught:
        format_value(kind, value, name="v")

    assert (caught.value.path, caught.value.value) == ("v", value)


@pytest.mark.parametrize(
    ("kind", "value", "key", "params"),
    [
        (ValueKind.STRING, 'a "quote"', "write_quote", {}),
        (ValueKind.STRING, "two\nlines", "write_quote", {}),
        (ValueKind.STRING, "Ж", "error_not_encodable", {"encoding": "Windows-1250"}),
        (ValueKind.STRING, 5, "write_not_of_kind", {"kind": "string"}),
        (None, [1], "write_not_a_scalar", {}),
    ],
)
def test_a_refusal_says_why_in_a_text_a_user_reads_translated(
    kind: ValueKind | None, value: Any, key: str, params: dict[str, str]
) -> None:
    with pytest.raises(InvalidValueError) as caught:
        format_value(kind, value, name="v")

    assert caught.value.text().key == key
    assert dict(caught.value.text().params) == params


def test_plain_number() -> None:
    assert plain_number(0.1) == "0.1"
    assert plain_number(-2.0) == "-2"
    assert plain_number(2.5e-10) == "0.00000000025"
