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
  disabled, with a line saying that they work when the chapter runs as a notebook.

Adding an explorer is a matter of a ``render(**values)`` function that returns a figure and
a dict of numbers, a dict of controls, and the positions of its live controls::

    def my_explorer() -> Explorer:
        def render(level: float) -> tuple[Figure, dict[str, Any]]:
            fig = plot_something(level)
            return fig, {"estimate": 1.23}

        level = slider("level L (m)", 5.0, 1.0, 10.0, 0.1)
        return Explorer({"level": level}, render, live={"level": positions(level, 9)})

Sliders made by :func:`slider` use ``continuous_update=False``: the figure is redrawn
when the mouse is released, so the page never stalls. A ``render`` that raises an
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
import functools
import html
import io
import itertools
import os
import threading
import weakref
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import ipywidgets as widgets
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Image
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure

from dstoolkit.errors import (
    AudioUnavailableError,
    DstoolkitError,
    EvidenceError,
    InvalidInputError,
    NotMonotoneError,
)
from dstoolkit.evidence import (
    ZADEH_FRAME,
    MassFunction,
    appendix_evidence,
    combine_dependent,
    conflict,
    default_theta,
    dempster,
    dependence,
    triangular_evidence,
    yager,
    zadeh_sources,
)
from dstoolkit.filters import BoundedNoise, enclosure_summary, random_walk
from dstoolkit.gauge import (
    PAPER_SWEEP,
    DetectionResult,
    RecordingConditions,
    TubeSetup,
    detect_resonances,
    direct_levels,
    fit_resonance_series,
    orders_eq43,
    spl_to_pa,
    synthesize_recording,
)
from dstoolkit.plots import (
    EnclosureFigure,
    FilterErrorsFigure,
    FilterStepFigure,
    plot_filter_errors,
)
from dstoolkit.plots.artists import (
    BelPlArtists,
    FocalIntervalArtists,
    KeptFigure,
    MassArtists,
    PboxArtists,
    PossibilityArtists,
    TextCachingCanvas,
    animate,
    draw_bel_pl,
    draw_focal_intervals,
    draw_masses,
    draw_pbox,
    draw_possibility,
    gauge_detection_figure,
    pbox_grid,
    update_bel_pl,
    update_focal_intervals,
    update_gauge_detection,
    update_masses,
    update_pbox,
    update_possibility,
)
from dstoolkit.studies import ORDER_SOURCES, filter_case, gauge_case

from ._lab import (
    VIRTUAL,
    LabSettings,
    device_options,
    lab_measurement,
    lab_numbers,
    plot_method_levels,
)
from ._readouts import filter_summary, step_numbers

Render = Callable[..., tuple[Figure | None, Mapping[str, Any]]]

#: The environment variable scripts/build-book.sh sets to "1": explorers built while the book
#: is executed for the static site precompute the states of their live controls.
STATIC_SITE_ENV = "DSTOOLKIT_STATIC_SITE"
#: The page of the book that says how to run the chapters as notebooks (book/run.md), as
#: linked from an explorer on a chapter page (both live in book/).
RUN_PAGE = "run.html"
#: Resolution of the explorers' figures (the notebook's inline backend uses 100 dpi too).
FIGURE_DPI = 100


def static_site() -> bool:
    """True while scripts/build-book.sh executes the book for the static site
    (``DSTOOLKIT_STATIC_SITE=1``), False in a notebook."""
    return os.environ.get(STATIC_SITE_ENV, "") == "1"


def slider(
    description: str,
    value: float,
    lo: float,
    hi: float,
    step: float,
    *,
    readout_format: str = ".3f",
) -> widgets.FloatSlider:
    """A float slider that redraws on release (``continuous_update=False``)."""
    return widgets.FloatSlider(
        value=value, min=lo, max=hi, step=step, description=description,
        continuous_update=False, readout_format=readout_format,
        style={"description_width": "initial"}, layout=widgets.Layout(width="320px"),
    )


def int_slider(description: str, value: int, lo: int, hi: int) -> widgets.IntSlider:
    """An integer slider that redraws on release."""
    return widgets.IntSlider(
        value=value, min=lo, max=hi, step=1, description=description,
        continuous_update=False, style={"description_width": "initial"},
        layout=widgets.Layout(width="320px"),
    )


def positions(control: widgets.ValueWidget, count: int = 9, lo: float | None = None,
              hi: float | None = None) -> tuple[Any, ...]:
    """``count`` evenly spaced values of a slider between ``lo`` and ``hi`` (its own range by
    default), on its step, with its current value among them: the positions a live control
    takes on the static site. A ``Dropdown`` gives all its options."""
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
    """The numbers as a one-row HTML table (floats to 4 decimals)."""
    head = "".join(f"<th style='padding:0 8px'>{html.escape(k)}</th>" for k in numbers)
    body = "".join(f"<td style='padding:0 8px'>{_format(v)}</td>" for v in numbers.values())
    return f"<table><tr>{head}</tr><tr>{body}</tr></table>"


def warning_html(message: str, note: str = "") -> str:
    """A readout that says why a setting is invalid (and ``note``, in italics)."""
    return (f"<p style='color:#b00020'>⚠ {html.escape(message)}"
            f"<i>{html.escape(note)}</i></p>")


def _sticks_out(fig: Figure) -> bool:
    """Whether anything drawn on ``fig`` reaches its edges (a tick label pushed out by a
    fixed layout, cut off by the edge): a pixel of the outermost ring of the drawn canvas
    that is not the figure's background. Layout engines keep a margin of a few pixels, so
    that ring is blank in a figure laid out by them. Reading the drawn pixels costs a
    fraction of a millisecond, where ``fig.get_tightbbox`` lays out every text again."""
    rgba = np.asarray(fig.canvas.buffer_rgba())
    background = np.round(np.asarray(to_rgba(fig.get_facecolor())) * 255).astype(np.uint8)
    ring = np.concatenate([rgba[0], rgba[-1], rgba[:, 0], rgba[:, -1]])
    return bool((ring != background).any())


def encode_png(rgba: np.ndarray, compress_level: int = 1) -> bytes:
    """An RGBA image (a drawn canvas) as a PNG of 256 colours: a third to a quarter of the
    bytes of full colour, no visible difference on a plot, and a palette image compresses
    fast. ``compress_level`` 1 (the kernel: fast) to 9 (the static site: small)."""
    from PIL import Image as PILImage

    image = PILImage.fromarray(rgba).convert("RGB").quantize(
        256, method=PILImage.Quantize.FASTOCTREE)
    buffer = io.BytesIO()
    image.save(buffer, format="png", compress_level=compress_level)
    return buffer.getvalue()


def png_output(png: bytes) -> dict[str, Any]:
    """A PNG as an ``Output`` widget's display_data output (what the site embeds)."""
    return {"output_type": "display_data", "metadata": {},
            "data": {"image/png": base64.b64encode(png).decode("ascii"),
                     "text/plain": "<Figure>"}}


