"""Input checks at the door, shared by every layer: each names the argument and what to do.

They turn what numpy would raise deep inside a computation (a broadcast error, a ragged
list, a string or complex number, NaN travelling into an estimate) into one
:class:`~dstoolkit.errors.InvalidInputError` that names the argument.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from dstoolkit.errors import DetectionError, InvalidInputError

__all__ = ["as_signal", "real_array", "real_number", "refuse_masked", "whole_number"]


def refuse_masked(
    value: Any, name: str, error: type[InvalidInputError] = InvalidInputError
) -> None:
    """Refuse a masked array with masked entries: numpy would use the values under the mask.

    Parameters
    ----------
    value : object
        What the caller was given.
    name : str
        The argument's name, as the error message should say it.
    error : type, optional
        The :class:`~dstoolkit.errors.InvalidInputError` subclass to raise.

    Raises
    ------
    InvalidInputError
        (or ``error``) For a :class:`numpy.ma.MaskedArray` with any entry masked.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.utils.checks import refuse_masked
    >>> refuse_masked(np.ma.masked_array([1.0, -999.0], mask=[False, True]), "readings")
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: readings has 1 masked entry: ...
    """
    if isinstance(value, np.ma.MaskedArray):
        masked = int(np.ma.getmaskarray(value).sum())
        if masked:
            raise error(
                f"{name} has {masked} masked {'entry' if masked == 1 else 'entries'}: masks "
                "are not honoured here (the values under them would be used); remove those "
                "entries or fill them (value.filled(...)) with real numbers"
            )


def _as_float(value: Any, name: str, error: type[InvalidInputError]) -> float:
    try:
        return float(value)
    except OverflowError:  # an int beyond 1.8e308
        raise error(f"{name} must be a finite number, got one too large for a float") from None


def real_array(
    value: Any,
    name: str,
    *,
    finite: bool = True,
    allow_inf: bool = False,
    ndim: tuple[int, ...] | None = None,
    error: type[InvalidInputError] = InvalidInputError,
) -> np.ndarray:
    """Return ``value`` as a float array of real numbers, or refuse it by name.

    Parameters
    ----------
    value : array_like
        What the caller was given: a number, a list or an array of real numbers.
    name : str
        The argument's name, as the error message should say it.
    finite : bool, optional
        Refuse NaN (and ±inf unless ``allow_inf``). Default True.
    allow_inf : bool, optional
        Let ±inf through when ``finite`` is set (a frame bound may be infinite).
    ndim : tuple of int, optional
        The numbers of dimensions allowed; None allows any.
    error : type, optional
        The :class:`~dstoolkit.errors.InvalidInputError` subclass to raise.

    Returns
    -------
    numpy.ndarray
        ``value`` as a float array of the same shape (no copy when it already is one).

    Raises
    ------
    InvalidInputError
        (or ``error``) For strings, complex numbers, objects, ragged lists, a wrong number
        of dimensions, or NaN/±inf as above; the message names ``name`` and says what to do.

    See Also
    --------
    real_number, whole_number

    Examples
    --------
    >>> from dstoolkit.utils.checks import real_array
    >>> real_array([1, 2.5], "readings")
    array([1. , 2.5])
    >>> real_array([1.0, float("nan")], "readings")
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: readings contains NaN or infinite values ...
    """
    if isinstance(value, (str, bytes)):
        raise error(f"{name} must be numbers, got the string {value!r}")
    refuse_masked(value, name, error)
    try:
        raw = np.asarray(value)
    except (ValueError, TypeError) as exc:  # ragged nesting
        raise error(
            f"{name} must be a regular array of numbers (equal-length rows): {exc}"
        ) from exc
    if raw.dtype.kind not in "biuf":
        kind = {
            "c": "complex numbers",
            "U": "strings",
            "S": "bytes",
            "O": "objects",
            "M": "dates",
            "m": "time spans",
        }.get(raw.dtype.kind, str(raw.dtype))
        if raw.dtype.kind == "O":
            try:
                raw = raw.astype(float)
            except (ValueError, TypeError) as exc:
                raise error(f"{name} must be real numbers, got {kind} ({exc})") from exc
        else:
            raise error(f"{name} must be real numbers, got {kind}")
    arr = raw.astype(float, copy=False)
    if ndim is not None and arr.ndim not in ndim:
        raise error(
            f"{name} must have {' or '.join(map(str, ndim))} dimension(s), got shape {arr.shape}"
        )
    if finite:
        bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
        if bad.any():
            where = np.argwhere(bad)[0].tolist() if arr.ndim else []
            raise error(
                f"{name} contains {'NaN' if allow_inf else 'NaN or infinite values'}"
                + (f" (first at index {where})" if where else "")
                + "; give finite numbers (remove or replace missing values)"
            )
    return arr


def real_number(
    value: Any,
    name: str,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    error: type[InvalidInputError] = InvalidInputError,
) -> float:
    """Return ``value`` as a finite float within ``[low, high]``, or refuse it by name.

    Parameters
    ----------
    value : float
        A real number (a Python or numpy number; not a bool, a string or a complex number).
    name : str
        The argument's name, as the error message should say it.
    low, high : float, optional
        The bounds; None leaves that side unbounded.
    low_open, high_open : bool, optional
        Exclude the bound itself on that side.
    error : type, optional
        The :class:`~dstoolkit.errors.InvalidInputError` subclass to raise.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    InvalidInputError
        (or ``error``) For a value that is not a real number, is not finite, or lies
        outside the bounds; the message names ``name`` and the interval.

    See Also
    --------
    real_array, whole_number

    Examples
    --------
    >>> from dstoolkit.utils.checks import real_number
    >>> real_number(0.3, "alpha", low=0.0, high=1.0)
    0.3
    >>> real_number(1.5, "alpha", low=0.0, high=1.0)
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: alpha must lie in [0.0, 1.0], got 1.5
    """
    if (
        isinstance(value, bool)
        or not isinstance(value, numbers.Real | np.number)
        or isinstance(value, complex | np.complexfloating)
    ):
        raise error(f"{name} must be a real number, got {value!r}")
    x = _as_float(value, name, error)
    if not math.isfinite(x):
        raise error(f"{name} must be a finite number, got {x}")
    too_low = low is not None and (x <= low if low_open else x < low)
    too_high = high is not None and (x >= high if high_open else x > high)
    if too_low or too_high:
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        raise error(
            f"{name} must lie in {left}{'-inf' if low is None else low}, "
            f"{'inf' if high is None else high}{right}, got {x}"
        )
    return x


def whole_number(
    value: Any,
    name: str,
    *,
    low: int = 0,
    high: int | None = None,
    error: type[InvalidInputError] = InvalidInputError,
) -> int:
    """Return ``value`` as an int within ``[low, high]``, or refuse it by name.

    Parameters
    ----------
    value : int or float
        A whole number; a float that is a whole number (``3.0``) is accepted.
    name : str
        The argument's name, as the error message should say it.
    low : int, optional
        The smallest value allowed. Default 0.
    high : int, optional
        The largest value allowed; None for no limit.
    error : type, optional
        The :class:`~dstoolkit.errors.InvalidInputError` subclass to raise.

    Returns
    -------
    int
        ``value`` as an int.

    Raises
    ------
    InvalidInputError
        (or ``error``) For a bool, a fraction, a non-finite or non-real value, or one
        outside the bounds.

    See Also
    --------
    real_array, real_number

    Examples
    --------
    >>> from dstoolkit.utils.checks import whole_number
    >>> whole_number(3.0, "runs", low=1)
    3
    >>> whole_number(2.5, "runs", low=1)
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: runs must be a whole number, got 2.5
    """
    if (
        isinstance(value, bool)
        or not isinstance(value, numbers.Real | np.number)
        or isinstance(value, complex | np.complexfloating)
    ):
        raise error(f"{name} must be a whole number, got {value!r}")
    if isinstance(value, numbers.Integral):  # exact, however large
        n = int(value)
    else:
        x = _as_float(value, name, error)
        if not math.isfinite(x) or not x.is_integer():
            raise error(f"{name} must be a whole number, got {value!r}")
        n = int(x)
    if n < low or (high is not None and n > high):
        raise error(
            f"{name} must be a whole number in [{low}, {'∞' if high is None else high}], "
            f"got {n if abs(n) < 10**20 else f'a number of {len(str(abs(n)))} digits'}"
        )
    return n


def as_signal(x: ArrayLike, what: str) -> np.ndarray:
    """Return a recording or reference signal as one finite channel.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, 1)
        The samples; an (n, 1) column (one channel of a recording) is accepted.
    what : str
        What the signal is ("recording", "reference"), as the error message should say it.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The samples as floats.

    Raises
    ------
    DetectionError
        When ``x`` is not one channel, is empty, or holds NaN or infinite samples.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.utils.checks import as_signal
    >>> as_signal(np.zeros((4, 1)), "recording").shape
    (4,)
    """
    a = np.asarray(x, dtype=float)
    if a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if a.ndim != 1:
        raise DetectionError(
            f"{what} must be one channel (a 1-D array), got shape {a.shape}; pick a channel, "
            "e.g. recording[:, 0]"
        )
    if a.size == 0:
        raise DetectionError(f"{what} is empty")
    if not np.all(np.isfinite(a)):
        raise DetectionError(f"{what} contains NaN or infinite samples")
    return a
