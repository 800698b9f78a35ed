"""The lab: one measurement from the lab's settings, its pictures, and a wiring diagram.

The lab chapter (``book/lab.md``) and its widget (:func:`dstoolkit.teaching.lab_widget`)
measure a level with a real sound card when one is chosen, and otherwise with the
*virtual tube*: :func:`dstoolkit.audio.simulate_measurement` builds the recording a
loopback would return, calibration chirps and all, so the lab runs on any machine and in
the book's build. :func:`lab_measurement` is that choice in one place.

:func:`imitate_audio_failure` makes ``import sounddevice`` fail, or PortAudio see no device,
inside a ``with`` block, so that the chapter can print the messages a learner would meet
without touching a sound card.
"""

from __future__ import annotations

import sys
import types
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Literal, cast

import numpy as np
from matplotlib import patches
from matplotlib.axes import Axes
from matplotlib.figure import Figure

import dstoolkit.audio as audio
from dstoolkit.audio import WavRecording
from dstoolkit.errors import InvalidInputError
from dstoolkit.gauge import PAPER_SWEEP, LinearSweep, TubeSetup, speed_of_sound, valid_correlation
from dstoolkit.plots import GREY, STYLE, TRUTH_COLOUR, add_trace

from ._readouts import method_label

#: The value of the device pickers that means "no sound card: the virtual tube".
VIRTUAL = "virtual"
#: How the device pickers show :data:`VIRTUAL`.
VIRTUAL_LABEL = "virtual tube (no device)"


def device_options(kind: Literal["input", "output"]) -> list[tuple[str, Any]]:
    """Choices of a device picker: the virtual tube first, then the devices PortAudio sees.

    Only the virtual tube when sounddevice/PortAudio is missing or sees no device
    (:func:`dstoolkit.audio.audio_available`); nothing is played or recorded here.
    """
    options: list[tuple[str, Any]] = [(VIRTUAL_LABEL, VIRTUAL)]
    if audio.audio_available():
        for d in audio.list_devices(kind):
            default = d.default_input if kind == "input" else d.default_output
            options.append((f"{d.index}: {d.name}{' (default)' if default else ''}", d.index))
    return options


@dataclass(frozen=True)
class LabSettings:
    """What the lab's controls say.

    Parameters
    ----------
    temperature_c
        The thermometer's reading, °C: the analysis takes c from it (c = 331.3 + 0.606 T).
    level_m
        The virtual tube's level, m (with a device: only when ``through_virtual_tube``).
    thermometer_error_c
        How much the thermometer reads too high, °C: the virtual tube's air is at
        ``temperature_c − thermometer_error_c``. 0 for a perfect thermometer.
    room_noise_dbfs
        RMS of the white noise added to a simulated recording, dB full scale.
    volume
        Peak of the played signal, full scale (0–1].
    input_device
        PortAudio device index, or :data:`VIRTUAL`. The virtual tube is used when either
        device is :data:`VIRTUAL`.
    output_device
        PortAudio device index, or :data:`VIRTUAL`.
    through_virtual_tube
        With devices: play the virtual tube's standing wave instead of the bare sweep (for a
        loopback, ``scripts/audio-loopback.sh``, with no tube attached).
    seed
        Seed of the simulated recording's noise and latency.
    sweep
        The sweep (default the paper's, 1000 → 2400 Hz in 5 s).

    See Also
    --------
    lab_measurement : the measurement these settings describe.
    dstoolkit.audio.simulate_measurement : the virtual tube's recording.

    References
    ----------
    The paper's law of the speed of sound, c = 331.3 + 0.606 T (m/s, T in °C).

    Examples
    --------
    >>> s = LabSettings(level_m=3.0, thermometer_error_c=1.5)
    >>> s.simulated, s.virtual_tube.temperature_c
    (True, 19.5)
    """

    temperature_c: float = 21.0
    level_m: float = 2.5
    thermometer_error_c: float = 0.0
    room_noise_dbfs: float = -60.0
    volume: float = 0.1  # the safety advice of the lab: start low, raise step by step
    input_device: int | str = VIRTUAL
    output_device: int | str = VIRTUAL
    through_virtual_tube: bool = False
    seed: int = 0
    sweep: LinearSweep = PAPER_SWEEP

    @property
    def simulated(self) -> bool:
        """True when no sound card is used (either picker on the virtual tube)."""
        return VIRTUAL in (self.input_device, self.output_device)

    @property
    def virtual_tube(self) -> TubeSetup:
        """The simulated gauge: ``level_m`` of air at the true temperature."""
        return TubeSetup(
            level_m=self.level_m, temperature_c=self.temperature_c - self.thermometer_error_c
        )

    @property
    def simulated_latency_s(self) -> float:
        """The audio latency of the simulated sound card.

        50–200 ms, a new one per seed, as a real stream has (the calibration chirp finds it).
        """
        return float(0.05 + 0.15 * np.random.default_rng(self.seed).random())