class Explorer(widgets.VBox):
    """Controls, a readout of numbers and a figure that follows the controls.

    Parameters
    ----------
    controls
        Named controls; their values are passed to ``render`` as keyword arguments.
    render
        ``render(**values) -> (figure or None, numbers)``. The figure is shown as a PNG in
        the output area and closed; the numbers fill the readout.
    title
        Optional bold line above the controls.
    live
        The controls that answer on the static site (one or two), each with its positions
        (:func:`positions`); every combination is rendered when the site is built.
    static
        Build the static-site form; default: :func:`static_site` (the environment).

    Attributes
    ----------
    controls
        The control widgets, by name.
    readout
        The ``HTML`` readout of the numbers.
    output
        The figure's ``Output``. On the static site the live controls are
        ``SelectionSlider``s (or the original ``Dropdown``) and the others are disabled.
    figure
        The last figure drawn (closed; ``figure.savefig`` still works).
    picture
        The PNG of that figure as shown (also the explorer's still picture in print).
    numbers
        The last numbers shown; ``{"error": message}`` after an invalid setting.
    states
        Static site only: the numbers of every precomputed state, keyed by the live
        controls' values (in the order of ``live``).
    """

    def __init__(
        self, controls: Mapping[str, widgets.ValueWidget], render: Render, *, title: str = "",
        live: Mapping[str, Sequence[Any]] | None = None, static: bool | None = None,
    ) -> None:
        super().__init__()
        self.controls = dict(controls)
        self._render = render
        # one refresh at a time: a render and the picture it draws belong together, also
        # when two threads move the controls (a re-entrant lock: a render may move one)
        self._lock = threading.RLock()
        self.live = {name: tuple(values) for name, values in (live or {}).items()}
        unknown = set(self.live) - set(self.controls)
        if unknown or len(self.live) > 2:
            raise InvalidInputError(f"live controls must be one or two of "
                                    f"{list(self.controls)}, got {list(self.live)}")
        self.static = static_site() if static is None else static
        self.figure: Figure | None = None
        self.picture: bytes | None = None
        self.numbers: dict[str, Any] = {}
        self.states: dict[tuple[Any, ...], dict[str, Any]] = {}
        self.readout = widgets.HTML()
        self.output = widgets.Output()
        self._layouts: dict[tuple[Any, ...], list[Any]] = {}
        self._engines: weakref.WeakKeyDictionary[Figure, Any] = weakref.WeakKeyDictionary()
        self._kept: Figure | None = None  # the figure whose background is kept for blitting
        self._background: Any = None
        self._animated: list[Any] = []
        self._head = [widgets.HTML(f"<b>{html.escape(title)}</b>")] if title else []
        if self.static:
            self._build_static()
        else:
            for control in self.controls.values():
                control.observe(self._on_change, "value")
            self.children = (*self._head, self._row(self.controls.values()), self.readout,
                             self.output)
            self.refresh()

    @staticmethod
    def _row(children: Any) -> widgets.HBox:
        return widgets.HBox(list(children), layout=widgets.Layout(flex_flow="row wrap"))

    def values(self) -> dict[str, Any]:
        """The controls' current values, by name."""
        return {name: control.value for name, control in self.controls.items()}

    def _on_change(self, _change: Any) -> None:
        self.refresh()

    def refresh(self, **overrides: Any) -> None:
        """Render the controls' values (``overrides`` replacing some) into the readout and
        the output: a new PNG, or a warning and no figure after an invalid setting (any
        error of the package, a memory budget refused as well). Safe from several
        threads: one refresh runs at a time."""
        with self._lock:
            self._refresh(overrides)

    def _refresh(self, overrides: dict[str, Any]) -> None:
        try:
            fig, numbers = self._render(**{**self.values(), **overrides})
        except (ValueError, DstoolkitError) as exc:  # say what is wrong, whatever the error
            self.numbers = {"error": str(exc)}
            # A precomputed state has no figure to fall back on; in a kernel the last one
            # stays, and the warning says which setting it shows.
            kept = "" if self.static or not self.output.outputs else (
                " (the figure below shows the last valid setting)")
            self.readout.value = warning_html(str(exc), kept)
            if self.static:
                self.output.outputs = ()
            return
        self.numbers = dict(numbers)
        self.readout.value = readout_html(self.numbers)
        if fig is not None:
            self.figure = fig
            self.picture = self.png(fig)
            self.output.outputs = (png_output(self.picture),)
            plt.close(fig)

    def png(self, fig: Figure) -> bytes:
        """``fig`` as PNG bytes.

        A render that keeps its figure (returns the same ``Figure`` on every call, updated
        in place) may mark the artists that follow the controls as *animated*
        (``artist.set_animated(True)``): while nothing else of the figure changed (matplotlib
        marks the figure stale when a non-animated artist, a limit or a text changes), the
        picture of the rest is restored from the last draw and only those artists are drawn
        on it (blitting), in order of their zorder. Otherwise the whole figure is drawn
        and the animated artists on top. The figure is drawn on a
        ``TextCachingCanvas``, which draws text it drew before from a cache (the same pixels).
        """
        if not isinstance(fig.canvas, TextCachingCanvas):  # it caches the text it drew
            TextCachingCanvas(fig)
        if fig.get_dpi() != FIGURE_DPI:  # set_dpi marks the figure stale, even unchanged
            fig.set_dpi(FIGURE_DPI)
        if fig is self._kept and not fig.stale:
            fig.canvas.restore_region(self._background)
            animated = self._animated
        else:
            self._draw(fig)
            # the animated artists are looked up at each whole draw (adding an artist makes
            # the figure stale)
            animated = sorted(fig.findobj(lambda artist: artist.get_animated()),
                              key=lambda artist: artist.get_zorder())
            self._kept = fig if animated else None
            self._background = fig.canvas.copy_from_bbox(fig.bbox) if animated else None
            self._animated = animated
        for artist in animated:
            fig.draw_artist(artist)
        return encode_png(np.asarray(fig.canvas.buffer_rgba()),
                          compress_level=6 if self.static else 1)

    def _draw(self, fig: Figure) -> None:
        """Draw all of ``fig`` but its animated artists. The first figure of a shape (size,
        number of axes) is laid out by its layout engine; later ones, and later draws of a
        kept figure, reuse those axes positions (no layout pass, and axes that stay put when
        a control moves), unless something (wider tick labels) would then stick out of the
        figure: that one is laid out afresh."""
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
        """Render every combination of the live controls' positions into a stack of states
        (:func:`state_stack`) that the site's sliders switch in the browser."""
        names = list(self.live)
        start = tuple(self.controls[name].value for name in names)
        leaves: dict[tuple[Any, ...], widgets.Widget] = {}
        combos = itertools.product(*(self.live[name] for name in names))
        # the start state last: the attributes then describe it, as in a kernel
        for combo in sorted(combos, key=lambda combo: combo == start):
            self.refresh(**dict(zip(names, combo, strict=True)))
            self.states[combo] = dict(self.numbers)
            settings = {self.controls[name].description: shown_value(self.controls[name], v)
                        for name, v in zip(names, combo, strict=True)}
            leaves[combo] = state_leaf(self.readout, self.output,
                                       figure_alt(settings, self.numbers))
        fixed = [c for name, c in self.controls.items() if name not in self.live]
        for control in fixed:
            control.disabled = True
        stack, site = state_stack(self.controls, self.live, leaves)
        self.controls.update(site)
        self.children = (*self._head, self._row(site.values()), self._row(fixed),
                         site_note(list(site.values()), bool(fixed)), stack)


def shown_value(control: widgets.ValueWidget, value: Any) -> str:
    """``value`` as ``control`` shows it: a dropdown's option label, a slider's readout."""
    if isinstance(control, widgets.Dropdown):
        for label, option in zip(control._options_labels, control._options_values,
                                 strict=True):
            if option == value:
                return str(label)
        return str(value)
    if isinstance(control, widgets.IntSlider):
        return format(int(value), "d")
    if isinstance(control, widgets.FloatSlider):
        return format(value, control.readout_format)
    return str(value)


def _plain(value: Any) -> str:
    if isinstance(value, float | np.floating):
        return f"{float(value):.4f}"
    return str(value)


def figure_alt(settings: Mapping[str, str], numbers: Mapping[str, Any],
               what: str = "Figure") -> str:
    """The text alternative of a precomputed figure, made from its numbers.

    Parameters
    ----------
    settings
        The controls' labels and the values they show for this figure.
    numbers
        The numbers of the readout (floats to 4 decimals, as the readout shows them).
    what
        The first word(s): what the picture is.

    Returns
    -------
    str
        For example "Figure for level L (m) = 9.6: estimate (m) 9.6100, truth (m) 9.6000."
    """
    at = ", ".join(f"{label} = {value}" for label, value in settings.items())
    shown = ", ".join(f"{name} {_plain(value)}" for name, value in numbers.items())
    head = f"{what} for {at}" if at else what
    return f"{head}: {shown}." if shown else f"{head}."


def image_html(png: bytes, alt: str) -> str:
    """A PNG as an ``<img>`` with its text alternative, the picture inlined as a data URL
    (the book's build moves it into a file beside the page, loaded when the state shows)."""
    data = base64.b64encode(png).decode("ascii")
    return (f"<img class='dstoolkit-figure' src='data:image/png;base64,{data}' "
            f"alt='{html.escape(alt, quote=True)}' style='max-width:100%;height:auto'>")


def state_leaf(readout: widgets.HTML, output: widgets.Output,
               alt: str | Sequence[str] = "Figure") -> widgets.VBox:
    """A copy of what a readout and an output show now: one precomputed state.

    The output's pictures become ``<img>`` elements with the text alternatives ``alt``
    (one for every picture, or one for all), in an ``HTML`` widget after the readout.
    """
    alts = [alt] if isinstance(alt, str) else list(alt)
    pictures = [base64.b64decode(o["data"]["image/png"]) for o in output.outputs
                if "image/png" in o.get("data", {})]
    images = "".join(image_html(png, alts[min(i, len(alts) - 1)])
                     for i, png in enumerate(pictures))
    children: list[widgets.Widget] = [widgets.HTML(readout.value)]
    if images:
        children.append(widgets.HTML(images))
    return widgets.VBox(children)


def site_control(control: widgets.ValueWidget, options: Sequence[Any]) -> widgets.ValueWidget:
    """A control as it is live on the static site: a ``Dropdown`` itself (all its options
    precomputed), a slider as a ``SelectionSlider`` over ``options`` that follows the drag."""
    if isinstance(control, widgets.Dropdown):
        if tuple(control._options_values) != tuple(options):
            raise InvalidInputError(f"a live dropdown precomputes all its options "
                                    f"({control.description!r}): pass positions(dropdown)")
        return control
    if control.value not in options:
        raise InvalidInputError(f"the positions of {control.description!r} must include its "
                                f"value {control.value}: the page opens on it")
    fmt = "d" if isinstance(control, widgets.IntSlider) else control.readout_format
    return widgets.SelectionSlider(
        options=[(format(v, fmt), v) for v in options], value=control.value,
        description=control.description, continuous_update=True,
        style={"description_width": control.style.description_width or "initial"},
        layout=widgets.Layout(width=control.layout.width or "320px"))


