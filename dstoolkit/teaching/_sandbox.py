"""Plain data across processes, and the runner of a learner's function in isolation.

This module imports the standard library only: the grader runs its source as the program
of a fresh interpreter (``python -I -S -c``), where dstoolkit cannot be imported.

* :func:`encode` / :func:`decode` carry answers as JSON: numbers, strings, booleans,
  ``None``, ``...``, lists, tuples, sets (as frozensets) and dicts with any such keys. Any
  other object (one of the learner's classes, say) becomes an opaque marker, never
  asked for its value, so an answer object cannot run code in the process that compares.
* :func:`main` is the runner: it reads the answer cells' source, the function's name and
  the cases (encoded) from its standard input, limits its own memory and forbids itself
  files, sockets, new processes, signals and dstoolkit (an audit hook, which Python code
  cannot remove), runs the source, then calls the function on each case and writes one
  line per outcome to its standard output. It never sees an expected answer.
"""

from __future__ import annotations

import json
import math
from typing import Any

#: Modules an answer may use, imported before the runner closes the file system.
ALLOWED_MODULES = (
    "math",
    "cmath",
    "itertools",
    "functools",
    "collections",
    "operator",
    "fractions",
    "statistics",
    "heapq",
    "bisect",
    "copy",
    "numpy",
    "numpy.linalg",
)
#: Bytes of memory the runner may address.
MEMORY = 2 * 1024**3
#: Characters of an encoded answer, at most.
MAX_TEXT = 1_000_000
#: Containers within containers that an answer may hold: :func:`encode` writes no deeper,
#: and :func:`decode` reads no deeper (a line crafted by hand cannot exhaust the stack).
MAX_DEPTH = 50


def encode(value: Any, depth: int = 0) -> Any:
    """Return ``value`` as JSON-ready plain data (see the module docstring)."""
    if depth > MAX_DEPTH:
        return {"$": "object", "type": "too deep"}
    kind = type(value)
    if value is None or kind in (bool, str):
        return value
    if kind is int:
        return value if abs(value) < 2**63 else float(value)
    if kind is float:
        return value if math.isfinite(value) else {"$": "float", "v": repr(value)}
    if value is ...:
        return {"$": "..."}
    if kind.__module__ == "numpy" and hasattr(value, "tolist"):
        return encode(value.tolist(), depth + 1)
    if kind is list:
        return [encode(v, depth + 1) for v in value]
    if kind is tuple:
        return {"$": "tuple", "v": [encode(v, depth + 1) for v in value]}
    if kind in (set, frozenset):
        return {"$": "set", "v": [encode(v, depth + 1) for v in value]}
    if kind is dict:
        return {
            "$": "dict",
            "v": [[encode(k, depth + 1), encode(v, depth + 1)] for k, v in value.items()],
        }
    return {"$": "object", "type": kind.__name__[:60]}


class Opaque:
    """An answer that was not plain data (its type's name only); it equals nothing."""

    def __init__(self, type_name: str) -> None:
        self.type_name = type_name

    def __repr__(self) -> str:
        return f"<an object of type {self.type_name}>"


def decode(data: Any, depth: int = 0) -> Any:
    """Return the value that :func:`encode` wrote (sets as frozensets).

    Data that :func:`encode` cannot have written (a line the learner's code wrote by hand:
    a tag without its value, nesting deeper than ``MAX_DEPTH``) is an :class:`Opaque`
    answer, which equals nothing; decoding never raises.
    """
    if depth > MAX_DEPTH:
        return Opaque("too deep")
    if isinstance(data, list):
        return [decode(v, depth + 1) for v in data]
    if not isinstance(data, dict):
        return data
    tag = data.get("$")
    try:
        if tag == "...":
            return ...
        if tag == "float":
            return float(data["v"])
        if tag == "tuple":
            return tuple(decode(v, depth + 1) for v in data["v"])
        if tag == "set":
            return frozenset(_hashable(decode(v, depth + 1)) for v in data["v"])
        if tag == "dict":
            return {_hashable(decode(k, depth + 1)): decode(v, depth + 1) for k, v in data["v"]}
    except (KeyError, TypeError, ValueError):
        return Opaque("malformed")
    return Opaque(str(data.get("type", "?")))


def _hashable(value: Any) -> Any:
    if isinstance(value, list):
        return tuple(_hashable(v) for v in value)
    if isinstance(value, dict | Opaque):
        return repr(value)
    return value


