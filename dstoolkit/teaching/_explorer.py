"""Interactive explorers (ipywidgets) built from dstoolkit, for the book and the notebooks.

Every explorer is a function that returns an :class:`Explorer`, a ``VBox`` holding its
controls, a readout of the numbers that matter and an ``Output`` with the figure. One
definition serves two modes:

* **in a kernel** (a notebook, JupyterLab): every control is live; a change re-renders the
  figure and the readout.
* **on the static site** (the book executed by ``scripts/build-book.sh``, which sets the
  environment variable ``DSTOOLKIT_STATIC_SITE=1``; or ``Explorer(..., static=True)``): the
  explorer's *live* controls (one or two, declared with ``live=``) are replaced by sliders
  over precomputed positions. Every combination of positions is rendered at build time into
  a readout and a PNG, held in an ipywidgets ``Stack`` whose ``selected_index`` is
  ``jslink``-ed to the slider's ``index``; the browser switches between them with no
  kernel. Two live controls give a ``Stack`` of ``Stack``s. The other controls are shown
  disabled, with a line saying that they work when the chapter runs as a notebook. On the
  published site ``scripts/site_postbuild.py`` writes this widget state as plain HTML with
  native controls, and ``book/_static/explorers.js`` switches the states.

Adding an explorer is a matter of a ``render(**values)`` function that returns a figure and
a dict of numbers, a dict of controls, and the positions of its live controls::

    def my_explorer() -> Explorer:
        def render(level: float) -> tuple[Figure, dict[str, Any]]:
            fig = plot_something(level)
            return fig, {"estimate": 1.23}

        level = slider("level L (m)", 5.0, 1.0, 10.0, 0.1)
        return Explorer({"level": level}, render, live={"level": positions(level, 9)})

An explorer with more than one row of controls (buttons, notes between them) passes
``rows=``; a render may return several figures (one picture each); a subclass may write its
own readout (:meth:`Explorer.readout_for`) and text alternatives
(:meth:`Explorer.figure_alts`), or redraw only when asked (``redraws_on_change = False``,
a button calling :meth:`Explorer.refresh`): the lab's measuring station
(:class:`~dstoolkit.teaching.LabWidget`) is such an explorer.

In a kernel a change never makes the explorer lag: the control's callback only notes the
latest values and wakes one worker thread, which computes them (values set while it
computes replace each other: the latest wins, the ones in between are dropped). Until the
figure follows the controls again the status line says "Computing…" and the stale figure
is dimmed (:data:`STALE_CLASS`). :meth:`Explorer.wait` joins the pending work, and reading
``numbers``, ``figure``, ``figures`` or ``picture`` waits for it; outside a kernel (a script,
the tests, the static site's precomputation) a change is computed at once, before the
assignment returns. Sliders made by :func:`slider` follow the drag
(``continuous_update=True``). A ``render`` that raises an
:class:`~dstoolkit.errors.EvidenceError` (or any ``ValueError``) shows the message in the
readout instead of a figure: the learner sees *why* a setting is invalid.

Speed: a redraw keeps the axes where the first figure's layout engine put them (the layout
is computed once per figure shape, not on every change) and encodes the PNG with fast
compression as 256 colours (:data:`FIGURE_DPI`, :func:`encode_png`). A render may keep its
figure and update its artists in place; the artists it marks as animated are then blitted
onto the rest of the last picture while nothing else changed (:meth:`Explorer.png`).
"""

from __future__ import annotations

import base64
import html
import io
import itertools
import os
import re
import threading
import weakref
from collections.abc import Callable, Mapping, Sequence
from typing import Any, cast

import ipywidgets as widgets
import matplotlib.pyplot as plt
import numpy as np
import traitlets
from matplotlib.artist import Artist
from matplotlib.axis import Axis as MplAxis
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure

from dstoolkit.errors import (
    DstoolkitError,
    InvalidInputError,
)

Render = Callable[..., tuple[Figure | Sequence[Figure] | None, Mapping[str, Any]]]
#: What a state's figure shows, in words, from its numbers (its text alternative).
Describe = Callable[[Mapping[str, Any]], str]

#: The environment variable scripts/build-book.sh sets to "1": explorers built while the book
#: is executed for the static site precompute the states of their live controls.
STATIC_SITE_ENV = "DSTOOLKIT_STATIC_SITE"
#: The page of the book that says how to run the chapters as notebooks (book/run.md), as
#: linked from an explorer on a chapter page (both live in book/).
RUN_PAGE = "run.html"
#: Resolution of the explorers' figures (the notebook's inline backend uses 100 dpi too).
FIGURE_DPI = 100
#: The CSS class of an explorer's output while its figure is out of date (being recomputed).
STALE_CLASS = "dstoolkit-stale"
#: The status line while the explorer computes the controls' latest values.
WORKING = "Computing…"
#: A value no control holds: every control is said in an explorer's first sentence.
_UNSAID = object()
#: Seconds an explorer's worker thread waits for a change before it ends.
WORKER_IDLE_S = 60.0
#: How a notebook shows a stale figure (the explorer carries this style with it).
_STALE_STYLE = (
    f"<style>.{STALE_CLASS}{{opacity:0.4;filter:grayscale(1);transition:opacity 0.05s}}</style>"
)


def in_kernel() -> bool:
    """Whether this runs in a Jupyter kernel (a front end shows the widgets).

    Returns
    -------
    bool
        True inside an IPython kernel (a notebook, JupyterLab, nbclient); False in a script,
        a plain interpreter or the tests' own process.

    Examples
    --------
    >>> in_kernel()
    False
    """
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with ipywidgets
        return False
    shell = get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None


