"""The certificate format (solverplan/certify/schema.py): exact numbers, round trips, format errors."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from solverplan.certify.schema import (
    EXAMPLE,
    Certificate,
    CertificateFormatError,
    _terminating_decimal,
    dumps_certificate,
    json_value,
    number_text,
    parse_certificate,
    parse_number,
)
from solverplan.errors import InputError
from tests.certify import cases


@pytest.mark.parametrize(
    "value,expected",
    [(3, Fraction(3)), ("1/3", Fraction(1, 3)), (" -2 / 6 ", Fraction(-1, 3)), ("0.25", Fraction(1, 4)), ("1e-3", Fraction(1, 1000)), (Decimal("0.1"), Fraction(1, 10))],
)
def test_parse_number_is_exact(value, expected):
    assert parse_number(value, "x") == expected


@pytest.mark.parametrize(
    "value,fragment",
    [(0.1, "is a binary float"), (True, "True is not a number"), ("inf", "is not finite"), ("NaN", "is not finite"), ("1/0", "divides by zero"), ([1], "is not a number")],
)
def test_parse_number_refuses(value, fragment):
    with pytest.raises(CertificateFormatError, match="^here: ") as info:
        parse_number(value, "here")
    assert fragment in str(info.value)
    assert isinstance(info.value, InputError)  # exit code 2 in the CLI


def test_numbers_as_json():
    assert [json_value(x) for x in (Fraction(4), Fraction(1, 4), Fraction(1, 3), Fraction(-5, 2))] == [4, "0.25", "1/3", "-2.5"]
    assert number_text(Fraction(1, 1024)) == "1/1024"  # shorter than its 10-digit decimal
    assert number_text(Fraction(-1, 20)) == "-0.05"


@given(numerator=st.integers(-10**40, 10**40), twos=st.integers(0, 90), fives=st.integers(0, 60), other=st.sampled_from([1, 1, 3, 7, 9, 77]))
def test_a_fraction_has_a_finite_decimal_iff_its_denominator_divides_a_power_of_ten(numerator, twos, fives, other):
    """The checker's decimals (least power of ten found by bisection) agree with the planner's
    :func:`solverplan.exact.format_number` (factors 2 and 5 counted), two independent ways of writing one number."""
    from solverplan.exact import format_number

    value = Fraction(numerator, 2**twos * 5**fives * other)
    if value.denominator == 1:
        return
    decimal = _terminating_decimal(value)
    planner = format_number(value)
    assert (decimal is None) == ("/" in planner)
    if decimal is not None:
        assert decimal == planner and Fraction(Decimal(decimal)) == value


@pytest.mark.parametrize("name", [*cases.ALL_VALID, "square_neutral"])
def test_round_trips(name):
    data = cases.square_neutral_cycle() if name == "square_neutral" else cases.ALL_VALID[name]()
    cert = Certificate.from_json(data)
    assert Certificate.from_json(cert.to_json()) == cert
    assert parse_certificate(dumps_certificate(cert)) == cert


def test_example_is_a_plan():
    cert = Certificate.from_json(EXAMPLE)
    assert cert.kind == "plan" and cert.claims.bounces == 1 and cert.goal is not None


def test_python_floats_in_data_are_refused_with_their_place():
    data = cases.square_up()
    data["stages"][0]["moves"][0]["source"] = [0.1, "9/10"]
    with pytest.raises(CertificateFormatError, match=r"^stages\[0\]\.moves\[0\]\.source: 0\.1 is a binary float"):
        Certificate.from_json(data)


def test_kind_specific_blocks():
    cycle = cases.square_cycle()
    with pytest.raises(CertificateFormatError, match="a plan certificate has no cycle block"):
        Certificate.from_json(dict(cycle, kind="plan", goal=[{"edge": 0, "t0": 0, "t1": 1}]))
    with pytest.raises(CertificateFormatError, match="a cycle certificate has no goal"):
        Certificate.from_json(dict(cycle, goal=[{"edge": 0, "t0": 0, "t1": 1}]))
    with pytest.raises(CertificateFormatError, match="needs the cycle block"):
        Certificate.from_json({k: v for k, v in cycle.items() if k != "cycle"})
    with pytest.raises(CertificateFormatError, match="needs a non-empty goal set"):
        Certificate.from_json(dict(cases.square_up(), goal=None))


# ---------------------------------------------------------------------- versions and ε
def test_epsilon_belongs_to_localize_certificates_of_version_2():
    from solverplan.certify.schema import READ_VERSIONS, VERSION, CertificateFormatError

    assert VERSION == 4 and READ_VERSIONS == (1, 2, 3, 4)
    cert = Certificate.from_json(cases.localize_square())
    assert cert.kind == "localize" and cert.claims.epsilon == Fraction(19, 2)
    assert Certificate.from_json(cert.to_json()) == cert and cert.to_json()["claims"]["epsilon"] == "9.5"
    bare = cases.localize_square()
    del bare["claims"]["epsilon"]
    with pytest.raises(CertificateFormatError, match=r"claims.epsilon: a localize certificate claims ε"):
        Certificate.from_json(bare)
    funnel = cases.funnel_square()
    funnel["claims"]["epsilon"] = "1"
    with pytest.raises(CertificateFormatError, match="claims.epsilon: only a localize certificate claims ε, not a funnel certificate"):
        Certificate.from_json(funnel)
    old = cases.localize_square()
    old["version"] = 1
    with pytest.raises(CertificateFormatError, match="kind: 'localize' is not one of plan, cycle, funnel$"):
        Certificate.from_json(old)


def test_version_1_certificates_are_read_and_written_back_as_version_1():
    plan = cases.square_up()
    plan["version"] = 1
    cert = Certificate.from_json(plan)
    assert cert.version == 1 and cert.kind == "plan" and cert.to_json()["version"] == 1
    funnel = cases.funnel_square()
    funnel["version"] = 1
    funnel["claims"]["objective"] = "localize-fewest"
    old = Certificate.from_json(funnel)
    assert old.kind == "localize" and old.claims.epsilon is None
    back = old.to_json()
    assert back["version"] == 1 and back["kind"] == "funnel" and "epsilon" not in back["claims"]
    assert Certificate.from_json(back) == old


def test_numbers_longer_than_pythons_digit_guard_round_trip_and_hostile_lengths_are_refused():
    from fractions import Fraction

    from solverplan.certify.schema import MAX_DIGITS, CertificateFormatError, number_text, parse_number

    long = Fraction(3**20_000 + 1, 7**9_000)  # 9,543 and 7,606 digits: beyond int()'s 4,300
    assert parse_number(number_text(long), "x") == long
    with pytest.raises(CertificateFormatError, match=r"^x: an integer of 200,002 digits \(at most 200,000 are read\)$"):
        parse_number("1" * (MAX_DIGITS + 2) + "/3", "x")


@given(bits=st.integers(1, 60_000), negative=st.booleans(), data=st.data())
def test_long_integers_are_converted_half_by_half_without_lifting_the_digit_guard(bits, negative, data):
    """The checker reads and writes integers past Python's 4,300-digit guard piece by piece, exactly, and leaves the
    guard (a setting of the whole process) as it was; the planner's printer agrees."""
    import sys

    from solverplan.certify.schema import _int_of, _text_of
    from solverplan.exact import format_number

    n = data.draw(st.integers(2 ** (bits - 1), 2**bits - 1)) * (-1 if negative else 1)
    guard = sys.get_int_max_str_digits()
    text = _text_of(n)
    assert sys.get_int_max_str_digits() == guard
    assert _int_of(text) == n and format_number(n) == text