def lab_measurement(settings: LabSettings) -> audio.Analysis:
    """Measure a level as the lab's controls say, and analyse it with every filter.

    With the virtual tube: :func:`dstoolkit.audio.simulate_measurement` (no audio at
    all), then :func:`~dstoolkit.audio.analyze`. With devices:
    :func:`dstoolkit.audio.measure` plays and records through them (about 7 s).

    Parameters
    ----------
    settings
        The lab's controls: level (m), temperature (°C), devices, sweep, seed.

    Returns
    -------
    dstoolkit.audio.Analysis
        The recording, its resonances, the level ± uncertainty (m) and the level by every
        filter; with the virtual tube also the true level and the error.

    Raises
    ------
    AudioUnavailableError
        No sounddevice/PortAudio, or the devices fail (the message says what to do).
    DetectionError
        A bad recording: silent, clipped, too short, no tube echo, too few resonances.
    ValueError
        Bad settings.

    See Also
    --------
    lab_numbers : the numbers the lab widget prints for the analysis.
    dstoolkit.audio.analyze : the analysis of a recording.

    References
    ----------
    The level is the paper's eq. 35, L = c/(2 f_F), from the spacing of the resonances; each
    filter follows eq. 32 per step with the orders of eq. 43.

    Examples
    --------
    The virtual tube with a short sweep (no sound card is touched):

    >>> from dstoolkit.gauge import LinearSweep
    >>> short = LinearSweep(1000.0, 1600.0, duration=2.0)
    >>> analysis = lab_measurement(LabSettings(level_m=9.6, sweep=short))
    >>> round(analysis.level.level_m, 2)
    9.6
    """
    s = settings
    if s.simulated:
        recording = audio.simulate_measurement(
            s.virtual_tube,
            temperature_c=s.temperature_c,
            sweep=s.sweep,
            latency_s=s.simulated_latency_s,
            noise_rms=10.0 ** (s.room_noise_dbfs / 20.0),
            amplitude=s.volume,
            seed=s.seed,
        )
        return audio.analyze(recording)
    return audio.measure(
        s.temperature_c,
        sweep=s.sweep,
        input_device=s.input_device,
        output_device=s.output_device,
        virtual_tube=s.virtual_tube if s.through_virtual_tube else None,
        amplitude=s.volume,
    )


def lab_numbers(analysis: audio.Analysis) -> dict[str, Any]:
    """Return the numbers the lab widget prints for one analysis.

    The level and its uncertainty, the truth when known, the resonances, the latency and the level
    by every filter.

    Parameters
    ----------
    analysis
        An analysis from :func:`lab_measurement` or :func:`dstoolkit.audio.analyze`.

    Returns
    -------
    dict
        Label (with its unit: m, mm, ms, m/s) → value: ``"level (m)"``, ``"± 1σ (m)"``,
        ``"true level (m)"`` and ``"error (mm)"`` when the truth is known, ``"resonances"``,
        ``"missed"``, ``"latency (ms)"``, ``"c (m/s)"`` and ``"<filter> (m)"`` per filter.

    See Also
    --------
    lab_measurement : the measurement these numbers describe.

    Examples
    --------
    >>> from dstoolkit.audio import analyze, simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> numbers = lab_numbers(analyze(rec, methods=("direct",)))
    >>> numbers["true level (m)"], numbers["resonances"], round(numbers["c (m/s)"], 2)
    (9.6, 77, 343.42)
    >>> list(numbers)[-1]
    'direct (m)'
    """
    lv, det = analysis.level, analysis.detection
    numbers: dict[str, Any] = {"level (m)": lv.level_m, "± 1σ (m)": lv.uncertainty_m}
    if analysis.true_level_m is not None and analysis.error_m is not None:
        numbers["true level (m)"] = analysis.true_level_m
        numbers["error (mm)"] = 1e3 * analysis.error_m
    numbers.update(
        {
            "resonances": int(det.frequencies.size),
            "missed": int(det.missed.size),
            "latency (ms)": 1e3 * analysis.latency_s,
            "c (m/s)": lv.speed_of_sound,
        }
    )
    numbers.update({f"{m} (m)": v for m, v in analysis.filter_levels.items()})
    return numbers