def static_site() -> bool:
    """Whether the book is being executed for the static site.

    Returns
    -------
    bool
        True while scripts/build-book.sh executes the book (it sets the environment
        variable ``DSTOOLKIT_STATIC_SITE=1``, :data:`STATIC_SITE_ENV`); False in a notebook.

    See Also
    --------
    Explorer : Builds its static-site form when this is True.

    Examples
    --------
    >>> import os
    >>> static_site() == (os.environ.get(STATIC_SITE_ENV) == "1")
    True
    """
    return os.environ.get(STATIC_SITE_ENV, "") == "1"


class StepSlider(widgets.FloatSlider):
    """A float slider whose value is always one of its steps.

    A value typed into its readout (or set from Python) moves the slider to the nearest
    step within its range, and the explorer draws that value; a value that is no number
    (NaN) is refused (a ``TraitError``) and the slider keeps its value, so the readout
    reverts. The slider's handle, its readout and the figure always show the same value.

    Examples
    --------
    >>> s = StepSlider(value=4.6, min=1.0, max=10.6, step=0.1)
    >>> s.value = 4.63
    >>> s.value
    4.6
    >>> s.value = 50.0
    >>> s.value
    10.6
    """

    # An ordinary override of FloatSlider's validator of ``value`` (same name), so it is
    # the one validator of the trait; it caps to the range as FloatSlider's does, then snaps.
    @traitlets.validate("value")
    def _validate_value(self, proposal: Any) -> float:
        value = float(proposal["value"])
        if not np.isfinite(value):
            raise traitlets.TraitError(
                f"{self.description or 'the slider'}: {proposal['value']!r} is not a value "
                f"between {self.min} and {self.max}; type a number"
            )
        lo, hi = float(self.min), float(self.max)
        steps = round((min(max(value, lo), hi) - lo) / self.step)
        return round(min(hi, lo + steps * self.step), 10)


def slider(
    description: str,
    value: float,
    lo: float,
    hi: float,
    step: float,
    *,
    readout_format: str = ".3f",
) -> StepSlider:
    """Return a float slider that follows the drag (``continuous_update=True``).

    Parameters
    ----------
    description : str
        The label, with the unit ("level L (m)").
    value : float
        The start value.
    lo, hi : float
        The range.
    step : float
        The step between values.
    readout_format : str, optional
        How the value is printed beside the slider (a format spec, default ".3f").

    Returns
    -------
    StepSlider
        320 px wide, its label in full; a typed value snaps to the nearest step.

    See Also
    --------
    positions : The values it takes on the static site.

    Examples
    --------
    >>> s = slider("level L (m)", 9.6, 1.0, 10.6, 0.1, readout_format=".1f")
    >>> s.value, s.continuous_update
    (9.6, True)
    """
    return StepSlider(
        value=value,
        min=lo,
        max=hi,
        step=step,
        description=description,
        continuous_update=True,
        readout_format=readout_format,
        style={"description_width": "initial"},
        layout=widgets.Layout(width="320px"),
    )


def int_slider(description: str, value: int, lo: int, hi: int) -> widgets.IntSlider:
    """Return an integer slider that follows the drag.

    Parameters
    ----------
    description : str
        The label.
    value : int
        The start value.
    lo, hi : int
        The range.

    Returns
    -------
    ipywidgets.IntSlider
        Step 1, ``continuous_update=True``.

    Examples
    --------
    >>> int_slider("cuts p", 3, 1, 12).max
    12
    """
    return widgets.IntSlider(
        value=value,
        min=lo,
        max=hi,
        step=1,
        description=description,
        continuous_update=True,
        style={"description_width": "initial"},
        layout=widgets.Layout(width="320px"),
    )


def positions(
    control: widgets.ValueWidget, count: int = 9, lo: float | None = None, hi: float | None = None
) -> tuple[Any, ...]:
    """Return the positions a live control takes on the static site.

    Parameters
    ----------
    control : ipywidgets.ValueWidget
        A slider (float or integer) or a ``Dropdown``.
    count : int, optional
        How many evenly spaced values (default 9).
    lo, hi : float, optional
        Their range; default the slider's own.

    Returns
    -------
    tuple
        ``count`` evenly spaced values of the slider on its step, with its current value
        among them (sorted, duplicates dropped); all the options of a ``Dropdown``.

    See Also
    --------
    Explorer : Takes them as ``live=``.

    Examples
    --------
    >>> positions(slider("s", 0.37, 0.0, 1.0, 0.01), 5)
    (0.0, 0.25, 0.37, 0.5, 0.75, 1.0)
    """
    if isinstance(control, widgets.Dropdown):
        return tuple(control._options_values)
    lo = control.min if lo is None else lo
    hi = control.max if hi is None else hi
    step = control.step
    grid = np.round(np.linspace(lo, hi, count) / step) * step
    values = {round(float(v), 10) for v in grid} | {round(float(control.value), 10)}
    if isinstance(control, widgets.IntSlider):
        return tuple(sorted({int(round(v)) for v in values}))
    return tuple(sorted(values))


def _format(value: Any) -> str:
    if isinstance(value, float | np.floating):
        return f"{float(value):.4f}"
    return html.escape(str(value))


def readout_html(numbers: Mapping[str, Any]) -> str:
    """Return the numbers as a one-row HTML table (floats to 4 decimals)."""
    head = "".join(f"<th style='padding:0 8px'>{html.escape(k)}</th>" for k in numbers)
    body = "".join(f"<td style='padding:0 8px'>{_format(v)}</td>" for v in numbers.values())
    return f"<table><tr>{head}</tr><tr>{body}</tr></table>"


def warning_html(message: str, note: str = "") -> str:
    """Return a readout that says why a setting is invalid (and ``note``, in italics)."""
    return f"<p style='color:#b00020'>⚠ {html.escape(message)}<i>{html.escape(note)}</i></p>"


