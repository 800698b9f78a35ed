"""The readouts of the explorers.

The numbers a reader sees under a figure, as text keys with their units (a filter run's summary, one
step of the filter, a gauge's detection, one run of the gauge, every filter under wrong noise
bounds).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from dstoolkit.filters import FilterResult, converged_at, registered_filters
from dstoolkit.gauge import (
    DetectionResult,
    TubeSetup,
    direct_levels,
    fit_resonance_series,
    level_from_resonance,
    orders_eq43,
)
from dstoolkit.plots import STYLE


def method_label(name: str) -> str:
    """Return how the readouts name a method of the paper's Table 3.

    That is its figure label, or ``name`` itself for another method.

    Parameters
    ----------
    name : str
        A method's key ("dependent_evidence", "kalman", …).

    Returns
    -------
    str
        Its label in the figures.

    Examples
    --------
    >>> method_label("kalman"), method_label("mine")
    ('Kalman', 'mine')
    """
    style: Any = STYLE.get(name)  # a dict of mixed values: matplotlib's keywords
    return name if style is None else str(style["label"])


def filter_summary(seq: Any, orders: np.ndarray, result: FilterResult) -> dict[str, Any]:
    """Return the numbers the filter widget prints.

    First and last estimates, mean absolute errors of the estimates and of the readings (Hz), the
    step from which the error stays below 1 Hz, the mean level error |L̂_k − L| with L̂_k = n_k c/(2
    x̂_k) (eq. 32, mm, as in Table 3) and the steps in total conflict.
    """
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
    """Return the diagnostics of one step of a recorded run (1-based ``step`` >= 2).

    Conflicts of both fusions, D, R12, R21, the focal elements of the final evidence, the estimate
    and its error.
    """
    d, t = result.diagnostics, step - 1
    est = float(result.estimates[t, 0])
    return {
        "K (Step 4)": float(d["conflict_step4"][t]),
        "K (Step 6)": float(d["conflict_step6"][t]),
        "D": float(d["dependence"][t]),
        "R12": float(d["r12"][t]),
        "R21": float(d["r21"][t]),
        "final focal elements": int(d["n_final"][t]),
        "x̂ (Hz)": est,
        "x̂ − x (Hz)": est - float(truth),
    }


def gauge_reading(setup: TubeSetup, detection: DetectionResult) -> dict[str, Any]:
    """Return the numbers the gauge explorer prints for one detection in the tube ``setup``.

    The level by the series fit z_k = f_F (n_1 + s_k) + b (b free, the slope only) and by
    the paper's direct measurement (eq. 32 with the orders of eq. 43 at every reading: their
    mean and mean absolute error); how many of those orders are wrong; the detection's
    count, missed and spurious peaks.
    """
    c, f_f = setup.speed_of_sound, setup.fundamental_hz
    z = detection.frequencies
    fit = fit_resonance_series(z, detection.steps, offset_hz=None)
    true_orders = np.rint(z / f_f)
    direct = direct_levels(z, c)
    return {
        "series-fit L (m)": fit.level(c),
        "fit error (mm)": 1e3 * (fit.level(c) - setup.level_m),
        "eq. 32/43: mean L (m)": float(np.mean(direct)),
        "mean |L_k − L| (mm)": 1e3 * float(np.mean(np.abs(direct - setup.level_m))),
        "eq. 43 orders wrong": f"{int(np.sum(orders_eq43(z) != true_orders[:-1]))}/{z.size - 1}",
        "resonances": int(z.size),
        "missed": int(detection.missed.size),
        "spurious": int(detection.spurious.size),
    }


def _short_label(name: str) -> str:
    """Return a method's name in readouts that must fit two lines (the registry's short one)."""
    short = {entry.name: entry.short_label for entry in registered_filters()}
    return short.get(name) or ("direct" if name == "direct" else method_label(name))


def estimation_numbers(run: Any) -> dict[str, Any]:
    """Return what the level-estimation explorer prints for a :class:`~dstoolkit.studies.GaugeRun`.

    For the readings (direct, eq. 32) and each filter, "mean |L̂ − L| mm / mean |x̂ − f| Hz" in one
    entry, and how many orders n_k are wrong.
    """
    levels = run.levels()
    freq = run.frequency_errors()
    out: dict[str, Any] = {}
    for name in levels:
        label = _short_label(name)
        level_mm = 1e3 * float(np.mean(np.abs(levels[name] - run.level_m)))
        out[label] = f"{level_mm:.4g} mm / {float(np.mean(freq[name])):.3g} Hz"
    wrong = int(np.sum(run.orders != run.true_orders[:-1]))
    out["wrong n_k"] = f"{wrong}/{run.orders.size}"
    return out


def mismatch_numbers(result: Any) -> dict[str, Any]:
    """Mean |x̂ − x| (Hz) of each method, and the runs where the strict filter failed.

    The methods are those of a :class:`~dstoolkit.studies.MismatchResult`; the runs are
    those in which the strict bounded-error filter failed.
    """
    out: dict[str, Any] = {f"{method_label(m)} (Hz)": v for m, v in result.mean_errors().items()}
    out["bounded error: inconsistent runs"] = f"{result.inconsistent_runs:.0%}"
    return out


def lowest_and_highest(values: Mapping[str, float], fmt: str = ".3g") -> tuple[str, str]:
    """Return the names of the lowest and of the highest values, as the readout rounds them.

    The values are compared as they are shown (``fmt``), so a difference in the last bits
    of a float never decides; names that tie are joined with "and".

    Parameters
    ----------
    values : Mapping[str, float]
        Numbers by name (a method's error, say).
    fmt : str, optional
        The format they are shown in (default three significant digits).

    Returns
    -------
    tuple[str, str]
        The lowest name(s) and the highest name(s).

    Examples
    --------
    >>> lowest_and_highest({"Kalman": 0.47567157028734586, "unscented Kalman": 0.4756715702873353,
    ...                     "paper": 1.02})
    ('Kalman and unscented Kalman', 'paper')
    """
    shown = {name: float(format(float(v), fmt)) for name, v in values.items()}
    low, high = min(shown.values()), max(shown.values())
    return (
        " and ".join(name for name, v in shown.items() if v == low),
        " and ".join(name for name, v in shown.items() if v == high),
    )