# -- pictures -----------------------------------------------------------------------------------


def plot_method_levels(analysis: audio.Analysis, ax: Axes | None = None) -> Figure:
    """Plot the level by the series fit and by every filter, beside the true level if known.

    The series fit is shown with its 1σ and 2σ uncertainty; each filter's level is eq. 32 per
    step with the orders of eq. 43, averaged.

    Parameters
    ----------
    analysis
        An analysis from :func:`lab_measurement` or :func:`dstoolkit.audio.analyze`.
    ax
        Axes to draw on; None draws on a new figure (8 × 2.6 in).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax`` (or the new one): one row per method, level L in m.

    See Also
    --------
    lab_numbers : the same levels as numbers.

    References
    ----------
    The paper's eqs. 32 and 43 (the level from one resonance and its order) and eq. 35
    (the level from the spacing of the resonances).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from dstoolkit.audio import analyze, simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> fig = plot_method_levels(analyze(rec, methods=("direct",)))
    >>> [t.get_text() for t in fig.axes[0].get_yticklabels()][0]
    'series fit (spacing)'
    """
    if ax is None:
        fig = Figure(figsize=(8.0, 2.6), layout="constrained")
        ax = fig.add_subplot()
    fig = cast(Figure, ax.figure)
    lv = analysis.level
    names = ["series fit (spacing)", *(method_label(m) for m in analysis.filter_levels)]
    y = np.arange(len(names))[::-1]
    ax.errorbar(
        [lv.level_m],
        [y[0]],
        xerr=[[2 * lv.uncertainty_m]],
        fmt="none",
        ecolor="0.75",
        elinewidth=6,
        label="± 2σ",
    )
    ax.errorbar(
        [lv.level_m],
        [y[0]],
        xerr=[[lv.uncertainty_m]],
        fmt="o",
        color="black",
        ecolor="0.35",
        elinewidth=6,
        label="level ± 1σ",
    )
    for yi, (m, value) in zip(y[1:], analysis.filter_levels.items(), strict=True):
        st: Any = STYLE.get(m, {"color": "k", "marker": "s"})
        ax.plot([value], [yi], ls="", marker=st["marker"], color=st["color"])
    if analysis.true_level_m is not None:
        ax.axvline(analysis.true_level_m, color=TRUTH_COLOUR, lw=1.2, label="true level")
    ax.set_yticks(y, names)
    ax.set_xlabel("level L (m)")
    ax.ticklabel_format(axis="x", useOffset=False)
    ax.set_title("the level by the series fit and by each filter")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    return fig


def calibration_correlation(recording: WavRecording) -> np.ndarray:
    """|c[j]| = |Σ_i recording[j + i] chirp[i]| normalised to its maximum.

    The matched filter of :func:`dstoolkit.gauge.estimate_latency` over the whole recording (index j
    is where a chirp would start).

    Parameters
    ----------
    recording
        A recording with the calibration chirps, from :func:`~dstoolkit.audio.measure` or
        :func:`~dstoolkit.audio.simulate_measurement`.

    Returns
    -------
    numpy.ndarray
        |c[j]| / max |c|, shape (samples − chirp samples + 1,), dimensionless in [0, 1].

    See Also
    --------
    plot_calibration : the picture of this correlation.

    Examples
    --------
    The opening chirp is found one latency after it was played:

    >>> import numpy as np
    >>> from dstoolkit.audio import simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> c = calibration_correlation(rec)
    >>> float(c.max()), c.ndim
    (1.0, 1)
    """
    chirp = audio.calibration_chirp(recording.samplerate)
    c = np.abs(valid_correlation(recording.samples, chirp))
    return c / max(float(c.max()), 1e-300)


