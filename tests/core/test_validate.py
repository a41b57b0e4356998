"""core.validate: the one number/list/mapping check behind every reader and model class."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydrokit.core.validate import cut, cut_repr, mapping, number, quantities, quantity, vector
from hydrokit.errors import InputError


@pytest.mark.parametrize(
    ("value", "match"),
    [
        (True, r"field 'dt' = True: expected a number"),  # YAML 'yes' is not 1.0
        ("3", r"field 'dt' = '3': expected a number"),  # text is refused, not guessed
        (None, r"field 'dt' = None: expected a number"),
        (float("nan"), r"field 'dt' = nan: expected a finite number"),
        (float("inf"), r"field 'dt' = inf: expected a finite number"),
    ],
)
def test_number_rejects_non_numbers(value: object, match: str) -> None:
    with pytest.raises(InputError, match=match) as exc:
        number(value, "dt", "m.yaml")
    # one line, prefixed with the file
    assert str(exc.value).startswith("m.yaml: field 'dt'") and "\n" not in str(exc.value)


def test_number_sign_options() -> None:
    with pytest.raises(InputError, match=r"field 'duration' = -5: expected a positive number"):
        number(-5, "duration", positive=True)
    with pytest.raises(InputError, match=r"field 'duration' = 0: expected a positive number"):
        number(0, "duration", positive=True)
    with pytest.raises(InputError, match=r"field 'speed' = -0.1: expected a number ≥ 0"):
        number(-0.1, "speed", nonneg=True)
    assert number(0, "speed", nonneg=True) == 0.0
    # accepted values come back as float, unchanged (no unit conversion here)
    got = number(3, "n")
    assert got == 3.0 and type(got) is float
    assert number(-2.5, "x") == -2.5
    assert number(np.float64(0.25), "x", positive=True) == 0.25


def test_vector() -> None:
    np.testing.assert_array_equal(vector([1, -2.5, 3], 3, "position"), [1.0, -2.5, 3.0])
    np.testing.assert_array_equal(vector((0, 1), 2, "range"), [0.0, 1.0])
    with pytest.raises(InputError, match=r"field 'position' = \[1, 2\]: expected a list of 3 numbers"):
        vector([1, 2], 3, "position", "v.yaml")
    with pytest.raises(InputError, match=r"field 'position' = '1,2,3': expected a list of 3 numbers"):
        vector("1,2,3", 3, "position")
    # a bad entry is named by its index
    with pytest.raises(InputError, match=r"field 'position\[1\]' = True: expected a number"):
        vector([0, True, 0], 3, "position")
    with pytest.raises(InputError, match=r"field 'position\[2\]' = nan: expected a finite number"):
        vector([0, 0, float("nan")], 3, "position")


def test_mapping() -> None:
    d = {"a": 1}
    assert mapping(d, "fluid") is d
    with pytest.raises(InputError, match=r"^f.yaml: field 'fluid' = \[1\]: expected a mapping$"):
        mapping([1], "fluid", "f.yaml")


def test_quantity_names_the_parameter_and_shows_a_float() -> None:
    with pytest.raises(InputError, match=r"^PID ki = -2.0: expected a number ≥ 0$"):
        quantity(-2, "PID ki", nonneg=True)
    with pytest.raises(InputError, match=r"^T max_thrust = 0.0: expected a positive number in N$"):
        quantity(0, "T max_thrust", positive=True, unit="N")
    with pytest.raises(InputError, match=r"^T max_thrust = 'lots': expected a number in N$"):
        quantity("lots", "T max_thrust", unit="N")
    with pytest.raises(InputError, match="expected a number"):
        quantity(False, "k")
    # ±∞ only when allowed (an open controller limit); NaN never
    with pytest.raises(InputError, match="expected a finite number"):
        quantity(-math.inf, "PID output_min")
    assert quantity(-math.inf, "PID output_min", allow_inf=True) == -math.inf
    with pytest.raises(InputError, match="expected a finite number"):
        quantity(math.nan, "PID output_min", allow_inf=True)


def test_quantities() -> None:
    assert quantities((1, 2.5, -3), "p", 3) == (1.0, 2.5, -3.0)
    assert quantities(np.array([0.5, 0.25]), "kt") == (0.5, 0.25)
    for bad in ([1, 2], "abc", 5, [1, "2", 3], [1, math.inf, 3], [1, True, 3]):
        with pytest.raises(InputError, match=r"^thruster 'T' position = .*: expected 3 finite numbers$"):
            quantities(bad, "thruster 'T' position", 3)
    with pytest.raises(InputError, match="expected a list of finite numbers"):
        quantities([], "kt_forward")


def test_cut_keeps_80_characters_and_shortens_longer_text_to_start_and_end():
    # the documented form: up to 80 characters unchanged; longer → first 60, "…", last 15 and
    # the length, so a message never echoes a whole file
    text = "".join(chr(ord("a") + k % 26) for k in range(81))
    assert cut(text[:80]) == text[:80]
    assert cut(text) == f"{text[:60]}…{text[-15:]} (81 characters)"
    assert cut_repr("x" * 100) == f"'{'x' * 59}…{'x' * 14}' (102 characters)"


def test_finite_samples_names_the_column_unit_and_first_bad_sample():
    from hydrokit.core.validate import finite_samples

    finite_samples(np.arange(5.0), "t", "s", "a.csv")  # all finite: no error
    v = np.array([0.0, 1.0, -np.inf, np.nan, 2.0])
    with pytest.raises(InputError) as err:
        finite_samples(v, "y", "m", "a.csv")
    assert (
        str(err.value) == "a.csv: column 'y' (m) holds -inf at sample 2 (of 5 samples; 2 bad): expected finite numbers"
    )


def test_increasing_names_the_first_repeated_or_backward_stamp():
    from hydrokit.core.validate import increasing

    increasing(np.array([0.0, 0.1, 0.2]), "t", "s")  # strictly increasing: no error
    with pytest.raises(InputError) as err:
        increasing(np.array([0.0, 0.1, 0.1, 0.05]), "t", "s", "a.csv")
    assert (
        str(err.value) == "a.csv: column 't' (s) goes from 0.1 to 0.1 at sample 2: expected strictly increasing values"
    )
    with pytest.raises(InputError) as err:
        increasing(np.array([0.0, 0.1, 0.2, 0.15]), "t", "s")
    assert str(err.value) == "column 't' (s) goes from 0.2 to 0.15 at sample 3: expected strictly increasing values"


@pytest.mark.parametrize(
    "value",
    [[[1, 2, 3], [4, 5, 6]], [[1, 2], [3, 4], [5, 6]], [[1, 2, 3], [4, 5], [6, 7, 8]]],
    ids=["two rows", "rows of two", "one short row"],
)
def test_matrix_refuses_a_wrong_row_count_or_row_length(value) -> None:
    from hydrokit.core.validate import matrix

    np.testing.assert_array_equal(matrix([[1, 0, 0], [0, 2, 0], [0, 0, 3]], 3, "M"), np.diag([1.0, 2, 3]))
    with pytest.raises(InputError, match=r"field 'M': expected an 3x3 matrix"):
        matrix(value, 3, "M")
