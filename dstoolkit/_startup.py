"""A quiet stop while the ``dstoolkit`` command is still importing its modules.

Importing numpy and scipy takes a moment; a Ctrl-C (or SIGTERM, SIGHUP, SIGQUIT) then would
print a long traceback from inside them. When this process is the command (``dstoolkit`` or
``python -m dstoolkit``), the package's first import installs handlers that print one line
and exit with ``128 +`` the signal's number: nothing has been written yet. The command's
own handlers (:func:`dstoolkit.utils.signals.stop_on_signals`) take over once it runs. A
program that merely imports dstoolkit keeps its handlers.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from types import FrameType

_NAMES = {
    signal.SIGINT: "interrupted (Ctrl-C)",
    signal.SIGTERM: "terminated (SIGTERM)",
    signal.SIGHUP: "hung up (SIGHUP)",
    signal.SIGQUIT: "quit (SIGQUIT)",
}


def _is_the_command(argv: list[str]) -> bool:
    """Whether the interpreter's own command line runs dstoolkit's command."""
    if len(argv) >= 2 and os.path.basename(argv[1]) == "dstoolkit":  # the console script
        return True
    return any(
        (a == "-m" and b == "dstoolkit") or a == "-mdstoolkit"
        for a, b in zip(argv, [*argv[1:], ""], strict=True)
    )


def _quiet_stop(signum: int, frame: FrameType | None) -> None:
    name = _NAMES.get(signal.Signals(signum), f"signal {signum}")
    os.write(2, f"{name}: stopped while starting or exiting; no file was being written\n".encode())
    os._exit(128 + signum)


def install_if_command() -> None:
    """Install the quiet handlers when this process is the ``dstoolkit`` command."""
    if threading.current_thread() is not threading.main_thread():
        return
    if not _is_the_command(list(getattr(sys, "orig_argv", []))):
        return
    for signum in _NAMES:
        if signal.getsignal(signum) is not signal.SIG_IGN:  # nohup keeps SIGHUP ignored
            signal.signal(signum, _quiet_stop)


install_if_command()
