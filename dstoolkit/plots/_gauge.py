"""Pictures of the gauge.

The recorded waveform (paper Fig. 6), the resonances (Fig. 7) and the gauge explorer's
detection (a figure built once and updated).

Like :mod:`dstoolkit.plots`, each function draws on a given ``Axes`` (or a new
figure), returns the :class:`~matplotlib.figure.Figure` and never calls ``plt.show()``.
"""

from __future__ import annotations

from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.transforms import offset_copy

from dstoolkit.gauge import DetectionResult, Recording, TubeSetup

from ._evidence import _axes
from ._kept import animate, set_limits, snapped_limits, zero_based_limits
from ._style import (
    BEL_COLOUR,
    BETP_COLOUR,
    FONT_PT,
    GREY,
    SMALL_PT,
    TRUTH_COLOUR,
    legend_above,
    root_figure,
    styled,
)

#: ``TraceLine`` draws through extremes only from this many samples per quarter pixel:
#: fewer draw the shapes of single waves, which a line through extremes would not show.
TRACE_RUN = 16
#: Vertices per piece in which Agg fills a ``TraceLine`` through extremes: its rasteriser
#: keeps the cells of the largest path it has filled for as long as the figure's canvas
#: lives, tens of MiB for a recording's band in one piece.
TRACE_CHUNK = 1000


class TraceLine(Line2D):
    """A line through a long trace of samples at increasing times (a recording).

    It is drawn through its extremes per pixel column of the view: in each of four runs per
    pixel, its lowest and highest sample, in time order.

    Where the view holds ``TRACE_RUN`` samples or more per quarter pixel, the line through
    every sample is a solid band and the line through the extremes covers the same span in
    every column of pixels, much faster (a 220,000-sample recording across 780 pixels:
    6,240 points); with fewer, every sample is drawn. The line keeps every sample as its
    data and picks the view's at each draw, so a zoomed axes (``set_xlim``) is drawn right.
    Agg fills it in pieces of :data:`TRACE_CHUNK` vertices.

    """

    def draw(self, renderer: Any) -> None:
        t = np.asarray(self.get_xdata(orig=True))
        y = np.asarray(self.get_ydata(orig=True))
        axes = self.axes
        assert axes is not None, "a TraceLine is drawn on axes"
        columns = 4 * int(np.ceil(axes.bbox.width))
        lo, hi = sorted(axes.get_xlim())
        first, last = np.searchsorted(t, [lo, hi])
        first, last = max(first - 1, 0), min(last + 1, t.size)
        if last - first < TRACE_RUN * columns:  # a line through waves, not a band: all of it
            super().draw(renderer)
            return
        view = y[first:last]
        run = view.size // columns
        runs = view[: run * columns].reshape(columns, run)
        low, high = runs.argmin(axis=1), runs.argmax(axis=1)
        start = first + np.arange(columns) * run
        keep = np.concatenate(
            [
                [first],
                (start[:, None] + np.sort(np.column_stack([low, high]), axis=1)).ravel(),
                np.arange(first + run * columns, last),
                [last - 1],
            ]
        )
        keep = keep[np.r_[True, np.diff(keep) > 0]]
        self.set_data(t[keep], y[keep])
        try:
            with mpl.rc_context({"agg.path.chunksize": TRACE_CHUNK}):
                super().draw(renderer)
        finally:
            self.set_data(t, y)


def add_trace(ax: Axes, times: np.ndarray, samples: np.ndarray, **kwargs: Any) -> Line2D:
    """Draw a long trace of samples (a recording) on ``ax``, as a line through its extremes.

    In every pixel column of the view the line passes through the lowest and highest sample
    of four runs, in time order: the band a line through every sample would fill, at a
    fraction of the points; where the view holds few samples per pixel, every one is drawn.
    The line keeps every sample, so a later ``set_xlim`` is drawn right. Agg fills it in
    pieces (its rasteriser keeps the cells of the largest piece for as long as the figure's
    canvas lives: tens of MiB for a recording in one piece).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw; its limits are fitted to the trace.
    times : numpy.ndarray, shape (n,)
        The sample times, increasing.
    samples : numpy.ndarray, shape (n,)
        The samples.
    **kwargs
        What :class:`matplotlib.lines.Line2D` takes (``lw``, ``color``, ``label``...).

    Returns
    -------
    matplotlib.lines.Line2D
        The line.

    See Also
    --------
    plot_recording : A recording with its envelope and resonances.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> from dstoolkit.plots import add_trace
    >>> t = np.arange(200_000) / 44100
    >>> line = add_trace(Figure().subplots(), t, np.sin(2e3 * t), lw=0.3)
    >>> line.get_xdata().size, bool(line.axes.get_ylim()[1] > 1)
    (200000, True)
    """
    line = ax.add_line(TraceLine(times, samples, **kwargs))
    ax.autoscale_view()
    return line


