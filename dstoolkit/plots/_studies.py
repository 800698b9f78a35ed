"""Figures of the studies beyond the paper (:mod:`dstoolkit.studies`).

Methods are drawn in the colours, line styles and markers of
:data:`dstoolkit.plots.STYLE`, so a method looks the same in Table 3, Figs. 10–11 and every
study, and no two methods differ in colour alone.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.text import Annotation
from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator, StrMethodFormatter

from dstoolkit.errors import InvalidInputError
from dstoolkit.evidence import possibility
from dstoolkit.filters import BoundedNoise
from dstoolkit.studies import ExampleComparison, MismatchResult, OrderRuleStudy

from ._experiments import EXTRA_STYLES, STYLE, line_style
from ._kept import animate, set_limits, snapped_limits
from ._style import (
    END_LABEL_GID,
    SMALL_PT,
    label_line_ends,
    legend_above,
    log_ticks,
    new_figure,
    place_line_end_labels,
    root_figure,
    styled,
)

#: How the order rules are drawn in :func:`plot_order_rule_study`: line style, label.
RULE_STYLE = {"eq43": ("-", "eq. 43"), "fit": ("--", "series fit"), "true": (":", "true")}


def _style(name: str) -> dict[str, Any]:
    """Return a method's colour, line style, marker and label.

    Any other name is drawn black, solid, with a cross.
    """
    return STYLE.get(name, {**EXTRA_STYLES[0], "label": name})


def _figure(ax: Axes | None, figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    if ax is not None:
        return root_figure(ax), ax
    fig = new_figure(*figsize)
    return fig, fig.add_subplot()


@styled
def plot_step_errors(
    errors: Mapping[str, np.ndarray],
    ax: Axes | None = None,
    *,
    unit: str = "Hz",
    title: str | None = None,
    legend: bool = True,
    end_labels: bool = False,
) -> Figure:
    """Mean |x̂_k − x_k| over runs against the step k, one line per method (log scale).

    ``errors`` maps a method to absolute errors of shape (runs, K) or (K,); a name that is
    not a method of STYLE (a variant, say) gets a style of ``EXTRA_STYLES``.
    ``update_step_errors`` draws other errors of the same methods on the axes. With
    ``end_labels`` each line's name is also written at its end (:func:`label_line_ends`;
    for a figure that is not redrawn).

    Parameters
    ----------
    errors : collections.abc.Mapping
        Method (or variant) name to its absolute errors (unit ``unit``), shape (runs, K)
        or (K,).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    unit : str, optional
        Unit of the errors.
    title : str, optional
        Title of the axes.
    legend : bool, optional
        Whether the legend is drawn above the axes.
    end_labels : bool, optional
        Whether each line is also named at its end.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).

    Examples
    --------
    >>> import numpy as np
    >>> errors = {"direct": np.full((2, 10), 2.0), "dependent_evidence": np.full(10, 0.5)}
    >>> fig = plot_step_errors(errors, end_labels=True)
    >>> len(fig.axes[0].texts)
    2
    """
    fig, ax = _figure(ax, (7.5, 3.4))
    extra = iter(EXTRA_STYLES)
    for name in errors:
        st = STYLE.get(name) or {**next(extra, EXTRA_STYLES[0]), "label": name}
        ax.semilogy([], [], lw=1.3, label=st["label"], **line_style(st))
    update_step_errors(ax, errors)
    ax.set_xlabel("step k")
    ax.set_ylabel(f"mean |x̂ − x| ({unit})")
    ax.grid(True, which="both", alpha=0.3)
    log_ticks(ax.yaxis)
    if title:
        ax.set_title(title, loc="left")
    if legend:
        legend_above(ax, ncols=2)
    if end_labels:
        label_line_ends(ax)
    return fig


def update_step_errors(ax: Axes, errors: Mapping[str, np.ndarray]) -> None:
    """Draw other errors on axes of :func:`plot_step_errors` drawn for the same methods.

    The same names in the same order; the limits follow.
    """
    if len(ax.lines) != len(errors):
        raise InvalidInputError(
            f"these axes draw {len(ax.lines)} methods, not "
            f"{len(errors)}: draw them anew with plot_step_errors"
        )
    for line, err in zip(ax.lines, errors.values(), strict=True):
        err = np.atleast_2d(np.asarray(err, dtype=float))
        line.set_data(np.arange(1, err.shape[1] + 1), err.mean(axis=0))
    if not ax.lines[0].get_animated():
        ax.relim()
        ax.autoscale_view()
        return
    # kept by an explorer (noise_bounds_figure): limits that change only when they must
    steps = max(np.size(line.get_xdata()) for line in ax.lines)
    y = np.concatenate([line.get_ydata() for line in ax.lines])
    y = y[np.isfinite(y) & (y > 0)]
    pad = 0.05 * (steps - 1)
    set_limits(
        ax,
        x=(1.0 - pad, steps + pad),
        y=snapped_limits(float(y.min()), float(y.max()), log=True) if y.size else None,
    )


def _possibilities(
    true: BoundedNoise, assumed: BoundedNoise
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return a grid over both noises' supports (and 15 % beyond) and the possibility of each."""
    lo = min(true.lower[0], assumed.lower[0])
    hi = max(true.upper[0], assumed.upper[0])
    pad = 0.15 * (hi - lo if hi > lo else 1.0)
    x = np.linspace(lo - pad, hi + pad, 801)
    y_true, y_assumed = (
        np.asarray(possibility(x, noise.lower[0], noise.mode[0], noise.upper[0]))
        for noise in (true, assumed)
    )
    return x, y_true, y_assumed


#: How :func:`plot_noise_assumption` draws the true noise (filled) and the assumed (a line).
_TRUE_FILL: dict[str, Any] = {"color": "0.6", "alpha": 0.5, "label": "true"}
_ASSUMED_LINE: dict[str, Any] = {"color": "C3", "lw": 1.5, "label": "assumed"}


@styled
def plot_noise_assumption(
    true: BoundedNoise,
    assumed: BoundedNoise,
    ax: Axes | None = None,
    *,
    title: str | None = None,
    xlabel: str = "noise (Hz)",
) -> Figure:
    """Plot the possibility distribution of the true noise and of the noise a filter assumes.

    The true noise filled, the assumed one a line; scalar noises (paper eqs. 22–23).
    ``update_noise_assumption`` draws other noises on the axes.

    Parameters
    ----------
    true, assumed : dstoolkit.filters.BoundedNoise
        The noise of the data and the noise the filter assumes (scalar).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    title : str, optional
        Title of the axes.
    xlabel : str, optional
        Label of the x axis: the noise and its unit.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).

    References
    ----------
    The paper's eqs. (22)–(23).

    Examples
    --------
    >>> from dstoolkit.filters import BoundedNoise
    >>> fig = plot_noise_assumption(BoundedNoise(-10.59, -6.9, -3.21),
    ...                             BoundedNoise(-8.0, -6.9, -5.0))
    >>> fig.axes[0].get_ylabel()
    'possibility'
    """
    fig, ax = _figure(ax, (4.0, 2.6))
    x, y_true, y_assumed = _possibilities(true, assumed)
    ax.fill_between(x, y_true, **_TRUE_FILL)
    ax.plot(x, y_assumed, **_ASSUMED_LINE)
    ax.set_ylim(0, 1.15)
    ax.set_yticks([0, 1])
    ax.set_xlabel(xlabel)
    ax.set_ylabel("possibility")
    if title:
        ax.set_title(title, loc="left")
    legend_above(ax, ncols=2)
    for name in ("true", "assumed"):  # named beside their flanks, moved by update_noise_assumption
        ax.annotate(
            name,
            (0.0, 0.5),
            xytext=(0.0, 0.0),
            textcoords="offset points",
            va="center",
            fontsize=SMALL_PT,
            color="#222222",
            gid=_PEAK_LABEL_GID,
        )
    _place_peak_labels(ax, true, assumed)
    return fig


