"""Checks of user-given numbers, lists and mappings, with one-line error messages.

One implementation for every layer, so a number is accepted or refused by the same rules
whether it comes from a file (:func:`number`, :func:`vector`, :func:`mapping`: the message
names the *field*, ``field 'dt' = -1: expected a positive number``) or from a model
constructor (:func:`quantity`, :func:`quantities`: the message names the parameter in
full, ``PID ki = -2.0: expected a number ≥ 0``).

The rules: ``bool`` is not a number (YAML's ``yes`` must not become 1.0), neither is text
(``"3"`` is refused rather than guessed), and NaN or ±∞ are refused unless the caller allows
infinity explicitly (an open controller limit). Every failure raises
:class:`hydrokit.errors.InputError`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from hydrokit.errors import InputError

_REAL = (int, float, np.integer, np.floating)


def cut(text: str, limit: int = 80) -> str:
    """``text`` cut to about ``limit`` characters (its start and end kept), so a message never
    echoes a whole file: ``'yyyy…yyyy' (100002 characters)``."""
    return text if len(text) <= limit else f"{text[: limit - 20]}…{text[-15:]} ({len(text)} characters)"


def cut_repr(value: object, limit: int = 80) -> str:
    """``repr(value)`` cut by :func:`cut`."""
    return cut(repr(value), limit)


def _is_real(value: object) -> bool:
    # bool is an int subclass (and np.bool_ is not a number type here): refuse both
    return isinstance(value, _REAL) and not isinstance(value, (bool, np.bool_))


def _checked(
    value: object,
    label: str,
    source: str,
    positive: bool,
    nonneg: bool,
    allow_inf: bool,
    unit: str,
) -> float:
    """The one number check: ``label = value!r: expected …`` on failure."""
    in_unit = f" in {unit}" if unit else ""
    shown = cut_repr(value)
    if not _is_real(value):
        raise InputError(f"{label} = {shown}: expected a number{in_unit}", source)
    v = float(value)  # type: ignore[arg-type]
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise InputError(f"{label} = {shown}: expected a finite number{in_unit}", source)
    if positive and not v > 0:
        raise InputError(f"{label} = {shown}: expected a positive number{in_unit}", source)
    if nonneg and not v >= 0:
        raise InputError(f"{label} = {shown}: expected a number ≥ 0{in_unit}", source)
    return v


#: what a physical body can measure: (smallest, largest, unit, words). A part below a micrometre
#: or above a kilometre is a typo or a unit slip (1e-200 m gave an all-zero vehicle fragment);
#: masses from a micrometre cube of water (1e-15 kg) to a kilometre cube of steel (8e12 kg)
BODY_RANGES = {
    "size": (1e-6, 1e3, "m", "a size from a micrometre to a kilometre"),
    "area": (1e-12, 1e6, "m²", "an area from a square micrometre to a square kilometre"),
    "volume": (1e-18, 1e9, "m³", "a volume from a cubic micrometre to a cubic kilometre"),
    "mass": (1e-15, 1e13, "kg", "a mass from a micrometre cube of water to a kilometre cube of steel"),
}


def body_quantity(value: float, kind: str, field: str, source: str = "", shown: float | None = None) -> float:
    """``value`` (already a finite number) if a physical body can have it as its ``kind``
    ("size", "area", "volume" or "mass"; see :data:`BODY_RANGES`), else one line naming
    ``field`` and the number (``shown`` when the field held another quantity, e.g. a weight)."""
    lo, hi, unit, words = BODY_RANGES[kind]
    if not lo <= value <= hi:
        given = value if shown is None else shown
        raise InputError(
            f"field '{cut(field)}' = {given:g}: expected {words} ({lo:g} to {hi:g} {unit}); no physical body has "
            f"{value:g} {unit}",
            source,
        )
    return value


# ---------------------------------------------------------------------------- file fields
def number(value: Any, field: str, source: str = "", *, positive: bool = False, nonneg: bool = False) -> float:
    """A finite number from a file field.

    Parameters
    ----------
    value : object
        The value as read (int or float; bool, text, NaN and ±∞ are refused).
    field : str
        The field's name in the file, e.g. ``guidance.lookahead`` or ``thrusters[0].max_rpm``.
    source : str, optional
        The file name, prefixed to the message.
    positive : bool, optional
        Require value > 0.
    nonneg : bool, optional
        Require value ≥ 0.

    Returns
    -------
    float
        The value (in the field's own unit; no conversion here).

    Raises
    ------
    InputError
        ``field '<field>' = <value!r>: expected …`` (one line).
    """
    return _checked(value, f"field '{cut(field)}'", source, positive, nonneg, False, "")


def vector(value: Any, n: int, field: str, source: str = "") -> np.ndarray:
    """A list (or tuple) of exactly ``n`` finite numbers from a file field.

    Parameters
    ----------
    value : object
        The value as read.
    n : int
        The required number of entries.
    field : str
        The field's name in the file; an entry is named ``field[i]``.
    source : str, optional
        The file name, prefixed to the message.

    Returns
    -------
    ndarray, shape (n,)
        The values as floats (in the field's own unit).

    Raises
    ------
    InputError
        Not a list of n entries, or an entry that is not a finite number.
    """
    if not isinstance(value, (list, tuple)) or len(value) != n:
        raise InputError(f"field '{cut(field)}' = {cut_repr(value)}: expected a list of {n} numbers", source)
    return np.array([number(v, f"{field}[{i}]", source) for i, v in enumerate(value)], dtype=float)


def matrix(value: Any, n: int, field: str, source: str = "", allow_diag: bool = True) -> np.ndarray:
    """An n×n matrix from a file field: an n×n nested list, or (``allow_diag``) n numbers for
    its diagonal. Entries must be finite numbers (in the field's own unit).

    Raises
    ------
    InputError
        Not a list, the wrong shape (rows and their lengths are named), or a bad entry
        ``field[i][j]`` / ``field[i]``.
    """
    if not isinstance(value, list):
        raise InputError(
            f"field '{cut(field)}' = {cut_repr(value)}: expected a list of {n} numbers or an {n}x{n} matrix", source
        )
    if value and all(isinstance(r, list) for r in value):
        if len(value) != n or any(len(r) != n for r in value):
            raise InputError(
                f"field '{cut(field)}': expected an {n}x{n} matrix, got {len(value)} rows of lengths "
                f"{cut(str([len(r) for r in value]))}",
                source,
            )
        return np.array(
            [[number(x, f"{field}[{i}][{j}]", source) for j, x in enumerate(r)] for i, r in enumerate(value)]
        )
    if len(value) != n or not allow_diag:
        raise InputError(f"field '{cut(field)}' has {len(value)} values; expected {n} (or an {n}x{n} matrix)", source)
    return np.diag([number(x, f"{field}[{i}]", source) for i, x in enumerate(value)])


def finite_samples(values: np.ndarray, column: str, unit: str, source: str = "") -> None:
    """Refuse a recorded column holding NaN or ±∞, naming the first bad sample.

    Parameters
    ----------
    values : ndarray
        The column as read (any unit).
    column : str
        Its name in messages, e.g. ``'t'``.
    unit : str
        Its unit, e.g. ``'s'``.
    source : str, optional
        The file name, prefixed to the message.

    Raises
    ------
    InputError
        ``column 't' (s) holds nan at sample 3 (of 120 samples; 2 bad): expected finite numbers``.
    """
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        k = int(bad[0])
        raise InputError(
            f"column '{column}' ({unit}) holds {float(values.flat[k])!r} at sample {k} "
            f"(of {values.size} samples; {bad.size} bad): expected finite numbers",
            source,
        )


def increasing(values: np.ndarray, column: str, unit: str, source: str = "") -> None:
    """Refuse a column that does not increase strictly (a repeated or backward time stamp).

    Raises
    ------
    InputError
        ``column 't' (s) goes from 0.3 to 0.3 at sample 4: expected strictly increasing values``.
    """
    steps = np.diff(values)
    if np.all(steps > 0):
        return
    k = int(np.argmax(steps <= 0))  # the first step that does not go forward
    a, b = float(values[k]), float(values[k + 1])
    raise InputError(
        f"column '{column}' ({unit}) goes from {a:g} to {b:g} at sample {k + 1}: expected strictly increasing values",
        source,
    )


def record(t: Any, y: Any, signal: str, unit: str, source: str = "") -> tuple[np.ndarray, np.ndarray]:
    """A recorded time series (t in s, y in ``unit``) as float arrays, or one line naming the fault.

    The one check of a record handed over from Python (files are checked row by row by their
    readers): equal 1-D shapes (the message calls y the ``signal``), finite samples
    (:func:`finite_samples`), strictly increasing time (:func:`increasing`).
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if t.shape != y.shape or t.ndim != 1:
        raise InputError(f"time and {signal} must be 1-D of equal length, got {t.shape} and {y.shape}", source)
    finite_samples(t, "t", "s", source)
    finite_samples(y, "y", unit, source)
    increasing(t, "t", "s", source)
    return t, y


def mapping(value: Any, field: str, source: str = "") -> dict:
    """A mapping (YAML block of ``key: value`` lines) from a file field.

    Parameters
    ----------
    value : object
        The value as read.
    field : str
        The field's name in the file.
    source : str, optional
        The file name, prefixed to the message.

    Returns
    -------
    dict
        ``value`` itself (not copied).

    Raises
    ------
    InputError
        ``field '<field>' = <value!r>: expected a mapping``.
    """
    if not isinstance(value, dict):
        raise InputError(f"field '{cut(field)}' = {cut_repr(value)}: expected a mapping", source)
    return value


# ---------------------------------------------------------------------- model parameters
def quantity(
    value: Any,
    what: str,
    source: str = "",
    *,
    positive: bool = False,
    nonneg: bool = False,
    allow_inf: bool = False,
    unit: str = "",
) -> float:
    """A model parameter as a float, named in full in the message.

    Parameters
    ----------
    value : object
        An int, float or numpy number (bool and text are refused).
    what : str
        The parameter as the message names it, e.g. ``PID kp`` or ``thruster 'T1' diameter``.
    source : str, optional
        Where it came from (a file), prefixed to the message.
    positive, nonneg : bool, optional
        Require value > 0 or ≥ 0.
    allow_inf : bool, optional
        Accept ±∞ (e.g. an absent output limit); NaN is always refused.
    unit : str, optional
        The SI unit expected, named in the message (``expected a positive number in m``).

    Returns
    -------
    float
        The value.

    Raises
    ------
    InputError
        ``<what> = <value>: expected …``; a number is shown as a float (``-2.0``), which is
        what the model stores.
    """
    shown = float(value) if _is_real(value) else value
    return _checked(shown, what, source, positive, nonneg, allow_inf, unit)


def quantities(value: Any, what: str, n: int | None = None, source: str = "") -> tuple[float, ...]:
    """A model parameter that is a sequence of finite numbers (a 3-vector, coefficients).

    Parameters
    ----------
    value : object
        A list, tuple or 1-D array (text and mappings are refused).
    what : str
        The parameter as the message names it, e.g. ``thruster 'T1' position``.
    n : int or None, optional
        The required length; None = any length ≥ 1.
    source : str, optional
        Where it came from, prefixed to the message.

    Returns
    -------
    tuple of float
        The values, in the parameter's own unit.

    Raises
    ------
    InputError
        ``<what> = <value!r>: expected …`` naming the length or the bad entry.
    """
    expected = f"{n} finite numbers" if n is not None else "a list of finite numbers"
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (Iterable, np.ndarray)):
        raise InputError(f"{what} = {cut_repr(value)}: expected {expected}", source)
    items = list(np.asarray(value, dtype=object).reshape(-1)) if isinstance(value, np.ndarray) else list(value)
    if (n is not None and len(items) != n) or not items:
        raise InputError(f"{what} = {cut_repr(value)}: expected {expected}", source)
    if not all(_is_real(x) and math.isfinite(float(x)) for x in items):
        raise InputError(f"{what} = {cut_repr(value)}: expected {expected}", source)
    return tuple(float(x) for x in items)


# ---------------------------------------------------------------------------- sysid windows
#: words of a sysid window that mean whole runs (``--window none``)
WHOLE_RUNS = ("none", "off", "whole")


def window_length(value: Any, label: str = "window", source: str = "") -> float | str | None:
    """A sysid window as given: ``hydrokit sysid --window`` or a project's ``sysid.window``.

    Parameters
    ----------
    value : object
        ``"auto"``; None or ``"none"`` / ``"off"`` / ``"whole"`` (whole runs); or a window length
        in seconds > 0 (a number, ``"30"`` or ``"30s"``). A bool (YAML's ``yes``, ``off``) is refused.
    label : str, optional
        How the message names the value: ``window`` (the option) or ``field 'sysid.window' =``.
    source : str, optional
        The option or file, prefixed to the message.

    Returns
    -------
    "auto", None or float
        ``"auto"``, None for whole runs, or the window length, s.

    Raises
    ------
    InputError
        ``<label> <value!r>: expected a length in seconds …, 'auto' or 'none'`` (one line).
    """
    if value is None:
        return None
    expected = "expected a length in seconds (e.g. 30), 'auto' or 'none'"
    if isinstance(value, str):
        text = value.strip().lower()
        if text == "auto":
            return "auto"
        if text in WHOLE_RUNS:
            return None
        try:
            value = float(text.removesuffix("s"))  # the message shows the number read
        except ValueError:
            raise InputError(f"{label} {cut_repr(value)}: {expected}", source) from None
    elif isinstance(value, bool):
        raise InputError(f"{label} {value!r}: {expected} (YAML reads yes/no/on/off as true/false)", source)
    elif not _is_real(value):
        raise InputError(f"{label} {cut_repr(value)}: {expected}", source)
    s = float(value)
    if not (math.isfinite(s) and s > 0):
        raise InputError(f"{label} {cut_repr(value)}: expected a length > 0 s, 'auto' or 'none'", source)
    return s


def window_within(window: Any, runs: Iterable[Any], label: str = "window", source: str = "") -> float | str | None:
    """``window`` (:func:`window_length`) checked against the runs' lengths.

    Parameters
    ----------
    window : object — as :func:`window_length` takes it
    runs : objects with ``name`` and ``time`` (row times, s) — the training runs
    label, source : str — as in :func:`window_length`

    Returns
    -------
    "auto", None or float — as :func:`window_length`; a length is at most every run's, s

    Raises
    ------
    InputError
        A bad value, or a window longer than a run (naming the run and both lengths, s).
    """
    length = window_length(window, label, source)
    if isinstance(length, float):
        for r in runs:
            t = np.asarray(r.time, float)
            duration = float(t[-1] - t[0]) if t.size else 0.0
            if length > duration + 1e-9:
                raise InputError(
                    f"{label} {length:g} s is longer than run {r.name} ({duration:g} s); expected a window ≤ "
                    f"{duration:g} s, or 'none' to fit whole runs",
                    source,
                )
    return length
