"""The explorers of the chapter on the recursive filter (book/recursive_filter.md)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets
from matplotlib.figure import Figure

from dstoolkit.evidence import MassRule
from dstoolkit.plots import (
    FilterErrorsFigure,
    FilterStepFigure,
    plot_filter_errors,
)
from dstoolkit.plots.artists import (
    KeptFigure,
)
from dstoolkit.studies import ORDER_SOURCES, filter_case, gauge_case

from ._explorer import (
    Explorer,
    int_slider,
    positions,
    slider,
)
from ._readouts import filter_summary, step_numbers

# -- the recursive filter on the gauge (book/recursive_filter.md) ---------------------------------


def render_filter(
    v_lower: float,
    v_mode: float,
    v_upper: float,
    w_lower: float,
    w_mode: float,
    w_upper: float,
    p: int,
    epsilon: float,
    level: float,
    temperature: float,
    start: str,
    orders: str,
    mass_rule: MassRule,
    seed: int = 0,
    kept: KeptFigure[FilterErrorsFigure] | None = None,
) -> tuple[Figure, dict[str, Any]]:
    """One run of the paper's filter on a simulated gauge: its figure and its numbers.

    What :func:`filter_widget` recomputes on every change.

    Parameters
    ----------
    v_lower, v_mode, v_upper : float
        The state noise v the filter assumes, Hz.
    w_lower, w_mode, w_upper : float
        The observation noise w the filter assumes, Hz (the readings carry the paper's).
    p : int
        The number of α-cuts.
    epsilon : float
        The discount ε.
    level : float
        The level L, m.
    temperature : float
        The temperature T, °C.
    start : {"observation", "mean_corrected"}
        The start value: z_1 (the paper's) or z_1 + E[w].
    orders : str
        Where the orders n_k come from (a key of :data:`dstoolkit.studies.ORDER_SOURCES`).
    mass_rule : {"min", "m1", "m2"}
        How m(D) is taken.
    seed : int, optional
        The readings' seed.
    kept : optional
        A ``KeptFigure`` of a ``FilterErrorsFigure`` (as the widget holds): drawn without
        pyplot on the first call, redrawn in place later; without it every call draws a new
        figure.

    Returns
    -------
    figure : Figure
        Estimates, hull and readings against the truth, and the absolute errors (the
        paper's Fig. 10).
    numbers : dict[str, Any]
        The run's first and last estimates, mean errors, convergence step, mean level
        error and total-conflict steps.

    See Also
    --------
    filter_widget, dstoolkit.studies.filter_case

    References
    ----------
    The paper's §3.2, eqs. 39–40.

    Examples
    --------
    >>> fig, numbers = render_filter(-0.3, 0.0, 0.3, -10.59, -6.9, -3.21, 3, 0.05, 9.6, 23.9,
    ...                              "observation", "true", "min")
    >>> numbers["mean |x̂ − x| (Hz)"] < numbers["mean |z − x| (Hz)"]
    True
    """
    seq, n, result = filter_case(
        level,
        temperature,
        state_noise=(v_lower, v_mode, v_upper),
        obs_noise=(w_lower, w_mode, w_upper),
        p=p,
        epsilon=epsilon,
        start=start,
        mass_rule=mass_rule,
        orders=orders,
        seed=seed,
    )
    run = (result, seq.truth, seq.readings)
    title = (
        f"L = {level:.1f} m, T = {temperature:.1f} °C (f_F = {seq.fundamental_hz:.2f} "
        f"Hz, {seq.truth.shape[0]} resonances), p = {p}, ε = {epsilon:.2f}, "
        f"start: {start}"
    )
    fig = plot_filter_errors(*run, title=title) if kept is None else kept(*run, title=title).figure
    return fig, filter_summary(seq, n, result)


def describe_filter(numbers: Mapping[str, Any]) -> str:
    """Say what the filter widget's figure shows: the estimate's error against the readings'."""
    est, obs = float(numbers["mean |x̂ − x| (Hz)"]), float(numbers["mean |z − x| (Hz)"])
    below = numbers["below 1 Hz from step"]
    settles = (
        "never stays below 1 Hz" if below == "never" else f"stays below 1 Hz from step {below}"
    )
    closer = f"{obs / est:.1f} times closer to the truth than" if est < obs else "no closer than"
    return (
        f"deviations from the truth over the steps: the estimate's error {settles}, "
        f"on average {closer} the readings"
    )


def describe_step(numbers: Mapping[str, Any]) -> str:
    """Say what one step of the filter shows: where the estimate lies against the truth."""
    error = float(numbers["x̂ − x (Hz)"])
    side = "above" if error > 0 else "below"
    return (
        f"the step's evidence, its fusion and the final focal elements over the state; "
        f"the estimate lies {abs(error):.2f} Hz {side} the truth, with dependence D "
        f"{float(numbers['D']):.2f}"
    )


def filter_widget(
    level_m: float = 9.6,
    temperature_c: float = 23.9,
    *,
    p: int = 3,
    epsilon: float = 0.05,
    start: str = "observation",
    state_noise: tuple[float, float, float] = (-0.3, 0.0, 0.3),
    obs_noise: tuple[float, float, float] = (-10.59, -6.9, -3.21),
    seed: int = 0,
) -> Explorer:
    """Return the paper's filter on a simulated gauge, live.

    Every redraw is one filter run of about 83 steps and its figure
    (:func:`render_filter`); sliders follow the drag, the latest value winning.

    Parameters
    ----------
    level_m : float, optional
        The start level L, m.
    temperature_c : float, optional
        The start temperature T, °C.
    p : int, optional
        The number of α-cuts.
    epsilon : float, optional
        The discount ε.
    start : {"observation", "mean_corrected"}, optional
        The start value.
    state_noise, obs_noise : tuple of float, optional
        (lower, mode, upper) of v and w the filter assumes at the start, Hz (the paper's).
    seed : int, optional
        The readings' seed.

    Returns
    -------
    Explorer
        Controls: the assumed noise bounds (``v_lower`` … ``w_upper``), ``p``, ``epsilon``,
        ``level``, ``temperature``, ``start``, ``orders``, ``mass_rule``; on the static site
        ``level`` and ``epsilon`` answer. Readout: first and last estimates, mean errors,
        convergence step, mean level error and total-conflict steps.

    See Also
    --------
    render_filter, filter_step_explorer

    References
    ----------
    The paper's §3.2, eqs. 39–40, and its Fig. 10.

    Examples
    --------
    >>> ex = filter_widget()
    >>> ex.numbers["total-conflict steps"]
    0
    """
    (v_lo, v_c, v_hi), (w_lo, w_c, w_hi) = state_noise, obs_noise
    controls = {
        "v_lower": slider("v lower", v_lo, -1.0, 0.0, 0.01, readout_format=".2f"),
        "v_mode": slider("v mode", v_c, -1.0, 1.0, 0.01, readout_format=".2f"),
        "v_upper": slider("v upper", v_hi, 0.0, 1.0, 0.01, readout_format=".2f"),
        "w_lower": slider("w lower", w_lo, -20.0, 0.0, 0.01, readout_format=".2f"),
        "w_mode": slider("w mode", w_c, -20.0, 5.0, 0.01, readout_format=".2f"),
        "w_upper": slider("w upper", w_hi, -10.0, 5.0, 0.01, readout_format=".2f"),
        "p": int_slider("cuts p", p, 1, 8),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
        "level": slider("level L (m)", level_m, 1.0, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider(
            "temperature T (°C)", temperature_c, 0.0, 40.0, 0.1, readout_format=".1f"
        ),
        "start": widgets.Dropdown(
            options=[("z_1 (paper)", "observation"), ("z_1 + E[w]", "mean_corrected")],
            value=start,
            description="start",
        ),
        "orders": widgets.Dropdown(
            options=list(ORDER_SOURCES.items()), value="true", description="orders"
        ),
        "mass_rule": widgets.Dropdown(
            options=["min", "m1", "m2"], value="min", description="m(D) rule"
        ),
    }

    kept = KeptFigure(
        functools.partial(FilterErrorsFigure, pyplot=False), FilterErrorsFigure.update
    )

    def render(**values: Any) -> tuple[Figure, dict[str, Any]]:
        return render_filter(**values, seed=seed, kept=kept)

    live = {
        "level": positions(controls["level"], 9, 1.6, 9.6),
        "epsilon": positions(controls["epsilon"], 3, 0.0, 0.5),
    }
    return Explorer(
        controls,
        render,
        title="The dependent-evidence filter on a simulated gauge",
        live=live,
        said=("mean |x̂ − x| (Hz)", "mean |L̂ − L| (mm)"),
        describe=describe_filter,
    )


def filter_step_explorer(
    level_m: float = 9.6,
    temperature_c: float = 23.9,
    step: int = 2,
    start: str = "mean_corrected",
    epsilon: float = 0.05,
    steps: int = 20,
    seed: int = 0,
) -> Explorer:
    """Every evidence of one step of the paper's filter, with its diagnostics.

    On the first ``steps`` readings of a simulated gauge (true orders): pick the step, the
    start value and the discount ε. Moving the step redraws; it does not filter again.

    Parameters
    ----------
    level_m : float, optional
        The level L, m.
    temperature_c : float, optional
        The temperature T, °C.
    step : int, optional
        The start step k + 1, from 2.
    start : {"observation", "mean_corrected"}, optional
        The start value.
    epsilon : float, optional
        The discount ε.
    steps : int, optional
        How many readings are filtered.
    seed : int, optional
        The readings' seed.

    Returns
    -------
    Explorer
        Controls ``step``, ``start``, ``epsilon``; on the static site ``step`` answers.
        Readout: the conflicts of Steps 4 and 6, D, R12, R21, the final focal elements, the
        estimate and its error.

    See Also
    --------
    dstoolkit.plots.FilterStepFigure : The figure.

    References
    ----------
    The paper's Steps 2–6 and Fig. 3.

    Examples
    --------
    >>> ex = filter_step_explorer(steps=4)
    >>> sorted(ex.numbers)[:2]
    ['D', 'K (Step 4)']
    """
    controls = {
        "step": int_slider("step k + 1", step, 2, steps),
        "start": widgets.Dropdown(
            options=[("z_1 (paper)", "observation"), ("z_1 + E[w]", "mean_corrected")],
            value=start,
            description="start",
        ),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
    }

    seq = gauge_case(level_m, temperature_c, seed)

    @functools.lru_cache(maxsize=8)  # moving the step re-draws, it does not re-filter
    def run(start: str, epsilon: float) -> Any:
        return filter_case(
            level_m,
            temperature_c,
            start=start,
            epsilon=epsilon,
            seed=seed,
            record=True,
            first=steps,
        )[2]

    kept = KeptFigure(
        functools.partial(FilterStepFigure, figsize=(9.0, 9.0), pyplot=False),
        FilterStepFigure.update,
    )

    def render(step: int, start: str, epsilon: float):
        result = run(start, epsilon)
        entry, truth = result.steps[step - 1], float(seq.truth[step - 1, 0])
        figure = kept(entry, truth, key=FilterStepFigure.panels_of(entry))  # one per panels
        return figure.figure, step_numbers(result, step, truth)

    live = {"step": positions(controls["step"], 10)}
    return Explorer(
        controls,
        render,
        title="Inside one step of the filter",
        live=live,
        said=("x̂ (Hz)", "x̂ − x (Hz)"),
        describe=describe_step,
    )