@styled
def plot_recording(
    recording: Recording,
    detection: DetectionResult | None = None,
    ax: Axes | None = None,
    *,
    frequency_axis: bool = True,
    title: str | None = None,
) -> Figure:
    """Plot the microphone signal over time with its envelope and detected peaks (Fig. 6).

    With ``frequency_axis`` a top axis reads time as the sweep's instantaneous frequency
    f₀ + k (t − τ) (τ from ``detection`` when given, else the simulated latency, else 0).
    The signal is a ``TraceLine`` (drawn through its extremes per pixel column).

    Parameters
    ----------
    recording : dstoolkit.gauge.Recording
        A recording (simulated or real).
    detection : dstoolkit.gauge.DetectionResult, optional
        Its detected resonances, drawn on the envelope.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    frequency_axis : bool, optional
        Whether a top axis reads time as the sweep's frequency.
    title : str, optional
        Title of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    References
    ----------
    The paper's Fig. 6.

    Examples
    --------
    >>> from dstoolkit.gauge import PAPER_SWEEP, TubeSetup, detect_resonances, synthesize_recording
    >>> from dstoolkit.teaching import GAUGE_CONDITIONS
    >>> setup = TubeSetup(4.6, 26.5)
    >>> recording = synthesize_recording(setup, PAPER_SWEEP, GAUGE_CONDITIONS, seed=0)
    >>> detection = detect_resonances(recording)
    >>> fig = plot_recording(recording, detection)
    >>> fig.axes[0].get_xlabel()
    'time t (s)'
    """
    fig, ax = _axes(ax, (8.0, 3.2))
    t = recording.times
    add_trace(ax, t, recording.samples, lw=0.3, color=GREY, label="microphone")
    tau = 0.0
    if detection is not None:
        tau = detection.latency_s
        ax.plot(
            detection.envelope_times, detection.envelope, color=BEL_COLOUR, lw=1.0, label="envelope"
        )
        ax.plot(detection.envelope_times, -detection.envelope, color=BEL_COLOUR, lw=1.0)
        ax.plot(
            detection.peak_times,
            detection.amplitudes,
            "v",
            ms=4,
            color=BETP_COLOUR,
            label="resonances",
        )
    elif recording.conditions is not None:
        tau = recording.conditions.latency_s
    ax.set_xlabel("time t (s)")
    ax.set_ylabel("amplitude (full scale)")
    ax.set_xlim(t[0], t[-1])
    if frequency_axis:
        sweep = recording.sweep
        top = ax.secondary_xaxis(
            "top",
            functions=(
                lambda x: sweep.frequency_at(np.asarray(x) - tau),
                lambda f: sweep.time_at(f) + tau,
            ),
        )
        top.set_xlabel("instantaneous frequency of the sweep (Hz)")
    if title is None and recording.setup is not None:
        title = f"L = {recording.setup.level_m:g} m, T = {recording.setup.temperature_c:g} °C"
    if title:
        ax.set_title(title)
    if frequency_axis:  # the top axis holds the frequencies: the legend goes below the label
        below = offset_copy(
            ax.transAxes, fig=root_figure(ax), y=-2.6 * FONT_PT - 2 * SMALL_PT, units="points"
        )
        ax.legend(
            loc="upper center",
            bbox_to_anchor=(0.5, 0.0),
            bbox_transform=below,
            ncols=3,
            frameon=False,
            borderaxespad=0.0,
        )
    else:
        legend_above(ax)
    return fig


@styled
def plot_resonances(
    detection: DetectionResult,
    ax: Axes | None = None,
    *,
    true_frequencies: Any = None,
    title: str | None = None,
) -> Figure:
    """Resonance frequencies z_k with their envelope amplitudes as stems (Fig. 7).

    ``true_frequencies`` (e.g. n c/(2L) in the band) are drawn as thin dotted vertical
    lines; detected resonances as solid stems with dots, missed ones as crosses on the
    axis, spurious peaks as dashed grey stems topped by a square: each kind has its own
    line style or marker, not only its colour.

    Parameters
    ----------
    detection : dstoolkit.gauge.DetectionResult
        The resonances detected in one recording.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; by default a new figure of its own.
    true_frequencies : array_like, optional
        Shape (n,): the resonances the model expects, n c/(2L) (Hz).
    title : str, optional
        Title of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on.

    References
    ----------
    The paper's Fig. 7.

    Examples
    --------
    >>> from dstoolkit.gauge import PAPER_SWEEP, TubeSetup, detect_resonances, synthesize_recording
    >>> from dstoolkit.teaching import GAUGE_CONDITIONS
    >>> setup = TubeSetup(4.6, 26.5)
    >>> recording = synthesize_recording(setup, PAPER_SWEEP, GAUGE_CONDITIONS, seed=0)
    >>> detection = detect_resonances(recording)
    >>> fig = plot_resonances(detection, true_frequencies=setup.resonances(PAPER_SWEEP.band)[1])
    >>> fig.axes[0].get_xlabel()
    'resonance frequency (Hz)'
    """
    fig, ax = _axes(ax, (8.0, 3.2))
    if true_frequencies is not None:
        for f in np.asarray(true_frequencies, dtype=float):
            ax.axvline(f, color=TRUTH_COLOUR, lw=0.8, ls=":")
        ax.plot([], [], color=TRUTH_COLOUR, lw=0.8, ls=":", label="n c/(2L)")
    markers, stems, base = ax.stem(
        detection.frequencies,
        detection.amplitudes,
        linefmt="-",
        markerfmt="o",
        basefmt=" ",
        label=f"detected z_k ({detection.frequencies.size})",
    )
    stems.set_color(BEL_COLOUR)
    markers.set_color(BEL_COLOUR)
    markers.set_markersize(3)
    if detection.missed.size:
        ax.plot(
            detection.missed,
            np.zeros(detection.missed.size),
            "x",
            color=BETP_COLOUR,
            label=f"missed ({detection.missed.size})",
        )
    if detection.spurious.size:
        top = 0.5 * np.max(detection.amplitudes)
        ax.vlines(detection.spurious, 0, top, color=GREY, ls="--")
        ax.plot(detection.spurious, np.full(detection.spurious.size, top), "s", ms=3.5, color=GREY)
        ax.plot(
            [],
            [],
            color=GREY,
            ls="--",
            marker="s",
            ms=3.5,  # the legend's entry
            label=f"spurious ({detection.spurious.size})",
        )
    ax.set_xlabel("resonance frequency (Hz)")
    ax.set_ylabel("envelope amplitude (full scale)")
    ax.set_ylim(bottom=0)
    ax.set_title(title or f"f_F = {detection.fundamental_hz:.2f} Hz", loc="left")
    legend_above(ax, ncols=4)
    return fig


