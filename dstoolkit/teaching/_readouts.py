"""The readouts of the filter explorers: a run's summary and one step's numbers, as text
keys a reader sees (units in the keys)."""

from __future__ import annotations

from typing import Any

import numpy as np

from dstoolkit.filters import FilterResult, converged_at
from dstoolkit.gauge import level_from_resonance


def filter_summary(seq: Any, orders: np.ndarray, result: FilterResult) -> dict[str, Any]:
    """The numbers the filter widget prints: first and last estimates, mean absolute errors
    of the estimates and of the readings (Hz), the step from which the error stays below
    1 Hz, the mean level error |L̂_k − L| with L̂_k = n_k c/(2 x̂_k) (eq. 32, mm, as in
    Table 3) and the steps in total conflict."""
    x = seq.truth[:, 0]
    est = result.estimates[:, 0]
    level = level_from_resonance(est[:-1], orders, seq.speed_of_sound)
    first = converged_at(est - x)
    return {
        "x̂_2 (Hz)": float(est[1]),
        f"x̂_{est.size} (Hz)": float(est[-1]),
        "mean |x̂ − x| (Hz)": float(np.mean(np.abs(est - x))),
        "mean |z − x| (Hz)": float(np.mean(np.abs(seq.readings[:, 0] - x))),
        "below 1 Hz from step": "never" if first is None else first,
        "mean |L̂ − L| (mm)": 1e3 * float(np.mean(np.abs(level - seq.level_m))),
        "total-conflict steps": int(np.nansum(result.diagnostics["fallback"])),
    }


def step_numbers(result: FilterResult, step: int, truth: float) -> dict[str, Any]:
    """The diagnostics of one step of a recorded run (1-based ``step`` >= 2): conflicts of
    both fusions, D, R12, R21, the focal elements of the final evidence, the estimate and
    its error."""
    d, t = result.diagnostics, step - 1
    est = float(result.estimates[t, 0])
    return {"K (Step 4)": float(d["conflict_step4"][t]),
            "K (Step 6)": float(d["conflict_step6"][t]), "D": float(d["dependence"][t]),
            "R12": float(d["r12"][t]), "R21": float(d["r21"][t]),
            "final focal elements": int(d["n_final"][t]),
            "x̂ (Hz)": est, "x̂ − x (Hz)": est - float(truth)}