def plot_calibration(recording: WavRecording, *, zoom_ms: float = 4.0) -> Figure:
    """How the latency is found.

    The recording with its two chirps and the sweep (top), the chirp's matched filter over the
    recording (middle) and around the opening chirp, in ms after it was played (bottom). Needs a
    recording made by :func:`~dstoolkit.audio.measure` or
    :func:`~dstoolkit.audio.simulate_measurement` (its metadata say when the chirp was played).

    Parameters
    ----------
    recording
        A recording whose metadata hold the latency and the sweep's onset (s).
    zoom_ms
        Half width of the bottom panel around the latency, ms.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels (8 × 6.6 in): recording, matched filter, zoom on the latency.

    Raises
    ------
    InvalidInputError
        The recording's metadata do not hold the calibration.

    See Also
    --------
    calibration_correlation : the matched filter drawn in the middle and bottom panels.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from dstoolkit.audio import simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> fig = plot_calibration(rec, zoom_ms=2.0)
    >>> len(fig.axes), fig.axes[2].get_legend().get_texts()[0].get_text()
    (3, 'τ = 100.00 ms')
    """
    meta, fs = recording.metadata, recording.samplerate
    if meta.latency_s is None or meta.sweep_onset_s is None:
        raise InvalidInputError(
            "the recording's metadata do not hold the calibration "
            "(latency and sweep onset); record it with "
            "dstoolkit.audio.measure"
        )
    chirp_s = audio.calibration_chirp(fs).size / fs
    played = meta.sweep_onset_s - meta.latency_s - audio.CALIBRATION_GAP_S - chirp_s
    c = calibration_correlation(recording)
    t = np.arange(recording.samples.size) / fs
    fig = Figure(figsize=(8.0, 6.6), layout="constrained")
    top, mid, bottom = fig.subplots(3, 1, height_ratios=[2, 2, 2])
    add_trace(top, t, recording.samples, lw=0.3, color=GREY)
    arrive = played + meta.latency_s
    top.axvspan(arrive, arrive + chirp_s, color="C1", alpha=0.3, label="opening chirp")
    top.axvspan(
        meta.sweep_onset_s,
        meta.sweep_onset_s + (meta.sweep_duration_s or 0.0),
        color="C0",
        alpha=0.12,
        label="sweep",
    )
    top.axvline(played, color="black", lw=0.8, ls="--", label="chirp played")
    top.set_xlim(t[0], t[-1])
    top.set_xlabel("time in the recording (s)")
    top.set_ylabel("amplitude")
    top.legend(loc="lower right", fontsize="small")
    add_trace(mid, t[: c.size], c, lw=0.8, color="C1")
    half = c.size // 2
    for j, name in (
        (int(np.argmax(c[:half])), "opening chirp"),
        (half + int(np.argmax(c[half:])), "closing chirp"),
    ):
        mid.annotate(
            name,
            (t[j], c[j]),
            xytext=(6, -4),
            textcoords="offset points",
            fontsize="small",
            va="top",
        )
    mid.set_xlim(t[0], t[-1])
    mid.set_xlabel("where the chirp would start (s)")
    mid.set_ylabel("|matched filter|")
    lag_ms = 1e3 * (t[: c.size] - played)
    near = np.abs(lag_ms - 1e3 * meta.latency_s) <= zoom_ms
    bottom.plot(lag_ms[near], c[near], ".-", ms=2, lw=0.8, color="C1")
    bottom.axvline(
        1e3 * meta.latency_s, color="black", lw=1.0, label=f"τ = {1e3 * meta.latency_s:.2f} ms"
    )
    bottom.set_xlabel("lag after the chirp was played (ms)")
    bottom.set_ylabel("|matched filter|")
    bottom.legend(loc="upper right", fontsize="small")
    return fig


