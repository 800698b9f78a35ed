"""Summaries of a filter run against the truth."""

from __future__ import annotations

from typing import Any

import numpy as np


def enclosure_summary(result: Any, truth: Any) -> dict[str, Any]:
    """How well a run's bounds enclose the truth.

    Parameters
    ----------
    result : FilterResult
        One run; its ``lower``/``upper`` (T, n), and ``diagnostics
        ["resets"]`` when the filter has it (the bounded-error filter).
    truth : array_like, shape (T, n) or (T,)
        The true states.

    Returns
    -------
    dict
        ``"first empty box"`` (the first step whose box became empty, or ``"never"``),
        ``"truth inside (fraction of steps)"`` and ``"mean width"`` (the state's unit).

    See Also
    --------
    converged_at : when the error settles.

    Examples
    --------
    >>> from dstoolkit.filters import BoundedErrorFilter, random_walk
    >>> run = BoundedErrorFilter().run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
    >>> enclosure_summary(run, [1.0, 1.1, 1.0, 1.05])["truth inside (fraction of steps)"]
    1.0
    """
    resets = np.flatnonzero(result.diagnostics.get("resets", np.zeros(0, bool)))
    x = np.asarray(truth).reshape(result.lower.shape)
    inside = np.all((result.lower <= x) & (x <= result.upper), axis=-1)
    return {
        "first empty box": int(resets[0]) if resets.size else "never",
        "truth inside (fraction of steps)": float(inside.mean()),
        "mean width": float(np.mean(result.upper - result.lower)),
    }


def converged_at(errors: Any, threshold: float = 1.0) -> int | None:
    """Find the first step from which every |error| stays below a threshold.

    Parameters
    ----------
    errors : array_like, shape (T,)
        The estimation errors of steps 1..T (the state's unit).
    threshold : float
        The bound, in the errors' unit.

    Returns
    -------
    int or None
        k (1-based); None when the last error is not below ``threshold``.

    See Also
    --------
    enclosure_summary : whether the bounds hold the truth.

    Examples
    --------
    >>> converged_at([3.0, 0.5, 2.0, 0.4, 0.2])
    4
    """
    below = np.abs(np.asarray(errors, dtype=float).reshape(-1)) < threshold
    if not below[-1]:
        return None
    above = np.flatnonzero(~below)
    return int(above[-1] + 2) if above.size else 1