def state_stack(controls: Mapping[str, widgets.ValueWidget], live: Mapping[str, Sequence[Any]],
                leaves: Mapping[tuple[Any, ...], widgets.Widget],
                ) -> tuple[widgets.Stack, dict[str, widgets.ValueWidget]]:
    """The precomputed states ``leaves`` (keyed by the live controls' values, in the order
    of ``live``) in a ``Stack`` whose ``selected_index`` is ``jslink``-ed to the first live
    control's ``index``; with two live controls, a ``Stack`` of ``Stack``s, every inner one
    linked to the second control. Returns the stack and the site's controls by name."""
    names = list(live)
    site = {name: site_control(controls[name], live[name]) for name in names}

    def stack(prefix: tuple[Any, ...], depth: int) -> widgets.Widget:
        if depth == len(names):
            return leaves[prefix]
        name = names[depth]
        options = tuple(live[name])
        box = widgets.Stack([stack((*prefix, v), depth + 1) for v in options],
                            selected_index=options.index(controls[name].value))
        box.add_class("dstoolkit-states")  # a live region in the book (explorers-a11y.js)
        box.links = [widgets.jslink((site[name], "index"), (box, "selected_index"))]
        return box

    return stack((), 0), site


def site_note(live: Sequence[widgets.ValueWidget], some_disabled: bool) -> widgets.HTML:
    """The line under an explorer's controls on the static site: which controls answer on
    this page, and where the others work."""
    names = " and ".join(html.escape(c.description) for c in live)
    rest = ("the other controls are disabled here and work when this chapter runs as a "
            "notebook" if some_disabled else "in a notebook every value is possible")
    head = (f"On this page {names} {'answer' if len(live) > 1 else 'answers'}; {rest}"
            if live else "These controls work when this chapter runs as a notebook")
    return widgets.HTML(f"<p class='dstoolkit-site-note' style='font-size:0.9em;margin:0'>"
                        f"<i>{head}: see <a href='{RUN_PAGE}'>Run this book</a>.</i></p>")


# -- mass functions on a finite frame ----------------------------------------------------

LEVEL_FRAME = ("low", "mid", "high")


def mass_function_explorer(low: float = 0.4, mid: float = 0.0, high: float = 0.1,
                           low_mid: float = 0.3) -> Explorer:
    """Masses on {low}, {mid}, {high} and {low, mid} (the sliders start at the values
    given); the rest goes to Θ (ignorance).

    Shows Bel and Pl of every subset of Θ = {low, mid, high} and BetP of the singletons
    (paper Def. 2; Bel/Pl/BetP as in the chapter on mass functions). Moving mass from Θ
    to a singleton closes the gap between Bel and Pl.
    """
    controls = {
        "low": slider("m({low})", low, 0.0, 1.0, 0.05, readout_format=".2f"),
        "mid": slider("m({mid})", mid, 0.0, 1.0, 0.05, readout_format=".2f"),
        "high": slider("m({high})", high, 0.0, 1.0, 0.05, readout_format=".2f"),
        "low_mid": slider("m({low, mid})", low_mid, 0.0, 1.0, 0.05, readout_format=".2f"),
    }

    @functools.cache
    def drawn() -> tuple[Figure, MassArtists, BelPlArtists]:
        """The figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(9.5, 3.0), layout="constrained")
        ax1, ax2 = fig.subplots(1, 2, width_ratios=[1, 2.2])
        return (fig, draw_masses(ax1, title="masses", animated=True),
                draw_bel_pl(ax2, LEVEL_FRAME, title="belief, plausibility, pignistic",
                            animated=True))

    def render(low: float, mid: float, high: float, low_mid: float):
        given = {"low": low, "mid": mid, "high": high, ("low", "mid"): low_mid}
        rest = 1.0 - sum(given.values())
        if rest < -1e-9:
            raise EvidenceError(
                f"the masses add up to {1 - rest:.2f} > 1; lower a slider (what is left "
                "goes to Θ)"
            )
        mf = MassFunction({**given, LEVEL_FRAME: max(rest, 0.0)}, LEVEL_FRAME)
        fig, masses, bel_pl = drawn()
        update_masses(masses, mf)
        update_bel_pl(bel_pl, mf)
        betp = mf.pignistic()
        return fig, {"m(Θ)": max(rest, 0.0), **{f"BetP({h})": betp[h] for h in LEVEL_FRAME},
                     "Pl({low}) − Bel({low})": mf.plausibility("low") - mf.belief("low")}

    # On the site: m({low}) up to what the other start values leave, m({high}) in four
    # steps (a total over 1 shows the warning, as in a kernel).
    live = {"low": positions(controls["low"], 8, 0.0, 0.7),
            "high": positions(controls["high"], 4, 0.0, 0.3)}
    return Explorer(controls, render, title="A mass function on Θ = {low, mid, high}",
                    live=live)


# -- conflict: Zadeh's example -------------------------------------------------------------


def conflict_explorer(x: float = 0.99, y: float = 0.99, epsilon: float = 0.0,
                      rule: str = "Dempster") -> Explorer:
    """Zadeh's example (paper eq. 1 and its famous failure): two nearly certain doctors
    who disagree, combined by Dempster's rule or Yager's, after an optional discount ε
    (the controls start at the values given)."""
    controls = {
        "x": slider("doctor 1: m(meningitis)", x, 0.0, 1.0, 0.01, readout_format=".2f"),
        "y": slider("doctor 2: m(concussion)", y, 0.0, 1.0, 0.01, readout_format=".2f"),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
        "rule": widgets.Dropdown(options=["Dempster", "Yager"], value=rule,
                                 description="rule"),
    }

    @functools.cache
    def drawn() -> tuple[Figure, list[MassArtists]]:
        """The figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(10, 2.8), layout="constrained")
        axes = fig.subplots(1, 3, sharey=True)
        panels = [draw_masses(ax, title=name, animated=True) for ax, name in
                  zip(axes, ("doctor 1", "doctor 2", "combined"), strict=True)]
        animate(axes[2].title, spines_of=axes[2])  # the rule's name
        return fig, panels

    def render(x: float, y: float, epsilon: float, rule: str):
        m1, m2 = zadeh_sources(x, y, epsilon)
        k = conflict(m1, m2)
        combined = dempster(m1, m2) if rule == "Dempster" else yager(m1, m2)
        fig, panels = drawn()
        update_masses(panels[0], m1)
        update_masses(panels[1], m2)
        update_masses(panels[2], combined, title=f"{rule}'s rule")
        return fig, {"conflict K": k, **{f"m({h})": combined.mass_of(h) for h in ZADEH_FRAME},
                     "m(Θ)": combined.mass_of(ZADEH_FRAME)}

    live = {"epsilon": positions(controls["epsilon"], 11), "rule": positions(controls["rule"])}
    return Explorer(controls, render, title="Zadeh's two doctors", live=live)


# -- dependent evidence: the paper's Appendix A -----------------------------------------------


