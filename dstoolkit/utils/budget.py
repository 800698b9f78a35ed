"""Bounded work: the memory budget, set in this one place, and checks against it.

Every computation whose memory grows with its input (the products of Dempster's rule,
eq. 1; a batch of filter runs; the particle filter's pre-drawn noise; a recording read for
analysis) asks :func:`check_memory` before it allocates, or :func:`rows_per_chunk` how
many rows fit, and then works in chunks or refuses with a
:class:`~dstoolkit.errors.MemoryBudgetError` that gives the size. The budget is 1 GiB unless
``DSTOOLKIT_MEMORY_BUDGET`` (bytes, or with a K/M/G suffix) or :func:`set_memory_budget` says
otherwise.
"""

from __future__ import annotations

import os

from dstoolkit.errors import InvalidInputError, MemoryBudgetError

#: The memory budget when nothing else is set: 1 GiB.
DEFAULT_MEMORY_BUDGET = 2**30
_SUFFIX = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30}
_budget: int | None = None


#: The largest budget one can give: 1 PiB (more is no budget at all).
MAX_MEMORY_BUDGET = 2**50


def _parse_bytes(given: str) -> int:
    """The budget ``DSTOOLKIT_MEMORY_BUDGET`` gives: bytes, or a number with a K/M/G
    suffix (``KiB``, ``MB`` ... read as powers of 1024), from 1 MiB to 1 PiB."""
    text = given.strip().upper().removesuffix("B").removesuffix("I")
    unit = text[-1:] if text[-1:] in _SUFFIX else ""
    number = text[: len(text) - len(unit)].strip()
    try:
        value = float(number) * _SUFFIX[unit]  # "inf" and "nan" are out of range below
    except ValueError:
        value = -1.0
    if not 2**20 <= value <= MAX_MEMORY_BUDGET:
        raise InvalidInputError(
            f"DSTOOLKIT_MEMORY_BUDGET={given!r} is not a size from 1 MiB to 1 PiB; give bytes, "
            "or a number with a suffix, e.g. 2G or 512M"
        )
    return int(value)


def memory_budget() -> int:
    """The memory budget in bytes: :func:`set_memory_budget`, else
    ``DSTOOLKIT_MEMORY_BUDGET``, else :data:`DEFAULT_MEMORY_BUDGET`."""
    if _budget is not None:
        return _budget
    env = os.environ.get("DSTOOLKIT_MEMORY_BUDGET")
    return _parse_bytes(env) if env else DEFAULT_MEMORY_BUDGET


def set_memory_budget(nbytes: int | None) -> None:
    """Set the memory budget (bytes) for every large allocation; None restores the default."""
    global _budget
    if nbytes is not None and (isinstance(nbytes, bool) or not isinstance(nbytes, int)
                               or not 2**20 <= nbytes <= MAX_MEMORY_BUDGET):
        raise InvalidInputError(
            f"the memory budget must be a whole number of bytes, at least 1 MiB and at most "
            f"1 PiB, got "
            f"{nbytes!r}"
        )
    _budget = nbytes


def format_bytes(nbytes: float) -> str:
    """``1.95 GiB``, ``640 MiB``, ``12 KiB``."""
    for unit, size in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if nbytes >= size:
            return f"{nbytes / size:.3g} {unit}"
    return f"{int(nbytes)} bytes"


def check_memory(nbytes: float, what: str, advice: str) -> None:
    """Raise :class:`~dstoolkit.errors.MemoryBudgetError` when ``what`` would need more than the
    budget.

    ``advice`` says how to make the work smaller (fewer focal elements, fewer steps...).
    """
    budget = memory_budget()
    if not nbytes <= budget:  # NaN or inf (a size that overflowed) is over any budget
        raise MemoryBudgetError(
            f"{what} needs about {format_bytes(nbytes)}, more than the memory budget of "
            f"{format_bytes(budget)}; {advice}, or raise the budget "
            "(dstoolkit.evidence.set_memory_budget, or the environment variable "
            "DSTOOLKIT_MEMORY_BUDGET)"
        )


def rows_per_chunk(bytes_per_row: float, rows: int, what: str, advice: str,
                   share: float = 0.25) -> int:
    """How many rows (runs of a batch) to process at once so that one chunk uses at most
    ``share`` of the budget; refuses (:func:`check_memory`) when a single row does not fit.
    """
    check_memory(bytes_per_row / share, f"{what} (one run, with working space)", advice)
    return max(1, min(rows, int(share * memory_budget() // max(bytes_per_row, 1.0))))
