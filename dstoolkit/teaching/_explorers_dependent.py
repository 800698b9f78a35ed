"""The explorer of the chapter on dependent evidence (book/dependent_evidence.md).

The paper's Appendix A.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets
from matplotlib.figure import Figure

from dstoolkit.evidence import (
    MassRule,
    appendix_evidence,
    combine_dependent,
    dempster,
    dependence,
)
from dstoolkit.plots.artists import (
    FocalIntervalArtists,
    animate,
    draw_focal_intervals,
    update_focal_intervals,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)

# -- dependent evidence: the paper's Appendix A -----------------------------------------------


def describe_dependent(numbers: Mapping[str, Any]) -> str:
    """Say what the dependent-evidence figure shows: where the two combinations' means lie."""
    dep, naive = float(numbers["E[dependent]"]), float(numbers["E[Dempster]"])
    side = "above" if dep > naive else "below"
    return (
        f"the focal intervals of E1, E2, their dependent combination and Dempster's: with "
        f"dependence D {float(numbers['D']):.2f} the dependent combination's expectation "
        f"{dep:.3g} lies {abs(dep - naive):.3g} {side} Dempster's"
    )


def dependent_combination_explorer(
    a2: float = 0.6, a3: float = 0.1, b2: float = 0.3, b3: float = 0.6, mass_rule: MassRule = "min"
) -> Explorer:
    """Return the paper's Appendix A, live: two dependent pieces of evidence and their combination.

    Vary the masses of E1 and E2: their energies, the degree of dependence D, the
    dependency coefficients R12, R21 and the combined evidence, beside plain Dempster that
    treats them as independent.

    Parameters
    ----------
    a2, a3 : float, optional
        E1's masses on [0.30, 1.90] and [0.32, 1.93] (the paper's values by default).
    b2, b3 : float, optional
        E2's masses on [0.41, 1.61] and [0.30, 1.90].
    mass_rule : {"min", "m1", "m2"}, optional
        How m(D) is taken from the two masses.

    Returns
    -------
    Explorer
        Controls ``a2``, ``a3``, ``b2``, ``b3``, ``mass_rule``; on the static site ``a2``
        answers. Readout: En'(E1), En'(E2), En'(E1,E2), D, R12, R21 and both pignistic
        expectations.

    See Also
    --------
    dstoolkit.evidence.dependence, dstoolkit.evidence.combine_dependent

    References
    ----------
    The paper's eqs. A1–A6 (energies, D, R12, R21) and A7–A8, then eq. 1.

    Examples
    --------
    >>> ex = dependent_combination_explorer()
    >>> 0.0 < ex.numbers["D"] < 1.0
    True
    """
    controls = {
        "a2": slider("m1([0.30, 1.90])", a2, 0.0, 1.0, 0.05, readout_format=".2f"),
        "a3": slider("m1([0.32, 1.93])", a3, 0.0, 1.0, 0.05, readout_format=".2f"),
        "b2": slider("m2([0.41, 1.61])", b2, 0.0, 1.0, 0.05, readout_format=".2f"),
        "b3": slider("m2([0.30, 1.90])", b3, 0.0, 1.0, 0.05, readout_format=".2f"),
        "mass_rule": widgets.Dropdown(
            options=["min", "m1", "m2"], value=mass_rule, description="m(D) rule"
        ),
    }
    names = ("E1", "E2", "dependent combination (A7–A8, then eq. 1)", "Dempster as if independent")

    @functools.cache
    def drawn() -> tuple[Figure, list[tuple[FocalIntervalArtists, Any]]]:
        """Return the figure, made by the first render and updated by the others.

        Per panel, the bars and the red line at the pignistic expectation.
        """
        fig = Figure(figsize=(10, 4.6), layout="constrained")
        axes = fig.subplots(2, 2, sharex=True)
        panels = [
            (
                draw_focal_intervals(ax, title=name, animated=True),
                ax.axvline(0.0, color="#d62728", lw=1.2),
            )
            for ax, name in zip(axes.flat, names, strict=True)
        ]
        for bars, line in panels:
            animate(line, spines_of=bars.ax)
        return fig, panels

    def render(a2: float, a3: float, b2: float, b3: float, mass_rule: MassRule):
        e1, e2 = appendix_evidence((a2, a3), (b2, b3))
        dep = dependence(e1, e2, mass_rule=mass_rule)
        both = combine_dependent(e1, e2, mass_rule=mass_rule)
        naive = dempster(e1, e2)
        fig, panels = drawn()
        for (bars, line), ev in zip(panels, (e1, e2, both, naive), strict=True):
            update_focal_intervals(bars, ev, xlim=(-0.4, 3.6))
            line.set_xdata([ev.pignistic_expectation_1d()] * 2)
        return fig, {
            "En'(E1)": dep.energy1,
            "En'(E2)": dep.energy2,
            "En'(E1,E2)": dep.joint_energy,
            "D": dep.degree,
            "R12": dep.r12,
            "R21": dep.r21,
            "E[dependent]": both.pignistic_expectation_1d(),
            "E[Dempster]": naive.pignistic_expectation_1d(),
        }

    live = {"a2": positions(controls["a2"], 9, 0.0, 0.8)}
    return Explorer(
        controls,
        render,
        title="Dependent evidence: the paper's Appendix A",
        live=live,
        said=("D", "E[dependent]"),
        describe=describe_dependent,
    )
