"""The explorer of the chapter on belief functions beyond Dempster (book/beyond_dempster.md).

The same evidence fused with itself: which rule counts it once.
"""

from __future__ import annotations

from typing import Any

import ipywidgets as widgets

from ._ex_belief import RULES, copies_belief
from ._explorer import Explorer, positions, slider

#: The most copies the explorer fuses.
MAX_COPIES = 6


def copies_explorer(shared: float = 0.4, copies: int = 3) -> Explorer:
    """Show Bel({ok}) when one source is fused with copies of itself, by three rules.

    The source is m({ok}) = ``shared``, m({ok, high}) = m(Θ) = (1 − shared)/2 on the frame
    {low, ok, high}. Fusing copies of it adds no information: the cautious rule is
    idempotent and leaves Bel({ok}) where it is; Dempster's rule counts each copy as a new
    witness; the paper's rule (eqs. 9–10, fusing the copies one after the other) discounts
    them by their dependence first.

    Parameters
    ----------
    shared : float, optional
        The start value of m({ok}).
    copies : int, optional
        The start value of the number of copies fused (1 is the source alone).

    Returns
    -------
    Explorer
        Controls ``shared`` and ``copies``, both answering on the static site. Readout:
        Bel({ok}) by each rule after that many copies.

    Examples
    --------
    >>> ex = copies_explorer(0.4, 3)
    >>> round(ex.numbers["Bel({ok}), cautious rule"], 6)
    0.4
    """
    from dstoolkit.plots import RULE_STYLE, plot_rule_curves

    controls = {
        "shared": slider("source's m({ok})", shared, 0.1, 0.9, 0.1, readout_format=".1f"),
        "copies": widgets.IntSlider(
            value=int(copies),
            min=1,
            max=MAX_COPIES,
            step=1,
            description="copies n",
            continuous_update=False,
            style={"description_width": "initial"},
        ),
    }

    def render(shared: float, copies: int) -> tuple[Any, dict[str, Any]]:
        ns = list(range(1, MAX_COPIES + 1))
        curves = {rule: [copies_belief(shared, n, rule) for n in ns] for rule in RULES}
        fig = plot_rule_curves(
            ns,
            curves,
            xlabel="copies of the source fused, n (no unit)",
            ylabel="Bel({ok})",
            current=copies,
            title=f"one source, m({{ok}}) = {shared:.1f}, fused with itself",
        )
        fig.axes[0].set_ylim(0.0, 1.02)
        return fig, {
            f"Bel({{ok}}), {RULE_STYLE[rule]['label']}": curves[rule][int(copies) - 1]
            for rule in RULES
        }

    live = {
        "shared": positions(controls["shared"], 9),
        "copies": positions(controls["copies"], MAX_COPIES),
    }
    return Explorer(
        controls, render, title="Fusing a source with itself: who counts it once?", live=live
    )
