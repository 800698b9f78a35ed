"""The explorer of the chapter on combining evidence (book/combining_evidence.md).

Zadeh's two doctors.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets
from matplotlib.figure import Figure

from dstoolkit.evidence import (
    ZADEH_FRAME,
    conflict,
    dempster,
    yager,
    zadeh_sources,
)
from dstoolkit.plots.artists import (
    MassArtists,
    animate,
    draw_masses,
    update_masses,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)
from ._readouts import lowest_and_highest

# -- conflict: Zadeh's example -------------------------------------------------------------


def describe_doctors(numbers: Mapping[str, Any]) -> str:
    """Say what the two doctors' figure shows: where the combination puts its mass."""
    masses = {name[2:-1]: float(v) for name, v in numbers.items() if name.startswith("m(")}
    _, most = lowest_and_highest(masses, ".2f")
    return (
        f"each doctor's masses and their combination: the conflict K is "
        f"{float(numbers['conflict K']):.2f}, and the combination puts most mass "
        f"({max(masses.values()):.2f}) on {most}"
    )


def conflict_explorer(
    x: float = 0.99, y: float = 0.99, epsilon: float = 0.0, rule: str = "Dempster"
) -> Explorer:
    """Zadeh's example: two nearly certain doctors who disagree, combined.

    The doctors' masses, an optional discount ε and the rule (Dempster's or Yager's) give
    the conflict K and the combined masses: Dempster's rule puts all the mass on the
    diagnosis both found unlikely.

    Parameters
    ----------
    x, y : float, optional
        Doctor 1's m(meningitis) and doctor 2's m(concussion), in [0, 1].
    epsilon : float, optional
        The discount ε moved to Θ, in [0, 0.5].
    rule : {"Dempster", "Yager"}, optional
        The combination rule.

    Returns
    -------
    Explorer
        Controls ``x``, ``y``, ``epsilon``, ``rule``; on the static site ``epsilon`` and
        ``rule`` answer. Readout: K and the combined masses.

    See Also
    --------
    dstoolkit.evidence.dempster, dstoolkit.evidence.yager, dstoolkit.evidence.zadeh_sources

    References
    ----------
    The paper's eq. 1 (Dempster's rule) and its discussion of Zadeh's example.

    Examples
    --------
    >>> ex = conflict_explorer()
    >>> round(ex.numbers["conflict K"], 4), round(ex.numbers["m(tumour)"], 4)
    (0.9999, 1.0)
    """
    controls = {
        "x": slider("doctor 1: m(meningitis)", x, 0.0, 1.0, 0.01, readout_format=".2f"),
        "y": slider("doctor 2: m(concussion)", y, 0.0, 1.0, 0.01, readout_format=".2f"),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
        "rule": widgets.Dropdown(options=["Dempster", "Yager"], value=rule, description="rule"),
    }

    @functools.cache
    def drawn() -> tuple[Figure, list[MassArtists]]:
        """Return the figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(10, 2.8), layout="constrained")
        axes = fig.subplots(1, 3, sharey=True)
        panels = [
            draw_masses(ax, title=name, animated=True)
            for ax, name in zip(axes, ("doctor 1", "doctor 2", "combined"), strict=True)
        ]
        animate(axes[2].title, spines_of=axes[2])  # the rule's name
        return fig, panels

    def render(x: float, y: float, epsilon: float, rule: str):
        m1, m2 = zadeh_sources(x, y, epsilon)
        k = conflict(m1, m2)
        combined = dempster(m1, m2) if rule == "Dempster" else yager(m1, m2)
        fig, panels = drawn()
        update_masses(panels[0], m1)
        update_masses(panels[1], m2)
        update_masses(panels[2], combined, title=f"{rule}'s rule")
        return fig, {
            "conflict K": k,
            **{f"m({h})": combined.mass_of(h) for h in ZADEH_FRAME},
            "m(Θ)": combined.mass_of(ZADEH_FRAME),
        }

    live = {"epsilon": positions(controls["epsilon"], 11), "rule": positions(controls["rule"])}
    return Explorer(
        controls,
        render,
        title="Zadeh's two doctors",
        live=live,
        said=("conflict K", "m(tumour)"),
        describe=describe_doctors,
    )