def _sticks_out(fig: Figure) -> bool:
    """Tell whether anything drawn on ``fig`` reaches its edges.

    Something reaching an edge (a tick label pushed out by a fixed layout, cut off by the edge)
    is a pixel of the outermost ring of the drawn canvas that is not the figure's background.
    Layout engines keep a margin of a few pixels, so that ring is blank in a figure laid out by
    them. Reading the drawn pixels costs a fraction of a millisecond, where ``fig.get_tightbbox``
    lays out every text again.
    """
    rgba = np.asarray(_agg(fig).buffer_rgba())
    background = np.round(np.asarray(to_rgba(fig.get_facecolor())) * 255).astype(np.uint8)
    ring = np.concatenate([rgba[0], rgba[-1], rgba[:, 0], rgba[:, -1]])
    return bool((ring != background).any())


def _animated_artists(artist: Artist) -> list[Artist]:
    """Return the animated artists in ``artist`` and below it, ``artist`` first if animated.

    An axis (``XAxis``, ``YAxis``) counts as one artist: its ticks are not searched (there
    are hundreds of them, and the explorers animate an axis whole, if at all).
    """
    found = [artist] if artist.get_animated() else []
    if not isinstance(artist, MplAxis):
        for child in artist.get_children():
            found += _animated_artists(child)
    return found


def _agg(fig: Figure) -> FigureCanvasAgg:
    """Return ``fig``'s Agg canvas (one once :meth:`Explorer.png` drew it)."""
    return cast(FigureCanvasAgg, fig.canvas)


def encode_png(rgba: np.ndarray, compress_level: int = 1) -> bytes:
    """Return an RGBA image (a drawn canvas) as a PNG of 256 colours.

    A third to a quarter of the bytes of full colour, no visible difference on a plot, and a palette
    image compresses fast. ``compress_level`` 1 (the kernel: fast) to 9 (the static site: small).
    """
    from PIL import Image as PILImage

    image = (
        PILImage.fromarray(rgba).convert("RGB").quantize(256, method=PILImage.Quantize.FASTOCTREE)
    )
    buffer = io.BytesIO()
    image.save(buffer, format="png", compress_level=compress_level)
    return buffer.getvalue()


def png_output(png: bytes) -> dict[str, Any]:
    """Return a PNG as an ``Output`` widget's display_data output (what the site embeds)."""
    return {
        "output_type": "display_data",
        "metadata": {},
        "data": {"image/png": base64.b64encode(png).decode("ascii"), "text/plain": "<Figure>"},
    }


