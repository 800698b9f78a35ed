"""The explorer of the chapter from a bounded noise to evidence (book/noise_to_evidence.md)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from dstoolkit.evidence import (
    default_theta,
    triangular_evidence,
)
from dstoolkit.plots.artists import (
    FocalIntervalArtists,
    PboxArtists,
    PossibilityArtists,
    draw_focal_intervals,
    draw_pbox,
    draw_possibility,
    pbox_grid,
    update_focal_intervals,
    update_pbox,
    update_possibility,
)

from ._explorer import (
    Explorer,
    int_slider,
    positions,
    slider,
)

# -- from a bounded noise to evidence ----------------------------------------------------------


def describe_noise(numbers: Mapping[str, Any]) -> str:
    """Say what the noise-to-evidence figure shows: the cuts, their mass and the p-box."""
    expectation = float(numbers["pignistic expectation"])
    return (
        f"the possibility distribution with its α-cuts, the nested focal intervals each "
        f"carrying {float(numbers['mass per cut']):.3g}, and the p-box between belief and "
        f"plausibility; the pignistic expectation lies at {expectation:.3g}"
    )


def noise_evidence_explorer(
    lower: float = -0.3,
    mode: float = 0.0,
    upper: float = 0.3,
    p: int = 3,
    epsilon: float = 0.05,
) -> Explorer:
    """From a bounded noise to evidence: α-cuts of a triangular possibility distribution.

    The support [lower, upper], the mode, the number of α-cuts p and the discount ε give
    the focal elements and the p-box. The slider ranges follow the support given.

    Parameters
    ----------
    lower, mode, upper : float, optional
        The noise's support and mode (default the paper's state noise, Table 1).
    p : int, optional
        The number of α-cuts, 1 to 12.
    epsilon : float, optional
        The discount ε (the mass on Θ), in [0, 0.5].

    Returns
    -------
    Explorer
        Controls ``lower``, ``mode``, ``upper``, ``p``, ``epsilon``; on the static site ``p``
        and ``epsilon`` answer. Readout: the mass per cut, m(Θ), Θ and the pignistic
        expectation.

    See Also
    --------
    dstoolkit.evidence.triangular_evidence : The evidence drawn.

    References
    ----------
    The paper's eqs. 22–26.

    Examples
    --------
    >>> ex = noise_evidence_explorer(p=4, epsilon=0.2)
    >>> round(ex.numbers["mass per cut"], 2)
    0.2
    """
    span = upper - lower if upper > lower else 1.0
    step = float(10.0 ** np.floor(np.log10(span / 200.0)))
    controls = {
        "lower": slider("lower a", lower, lower - span, upper, step),
        "mode": slider("mode c", mode, lower - span, upper + span, step),
        "upper": slider("upper b", upper, lower, upper + span, step),
        "p": int_slider("cuts p", p, 1, 12),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
    }
    view = (lower - 0.6 * span, upper + 0.6 * span)

    @functools.cache
    def drawn() -> tuple[Figure, PossibilityArtists, FocalIntervalArtists, PboxArtists]:
        """Return the figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(12, 3.0), layout="constrained")
        ax1, ax2, ax3 = fig.subplots(1, 3)
        return (
            fig,
            draw_possibility(ax1, view, evidence=True, title="π and its α-cuts", animated=True),
            draw_focal_intervals(ax2, title="focal elements", animated=True),
            draw_pbox(ax3, pbox_grid(*view), title="p-box", animated=True),
        )

    def render(lower: float, mode: float, upper: float, p: int, epsilon: float):
        ev = triangular_evidence(lower, mode, upper, p=p, epsilon=epsilon)
        fig, possibility, bars, pbox = drawn()
        update_possibility(possibility, lower, mode, upper, p, evidence=ev)
        update_focal_intervals(bars, ev, xlim=view, label_masses=p <= 6)
        update_pbox(pbox, ev)
        t_lo, t_hi = default_theta(lower, mode, upper)
        return fig, {
            "mass per cut": (1.0 - epsilon) / p,
            "m(Θ)": epsilon,
            "Θ": f"[{t_lo:.4g}, {t_hi:.4g}]",
            "pignistic expectation": ev.pignistic_expectation_1d(),
        }

    live = {
        "p": positions(controls["p"], 8, 1, 8),
        "epsilon": positions(controls["epsilon"], 2, 0.0, 0.5),
    }
    return Explorer(
        controls,
        render,
        title="From a bounded noise to evidence",
        live=live,
        said=("mass per cut", "pignistic expectation"),
        describe=describe_noise,
    )
