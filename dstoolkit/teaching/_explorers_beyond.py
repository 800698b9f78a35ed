"""The explorer of the chapter beyond the paper (book/beyond_the_paper.md).

Every filter under wrong noise bounds.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import ipywidgets as widgets

from dstoolkit.filters import BoundedNoise, filter_named, registered_filters
from dstoolkit.plots.artists import (
    KeptFigure,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)
from ._readouts import lowest_and_highest, mismatch_numbers

# -- beyond the paper: every filter under wrong noise bounds ------------------------------------


def describe_mismatch(numbers: Mapping[str, Any]) -> str:
    """Say what the noise-bounds figure shows: which filter's error is lowest and highest."""
    errors = {
        name.removesuffix(" (Hz)"): float(value)
        for name, value in numbers.items()
        if name.endswith("(Hz)")
    }
    best, worst = lowest_and_highest(errors)
    low, high = min(errors.values()), max(errors.values())
    return (
        f"the true and assumed noise bounds above, each filter's mean error over the steps "
        f"below: {best} lowest ({low:.3g} Hz), {worst} highest ({high:.3g} Hz)"
    )


def noise_bounds_explorer(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    runs: int = 20,
    seed: int = 0,
    start: str = "mean_corrected",
) -> Explorer:
    """Every filter on the same simulated gauge runs, each with the noise bounds you assume.

    The sliders set the lower, mode and upper of v and of w that every filter assumes: the
    figure shows the assumed against the true possibility distributions and the mean
    |x̂_k − x_k| per step of every method. Moving the start value reruns only the paper's
    filter.

    Parameters
    ----------
    level_m : float, optional
        The level L, m.
    temperature_c : float, optional
        The temperature T, °C.
    runs : int, optional
        How many runs are averaged.
    seed : int, optional
        The runs' seed.
    start : {"observation", "mean_corrected"}, optional
        The paper's filter's start value.

    Returns
    -------
    Explorer
        Controls ``v_lower`` … ``w_upper`` and ``start``; on the static site ``w_upper`` and
        ``v_upper`` answer. Readout:
        every method's mean |x̂ − x| and the bounded-error filter's inconsistent runs.

    See Also
    --------
    dstoolkit.studies.noise_mismatch : The study behind it.

    References
    ----------
    The paper's eqs. 39–40 (the gauge's model and noises).

    Examples
    --------
    >>> ex = noise_bounds_explorer(runs=2)
    >>> "bounded error: inconsistent runs" in ex.numbers
    True
    """
    from dstoolkit.plots.artists import noise_bounds_figure, update_noise_bounds_figure
    from dstoolkit.studies import noise_mismatch, tracking_data

    # every registered filter; the start value moves only the paper's filter: the others
    # are kept per noise bounds
    methods = tuple(entry.name for entry in registered_filters())
    paper = (filter_named("paper"),)
    others = tuple(m for m in methods if m not in paper)

    data = tracking_data(level_m, temperature_c, runs=runs, seed=seed)
    v, w = data.state_noise, data.obs_noise
    controls = {
        "v_lower": slider("v lower", float(v.lower[0]), -1.0, 0.0, 0.01, readout_format=".2f"),
        "v_mode": slider("v mode", float(v.mode[0]), -0.5, 0.5, 0.01, readout_format=".2f"),
        "v_upper": slider("v upper", float(v.upper[0]), 0.0, 1.0, 0.01, readout_format=".2f"),
        "w_lower": slider("w lower", float(w.lower[0]), -20.0, -4.0, 0.01, readout_format=".2f"),
        "w_mode": slider("w mode", float(w.mode[0]), -12.0, -2.0, 0.01, readout_format=".2f"),
        "w_upper": slider("w upper", float(w.upper[0]), -8.0, 5.0, 0.01, readout_format=".2f"),
        "start": widgets.Dropdown(
            options=[("z_1 (paper)", "observation"), ("z_1 + E[w]", "mean_corrected")],
            value=start,
            description="start",
        ),
    }

    title = f"L = {level_m:.1f} m, {runs} runs, true orders"
    ranges = {
        name: (controls[name].min, controls[name].max) for name in controls if name != "start"
    }
    kept = KeptFigure(
        functools.partial(
            noise_bounds_figure,
            title=title,
            v_range=(ranges["v_lower"][0], ranges["v_upper"][1]),
            w_range=(ranges["w_lower"][0], ranges["w_upper"][1]),
        ),
        update_noise_bounds_figure,
    )

    @functools.lru_cache(maxsize=4)
    def rivals(v_bounds: tuple[float, ...], w_bounds: tuple[float, ...]) -> Any:
        return noise_mismatch(
            data, BoundedNoise(*v_bounds), BoundedNoise(*w_bounds), methods=others, seed=seed
        )

    def render(
        v_lower: float,
        v_mode: float,
        v_upper: float,
        w_lower: float,
        w_mode: float,
        w_upper: float,
        start: str,
    ):
        assumed_v = BoundedNoise(v_lower, v_mode, v_upper)
        assumed_w = BoundedNoise(w_lower, w_mode, w_upper)
        rest = rivals((v_lower, v_mode, v_upper), (w_lower, w_mode, w_upper))
        ours = noise_mismatch(data, assumed_v, assumed_w, methods=paper, seed=seed, start=start)
        errors, seconds = ours.errors | rest.errors, ours.seconds | rest.seconds
        result = replace(
            rest,
            errors={m: errors[m] for m in methods},
            seconds={m: seconds[m] for m in methods},
        )
        fig = kept(v, w, assumed_v, assumed_w, result.errors)
        return fig, mismatch_numbers(result)

    live = {
        "w_upper": positions(controls["w_upper"], 8, -6.21, 4.29),
        "v_upper": positions(controls["v_upper"], 1, 0.9, 0.9),
    }
    return Explorer(
        controls,
        render,
        title="Every filter with the noise bounds you assume",
        live=live,
        said=("dependent evidence (paper) (Hz)", "bounded error: inconsistent runs"),
        describe=describe_mismatch,
    )