class Explorer(widgets.VBox):
    r"""Controls, a readout of numbers and a figure that follows the controls.

    Parameters
    ----------
    controls : Mapping[str, ipywidgets.ValueWidget]
        Named controls; their values are passed to ``render`` as keyword arguments.
    render : Callable[..., tuple[Figure | Sequence[Figure] | None, Mapping[str, Any]]]
        ``render(**values) -> (figures, numbers)``: a figure, several figures or None,
        and the numbers of the readout. Every figure is shown as a PNG in the output area
        and closed. An :class:`~dstoolkit.errors.DstoolkitError` or ``ValueError`` it
        raises is shown as a warning in the readout.
    title : str, optional
        A bold line above the controls.
    live : Mapping[str, Sequence], optional
        The controls that answer on the static site (one or two), each with its positions
        (:func:`positions`); every combination is rendered when the site is built.
    static : bool, optional
        Build the static-site form; default: :func:`static_site` (the environment).
    rows : Sequence[ipywidgets.Widget | Sequence[ipywidgets.Widget]], optional
        The explorer's body between the title and the readout: widgets, or rows of widgets
        (buttons and notes as well as controls). Default: one row of all the controls.
        On the static site the live controls in them become the site's sliders and every
        other control or button is disabled.
    draw : bool, optional
        In a kernel, render the controls' values at once (default); else the readout and
        the output stay empty until :meth:`refresh`.
    said : Sequence[str], optional
        The numbers (by name) that the sentence announcing a change of state says after
        the control's new value (:func:`change_sentence`), on the static site and in a
        kernel's status line; default the first two.
    describe : Callable[[Mapping[str, Any]], str], optional
        What a state's figure shows, in words (its trend, where the estimate lies against
        the truth), from the state's numbers: the picture's text alternative
        (``figure_alt``). Default: the numbers themselves.
    background : bool, optional
        Compute a change of a control in a worker thread, the latest values winning
        (:meth:`wait` joins it); default: whether this runs in a Jupyter kernel. Else a
        change is computed before the assignment returns.

    Attributes
    ----------
    controls : dict[str, ipywidgets.ValueWidget]
        The control widgets, by name. On the static site the live controls are
        ``SelectionSlider``s (or the original ``Dropdown``) and the others are disabled.
    readout : ipywidgets.HTML
        The readout of the numbers.
    status : ipywidgets.HTML
        Kernel only: "Computing…" (``WORKING``) from a change until the figure follows
        it; then the sentence that says the new state once, in a polite status element
        (``announce_html``: the controls that moved and the one or two results that
        changed); the error after a render that failed.
    computed : int
        How many renders ran (the first one and the precomputed states included).
    output : ipywidgets.Output
        The figures, as PNG outputs (kernel only: the static site shows its precomputed
        states instead, and this widget is closed empty).
    figure : Figure or None
        The last (first) figure drawn (closed; ``figure.savefig`` still works).
    figures : list[Figure]
        Every figure of the last render.
    picture : bytes or None
        The PNG of ``figure`` as shown (also the explorer's still picture in print).
    numbers : dict[str, Any]
        The last numbers shown; ``{"error": message}`` after an invalid setting.
    states : dict[tuple, dict[str, Any]]
        Static site only: the numbers of every precomputed state, keyed by the live
        controls' values (in the order of ``live``).

    See Also
    --------
    slider, positions : Controls and the positions a live control takes on the site.
    static_site : Whether the static site is being built.

    Examples
    --------
    >>> import ipywidgets as widgets
    >>> from matplotlib.figure import Figure
    >>> def render(level):
    ...     fig = Figure(figsize=(3, 2))
    ...     fig.add_subplot().plot([0, 1], [0, level])
    ...     return fig, {"level (m)": level}
    >>> level = slider("level L (m)", 2.0, 1.0, 3.0, 0.5)
    >>> ex = Explorer({"level": level}, render, static=False)
    >>> ex.numbers
    {'level (m)': 2.0}
    >>> level.value = 3.0
    >>> ex.numbers, ex.picture[:4]
    ({'level (m)': 3.0}, b'\x89PNG')
    >>> site = Explorer({"level": slider("level L (m)", 2.0, 1.0, 3.0, 0.5)}, render,
    ...                 live={"level": positions(level, 3, 1.0, 3.0)}, static=True)
    >>> sorted(site.states)
    [(1.0,), (2.0,), (3.0,)]
    """

    #: In a kernel, whether the figure of the last valid setting stays shown (with a note
    #: in the warning) when a setting is invalid; else the output is emptied.
    keeps_last_figure: bool = True
    #: Whether a change of a control redraws (else only ``refresh()`` does).
    redraws_on_change: bool = True

    def __init__(
        self,
        controls: Mapping[str, widgets.ValueWidget],
        render: Render,
        *,
        title: str = "",
        live: Mapping[str, Sequence[Any]] | None = None,
        static: bool | None = None,
        rows: Sequence[widgets.Widget | Sequence[widgets.Widget]] | None = None,
        draw: bool = True,
        said: Sequence[str] | None = None,
        describe: Describe | None = None,
        background: bool | None = None,
    ) -> None:
        super().__init__()
        self.controls = dict(controls)
        self._render = render
        self._said = None if said is None else tuple(said)
        self._describe = describe
        # one refresh at a time: a render and the picture it draws belong together, also
        # when two threads move the controls (a re-entrant lock: a render may move one)
        self._lock = threading.RLock()
        self.live = {name: tuple(values) for name, values in (live or {}).items()}
        unknown = set(self.live) - set(self.controls)
        if unknown or len(self.live) > 2:
            raise InvalidInputError(
                f"live controls must be one or two of {list(self.controls)}, got {list(self.live)}"
            )
        self.static = static_site() if static is None else static
        self._figure: Figure | None = None
        self._figures: list[Figure] = []
        self._picture: bytes | None = None
        self._numbers: dict[str, Any] = {}
        self.states: dict[tuple[Any, ...], dict[str, Any]] = {}
        self.readout = widgets.HTML()
        self.output = widgets.Output()
        self.status = widgets.HTML(layout=widgets.Layout(min_height="1.5em"))
        self.status.add_class("dstoolkit-status")
        self.computed = 0
        # the worker: one slot for the latest values not yet computed (None: nothing
        # pending), the thread, whether it computes, the last error it met
        self.background = (in_kernel() if background is None else background) and not self.static
        self._pending: dict[str, Any] | None = None
        self._working = False
        self._worker: threading.Thread | None = None
        self._failure: BaseException | None = None
        self._wake = threading.Condition()
        self._holder: int | None = None  # the thread inside refresh() (it never waits)
        self._announced: dict[str, Any] = {}  # the values the status line last said
        self._layouts: dict[tuple[Any, ...], list[Any]] = {}
        self._engines: weakref.WeakKeyDictionary[Figure, Any] = weakref.WeakKeyDictionary()
        self._kept: Figure | None = None  # the figure whose background is kept for blitting
        self._background: Any = None
        self._animated: list[Any] = []
        self._head = [widgets.HTML(f"<b>{html.escape(title)}</b>")] if title else []
        self._rows = (
            None
            if rows is None
            else [row if isinstance(row, widgets.Widget) else self._row(row) for row in rows]
        )
        if self.static:
            self._build_static()
        else:
            if self.redraws_on_change:
                for control in self.controls.values():
                    control.observe(self._on_change, "value")
            body = self._rows or [self._row(self.controls.values())]
            tail = [widgets.HTML(_STALE_STYLE), self.status] if self.background else []
            self.children = (*self._head, *body, self.readout, *tail, self.output)
            if draw:
                self.refresh()
            self._announced = self.values()  # a change says only the controls that moved

    @staticmethod
    def _row(children: Any) -> widgets.HBox:
        return widgets.HBox(list(children), layout=widgets.Layout(flex_flow="row wrap"))

    def values(self) -> dict[str, Any]:
        """Return the controls' current values, by name.

        Returns
        -------
        dict[str, Any]
            Each control's ``value``, keyed as in ``controls``.
        """
        return {name: control.value for name, control in self.controls.items()}

    # -- what the last render showed (reading waits for pending work) ----------------------

    @property
    def numbers(self) -> dict[str, Any]:
        """The last numbers shown; ``{"error": message}`` after an invalid setting."""
        self._join()
        return self._numbers

    @numbers.setter
    def numbers(self, value: dict[str, Any]) -> None:
        self._numbers = value

    @property
    def figure(self) -> Figure | None:
        """The last (first) figure drawn (closed; ``figure.savefig`` still works)."""
        self._join()
        return self._figure

    @figure.setter
    def figure(self, value: Figure | None) -> None:
        self._figure = value

    @property
    def figures(self) -> list[Figure]:
        """Every figure of the last render."""
        self._join()
        return self._figures

    @figures.setter
    def figures(self, value: list[Figure]) -> None:
        self._figures = value

    @property
    def picture(self) -> bytes | None:
        """The PNG of ``figure`` as shown (also the explorer's still picture in print)."""
        self._join()
        return self._picture

    @picture.setter
    def picture(self, value: bytes | None) -> None:
        self._picture = value

    # -- a change of a control ---------------------------------------------------------------

    def _on_change(self, _change: Any) -> None:
        if not self.background:
            self.refresh()
            return
        # only note the latest values and wake the worker: the front end's next message
        # (the drag goes on) is read at once, whatever the computation costs
        with self._wake:
            self._pending = self.values()
            if not self._working:
                self._working = True
                self.status.value = WORKING
                self.output.add_class(STALE_CLASS)
            if self._worker is None or not self._worker.is_alive():
                self._worker = threading.Thread(
                    target=self._work, name="dstoolkit-explorer", daemon=True
                )
                self._worker.start()
            self._wake.notify_all()

    def _work(self) -> None:
        """Compute the latest pending values until none are left, then wait (the worker).

        A worker left idle for ``WORKER_IDLE_S`` ends (the next change starts another): an
        explorer no longer shown holds no thread.
        """
        while True:
            with self._wake:
                if not self._wake.wait_for(lambda: self._pending is not None, WORKER_IDLE_S):
                    self._worker = None
                    return
                values, self._pending = self._pending, None
            if values is None:  # wait_for returned with a value pending: never None here
                continue
            failure: BaseException | None = None
            try:
                self.refresh(**values)
            except Exception as exc:  # a bug in a render: shown, and raised again by wait()
                failure = exc
                self.readout.value = warning_html(f"{type(exc).__name__}: {exc}")
            with self._wake:
                self._failure = failure or self._failure
                if self._pending is None:  # up to date: say so, undim the figure
                    self._working = False
                    self.status.value = (
                        self._sentence_html(values)
                        if failure is None
                        else html.escape(f"Failed: {type(failure).__name__}")
                    )
                    self.output.remove_class(STALE_CLASS)
                    self._wake.notify_all()

    def _sentence_html(self, values: Mapping[str, Any]) -> str:
        """Return the status line that says a computed state once (:func:`announce_html`).

        It names the controls whose values differ from the last state said (all of them the
        first time) and the explorer's ``said`` results.
        """
        moved = [name for name, v in values.items() if self._announced.get(name, _UNSAID) != v]
        self._announced = dict(values)
        settings = {
            self.controls[name].description: shown_value(self.controls[name], values[name])
            for name in moved
        }
        return announce_html(self.change_sentence(settings, self._numbers))

    def _join(self) -> None:
        """Wait for pending work, unless called by the worker itself (a render reading)."""
        inside = self._holder == threading.get_ident()
        if (
            self._worker is not None
            and not inside
            and threading.current_thread() is not self._worker
        ):
            self.wait()

    def wait(self, timeout: float | None = None) -> None:
        """Wait until the explorer shows the controls' latest values.

        Parameters
        ----------
        timeout : float, optional
            Seconds to wait at most; default: as long as the computation takes.

        Raises
        ------
        TimeoutError
            The work was still pending after ``timeout`` seconds.
        Exception
            The error a render raised in the worker since the last ``wait`` (other than
            the invalid settings the readout explains): the readout shows it too.
        """
        with self._wake:
            done = self._wake.wait_for(lambda: not self._working, timeout)
            failure, self._failure = self._failure, None
        if not done:
            raise TimeoutError(
                f"the explorer was still computing after {timeout} s: wait longer, or "
                "check that its render returns"
            )
        if failure is not None:
            raise failure

    def refresh(self, **overrides: Any) -> None:
        """Render the controls' values into the readout and the output.

        A new PNG per figure, or a warning after an invalid setting (any error of the
        package, a memory budget refused as well). Safe from several threads: one refresh
        runs at a time.

        Parameters
        ----------
        **overrides
            Values to render instead of some controls' (by control name); the controls
            themselves do not move.
        """
        with self._lock:
            outer, self._holder = self._holder, threading.get_ident()
            try:
                self.computed += 1
                self._refresh(overrides)
            finally:
                self._holder = outer

    def readout_for(self, numbers: Mapping[str, Any]) -> str:
        """Return the readout's HTML for the numbers of a valid render.

        Parameters
        ----------
        numbers : Mapping[str, Any]
            The numbers ``render`` returned.

        Returns
        -------
        str
            A one-row table (``readout_html``); an explorer may say more.
        """
        return readout_html(numbers)

    def figure_alts(self, settings: Mapping[str, str], numbers: Mapping[str, Any]) -> list[str]:
        """Return the text alternatives of a precomputed state's pictures, one per figure.

        Parameters
        ----------
        settings : Mapping[str, str]
            The live controls' labels and the values they show in this state.
        numbers : Mapping[str, Any]
            The state's numbers.

        Returns
        -------
        list[str]
            One ``figure_alt`` for every picture (the last one serves the rest): what the
            figure shows in words if the explorer has ``describe``, else its numbers.
        """
        words = None if self._describe is None or "error" in numbers else self._describe(numbers)
        return [figure_alt(settings, numbers, words=words)]

    def change_sentence(self, settings: Mapping[str, str], numbers: Mapping[str, Any]) -> str:
        """Return the sentence announcing a precomputed state (:func:`change_sentence`).

        Parameters
        ----------
        settings : Mapping[str, str]
            The live controls' labels and the values they show in this state.
        numbers : Mapping[str, Any]
            The state's numbers; the explorer's ``said`` ones are spoken.

        Returns
        -------
        str
            One short sentence.
        """
        said = self._said if self._said is not None else tuple(numbers)[:2]
        return change_sentence(settings, numbers, said)

    def _refresh(self, overrides: dict[str, Any]) -> None:
        try:
            drawn, numbers = self._render(**{**self.values(), **overrides})
        except (ValueError, DstoolkitError) as exc:  # say what is wrong, whatever the error
            self.numbers = {"error": str(exc)}
            # A precomputed state has no figure to fall back on; in a kernel the last one
            # stays (unless the explorer says otherwise), and the warning says which
            # setting it shows.
            keep = self.keeps_last_figure and not self.static
            kept = (
                " (the figure below shows the last valid setting)"
                if (keep and self.output.outputs)
                else ""
            )
            self.readout.value = warning_html(str(exc), kept)
            if not keep:
                self.output.outputs = ()
            return
        self.numbers = dict(numbers)
        self.readout.value = self.readout_for(self._numbers)
        figures = [] if drawn is None else [drawn] if isinstance(drawn, Figure) else list(drawn)
        if figures:
            self.figures = figures
            self.figure = figures[0]
            pictures = [self.png(fig) for fig in figures]
            self.picture = pictures[0]
            self.output.outputs = tuple(png_output(png) for png in pictures)
            for fig in figures:
                plt.close(fig)

    def png(self, fig: Figure) -> bytes:
        """``fig`` as PNG bytes, drawn as the explorer shows it.

        A render that keeps its figure (returns the same ``Figure`` on every call, updated
        in place) may mark the artists that follow the controls as *animated*
        (``artist.set_animated(True)``): while nothing else of the figure changed (matplotlib
        marks the figure stale when a non-animated artist, a limit or a text changes), the
        picture of the rest is restored from the last draw and only those artists are drawn
        on it (blitting), in order of their zorder. Otherwise the whole figure is drawn
        and the animated artists on top. The figure is drawn on an Agg canvas.

        Parameters
        ----------
        fig : Figure
            The figure ``render`` returned.

        Returns
        -------
        bytes
            A PNG of 256 colours at ``FIGURE_DPI`` (``encode_png``): fast
            compression in a kernel, small on the static site.
        """
        if not isinstance(fig.canvas, FigureCanvasAgg):  # blitting needs Agg's buffer
            FigureCanvasAgg(fig)
        if fig.get_dpi() != FIGURE_DPI:  # set_dpi marks the figure stale, even unchanged
            fig.set_dpi(FIGURE_DPI)
        if fig is self._kept and not fig.stale:
            _agg(fig).restore_region(self._background)
            animated = self._animated
        else:
            self._draw(fig)
            # the animated artists are looked up at each whole draw (adding an artist makes
            # the figure stale)
            animated = sorted(_animated_artists(fig), key=lambda artist: artist.get_zorder())
            self._kept = fig if animated else None
            self._background = _agg(fig).copy_from_bbox(fig.bbox) if animated else None
            self._animated = animated
        for artist in animated:
            fig.draw_artist(artist)
        return encode_png(
            np.asarray(_agg(fig).buffer_rgba()), compress_level=6 if self.static else 1
        )

    def _draw(self, fig: Figure) -> None:
        """Draw all of ``fig`` but its animated artists.

        The first figure of a shape (size, number of axes) is laid out by its layout engine; later
        ones, and later draws of a kept figure, reuse those axes positions (no layout pass, and axes
        that stay put when a control moves), unless something (wider tick labels) would then stick
        out of the figure: that one is laid out afresh.
        """
        engine = self._engines.get(fig) or fig.get_layout_engine()
        key = (*np.round(fig.get_size_inches(), 3), len(fig.axes))
        layout = self._layouts.get(key) if engine is not None else None
        if layout is not None:
            self._engines[fig] = engine  # set_layout_engine("none") hides it from now on
            fig.set_layout_engine("none")
            for ax, box in zip(fig.axes, layout, strict=True):
                if ax.get_position().bounds != box.bounds:
                    ax.set_position(box)
        fig.canvas.draw()
        if layout is not None and _sticks_out(fig):
            fig.set_layout_engine(engine)
            for ax in fig.axes:  # set_position took them out of the layout
                ax.set_in_layout(True)
            fig.canvas.draw()
        elif layout is None and engine is not None:
            self._layouts[key] = [ax.get_position() for ax in fig.axes]
        fig.stale = False  # the check re-placed titles and ticks where the draw put them

    # -- the static site -------------------------------------------------------------------

    def _build_static(self) -> None:
        """Render every combination of the live controls' positions into a stack of states.

        The site's sliders switch the states (:func:`state_stack`) in the browser. The kernel's
        readout and output are left empty and closed: only the states carry pictures.
        """
        names = list(self.live)
        start = tuple(self.controls[name].value for name in names)
        leaves: dict[tuple[Any, ...], widgets.Widget] = {}
        combos = itertools.product(*(self.live[name] for name in names))
        # the start state last: the attributes then describe it, as in a kernel
        for combo in sorted(combos, key=lambda combo: combo == start):
            self.refresh(**dict(zip(names, combo, strict=True)))
            self.states[combo] = dict(self.numbers)
            settings = {
                self.controls[name].description: shown_value(self.controls[name], v)
                for name, v in zip(names, combo, strict=True)
            }
            leaves[combo] = state_leaf(
                self.readout,
                self.output,
                self.figure_alts(settings, self.numbers),
                said=self.change_sentence(settings, self.numbers),
            )
        fixed = [c for name, c in self.controls.items() if name not in self.live]
        stack, site = state_stack(self.controls, self.live, leaves)
        by_id = {id(self.controls[name]): site[name] for name in names}
        self.controls.update(site)
        body = (
            [self._row(site.values()), self._row(fixed)]
            if self._rows is None
            else [_site_form(row, by_id) for row in self._rows]
        )
        shown = {id(c) for c in site.values()}
        for widget in [*fixed, *_widgets_in(body)]:  # controls and buttons alike
            if id(widget) not in shown and hasattr(widget, "disabled"):
                widget.disabled = True
        # the page's script copies the shown state's sentence into this live region
        announce = widgets.HTML("")
        announce.add_class("dstoolkit-announce")
        self.children = (
            *self._head,
            *body,
            site_note(list(site.values()), bool(fixed)),
            stack,
            announce,
        )
        # the kernel's readout and output are not shown on the site: empty, and closed so
        # that the page's widget state holds no copy of a picture
        self.output.outputs = ()
        self.output.close()
        self.readout.close()


