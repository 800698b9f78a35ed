"""The explorer of the chapter on random sets (book/random_sets.md): the image of an interval
by several methods."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import ipywidgets as widgets
import numpy as np
from matplotlib.figure import Figure

from dstoolkit.errors import (
    EvidenceError,
    NotMonotoneError,
)
from dstoolkit.plots.artists import (
    animate,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)

# -- random sets and the extension principle (book/random_sets.md) -------------------------------

#: Functions of one variable for :func:`extension_explorer`, vectorised on points (..., 1).
EXTENSION_FUNCTIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "x²": lambda x: x[..., 0] ** 2,
    "sin x": lambda x: np.sin(x[..., 0]),
    "x³ − 3x": lambda x: x[..., 0] ** 3 - 3.0 * x[..., 0],
    "exp(−x)": lambda x: np.exp(-x[..., 0]),
    "2x + 1": lambda x: 2.0 * x[..., 0] + 1.0,
}
IMAGE_METHOD_NAMES: tuple[str, ...] = ("vertex", "monotone", "subdivision")


def compare_image_methods(
    f: Callable[[np.ndarray], np.ndarray], lo: Any, hi: Any, signs: Any = 1
) -> dict[str, dict[str, Any]]:
    """The image of one box [lo, hi] through f by the vertex method (Prop. 1), the monotone
    shortcut with the declared ``signs`` (Prop. 2) and subdivision (the fallback).

    Returns, per method, ``image`` ((lo, hi) or None when the method refused), ``message``
    (the VertexMethodWarning or NotMonotoneError text, else "") and ``evaluations`` (how
    many points f was evaluated at, the checks included).
    """
    import warnings

    from dstoolkit.evidence import image

    lo_a, hi_a = np.atleast_1d(np.asarray(lo, float)), np.atleast_1d(np.asarray(hi, float))
    signs_a = np.broadcast_to(np.asarray(signs, dtype=int), lo_a.shape)
    out: dict[str, dict[str, Any]] = {}
    for method in IMAGE_METHOD_NAMES:
        count = [0]

        def counted(x: np.ndarray, count: list[int] = count) -> np.ndarray:
            count[0] += int(np.prod(np.shape(x)[:-1]))
            return f(x)

        entry: dict[str, Any] = {"image": None, "message": ""}
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                i_lo, i_hi = image((lo_a, hi_a), counted, method=method, monotone=signs_a)
                entry["image"] = (float(np.ravel(i_lo)[0]), float(np.ravel(i_hi)[0]))
            except NotMonotoneError as exc:
                entry["message"] = f"NotMonotoneError: {exc}"
        if caught and not entry["message"]:
            entry["message"] = f"{caught[0].category.__name__}: {caught[0].message}"
        entry["evaluations"] = count[0]
        out[method] = entry
    return out


def _extension_extent(ax: Any, bars: Any) -> tuple[float, ...]:
    """What the autoscaled ranges of :func:`extension_explorer`'s figure follow: the data
    x extent of f's panel ``ax`` and the y extent of both panels (they share y)."""
    ys = [v for a in (ax, bars) for v in a.dataLim.intervaly if np.isfinite(v)]
    return (*ax.dataLim.intervalx, min(ys, default=np.nan), max(ys, default=np.nan))