def draw_gauge(ax: Axes | None = None) -> Figure:
    """Return a wiring diagram of the lab's gauge.

    Tube, liquid, speaker and microphone at the top, thermometer, the cables to the laptop's sound
    card, and the level L.

    Parameters
    ----------
    ax
        Axes to draw on; None draws on a new figure (8 × 6 in).

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax`` (or the new one).

    See Also
    --------
    lab_measurement : a measurement with this gauge (or its virtual tube).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> draw_gauge().axes[0].get_title()
    "The lab's gauge: speaker and microphone at the top, level L below"
    """
    if ax is None:
        fig = Figure(figsize=(8.0, 6.0), layout="constrained")
        ax = fig.add_subplot()
    fig = cast(Figure, ax.figure)
    ax.set_xlim(-3.2, 8.6)
    ax.set_ylim(-0.6, 11.2)
    ax.set_aspect("equal")
    ax.axis("off")
    wall, inner = "#6b6b6b", 0.9  # tube: x in [0, inner], walls drawn as thick lines
    water, surface = "#9ecae1", 1.6
    ax.add_patch(
        patches.Rectangle((-1.3, 0.0), inner + 2.6, 2.6, fc=water, ec="#3182bd", lw=1.5)
    )  # bucket of liquid
    ax.add_patch(patches.Rectangle((0, 0.3), inner, surface - 0.3, fc="#6baed6", ec="none"))
    for x in (0.0, inner):
        ax.plot([x, x], [0.3, 9.6], color=wall, lw=3)
    ax.plot([0, inner], [surface, surface], color="#08519c", lw=2)
    ax.text(-1.2, 0.35, "bucket of water\n(or a movable plug)", fontsize=8, va="bottom")
    # speaker on the top, microphone through the wall just below it
    ax.add_patch(patches.Rectangle((-0.25, 9.6), inner + 0.5, 0.25, fc="#444", ec="none"))
    ax.add_patch(
        patches.Polygon(
            [(0.15, 9.85), (inner - 0.15, 9.85), (inner + 0.15, 10.5), (-0.15, 10.5)],
            fc="#222",
            ec="none",
        )
    )
    ax.text(-0.3, 10.75, "speaker (faces down)", fontsize=8, ha="left")
    ax.add_patch(patches.Circle((inner + 0.12, 9.3), 0.14, fc="#d62728", ec="black", lw=0.8))
    ax.text(
        inner + 0.4,
        9.1,
        "microphone,\nflush with the wall,\n~3 cm below\nthe speaker",
        fontsize=8,
        va="top",
    )
    ax.add_patch(patches.Rectangle((inner + 0.05, 6.0), 0.1, 1.4, fc="#fdae6b", ec="black", lw=0.6))
    ax.text(inner + 0.4, 6.6, "thermometer probe\n(air inside the tube)", fontsize=8, va="center")
    # the level L: from the speaker platform to the surface
    ax.annotate(
        "",
        xy=(-0.6, surface),
        xytext=(-0.6, 9.6),
        arrowprops={"arrowstyle": "<->", "color": "black", "lw": 1.0},
    )
    ax.text(-0.8, 0.5 * (9.6 + surface), "L", fontsize=13, ha="right", va="center")
    ax.text(-2.9, 4.2, "PVC tube\nd = 75 mm,\n2–10 m", fontsize=8, va="center")
    # laptop with its sound card, cables taped along the tube
    ax.add_patch(
        patches.FancyBboxPatch(
            (5.4, 3.4), 2.9, 1.8, boxstyle="round,pad=0.1", fc="#f0f0f0", ec="black"
        )
    )
    ax.text(6.85, 4.55, "laptop", fontsize=9, ha="center", weight="bold")
    ax.text(6.85, 3.8, "headphone out → amplifier\nmic in / USB", fontsize=7, ha="center")
    cable: dict[str, Any] = {"color": "black", "lw": 1.0}
    ax.plot([inner + 0.25, 4.6, 4.6, 5.4], [10.2, 10.2, 4.8, 4.8], **cable)
    ax.plot(
        [inner + 0.26, 0.6 + inner, 0.6 + inner, 4.3, 4.3, 5.4],
        [9.3, 9.3, 9.75, 9.75, 4.0, 4.0],
        ls="--",
        **cable,
    )
    ax.text(
        4.8,
        7.6,
        "speaker cable (—)\nmicrophone cable (- -)\ntied to a post,\naway from the mouth",
        fontsize=7,
        va="center",
    )
    ax.set_title("The lab's gauge: speaker and microphone at the top, level L below")
    return fig


