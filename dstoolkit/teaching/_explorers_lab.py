"""The lab's measuring station (book/lab.md), an explorer whose redraw is the Record button."""

from __future__ import annotations

import html
from collections.abc import Mapping
from typing import Any

import ipywidgets as widgets
from matplotlib.figure import Figure

import dstoolkit.audio as audio
from dstoolkit.audio import Analysis
from dstoolkit.errors import AudioUnavailableError

from ._explorer import (
    Explorer,
    figure_alt,
    positions,
    readout_html,
    slider,
    warning_html,
)
from ._lab import (
    VIRTUAL,
    VIRTUAL_LABEL,
    LabSettings,
    device_options,
    lab_measurement,
    lab_numbers,
    plot_method_levels,
)
from ._readouts import lowest_and_highest, method_label

# -- the lab: measure with a sound card, or with the virtual tube ---------------------------------


#: Positions of the virtual tube's level, the lab's control that is live on the static site.
LAB_LIVE_LEVELS = 8


class LabWidget(Explorer):
    """The lab's measuring station (book/lab.md), an :class:`Explorer` redrawn by a button.

    Pick the devices, give the thermometer's reading, press Record, and read the level with
    its uncertainty, the resonances and the level by every filter of the paper's Table 3.
    With either device picker on "virtual tube (no device)" — the only choice on a machine
    without a sound card — Record simulates the measurement on the virtual tube (its level,
    the thermometer's error and the room noise are controls); with devices it plays the
    sweep and records it through them, see :func:`dstoolkit.teaching.lab_measurement`.
    When the widget is built it measures once on the virtual tube, so that a book executed
    at build time shows a first result. On the static site the virtual tube's level is the
    live control (``LAB_LIVE_LEVELS`` positions, each a first record at that level).

    Parameters
    ----------
    settings : LabSettings, optional
        The controls' start values (default ``LabSettings()``).
    devices : bool, optional
        False: offer the virtual tube only, with no device lookup. Default: list the
        devices PortAudio sees.
    record_now : bool, optional
        Make the first (virtual) measurement at once (default True).
    static : bool, optional
        Build the static-site form; default: :func:`static_site`.

    Attributes
    ----------
    controls : dict[str, ipywidgets.ValueWidget]
        The controls by name: ``input``, ``output``, ``temperature``, ``volume``, ``level``,
        ``thermometer_error``, ``room_noise``, ``through_virtual_tube``.
    button : ipywidgets.Button
        The Record button; ``button.click()`` records, as a click does.
    devices_button : ipywidgets.Button
        Looks for sound devices again (:meth:`refresh_devices`).
    analysis : dstoolkit.audio.Analysis or None
        The last analysis, None after a failure.
    numbers : dict[str, Any]
        The numbers shown (:func:`dstoolkit.teaching.lab_numbers`), ``{"error": message}``
        after a failure (the output is then emptied: no stale figure).
    figure : Figure or None
        The last figure of the recording and its resonances.
    method_figure : Figure or None
        The last figure of the level by every method.
    measurements : int
        Records made so far; a simulated record uses it as its seed.

    See Also
    --------
    lab_widget : The station with the lab chapter's start values.
    lab_measurement : One measurement from :class:`LabSettings`.

    Examples
    --------
    >>> station = LabWidget(devices=False, record_now=False, static=False)
    >>> station.controls["level"].value = 3.0
    >>> station.button.click()
    >>> round(station.numbers["level (m)"], 2), station.measurements
    (3.0, 1)
    """

    keeps_last_figure = False  # a failed record shows its message and no stale figure
    redraws_on_change = False  # only a click of Record measures

    def __init__(
        self,
        settings: LabSettings | None = None,
        *,
        devices: bool | None = None,
        record_now: bool = True,
        static: bool | None = None,
    ) -> None:
        s = LabSettings() if settings is None else settings
        c = _lab_controls(s, devices)
        self._sweep = s.sweep
        self.analysis: Analysis | None = None
        self.method_figure: Figure | None = None
        self.measurements = 0
        self.button = widgets.Button(
            description="● Record", button_style="danger", tooltip="play the sweep and record it"
        )
        self.devices_button = widgets.Button(
            description="↻ devices", tooltip="look for sound devices again"
        )
        rows = [
            [c["input"], c["output"]],
            [self.devices_button],
            [c["temperature"], c["volume"]],
            widgets.HTML("<i>the virtual tube (without a device, or through a loopback):</i>"),
            [c["level"], c["thermometer_error"]],
            [c["room_noise"], c["through_virtual_tube"]],
            [self.button],
        ]
        super().__init__(
            c,
            self._measure,
            title="The lab: measure a level",
            live={"level": positions(c["level"], LAB_LIVE_LEVELS, 1.0, 11.5)},
            static=static,
            rows=rows,
            draw=record_now,
            said=("level (m)", "resonances"),
        )
        self.button.on_click(self.record)
        self.devices_button.on_click(self.refresh_devices)
        for name in ("input", "output", "through_virtual_tube"):
            c[name].observe(lambda _change: self._sync(), "value")
        if not self.static:
            self._sync()

    def settings(self, values: Mapping[str, Any] | None = None) -> LabSettings:
        """Return the controls as :class:`~dstoolkit.teaching.LabSettings`.

        Parameters
        ----------
        values : Mapping[str, Any], optional
            The controls' values by name; default: their current values.

        Returns
        -------
        LabSettings
            The settings of the next record; its seed is the record count (0 for every
            state of the static site: each is a first record).
        """
        v = self.values() if values is None else values
        return LabSettings(
            temperature_c=v["temperature"],
            level_m=v["level"],
            thermometer_error_c=v["thermometer_error"],
            room_noise_dbfs=v["room_noise"],
            volume=v["volume"],
            input_device=v["input"],
            output_device=v["output"],
            through_virtual_tube=v["through_virtual_tube"],
            seed=0 if self.static else self.measurements,
            sweep=self._sweep,
        )

    def _measure(self, **values: Any) -> tuple[list[Figure], dict[str, Any]]:
        """Return the explorer's render: one record with ``values``, its two figures and numbers."""
        self.analysis = None
        try:
            analysis = lab_measurement(self.settings(values))
        finally:
            self.measurements += 1
        self.analysis, self.method_figure = analysis, plot_method_levels(analysis)
        return [analysis.figure(), self.method_figure], lab_numbers(analysis)

    def readout_for(self, numbers: Mapping[str, Any]) -> str:
        """Return the record's readout.

        The level ± 1σ, the numbers, the level by each filter, the analysis' notes and its full
        report.

        Parameters
        ----------
        numbers : Mapping[str, Any]
            The numbers of :func:`~dstoolkit.teaching.lab_numbers`.

        Returns
        -------
        str
            The readout's HTML.
        """
        analysis = self.analysis
        if analysis is None:  # pragma: no cover - a valid render always leaves one
            return super().readout_for(numbers)
        lv = analysis.level
        head = (
            f"<p><b>L = {lv.level_m:.4f} m ± {lv.uncertainty_m:.4f} m</b> (1σ), "
            f"{html.escape(analysis.recording.metadata.source or '')}</p>"
        )
        notes = "".join(f"<p style='color:#b36b00'>{html.escape(n)}</p>" for n in analysis.notes)
        report = (
            f"<details><summary>full report</summary><pre>"
            f"{html.escape(analysis.summary())}</pre></details>"
        )
        by_method = {method_label(m): v for m, v in analysis.filter_levels.items()}
        main = {
            k: v for k, v in numbers.items() if k.removesuffix(" (m)") not in analysis.filter_levels
        }
        return (
            head
            + readout_html(main)
            + "<p>level by each filter (m):</p>"
            + readout_html(by_method)
            + notes
            + report
        )

    def figure_alts(self, settings: Mapping[str, str], numbers: Mapping[str, Any]) -> list[str]:
        """Return the text alternatives of a state's two pictures, in words.

        The recording: its resonances and where the measured level lies against the truth;
        the level by each method: which method is closest to the truth and which farthest.

        Parameters
        ----------
        settings : Mapping[str, str]
            The level's label and the value it shows.
        numbers : Mapping[str, Any]
            The state's numbers.

        Returns
        -------
        list[str]
            Two texts, in the order of the pictures.
        """
        if "error" in numbers:
            return [figure_alt(settings, numbers, "Recording and its resonances")]
        error = float(numbers["error (mm)"])
        truth = float(numbers["true level (m)"])
        methods = {
            name.removesuffix(" (m)"): abs(float(v) - truth)
            for name, v in numbers.items()
            if name.endswith(" (m)") and name not in {"level (m)", "true level (m)", "± 1σ (m)"}
        }
        words = (
            f"the recording's envelope with its {numbers['resonances']} resonances found, "
            f"{numbers['missed']} missed; the measured level lies {abs(error):.1f} mm "
            f"{'above' if error > 0 else 'below'} the truth"
        )
        found = [figure_alt(settings, numbers, "Recording and its resonances", words=words)]
        if methods:
            shown = {method_label(name): off for name, off in methods.items()}
            best, worst = lowest_and_highest({name: 1e3 * off for name, off in shown.items()})
            found.append(
                figure_alt(
                    settings,
                    numbers,
                    "Level by each method",
                    words=f"each method's level beside the true level: {best} closest "
                    f"({1e3 * min(methods.values()):.3g} mm off), {worst} farthest "
                    f"({1e3 * max(methods.values()):.3g} mm off)",
                )
            )
        return found

    def _sync(self) -> None:
        """Grey out the controls the chosen devices do not use."""
        s = self.settings()
        virtual_used = s.simulated or s.through_virtual_tube
        self.controls["level"].disabled = not virtual_used
        self.controls["thermometer_error"].disabled = not virtual_used
        self.controls["room_noise"].disabled = not s.simulated
        self.controls["through_virtual_tube"].disabled = s.simulated

    def refresh_devices(self, _button: Any = None) -> None:
        """Scan the sound devices again (after plugging one in or starting the loopback).

        Parameters
        ----------
        _button : ipywidgets.Button, optional
            The button clicked (ignored).
        """
        try:
            audio.refresh_devices()
        except AudioUnavailableError as exc:
            self.analysis, self.numbers = None, {"error": str(exc)}
            self.readout.value = warning_html(str(exc))
            self.output.outputs = ()
            return
        for name in ("input", "output"):
            self.controls[name].options = device_options(name)
            self.controls[name].value = VIRTUAL

    def record(self, _button: Any = None) -> None:
        """Measure once with the current settings and show the result.

        The button's click handler: the button is disabled while it records.

        Parameters
        ----------
        _button : ipywidgets.Button, optional
            The button clicked (ignored).
        """
        where = (
            "simulated on the virtual tube (no device)"
            if self.settings().simulated
            else "playing and recording, about 7 s"
        )
        self.button.disabled, self.button.description = True, "recording…"
        self.readout.value = f"<p>recording: {html.escape(where)}…</p>"
        try:
            self.refresh()
        finally:
            self.button.disabled, self.button.description = False, "● Record"


