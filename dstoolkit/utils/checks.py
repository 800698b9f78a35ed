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


def real_array(value: Any, name: str, *, finite: bool = True, allow_inf: bool = False,
               ndim: tuple[int, ...] | None = None, error: type[InvalidInputError]
               = InvalidInputError) -> np.ndarray:
    """``value`` as a float array of real numbers.

    Refuses (``error``, naming ``name``) strings, complex numbers, objects, ragged lists,
    arrays of the wrong number of dimensions (``ndim``: the allowed ones) and, with
    ``finite``, NaN (and ±inf unless ``allow_inf``).
    """
    if isinstance(value, (str, bytes)):
        raise error(f"{name} must be numbers, got the string {value!r}")
    try:
        raw = np.asarray(value)
    except (ValueError, TypeError) as exc:  # ragged nesting
        raise error(f"{name} must be a regular array of numbers (equal-length rows): "
                    f"{exc}") from exc
    if raw.dtype.kind not in "biuf":
        kind = {"c": "complex numbers", "U": "strings", "S": "bytes", "O": "objects",
                "M": "dates", "m": "time spans"}.get(raw.dtype.kind, str(raw.dtype))
        if raw.dtype.kind == "O":
            try:
                raw = raw.astype(float)
            except (ValueError, TypeError) as exc:
                raise error(f"{name} must be real numbers, got {kind} ({exc})") from exc
        else:
            raise error(f"{name} must be real numbers, got {kind}")
    arr = raw.astype(float, copy=False)
    if ndim is not None and arr.ndim not in ndim:
        raise error(f"{name} must have {' or '.join(map(str, ndim))} dimension(s), got shape "
                    f"{arr.shape}")
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


def real_number(value: Any, name: str, *, low: float | None = None, high: float | None = None,
                low_open: bool = False, high_open: bool = False,
                error: type[InvalidInputError] = InvalidInputError) -> float:
    """``value`` as a finite float within [low, high] (open ends with ``*_open``)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real | np.number) or \
            isinstance(value, complex | np.complexfloating):
        raise error(f"{name} must be a real number, got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise error(f"{name} must be a finite number, got {x}")
    too_low = low is not None and (x <= low if low_open else x < low)
    too_high = high is not None and (x >= high if high_open else x > high)
    if too_low or too_high:
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        raise error(f"{name} must lie in {left}{'-inf' if low is None else low}, "
                    f"{'inf' if high is None else high}{right}, got {x}")
    return x


def whole_number(value: Any, name: str, *, low: int = 0, high: int | None = None,
                 error: type[InvalidInputError] = InvalidInputError) -> int:
    """``value`` as an int in [low, high]; floats that are whole numbers are accepted."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real | np.number) or \
            isinstance(value, complex | np.complexfloating):
        raise error(f"{name} must be a whole number, got {value!r}")
    x = float(value)
    if not math.isfinite(x) or not x.is_integer():
        raise error(f"{name} must be a whole number, got {value!r}")
    n = int(x)
    if n < low or (high is not None and n > high):
        raise error(f"{name} must be a whole number in [{low}, {'∞' if high is None else high}]"
                    f", got {n}")
    return n


def as_signal(x: ArrayLike, what: str) -> np.ndarray:
    """A recording or reference signal as a 1-D finite float array.

    An (n, 1) column (one channel of a recording) is accepted; anything else that is not one
    finite, non-empty channel raises :class:`~dstoolkit.errors.DetectionError` naming ``what``.
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