def gauge_detection_figure(setup: TubeSetup, detection: DetectionResult) -> Figure:
    """Draw the gauge explorer's picture of one detection in the tube ``setup``.

    Top, the recording's envelope against the sweep's frequency, the model's resonances
    n c/(2L) (eqs. 29–32) and the detected peaks; bottom, the detection error
    z_k − n_k f_F.

    Built once and kept: :func:`update_gauge_detection` draws another detection on it. The
    data and the title are animated and the limits snap to round numbers, so that most
    changes redraw only them; the legend stands above the data. It is the explorer's own
    (9.5 in wide, in the notebook's style), not a figure of the book.
    """
    fig = Figure(figsize=(9.5, 4.8), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
    ax1.plot([], [], lw=0.8, color=BEL_COLOUR, label="envelope")
    ax1.vlines(
        [],
        0,
        1,
        transform=ax1.get_xaxis_transform(),
        color=TRUTH_COLOUR,
        lw=0.5,
        alpha=0.6,
        label="n c/(2L)",
    )
    ax1.plot([], [], "v", ms=4, color=BETP_COLOUR, label="detected peaks")
    ax1.set_ylabel("envelope (full scale)")
    legend_above(ax1, ncols=3, fontsize=8)
    ax1.set_title("", pad=8.0 + 1.75 * SMALL_PT)  # above the legend (legend_above's rule)
    ax2.axhline(0.0, color="black", lw=0.6)
    ax2.plot([], [], ".", color=BETP_COLOUR)
    ax2.set_ylabel("z_k − n_k f_F (Hz)")
    ax2.set_xlabel("sweep frequency (Hz)")
    ax2.set_xlim(detection.sweep.f_start, detection.sweep.f_stop)
    animate(*ax1.lines, *ax1.collections, ax1.title, ax2.lines[1])
    update_gauge_detection(fig, setup, detection)
    return fig


def update_gauge_detection(fig: Figure, setup: TubeSetup, detection: DetectionResult) -> None:
    """Draw another detection on a :func:`gauge_detection_figure`: new data and title.

    The envelope's limits where they cross round numbers, the error's where it crosses
    1, 2, 5 × 10ⁿ Hz.
    """
    (ax1, ax2), sweep = fig.axes, detection.sweep
    envelope, peaks = ax1.lines
    (model,) = ax1.collections
    f_env = sweep.frequency_at(detection.envelope_times - detection.latency_s)
    keep = (f_env >= sweep.f_start) & (f_env <= sweep.f_stop)
    envelope.set_data(f_env[keep], detection.envelope[keep])
    resonances = setup.resonances(sweep.band)[1]
    segments = np.zeros((resonances.size, 2, 2))
    segments[:, :, 0] = resonances[:, None]
    segments[:, 1, 1] = 1.0
    assert isinstance(model, LineCollection), "the model's lines are drawn by vlines"
    model.set_segments(list(segments))
    peaks.set_data(detection.raw_frequencies - detection.latency_offset_hz, detection.amplitudes)
    ax1.title.set_text(
        f"L = {setup.level_m:.1f} m, T = {setup.temperature_c:.1f} °C, c = "
        f"{setup.speed_of_sound:.1f} m/s, f_F = {setup.fundamental_hz:.2f} Hz"
    )
    f_f = setup.fundamental_hz
    errors = detection.frequencies - np.rint(detection.frequencies / f_f) * f_f
    ax2.lines[1].set_data(detection.frequencies, errors)
    # the error axis holds the zero line
    set_limits(
        ax1, y=snapped_limits(0.0, 1.3 * float(np.max(detection.envelope[keep])), margin=0.0)
    )
    set_limits(
        ax2,
        y=zero_based_limits(float(np.min(errors, initial=0.0)), float(np.max(errors, initial=0.0))),
    )
