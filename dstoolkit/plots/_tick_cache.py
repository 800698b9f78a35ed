"""Tick locators and formatters that remember: a kept figure's axes redraw faster.

While a figure is drawn, matplotlib asks each axis's locator for its ticks several times
(for the ticks, for the minor ticks that must not fall on them, for the label's place) and
formats their labels again, and an explorer draws its figure again on every change of a
control, mostly with the same view on some of its axes. :func:`remember_ticks` makes the
default locators of a figure's axes (``MaxNLocator`` and its subclasses such as
``AutoLocator``, and ``LogLocator``) return their last ticks again while nothing they depend
on has changed: the view interval, the axes' size in pixels, the tick labels' size and, on a
log axis, the smallest positive datum. Their ``ScalarFormatter`` returns its last labels
again for the same ticks and view. Other locators and formatters are left as they are.

While an axis draws itself, matplotlib works out its ticks three times (to draw them, to
place the axis label beside their labels, and for the spine's extent) and its tick labels'
boxes twice; nothing changes them in between, so the axis remembers them for the rest of
that draw.
"""

from __future__ import annotations

from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.axis import Axis, XAxis, YAxis
from matplotlib.figure import Figure
from matplotlib.ticker import Formatter, Locator, LogLocator, MaxNLocator, ScalarFormatter

#: The locators whose ticks depend on nothing but what :func:`_locator_state` reads.
_REMEMBERED_LOCATORS = (MaxNLocator, LogLocator)

#: For each locator or formatter class, its subclass that remembers (made on first use).
_subclasses: dict[type, type] = {}


def _locator_state(locator: Locator) -> tuple[Any, ...]:
    """Return what ``locator``'s ticks depend on: the key of its memory."""
    axis: Any = locator.axis
    name = axis.axis_name
    rc: Any = mpl.rcParams
    size = axis._major_tick_kw.get("labelsize", rc[f"{name}tick.labelsize"])
    return (
        tuple(axis.get_view_interval()),
        axis.axes.bbox.bounds,
        size,
        axis.get_minpos() if isinstance(locator, LogLocator) else None,
    )


def _remembering_locator(cls: Any) -> type:
    """Return the subclass of locator class ``cls`` whose call remembers its last ticks."""
    parent_call = cls.__call__

    def __call__(self: Any) -> Any:
        key = _locator_state(self)
        memory = self.__dict__.get("_last_ticks")
        if memory is None or memory[0] != key:
            memory = self._last_ticks = (key, np.asarray(parent_call(self)))
        return memory[1].copy()  # a copy: the caller may change it

    return type(cls.__name__, (cls,), {"__call__": __call__, "__doc__": cls.__doc__})


def _remembering_formatter(cls: Any) -> type:
    """Return the subclass of ``ScalarFormatter`` class ``cls`` that remembers its labels.

    ``format_ticks`` sets the formatter's offset and order of magnitude from the ticks and
    the view, then formats: for the ticks and view of its last call, those are as that call
    left them, and its labels are returned again.
    """
    parent_format = cls.format_ticks

    def format_ticks(self: Any, values: Any) -> list[str]:
        axis = self.axis
        view = None if axis is None else tuple(axis.get_view_interval())
        key = (tuple(np.asarray(values, dtype=float).ravel()), view)
        memory = self.__dict__.get("_last_labels")
        if memory is None or memory[0] != key:
            memory = self._last_labels = (key, list(parent_format(self, values)))
        return list(memory[1])

    return type(cls.__name__, (cls,), {"format_ticks": format_ticks, "__doc__": cls.__doc__})


def _remembering_axis(cls: Any) -> type:
    """Return the subclass of axis class ``cls`` that computes its ticks once per draw.

    Within one ``draw`` of the axis, ``_update_ticks`` (called by the draw, by the label's
    placement and by the spine's extent) returns the ticks of its first call, and
    ``_get_ticklabel_bboxes`` the boxes of its first call for those ticks: the draw
    changes neither in between. Outside a draw both compute as matplotlib does.
    """
    parent_draw, parent_ticks, parent_boxes = (
        cls.draw,
        cls._update_ticks,
        cls._get_ticklabel_bboxes,
    )

    def draw(self: Any, renderer: Any) -> None:
        self._drawing = {}
        try:
            parent_draw(self, renderer)
        finally:
            self._drawing = None

    # as matplotlib's own draw: it rasterizes when asked (matplotlib wraps a draw without
    # this mark in one that stops rasterizing)
    draw._supports_rasterization = True  # type: ignore[attr-defined]

    def _update_ticks(self: Any) -> list[Any]:
        drawing = self.__dict__.get("_drawing")
        if drawing is None:
            return parent_ticks(self)
        if "ticks" not in drawing:
            drawing["ticks"] = parent_ticks(self)
        return list(drawing["ticks"])

    def _get_ticklabel_bboxes(self: Any, ticks: list[Any], renderer: Any) -> Any:
        drawing = self.__dict__.get("_drawing")
        if drawing is None or ticks != drawing.get("ticks"):
            return parent_boxes(self, ticks, renderer)
        if "boxes" not in drawing:
            drawing["boxes"] = parent_boxes(self, ticks, renderer)
        first, second = drawing["boxes"]
        return list(first), list(second)

    return type(
        cls.__name__,
        (cls,),
        {
            "draw": draw,
            "_update_ticks": _update_ticks,
            "_get_ticklabel_bboxes": _get_ticklabel_bboxes,
            "__doc__": cls.__doc__,
        },
    )


def _remember(obj: Locator | Formatter | Axis | None) -> None:
    """Make ``obj`` an instance of its remembering subclass, if it has one, in place."""
    cls = type(obj)
    if obj is None or cls in _subclasses.values():
        return
    make: Any
    if isinstance(obj, _REMEMBERED_LOCATORS):
        make = _remembering_locator
    elif isinstance(obj, ScalarFormatter):
        make = _remembering_formatter
    elif isinstance(obj, XAxis | YAxis):
        make = _remembering_axis
    else:
        return
    sub = _subclasses.get(cls)
    if sub is None:
        sub = _subclasses[cls] = make(cls)
        sub.__module__ = cls.__module__
    obj.__class__ = sub


def remember_ticks(figure: Figure) -> None:
    """Make the axes, tick locators and formatters of ``figure`` remember what they computed.

    A locator of ``MaxNLocator`` (or a subclass) or ``LogLocator``, a ``ScalarFormatter``
    and an ``XAxis`` or ``YAxis`` become instances of their remembering subclasses, in
    place: ``isinstance`` tests still hold, and the ticks and labels are the same, computed
    again only when what they depend on changed (the axis's view, size or tick labels' size,
    or, on a log axis, the smallest positive datum; for labels, the ticks and the view; an
    axis's ticks, at each of its draws). Calling it again is harmless; a locator or
    formatter set later is made to remember at the next call.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure whose axes, and their major and minor locators and formatters, are made
        to remember.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> from dstoolkit.plots.artists import remember_ticks
    >>> fig = Figure()
    >>> ax = fig.subplots()
    >>> _ = ax.set_xlim(0.0, 10.0)
    >>> remember_ticks(fig)
    >>> ax.xaxis.get_major_locator()().tolist()
    [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
    """
    for ax in figure.axes:
        for axis in ax._axis_map.values():
            _remember(axis)
            for level in (axis.major, axis.minor):
                _remember(level.locator)
                _remember(level.formatter)
