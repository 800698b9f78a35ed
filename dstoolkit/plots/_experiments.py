"""Figures of the paper's results: Fig. 10 (frequency estimates and errors per step),
Fig. 11 (level estimates and errors per step) and Table 3 as a picture."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from matplotlib.figure import Figure

from dstoolkit.studies._experiments import Table3
from dstoolkit.studies._paper_results import TABLE3_MEAN_ABS_ERROR_M

#: Colour, marker and label of each method of Table 3 in every figure.
STYLE = {
    "dependent_evidence": {"color": "C0", "label": "dependent evidence (paper)"},
    "nassreddine": {"color": "C1", "label": "Nassreddine"},
    "direct": {"color": "C2", "label": "direct (eq. 32)"},
    "kalman": {"color": "C3", "label": "Kalman"},
    "particle": {"color": "C4", "label": "particle"},
    "bounded_error": {"color": "C5", "label": "bounded error"},
}


def _style(name: str) -> dict[str, str]:
    return STYLE.get(name, {"color": "k", "label": name})


def plot_table3(table: Table3) -> Figure:
    """Mean absolute level error against the level: ours (solid) and the paper's (dashed)."""
    fig = Figure(figsize=(7.5, 4.2))
    ax = fig.add_subplot()
    methods = list(dict.fromkeys(r.method for r in table.rows))
    for m in methods:
        rows = [r for r in table.rows if r.method == m]
        st = _style(m)
        ax.plot([r.level_m for r in rows], [r.mean_abs_error_m for r in rows], "o-",
                color=st["color"], label=f"{st['label']}, ours")
        paper = [(lv, v[m]) for lv, v in TABLE3_MEAN_ABS_ERROR_M.items() if m in v]
        if paper:
            ax.plot(*zip(*paper, strict=True), "s--", color=st["color"], alpha=0.6,
                    mfc="none", label=f"{st['label']}, paper")
    ax.set_yscale("log")
    ax.set_xlabel("true level L (m)")
    ax.set_ylabel("mean |L̂ − L| (m)")
    ax.set_title(f"Table 3: {table.simulation}-level simulation, n_k by {table.order_rule}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def plot_estimates(truth: np.ndarray, readings: np.ndarray,
                   estimates: Mapping[str, np.ndarray], *, quantity: str = "frequency",
                   unit: str = "Hz") -> Figure:
    """Fig. 10 / Fig. 11: (a) estimates, truth and readings per step; (b) absolute errors.

    ``truth`` and ``readings`` have one value per step (or a scalar truth for a level);
    ``estimates`` maps method names to one value per step.
    """
    fig = Figure(figsize=(8, 5.5))
    ax_a, ax_b = fig.subplots(2, 1, sharex=True)
    steps = np.arange(1, np.size(readings) + 1)
    truth = np.broadcast_to(np.asarray(truth, dtype=float).reshape(-1), steps.shape) \
        if np.size(truth) in (1, steps.size) else np.asarray(truth)
    ax_a.plot(steps, truth, "k-", lw=1.5, label="true")
    ax_a.plot(steps, readings, ".", color="0.5", ms=4, label="readings / direct")
    ax_b.plot(steps, np.abs(np.asarray(readings) - truth), ".", color="0.5", ms=4,
              label="readings / direct")
    for name, est in estimates.items():
        st = _style(name)
        est = np.asarray(est, dtype=float).reshape(-1)
        ax_a.plot(steps[: est.size], est, "-", color=st["color"], lw=1, label=st["label"])
        ax_b.plot(steps[: est.size], np.abs(est - truth[: est.size]), "-", color=st["color"],
                  lw=1, label=st["label"])
    ax_a.set_ylabel(f"{quantity} ({unit})")
    ax_b.set_ylabel(f"|error| ({unit})")
    ax_b.set_yscale("log")
    ax_b.set_xlabel("step k")
    ax_a.legend(fontsize=7, ncol=3)
    ax_a.set_title(f"(a) estimated {quantity}")
    ax_b.set_title("(b) absolute errors")
    for ax in (ax_a, ax_b):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig
