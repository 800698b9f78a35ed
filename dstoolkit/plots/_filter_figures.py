"""Pictures of filter runs: a run's band, the paper's Fig. 10 and one step's evidence.

Each picture is a small class that draws its figure once and then updates it in place
for another run (the explorers of :mod:`dstoolkit.teaching` redraw them on every change of
a control, so that a change costs a redraw, not a new figure); the ``plot_*`` function of
each is one such figure, made through pyplot for a notebook cell. A figure built for some
data and a kept one updated to the same data hold the same artists, data, texts and
limits: the constructor draws through ``update`` too.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator, StrMethodFormatter

from dstoolkit.errors import EvidenceError
from dstoolkit.filters import DependentRecord

from ._evidence import FocalIntervalArtists, draw_focal_intervals, update_focal_intervals
from ._kept import InnerTicks, set_limits, snapped_limits
from ._style import (
    BETP_COLOUR,
    SMALL_PT,
    column_size,
    label_line_ends,
    legend_above,
    place_line_end_labels,
    root_figure,
    styled,
)


def blank_figure(figsize: tuple[float, float], layout: str, *, pyplot: bool = True) -> Figure:
    """Make a new figure ``figsize`` inches large.

    Through pyplot (a notebook shows it when the cell ends), or a bare
    :class:`~matplotlib.figure.Figure` that pyplot does not know (an explorer keeps it and
    shows it as a PNG).
    """
    engine: Any = layout  # "constrained" or "none" (no engine, not the rcParams' default)
    if pyplot:
        return plt.figure(figsize=figsize, layout=engine)
    return Figure(figsize=figsize, layout=engine)


def _autoscale(*axes: Axes) -> None:
    """Set data limits and autoscaled view limits of ``axes`` from their artists' data now."""
    for ax in axes:
        ax.relim()
    for ax in axes:
        ax.autoscale_view()


# -- a run's band -----------------------------------------------------------------------------


class EnclosureFigure:
    """The figure of :func:`plot_enclosure`, kept.

    :meth:`update` draws another run of the same filter in place. Attributes: ``figure``,
    ``ax``.

    Parameters
    ----------
    result : dstoolkit.filters.FilterResult
        A filter run with ``lower`` and ``upper``, shape (K, d).
    truth : array_like
        Shape (K,) or (K, d): the true state per step.
    readings : array_like, optional
        Shape (K,): the readings, drawn as points.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    component : int, optional
        Which component of the state is drawn.
    title : str, optional
        Title of the axes.
    ylabel : str, optional
        Label of the y axis: the state and its unit.
    pyplot : bool, optional
        Whether the new figure is attached to pyplot (shown by a notebook).

    See Also
    --------
    plot_enclosure : the same figure, drawn once.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> kept = EnclosureFigure(result, seq.truth[:12], seq.readings[:12, 0], pyplot=False)
    >>> kept.update(result, seq.truth[:12]) is kept.figure
    True
    """

    @styled
    def __init__(
        self,
        result: Any,
        truth: Any,
        readings: Any = None,
        ax: Axes | None = None,
        *,
        component: int = 0,
        title: str | None = None,
        ylabel: str = "state x_k",
        pyplot: bool = True,
    ) -> None:
        if ax is None:
            ax = blank_figure(column_size(8.0, 3.0), "constrained", pyplot=pyplot).subplots()
        self.figure, self.ax, self.component = root_figure(ax), ax, component
        empty = np.zeros(0)
        self._band = ax.fill_between(
            empty, empty, empty, step="mid", alpha=0.35, label=f"{result.method} band"
        )
        self._truth = ax.plot([], [], "k-", lw=1.2, label="truth")[0]
        self._readings = (
            None
            if readings is None
            else ax.plot([], [], ".", ms=3, color="0.5", label="readings")[0]
        )
        # the steps of a reset: vertical lines over the whole height (x in steps, y in axes
        # fractions), one collection updated in place, outside the data limits
        self._resets = LineCollection(
            [], colors=BETP_COLOUR, linewidths=1, transform=ax.get_xaxis_transform()
        )
        ax.add_collection(self._resets, autolim=False)
        ax.set_xlabel("step k")
        ax.set_ylabel(ylabel)
        self.update(result, truth, readings, title=title)
        legend_above(ax)

    @styled
    def update(
        self, result: Any, truth: Any, readings: Any = None, *, title: str | None = None
    ) -> Figure:
        """Draw ``result`` (its band [lower, upper] per step), the ``truth`` and the ``readings``.

        The readings only if the figure was built with readings; steps flagged in
        ``result.diagnostics["resets"]`` get red vertical lines. Returns the figure.

        Parameters
        ----------
        result : dstoolkit.filters.FilterResult
            Another run of the filter.
        truth : array_like
            Shape (K,) or (K, d): its true states.
        readings : array_like, optional
            Shape (K,): its readings (only for a figure built with readings).
        title : str, optional
            Title of the axes.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.

        Raises
        ------
        dstoolkit.errors.EvidenceError
            If readings are given to a figure built without them.
        """
        if readings is not None and self._readings is None:
            raise EvidenceError(
                "this figure was built without readings: build a new EnclosureFigure to draw them"
            )
        ax, c = self.ax, self.component
        lower = np.asarray(result.lower)[:, c]
        upper = np.asarray(result.upper)[:, c]
        k = np.arange(lower.size)
        self._band.set_data(k, lower, upper)
        self._truth.set_data(k, np.asarray(truth).reshape(lower.size, -1)[:, c])
        if self._readings is not None:
            shown = readings is not None
            self._readings.set_visible(shown)
            self._readings.set_data(
                (k, np.asarray(readings).reshape(lower.size, -1)[:, 0]) if shown else ([], [])
            )
        resets = np.flatnonzero(result.diagnostics.get("resets", np.zeros(0, bool)))
        self._resets.set_segments([[(float(r), 0.0), (float(r), 1.0)] for r in resets])
        ax.title.set_text(title or "")  # keeps the pad legend_above gave it
        # the data's steps with matplotlib's margins; the states out to round numbers, so
        # that the limits (and with them the whole picture) change only when the band
        # crosses one: an explorer then redraws only the data (Explorer.png blits)
        ax.relim()
        (k0, y0), (k1, y1) = ax.dataLim.get_points()
        pad = ax.get_xmargin() * (k1 - k0)
        set_limits(ax, x=(k0 - pad, k1 + pad), y=snapped_limits(float(y0), float(y1)))
        return self.figure


@styled
def plot_enclosure(
    result: Any,
    truth: Any,
    readings: Any = None,
    ax: Axes | None = None,
    *,
    component: int = 0,
    title: str | None = None,
    ylabel: str = "state x_k",
) -> Figure:
    """Plot a filter run's band [lower, upper] per step, the truth and the readings.

    ``result`` is a :class:`~dstoolkit.filters.FilterResult` (its ``lower``/``upper``: boxes of
    a set-membership filter, hulls of evidence, or ±3σ of a Kalman filter). Steps flagged in
    ``result.diagnostics["resets"]`` (the box became empty) get red vertical lines.
    To redraw it for another run, keep an :class:`EnclosureFigure` instead.

    Parameters
    ----------
    result : dstoolkit.filters.FilterResult
        A filter run with ``lower`` and ``upper``, shape (K, d).
    truth : array_like
        Shape (K,) or (K, d): the true state per step.
    readings : array_like, optional
        Shape (K,): the readings, drawn as points.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    component : int, optional
        Which component of the state is drawn.
    title : str, optional
        Title of the axes.
    ylabel : str, optional
        Label of the y axis: the state and its unit.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> fig = plot_enclosure(result, seq.truth[:12], seq.readings[:12, 0],
    ...                      ylabel="frequency (Hz)")
    >>> fig.axes[0].get_ylabel()
    'frequency (Hz)'
    """
    return EnclosureFigure(
        result, truth, readings, ax, component=component, title=title, ylabel=ylabel
    ).figure