def _site_form(widget: widgets.Widget, site: Mapping[int, widgets.Widget]) -> widgets.Widget:
    """``widget`` with the live controls in it (keyed by ``id``) replaced by the site's."""
    if id(widget) in site:
        return site[id(widget)]
    if isinstance(widget, widgets.Box):
        widget.children = tuple(_site_form(child, site) for child in widget.children)
    return widget


def _widgets_in(body: Sequence[widgets.Widget]) -> list[widgets.Widget]:
    """Every widget in ``body``, boxes opened."""
    found: list[widgets.Widget] = []
    for widget in body:
        found.append(widget)
        if isinstance(widget, widgets.Box):
            found.extend(_widgets_in(widget.children))
    return found


def shown_value(control: widgets.ValueWidget, value: Any) -> str:
    """``value`` as ``control`` shows it: a dropdown's option label, a slider's readout."""
    if isinstance(control, widgets.Dropdown):
        for label, option in zip(control._options_labels, control._options_values, strict=True):
            if option == value:
                return str(label)
        return str(value)
    if isinstance(control, widgets.IntSlider):
        return format(int(value), "d")
    if isinstance(control, widgets.FloatSlider):
        return format(value, control.readout_format)
    return str(value)


def announce_html(sentence: str) -> str:
    """Return a kernel explorer's status line that says ``sentence`` to a screen reader.

    A polite, atomic status element (``role="status"``): ipywidgets has no public way to put
    ARIA attributes on a widget's own element, so the element is the HTML widget's content,
    written anew with each state.

    Parameters
    ----------
    sentence : str
        One short sentence (:func:`change_sentence`).

    Returns
    -------
    str
        The HTML of the status element, the sentence escaped.

    Examples
    --------
    >>> print(announce_html("Level L 5.1 m: estimate 5.091 m."))  # doctest: +NORMALIZE_WHITESPACE
    <span class="dstoolkit-announce" role="status" aria-live="polite"
    aria-atomic="true">Level L 5.1 m: estimate 5.091 m.</span>
    """
    return (
        '<span class="dstoolkit-announce" role="status" aria-live="polite" '
        f'aria-atomic="true">{html.escape(sentence)}</span>'
    )


