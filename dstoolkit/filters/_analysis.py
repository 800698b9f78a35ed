"""Summaries of a filter run against the truth."""

from __future__ import annotations

from typing import Any

import numpy as np


def enclosure_summary(result: Any, truth: Any) -> dict[str, Any]:
    """First step whose box became empty (or "never"), the fraction of steps whose band
    holds the truth, and the mean band width, of a filter run."""
    resets = np.flatnonzero(result.diagnostics.get("resets", np.zeros(0, bool)))
    x = np.asarray(truth).reshape(result.lower.shape)
    inside = np.all((result.lower <= x) & (x <= result.upper), axis=-1)
    return {"first empty box": int(resets[0]) if resets.size else "never",
            "truth inside (fraction of steps)": float(inside.mean()),
            "mean width": float(np.mean(result.upper - result.lower))}


def converged_at(errors: Any, threshold: float = 1.0) -> int | None:
    """The first step k (1-based) from which every |error| stays below ``threshold``;
    None when the last one is not below it."""
    below = np.abs(np.asarray(errors, dtype=float).reshape(-1)) < threshold
    if not below[-1]:
        return None
    above = np.flatnonzero(~below)
    return int(above[-1] + 2) if above.size else 1