def dumps(value: Any) -> str:
    """Return ``value`` encoded as one line of JSON (an opaque marker when too long)."""
    text = json.dumps(encode(value), ensure_ascii=True)
    return text if len(text) <= MAX_TEXT else json.dumps({"$": "object", "type": "too big"})


def loads(text: str) -> Any:
    """Return the value of a line written by :func:`dumps`.

    Raises ``ValueError`` when the line is no JSON; JSON nested too deep for the parser is
    an :class:`Opaque` answer.
    """
    try:
        data = json.loads(text)
    except RecursionError:
        return Opaque("too deep")
    return decode(data)


def _raised(err: BaseException) -> dict[str, str]:
    """Return an exception as plain data: the nearest built-in exception type and its text."""
    import builtins

    for klass in type(err).__mro__:
        if getattr(builtins, klass.__name__, None) is klass:
            name = klass.__name__
            break
    else:
        name = "BaseException"
    try:
        text = str(err)[:120]
    except BaseException:  # noqa: BLE001 - the learner's exception may refuse str()
        text = ""
    return {"raised": name, "text": text}


def _refuse(event: str, args: tuple) -> None:
    """Refuse what the learner's code must not do while graded (the audit hook).

    It refuses by raising; its lists are constants of its code and it reads no global
    name, so code that changes this module's globals or the builtins cannot widen it (and
    an error inside it refuses too).
    """
    if event == "import" and args[0].partition(".")[0] == "dstoolkit":
        raise ImportError("dstoolkit is not available in this test: write the computation yourself")
    if event == "open" or event.startswith(
        (
            "os.",
            "shutil.",
            "subprocess.",
            "_posixsubprocess.",
            "socket.",
            "ctypes.",
            "mmap.",
            "pty.",
            "fcntl.",
            "urllib.",
            "http.",
            "ftplib.",
            "smtplib.",
            "webbrowser.",
            "glob.",
            "sqlite3.",
            "resource.",
            "signal.",
            "sys.addaudithook",
            "sys.setprofile",
            "sys.settrace",
        )
    ):
        raise PermissionError(f"not allowed while your function is graded ({event})")


def _limit_resources() -> None:
    import resource

    for limit, value in (
        (resource.RLIMIT_AS, MEMORY),
        (resource.RLIMIT_FSIZE, 0),
        (resource.RLIMIT_CORE, 0),
        (resource.RLIMIT_NPROC, 0),
    ):
        try:
            resource.setrlimit(limit, (value, value))
        except (ValueError, OSError):  # a hard limit already lower
            pass


def main() -> None:
    """Run the learner's function on the cases read from standard input (the runner)."""
    import builtins
    import importlib
    import os
    import sys

    job = json.loads(sys.stdin.read())
    sys.path.extend(job.get("paths", []))
    for name in ALLOWED_MODULES:
        try:
            importlib.import_module(name)
        except ImportError:
            pass
    out = os.fdopen(os.dup(1), "w", encoding="utf-8")
    sink = os.open(os.devnull, os.O_WRONLY)
    os.dup2(sink, 1)
    os.dup2(sink, 2)
    sys.stdin = None
    _limit_resources()
    sys.addaudithook(_refuse)

    def say(record: dict[str, Any]) -> None:
        out.write(json.dumps(record) + "\n")
        out.flush()

    namespace: dict[str, Any] = {"__name__": "__answer__", "__builtins__": builtins}
    problems = []
    for number, source in enumerate(job["sources"], 1):
        try:
            exec(compile(source, f"<answer cell {number}>", "exec"), namespace)  # noqa: S102
        except BaseException as err:  # noqa: BLE001 - the learner's cell may raise anything
            problems.append(_raised(err))
    function = namespace.get(job["function"])
    if not callable(function):
        say({"ready": False, "problems": problems})
        return
    say({"ready": True, "problems": problems})
    for number, args in enumerate(job["cases"]):
        try:
            outcome: dict[str, Any] = {"value": encode(function(*decode(args)))}
        except BaseException as err:  # noqa: BLE001 - the learner's code may raise anything
            outcome = _raised(err)
        try:
            say({"case": number, **outcome})
        except BaseException:  # noqa: BLE001 - a result JSON cannot hold
            say({"case": number, "value": {"$": "object", "type": "unreadable"}})


if __name__ == "__main__":
    main()
