"""A command's standard output that prints on any locale and outlives a closed pipe.

Inside :func:`command_console`, text that the output's encoding cannot hold (``°``, ``±``
under ``LC_ALL=C`` or ``PYTHONIOENCODING=ascii``) is written in ASCII ("deg", "+/-", or a
backslash escape), and a reader that goes away (``dstoolkit table3 | head``) no longer
breaks the command: what is printed after that is dropped, and the command goes on to
finish its files; :attr:`Console.pipe_closed` says so afterwards.

:func:`run_command` runs a whole command that way, its outputs in one
:func:`~dstoolkit.utils.outputs.output_run`, its errors and stop signals each one line.
"""

from __future__ import annotations

import codecs
import contextlib
import io
import os
import sys
from collections.abc import Callable, Iterator
from typing import Any

from dstoolkit.errors import DstoolkitError
from dstoolkit.utils.outputs import output_run
from dstoolkit.utils.signals import _Stopped, stop_on_signals, stopped_message

__all__ = ["ASCII_FALLBACK", "Console", "command_console", "run_command"]

#: The name of the codec error handler that writes ASCII stand-ins.
ASCII_FALLBACK = "dstoolkit.ascii"
_STAND_INS = {
    "°": "deg",
    "±": "+/-",
    "σ": "sigma",
    "µ": "u",
    "×": "x",
    "−": "-",
    "–": "-",
    "—": "-",
    "≤": "<=",
    "≥": ">=",
    "≈": "~",
    "…": "...",
    "‘": "'",
    "’": "'",
    "“": '"',
    "”": '"',
}


def _stand_in(exc: UnicodeError) -> tuple[str, int]:
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text = exc.object[exc.start : exc.end]
    out = "".join(
        _STAND_INS.get(ch, ch.encode("ascii", "backslashreplace").decode("ascii")) for ch in text
    )
    return out, exc.end


codecs.register_error(ASCII_FALLBACK, _stand_in)


class Console:
    """``sys.stdout`` while a command runs: it drops its text once the reader has gone.

    Parameters
    ----------
    stream : text stream
        The standard output it guards.

    Examples
    --------
    >>> import io
    >>> from dstoolkit.utils.console import Console
    >>> console = Console(io.StringIO())
    >>> console.write("level")
    5
    """

    def __init__(self, stream: Any) -> None:
        self._stream = stream
        self.pipe_closed = False

    def write(self, text: str) -> int:
        """Write ``text``, or drop it when the reader has gone.

        Parameters
        ----------
        text : str
            What to print.

        Returns
        -------
        int
            ``len(text)``, written or dropped.
        """
        if not self.pipe_closed:
            try:
                self._stream.write(text)
            except BrokenPipeError:
                self._closed()
        return len(text)

    def flush(self) -> None:
        """Flush, or drop the text when the reader has gone."""
        if not self.pipe_closed:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._closed()

    def _closed(self) -> None:
        self.pipe_closed = True
        # what is still buffered goes nowhere, also when Python flushes it at exit
        with contextlib.suppress(OSError, ValueError, io.UnsupportedOperation):
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, self._stream.fileno())
            os.close(null)

    def __getattr__(self, name: str) -> Any:
        """Anything else is the stream's own (``encoding``, ``fileno``...)."""
        return getattr(self._stream, name)


@contextlib.contextmanager
def command_console() -> Iterator[Console]:
    """Give ``sys.stdout`` and ``sys.stderr`` ASCII stand-ins and stdout a closed-pipe guard.

    Yields
    ------
    Console
        The guarded ``sys.stdout``; its ``pipe_closed`` tells whether the reader went away.

    Examples
    --------
    >>> from dstoolkit.utils.console import command_console
    >>> with command_console() as console:
    ...     print("ok")
    ok
    >>> console.pipe_closed
    False
    """
    before: list[tuple[Any, str]] = []
    for stream in (sys.stdout, sys.stderr):
        errors = getattr(stream, "errors", None)
        if errors is not None and hasattr(stream, "reconfigure"):
            with contextlib.suppress(ValueError, io.UnsupportedOperation, AttributeError):
                stream.reconfigure(errors=ASCII_FALLBACK)
                before.append((stream, errors))
    stdout = sys.stdout
    console = Console(stdout)
    sys.stdout = console
    try:
        yield console
    finally:
        if sys.stdout is console:
            sys.stdout = stdout
        for stream, errors in before:
            with contextlib.suppress(ValueError, io.UnsupportedOperation, AttributeError):
                stream.reconfigure(errors=errors)


def run_command(body: Callable[[], int]) -> int:
    """Run a command's body with one-line errors, stop signals and outputs taken back whole.

    A package error or an OS error becomes one ``error:`` line on stderr (exit status 2).
    Ctrl-C, SIGTERM, SIGHUP and SIGQUIT stop the command with one line on stderr and the
    exit status 128 + the signal's number. After a failure, a stop or a non-zero status,
    the run is taken back whole (:func:`~dstoolkit.utils.outputs.output_run`): the files it
    wrote are removed and the files they replaced put back. A closed standard output
    (``| head``) ends in an ``error:`` line once the command has finished, its files kept.

    Parameters
    ----------
    body : callable
        The command; returns its exit status.

    Returns
    -------
    int
        The exit status.

    Examples
    --------
    >>> import contextlib, io
    >>> from dstoolkit.errors import InvalidInputError
    >>> from dstoolkit.utils.console import run_command
    >>> def fails():
    ...     raise InvalidInputError("no such chapter 'gauge'")
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     status = run_command(fails)
    >>> status, err.getvalue().splitlines()
    (2, ["error: no such chapter 'gauge'"])
    """
    with stop_on_signals(), command_console() as console:
        try:
            with output_run() as run:
                status = int(body())
                if status != 0:
                    run.discard()
        except (DstoolkitError, OSError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except (KeyboardInterrupt, _Stopped) as exc:
            what, status = stopped_message(exc)
            print(
                f"{what}: stopped; the files this command had written were removed "
                "and the files they replaced put back",
                file=sys.stderr,
            )
            return status
        if console.pipe_closed:
            print(
                "error: the standard output was closed before everything was printed "
                "(a pipe such as '| head'); the command finished and its files were kept",
                file=sys.stderr,
            )
            return status or 2
        return status