def _lab_controls(s: LabSettings, devices: bool | None) -> dict[str, widgets.ValueWidget]:
    """Return the station's controls at the settings ``s``, labels aligned.

    The device pickers list PortAudio's devices unless ``devices`` is False.
    """
    virtual = [(VIRTUAL_LABEL, VIRTUAL)]
    controls: dict[str, widgets.ValueWidget] = {
        "input": widgets.Dropdown(
            options=device_options("input") if devices is not False else virtual,
            value=VIRTUAL,
            description="microphone (input)",
        ),
        "output": widgets.Dropdown(
            options=device_options("output") if devices is not False else virtual,
            value=VIRTUAL,
            description="speaker (output)",
        ),
        "temperature": slider(
            "thermometer T (°C)", s.temperature_c, -10.0, 40.0, 0.1, readout_format=".1f"
        ),
        "volume": slider("volume (full scale)", s.volume, 0.05, 1.0, 0.05, readout_format=".2f"),
        "level": slider("level L (m)", s.level_m, 0.5, 12.0, 0.05, readout_format=".2f"),
        "thermometer_error": slider(
            "thermometer error (°C)", s.thermometer_error_c, -5.0, 5.0, 0.1, readout_format=".1f"
        ),
        "room_noise": slider(
            "room noise (dBFS)", s.room_noise_dbfs, -80.0, -10.0, 1.0, readout_format=".0f"
        ),
        "through_virtual_tube": widgets.Checkbox(
            value=s.through_virtual_tube,
            indent=False,
            description="with devices: play the virtual tube (loopback, no real tube)",
        ),
    }
    for control in controls.values():  # aligned labels, sliders with room to move
        control.style.description_width = "190px"
        control.layout.width = "440px"
    controls["through_virtual_tube"].layout.width = "auto"
    controls["thermometer_error"].tooltip = "how much the thermometer reads too high"
    return controls


def lab_widget(
    temperature_c: float = 21.0,
    level_m: float = 2.5,
    *,
    devices: bool | None = None,
    record_now: bool = True,
) -> LabWidget:
    """Return the lab's measuring station with the lab chapter's start values.

    Parameters
    ----------
    temperature_c : float, optional
        The thermometer's reading, °C.
    level_m : float, optional
        The virtual tube's level, m.
    devices : bool, optional
        False: offer the virtual tube only (no device lookup). Default: list the devices.
    record_now : bool, optional
        Make the first (virtual) measurement at once.

    Returns
    -------
    LabWidget
        Device pickers (filled from :func:`dstoolkit.audio.list_devices` when a sound card
        is there, else only the virtual tube), the thermometer's reading, the virtual tube's
        level, a Record button and the result.

    See Also
    --------
    LabWidget, lab_measurement

    Examples
    --------
    >>> station = lab_widget(level_m=3.0, devices=False)
    >>> abs(station.numbers["level (m)"] - 3.0) < 0.01
    True
    """
    return LabWidget(
        LabSettings(temperature_c=temperature_c, level_m=level_m),
        devices=devices,
        record_now=record_now,
    )
