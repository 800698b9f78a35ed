"""The explorer of the chapter on why bounded noise (book/why_bounded_noise.md).

A bounded-error filter with wrong bounds.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from dstoolkit.filters import enclosure_summary, random_walk
from dstoolkit.plots import (
    EnclosureFigure,
)
from dstoolkit.plots.artists import (
    KeptFigure,
    animate,
)

from ._explorer import (
    Explorer,
    positions,
    slider,
)

# -- why bounded noise: a bounded-error filter with wrong bounds --------------------------------


def describe_bounded(numbers: Mapping[str, Any]) -> str:
    """Say what the bounded-error figure shows: whether the band holds the truth."""
    inside = float(numbers["truth inside (fraction of steps)"])
    empty = numbers["first empty box"]
    fails = "never empties" if empty == "never" else f"empties at step {empty}"
    return (
        f"the filter's band over the steps with the truth and the readings: the truth lies "
        f"inside it at {inside:.0%} of the steps, the band {fails}, its mean width "
        f"{float(numbers['mean width']):.3g}"
    )


def bounded_error_explorer(
    v_half: float = 0.1, w_half: float = 1.0, steps: int = 60, seed: int = 7
) -> Explorer:
    """Return a bounded-error filter with wrong noise bounds, on one simulated random walk.

    The slider scales the bounds the filter assumes: too tight gives empty boxes (the filter
    resets) or boxes that miss the truth; too wide gives wide boxes.

    Parameters
    ----------
    v_half, w_half : float, optional
        The true half-widths of the state and observation noises.
    steps : int, optional
        The walk's length.
    seed : int, optional
        The walk's seed.

    Returns
    -------
    Explorer
        Control ``scale`` (assumed bounds ÷ true ones), live on the static site. Readout:
        :func:`dstoolkit.filters.enclosure_summary` of the run.

    See Also
    --------
    dstoolkit.filters.BoundedErrorFilter, dstoolkit.filters.random_walk

    Examples
    --------
    >>> ex = bounded_error_explorer(steps=20)
    >>> ex.controls["scale"].value
    1.0
    """
    from dstoolkit.filters import BoundedErrorFilter

    x, z = random_walk(v_half, w_half).simulate([0.0], steps, np.random.default_rng(seed))
    filt = BoundedErrorFilter(on_inconsistent="reset")

    def build(res: Any, title: str) -> EnclosureFigure:
        figure = EnclosureFigure(res, x, z, title=title, pyplot=False)
        figure.ax.legend(fontsize=8, loc="upper left")
        # what follows the control: a change redraws only these (Explorer.png blits)
        ax = figure.ax
        animate(*ax.lines, *ax.collections, ax.title, ax.get_legend())  # legend over the band
        return figure

    kept = KeptFigure(build, lambda figure, res, title: figure.update(res, x, z, title=title))

    def render(scale: float):
        res = filt.run(random_walk(v_half * scale, w_half * scale), z)
        return kept(res, f"bounds × {scale:g}").figure, enclosure_summary(res, x)

    scale = slider("assumed bounds × true", 1.0, 0.3, 3.0, 0.05)
    return Explorer(
        {"scale": scale},
        render,
        title="Bounded-error filter with wrong bounds",
        live={"scale": positions(scale, 11, 0.5, 3.0)},
        said=("truth inside (fraction of steps)", "mean width"),
        describe=describe_bounded,
    )
