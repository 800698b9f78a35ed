"""A check run in a child process that is killed at its time limit.

The trace function and the interval timer of :mod:`dstoolkit.teaching._limits` stop Python
code, and C code that waits; they cannot stop C code that computes (``sum(range(10**11))``,
a huge numpy product), which checks for signals only when it returns. On Unix a check
therefore runs in a child process (``fork``: it sees the learner's functions as they are,
nothing is pickled on the way in), which sends its verdict back through a pipe and is
killed if it is still running past the limit. The parent's state (globals, random
generators) is untouched by what the learner's code does in the child. Where ``fork`` is
missing the check runs in the calling process, as before.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import selectors
import signal
import sys
import time
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from dstoolkit.evidence import Evidence

T = TypeVar("T")

#: Seconds the parent waits past the limit before it kills the child: the child stops the
#: learner's Python code itself at the limit and reports that verdict.
GRACE_S = 2.0
_in_child = False


def run_isolated(work: Callable[[], T], seconds: float, stopped: Callable[[], T]) -> T:
    """Run ``work()`` in a child process; ``stopped()`` if it is still running past the limit.

    Parameters
    ----------
    work : callable
        The check; its result must pickle (a :class:`~dstoolkit.teaching.Feedback`).
    seconds : float
        The time limit; the child is killed :data:`GRACE_S` seconds after it.
    stopped : callable
        The result to give when the child had to be killed.

    Returns
    -------
    object
        What ``work()`` returned (an exception it raised is raised here).

    Examples
    --------
    >>> from dstoolkit.teaching._child_checks import run_isolated
    >>> run_isolated(lambda: sum(range(10)), 5.0, lambda: "stopped")
    45
    """
    if not hasattr(os, "fork") or _in_child:
        return work()
    read_fd, write_fd = os.pipe()
    for stream in (sys.stdout, sys.stderr):  # nothing printed twice by parent and child
        with contextlib.suppress(Exception):
            stream.flush()
    pid = os.fork()
    if pid == 0:  # the child: never returns
        _child(work, read_fd, write_fd)
    os.close(write_fd)
    try:
        data, finished = _read_until(read_fd, time.monotonic() + seconds + GRACE_S)
    finally:
        os.close(read_fd)
        if not _reaped(pid):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
    if not finished or not data:
        return stopped()
    kind, value = pickle.loads(data)
    if kind == "raised":
        raise value
    return value


def plain_data(value: Any, depth: int = 0) -> bool:
    """Tell whether ``value`` is built of numbers, strings, arrays and evidence only.

    Such an answer is compared in the calling process: none of its methods is the learner's
    code. Anything else (an object with its own ``__float__``, say) is compared in a child
    process (:func:`run_isolated`), which the time limit can stop.

    Parameters
    ----------
    value : object
        The answer.
    depth : int, optional
        How deep in containers ``value`` lies (beyond 8, it counts as not plain).

    Returns
    -------
    bool
        True for plain data.

    Examples
    --------
    >>> from dstoolkit.teaching._child_checks import plain_data
    >>> plain_data({"a": [0.1, 0.2]}), plain_data(object())
    (True, False)
    """
    if depth > 8:
        return False
    if value is None or type(value) in (bool, int, float, complex, str, bytes):
        return True
    if isinstance(value, np.generic) or isinstance(value, Evidence):
        return type(value).__module__.startswith(("numpy", "dstoolkit"))
    if type(value) is np.ndarray:
        return value.dtype.kind in "biufcUSb"
    if type(value) in (list, tuple, set, frozenset):
        return all(plain_data(item, depth + 1) for item in value)
    if type(value) is dict:
        return all(plain_data(k, depth + 1) and plain_data(v, depth + 1) for k, v in value.items())
    return False


def _child(work: Callable[[], Any], read_fd: int, write_fd: int) -> None:
    global _in_child
    _in_child = True
    status = 0
    try:
        os.close(read_fd)
        try:
            result: tuple[str, Any] = ("returned", work())
        except BaseException as exc:  # noqa: BLE001 - handed to the parent as it is
            result = ("raised", exc)
        try:
            data = pickle.dumps(result)
        except Exception as exc:  # noqa: BLE001 - an exception of the learner's own class
            data = pickle.dumps(("raised", RuntimeError(f"{type(exc).__name__}: {exc}")))
        with os.fdopen(write_fd, "wb") as fh:
            fh.write(data)
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
    except BaseException:  # noqa: BLE001 - the child must never run the parent's code on
        status = 1
    finally:
        os._exit(status)


def _read_until(fd: int, deadline: float) -> tuple[bytes, bool]:
    """Read ``fd`` to its end before ``deadline``; say whether the end was reached."""
    chunks: list[bytes] = []
    with selectors.DefaultSelector() as selector:
        selector.register(fd, selectors.EVENT_READ)
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not selector.select(left):
                return b"".join(chunks), False
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                return b"".join(chunks), True
            chunks.append(chunk)


def _reaped(pid: int) -> bool:
    with contextlib.suppress(ChildProcessError):
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done == 0:
            time.sleep(0.05)  # it has written its verdict and is exiting
            done, _ = os.waitpid(pid, os.WNOHANG)
        return done != 0
    return True
