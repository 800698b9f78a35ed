"""Running a learner's function under a time limit, and describing what it returned.

A check must give its verdict even when the learner's function never ends. The function
runs in the calling thread under a trace function that stops it once the deadline has
passed (a ``while True`` loop is stopped between two of its lines); in the main thread of
a Unix process an interval timer also stops code that waits in C (``time.sleep``) or that
caught the trace function's stop. The stop is a :class:`BaseException` (not an ``Exception``), so an
``except Exception`` in the learner's code does not swallow it. (A bare ``except:`` inside
an endless loop swallows every stop; only the kernel's interrupt, or nbgrader's cell time
limit, ends that.)
"""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

from dstoolkit.errors import InvalidInputError

#: Seconds a check gives the learner's function (all its cases together) by default.
DEFAULT_TIME_LIMIT = 5.0
_settings = {"time_limit": DEFAULT_TIME_LIMIT}
#: Results with more numbers than this get a short description instead of a comparison.
BIG = 10_000


class _TimeLimitReached(BaseException):  # noqa: N818 - a stop signal, not an error
    """Raised inside the learner's code when the check's deadline has passed."""


def set_time_limit(seconds: float) -> float:
    """Set how long a check lets a learner's function run (all its cases together).

    A sheet whose functions are slow on purpose raises it in its setup cell, e.g.
    ``set_time_limit(20)``; a single check takes ``check(..., time_limit=20)``.

    Parameters
    ----------
    seconds : float
        The new default, more than 0.

    Returns
    -------
    float
        The previous default.

    Raises
    ------
    InvalidInputError
        ``seconds`` is not a number more than 0.

    Examples
    --------
    >>> from dstoolkit.teaching import set_time_limit
    >>> previous = set_time_limit(20)
    >>> set_time_limit(previous)
    20.0
    """
    seconds = valid_limit(seconds)
    previous = _settings["time_limit"]
    _settings["time_limit"] = seconds
    return previous


def time_limit() -> float:
    """Return the time limit of a check, in seconds (see :func:`set_time_limit`)."""
    return _settings["time_limit"]


def valid_limit(seconds: Any) -> float:
    """``seconds`` as a float, or :class:`~dstoolkit.errors.InvalidInputError`."""
    try:
        value = float(seconds)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int beyond a float
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise InvalidInputError(
            f"a time limit must be a number of seconds above 0, not "
            f"{seconds!r}; e.g. set_time_limit(20)"
        )
    return value


def _alarm_available() -> bool:
    """Tell whether an interval timer can be used: Unix, the main thread, no one else's alarm."""
    if not hasattr(signal, "setitimer") or threading.current_thread() is not (
        threading.main_thread()
    ):
        return False
    if signal.getitimer(signal.ITIMER_REAL)[0] > 0:
        return False
    return signal.getsignal(signal.SIGALRM) in (signal.SIG_DFL, signal.SIG_IGN, None)


def _ring(signum: int, frame: Any) -> None:
    """Handle the timer's signal: stop the learner's code, never this module's clean-up."""
    if frame is not None and frame.f_code.co_filename == __file__:
        return
    raise _TimeLimitReached


def run_limited(fn: Callable[..., Any], args: tuple, end: float) -> Any:
    """Run ``fn(*args)`` and stop it with :class:`_TimeLimitReached` at ``end``.

    ``end`` is a :func:`time.monotonic` value.

    The trace function is set only for the frames ``fn`` opens: this function's own frame
    is not traced, so its clean-up always runs.
    """
    left = end - time.monotonic()
    if left <= 0:
        raise _TimeLimitReached

    def tracer(frame: Any, event: str, arg: Any) -> Any:
        if time.monotonic() > end:
            raise _TimeLimitReached
        return tracer

    previous_trace = sys.gettrace()
    alarm = _alarm_available()
    previous_handler: Any = None
    if alarm:
        previous_handler = signal.signal(signal.SIGALRM, _ring)
        signal.setitimer(signal.ITIMER_REAL, left + 0.5)
    sys.settrace(tracer)
    try:
        return fn(*args)
    finally:
        if alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous_handler)
        sys.settrace(previous_trace)


# -- describing a result ----------------------------------------------------------------------


def count_items(value: Any, limit: int = BIG) -> int:
    """How many numbers or items ``value`` holds, counted up to just past ``limit``."""
    size = getattr(value, "size", None)
    if isinstance(size, int) and hasattr(value, "shape"):
        return size
    if isinstance(value, str | bytes):
        return 1
    if isinstance(value, Mapping):
        items: Any = value.values()
        total = len(value)
    elif isinstance(value, list | tuple | set | frozenset):
        items = value
        total = len(value)
    else:
        return 1
    if total > limit:
        return total
    for item in items:
        if isinstance(item, str | bytes | int | float):
            continue
        total += count_items(item, limit - total)
        if total > limit:
            break
    return total


def describe(value: Any) -> str:
    """Return a short description of a value: its type and size, never its contents."""
    if value is None:
        return "None"
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "dtype"):
        return f"a numpy array of shape {tuple(shape)} ({value.dtype})"
    if isinstance(value, Mapping):
        return f"a {type(value).__name__} with {len(value)} entries"
    if isinstance(value, list | tuple | set | frozenset):
        return f"a {type(value).__name__} of {len(value)} items"
    if isinstance(value, str):
        return f"a str of {len(value)} characters"
    return f"a {type(value).__name__}"


def too_big(value: Any) -> bool:
    """Return True when ``value`` holds more than :data:`BIG` numbers or items."""
    try:
        return count_items(value) > BIG
    except Exception:  # noqa: BLE001 - an odd object whose len() or size fails
        return False