def _plain(value: Any) -> str:
    if isinstance(value, float | np.floating):
        return f"{float(value):.4f}"
    return str(value)


_UNIT = re.compile(r"^(.*\S)\s\(([^()]+)\)$")
#: The most words an error message takes in a sentence announcing a state.
_ERROR_WORDS = 16


def spoken(name: str, value: Any) -> str:
    """Return a name and its value as said aloud, the unit after the value.

    Parameters
    ----------
    name : str
        A control's label or a number's name, its unit last in parentheses ("level L (m)").
    value : Any
        The value: a float is said to 4 significant digits, anything else as it prints.

    Returns
    -------
    str
        For example "level L 5.1 m".

    Examples
    --------
    >>> spoken("series-fit L (m)", 5.10123), spoken("resonances", 41), spoken("m({low})", "0.30")
    ('series-fit L 5.101 m', 'resonances 41', 'm({low}) 0.30')
    """
    text = f"{float(value):.4g}" if isinstance(value, float | np.floating) else str(value)
    unit = _UNIT.match(name)
    if unit is None or len(unit[2].split()) > 2:  # "(share of steps)" says what, not a unit
        return f"{name} {text}"
    return f"{unit[1]} {text} {unit[2]}"


def change_sentence(
    settings: Mapping[str, str], numbers: Mapping[str, Any], said: Sequence[str]
) -> str:
    """Return one short sentence saying a state: the controls' values, then what moved.

    Parameters
    ----------
    settings : Mapping[str, str]
        The live controls' labels and the values they show.
    numbers : Mapping[str, Any]
        The state's numbers (``{"error": message}`` for an invalid setting).
    said : Sequence[str]
        The names of the numbers to say (one or two).

    Returns
    -------
    str
        For example "Level L 5.1 m: series-fit L 5.101 m, resonances 41."; an invalid
        setting's message in at most 16 words.

    Examples
    --------
    >>> change_sentence({"level L (m)": "5.1"}, {"estimate (m)": 5.0912, "found": 41},
    ...                 ["estimate (m)", "found"])
    'Level L 5.1 m: estimate 5.091 m, found 41.'
    """
    head = ", ".join(spoken(label, shown) for label, shown in settings.items())
    if "error" in numbers:
        words = str(numbers["error"]).split()
        cut = " ".join(words[:_ERROR_WORDS]) + ("…" if len(words) > _ERROR_WORDS else "")
        body = f"not possible: {cut}"
    else:
        body = ", ".join(spoken(name, numbers[name]) for name in said if name in numbers)
    text = (f"{head}: {body}" if head else body).rstrip(".") + "."
    first = text.split(" ", 1)[0]
    # a word is capitalised, a symbol ("m({low})", "w upper", "x̂") is not
    return text[:1].upper() + text[1:] if len(first) > 1 and first.isalpha() else text


