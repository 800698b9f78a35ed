"""Stop signals turned into exceptions, held back while outputs are moved into place.

A command run inside :func:`stop_on_signals` stops at Ctrl-C (SIGINT), SIGTERM, SIGHUP (its
terminal closed) and SIGQUIT by raising :class:`KeyboardInterrupt` (SIGINT) or a private
``_Stopped`` (a :class:`BaseException`, as Ctrl-C's is) where it was, so that its
``finally`` and ``except`` blocks run and remove what it made. Inside
:func:`deferred_signals` (the few renames that put a set of outputs in place, or take them
back) a signal is held and raised when the block ends, so that the files are never left half
moved. After the first signal, later ones are ignored while the command
cleans up.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType

__all__ = ["STOP_SIGNALS", "deferred_signals", "stop_on_signals", "stopped_message"]

#: The signals that stop a command, and how its one-line message names them.
STOP_SIGNALS: dict[int, str] = {
    signal.SIGINT: "interrupted (Ctrl-C)",
    signal.SIGTERM: "terminated (SIGTERM)",
    signal.SIGHUP: "hung up (SIGHUP, the terminal closed)",
    signal.SIGQUIT: "quit (SIGQUIT)",
}


class _Stopped(BaseException):
    """A stop signal other than SIGINT, raised where the program was.

    Parameters
    ----------
    signum : int
        The signal's number; the exit status is ``128 + signum``, as a shell reports it.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(STOP_SIGNALS.get(signum, f"signal {signum}"))
        self.signum = signum


class _Held:
    depth = 0
    pending: int | None = None


def _raise_for(signum: int) -> None:
    _ignore_stops()
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise _Stopped(signum)


def _ignore_stops() -> None:
    if threading.current_thread() is threading.main_thread():
        for signum in STOP_SIGNALS:
            signal.signal(signum, signal.SIG_IGN)


def _on_signal(signum: int, frame: FrameType | None) -> None:
    if _Held.depth > 0:
        _Held.pending = signum  # raised when the renames are done
        return
    _raise_for(signum)


@contextlib.contextmanager
def deferred_signals() -> Iterator[None]:
    """Hold stop signals for the block's duration; raise a held one when it ends.

    Examples
    --------
    >>> from dstoolkit.utils.signals import deferred_signals
    >>> with deferred_signals():
    ...     pass
    """
    _Held.depth += 1
    try:
        yield
    finally:
        _Held.depth -= 1
        if _Held.depth == 0 and _Held.pending is not None:
            signum, _Held.pending = _Held.pending, None
            _raise_for(signum)


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Turn the stop signals into exceptions for the block; give the handlers back after.

    Outside the main thread (where Python cannot set handlers) it does nothing.

    Examples
    --------
    >>> import signal
    >>> from dstoolkit.utils.signals import stop_on_signals
    >>> before = signal.getsignal(signal.SIGTERM)
    >>> with stop_on_signals():
    ...     pass
    >>> signal.getsignal(signal.SIGTERM) is before
    True
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {signum: signal.signal(signum, _on_signal) for signum in STOP_SIGNALS}
    try:
        yield
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)


def stopped_message(exc: BaseException) -> tuple[str, int]:
    """Name the signal that stopped a command, and its exit status.

    Parameters
    ----------
    exc : BaseException
        What :func:`stop_on_signals` raised (a KeyboardInterrupt for Ctrl-C).

    Returns
    -------
    what : str
        "interrupted (Ctrl-C)", "terminated (SIGTERM)"...
    status : int
        ``128 + signum``.

    Examples
    --------
    >>> from dstoolkit.utils.signals import stopped_message
    >>> stopped_message(KeyboardInterrupt())
    ('interrupted (Ctrl-C)', 130)
    """
    signum = exc.signum if isinstance(exc, _Stopped) else int(signal.SIGINT)
    return STOP_SIGNALS.get(signum, f"signal {signum}"), 128 + signum
