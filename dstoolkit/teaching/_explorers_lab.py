"""The lab's measuring station (book/lab.md), an explorer whose redraw is the Record button."""

from __future__ import annotations

import html
from typing import Any

import ipywidgets as widgets
import numpy as np
from IPython.display import Image
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from dstoolkit.errors import (
    AudioUnavailableError,
)

from ._explorer import (
    encode_png,
    figure_alt,
    positions,
    readout_html,
    shown_value,
    site_note,
    slider,
    state_leaf,
    state_stack,
    static_site,
)
from ._lab import (
    VIRTUAL,
    LabSettings,
    device_options,
    lab_measurement,
    lab_numbers,
    plot_method_levels,
)

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