def figure_alt(
    settings: Mapping[str, str],
    numbers: Mapping[str, Any],
    what: str = "Figure",
    words: str | None = None,
) -> str:
    """Return the text alternative of a precomputed figure, made from its numbers.

    Parameters
    ----------
    settings
        The controls' labels and the values they show for this figure.
    numbers
        The numbers of the readout (floats to 4 decimals, as the readout shows them).
    what
        The first word(s): what the picture is.
    words
        What the figure shows, in words; default: its numbers.

    Returns
    -------
    str
        For example "Figure for level L (m) = 9.6: estimate (m) 9.6100, truth (m) 9.6000."
    """
    at = ", ".join(f"{label} = {value}" for label, value in settings.items())
    shown = (
        ", ".join(f"{name} {_plain(value)}" for name, value in numbers.items())
        if words is None
        else words.rstrip(".")
    )
    head = f"{what} for {at}" if at else what
    return f"{head}: {shown}." if shown else f"{head}."


def image_html(png: bytes, alt: str) -> str:
    """Return a PNG as an ``<img>`` with its text alternative, inlined as a data URL.

    The book's build moves the picture into a file beside the page, loaded when the state shows.
    """
    data = base64.b64encode(png).decode("ascii")
    return (
        f"<img class='dstoolkit-figure' src='data:image/png;base64,{data}' "
        f"alt='{html.escape(alt, quote=True)}' style='max-width:100%;height:auto'>"
    )


