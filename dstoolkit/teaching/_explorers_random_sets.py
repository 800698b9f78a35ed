"""The explorer of the chapter on random sets (book/random_sets.md).

The image of an interval by four methods (vertex, monotone, subdivision, and the mean-value form's
outer enclosure).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from typing import Any, cast

import ipywidgets as widgets
import numpy as np
from matplotlib.figure import Figure

from dstoolkit.errors import (
    EvidenceError,
    NotMonotoneError,
)
from dstoolkit.evidence import ImageMethod
from dstoolkit.plots import OKABE_ITO
from dstoolkit.plots.artists import animate

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


def _square(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the interval {x² : x in [lo, hi]}."""
    a, b = lo**2, hi**2
    return np.where((lo <= 0) & (hi >= 0), 0.0, np.minimum(a, b)), np.maximum(a, b)


def _cos(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the interval {cos x : x in [lo, hi]}: the ends, and ±1 where cos peaks inside."""
    a, b = np.cos(lo), np.cos(hi)
    top = np.floor(hi / (2 * np.pi)) * 2 * np.pi >= lo
    bottom = np.floor((hi - np.pi) / (2 * np.pi)) * 2 * np.pi + np.pi >= lo
    return np.where(bottom, -1.0, np.minimum(a, b)), np.where(top, 1.0, np.maximum(a, b))


def _cubic_slope(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    sq_lo, sq_hi = _square(lo, hi)
    return 3.0 * sq_lo - 3.0, 3.0 * sq_hi - 3.0


#: The slopes of :data:`EXTENSION_FUNCTIONS` on a box [lo, hi] (..., 1): exact interval
#: derivatives, what the mean-value form needs.
EXTENSION_SLOPES: dict[str, Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]] = {
    "x²": lambda lo, hi: (2.0 * lo, 2.0 * hi),
    "sin x": _cos,
    "x³ − 3x": _cubic_slope,
    "exp(−x)": lambda lo, hi: (-np.exp(-lo), -np.exp(-hi)),
    "2x + 1": lambda lo, hi: (np.full_like(lo, 2.0), np.full_like(hi, 2.0)),
}
#: A bound of a function's slopes on boxes: ``slope(lo, hi) -> (d_lo, d_hi)``.
SlopeBound = Callable[[np.ndarray, np.ndarray], tuple[Any, Any]]
#: The methods :func:`compare_image_methods` runs; the mean-value form needs a slope bound.
IMAGE_METHOD_NAMES: tuple[str, ...] = ("vertex", "monotone", "subdivision", "mean_value")
#: How the extension explorer names and draws each method: the label under its bar (also
#: the readout's key), its line style and its marker (colour is only a third cue).
METHOD_LOOK: dict[str, dict[str, str]] = {
    "vertex": {"label": "vertex", "ls": "-", "marker": "o", "color": OKABE_ITO["orange"]},
    "monotone": {
        "label": "monotone",
        "ls": "--",
        "marker": "s",
        "color": OKABE_ITO["reddish purple"],
    },
    "subdivision": {
        "label": "subdivision",
        "ls": ":",
        "marker": "^",
        "color": OKABE_ITO["bluish green"],
    },
    "mean_value": {"label": "mean-value", "ls": "-.", "marker": "D", "color": OKABE_ITO["blue"]},
}
#: Sub-boxes of the mean-value form in the explorer.
MEAN_VALUE_PIECES = 8


def compare_image_methods(
    f: Callable[[np.ndarray], np.ndarray],
    lo: Any,
    hi: Any,
    signs: Any = 1,
    slope: SlopeBound | None = None,
    *,
    pieces: int = MEAN_VALUE_PIECES,
) -> dict[str, dict[str, Any]]:
    """Return the image of one box [lo, hi] through f by every method.

    The methods are those of :func:`~dstoolkit.evidence.image`.

    The vertex method (Prop. 1), the monotone shortcut with the declared ``signs``
    (Prop. 2) and subdivision (the fallback) are inner approximations; the mean-value
    form, run when ``slope`` is given, is an outer enclosure.

    Parameters
    ----------
    f : Callable
        Vectorised function of points (..., n) to (...,) (one output).
    lo, hi : float or array_like
        The box's ends, one per argument (n).
    signs : int or array_like, optional
        The declared monotonicity for the shortcut: +1 or −1 per argument (default +1).
    slope : Callable, optional
        ``slope(lo, hi) -> (d_lo, d_hi)``: a bound of f's derivatives on a box, for the
        mean-value form (left out without it).
    pieces : int, optional
        Sub-boxes per axis of the mean-value form.

    Returns
    -------
    dict[str, dict[str, Any]]
        Per method (``"vertex"``, ``"monotone"``, ``"subdivision"``, ``"mean_value"``):
        ``image`` ((lo, hi) or None when the method refused), ``message`` (the
        VertexMethodWarning or NotMonotoneError text, else "") and ``evaluations`` (how
        many points f was evaluated at, the checks included).

    See Also
    --------
    dstoolkit.evidence.image : The image of evidence through f.
    extension_explorer : These methods side by side, live.

    References
    ----------
    The paper's Prop. 1 (eq. 17) and Prop. 2 (eqs. 18–19).

    Examples
    --------
    >>> out = compare_image_methods(lambda x: x[..., 0] ** 2, -1.0, 2.0, 1,
    ...                             slope=lambda lo, hi: (2 * lo, 2 * hi))
    >>> out["vertex"]["image"], out["monotone"]["image"]
    ((1.0, 4.0), None)
    >>> a, b = out["mean_value"]["image"]
    >>> a <= 0.0 and b >= 4.0  # an outer enclosure of [0, 4]
    True
    """
    import warnings

    from dstoolkit.evidence import image

    lo_a, hi_a = np.atleast_1d(np.asarray(lo, float)), np.atleast_1d(np.asarray(hi, float))
    signs_a = np.broadcast_to(np.asarray(signs, dtype=int), lo_a.shape)
    out: dict[str, dict[str, Any]] = {}
    for method in IMAGE_METHOD_NAMES:
        if method == "mean_value" and slope is None:
            continue
        count = [0]

        def counted(x: np.ndarray, count: list[int] = count) -> np.ndarray:
            count[0] += int(np.prod(np.shape(x)[:-1]))
            return f(x)

        entry: dict[str, Any] = {"image": None, "message": ""}
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                i_lo, i_hi = cast(
                    tuple[np.ndarray, np.ndarray],
                    image(
                        (lo_a, hi_a),
                        counted,
                        method=cast(ImageMethod, method),
                        monotone=signs_a,
                        slope=slope,
                        subdivisions=pieces if method == "mean_value" else 8,
                    ),
                )
                entry["image"] = (float(np.ravel(i_lo)[0]), float(np.ravel(i_hi)[0]))
            except NotMonotoneError as exc:
                entry["message"] = f"NotMonotoneError: {exc}"
        if caught and not entry["message"]:
            entry["message"] = f"{caught[0].category.__name__}: {caught[0].message}"
        entry["evaluations"] = count[0]
        out[method] = entry
    return out


def _extension_extent(ax: Any) -> tuple[float, ...]:
    """Return what the autoscaled ranges of f's panel of :func:`extension_explorer` follow.

    The data x and y extents of the panel ``ax`` (f on the whole x range).
    """
    return (*ax.dataLim.intervalx, *ax.dataLim.intervaly)


def _image_range(images: list[tuple[float, float]]) -> tuple[float, float]:
    """Return the y-range of the images' panel: every image, with a margin.

    The images of a small box are small: on f's own range they would shrink to dots, so
    the panel has a range of its own, the hull of the images widened by a tenth of its
    width below and a fifth above (room for the ⚠ on the top bar), or, for a hull of one
    point, by a width of its own.
    """
    low = min(a for a, _ in images)
    high = max(b for _, b in images)
    span = high - low
    if not span > 1e-12 * max(1.0, abs(low), abs(high)):
        span = max(0.1 * abs(high), 0.1)
    return float(low - 0.1 * span), float(high + 0.2 * span)


def _shown_image(a: float, b: float, outer: bool) -> str:
    """Return an image as the readout prints it.

    4 significant digits of its ends to 10 decimals (1e-19 from the zoom shows as 0). An outer
    enclosure is rounded outward, so that the printed interval still contains the image.
    """
    a, b = (float(v) for v in np.round([a, b], 10) + 0.0)
    if outer:
        a = a if float(f"{a:.4g}") <= a else _down(a)
        b = b if float(f"{b:.4g}") >= b else _up(b)
    return f"[{a:.4g}, {b:.4g}]"


def _down(x: float) -> float:
    """``x`` rounded down to 4 significant digits."""
    if x == 0.0:
        return 0.0
    scale = 10.0 ** (np.floor(np.log10(abs(x))) - 3)
    return float(np.floor(x / scale) * scale)


def _up(x: float) -> float:
    """``x`` rounded up to 4 significant digits."""
    return -_down(-x)


def describe_extension(numbers: Mapping[str, Any]) -> str:
    """Say what the image explorer's figure shows: which methods hold and which fail."""
    failed = [name for name, value in numbers.items() if value == "NotMonotoneError"]
    narrow = [name for name, value in numbers.items() if "too narrow" in str(value)]
    notes = "".join(
        [
            f"; {' and '.join(failed)} {'refuse' if len(failed) > 1 else 'refuses'} f "
            "(not monotone)"
            if failed
            else "",
            f"; {' and '.join(narrow)} may be too narrow" if narrow else "",
        ]
    )
    return (
        f"f on the box with its mean-value enclosure, and the image by four methods side by "
        f"side: subdivision gives {numbers['subdivision']}, the mean-value form "
        f"{numbers['mean-value']}{notes}"
    )


def extension_explorer(
    function: str = "sin x", lo: float = 0.0, hi: float = 3.0, sign: int = 1
) -> Explorer:
    """Return the image of an interval through a function of one variable by four methods.

    The vertex method (Prop. 1, eq. 17), the monotone shortcut with a declared sign
    (Prop. 2, eqs. 18–19) and subdivision give values f takes (inner approximations):
    which ones are right, which warn, which refuse. The mean-value form gives an outer
    enclosure from f's slope on the box, never narrower than the image. The figure shows
    f, the box and the mean-value enclosure (a hatched band) and, in a second panel with a
    y-range of its own (so that the images of a small box do not shrink to dots), each
    method's image as a bar with its own line style, end marker and label.

    Parameters
    ----------
    function : str, optional
        The start function, a key of ``EXTENSION_FUNCTIONS`` (x², sin x, x³ − 3x,
        exp(−x), 2x + 1).
    lo, hi : float, optional
        The start box [lo, hi], within [−4, 4].
    sign : int, optional
        The declared monotonicity for the shortcut, +1 or −1.

    Returns
    -------
    Explorer
        Controls ``function``, ``lo``, ``hi``, ``sign``; on the static site ``hi`` and
        ``function`` answer. Readout: each method's image (``"NotMonotoneError"`` when the
        shortcut refuses, "⚠ too narrow?" when the vertex check warns) and, under
        "f calls", how often each method evaluated f, in the same order.

    See Also
    --------
    compare_image_methods : The numbers behind the explorer.
    dstoolkit.evidence.image : The image of evidence through f.

    References
    ----------
    The paper's Prop. 1 (eq. 17) and Prop. 2 (eqs. 18–19).

    Examples
    --------
    >>> ex = extension_explorer(function="x²", lo=-1.0, hi=2.0)
    >>> ex.numbers["subdivision"], ex.numbers["monotone"], ex.numbers["mean-value"]
    ('[0, 4]', 'NotMonotoneError', '[-0.08985, 4.036]')
    """
    controls = {
        "function": widgets.Dropdown(
            options=list(EXTENSION_FUNCTIONS), value=function, description="f(x)"
        ),
        "lo": slider("box lower end", lo, -4.0, 4.0, 0.1, readout_format=".1f"),
        "hi": slider("box upper end", hi, -4.0, 4.0, 0.1, readout_format=".1f"),
        "sign": widgets.Dropdown(
            options=[("increasing (+1)", 1), ("decreasing (−1)", -1)],
            value=sign,
            description="declared",
            style={"description_width": "initial"},
        ),
    }
    x = np.linspace(-4.0, 4.0, 801)
    labels = [METHOD_LOOK[m]["label"] for m in IMAGE_METHOD_NAMES]

    @functools.cache
    def drawn() -> dict[str, Any]:
        """Return the figure, made by the first render and updated by the others.

        f, f on the box, the box and the mean-value enclosure as a hatched band; per method its
        image as a bar (own line style and end markers, its name below), a ⚠ (shown when it warns)
        and the word "refused" (shown when it refuses).
        """
        # fixed margins, not a layout engine: the y tick labels change with the function
        # ("−0.75" is wider than "0.0"), and a layout made for the first ones cut the others
        # not the style's engine either (the stubs of matplotlib leave "none" out)
        fig = Figure(figsize=(9.5, 3.9), layout="none")  # type: ignore[arg-type]
        fig.subplots_adjust(left=0.075, right=0.93, bottom=0.25, top=0.91, wspace=0.06)
        # the images' panel has its y-range of its own (the images of a small box are small),
        # its tick labels on its right
        ax, bars = fig.subplots(1, 2, width_ratios=[2.6, 1.7])
        bars.yaxis.tick_right()
        (curve,) = ax.plot(x, x, color="black", lw=1.2)
        (on_box,) = ax.plot(x, x, color=OKABE_ITO["sky blue"], lw=3.5, label="f on the box")
        box = ax.axvspan(0.0, 1.0, color=OKABE_ITO["sky blue"], alpha=0.15)
        look = METHOD_LOOK["mean_value"]
        enclosure = ax.axhspan(
            0.0,
            1.0,
            facecolor="none",
            edgecolor=look["color"],
            hatch="///",
            lw=1.0,
            ls=look["ls"],
            label="mean-value enclosure",
        )
        ax.set_xlabel("x")
        # the legend below the panel: inside it, the hatched band (drawn over the still
        # picture) would cover it
        ax.legend(
            handles=[on_box, enclosure],
            fontsize=8,
            loc="upper left",
            ncol=2,
            bbox_to_anchor=(0.0, -0.17),
            frameon=False,
        )
        methods = {}
        for i, method in enumerate(IMAGE_METHOD_NAMES):
            look = METHOD_LOOK[method]
            methods[method] = {
                "refused": bars.text(
                    i,
                    0.5,
                    "refused:\nNot-\nMonotone-\nError",
                    ha="center",
                    va="center",
                    fontsize=8,
                    color="#b00020",
                    transform=bars.get_xaxis_transform(),
                ),
                "bar": bars.plot(
                    [i, i],
                    [0.0, 1.0],
                    lw=3,
                    ls=look["ls"],
                    marker=look["marker"],
                    ms=7,
                    color=look["color"],
                    clip_on=method != "mean_value",
                )[0],
                "warning": bars.text(
                    i, 0.0, "⚠", ha="center", va="bottom", color="#b00020", fontsize=12
                ),
            }
        bars.set_xticks(range(len(labels)), [lab.replace("-", "-\n") for lab in labels], fontsize=8)
        bars.set_xlim(-0.6, len(labels) - 0.4)
        bars.set_title("image f([lo, hi]), own y-range", fontsize=10)
        ax.set_title(f"f(x) = {function} on [{lo:g}, {hi:g}]")  # its font; its text follows
        animate(curve, on_box, box, enclosure, ax.title, spines_of=ax)
        animate(*(a for m in methods.values() for a in m.values()), spines_of=bars)
        return {
            "fig": fig,
            "ax": ax,
            "bars": bars,
            "curve": curve,
            "on_box": on_box,
            "box": box,
            "enclosure": enclosure,
            "methods": methods,
        }

    def render(function: str, lo: float, hi: float, sign: int):
        if lo > hi:
            raise EvidenceError(f"the box [{lo:g}, {hi:g}] has lo > hi: move the ends")
        f = EXTENSION_FUNCTIONS[function]
        result = compare_image_methods(f, lo, hi, sign, EXTENSION_SLOPES[function])
        d = drawn()
        d["curve"].set_ydata(f(x[:, None]))
        inside = np.linspace(lo, hi, 201)
        d["on_box"].set_data(inside, f(inside[:, None]))
        d["box"].set_x(lo)
        d["box"].set_width(hi - lo)
        d["ax"].title.set_text(f"f(x) = {function} on [{lo:g}, {hi:g}]")
        numbers: dict[str, Any] = {}
        images = [result[m]["image"] for m in d["methods"] if result[m]["image"] is not None]
        for method, shown in d["methods"].items():
            entry, label = result[method], METHOD_LOOK[method]["label"]
            refused = entry["image"] is None
            shown["refused"].set_visible(refused)
            for artist in ("bar", "warning"):
                shown[artist].set_visible(not refused)
            if refused:
                numbers[label] = "NotMonotoneError"
                continue
            a, b = entry["image"]
            if method == "mean_value":
                d["enclosure"].set_y(a)
                d["enclosure"].set_height(b - a)
            shown["bar"].set_ydata([a, b])
            warn = "warning" in entry["message"].lower()
            shown["warning"].set_visible(warn)
            shown["warning"].set_y(b)
            numbers[label] = _shown_image(a, b, method == "mean_value") + (
                " ⚠ too narrow?" if warn else ""
            )
        # f's panel follows f on the whole x range, as when drawn anew: autoscaled from the
        # curve alone (setting its ranges, even unchanged, would redraw the whole figure).
        # (Animated artists hidden for the relim leave the figure unchanged.)
        moving = (d["on_box"], d["enclosure"])
        extent = _extension_extent(d["ax"])
        shown = [artist.get_visible() for artist in moving]
        for artist in moving:
            artist.set_visible(False)
        d["ax"].relim(visible_only=True)
        for artist, visible in zip(moving, shown, strict=True):
            artist.set_visible(visible)
        if _extension_extent(d["ax"]) != extent:
            d["ax"].autoscale_view()
        # the images' panel follows the images (set only when it changes: a new range
        # redraws the whole figure)
        if images:
            wanted = _image_range(images)
            if not np.allclose(d["bars"].get_ylim(), wanted, rtol=0, atol=1e-12):
                d["bars"].set_ylim(*wanted)
        # how often each method evaluated f, in the order of the columns (one column, so that
        # the readout keeps to two lines)
        numbers["f calls"] = " / ".join(str(result[m]["evaluations"]) for m in IMAGE_METHOD_NAMES)
        return d["fig"], numbers

    live = {
        "hi": positions(controls["hi"], 8, 0.5, 4.0),
        "function": positions(controls["function"]),
    }
    return Explorer(
        controls,
        render,
        title="The image of an interval: four methods",
        live=live,
        said=("subdivision", "mean-value"),
        describe=describe_extension,
    )