def dependent_combination_explorer(a2: float = 0.6, a3: float = 0.1, b2: float = 0.3,
                                   b3: float = 0.6, mass_rule: str = "min") -> Explorer:
    """Vary the masses of E1 and E2 of Appendix A (the controls start at the values given;
    the defaults are the paper's): energies, degree of dependence D, dependency
    coefficients R12, R21 (eqs. A1–A6) and the combined evidence (A7–A8 then Dempster),
    beside plain Dempster that treats them as independent."""
    controls = {
        "a2": slider("m1([0.30, 1.90])", a2, 0.0, 1.0, 0.05, readout_format=".2f"),
        "a3": slider("m1([0.32, 1.93])", a3, 0.0, 1.0, 0.05, readout_format=".2f"),
        "b2": slider("m2([0.41, 1.61])", b2, 0.0, 1.0, 0.05, readout_format=".2f"),
        "b3": slider("m2([0.30, 1.90])", b3, 0.0, 1.0, 0.05, readout_format=".2f"),
        "mass_rule": widgets.Dropdown(options=["min", "m1", "m2"], value=mass_rule,
                                      description="m(D) rule"),
    }
    names = ("E1", "E2", "dependent combination (A7–A8, then eq. 1)",
             "Dempster as if independent")

    @functools.cache
    def drawn() -> tuple[Figure, list[tuple[FocalIntervalArtists, Any]]]:
        """The figure, made by the first render and updated by the others: per panel, the
        bars and the red line at the pignistic expectation."""
        fig = Figure(figsize=(10, 4.6), layout="constrained")
        axes = fig.subplots(2, 2, sharex=True)
        panels = [(draw_focal_intervals(ax, title=name, animated=True),
                   ax.axvline(0.0, color="#d62728", lw=1.2))
                  for ax, name in zip(axes.flat, names, strict=True)]
        for bars, line in panels:
            animate(line, spines_of=bars.ax)
        return fig, panels

    def render(a2: float, a3: float, b2: float, b3: float, mass_rule: str):
        e1, e2 = appendix_evidence((a2, a3), (b2, b3))
        dep = dependence(e1, e2, mass_rule=mass_rule)
        both = combine_dependent(e1, e2, mass_rule=mass_rule)
        naive = dempster(e1, e2)
        fig, panels = drawn()
        for (bars, line), ev in zip(panels, (e1, e2, both, naive), strict=True):
            update_focal_intervals(bars, ev, xlim=(-0.4, 3.6))
            line.set_xdata([ev.pignistic_expectation_1d()] * 2)
        return fig, {"En'(E1)": dep.energy1, "En'(E2)": dep.energy2,
                     "En'(E1,E2)": dep.joint_energy, "D": dep.degree, "R12": dep.r12,
                     "R21": dep.r21, "E[dependent]": both.pignistic_expectation_1d(),
                     "E[Dempster]": naive.pignistic_expectation_1d()}

    live = {"a2": positions(controls["a2"], 9, 0.0, 0.8)}
    return Explorer(controls, render, title="Dependent evidence: the paper's Appendix A",
                    live=live)


# -- from a bounded noise to evidence ----------------------------------------------------------


def noise_evidence_explorer(
    lower: float = -0.3, mode: float = 0.0, upper: float = 0.3, p: int = 3,
    epsilon: float = 0.05,
) -> Explorer:
    """Bounded noise → evidence (paper eqs. 22–26): support [lower, upper], mode, number of
    α-cuts p and discount ε give the focal elements and the p-box. The defaults are the
    paper's state noise (Table 1); the slider ranges follow the support given."""
    span = upper - lower if upper > lower else 1.0
    step = float(10.0 ** np.floor(np.log10(span / 200.0)))
    controls = {
        "lower": slider("lower a", lower, lower - span, upper, step),
        "mode": slider("mode c", mode, lower - span, upper + span, step),
        "upper": slider("upper b", upper, lower, upper + span, step),
        "p": int_slider("cuts p", p, 1, 12),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
    }
    view = (lower - 0.6 * span, upper + 0.6 * span)

    @functools.cache
    def drawn() -> tuple[Figure, PossibilityArtists, FocalIntervalArtists, PboxArtists]:
        """The figure, made by the first render and updated by the others."""
        fig = Figure(figsize=(12, 3.0), layout="constrained")
        ax1, ax2, ax3 = fig.subplots(1, 3)
        return (fig, draw_possibility(ax1, view, evidence=True, title="π and its α-cuts",
                                      animated=True),
                draw_focal_intervals(ax2, title="focal elements", animated=True),
                draw_pbox(ax3, pbox_grid(*view), title="p-box", animated=True))

    def render(lower: float, mode: float, upper: float, p: int, epsilon: float):
        ev = triangular_evidence(lower, mode, upper, p=p, epsilon=epsilon)
        fig, possibility, bars, pbox = drawn()
        update_possibility(possibility, lower, mode, upper, p, evidence=ev)
        update_focal_intervals(bars, ev, xlim=view, label_masses=p <= 6)
        update_pbox(pbox, ev)
        t_lo, t_hi = default_theta(lower, mode, upper)
        return fig, {"mass per cut": (1.0 - epsilon) / p, "m(Θ)": epsilon,
                     "Θ": f"[{t_lo:.4g}, {t_hi:.4g}]",
                     "pignistic expectation": ev.pignistic_expectation_1d()}

    live = {"p": positions(controls["p"], 8, 1, 8),
            "epsilon": positions(controls["epsilon"], 2, 0.0, 0.5)}
    return Explorer(controls, render, title="From a bounded noise to evidence", live=live)


# -- why bounded noise: a bounded-error filter with wrong bounds --------------------------------






def bounded_error_explorer(v_half: float = 0.1, w_half: float = 1.0, steps: int = 60,
                           seed: int = 7) -> Explorer:
    """One simulated random walk (seeded) filtered by the bounded-error filter whose
    noise bounds are the true ones times a factor: too tight → empty boxes or boxes that
    miss the truth; too wide → wide boxes."""
    from dstoolkit.filters import BoundedErrorFilter

    x, z = random_walk(v_half, w_half).simulate([0.0], steps, np.random.default_rng(seed))
    filt = BoundedErrorFilter(on_inconsistent="reset")

    def build(res: Any, title: str) -> EnclosureFigure:
        figure = EnclosureFigure(res, x, z, title=title, pyplot=False)
        figure.ax.legend(fontsize=8, loc="upper left")
        return figure

    kept = KeptFigure(build, lambda figure, res, title: figure.update(res, x, z, title=title))

    def render(scale: float):
        res = filt.run(random_walk(v_half * scale, w_half * scale), z)
        return kept(res, f"bounds × {scale:g}").figure, enclosure_summary(res, x)

    scale = slider("assumed bounds × true", 1.0, 0.3, 3.0, 0.05)
    return Explorer({"scale": scale}, render, title="Bounded-error filter with wrong bounds",
                    live={"scale": positions(scale, 11, 0.5, 3.0)})


# -- random sets and the extension principle (book/random_sets.md) -------------------------------

#: Functions of one variable for :func:`extension_explorer`, vectorised on points (..., 1).
EXTENSION_FUNCTIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "x²": lambda x: x[..., 0] ** 2,
    "sin x": lambda x: np.sin(x[..., 0]),
    "x³ − 3x": lambda x: x[..., 0] ** 3 - 3.0 * x[..., 0],
    "exp(−x)": lambda x: np.exp(-x[..., 0]),
    "2x + 1": lambda x: 2.0 * x[..., 0] + 1.0,
}
IMAGE_METHOD_NAMES: tuple[str, ...] = ("vertex", "monotone", "subdivision")


def compare_image_methods(
    f: Callable[[np.ndarray], np.ndarray], lo: Any, hi: Any, signs: Any = 1
) -> dict[str, dict[str, Any]]:
    """The image of one box [lo, hi] through f by the vertex method (Prop. 1), the monotone
    shortcut with the declared ``signs`` (Prop. 2) and subdivision (the fallback).

    Returns, per method, ``image`` ((lo, hi) or None when the method refused), ``message``
    (the VertexMethodWarning or NotMonotoneError text, else "") and ``evaluations`` (how
    many points f was evaluated at, the checks included).
    """
    import warnings

    from dstoolkit.evidence import image

    lo_a, hi_a = np.atleast_1d(np.asarray(lo, float)), np.atleast_1d(np.asarray(hi, float))
    signs_a = np.broadcast_to(np.asarray(signs, dtype=int), lo_a.shape)
    out: dict[str, dict[str, Any]] = {}
    for method in IMAGE_METHOD_NAMES:
        count = [0]

        def counted(x: np.ndarray, count: list[int] = count) -> np.ndarray:
            count[0] += int(np.prod(np.shape(x)[:-1]))
            return f(x)

        entry: dict[str, Any] = {"image": None, "message": ""}
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                i_lo, i_hi = image((lo_a, hi_a), counted, method=method, monotone=signs_a)
                entry["image"] = (float(np.ravel(i_lo)[0]), float(np.ravel(i_hi)[0]))
            except NotMonotoneError as exc:
                entry["message"] = f"NotMonotoneError: {exc}"
        if caught and not entry["message"]:
            entry["message"] = f"{caught[0].category.__name__}: {caught[0].message}"
        entry["evaluations"] = count[0]
        out[method] = entry
    return out


def _extension_extent(ax: Any, bars: Any) -> tuple[float, ...]:
    """What the autoscaled ranges of :func:`extension_explorer`'s figure follow: the data
    x extent of f's panel ``ax`` and the y extent of both panels (they share y)."""
    ys = [v for a in (ax, bars) for v in a.dataLim.intervaly if np.isfinite(v)]
    return (*ax.dataLim.intervalx, min(ys, default=np.nan), max(ys, default=np.nan))