def extension_explorer(function: str = "sin x", lo: float = 0.0, hi: float = 3.0,
                       sign: int = 1) -> Explorer:
    """The image of an interval [lo, hi] through a function of one variable by the vertex
    method (Prop. 1, eq. 17), the monotone shortcut with a declared sign (Prop. 2,
    eqs. 18–19) and subdivision: which ones are right, which warn, which refuse."""
    controls = {
        "function": widgets.Dropdown(options=list(EXTENSION_FUNCTIONS), value=function,
                                     description="f(x)"),
        "lo": slider("box lower end", lo, -4.0, 4.0, 0.1, readout_format=".1f"),
        "hi": slider("box upper end", hi, -4.0, 4.0, 0.1, readout_format=".1f"),
        "sign": widgets.Dropdown(options=[("increasing (+1)", 1), ("decreasing (−1)", -1)],
                                 value=sign, description="declared",
                                 style={"description_width": "initial"}),
    }
    colours = {"vertex": "#ff7f0e", "monotone": "#9467bd", "subdivision": "#2ca02c"}
    x = np.linspace(-4.0, 4.0, 801)

    @functools.cache
    def drawn() -> dict[str, Any]:
        """The figure, made by the first render and updated by the others: f, f on the
        box and the box; per method its image as a bar and a band across f, a ⚠ (shown
        when it warns) and the word "refused" (shown when it refuses)."""
        # fixed margins, not a layout engine: the y tick labels change with the function
        # ("−0.75" is wider than "0.0"), and a layout made for the first ones cut the others
        fig = Figure(figsize=(9.5, 3.4), layout="none")  # not the style's engine either
        fig.subplots_adjust(left=0.075, right=0.99, bottom=0.15, top=0.9, wspace=0.06)
        ax, bars = fig.subplots(1, 2, sharey=True, width_ratios=[3, 1.3])
        (curve,) = ax.plot(x, x, color="black", lw=1.2)
        (on_box,) = ax.plot(x, x, color="#1f77b4", lw=3, label="f on the box")
        box = ax.axvspan(0.0, 1.0, color="#1f77b4", alpha=0.12)
        ax.set_xlabel("x")
        methods = {}
        for i, method in enumerate(IMAGE_METHOD_NAMES):
            methods[method] = {
                "refused": bars.text(i, 0.5, "refused:\nNot-\nMonotone-\nError", ha="center",
                                     va="center", fontsize=8, color="#b00020",
                                     transform=bars.get_xaxis_transform()),
                "bar": bars.plot([i, i], [0.0, 1.0], lw=8, solid_capstyle="butt",
                                 color=colours[method])[0],
                "band": ax.axhspan(0.0, 1.0, color=colours[method], alpha=0.08),
                "warning": bars.text(i, 0.0, "⚠", ha="center", va="bottom", color="#b00020",
                                     fontsize=12),
            }
        bars.set_xticks(range(3), IMAGE_METHOD_NAMES, fontsize=8)
        bars.set_xlim(-0.6, 2.6)
        bars.set_title("image f([lo, hi])")
        ax.set_title(f"f(x) = {function} on [{lo:g}, {hi:g}]")  # its font; its text follows
        animate(curve, on_box, box, ax.title, *(m["band"] for m in methods.values()),
                spines_of=ax)
        animate(*(a for m in methods.values() for k, a in m.items() if k != "band"),
                spines_of=bars)
        return {"fig": fig, "ax": ax, "bars": bars, "curve": curve, "on_box": on_box,
                "box": box, "methods": methods}

    def render(function: str, lo: float, hi: float, sign: int):
        if lo > hi:
            raise EvidenceError(f"the box [{lo:g}, {hi:g}] has lo > hi: move the ends")
        f = EXTENSION_FUNCTIONS[function]
        result = compare_image_methods(f, lo, hi, sign)
        d = drawn()
        d["curve"].set_ydata(f(x[:, None]))
        inside = np.linspace(lo, hi, 201)
        d["on_box"].set_data(inside, f(inside[:, None]))
        d["box"].set_x(lo)
        d["box"].set_width(hi - lo)
        d["ax"].title.set_text(f"f(x) = {function} on [{lo:g}, {hi:g}]")
        numbers: dict[str, Any] = {}
        for method, shown in d["methods"].items():
            entry = result[method]
            refused = entry["image"] is None
            shown["refused"].set_visible(refused)
            for artist in ("bar", "band", "warning"):
                shown[artist].set_visible(not refused)
            if refused:
                numbers[method] = "NotMonotoneError"
                continue
            a, b = np.round(entry["image"], 10) + 0.0  # 1e-19 from the zoom shows as 0
            shown["bar"].set_ydata([a, b])
            shown["band"].set_y(a)
            shown["band"].set_height(b - a)
            warn = "warning" in entry["message"].lower()
            shown["warning"].set_visible(warn)
            shown["warning"].set_y(b)
            numbers[method] = f"[{a:.4g}, {b:.4g}]" + (" ⚠ too narrow?" if warn else "")
        # the ranges follow what is shown, as when drawn anew: autoscaled from the x extent
        # of f's panel and the y extent of both (setting them, even unchanged, would redraw
        # the whole figure)
        extent = _extension_extent(d["ax"], d["bars"])
        for ax in (d["ax"], d["bars"]):
            ax.relim(visible_only=True)
        if _extension_extent(d["ax"], d["bars"]) != extent:
            d["ax"].autoscale_view()
        numbers.update({f"{m} evaluations": result[m]["evaluations"]
                        for m in IMAGE_METHOD_NAMES})
        return d["fig"], numbers

    live = {"hi": positions(controls["hi"], 8, 0.5, 4.0),
            "function": positions(controls["function"])}
    return Explorer(controls, render, title="The image of an interval: three methods",
                    live=live)
