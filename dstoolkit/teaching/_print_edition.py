"""The explorers in print: a still picture of their first figure.

A widget needs a browser and a kernel; the PDF edition of the book (LaTeX) can show
neither. Next to its widget view, an explorer displayed in IPython also carries an
``image/png`` of the figure it shows first. The web page and JupyterLab show the widget
(it ranks first); the LaTeX build, which cannot show a widget, takes the picture.
"""

from __future__ import annotations

import io
from typing import Any


def first_figure_png(widget: Any) -> bytes | None:
    """PNG of the figure an explorer shows.

    The one it shows (its ``picture`` attribute), else its ``figure`` saved at 96 dpi, or None.
    Reusing the shown picture leaves a kept figure untouched (saving at another resolution would
    make it draw itself whole on the next change).
    """
    picture = getattr(widget, "picture", None)
    if picture is not None:
        return bytes(picture)
    figure = getattr(widget, "figure", None)
    if figure is None:
        return None
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=96)
    return buffer.getvalue()


def register_print_figures(*widget_types: type) -> None:
    """Give ``widget_types`` an ``image/png`` representation in the running IPython shell.

    Nothing happens outside IPython.
    """
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with the teaching extra
        return
    shell = get_ipython()
    if shell is None:
        return
    png = shell.display_formatter.formatters["image/png"]
    for widget_type in widget_types:
        png.for_type(widget_type, first_figure_png)