def extension_explorer(function: str = "sin x", lo: float = 0.0, hi: float = 3.0,
                       sign: int = 1) -> Explorer:
    """The image of an interval [lo, hi] through a function of one variable by the vertex
    method (Prop. 1, eq. 17), the monotone shortcut with a declared sign (Prop. 2,
    eqs. 18–19) and subdivision: which ones are right, which warn, which refuse."""
    controls = {
        "function": widgets.Dropdown(options=list(EXTENSION_FUNCTIONS), value=function,
                                     description="f(x)"),
        "lo": slider("box lower end", lo, -4.0, 4.0, 0.1, readout_format=".1f"),
        "hi": slider("box upper end", hi, -4.0, 4.0, 0.1, readout_format=".1f"),
        "sign": widgets.Dropdown(options=[("increasing (+1)", 1), ("decreasing (−1)", -1)],
                                 value=sign, description="declared",
                                 style={"description_width": "initial"}),
    }
    colours = {"vertex": "#ff7f0e", "monotone": "#9467bd", "subdivision": "#2ca02c"}
    x = np.linspace(-4.0, 4.0, 801)

    @functools.cache
    def drawn() -> dict[str, Any]:
        """The figure, made by the first render and updated by the others: f, f on the
        box and the box; per method its image as a bar and a band across f, a ⚠ (shown
        when it warns) and the word "refused" (shown when it refuses)."""
        # fixed margins, not a layout engine: the y tick labels change with the function
        # ("−0.75" is wider than "0.0"), and a layout made for the first ones cut the others
        fig = Figure(figsize=(9.5, 3.4), layout="none")  # not the style's engine either
        fig.subplots_adjust(left=0.075, right=0.99, bottom=0.15, top=0.9, wspace=0.06)
        ax, bars = fig.subplots(1, 2, sharey=True, width_ratios=[3, 1.3])
        (curve,) = ax.plot(x, x, color="black", lw=1.2)
        (on_box,) = ax.plot(x, x, color="#1f77b4", lw=3, label="f on the box")
        box = ax.axvspan(0.0, 1.0, color="#1f77b4", alpha=0.12)
        ax.set_xlabel("x")
        methods = {}
        for i, method in enumerate(IMAGE_METHOD_NAMES):
            methods[method] = {
                "refused": bars.text(i, 0.5, "refused:\nNot-\nMonotone-\nError", ha="center",
                                     va="center", fontsize=8, color="#b00020",
                                     transform=bars.get_xaxis_transform()),
                "bar": bars.plot([i, i], [0.0, 1.0], lw=8, solid_capstyle="butt",
                                 color=colours[method])[0],
                "band": ax.axhspan(0.0, 1.0, color=colours[method], alpha=0.08),
                "warning": bars.text(i, 0.0, "⚠", ha="center", va="bottom", color="#b00020",
                                     fontsize=12),
            }
        bars.set_xticks(range(3), IMAGE_METHOD_NAMES, fontsize=8)
        bars.set_xlim(-0.6, 2.6)
        bars.set_title("image f([lo, hi])")
        ax.set_title(f"f(x) = {function} on [{lo:g}, {hi:g}]")  # its font; its text follows
        animate(curve, on_box, box, ax.title, *(m["band"] for m in methods.values()),
                spines_of=ax)
        animate(*(a for m in methods.values() for k, a in m.items() if k != "band"),
                spines_of=bars)
        return {"fig": fig, "ax": ax, "bars": bars, "curve": curve, "on_box": on_box,
                "box": box, "methods": methods}

    def render(function: str, lo: float, hi: float, sign: int):
        if lo > hi:
            raise EvidenceError(f"the box [{lo:g}, {hi:g}] has lo > hi: move the ends")
        f = EXTENSION_FUNCTIONS[function]
        result = compare_image_methods(f, lo, hi, sign)
        d = drawn()
        d["curve"].set_ydata(f(x[:, None]))
        inside = np.linspace(lo, hi, 201)
        d["on_box"].set_data(inside, f(inside[:, None]))
        d["box"].set_x(lo)
        d["box"].set_width(hi - lo)
        d["ax"].title.set_text(f"f(x) = {function} on [{lo:g}, {hi:g}]")
        numbers: dict[str, Any] = {}
        for method, shown in d["methods"].items():
            entry = result[method]
            refused = entry["image"] is None
            shown["refused"].set_visible(refused)
            for artist in ("bar", "band", "warning"):
                shown[artist].set_visible(not refused)
            if refused:
                numbers[method] = "NotMonotoneError"
                continue
            a, b = np.round(entry["image"], 10) + 0.0  # 1e-19 from the zoom shows as 0
            shown["bar"].set_ydata([a, b])
            shown["band"].set_y(a)
            shown["band"].set_height(b - a)
            warn = "warning" in entry["message"].lower()
            shown["warning"].set_visible(warn)
            shown["warning"].set_y(b)
            numbers[method] = f"[{a:.4g}, {b:.4g}]" + (" ⚠ too narrow?" if warn else "")
        # the ranges follow what is shown, as when drawn anew: autoscaled from the x extent
        # of f's panel and the y extent of both (setting them, even unchanged, would redraw
        # the whole figure)
        extent = _extension_extent(d["ax"], d["bars"])
        for ax in (d["ax"], d["bars"]):
            ax.relim(visible_only=True)
        if _extension_extent(d["ax"], d["bars"]) != extent:
            d["ax"].autoscale_view()
        numbers.update({f"{m} evaluations": result[m]["evaluations"]
                        for m in IMAGE_METHOD_NAMES})
        return d["fig"], numbers

    live = {"hi": positions(controls["hi"], 8, 0.5, 4.0),
            "function": positions(controls["function"])}
    return Explorer(controls, render, title="The image of an interval: three methods",
                    live=live)


# -- the recursive filter on the gauge (book/recursive_filter.md) ---------------------------------













def render_filter(
    v_lower: float, v_mode: float, v_upper: float, w_lower: float, w_mode: float,
    w_upper: float, p: int, epsilon: float, level: float, temperature: float, start: str,
    orders: str, mass_rule: str, seed: int = 0,
    kept: KeptFigure[FilterErrorsFigure] | None = None,
) -> tuple[Figure, dict[str, Any]]:
    """What :func:`filter_widget` recomputes on every change: the run's figure (estimates,
    hull and readings against the truth, absolute errors; the paper's Fig. 10) and the
    numbers of ``filter_summary``. With ``kept`` (a ``KeptFigure`` of
    a ``FilterErrorsFigure``, as the widget holds) the figure is drawn without pyplot on the
    first call and redrawn in place on later ones; else each call draws a new figure."""
    seq, n, result = filter_case(
        level, temperature, state_noise=(v_lower, v_mode, v_upper),
        obs_noise=(w_lower, w_mode, w_upper), p=p, epsilon=epsilon, start=start,
        mass_rule=mass_rule, orders=orders, seed=seed)
    run = (result, seq.truth, seq.readings)
    title = (f"L = {level:.1f} m, T = {temperature:.1f} °C (f_F = {seq.fundamental_hz:.2f} "
             f"Hz, {seq.truth.shape[0]} resonances), p = {p}, ε = {epsilon:.2f}, "
             f"start: {start}")
    fig = (plot_filter_errors(*run, title=title) if kept is None
           else kept(*run, title=title).figure)
    return fig, filter_summary(seq, n, result)