#: The gid of the names :func:`plot_noise_assumption` writes at the distributions' peaks.
_PEAK_LABEL_GID = "peak-label"


def _place_peak_labels(ax: Axes, true: BoundedNoise, assumed: BoundedNoise) -> None:
    """Name the true noise left of its rising flank, the assumed right of its falling one.

    Both at half height, where each distribution's edge is its own.
    """
    true_label, assumed_label = (
        t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() == _PEAK_LABEL_GID
    )
    true_label.set_horizontalalignment("right")  # 3 pt left of the flank
    true_label.set_position((-3.0, 0.0))
    assumed_label.set_horizontalalignment("left")  # 3 pt right of it
    assumed_label.set_position((3.0, 0.0))
    for label, x in (
        (true_label, 0.5 * (true.lower[0] + true.mode[0])),
        (assumed_label, 0.5 * (assumed.mode[0] + assumed.upper[0])),
    ):
        if tuple(label.xy) != (float(x), 0.5):  # an unmoved label leaves a kept figure as is
            label.xy = (float(x), 0.5)


@styled
def update_noise_assumption(ax: Axes, true: BoundedNoise, assumed: BoundedNoise) -> None:
    """Draw other noises on axes of :func:`plot_noise_assumption`.

    The x limits follow, unless the curves are animated (kept by an explorer,
    :func:`noise_bounds_figure`).
    """
    x, y_true, y_assumed = _possibilities(true, assumed)
    fill: Any = ax.collections[0]  # a FillBetweenPolyCollection (matplotlib 3.10+)
    fill.set_data(x, y_true, 0)
    ax.lines[0].set_data(x, y_assumed)
    if not ax.lines[0].get_animated():  # kept by an explorer: its x limits stay
        ax.relim()  # the line spans the fill's x range
        ax.autoscale_view(scaley=False)
    _place_peak_labels(ax, true, assumed)