# -- the paper's Fig. 10 -----------------------------------------------------------------------


class FilterErrorsFigure:
    """The figure of :func:`plot_filter_errors`, kept.

    :meth:`update` draws another run in place. Attributes: ``figure``, ``axes`` (top,
    bottom).

    Parameters
    ----------
    result : dstoolkit.filters.FilterResult
        A run of a scalar filter.
    truth : array_like
        Shape (K,): the true state per step.
    readings : array_like
        Shape (K,): the readings.
    axes : collections.abc.Sequence, optional
        Axes to draw on (top, bottom); by default a new figure.
    title : str, optional
        Title of the axes.
    unit : str, optional
        Unit of the state.
    pyplot : bool, optional
        Whether the new figure is attached to pyplot (shown by a notebook).

    See Also
    --------
    plot_filter_errors : the same figure, drawn once.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> kept = FilterErrorsFigure(result, seq.truth[:12, 0], seq.readings[:12, 0], pyplot=False)
    >>> len(kept.axes)
    2
    """

    @styled
    def __init__(
        self,
        result: Any,
        truth: Any,
        readings: Any,
        axes: Sequence[Axes] | None = None,
        *,
        title: str | None = None,
        unit: str = "Hz",
        pyplot: bool = True,
    ) -> None:
        if axes is None:
            fig = blank_figure(column_size(6.4, 4.4), "none", pyplot=pyplot)
            axes = fig.subplots(2, 1, sharex=True)
            fig.subplots_adjust(left=0.12, right=0.84, top=0.8, bottom=0.11, hspace=0.12)
        top, bottom = axes
        self.figure, self.axes = root_figure(top), (top, bottom)
        self._titled = False
        self._deviations = (
            top.plot([], [], ".", ms=3, color="0.55", label="reading z_k − x_k")[0],
            top.plot([], [], "-", lw=1.4, color=BETP_COLOUR, label="estimate x̂_k − x_k")[0],
        )
        self._zero = top.axhline(0.0, color="black", lw=0.8)
        top.set_ylabel(f"deviation ({unit})")
        legend_above(top, ncols=2)
        bottom.set_yscale("log")
        self._errors = (
            bottom.plot([], [], ".", ms=3, color="0.55", label="reading |z_k − x_k|")[0],
            bottom.plot([], [], "-", lw=1.4, color=BETP_COLOUR, label="estimate |x̂_k − x_k|")[0],
        )
        bottom.set_ylabel(f"|error| ({unit})")
        bottom.yaxis.set_major_locator(FixedLocator((10.0 ** np.arange(-4, 4)).tolist()))
        bottom.yaxis.set_major_formatter(StrMethodFormatter("{x:g}"))
        bottom.yaxis.set_minor_locator(NullLocator())
        bottom.set_xlabel("step k")
        # each series named at its end, in short; update moves the names with the data
        self._end_labels = tuple(
            label_line_ends(ax, list(lines), labels=["reading", "estimate"])
            for ax, lines in ((top, self._deviations), (bottom, self._errors))
        )
        self.update(result, truth, readings, title=title)

    @styled
    def update(self, result: Any, truth: Any, readings: Any, *, title: str | None = None) -> Figure:
        """Draw the run ``result`` of a scalar filter against ``truth`` and ``readings``.

        ``title`` goes above the legend, wrapped to the figure's width. Returns the figure.

        Parameters
        ----------
        result : dstoolkit.filters.FilterResult
            Another run of a scalar filter.
        truth : array_like
            Shape (K,): its true states.
        readings : array_like
            Shape (K,): its readings.
        title : str, optional
            Written above the legend.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        x = np.asarray(truth, dtype=float).reshape(-1)
        est = np.asarray(result.estimates, dtype=float).reshape(-1) - x
        z = np.asarray(readings, dtype=float).reshape(-1) - x
        k = np.arange(1, x.size + 1)
        top, bottom = self.axes
        for line, values in zip(self._deviations, (z, est), strict=True):
            line.set_data(k, values)
        for line, values in zip(self._errors, (z, est), strict=True):
            line.set_data(k, np.abs(values) + 1e-6)
        if title or self._titled:  # above the legend, wrapped to the figure's width
            self.figure.suptitle(
                title or "", x=0.01, y=0.99, ha="left", va="top", fontsize=SMALL_PT, wrap=True
            )
            self._titled = True
        # The zero line widens the view only when 0 falls outside the data's (as
        # axhline does when it is drawn after the data).
        self._zero.set_visible(False)
        top.relim(visible_only=True)
        self._zero.set_visible(True)
        bottom.relim()
        bottom.set_autoscaley_on(True)
        for ax in self.axes:
            ax.autoscale_view()
        low, high = top.get_ylim()
        if not low <= 0.0 <= high:
            _autoscale(top)
        positive = np.abs(est)[np.abs(est) > 0]
        bottom.set_ylim(bottom=max(1e-3, 0.5 * float(positive.min())) if positive.size else 1e-3)
        for ax, lines, texts in zip(
            self.axes, (self._deviations, self._errors), self._end_labels, strict=True
        ):
            place_line_end_labels(ax, lines, texts)
        return self.figure


@styled
def plot_filter_errors(
    result: Any,
    truth: Any,
    readings: Any,
    axes: Sequence[Axes] | None = None,
    *,
    title: str | None = None,
    unit: str = "Hz",
) -> Figure:
    """Plot a scalar filter run against the truth, as the paper's Fig. 10.

    Top, x̂_k − x_k and the readings' z_k − x_k; bottom, the absolute errors |x̂_k − x_k|
    and |z_k − x_k| on a log scale. (The hull of the final evidence is not drawn: with the
    discounts' Θ in it, it is far wider than the readings' spread.)

    Drawn for speed (the filter widget redraws it on every change, as a kept
    :class:`FilterErrorsFigure`): fixed margins instead of a layout engine, and fixed log
    ticks with plain labels (no minor ticks, no mathtext).

    Parameters
    ----------
    result : dstoolkit.filters.FilterResult
        A run of a scalar filter.
    truth : array_like
        Shape (K,): the true state per step.
    readings : array_like
        Shape (K,): the readings.
    axes : collections.abc.Sequence, optional
        Axes to draw on (top, bottom); by default a new figure.
    title : str, optional
        Title of the axes.
    unit : str, optional
        Unit of the state.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    References
    ----------
    The paper's Fig. 10.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> fig = plot_filter_errors(result, seq.truth[:12, 0], seq.readings[:12, 0])
    >>> fig.axes[1].get_yscale()
    'log'
    """
    return FilterErrorsFigure(result, truth, readings, axes, title=title, unit=unit).figure


# -- one step of the paper's filter (Fig. 3) ---------------------------------------------------

#: The evidence a recorded step of the dependent-evidence filter holds (Steps 2–6), in
#: the order of the paper's flowchart (Fig. 3), with the titles used in the pictures.
FILTER_STEP_PANELS: tuple[tuple[str, str], ...] = (
    ("state", r"Step 2: state $\hat{x}_k + V$"),
    ("prediction", r"Step 2: prediction $E_{k+1|k}$"),
    ("observation_prediction", r"Step 3: observation prediction $g(E_{k+1|k})$"),
    ("observation", r"Step 4: observation $z_{k+1} + W$"),
    ("fused", "Step 4: fused (Dempster)"),
    ("mapped_back", r"Step 5: mapped back through $g^{-1}$"),
    ("final", "Step 6: final (dependent combination)"),
)


class FilterStepFigure:
    """The figure of :func:`plot_filter_step`, kept.

    :meth:`update` draws another recorded step in place, if it has the same panels
    (:meth:`panels_of`: a step that a total conflict stopped has fewer). Attributes:
    ``figure``, ``axes``, ``panels``.

    Parameters
    ----------
    entry : dstoolkit.filters.DependentRecord
        One recorded step of a scalar model.
    truth : float, optional
        The true state of that step.
    half_width : float, optional
        Half-width of the x range (unit ``unit``).
    figsize : tuple of float, optional
        Width and height (inches); the width is capped at the column's.
    unit : str, optional
        Unit of the state.
    pyplot : bool, optional
        Whether the figure is attached to pyplot (shown by a notebook).

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``entry`` is not a recorded step of a scalar model.

    See Also
    --------
    plot_filter_step : the same figure, drawn once.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> kept = FilterStepFigure(result.steps[1], truth=seq.truth[1, 0], pyplot=False)
    >>> kept.update(result.steps[2], truth=seq.truth[2, 0]) is kept.figure
    True
    """

    @staticmethod
    def panels_of(entry: DependentRecord) -> tuple[str, ...]:
        """Return the panels a recorded step fills: the keys of ``FILTER_STEP_PANELS`` it holds.

        Parameters
        ----------
        entry : dstoolkit.filters.DependentRecord
            One recorded step.

        Returns
        -------
        tuple of str
            The names of its panels, top to bottom.
        """
        return tuple(key for key, _ in FILTER_STEP_PANELS if getattr(entry, key) is not None)

    @styled
    def __init__(
        self,
        entry: DependentRecord,
        truth: float | None = None,
        *,
        half_width: float | None = None,
        figsize: tuple[float, float] = (6.4, 10.0),
        unit: str = "Hz",
        pyplot: bool = True,
    ) -> None:
        _check_step(entry)
        self.panels, self.unit = self.panels_of(entry), unit
        fig = blank_figure(column_size(*figsize), "constrained", pyplot=pyplot)
        self.figure, self.axes = fig, list(fig.subplots(len(self.panels), 1, squeeze=False)[:, 0])
        self._focal: list[FocalIntervalArtists] = []
        self._lines: list[tuple[Line2D, Line2D] | None] = []
        for ax, key in zip(self.axes, self.panels, strict=True):
            self._focal.append(draw_focal_intervals(ax, xlabel=""))
            ax.xaxis.set_major_locator(InnerTicks())  # the layout stays as the x range moves
            ax.set_ylabel("mass")
            if key == "state":
                self._lines.append(None)
                continue
            self._lines.append(
                (
                    ax.axvline(0.0, color=BETP_COLOUR, lw=1.2),
                    ax.axvline(0.0, color="black", lw=1.0, ls="--"),
                )
            )
            if ax is not self.axes[-1]:
                # no tick labels and no x label here: nothing to format or to place
                ax.tick_params(labelbottom=False)
                ax.xaxis.set_major_formatter(NullFormatter())
                ax.xaxis.set_label_coords(0.5, 0.0)
        missing = [name for key, name in FILTER_STEP_PANELS if key not in self.panels]
        if missing:  # no empty panels: the steps a total conflict stopped are named instead
            fig.suptitle("not reached (total conflict): " + "; ".join(missing), fontsize=SMALL_PT)
        self.update(entry, truth, half_width=half_width)

    @styled
    def update(
        self, entry: DependentRecord, truth: float | None = None, *, half_width: float | None = None
    ) -> Figure:
        """Draw the recorded step ``entry`` (with the ``truth`` of its state, if given).

        ``half_width`` of the x range: default, 0.75 × the widest cut of the observation
        evidence (its Θ aside). Returns the figure.

        Parameters
        ----------
        entry : dstoolkit.filters.DependentRecord
            Another recorded step, with the same panels.
        truth : float, optional
            Its true state.
        half_width : float, optional
            Half-width of the x range (unit of the state).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.

        Raises
        ------
        dstoolkit.errors.EvidenceError
            If the step fills other panels than the figure has.
        """
        _check_step(entry)
        if self.panels_of(entry) != self.panels:
            raise EvidenceError(
                f"this step fills the panels {self.panels_of(entry)}, the "
                f"figure has {self.panels}: build a new FilterStepFigure"
            )
        est = float(np.ravel(entry.estimate)[0])
        if half_width is None:
            obs = entry.observation
            assert obs is not None, "a step that reached the update has its observation"
            cuts = obs.widths < obs.widths.max()
            half_width = 0.75 * float(
                (obs.hi_1d[cuts] - obs.lo_1d[cuts]).max() if cuts.any() else 1.0
            )
        centre = est if truth is None else 0.5 * (est + float(truth))
        xlim = (centre - half_width, centre + half_width)
        assert entry.state is not None, "a recorded step holds the state it started from"
        shift = centre - float(entry.state.pignistic_expectation_1d())
        names = dict(FILTER_STEP_PANELS)
        for i, (ax, key) in enumerate(zip(self.axes, self.panels, strict=True)):
            ev = getattr(entry, key)
            lim = (xlim[0] - shift, xlim[1] - shift) if key == "state" else xlim
            update_focal_intervals(self._focal[i], ev, xlim=lim, label_masses=len(ev) <= 6)
            ax.set_xlabel(f"state at step {entry.step - 1} ({self.unit})" if key == "state" else "")
            # y = 1 where matplotlib would put it (nothing is drawn above the panel), so
            # that a draw skips the search for it (a tight box of each panel's y axis)
            ax.set_title(f"{names[key]} — {len(ev)} focal elements", loc="left", y=1.0)
            lines = self._lines[i]
            if lines is not None:
                estimate, true = lines
                estimate.set_xdata([est, est])
                true.set_visible(truth is not None)
                if truth is not None:
                    true.set_xdata([float(truth)] * 2)
        self.axes[-1].set_xlabel(
            f"state at step {entry.step} ({self.unit}); red: estimate, dashed: truth"
        )
        return self.figure


def _check_step(entry: DependentRecord) -> None:
    if not isinstance(entry, DependentRecord) or entry.final is None or entry.state is None:
        raise EvidenceError(
            "plot_filter_step needs a recorded step k >= 2 (run(..., "
            "record=True).steps[k - 1]); step 1 is the start value only"
        )


@styled
def plot_filter_step(
    entry: DependentRecord,
    truth: float | None = None,
    *,
    half_width: float | None = None,
    figsize: tuple[float, float] = (6.4, 10.0),
    unit: str = "Hz",
) -> Figure:
    """Plot every evidence of one recorded step of the paper's filter, stacked top to bottom.

    The step is a :class:`~dstoolkit.filters.DependentRecord` of a scalar model; the panels
    are stacked as in the flowchart (Fig. 3).

    Each panel draws the focal elements as in :func:`plot_focal_intervals`. The panels
    about x_{k+1} share one x range, centred on the final estimate (red line; black: the
    ``truth``); the state panel, about x_k, has the same width around x̂_k, so widths
    compare across panels. ``half_width`` defaults to the half-width of the observation
    evidence's widest cut (its Θ aside) plus a margin. To draw other steps in the same
    figure, keep a :class:`FilterStepFigure` instead.

    Parameters
    ----------
    entry : dstoolkit.filters.DependentRecord
        One recorded step of a scalar model.
    truth : float, optional
        The true state of that step.
    half_width : float, optional
        Half-width of the x range (unit ``unit``).
    figsize : tuple of float, optional
        Width and height (inches); the width is capped at the column's.
    unit : str, optional
        Unit of the state.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    Raises
    ------
    dstoolkit.errors.EvidenceError
        If ``entry`` is not a recorded step of a scalar model.

    References
    ----------
    The paper's Fig. 3.

    Examples
    --------
    >>> from dstoolkit.studies import filter_case
    >>> seq, _, result = filter_case(9.6, 23.9, record=True, first=12)
    >>> fig = plot_filter_step(result.steps[1], truth=seq.truth[1, 0])
    >>> len(fig.axes) > 2
    True
    """
    return FilterStepFigure(entry, truth, half_width=half_width, figsize=figsize, unit=unit).figure