def filter_widget(level_m: float = 9.6, temperature_c: float = 23.9, *, p: int = 3,
                  epsilon: float = 0.05, start: str = "observation",
                  state_noise: tuple[float, float, float] = (-0.3, 0.0, 0.3),
                  obs_noise: tuple[float, float, float] = (-10.59, -6.9, -3.21),
                  seed: int = 0) -> Explorer:
    """The paper's filter on a simulated gauge (§3.2, eqs. 39–40), live.

    Controls (``widget.controls``): the noise bounds the filter assumes (lower, mode,
    upper of v and of w; the readings always carry the paper's w), the number of cuts p,
    the discount ε, the level and temperature, the start value, where the orders n_k come
    from and the m(D) rule. ``widget.output`` shows the figure of :func:`render_filter`,
    ``widget.numbers`` the estimates and errors. Sliders redraw on release
    (``continuous_update=False``); one redraw is a filter run of ~83 steps and a figure.
    """
    (v_lo, v_c, v_hi), (w_lo, w_c, w_hi) = state_noise, obs_noise
    controls = {
        "v_lower": slider("v lower", v_lo, -1.0, 0.0, 0.01, readout_format=".2f"),
        "v_mode": slider("v mode", v_c, -1.0, 1.0, 0.01, readout_format=".2f"),
        "v_upper": slider("v upper", v_hi, 0.0, 1.0, 0.01, readout_format=".2f"),
        "w_lower": slider("w lower", w_lo, -20.0, 0.0, 0.01, readout_format=".2f"),
        "w_mode": slider("w mode", w_c, -20.0, 5.0, 0.01, readout_format=".2f"),
        "w_upper": slider("w upper", w_hi, -10.0, 5.0, 0.01, readout_format=".2f"),
        "p": int_slider("cuts p", p, 1, 8),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
        "level": slider("level L (m)", level_m, 1.0, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider("temperature T (°C)", temperature_c, 0.0, 40.0, 0.1,
                              readout_format=".1f"),
        "start": widgets.Dropdown(options=[("z_1 (paper)", "observation"),
                                           ("z_1 + E[w]", "mean_corrected")], value=start,
                                  description="start"),
        "orders": widgets.Dropdown(options=list(ORDER_SOURCES.items()), value="true",
                                   description="orders"),
        "mass_rule": widgets.Dropdown(options=["min", "m1", "m2"], value="min",
                                      description="m(D) rule"),
    }

    kept = KeptFigure(functools.partial(FilterErrorsFigure, pyplot=False),
                      FilterErrorsFigure.update)

    def render(**values: Any) -> tuple[Figure, dict[str, Any]]:
        return render_filter(**values, seed=seed, kept=kept)

    live = {"level": positions(controls["level"], 9, 1.6, 9.6),
            "epsilon": positions(controls["epsilon"], 3, 0.0, 0.5)}
    return Explorer(controls, render, title="The dependent-evidence filter on a simulated gauge",
                    live=live)




def filter_step_explorer(level_m: float = 9.6, temperature_c: float = 23.9, step: int = 2,
                         start: str = "mean_corrected", epsilon: float = 0.05,
                         steps: int = 20, seed: int = 0) -> Explorer:
    """Every evidence of one step of the paper's filter (Steps 2–6, Fig. 3) on the first
    ``steps`` readings of a simulated gauge (true orders), with its diagnostics: pick the
    step, the start value and the discount ε."""
    controls = {
        "step": int_slider("step k + 1", step, 2, steps),
        "start": widgets.Dropdown(options=[("z_1 (paper)", "observation"),
                                           ("z_1 + E[w]", "mean_corrected")], value=start,
                                  description="start"),
        "epsilon": slider("discount ε", epsilon, 0.0, 0.5, 0.01, readout_format=".2f"),
    }

    seq = gauge_case(level_m, temperature_c, seed)

    @functools.lru_cache(maxsize=8)  # moving the step re-draws, it does not re-filter
    def run(start: str, epsilon: float) -> Any:
        return filter_case(level_m, temperature_c, start=start, epsilon=epsilon, seed=seed,
                           record=True, first=steps)[2]

    kept = KeptFigure(functools.partial(FilterStepFigure, figsize=(9.0, 9.0), pyplot=False),
                      FilterStepFigure.update)

    def render(step: int, start: str, epsilon: float):
        result = run(start, epsilon)
        entry, truth = result.steps[step - 1], float(seq.truth[step - 1, 0])
        figure = kept(entry, truth, key=FilterStepFigure.panels_of(entry))  # one per panels
        return figure.figure, step_numbers(result, step, truth)

    live = {"step": positions(controls["step"], 10)}
    return Explorer(controls, render, title="Inside one step of the filter", live=live)


# -- the acoustic level gauge: a recording, its resonances and the level --------------------------

#: Recording conditions of the gauge chapter and its explorer: the paper's speaker jitter
#: (σ_v = 0.1 Hz), a quiet microphone (30 dB SPL), 10 ms of audio latency; the background
#: noise is the explorer's slider.
GAUGE_CONDITIONS = RecordingConditions(speaker_jitter_hz=0.1, microphone_noise_pa=spl_to_pa(30.0),
                                       background_noise_pa=spl_to_pa(50.0), latency_s=0.01)


def gauge_reading(setup: TubeSetup, detection: DetectionResult) -> dict[str, Any]:
    """The numbers the gauge explorer prints for one detection in the tube ``setup``.

    The level by the series fit z_k = f_F (n_1 + s_k) + b (b free, the slope only) and by
    the paper's direct measurement (eq. 32 with the orders of eq. 43 at every reading: their
    mean and mean absolute error); how many of those orders are wrong; the detection's
    count, missed and spurious peaks.
    """
    c, f_f = setup.speed_of_sound, setup.fundamental_hz
    z = detection.frequencies
    fit = fit_resonance_series(z, detection.steps, offset_hz=None)
    true_orders = np.rint(z / f_f)
    direct = direct_levels(z, c)
    return {
        "series-fit L (m)": fit.level(c),
        "fit error (mm)": 1e3 * (fit.level(c) - setup.level_m),
        "eq. 32/43: mean L (m)": float(np.mean(direct)),
        "mean |L_k − L| (mm)": 1e3 * float(np.mean(np.abs(direct - setup.level_m))),
        "eq. 43 orders wrong": f"{int(np.sum(orders_eq43(z) != true_orders[:-1]))}/{z.size - 1}",
        "resonances": int(z.size),
        "missed": int(detection.missed.size),
        "spurious": int(detection.spurious.size),
    }


def gauge_explorer(level_m: float = 4.6, temperature_c: float = 26.5,
                   top_reflection: float = 0.3, background_db: float = 50.0,
                   seed: int = 0) -> Explorer:
    """A simulated gauge (paper §4): level, temperature, the top's reflection R_t and the
    background noise → the recording's envelope and its detected resonances beside the
    model n c/(2L) (eqs. 29–32), the detection error z_k − n_k f_F, and the level by the
    series fit and by eqs. 32/43. One recording (the paper's sweep, seeded) is synthesised
    and analysed per change (its noise draws are kept), and the figure is kept and updated;
    the sliders redraw on release."""
    controls = {
        "level": slider("level L (m)", level_m, 1.0, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider("temperature T (°C)", temperature_c, 0.0, 30.0, 0.5,
                              readout_format=".1f"),
        "top_reflection": slider("top reflection R_t", top_reflection, 0.0, 0.9, 0.05,
                                 readout_format=".2f"),
        "background": slider("background noise (dB SPL)", background_db, 30.0, 100.0, 5.0,
                             readout_format=".0f"),
    }

    figure = KeptFigure(gauge_detection_figure, update_gauge_detection)

    def render(level: float, temperature: float, top_reflection: float, background: float):
        setup = TubeSetup(level, temperature, top_reflection=top_reflection)
        cond = replace(GAUGE_CONDITIONS, background_noise_pa=spl_to_pa(background))
        det = detect_resonances(synthesize_recording(setup, PAPER_SWEEP, cond, seed=seed))
        numbers = gauge_reading(setup, det)  # before the figure changes: it may raise
        return figure(setup, det), numbers

    live = {"level": positions(controls["level"], 9, 1.6, 9.6),
            "temperature": positions(controls["temperature"], 1, 5.0, 5.0)}
    return Explorer(controls, render, title="A simulated acoustic level gauge", live=live)


# -- the lab: measure with a sound card, or with the virtual tube ---------------------------------


#: Positions of the virtual tube's level, the lab's control that is live on the static site.
LAB_LIVE_LEVELS = 8


class LabWidget(widgets.VBox):
    """The lab's measuring station (book/lab.md): pick the devices, give the thermometer's
    reading, press Record, and read the level with its uncertainty, the resonances and the
    level by every filter of Table 3.

    With either device picker on "virtual tube (no device)" — the only choice on a machine
    without a sound card — Record simulates the measurement on the virtual tube (its level,
    the thermometer's error and the room noise are controls; about 0.5 s); with devices it
    plays the sweep and records it through them (about 7 s), see
    :func:`dstoolkit.teaching.lab_measurement`. When the widget is built it measures once on the
    virtual tube, so that a book executed at build time shows a first result.

    Attributes
    ----------
    controls : dict
        The controls by name: ``input``, ``output``, ``temperature``, ``volume``, ``level``,
        ``thermometer_error``, ``room_noise``, ``through_virtual_tube``.
    button
        The Record button; ``button.click()`` records, as a click does.
    readout
        The ``HTML`` with the numbers (or the error message).
    output
        The ``Output`` with the figures.
    analysis
        The last :class:`~dstoolkit.audio.Analysis`, None after a failure.
    numbers
        The numbers shown (:func:`dstoolkit.teaching.lab_numbers`), ``{"error": message}`` after
        a failure.
    figure
        The last figure of the recording and its resonances.
    method_figure
        The last figure of the level by every method.
    measurements
        Records made so far; a simulated record uses it as its seed.
    """

    def __init__(self, settings: LabSettings | None = None, *, devices: bool | None = None,
                 record_now: bool = True, static: bool | None = None) -> None:
        super().__init__()
        s = LabSettings() if settings is None else settings
        inputs = device_options("input") if devices is not False else None
        outputs = device_options("output") if devices is not False else None
        self.controls: dict[str, widgets.ValueWidget] = {
            "input": widgets.Dropdown(options=inputs or [("virtual tube (no device)", VIRTUAL)],
                                      value=VIRTUAL, description="microphone (input)",
                                      style={"description_width": "initial"}),
            "output": widgets.Dropdown(options=outputs or [("virtual tube (no device)",
                                                            VIRTUAL)],
                                       value=VIRTUAL, description="speaker (output)",
                                       style={"description_width": "initial"}),
            "temperature": slider("thermometer T (°C)", s.temperature_c, -10.0, 40.0, 0.1,
                                  readout_format=".1f"),
            "volume": slider("volume (full scale)", s.volume, 0.05, 1.0, 0.05,
                             readout_format=".2f"),
            "level": slider("level L (m)", s.level_m, 0.5, 12.0, 0.05, readout_format=".2f"),
            "thermometer_error": slider("thermometer error (°C)", s.thermometer_error_c,
                                        -5.0, 5.0, 0.1, readout_format=".1f"),
            "room_noise": slider("room noise (dBFS)", s.room_noise_dbfs, -80.0, -10.0, 1.0,
                                 readout_format=".0f"),
            "through_virtual_tube": widgets.Checkbox(
                value=s.through_virtual_tube, indent=False,
                description="with devices: play the virtual tube (loopback, no real tube)"),
        }
        self._sweep = s.sweep
        self.button = widgets.Button(description="● Record", button_style="danger",
                                     tooltip="play the sweep and record it")
        self.button.on_click(self.record)
        self.refresh = widgets.Button(description="↻ devices",
                                      tooltip="look for sound devices again")
        self.refresh.on_click(self.refresh_devices)
        self.readout = widgets.HTML()
        self.output = widgets.Output()
        self.analysis = None
        self.numbers: dict[str, Any] = {}
        self.figure: Figure | None = None
        self.method_figure: Figure | None = None
        self.measurements = 0
        for name in ("input", "output", "through_virtual_tube"):
            self.controls[name].observe(lambda _change: self._sync(), "value")
        self._sync()
        c = self.controls
        for control in c.values():  # aligned labels, sliders with room to move
            control.style.description_width = "190px"
            control.layout.width = "440px"
        c["through_virtual_tube"].layout.width = "auto"
        c["thermometer_error"].tooltip = "how much the thermometer reads too high"

        def row(*children: widgets.Widget) -> widgets.HBox:
            return widgets.HBox(list(children), layout=widgets.Layout(flex_flow="row wrap"))

        self.children = (
            widgets.HTML("<b>The lab: measure a level</b>"),
            row(c["input"], c["output"]), row(self.refresh),
            row(c["temperature"], c["volume"]),
            widgets.HTML("<i>the virtual tube (without a device, or through a loopback):</i>"),
            row(c["level"], c["thermometer_error"]),
            row(c["room_noise"], c["through_virtual_tube"]),
            row(self.button), self.readout, self.output,
        )
        if static_site() if static is None else static:
            self._build_static()
        elif record_now:
            self.record()

    def _build_static(self) -> None:
        """The static site's form: one simulated record per position of the virtual tube's
        level (the live control, :data:`LAB_LIVE_LEVELS`), switched in the browser by a
        slider (:func:`state_stack`); every other control and the buttons are disabled."""
        level = self.controls["level"]
        live = {"level": positions(level, LAB_LIVE_LEVELS, 1.0, 11.5)}
        start = level.value
        leaves: dict[tuple[Any, ...], widgets.Widget] = {}
        for value in sorted(live["level"], key=lambda v: v == start):  # the start one last
            level.value = value
            self.measurements = 0  # each state is the first record at its level
            self.record()
            at = {level.description: shown_value(level, value)}
            leaves[(value,)] = state_leaf(self.readout, self.output, [
                figure_alt(at, self.numbers, "Recording and its resonances"),
                figure_alt(at, {m: v for m, v in self.numbers.items()
                                if m.endswith("(m)")}, "Level by each method")])
        stack, site = state_stack(self.controls, live, leaves)
        for widget in [*self.controls.values(), self.button, self.refresh]:
            widget.disabled = True
        self.controls["level"] = site["level"]

        def swap(widget: widgets.Widget) -> widgets.Widget:
            if widget is level:
                return site["level"]
            if isinstance(widget, widgets.HBox):
                widget.children = tuple(swap(child) for child in widget.children)
            return widget

        rows = [swap(w) for w in self.children if w not in (self.readout, self.output)]
        self.children = (*rows, site_note([site["level"]], True), stack)

    def settings(self) -> LabSettings:
        """The controls as :class:`~dstoolkit.teaching.LabSettings` (seed: the record count)."""
        v = {name: control.value for name, control in self.controls.items()}
        return LabSettings(temperature_c=v["temperature"], level_m=v["level"],
                           thermometer_error_c=v["thermometer_error"],
                           room_noise_dbfs=v["room_noise"], volume=v["volume"],
                           input_device=v["input"], output_device=v["output"],
                           through_virtual_tube=v["through_virtual_tube"],
                           seed=self.measurements, sweep=self._sweep)

    def _sync(self) -> None:
        """Grey out the controls the chosen devices do not use."""
        s = self.settings()
        virtual_used = s.simulated or s.through_virtual_tube
        self.controls["level"].disabled = not virtual_used
        self.controls["thermometer_error"].disabled = not virtual_used
        self.controls["room_noise"].disabled = not s.simulated
        self.controls["through_virtual_tube"].disabled = s.simulated

    def _fail(self, message: str) -> None:
        self.analysis, self.numbers = None, {"error": message}
        self.readout.value = f"<p style='color:#b00020'>⚠ {html.escape(message)}</p>"
        self.output.outputs = ()

    def refresh_devices(self, _button: Any = None) -> None:
        """Scan the sound devices again (after plugging one in or starting the loopback)."""
        import dstoolkit.audio as audio

        try:
            audio.refresh_devices()
        except AudioUnavailableError as exc:
            self._fail(str(exc))
            return
        for kind, name in (("input", "input"), ("output", "output")):
            self.controls[name].options = device_options(kind)
            self.controls[name].value = VIRTUAL

    def record(self, _button: Any = None) -> None:
        """Measure once with the current settings and show the result (the button's
        click handler)."""
        settings = self.settings()
        self.button.disabled, self.button.description = True, "recording…"
        where = ("simulated on the virtual tube (no device)" if settings.simulated
                 else "playing and recording, about 7 s")
        self.readout.value = f"<p>recording: {html.escape(where)}…</p>"
        try:
            analysis = lab_measurement(settings)
        except (AudioUnavailableError, ValueError) as exc:  # DetectionError is a ValueError
            self._fail(str(exc))
            return
        finally:
            self.measurements += 1
            self.button.disabled, self.button.description = False, "● Record"
        self.analysis, self.numbers = analysis, lab_numbers(analysis)
        lv = analysis.level
        head = (f"<p><b>L = {lv.level_m:.4f} m ± {lv.uncertainty_m:.4f} m</b> (1σ), "
                f"{html.escape(analysis.recording.metadata.source or '')}</p>")
        notes = "".join(f"<p style='color:#b36b00'>{html.escape(n)}</p>" for n in analysis.notes)
        report = (f"<details><summary>full report</summary><pre>"
                  f"{html.escape(analysis.summary())}</pre></details>")
        from dstoolkit.plots import STYLE

        by_method = {STYLE.get(m, {"label": m})["label"]: v
                     for m, v in analysis.filter_levels.items()}
        main = {k: v for k, v in self.numbers.items()
                if k.removesuffix(" (m)") not in analysis.filter_levels}
        self.readout.value = (head + readout_html(main) + "<p>level by each filter (m):</p>"
                              + readout_html(by_method) + notes + report)
        self.figure, self.method_figure = analysis.figure(), plot_method_levels(analysis)
        # As PNG images set on the Output widget itself: they show whether or not the
        # notebook's matplotlib formatter is active, and a book executed at build time
        # embeds them in the widget's state.
        self.output.outputs = ()
        for fig in (self.figure, self.method_figure):
            if not hasattr(fig.canvas, "buffer_rgba"):  # a Figure() made without pyplot
                FigureCanvasAgg(fig)
            fig.set_dpi(96)
            fig.canvas.draw()
            png = encode_png(np.asarray(fig.canvas.buffer_rgba()))
            self.output.append_display_data(Image(data=png, format="png"))


def lab_widget(temperature_c: float = 21.0, level_m: float = 2.5, *,
               devices: bool | None = None, record_now: bool = True) -> LabWidget:
    """The lab's measuring station, :class:`LabWidget`: device pickers (filled from
    :func:`dstoolkit.audio.list_devices` when a sound card is there, else only the virtual
    tube), the thermometer's reading, the virtual tube's level, a Record button and the
    result. ``devices=False`` offers the virtual tube only (no device lookup); with
    ``record_now`` the first (virtual) measurement is made at once."""
    return LabWidget(LabSettings(temperature_c=temperature_c, level_m=level_m),
                     devices=devices, record_now=record_now)


# -- estimating the level: the paper's Figs. 10–11 for one run ------------------------------------

#: The figures the level-estimation explorer can draw (the paper's Figs. 10 and 11).
ESTIMATION_FIGURES: dict[str, str] = {"Fig. 10: frequencies": "frequency",
                                      "Fig. 11: levels": "level"}


#: Short method names for readouts that must fit two lines.
_SHORT_LABELS = {"direct": "direct", "dependent_evidence": "paper's filter"}


def estimation_numbers(run: Any) -> dict[str, Any]:
    """What the level-estimation explorer prints for a :class:`~dstoolkit.studies.GaugeRun`:
    for the readings (direct, eq. 32) and each filter, "mean |L̂ − L| mm / mean |x̂ − f| Hz"
    in one entry, and how many orders n_k are wrong."""
    from dstoolkit.plots import STYLE

    levels = run.levels()
    freq = run.frequency_errors()
    out: dict[str, Any] = {}
    for name in levels:
        label = _SHORT_LABELS.get(name, STYLE.get(name, {"label": name})["label"])
        level_mm = 1e3 * float(np.mean(np.abs(levels[name] - run.level_m)))
        out[label] = f"{level_mm:.4g} mm / {float(np.mean(freq[name])):.3g} Hz"
    wrong = int(np.sum(run.orders != run.true_orders[:-1]))
    out["wrong n_k"] = f"{wrong}/{run.orders.size}"
    return out


def level_estimation_explorer(level_m: float = 4.6, temperature_c: float = 26.5,
                              simulation: str = "frequency", order_rule: str = "eq43",
                              figure: str = "Fig. 11: levels", seed: int = 0) -> Explorer:
    """One simulated sweep filtered by the paper's filter and Nassreddine's (the paper's
    Figs. 10–11, :func:`dstoolkit.studies.gauge_run`): level, temperature, the
    simulation of the readings (the paper's w drawn i.i.d., or detected in a synthesised
    recording), where n_k comes from (eq. 43, the series fit, the truth), the run's seed and
    which figure. Numbers: ``estimation_numbers(run)``. A frequency-level redraw takes a
    few hundredths of a second, a waveform-level one a few tenths (a recording is
    synthesised and analysed): sliders redraw on release."""
    from dstoolkit.plots import plot_estimates
    from dstoolkit.plots.artists import update_estimates
    from dstoolkit.studies import gauge_run

    controls = {
        "level": slider("level L (m)", level_m, 1.3, 10.6, 0.1, readout_format=".1f"),
        "temperature": slider("temperature T (°C)", temperature_c, 0.0, 35.0, 0.5,
                              readout_format=".1f"),
        "simulation": widgets.Dropdown(options=[("frequency level (i.i.d. w)", "frequency"),
                                                ("waveform level (recording)", "waveform")],
                                       value=simulation, description="readings"),
        "order_rule": widgets.Dropdown(options=[("eq. 43 (paper)", "eq43"),
                                                ("series fit", "fit"), ("true", "true")],
                                       value=order_rule, description="n_k by"),
        "figure": widgets.Dropdown(options=list(ESTIMATION_FIGURES), value=figure,
                                   description="figure"),
        "seed": int_slider("run (seed)", seed, 0, 20),
    }

    kept = KeptFigure(functools.partial(plot_estimates, kept=True),
                      update_estimates)  # one per kind of figure
    run_of = functools.lru_cache(maxsize=32)(gauge_run)  # the figure dropdown re-draws

    def render(level: float, temperature: float, simulation: str, order_rule: str,
               figure: str, seed: int):
        run = run_of(level, temperature, simulation, order_rule, seed=seed)
        kind = ESTIMATION_FIGURES[figure]
        note = (f"L = {level:.1f} m, T = {temperature:.1f} °C,\n{simulation}-level "
                f"readings, n_k by {order_rule}, seed {seed}")
        if kind == "frequency":
            fig = kept(run.truth, run.readings, run.estimates, note=note, key=kind)
        else:
            levels = run.levels()
            fig = kept(run.level_m, levels.pop("direct"), levels, quantity="level", unit="m",
                       note=note, key=kind)
        return fig, estimation_numbers(run)

    live = {"level": positions(controls["level"], 9, 1.6, 9.6),
            "temperature": positions(controls["temperature"], 1, 5.0, 5.0)}
    return Explorer(controls, render, title="One run of the gauge: the paper's Figs. 10–11 "
                    "(readout: mean |L̂ − L| / mean |x̂ − f|)",
                    live=live)


# -- beyond the paper: every filter under wrong noise bounds ------------------------------------


def mismatch_numbers(result: Any) -> dict[str, Any]:
    """Mean |x̂ − x| (Hz) of each method of a :class:`~dstoolkit.studies.
    MismatchResult`, and the runs in which the strict bounded-error filter failed."""
    from dstoolkit.plots import STYLE

    out: dict[str, Any] = {f"{STYLE.get(m, {'label': m})['label']} (Hz)": v
                           for m, v in result.mean_errors().items()}
    out["bounded error: inconsistent runs"] = f"{result.inconsistent_runs:.0%}"
    return out


def noise_bounds_explorer(level_m: float = 4.6, temperature_c: float = 26.5, runs: int = 20,
                          seed: int = 0, start: str = "mean_corrected") -> Explorer:
    """Every filter on the same simulated gauge runs (eqs. 39–40 with the paper's noises v
    and w, true orders), each assuming the noise bounds set by the sliders (lower, mode,
    upper of v and of w): the assumed against the true possibility distributions, and the
    mean |x̂_k − x_k| per step of every method
    (:func:`dstoolkit.studies.noise_mismatch`). ``start`` is the paper's filter's
    start value (a dropdown too). One redraw filters ``runs`` runs by five methods (20 runs:
    about 0.08 s with the extra ``speed``, 0.11 s without; moving the start value reruns
    only the paper's filter): sliders redraw on release."""
    from dstoolkit.plots.artists import noise_bounds_figure, update_noise_bounds_figure
    from dstoolkit.studies import ALL_FILTERS, noise_mismatch, tracking_data

    # the start value moves only the paper's filter: the others are kept per noise bounds
    paper, others = ("dependent_evidence",), tuple(m for m in ALL_FILTERS
                                                   if m != "dependent_evidence")

    data = tracking_data(level_m, temperature_c, runs=runs, seed=seed)
    v, w = data.state_noise, data.obs_noise
    controls = {
        "v_lower": slider("v lower", float(v.lower[0]), -1.0, 0.0, 0.01, readout_format=".2f"),
        "v_mode": slider("v mode", float(v.mode[0]), -0.5, 0.5, 0.01, readout_format=".2f"),
        "v_upper": slider("v upper", float(v.upper[0]), 0.0, 1.0, 0.01, readout_format=".2f"),
        "w_lower": slider("w lower", float(w.lower[0]), -20.0, -4.0, 0.01,
                          readout_format=".2f"),
        "w_mode": slider("w mode", float(w.mode[0]), -12.0, -2.0, 0.01, readout_format=".2f"),
        "w_upper": slider("w upper", float(w.upper[0]), -8.0, 5.0, 0.01, readout_format=".2f"),
        "start": widgets.Dropdown(options=[("z_1 (paper)", "observation"),
                                           ("z_1 + E[w]", "mean_corrected")], value=start,
                                  description="start"),
    }

    title = f"L = {level_m:.1f} m, {runs} runs, true orders"
    ranges = {name: (controls[name].min, controls[name].max) for name in controls
              if name != "start"}
    kept = KeptFigure(functools.partial(
        noise_bounds_figure, title=title,
        v_range=(ranges["v_lower"][0], ranges["v_upper"][1]),
        w_range=(ranges["w_lower"][0], ranges["w_upper"][1])),
                      update_noise_bounds_figure)

    @functools.lru_cache(maxsize=4)
    def rivals(v_bounds: tuple[float, ...], w_bounds: tuple[float, ...]) -> Any:
        return noise_mismatch(data, BoundedNoise(*v_bounds), BoundedNoise(*w_bounds),
                              methods=others, seed=seed)

    def render(v_lower: float, v_mode: float, v_upper: float, w_lower: float, w_mode: float,
               w_upper: float, start: str):
        assumed_v = BoundedNoise(v_lower, v_mode, v_upper)
        assumed_w = BoundedNoise(w_lower, w_mode, w_upper)
        rest = rivals((v_lower, v_mode, v_upper), (w_lower, w_mode, w_upper))
        ours = noise_mismatch(data, assumed_v, assumed_w, methods=paper, seed=seed,
                              start=start)
        errors, seconds = ours.errors | rest.errors, ours.seconds | rest.seconds
        result = replace(rest, errors={m: errors[m] for m in ALL_FILTERS},
                         seconds={m: seconds[m] for m in ALL_FILTERS})
        fig = kept(v, w, assumed_v, assumed_w, result.errors)
        return fig, mismatch_numbers(result)

    live = {"w_upper": positions(controls["w_upper"], 8, -6.21, 4.29),
            "v_upper": positions(controls["v_upper"], 1, 0.9, 0.9)}
    return Explorer(controls, render, title="Every filter with the noise bounds you assume",
                    live=live)
