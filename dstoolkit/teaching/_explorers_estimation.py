"""The explorer of the chapter on estimating the level (book/estimating_level.md).

The paper's Figs. 10–11 for one run.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets

from dstoolkit.plots.artists import (
    KeptFigure,
)

from ._explorer import (
    Explorer,
    int_slider,
    positions,
    slider,
)
from ._readouts import estimation_numbers, lowest_and_highest

# -- estimating the level: the paper's Figs. 10–11 for one run ------------------------------------

#: The figures the level-estimation explorer can draw (the paper's Figs. 10 and 11).
ESTIMATION_FIGURES: dict[str, str] = {
    "Fig. 10: frequencies": "frequency",
    "Fig. 11: levels": "level",
}


def describe_estimation(numbers: Mapping[str, Any]) -> str:
    """Say what the level-estimation figure shows: which estimate stays closest to the truth."""
    errors = {
        name: float(str(value).split()[0]) for name, value in numbers.items() if name != "wrong n_k"
    }
    best, worst = lowest_and_highest(errors, ".4g")
    low, high = min(errors.values()), max(errors.values())
    return (
        f"estimates over the steps beside the truth: {best} closest "
        f"(mean error {low:.4g} mm), {worst} farthest ({high:.4g} mm); "
        f"{numbers['wrong n_k']} orders n_k wrong"
    )


def level_estimation_explorer(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    simulation: str = "frequency",
    order_rule: str = "eq43",
    figure: str = "Fig. 11: levels",
    seed: int = 0,
) -> Explorer:
    """One simulated sweep filtered by every method: the paper's Figs. 10–11 for one run.

    Level, temperature, the simulation of the readings (the paper's w drawn i.i.d., or
    detected in a synthesised recording), where n_k comes from, the run's seed and which
    figure. A waveform-level redraw synthesises and analyses a recording.

    Parameters
    ----------
    level_m : float, optional
        The level L, m.
    temperature_c : float, optional
        The temperature T, °C.
    simulation : {"frequency", "waveform"}, optional
        How the readings are simulated.
    order_rule : {"eq43", "fit", "true"}, optional
        Where the orders n_k come from.
    figure : str, optional
        "Fig. 10: frequencies" or "Fig. 11: levels" (the paper's figures).
    seed : int, optional
        The run's seed.

    Returns
    -------
    Explorer
        Controls ``level``, ``temperature``, ``simulation``, ``order_rule``, ``figure``,
        ``seed``; on the static site ``level`` and ``temperature`` answer. Readout:
        per method, mean |L̂ − L| and mean |x̂ − f|, and how many orders n_k are wrong.

    See Also
    --------
    dstoolkit.studies.gauge_run : The run.

    References
    ----------
    The paper's Figs. 10–11 and eqs. 32 and 43.

    Examples
    --------
    >>> ex = level_estimation_explorer()
    >>> "wrong n_k" in ex.numbers
    True
    """
    from dstoolkit.plots import plot_estimates
    from dstoolkit.plots.artists import update_estimates
    from dstoolkit.studies import gauge_run

    controls = {
        "level": slider("level L (m)", level_m, 1.3, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider(
            "temperature T (°C)", temperature_c, 0.0, 35.0, 0.5, readout_format=".1f"
        ),
        "simulation": widgets.Dropdown(
            options=[
                ("frequency level (i.i.d. w)", "frequency"),
                ("waveform level (recording)", "waveform"),
            ],
            value=simulation,
            description="readings",
        ),
        "order_rule": widgets.Dropdown(
            options=[("eq. 43 (paper)", "eq43"), ("series fit", "fit"), ("true", "true")],
            value=order_rule,
            description="n_k by",
        ),
        "figure": widgets.Dropdown(
            options=list(ESTIMATION_FIGURES), value=figure, description="figure"
        ),
        "seed": int_slider("run (seed)", seed, 0, 20),
    }

    kept = KeptFigure(
        functools.partial(plot_estimates, kept=True), update_estimates
    )  # one per kind of figure
    run_of = functools.lru_cache(maxsize=32)(gauge_run)  # the figure dropdown re-draws

    def render(
        level: float, temperature: float, simulation: str, order_rule: str, figure: str, seed: int
    ):
        run = run_of(level, temperature, simulation, order_rule, seed=seed)
        kind = ESTIMATION_FIGURES[figure]
        note = (
            f"L = {level:.1f} m, T = {temperature:.1f} °C,\n{simulation}-level "
            f"readings, n_k by {order_rule}, seed {seed}"
        )
        if kind == "frequency":
            fig = kept(run.truth, run.readings, run.estimates, note=note, key=kind)
        else:
            levels = run.levels()
            fig = kept(
                run.level_m,
                levels.pop("direct"),
                levels,
                quantity="level",
                unit="m",
                note=note,
                key=kind,
            )
        return fig, estimation_numbers(run)

    live = {
        "level": positions(controls["level"], 9, 1.6, 9.6),
        "temperature": positions(controls["temperature"], 1, 5.0, 5.0),
    }
    return Explorer(
        controls,
        render,
        title="One run of the gauge: the paper's Figs. 10–11 "
        "(readout: mean |L̂ − L| / mean |x̂ − f|)",
        live=live,
        said=("paper's filter", "wrong n_k"),
        describe=describe_estimation,
    )
