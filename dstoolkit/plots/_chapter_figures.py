"""Figures of single chapters.

The image of a function by two methods, a sweep's envelope against the resonances of
steady tones, and one step of Nassreddine's filter.

Each series has its own line style, hatch or marker and a label written next to it, so
that none is told apart by its colour alone.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from dstoolkit.errors import InvalidInputError
from dstoolkit.evidence import IntervalEvidence
from dstoolkit.filters import NassreddineRecord

from ._evidence import _axes, plot_focal_intervals
from ._style import (
    BETP_COLOUR,
    OKABE_ITO,
    SMALL_PT,
    column_size,
    label_line_ends,
    legend_above,
    root_figure,
    spread_positions,
    styled,
)

#: How each method's image is drawn: colour, hatch, the label's name.
_BANDS = {
    "subdivision": (OKABE_ITO["bluish green"], "//", "subdivision"),
    "vertex": (OKABE_ITO["orange"], "\\\\", "vertex"),
}


@styled
def plot_image_methods(
    cases: Mapping[
        str, tuple[Callable[[np.ndarray], np.ndarray], float, float, Mapping[str, Sequence[float]]]
    ],
) -> Figure:
    """Draw the image of a function of one variable on a box by two methods, one panel a case.

    In each panel: the function near the box (thin), on the box (thick; the title names the
    box, so that no label lies over the bands or the curve), and as hatched horizontal bands
    the image [a, b] that each method gives, each band labelled at the right edge with its
    method and interval.

    Parameters
    ----------
    cases : collections.abc.Mapping
        Panel title (the function's name) to ``(f, lo, hi, images)``: ``f`` maps points of
        shape (n, 1) to values of shape (n,); ``[lo, hi]`` is the box (no unit); ``images``
        maps ``"subdivision"`` and/or ``"vertex"`` to its ``(a, b)``.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per case, stacked.

    Raises
    ------
    InvalidInputError
        If ``cases`` is empty or names a method other than the two.

    See Also
    --------
    dstoolkit.teaching.compare_image_methods : the images this figure draws.

    Examples
    --------
    >>> import numpy as np
    >>> square = lambda x: x[..., 0] ** 2
    >>> fig = plot_image_methods({"x²": (square, -1.0, 2.0,
    ...                           {"vertex": (1.0, 4.0), "subdivision": (0.0, 4.0)})})
    >>> [t.get_text() for t in fig.axes[0].texts], fig.axes[0].get_title(loc="left")
    (['subdivision: [0, 4]', 'vertex: [1, 4]'], 'f(x) = x², thick on the box [-1, 2]')
    """
    if not cases:
        raise InvalidInputError("plot_image_methods needs at least one case")
    fig, grid = plt.subplots(
        len(cases),
        1,
        figsize=column_size(6.4, 3.2 * len(cases)),
        layout="constrained",
        squeeze=False,
    )
    axes = list(grid[:, 0])
    for ax, (name, (f, lo, hi, images)) in zip(axes, cases.items(), strict=True):
        unknown = set(images) - set(_BANDS)
        if unknown:
            raise InvalidInputError(
                f"plot_image_methods draws the methods {sorted(_BANDS)}, not {sorted(unknown)}"
            )
        x = np.linspace(lo - 1.0, hi + 1.0, 400)
        ax.plot(x, f(x[:, None]), color=OKABE_ITO["black"], lw=1)
        inside = np.linspace(lo, hi, 200)
        ax.plot(inside, f(inside[:, None]), color=OKABE_ITO["blue"], lw=3)
        bands = []
        for method, (colour, hatch, label) in _BANDS.items():
            if method in images:
                a, b = np.round(np.asarray(images[method], dtype=float), 10) + 0.0
                ax.axhspan(a, b, facecolor=colour, alpha=0.3, hatch=hatch, edgecolor=colour, lw=0.8)
                bands.append((a, b, f"{label}: [{a:.3g}, {b:.3g}]"))
        ax.set_title(f"f(x) = {name}, thick on the box [{lo:g}, {hi:g}]", loc="left")
        ax.set_xlabel("x (no unit)")
        ax.set_ylabel("f(x) (no unit)")
        _label_bands(ax, bands)
    return fig


def _label_bands(ax: Axes, bands: list[tuple[float, float, str]]) -> None:
    """Write each band's label right of the axes, moved apart where two would overlap.

    Each label sits beside the part of its band no narrower band covers (the middle of the
    larger free part).
    """
    ax.get_ylim()  # the limits, autoscaled now if they are still pending
    to_axes = ax.transScale + ax.transLimits
    wanted = []
    for a, b, _ in bands:
        inner = [(c, d) for c, d, _ in bands if a <= c and d <= b and (c, d) != (a, b)]
        if inner:  # the larger of the two parts outside the narrower band
            c, d = inner[0]
            y = 0.5 * (a + c) if c - a >= b - d else 0.5 * (d + b)
        else:
            y = 0.5 * (a + b)
        wanted.append(float(np.clip(to_axes.transform((0.0, y))[1], 0.0, 1.0)))
    height_pt = ax.get_position().height * root_figure(ax).get_figheight() * 72.0
    for y, (_, _, text) in zip(
        spread_positions(wanted, 1.25 * SMALL_PT / height_pt), bands, strict=True
    ):
        ax.text(
            1.02,
            y,
            text,
            transform=ax.transAxes,
            ha="left",
            va="center",
            fontsize=SMALL_PT,
            color="#222222",
        )


@styled
def plot_sweep_peaks(
    frequencies: np.ndarray,
    steady: np.ndarray,
    swept: np.ndarray,
    resonances: np.ndarray,
    shift_hz: float,
) -> Figure:
    """Plot amplitude against frequency for steady tones and for a sweep.

    With the resonances n c/(2L) and the same shifted by ``shift_hz``, where the sweep's
    envelope peaks.

    Parameters
    ----------
    frequencies : numpy.ndarray
        Shape (n,): frequencies (Hz).
    steady, swept : numpy.ndarray
        Shape (n,): amplitude relative to the source's (no unit) for steady tones and
        for the sweep
        read at the speaker's frequency.
    resonances : numpy.ndarray
        Shape (m,): the resonances n c/(2L) in the range (Hz).
    shift_hz : float
        Where the sweep's peaks sit above them, κ L / c (Hz).

    Returns
    -------
    matplotlib.figure.Figure
        The two curves, labelled at their ends, and the two sets of vertical lines (dotted
        and dash-dotted), named in the legend above.

    Raises
    ------
    InvalidInputError
        If the three curves' arrays do not have one shape.

    See Also
    --------
    plot_resonances : the resonances a detector finds in a recording.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(100.0, 130.0, 301)
    >>> fig = plot_sweep_peaks(f, np.cos(f / 3) ** 2, np.cos((f - 1) / 3) ** 2,
    ...                        np.array([108.4, 117.8]), 1.0)
    >>> [t.get_text() for t in fig.axes[0].texts]
    ['steady tones, eq. (29)', 'sweep, read as f(u)']
    """
    frequencies, steady, swept = (np.asarray(v, dtype=float) for v in (frequencies, steady, swept))
    if not frequencies.shape == steady.shape == swept.shape:
        raise InvalidInputError(
            f"plot_sweep_peaks needs frequencies, steady and swept of one shape, got "
            f"{frequencies.shape}, {steady.shape} and {swept.shape}"
        )
    fig, ax = _axes(None, (6.4, 3.0))
    resonances = np.asarray(resonances, dtype=float)
    curves = [
        ax.plot(
            frequencies, steady, color=OKABE_ITO["black"], ls="-", label="steady tones, eq. (29)"
        )[0],
        ax.plot(frequencies, swept, color=OKABE_ITO["blue"], ls="--", label="sweep, read as f(u)")[
            0
        ],
    ]
    ax.vlines(
        resonances,
        0,
        1,
        transform=ax.get_xaxis_transform(),
        color=OKABE_ITO["bluish green"],
        lw=1.2,
        ls=":",
        label="n c/(2L)",
    )
    ax.vlines(
        resonances + shift_hz,
        0,
        1,
        transform=ax.get_xaxis_transform(),
        color=OKABE_ITO["vermillion"],
        lw=1,
        ls="-.",
        label="n c/(2L) + κL/c",
    )
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("amplitude / A (no unit)")
    legend_above(ax, ncols=2)
    label_line_ends(ax, curves)
    return fig


@styled
def plot_nassreddine_step(
    record: NassreddineRecord,
    carried: IntervalEvidence,
    *,
    xlim: tuple[float, float],
    truth: float | None = None,
    xlabel: str = "state x (no unit)",
) -> Figure:
    """Draw one step of Nassreddine's filter on a scalar model, one panel a stage.

    Top to bottom: the mass function on intervals the step starts from, its prediction
    f(X) + E_v, the evidence of the reading (in the state's space: ``g`` is the identity,
    or the reading is mapped back through g⁻¹), the contractions renormalised (Dempster's
    rule, eq. 1) with their conflict K, and what the clustering cap carries to the next
    step. Each panel stacks the focal elements as in :func:`plot_focal_intervals` over one
    x range (bars that run off it are wider, built on Θ); a vertical line marks the
    pignistic expectation of the posterior (eq. 20) and a dashed one the ``truth``.

    Parameters
    ----------
    record : dstoolkit.filters.NassreddineRecord
        One step of a scalar model, from :meth:`dstoolkit.filters.NassreddineFilter.step`.
    carried : dstoolkit.evidence.IntervalEvidence
        The posterior after the cap (the state that step returned, its ``carried``).
    xlim : tuple of float
        The x range of every panel; wider focal elements (those built on Θ) are clipped.
    truth : float, optional
        The true state of that step.
    xlabel : str, optional
        The state and its unit, e.g. ``"frequency (Hz)"``.

    Returns
    -------
    matplotlib.figure.Figure
        Five panels, stacked.

    Raises
    ------
    InvalidInputError
        If ``record`` is the first step (it has no prediction) or not of a scalar model.

    References
    ----------
    The paper's §1 on Nassreddine's method; Dempster's rule (eq. 1), the pignistic
    expectation (eq. 20).

    Examples
    --------
    >>> from dstoolkit.evidence import IntervalEvidence
    >>> from dstoolkit.filters import NassreddineFilter, random_walk
    >>> filt = NassreddineFilter(p=2, max_focal=4)
    >>> model = random_walk(0.5, 1.0)
    >>> state, record = filt.step(filt.initialize(model, 0.2), 0.5)
    >>> carried = IntervalEvidence.from_boxes(state.carried)
    >>> fig = plot_nassreddine_step(record, carried, xlim=(-2.0, 2.5))
    >>> len(fig.axes)
    5
    """
    if record.state is None or record.prediction is None:
        raise InvalidInputError(
            "plot_nassreddine_step needs a step after the first (the first has no "
            "prediction): pass a record returned by NassreddineFilter.step"
        )
    if record.posterior.dim != 1:
        raise InvalidInputError("plot_nassreddine_step draws a scalar model's step only")
    panels = (
        (record.state, f"start: the state's evidence ({len(record.state)} intervals)"),
        (record.prediction, f"prediction f(X) + E_v ({len(record.prediction)})"),
        (record.observation, f"the reading's evidence z + E_w ({len(record.observation)})"),
        (
            record.posterior,
            f"contractions, renormalised ({len(record.posterior)}; K = {record.conflict:.3f})",
        ),
        (carried, f"after the cap: {len(carried)} intervals carried to the next step"),
    )
    fig, grid = plt.subplots(
        len(panels), 1, figsize=column_size(6.4, 9.6), sharex=True, layout="constrained"
    )
    estimate = float(record.estimate[0])
    for ax, (ev, title) in zip(grid, panels, strict=True):
        # no mass written on the bars: the thin ones would stack their labels
        plot_focal_intervals(ev, ax, xlim=xlim, label_masses=False, xlabel=xlabel)
        ax.set_title(title, loc="left", fontsize=SMALL_PT + 1)
        if ax is not grid[-1]:
            ax.set_xlabel("")
    for ax in grid[3:]:
        ax.axvline(estimate, color=BETP_COLOUR, lw=1.5, label="estimate x̂ (eq. 20)")
        if truth is not None:
            ax.axvline(truth, color="black", ls="--", lw=1.2, label="truth")
    legend_above(grid[3], ncols=2)
    return fig
