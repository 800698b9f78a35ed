"""The explorers' canvas caches the text it drew (dstoolkit.plots._text_cache).

The pictures must be the same to the byte as plain Agg's, text drawn again from the cache
included.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from dstoolkit.plots import _text_cache  # noqa: E402
from dstoolkit.plots._text_cache import TextCachingCanvas, TextCachingRenderer  # noqa: E402
from dstoolkit.teaching import (  # noqa: E402
    filter_step_explorer,
    gauge_explorer,
    mass_function_explorer,
)


def pixels(fig: Figure, canvas: type[FigureCanvasAgg]) -> np.ndarray:
    """Draw ``fig`` whole on a new ``canvas``, its animated artists on top.

    This is how an explorer draws a figure that changed.
    """
    canvas(fig)
    fig.canvas.draw()
    for artist in sorted(fig.findobj(lambda a: a.get_animated()), key=lambda a: a.get_zorder()):
        fig.draw_artist(artist)
    return np.asarray(fig.canvas.buffer_rgba()).copy()


def text_figure(shift: float) -> Figure:
    """Make text of every kind a figure draws.

    Rotated, small and large, bold, non-antialiased, mathtext, non-ASCII, at positions
    whose sub-pixel part moves with ``shift``.
    """
    fig = Figure(figsize=(4.0, 3.0), dpi=96)
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1])
    ax.set_xlabel("step k — x̂_k (Hz)")
    ax.set_ylabel("|error| (m)")  # rotated 90°
    ax.set_title("Step 4: fused (Dempster) — 28 focal elements", loc="left", fontsize=9)
    ax.text(0.1 + shift, 0.5 + shift, "0.3167 [1093, 1100]", fontsize=7.3)
    ax.text(0.3 + shift, 0.2, "bold, 30°", rotation=30, fontweight="bold")
    ax.text(0.5, 0.7 + shift, "no antialiasing", antialiased=False)
    ax.text(0.6 + shift, 0.4, r"$\alpha_k^2 + \sqrt{x}$")
    return fig


def test_cached_text_draws_the_same_pixels_as_agg() -> None:
    """Cached text draws Agg's pixels, whether the canvas caches or not.

    On a matplotlib whose text path the cache replays (3.11's: the one installed in the
    project's environment), the canvas caches; on another it draws as Agg does. Either way
    the pixels are Agg's.
    """
    if tuple(int(part) for part in matplotlib.__version__.split(".")[:2]) == (3, 11):
        assert _text_cache.SUPPORTED, "3.11 changed its text path: see plots/_text_cache.py"
    _text_cache._layouts.clear()
    _text_cache._glyphs.clear()
    _text_cache._metrics.clear()
    for shift in (0.0, 0.0013, 0.0, 0.25):  # fresh, moved by sub-pixels, drawn again
        fig = text_figure(shift)
        cached = pixels(fig, TextCachingCanvas)
        expected = TextCachingRenderer if _text_cache.SUPPORTED else RendererAgg
        assert type(fig.canvas.get_renderer()) is expected
        np.testing.assert_array_equal(cached, pixels(fig, FigureCanvasAgg))
    assert bool(_text_cache._glyphs) == bool(_text_cache._metrics) == _text_cache.SUPPORTED


def test_the_cache_stays_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_text_cache, "MAX_ENTRIES", 5)
    cache: dict[int, int] = {}
    for i in range(12):
        _text_cache._remember(cache, i, i)
        assert len(cache) <= 5
    assert cache[11] == 11


@pytest.mark.parametrize(
    "make, changes",
    [
        (filter_step_explorer, [("step", 3), ("epsilon", 0.1), ("step", 6)]),
        (gauge_explorer, [("level", 6.0), ("top_reflection", 0.5)]),
        (mass_function_explorer, [("low", 0.35), ("high", 0.15)]),  # blitted: animated bars
    ],
)
def test_explorer_pictures_are_agg_pictures(make, changes) -> None:
    """What an explorer shows is what plain Agg draws for the same figure.

    The explorer draws through its caching canvas, blitted or whole.
    """
    ex = make()
    for name, value in changes:
        ex.controls[name].value = value
        shown = np.asarray(ex.figure.canvas.buffer_rgba()).copy()
        assert isinstance(ex.figure.canvas, TextCachingCanvas)
        np.testing.assert_array_equal(shown, pixels(ex.figure, FigureCanvasAgg))


def test_mathtext_glyphs_come_from_the_cache() -> None:
    """A mathtext string drawn again takes its glyphs from the cache, not from FreeType."""
    fig = Figure(figsize=(2.0, 1.0), dpi=100)
    fig.text(0.1, 0.4, r"$\hat{x}_{k+1|k} = g^{-1}(\sqrt{z})$")
    TextCachingCanvas(fig)
    if not _text_cache.SUPPORTED:  # another matplotlib: drawn as by Agg, nothing cached
        assert type(fig.canvas.get_renderer()) is RendererAgg
        return
    _text_cache._glyphs.clear()
    fig.canvas.draw()
    glyphs = dict(_text_cache._glyphs)
    assert len(glyphs) >= 8  # x, k, 1, g, z, the radical, ... each at its offset
    fig.canvas.draw()
    assert _text_cache._glyphs == glyphs  # drawn again: nothing new rendered
