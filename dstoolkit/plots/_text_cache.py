"""An Agg canvas that remembers the text it drew: the explorers' figures redraw faster.

An explorer redraws its figure on every change of a control, and most of what it draws
again is text (titles, axis labels, tick labels), much of it the same as the last time.
With matplotlib ≥ 3.11, Agg lays out each string with libraqm and renders it glyph by
glyph through FreeType, every time: much of the cost of a redraw.
:class:`TextCachingCanvas` keeps both results:

- the layout of a string (its glyphs and their positions) per string, font, size and dpi
  (a mathtext string's layout is kept by matplotlib's mathtext parser);
- the bitmap of a glyph per font, size, glyph, angle and sub-pixel position (1/64 px, as
  Agg places it), so that a glyph drawn again at another whole-pixel position is the same
  bitmap moved;
- a font's line metrics (ascent, descent, line gap from its tables), which matplotlib reads
  again each time it places a text.

Each cached glyph is drawn through the same Agg call as before, at the same place, so the
picture is the same to the byte (tested). When matplotlib renders text otherwise (before
3.11, or a future change of its private text path), the canvas renders as plain Agg does.
The caches are bounded (:data:`MAX_ENTRIES` each; emptied when full).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from matplotlib.backends import backend_agg
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg
from matplotlib.font_manager import fontManager, get_font
from matplotlib.ft2font import FT2Font, RenderMode

#: Entries per cache (layouts, glyph bitmaps): some tens of MB at most.
MAX_ENTRIES = 20_000

#: Whether this matplotlib draws text the way the cache replays it (3.11's glyph path).
SUPPORTED = (
    hasattr(RendererAgg, "_draw_text_glyphs_and_boxes")
    and hasattr(RendererAgg, "_prepare_font")
    and all(hasattr(FT2Font, name) for name in ("_layout", "_render_glyph", "_set_transform"))
    and hasattr(backend_agg, "get_hinting_flag")
)

_layouts: dict[tuple[Any, ...], tuple[tuple[Any, int, float, float], ...]] = {}
_glyphs: dict[tuple[Any, ...], tuple[np.ndarray, int, int]] = {}
_metrics: dict[tuple[Any, float], tuple[float | None, float | None, float | None]] = {}


def _remember(cache: dict[Any, Any], key: Any, value: Any) -> Any:
    if len(cache) >= MAX_ENTRIES:
        cache.clear()
    cache[key] = value
    return value


class TextCachingRenderer(RendererAgg):
    """Agg's renderer with cached text layouts, glyph bitmaps and line metrics.

    Plain text and mathtext (its rules as Agg draws them); TeX is drawn as by Agg.
    """

    def _get_font_height_metrics(self, prop: Any) -> tuple[float | None, ...]:
        """Return (ascent, descent, line gap) in pixels of the font of ``prop``.

        As ``matplotlib.text.Text`` computes them from the font's OS/2 or hhea table (the
        hook it asks a renderer first); (None, None, None) when the font has neither.
        """
        key = (prop, self.dpi)
        cached = _metrics.get(key)
        if cached is None:
            font = get_font(fontManager._find_fonts_by_props(prop))
            cached = (None, None, None)
            for table_name, gap, ascent, descent in (
                ("OS/2", "sTypoLineGap", "sTypoAscender", "sTypoDescender"),
                ("hhea", "lineGap", "ascent", "descent"),
            ):
                table: Any = font.get_sfnt_table(table_name)  # type: ignore[call-overload]
                head: Any = font.get_sfnt_table("head")
                if table is None or head is None:
                    continue
                scale = 1 / head["unitsPerEm"] * prop.get_size_in_points() * self.dpi / 72
                cached = (table[ascent] * scale, -table[descent] * scale, table[gap] * scale)
                break
            _remember(_metrics, (prop.copy(), self.dpi), cached)  # a copy: prop may change
        return cached

    def draw_text(
        self,
        gc: Any,
        x: float,
        y: float,
        s: str,
        prop: Any,
        angle: float,
        ismath: Any = False,
        mtext: Any = None,
    ) -> None:
        if ismath == "TeX":  # drawn as by Agg
            super().draw_text(gc, x, y, s, prop, angle, ismath, mtext)
        elif ismath:
            # mathtext: matplotlib's parser keeps the parse (the glyphs at their sizes, and
            # the rules); the glyphs come from the cache, the rules are drawn as Agg does
            parse = self.mathtext_parser.parse(s, self.dpi, prop, antialiased=gc.get_antialiased())
            glyphs = [(font, size, glyph, dx, dy) for font, size, _, glyph, dx, dy in parse.glyphs]
            self._draw_glyphs(gc, x, y, angle, glyphs)
            if parse.rects:
                self._draw_text_glyphs_and_boxes(gc, x, y, angle, (), parse.rects)
        else:
            self._draw_glyphs(gc, x, y, angle, self._plain_glyphs(s, prop, mtext))

    def _plain_glyphs(
        self, s: str, prop: Any, mtext: Any
    ) -> list[tuple[Any, float, Any, float, float]]:
        """Return the glyphs of plain text ``s``: (font, size, glyph, x, y), laid out once."""
        flags = backend_agg.get_hinting_flag()
        features = mtext.get_fontfeatures() if mtext is not None else None
        language = mtext.get_language() if mtext is not None else None
        key = (
            s,
            prop,
            self.dpi,
            flags,
            None if features is None else tuple(features),
            None if language is None else str(language),
        )
        items = _layouts.get(key)
        if items is None:
            font = self._prepare_font(prop)
            items = _remember(
                _layouts,
                (s, prop.copy(), *key[2:]),
                tuple(
                    (item.ft_object, item.glyph_index, item.x, item.y)
                    for item in font._layout(s, flags=flags, features=features, language=language)
                ),
            )
        size = prop.get_size_in_points()
        return [(font, size, glyph, dx, dy) for font, glyph, dx, dy in items]

    def _draw_glyphs(
        self,
        gc: Any,
        x: float,
        y: float,
        angle: float,
        glyphs: list[tuple[Any, float, Any, float, float]],
    ) -> None:
        """Draw ``glyphs`` (font, size, glyph, x, y from the text's origin, y upwards).

        As ``RendererAgg._draw_text_glyphs_and_boxes`` does, each glyph's bitmap from the
        cache where it was rendered before at the same sub-pixel offset.
        """
        flags = backend_agg.get_hinting_flag()
        cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        matrix = (0x10000 * np.array([[cos, -sin], [sin, cos]])).round().astype(int)
        mode = RenderMode.NORMAL if gc.get_antialiased() else RenderMode.MONO
        height = self.height
        for font, size, glyph, dx, dy in glyphs:
            tx = round(0x40 * (x + dx * cos - dy * sin))
            ty = round(0x40 * (height - y + dx * sin + dy * cos))
            gkey = (font, size, self.dpi, glyph, angle, flags, mode, tx & 63, ty & 63)
            cached = _glyphs.get(gkey)
            if cached is None:  # rendered at the sub-pixel offset only, moved by whole pixels
                font.set_size(size, self.dpi)
                font._set_transform(matrix, [tx & 63, ty & 63])
                bitmap = font._render_glyph(glyph, flags, mode)
                buffer = np.array(bitmap.buffer)
                if mode is RenderMode.MONO:
                    buffer *= 0xFF
                cached = _remember(_glyphs, gkey, (buffer, bitmap.left, bitmap.top))
            buffer, left, top = cached
            self._renderer.draw_text_image(
                buffer, left + (tx >> 6), int(height) - top - (ty >> 6) + buffer.shape[0], 0, gc
            )


class TextCachingCanvas(FigureCanvasAgg):
    """:class:`~matplotlib.backends.backend_agg.FigureCanvasAgg` whose renderer caches text.

    The renderer is a :class:`TextCachingRenderer`, where this matplotlib allows
    (:data:`SUPPORTED`).
    """

    def get_renderer(self) -> RendererAgg:
        renderer = super().get_renderer()
        if SUPPORTED and type(renderer) is RendererAgg:
            renderer.__class__ = TextCachingRenderer
        return renderer
