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

__all__ = [
    "DEFAULT_MEMORY_BUDGET",
    "MAX_MEMORY_BUDGET",
    "check_memory",
    "format_bytes",
    "memory_budget",
    "rows_per_chunk",
    "set_memory_budget",
]

#: The memory budget when nothing else is set: 1 GiB.
DEFAULT_MEMORY_BUDGET = 2**30
_SUFFIX = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30}
_budget: int | None = None


#: The largest budget one can give: 1 PiB (more is no budget at all).
MAX_MEMORY_BUDGET = 2**50


def _parse_bytes(given: str) -> int:
    """Parse the budget ``DSTOOLKIT_MEMORY_BUDGET`` gives.

    Bytes, or a number with a K/M/G suffix (``KiB``, ``MB`` ... read as powers of 1024),
    from 1 MiB to 1 PiB.
    """
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
    """Return the memory budget in bytes.

    Returns
    -------
    int
        What :func:`set_memory_budget` set, else the environment variable
        ``DSTOOLKIT_MEMORY_BUDGET`` (bytes, or with a K/M/G suffix), else
        ``DEFAULT_MEMORY_BUDGET`` (1 GiB).

    Raises
    ------
    InvalidInputError
        When ``DSTOOLKIT_MEMORY_BUDGET`` is not a size from 1 MiB to 1 PiB.

    See Also
    --------
    set_memory_budget

    Examples
    --------
    >>> from dstoolkit.utils.budget import memory_budget, set_memory_budget
    >>> set_memory_budget(2**28)
    >>> memory_budget()
    268435456
    >>> set_memory_budget(None)
    """
    if _budget is not None:
        return _budget
    env = os.environ.get("DSTOOLKIT_MEMORY_BUDGET")
    return _parse_bytes(env) if env else DEFAULT_MEMORY_BUDGET


def set_memory_budget(nbytes: int | None) -> None:
    """Set the memory budget for every large allocation of the package.

    Parameters
    ----------
    nbytes : int or None
        The budget in bytes, from 1 MiB to 1 PiB; None restores the default (the environment
        variable ``DSTOOLKIT_MEMORY_BUDGET``, else 1 GiB).

    Raises
    ------
    InvalidInputError
        When ``nbytes`` is not a whole number of bytes in that range.

    See Also
    --------
    memory_budget

    Examples
    --------
    >>> from dstoolkit.utils.budget import set_memory_budget
    >>> set_memory_budget(512 * 2**20)  # 512 MiB for what follows
    >>> set_memory_budget(None)
    """
    global _budget
    if nbytes is not None and (
        isinstance(nbytes, bool)
        or not isinstance(nbytes, int)
        or not 2**20 <= nbytes <= MAX_MEMORY_BUDGET
    ):
        raise InvalidInputError(
            f"the memory budget must be a whole number of bytes, at least 1 MiB and at most "
            f"1 PiB, got "
            f"{nbytes!r}"
        )
    _budget = nbytes


def format_bytes(nbytes: float) -> str:
    """Write a size in bytes as people read it.

    Parameters
    ----------
    nbytes : float
        A size in bytes.

    Returns
    -------
    str
        Three significant digits in the largest binary unit that fits (GiB, MiB, KiB), or
        whole bytes below 1 KiB.

    Examples
    --------
    >>> from dstoolkit.utils.budget import format_bytes
    >>> format_bytes(2_100_000_000), format_bytes(640 * 2**20), format_bytes(12)
    ('1.96 GiB', '640 MiB', '12 bytes')
    """
    for unit, size in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if nbytes >= size:
            return f"{nbytes / size:.3g} {unit}"
    return f"{int(nbytes)} bytes"


def check_memory(nbytes: float, what: str, advice: str) -> None:
    """Refuse work that would need more memory than the budget, before it starts.

    Parameters
    ----------
    nbytes : float
        The memory the work would need, in bytes (NaN or inf, from a size that overflowed,
        is over any budget).
    what : str
        What the work is, as the message should name it ("Dempster's rule on 4000 × 4000
        focal elements").
    advice : str
        How to make the work smaller ("use fewer focal elements").

    Raises
    ------
    MemoryBudgetError
        When ``nbytes`` exceeds :func:`memory_budget`; the message gives both sizes, the
        advice and how to raise the budget.

    See Also
    --------
    rows_per_chunk, memory_budget

    Examples
    --------
    >>> from dstoolkit.utils.budget import check_memory
    >>> check_memory(2**20, "a small product", "use fewer focal elements")
    >>> check_memory(2**60, "a huge product", "use fewer focal elements")
    Traceback (most recent call last):
    ...
    dstoolkit.errors.MemoryBudgetError: a huge product needs about 1.07e+09 GiB, ...
    """
    budget = memory_budget()
    if not nbytes <= budget:  # NaN or inf (a size that overflowed) is over any budget
        raise MemoryBudgetError(
            f"{what} needs about {format_bytes(nbytes)}, more than the memory budget of "
            f"{format_bytes(budget)}; {advice}, or raise the budget "
            "(dstoolkit.evidence.set_memory_budget, or the environment variable "
            "DSTOOLKIT_MEMORY_BUDGET)"
        )


def rows_per_chunk(
    bytes_per_row: float, rows: int, what: str, advice: str, share: float = 0.25
) -> int:
    """Return how many rows (runs of a batch) to process at once within the budget.

    Parameters
    ----------
    bytes_per_row : float
        The memory one row needs, in bytes.
    rows : int
        How many rows there are in all.
    what, advice : str
        As for :func:`check_memory`, used when a single row does not fit.
    share : float, optional
        The fraction of the budget one chunk may use (the rest is working space).

    Returns
    -------
    int
        A chunk size from 1 to ``rows``.

    Raises
    ------
    MemoryBudgetError
        When one row with its working space does not fit in the budget.

    Examples
    --------
    >>> from dstoolkit.utils.budget import rows_per_chunk, set_memory_budget
    >>> set_memory_budget(2**30)
    >>> rows_per_chunk(2**20, rows=10_000, what="a batch", advice="use fewer runs")
    256
    >>> set_memory_budget(None)
    """
    check_memory(bytes_per_row / share, f"{what} (one run, with working space)", advice)
    return max(1, min(rows, int(share * memory_budget() // max(bytes_per_row, 1.0))))
