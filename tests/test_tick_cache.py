"""Tick locators and formatters that remember their last ticks (dstoolkit.plots.artists).

Remembering must never show other ticks or labels than matplotlib's own: after every change
of what they depend on, they are computed again.
"""

from __future__ import annotations

import matplotlib
import numpy as np

matplotlib.use("Agg")

from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.ticker import AutoLocator, LogLocator, MaxNLocator, ScalarFormatter  # noqa: E402

from dstoolkit.plots.artists import remember_ticks  # noqa: E402


def labels(fig: Figure) -> list[list[str]]:
    """Return the drawn tick labels of every axis of ``fig``."""
    fig.canvas.draw()
    return [
        [t.get_text() for t in axis.get_ticklabels() if t.get_visible()]
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
    ]


def pixels(fig: Figure) -> np.ndarray:
    """Return the picture of ``fig`` as its last draw left it."""
    return np.asarray(fig.canvas.buffer_rgba()).copy()


def twin_figures() -> tuple[Figure, Figure]:
    """Make two equal figures, each with a linear and a log axes."""
    figs = []
    for _ in range(2):
        fig = Figure(figsize=(5.0, 4.0), dpi=100)
        FigureCanvasAgg(fig)
        lin, log = fig.subplots(2, 1)
        lin.plot([0.0, 1.0], [1000.0, 1001.0])
        lin.set_xlabel("x (Hz)")
        lin.set_ylabel("y (Hz)")
        log.semilogy([1.0, 2.0, 3.0], [0.001, 0.5, 2.0])
        log.set_ylabel("|error| (m)")
        figs.append(fig)
    return figs[0], figs[1]


def test_remembered_ticks_follow_every_change_as_matplotlib_does() -> None:
    kept, fresh = twin_figures()
    remember_ticks(kept)
    for ax in kept.axes:  # still the classes matplotlib tests for
        assert isinstance(ax.xaxis.get_major_locator(), AutoLocator | LogLocator)
        assert isinstance(ax.xaxis.get_major_formatter(), ScalarFormatter)
    assert labels(kept) == labels(fresh)
    changes = [
        lambda f: f.axes[0].set_xlim(0.2, 0.7),  # another view
        lambda f: f.axes[0].set_ylim(1000.0005, 1000.0009),  # labels with an offset
        lambda f: f.axes[1].set_ylim(0.01, 100.0),  # another log view
        lambda f: f.set_size_inches(3.0, 6.0),  # another size: other tick spacing
        lambda f: f.axes[0].tick_params(labelsize=20),  # larger labels: fewer ticks
        lambda f: f.axes[0].set_xlim(0.2, 0.7),  # the same view again
        lambda f: f.axes[1].set_ylim(1e-6, 1e6),  # wider tick labels: the label moves out
        lambda f: f.axes[0].tick_params(axis="y", labelrotation=30),
    ]
    for change in changes:
        change(kept)
        change(fresh)
        assert labels(kept) == labels(fresh)
        np.testing.assert_array_equal(pixels(kept), pixels(fresh))
        for a, b in zip(kept.axes, fresh.axes, strict=True):
            assert a.yaxis.label.get_position() == b.yaxis.label.get_position()
            assert a.xaxis.label.get_position() == b.xaxis.label.get_position()
            np.testing.assert_array_equal(a.get_yticks(), b.get_yticks())
            assert a.yaxis.get_offset_text().get_text() == b.yaxis.get_offset_text().get_text()


def test_a_locator_set_later_remembers_at_the_next_call() -> None:
    fig = Figure()
    ax = fig.subplots()
    remember_ticks(fig)
    plain = MaxNLocator(3)
    ax.xaxis.set_major_locator(plain)
    assert type(plain) is MaxNLocator
    remember_ticks(fig)
    remember_ticks(fig)  # twice: one subclass, not a subclass of it
    assert type(plain).__mro__[1] is MaxNLocator
    ax.set_xlim(0.0, 9.0)
    assert plain().tolist() == MaxNLocator(3).tick_values(0.0, 9.0).tolist()