def state_leaf(
    readout: widgets.HTML,
    output: widgets.Output,
    alt: str | Sequence[str] = "Figure",
    said: str = "",
) -> widgets.VBox:
    """Return a copy of what a readout and an output show now: one precomputed state.

    The output's pictures become ``<img>`` elements with the text alternatives ``alt``
    (one for every picture, or one for all), in an ``HTML`` widget after the readout. The
    sentence ``said`` (:func:`change_sentence`) goes with the readout, hidden: the page's
    script announces it when the state is shown.
    """
    alts = [alt] if isinstance(alt, str) else list(alt)
    pictures = [
        base64.b64decode(o["data"]["image/png"])
        for o in output.outputs
        if "image/png" in o.get("data", {})
    ]
    images = "".join(image_html(png, alts[min(i, len(alts) - 1)]) for i, png in enumerate(pictures))
    hidden = f"<p class='dstoolkit-said' hidden>{html.escape(said)}</p>" if said else ""
    children: list[widgets.Widget] = [widgets.HTML(readout.value + hidden)]
    if images:
        children.append(widgets.HTML(images))
    return widgets.VBox(children)


def site_control(control: widgets.ValueWidget, options: Sequence[Any]) -> widgets.ValueWidget:
    """Return a control as it is live on the static site.

    A ``Dropdown`` itself (all its options precomputed), a slider as a ``SelectionSlider`` over
    ``options`` that follows the drag.
    """
    if isinstance(control, widgets.Dropdown):
        if tuple(control._options_values) != tuple(options):
            raise InvalidInputError(
                f"a live dropdown precomputes all its options "
                f"({control.description!r}): pass positions(dropdown)"
            )
        return control
    if control.value not in options:
        raise InvalidInputError(
            f"the positions of {control.description!r} must include its "
            f"value {control.value}: the page opens on it"
        )
    fmt = "d" if isinstance(control, widgets.IntSlider) else control.readout_format
    return widgets.SelectionSlider(
        options=[(format(v, fmt), v) for v in options],
        value=control.value,
        description=control.description,
        continuous_update=True,
        style={"description_width": control.style.description_width or "initial"},
        layout=widgets.Layout(width=control.layout.width or "320px"),
    )


def state_stack(
    controls: Mapping[str, widgets.ValueWidget],
    live: Mapping[str, Sequence[Any]],
    leaves: Mapping[tuple[Any, ...], widgets.Widget],
) -> tuple[widgets.Stack, dict[str, widgets.ValueWidget]]:
    """Put the precomputed states in a ``Stack`` linked to the live controls.

    The states ``leaves`` (keyed by the live controls' values, in the order of ``live``) go
    in a ``Stack`` whose ``selected_index`` is ``jslink``-ed to the first live
    control's ``index``; with two live controls, a ``Stack`` of ``Stack``s, every inner one
    linked to the second control. Returns the stack and the site's controls by name.
    """
    names = list(live)
    site = {name: site_control(controls[name], live[name]) for name in names}

    def stack(prefix: tuple[Any, ...], depth: int) -> widgets.Widget:
        if depth == len(names):
            return leaves[prefix]
        name = names[depth]
        options = tuple(live[name])
        box = widgets.Stack(
            [stack((*prefix, v), depth + 1) for v in options],
            selected_index=options.index(controls[name].value),
        )
        box.add_class("dstoolkit-states")  # announced on the site (book/_static/explorers.js)
        box.links = [widgets.jslink((site[name], "index"), (box, "selected_index"))]
        return box

    return stack((), 0), site


def site_note(live: Sequence[widgets.ValueWidget], some_disabled: bool) -> widgets.HTML:
    """Return the line under an explorer's controls on the static site.

    Which controls answer on this page, and where the others work.
    """
    names = " and ".join(html.escape(c.description) for c in live)
    rest = (
        "the other controls are disabled here and work when this chapter runs as a notebook"
        if some_disabled
        else "in a notebook every value is possible"
    )
    head = (
        f"On this page {names} {'answer' if len(live) > 1 else 'answers'}; {rest}"
        if live
        else "These controls work when this chapter runs as a notebook"
    )
    return widgets.HTML(
        f"<p class='dstoolkit-site-note' style='font-size:0.9em;margin:0'>"
        f"<i>{head}: see <a href='{RUN_PAGE}'>Run this book</a>.</i></p>"
    )
