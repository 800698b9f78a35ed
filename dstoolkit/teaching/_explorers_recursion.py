"""The explorer of the chapter on the one recursion (book/one_recursion.md).

How the noise a Gaussian filter assumes, and the orders it is fed, show in its NEES and NIS.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets

from ._explorer import Explorer, positions, slider


def verdict(value: float, band: tuple[float, float]) -> str:
    """Say where an average NEES or NIS lies against its band, in words.

    Parameters
    ----------
    value : float
        The average.
    band : tuple of float
        Its χ² band (low, high).

    Returns
    -------
    str
        ``"consistent"``, ``"overconfident"`` (above) or ``"conservative"`` (below).

    Examples
    --------
    >>> verdict(2.0, (0.6, 1.4))
    'overconfident'
    """
    if value > band[1]:
        return "overconfident"
    return "conservative" if value < band[0] else "consistent"


def describe_consistency(numbers: Mapping[str, Any]) -> str:
    """Say what the consistency figure shows: the averages against the band."""
    return (
        f"average NEES and NIS over the steps against the 95 % band of a consistent filter: "
        f"NEES stays inside at {float(numbers['NEES inside (share of steps)']):.0%} of the "
        f"steps and says {numbers['NEES says']}, NIS says {numbers['NIS says']}"
    )


def consistency_explorer(
    level_m: float = 4.6,
    temperature_c: float = 26.5,
    runs: int = 50,
    seed: int = 0,
    scale: float = 1.0,
    orders: str = "true",
) -> Explorer:
    """Show the Kalman and unscented filters' NEES and NIS on the gauge, with the noise you assume.

    The runs follow the gauge's eqs. (39)–(40) with the paper's noises; the slider scales
    the bounds of both noises the filters assume (their variances by the square), the
    drop-down chooses the orders n_k fed to f: the simulation's true ones or eq. (43)'s.
    The figure shows the average NEES and NIS per step against their 95 % χ² bands.

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
    scale : float, optional
        The start value of the assumed noises' scale.
    orders : {"true", "eq43"}, optional
        The start value of the orders' source.

    Returns
    -------
    Explorer
        Controls ``scale`` and ``orders``, both answering on the static site. Readout:
        the Kalman filter's mean NEES and NIS, their bands, the share of steps whose NEES
        is inside its band, and a verdict for each.

    See Also
    --------
    dstoolkit.studies.gauge_consistency : The study behind it.

    Examples
    --------
    >>> ex = consistency_explorer(runs=5)
    >>> ex.numbers["NEES says"]
    'consistent'
    """
    from dstoolkit.plots import plot_consistency
    from dstoolkit.studies import gauge_consistency

    controls = {
        "scale": slider("assumed noise scale s", scale, 0.5, 2.0, 0.05, readout_format=".2f"),
        "orders": widgets.Dropdown(
            options=[("true orders", "true"), ("eq. 43 from the readings", "eq43")],
            value=orders,
            description="orders n_k",
        ),
    }

    @functools.lru_cache(maxsize=8)
    def study(s: float, source: str) -> Any:
        return gauge_consistency(
            level_m, temperature_c, runs=runs, seed=seed, scale=s, orders=source
        )

    def render(scale: float, orders: str):
        result = study(round(float(scale), 10), orders)
        nees = float(result.nees["kalman"].mean())
        nis = float(result.nis["kalman"][1:].mean())
        fig = plot_consistency(
            result,
            title=f"L = {level_m:.1f} m, {runs} runs, s = {scale:.2f}, "
            + ("true orders" if orders == "true" else "orders of eq. 43"),
        )
        low, high = result.nees_band
        return fig, {
            "mean NEES": nees,
            "mean NIS": nis,
            "band": f"[{low:.2f}, {high:.2f}]",
            "NEES inside (share of steps)": result.share("kalman"),
            "NEES says": verdict(nees, result.nees_band),
            "NIS says": verdict(nis, result.nis_band),
        }

    live = {
        "scale": positions(controls["scale"], 16, 0.5, 2.0),
        "orders": positions(controls["orders"]),
    }
    return Explorer(
        controls,
        render,
        title="NEES and NIS with the noise you assume",
        live=live,
        said=("NEES says", "NIS says"),
        describe=describe_consistency,
    )
