"""The explorer of the chapter on belief functions beyond Dempster (book/beyond_dempster.md).

The same evidence fused with itself: which rule counts it once.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets

from ._ex_belief import RULES, copies_belief
from ._explorer import Explorer, positions, slider
from ._readouts import lowest_and_highest

#: The most copies the explorer fuses.
MAX_COPIES = 6


def describe_copies(numbers: Mapping[str, Any]) -> str:
    """Say what the copies figure shows: which rule believes {ok} most and least at n.

    The rules are compared as the readout shows them (four decimals), so that rules which
    agree there are named together.
    """
    by_rule = {name.split(", ", 1)[1]: float(value) for name, value in numbers.items()}
    low, high = lowest_and_highest(by_rule, ".4f")
    lines = "Bel({ok}) against the number of copies fused, one line per rule"
    if low == high:
        return f"{lines}; at the marked number of copies all the rules agree"
    return f"{lines}; at the marked number of copies {high} believes {{ok}} most, {low} least"


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

    # the readout's names: the rules' labels without their equation numbers, which a
    # screen reader would otherwise read after the value
    name = {rule: f"Bel({{ok}}), {RULE_STYLE[rule]['label'].split(' (')[0]}" for rule in RULES}

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
        return fig, {name[rule]: curves[rule][int(copies) - 1] for rule in RULES}

    live = {
        "shared": positions(controls["shared"], 9),
        "copies": positions(controls["copies"], MAX_COPIES),
    }
    paper, _, dempster = (name[rule] for rule in RULES)
    return Explorer(
        controls,
        render,
        title="Fusing a source with itself: who counts it once?",
        live=live,
        said=(paper, dempster),
        describe=describe_copies,
    )