def noise_bounds_figure(
    true_v: BoundedNoise,
    true_w: BoundedNoise,
    assumed_v: BoundedNoise,
    assumed_w: BoundedNoise,
    errors: Mapping[str, np.ndarray],
    *,
    title: str,
    v_range: tuple[float, float],
    w_range: tuple[float, float],
) -> Figure:
    """Draw the noise-bounds explorer's figure.

    The true and assumed possibility distributions of v and w
    (:func:`plot_noise_assumption`) beside every method's mean error per step
    (:func:`plot_step_errors`, titled ``title``, each line named at its end). The
    explorer's own (11 in wide, in the notebook's style);
    :func:`update_noise_bounds_figure` draws other assumptions on it. The noises' axes
    span ``v_range`` and ``w_range`` (the sliders' ranges of the bounds, with matplotlib's
    margin) whatever the assumption, the errors' axis snaps to round numbers
    (``snapped_limits``) and the data are animated: most changes redraw only the data
    (blitting), and the true noise stands still while the assumed one moves.
    """
    fig = Figure(figsize=(11, 3.8), layout="constrained")
    ax_v, ax_w, ax_e = fig.subplots(1, 3, width_ratios=[1, 1, 2.2])
    plot_noise_assumption(true_v, assumed_v, ax_v, title="state noise v (Hz)")
    plot_noise_assumption(true_w, assumed_w, ax_w, title="observation noise w (Hz)")
    plot_step_errors(errors, ax_e, title=title, end_labels=True)
    for ax, (lo, hi) in ((ax_v, v_range), (ax_w, w_range)):
        ax.set_xlim(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
    # the data follow the controls and are redrawn alone (blitting) while the limits,
    # snapped to round numbers, stay
    animate(*(artist for ax in fig.axes for artist in (*ax.lines, *ax.collections, *ax.texts)))
    update_noise_bounds_figure(fig, true_v, true_w, assumed_v, assumed_w, errors)
    return fig


def update_noise_bounds_figure(
    fig: Figure,
    true_v: BoundedNoise,
    true_w: BoundedNoise,
    assumed_v: BoundedNoise,
    assumed_w: BoundedNoise,
    errors: Mapping[str, np.ndarray],
) -> None:
    """Draw other assumed noises and their errors on a :func:`noise_bounds_figure`.

    Its title stays.
    """
    ax_v, ax_w, ax_e = fig.axes
    update_noise_assumption(ax_v, true_v, assumed_v)
    update_noise_assumption(ax_w, true_w, assumed_w)
    update_step_errors(ax_e, errors)
    # each method's name stays level with its line's end (the lines are told apart by
    # their names, styles and markers as well as by colour)
    names = [text for text in ax_e.texts if text.get_gid() == END_LABEL_GID]
    place_line_end_labels(ax_e, ax_e.lines, names)


#: How :func:`plot_scale_study` marks a scale where the bounded-error filter failed: a
#: large black cross (no method is drawn in black there) with a white edge.
FAILED_MARK: dict[str, Any] = {
    "marker": "X",
    "ms": 11,
    "mfc": "black",
    "mec": "white",
    "mew": 1.0,
    "zorder": 5,
}


@styled
def plot_scale_study(study: Mapping[float, MismatchResult], ax: Axes | None = None) -> Figure:
    """Plot mean |x̂ − x| of each method against the factor scaling the assumed bounds.

    The bounds are scaled about the modes; each method is named at its line's end and has
    its own line style and marker. Where the bounded-error filter failed in some runs its
    point is marked by a large black cross (``FAILED_MARK``: black, not a colour that a
    colour-vision deficiency confuses with a method's), named "failed runs" beside the first
    one and in the legend, and the fraction of failed runs is written under that scale's
    tick label (away from the lines, which it would cross inside the axes).

    Parameters
    ----------
    study : collections.abc.Mapping
        Scale factor to the result of :func:`dstoolkit.studies.bound_scale_study` there.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).

    Examples
    --------
    >>> from dstoolkit.studies import bound_scale_study, tracking_data
    >>> study = bound_scale_study(tracking_data(runs=2), [0.5, 1.0, 2.0],
    ...                           methods=("kalman", "bounded_error"))
    >>> plot_scale_study(study).axes[0].get_yscale()
    'log'
    """
    fig, ax = _figure(ax, (7.5, 3.6))
    scales = np.array(sorted(study))
    methods = list(next(iter(study.values())).errors)
    labels = {_style(name)["label"] for name in methods}
    for name in methods:
        st = _style(name)
        ax.loglog(
            scales,
            [study[s].mean_errors()[name] for s in scales],
            ls=st["ls"],
            marker=st["marker"],
            color=st["color"],
            label=st["label"],
        )
    failed = {s: study[s].inconsistent_runs if "bounded_error" in methods else 0 for s in scales}
    crosses = [s for s, frac in failed.items() if frac > 0]
    if crosses:
        ax.plot(
            crosses,
            [study[s].mean_errors()["bounded_error"] for s in crosses],
            ls="none",
            label="failed runs",
            **FAILED_MARK,
        )
        ax.annotate(  # named beside its first mark too, as the lines are at their ends
            "failed runs",
            (crosses[0], study[crosses[0]].mean_errors()["bounded_error"]),
            xytext=(9.0, 6.0),
            textcoords="offset points",
            fontsize=SMALL_PT,
            color="#222222",
        )
    ax.axvline(1.0, color="black", lw=0.8, ls="--")
    ax.xaxis.set_major_locator(FixedLocator(scales.tolist()))
    ax.xaxis.set_major_formatter(
        FuncFormatter(
            lambda x, _: (
                f"{x:g}"
                + next((f"\n{f:.0%} failed" for s, f in failed.items() if s == x and f > 0), "")
            )
        )
    )
    ax.xaxis.set_minor_locator(NullLocator())
    ax.yaxis.set_major_formatter(StrMethodFormatter("{x:g}"))
    ax.yaxis.set_minor_formatter(StrMethodFormatter("{x:g}"))
    ax.set_xlabel("assumed bounds ÷ true bounds (–)")
    ax.set_ylabel("mean |x̂ − x| (Hz)")
    ax.grid(True, which="both", alpha=0.3)
    legend_above(ax, ncols=3)
    label_line_ends(ax, [line for line in ax.lines if line.get_label() in labels], short=True)
    return fig


@styled
def plot_order_rule_study(studies: Sequence[OrderRuleStudy]) -> Figure:
    """Plot mean absolute level error against the level, one panel per simulation (stacked).

    Line style = order rule, colour and marker = method; grey diamonds on a thick line: the
    series fit's own level.

    Parameters
    ----------
    studies : collections.abc.Sequence
        One result of :func:`dstoolkit.studies.order_rule_study` per panel.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (not attached to pyplot).

    Examples
    --------
    >>> from dstoolkit.studies import order_rule_study
    >>> study = order_rule_study(runs=1, cases=((1.3, 27.0),))
    >>> len(plot_order_rule_study([study]).axes)
    1
    """
    fig = new_figure(6.4, 1.4 + 2.8 * len(studies))
    axes = fig.subplots(len(studies), 1, sharex=True, squeeze=False)[:, 0]
    for ax, study in zip(axes, studies, strict=True):
        for rule, by_method in study.errors.items():
            ls, rule_label = RULE_STYLE.get(rule, ("-", rule))
            for name, err in by_method.items():
                st = _style(name)
                ax.semilogy(
                    study.levels,
                    err,
                    ls=ls,
                    marker=st["marker"],
                    color=st["color"],
                    ms=4,
                    label=f"{st['label']}, n_k {rule_label}",
                )
        ax.semilogy(
            study.levels,
            study.slope,
            "D-",
            color="0.3",
            ms=4,
            lw=2,
            label="series fit's level c/(2 f_F)",
        )
        ax.set_title(f"{study.simulation}-level simulation", loc="left")
        ax.set_ylabel("mean |L̂ − L| (m)")
        ax.grid(True, which="both", alpha=0.3)
        log_ticks(ax.yaxis)
    axes[-1].set_xlabel("true level L (m)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=2)
    for ax in axes:  # once the layout has its legend: the labels' spacing needs the heights
        label_line_ends(ax, short=True)
    return fig


@styled
def plot_example(comparison: ExampleComparison, run: int = 0) -> Figure:
    """Plot the predator–prey example.

    (a) the populations (P, Q) of one run, truth, census readings and every method's
    estimate; (b) |x̂_k − x_k| per step (log-populations).

    Parameters
    ----------
    comparison : dstoolkit.studies.ExampleComparison
        The result of :func:`dstoolkit.studies.example_comparison`.
    run : int, optional
        Which run panel (a) shows.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels (not attached to pyplot).

    Examples
    --------
    >>> from dstoolkit.studies import example_comparison
    >>> fig = plot_example(example_comparison(steps=15, runs=1))
    >>> len(fig.axes)
    2
    """
    fig = new_figure(6.4, 7.6)
    ax_a, ax_b = fig.subplots(2, 1, height_ratios=[1.1, 1])
    truth = np.exp(comparison.truth[run])
    ax_a.plot(*comparison.readings[run].T, ".", color="0.6", ms=4, label="census z_k")
    ax_a.plot(*truth.T, "k-", lw=1.8, label="true")
    for name, est in comparison.estimates.items():
        st = _style(name)
        ax_a.plot(*np.exp(est[run]).T, lw=1, label=st["label"], **line_style(st))
    ax_a.set_xlabel("prey P (individuals)")
    ax_a.set_ylabel("predators Q (individuals)")
    ax_a.set_title("(a) one run in the (P, Q) plane", loc="left")
    legend_above(ax_a, ncols=3)
    plot_step_errors(
        comparison.step_errors(run),
        ax_b,
        unit="log-population",
        title="(b) |x̂_k − x_k| per step",
        legend=False,  # styles as in (a)
        end_labels=True,
    )
    label_line_ends(ax_a, short=True)
    return fig


__all__ = [
    "plot_example",
    "plot_noise_assumption",
    "plot_order_rule_study",
    "plot_scale_study",
    "plot_step_errors",
]