# -- imitating a machine without audio (for the chapter's error messages and for tests) ----------


class _PortAudioError(Exception):
    """Stands for sounddevice.PortAudioError in the imitation of a machine without devices."""


def _sounddevice_without_devices() -> types.ModuleType:
    """Return a stand-in for sounddevice on a machine where PortAudio finds no device."""
    sd = types.ModuleType("sounddevice")
    sd.PortAudioError = _PortAudioError  # type: ignore[attr-defined]
    sd.default = types.SimpleNamespace(device=[-1, -1])  # type: ignore[attr-defined]

    def query_devices(device: Any = None, kind: Any = None) -> Any:
        if device is None and kind is None:
            return []
        raise _PortAudioError(f"Error querying device {-1 if device is None else device}")

    sd.query_devices = query_devices  # type: ignore[attr-defined]
    sd.query_hostapis = lambda: [{"name": "ALSA"}]  # type: ignore[attr-defined]
    return sd


@contextmanager
def imitate_audio_failure(kind: Literal["no sounddevice", "no device"]) -> Iterator[None]:
    """Make the sound card fail inside the block, as on a machine without one.

    Inside the block, ``import sounddevice`` fails ("no sounddevice": as without the
    package) or PortAudio sees no device ("no device": as on a machine without a sound
    card). Nothing is played or recorded; the real module is restored afterwards.

    Parameters
    ----------
    kind
        ``"no sounddevice"`` or ``"no device"``.

    Yields
    ------
    None
        Inside the block, the failure holds.

    Raises
    ------
    InvalidInputError
        ``kind`` is neither of the two.

    See Also
    --------
    dstoolkit.audio.audio_available : what the block makes False.

    Examples
    --------
    >>> from dstoolkit.audio import audio_available
    >>> with imitate_audio_failure("no device"):
    ...     audio_available()
    False
    """
    if kind == "no sounddevice":
        stand_in: types.ModuleType | None = None  # None in sys.modules: import raises
    elif kind == "no device":
        stand_in = _sounddevice_without_devices()
    else:
        raise InvalidInputError(f"kind must be 'no sounddevice' or 'no device', not {kind!r}")
    missing = object()
    saved = sys.modules.get("sounddevice", missing)
    sys.modules["sounddevice"] = stand_in  # type: ignore[assignment]
    try:
        yield
    finally:
        if saved is missing:
            del sys.modules["sounddevice"]
        else:
            sys.modules["sounddevice"] = saved  # type: ignore[assignment]


def level_error_from_temperature(
    level_m: float, temperature_c: float, thermometer_error_c: float
) -> float:
    """Return the level error (m) of a thermometer that reads ``thermometer_error_c`` too high.

    L = c/(2 f_F) (eq. 35) scales with c, so δL = L (c(T + δT) − c(T))/c(T).

    Parameters
    ----------
    level_m
        The true level L, m.
    temperature_c
        The air's true temperature T, °C.
    thermometer_error_c
        How much the thermometer reads too high, δT in °C (negative: too low).

    Returns
    -------
    float
        δL, m: positive when the level is overestimated.

    See Also
    --------
    LabSettings : ``thermometer_error_c`` sets this error on the virtual tube.

    References
    ----------
    The paper's eq. 35 (L = c/(2 f_F)) and its law c = 331.3 + 0.606 T.

    Examples
    --------
    A thermometer 1 °C too high over 2.5 m of air at 21 °C:

    >>> round(1e3 * level_error_from_temperature(2.5, 21.0, 1.0), 1)
    4.4
    """
    c_true = float(speed_of_sound(temperature_c))
    c_read = float(speed_of_sound(temperature_c + thermometer_error_c))
    return level_m * (c_read - c_true) / c_true


__all__ = [
    "VIRTUAL",
    "VIRTUAL_LABEL",
    "LabSettings",
    "calibration_correlation",
    "device_options",
    "draw_gauge",
    "imitate_audio_failure",
    "lab_measurement",
    "lab_numbers",
    "level_error_from_temperature",
    "plot_calibration",
    "plot_method_levels",
]
