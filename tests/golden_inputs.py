"""Helpers of the golden tests: inputs moved by a few ulps, the stand-in for another CPU.

Stored results were computed on one machine; another CPU's floating point (another SIMD
width for sums, another ``exp``/``sin``) gives inputs and intermediate values that differ
in their last bits. A golden test that holds only on the machine that wrote it is a test
of that machine, so every golden module also runs its comparison on inputs moved by
:func:`nudged` and checks the result stays within the tolerance it states.
"""

from __future__ import annotations

import numpy as np

#: How far :func:`nudged` moves each input: ±4 units in the last place.
ULPS = 4


def nudged(x: np.ndarray, seed: int, ulps: int = ULPS) -> np.ndarray:
    """Move every element of ``x`` by a random whole number of ulps in [−ulps, ulps].

    Uses :func:`numpy.nextafter`, so each element moves to one of its 2·ulps + 1 nearest
    floats (itself included), independently of the others.
    """
    out = np.array(x, dtype=float)
    steps = np.random.default_rng(seed).integers(-ulps, ulps + 1, size=out.shape)
    for s in range(1, ulps + 1):
        out = np.where(steps >= s, np.nextafter(out, np.inf), out)
        out = np.where(steps <= -s, np.nextafter(out, -np.inf), out)
    return out


def shifted(x: float, ulps: int) -> float:
    """Move ``x`` by exactly ``ulps`` units in the last place (up if positive, else down)."""
    toward = np.inf if ulps > 0 else -np.inf
    out = np.float64(x)
    for _ in range(abs(ulps)):
        out = np.nextafter(out, toward)
    return float(out)
