"""Measure a level with real audio, or analyse a recording: the gauge end to end.

One measurement plays, in a single audio stream (the latency changes from stream to
stream, so the calibration must share the sweep's stream)::

    | lead-in 0.5 s | chirp 0.25 s | gap 0.25 s | sweep 5 s | gap | chirp | tail 0.5 s |

The opening chirp's position in the recording gives the latency τ
(:func:`dstoolkit.gauge.estimate_latency`); the sweep then arrives at ``sweep_onset_s``.
The closing chirp must give the same τ: otherwise the stream lost or inserted samples on
the way (an xrun, under a heavy processor load) and the measurement is repeated. The
recording and what is known about it are saved as a WAV file
(:mod:`dstoolkit.audio`); :func:`analyze` turns such a file into resonances
(:func:`dstoolkit.gauge.detect_resonances`, with τ corrected) and a level
with its uncertainty (:func:`estimate_level`).

With ``virtual_tube=TubeSetup(...)`` the played sweep is first shaped by the tube model
(:mod:`dstoolkit.gauge`): through a loopback the whole real audio path carries a
standing-wave recording whose true level is known. :func:`simulate_measurement` builds the
same recording without any audio (a pure delay instead of the sound card), so the lab runs
anywhere.

Command-line use: :func:`add_measure_arguments` / :func:`measure_command` and
:func:`add_analyze_arguments` / :func:`analyze_command` implement
``python -m dstoolkit measure`` and ``python -m dstoolkit analyze``.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

from dstoolkit.audio import _devices as audio
from dstoolkit.errors import (
    AudioDropoutError,
    DetectionError,
    DstoolkitError,
    InvalidInputError,
)
from dstoolkit.gauge import (
    DEFAULT_AMPLITUDE,
    PAPER_SWEEP,
    DetectionResult,
    LinearSweep,
    Recording,
    ResonanceSeriesFit,
    SpeedModel,
    TubeSetup,
    detect_resonances,
    fit_resonance_series,
    speed_of_sound,
    virtual_tube_signal,
)
from dstoolkit.studies import (
    METHODS,
    CaseReadings,
    estimate_levels,
    estimate_orders,
    paper_filters,
)
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.outputs import atomic_write, check_outputs, figure_tag, made_by

from ._recording_io import (
    RecordingFileError,
    RecordingMetadata,
    WavRecording,
    load_recording,
    open_recording,
    read_metadata,
    save_recording,
)

#: Silence between the calibration chirp and the sweep, s (its echoes in a real tube die).
CALIBRATION_GAP_S = 0.25
#: Largest difference between the latencies found by the opening and the closing chirp, s.
#: Separate input and output clocks drift by up to about 100 ppm (0.7 ms over one
#: measurement); a lost or inserted buffer moves the closing chirp by 5 ms or more.
MAX_LATENCY_DRIFT_S = 0.002
#: Standard uncertainty of a thermometer reading, °C, unless told otherwise.
DEFAULT_TEMPERATURE_UNCERTAINTY_C = 0.5


# -- level and its uncertainty ---------------------------------------------------------------


@dataclass(frozen=True)
class LevelEstimate:
    """A level from a series of resonances, with its standard uncertainty.

    ``level_m`` = c/(2 f_F), f_F the slope of the fit z_k = f_F (n_1 + s_k) + b
    (:func:`dstoolkit.gauge.fit_resonance_series` with b free): the spacing of the
    resonances, untouched by any offset common to all of them (latency, sweep rate,
    detector bias). ``uncertainty_m`` combines in quadrature:

    - ``fit_uncertainty_m``: the least-squares standard error of the slope;
    - ``offset_uncertainty_m``: half the difference from the fit with b = 0, which
      trusts the detector's offset corrections (κ/(2 f_F) and κτ) instead. Where they
      disagree the offsets were not removed as modelled (a wrong latency, a second
      reflector, the echoes' pull): this systematic term says so;
    - ``temperature_uncertainty_m``: L σ_c/c from the thermometer's uncertainty
      (c = 331.3 + 0.606 T: 0.5 °C is 0.09 % of L, 8 mm at 9.6 m).

    Parameters
    ----------
    level_m : float
        The level L = c/(2 f_F), m (the paper's eq. 35 with the fitted f_F).
    uncertainty_m : float
        Its standard uncertainty, m: the three terms below in quadrature.
    fit_uncertainty_m : float
        From the slope's least-squares standard error, m.
    offset_uncertainty_m : float
        Half the difference from the fit with b = 0, m.
    temperature_uncertainty_m : float
        From the thermometer's uncertainty, m.
    speed_of_sound : float
        c at the measured temperature, m/s (the paper's eq. 32).
    fit : ResonanceSeriesFit
        The fit of the resonance series (:func:`dstoolkit.gauge.fit_resonance_series`).

    See Also
    --------
    analyze : Returns one in :attr:`Analysis.level`.
    """

    level_m: float
    uncertainty_m: float
    fit_uncertainty_m: float
    offset_uncertainty_m: float
    temperature_uncertainty_m: float
    speed_of_sound: float
    fit: ResonanceSeriesFit


def estimate_level(
    detection: DetectionResult,
    temperature_c: float,
    *,
    temperature_uncertainty_c: float = DEFAULT_TEMPERATURE_UNCERTAINTY_C,
    speed_model: SpeedModel = "paper",
) -> LevelEstimate:
    """Estimate the level and its uncertainty from detected resonances (eqs. 32, 35).

    See :class:`LevelEstimate`. Missed resonances are fine: the fit uses the detection's
    ``steps``, which jump over them.
    """
    if not math.isfinite(temperature_c) or not -50.0 <= temperature_c <= 100.0:
        raise InvalidInputError(f"temperature_c = {temperature_c} °C is not an air temperature")
    if not temperature_uncertainty_c >= 0:
        raise InvalidInputError(
            f"temperature_uncertainty_c must be >= 0, got {temperature_uncertainty_c}"
        )
    z, steps = detection.frequencies, detection.steps
    c = float(speed_of_sound(temperature_c, speed_model))
    fit = fit_resonance_series(z, steps, offset_hz=None)
    level = fit.level(c)
    s = steps.astype(float)
    dof = max(z.size - 2, 1)
    slope_se = (
        fit.residual_rms_hz
        * math.sqrt(z.size / dof)
        / math.sqrt(float(np.sum((s - s.mean()) ** 2)))
    )
    fit_u = level * slope_se / fit.fundamental_hz
    offset_u = 0.5 * abs(fit_resonance_series(z, steps, offset_hz=0.0).level(c) - level)
    dc = float(speed_of_sound(temperature_c + temperature_uncertainty_c, speed_model)) - c
    temp_u = level * abs(dc) / c
    return LevelEstimate(
        level_m=level,
        uncertainty_m=math.sqrt(fit_u**2 + offset_u**2 + temp_u**2),
        fit_uncertainty_m=fit_u,
        offset_uncertainty_m=offset_u,
        temperature_uncertainty_m=temp_u,
        speed_of_sound=c,
        fit=fit,
    )


def filter_levels(
    detection: DetectionResult,
    speed_of_sound: float,
    methods: Sequence[str] = METHODS,
    seed: int = 0,
) -> dict[str, float]:
    """Estimate the level (m) by each method of Table 3 over one recording's resonances.

    The methods: the paper's filter, Nassreddine's, direct, Kalman, particle.

    Parameters
    ----------
    detection : DetectionResult
        The recording's resonances (:func:`dstoolkit.gauge.detect_resonances`).
    speed_of_sound : float
        c, m/s (the paper's eq. 32).
    methods : sequence of str
        Methods to run, keys of Table 3: "dependent_evidence", "nassreddine", "direct",
        "kalman", "particle".
    seed : int
        Seed of the particle filter's random numbers.

    Returns
    -------
    dict of str to float
        The mean level L̂ by each method, m, in the order of ``methods``.

    Raises
    ------
    DetectionError
        Fewer than 3 consecutive resonances.

    See Also
    --------
    analyze : Calls it with its ``methods``.
    dstoolkit.studies.estimate_levels : The level per step by one method.

    References
    ----------
    The paper's eqs. 32 (speed of sound), 39 (the state transition) and 43 (the orders),
    and its Table 3.

    Notes
    -----
    Each method gives a level per step, L̂_k = n_k c/(2 x̂_k) (eq. 32, orders by eq. 43),
    averaged here (:func:`dstoolkit.studies.estimate_levels`, the paper's noise
    evidence of Tables 1–2). The readings are the detector's with the latency corrected but
    the sweep-rate offset κ/(2 f_F) left in: that is how the paper's detector read them and
    how its observation noise w (mode −6.9 Hz) was characterised. Eq. 39 links neighbouring
    resonances, so over a missed one it does not hold: the methods run on the longest run of
    consecutive resonances.

    Examples
    --------
    A recording of a 9.6 m virtual tube, simulated without a sound device:

    >>> from dstoolkit.audio import analyze, filter_levels, simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> found = analyze(rec, methods=())
    >>> levels = filter_levels(found.detection, found.level.speed_of_sound, ["kalman"])
    >>> round(levels["kalman"], 1)
    9.6
    """
    steps = detection.steps
    breaks = np.flatnonzero(np.diff(steps) != 1) + 1
    runs = np.split(np.arange(steps.size), breaks)
    longest = max(runs, key=len)
    if longest.size < 3:
        raise DetectionError(
            f"the filters need at least 3 consecutive resonances; the longest run has "
            f"{longest.size}"
        )
    z = detection.raw_frequencies - detection.latency_offset_hz * detection.corrected[1]
    case = CaseReadings(
        level_m=math.nan,
        temperature_c=math.nan,
        speed_of_sound=speed_of_sound,
        readings=z[longest][None, :],
    )
    orders = estimate_orders(case, "eq43")
    filters = paper_filters(seed)
    return {m: float(np.mean(estimate_levels(m, case, orders, filters))) for m in methods}


# -- analysis of a recording -------------------------------------------------------------------


@dataclass(frozen=True)
class Analysis:
    """A recording analysed: its resonances and the level.

    Parameters
    ----------
    recording : WavRecording
        The recording as read (or as made).
    gauge_recording : Recording
        The part from the moment the sweep was played (τ before it arrives), in the form
        the gauge's detection and plots take.
    detection : DetectionResult
        The resonances found (:func:`dstoolkit.gauge.detect_resonances`).
    level : LevelEstimate
        The level and its uncertainty.
    temperature_c : float
        The air temperature used, °C.
    latency_s : float
        The audio latency τ corrected, s.
    true_level_m : float or None
        The true level when known (virtual tube), m.
    filter_levels : dict of str to float
        The level by each method of Table 3 (:func:`filter_levels`), m; empty when not
        asked.
    notes : tuple of str
        Warnings and assumptions, one line each (missed resonances, an assumed sweep).

    See Also
    --------
    analyze : Makes it.
    """

    recording: WavRecording
    gauge_recording: Recording
    detection: DetectionResult
    level: LevelEstimate
    temperature_c: float
    latency_s: float
    true_level_m: float | None
    filter_levels: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = field(default=())

    @property
    def error_m(self) -> float | None:
        """Measured − true level when the truth is known (virtual tube), else None.

        Returns
        -------
        float or None
            ``level.level_m - true_level_m``, m.
        """
        return None if self.true_level_m is None else self.level.level_m - self.true_level_m

    def summary(self) -> str:
        """Describe the analysis in a few lines of text, as the command line prints it.

        Returns
        -------
        str
            Level ± uncertainty and its parts, the resonances found, missed and spurious,
            temperature and latency, the error against a known level, the levels by method
            and the notes, one per line.
        """
        lv = self.level
        d = self.detection
        lines = [
            f"level L = {lv.level_m:.4f} m ± {lv.uncertainty_m:.4f} m (1 sigma; fit "
            f"{lv.fit_uncertainty_m:.4f}, offsets {lv.offset_uncertainty_m:.4f}, "
            f"temperature {lv.temperature_uncertainty_m:.4f})",
            f"resonances: {d.frequencies.size} found, {d.missed.size} missed"
            + (f" (near {', '.join(f'{f:.0f}' for f in d.missed)} Hz)" if d.missed.size else "")
            + f", {d.spurious.size} spurious; f_F = {d.fundamental_hz:.3f} Hz",
            f"temperature {self.temperature_c:g} °C (c = {lv.speed_of_sound:.2f} m/s), "
            f"audio latency {1e3 * self.latency_s:.1f} ms",
        ]
        error = self.error_m
        if error is not None:
            lines.append(f"true level {self.true_level_m:g} m: error {1e3 * error:+.1f} mm")
        if self.filter_levels:
            lines.append(
                "by method (eq. 32 per step, orders by eq. 43, averaged): "
                + ", ".join(f"{m} {lv_m:.4f} m" for m, lv_m in self.filter_levels.items())
            )
        lines.extend(self.notes)
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Draw the recording with its envelope and peaks (Fig. 6) above the resonances (Fig. 7).

        Needs matplotlib (the ``plots`` extra).

        Returns
        -------
        matplotlib.figure.Figure
            Two panels, not shown (save it with ``savefig``).
        """
        from matplotlib.figure import Figure

        from dstoolkit.plots import plot_recording, plot_resonances

        fig = Figure(figsize=(8.0, 6.4), layout="constrained")
        top, bottom = fig.subplots(2, 1)
        truth = None
        if self.true_level_m is not None:
            f_f = self.level.speed_of_sound / (2.0 * self.true_level_m)
            lo, hi = self.detection.sweep.band
            truth = f_f * np.arange(math.ceil(lo / f_f), math.floor(hi / f_f) + 1)
        title = f"L = {self.level.level_m:.3f} ± {self.level.uncertainty_m:.3f} m"
        if self.true_level_m is not None:
            title += f" (true {self.true_level_m:g} m)"
        plot_recording(self.gauge_recording, self.detection, top, title=title)
        plot_resonances(self.detection, bottom, true_frequencies=truth)
        return fig


def sweep_from_metadata(metadata: RecordingMetadata, samplerate: float) -> LinearSweep | None:
    """Return the sweep a recording's metadata describes, or None when it does not say."""
    m = metadata
    if m.f_start_hz is None or m.f_stop_hz is None or m.sweep_duration_s is None:
        return None
    taper = PAPER_SWEEP.taper if m.sweep_taper_s is None else m.sweep_taper_s
    return LinearSweep(
        f_start=m.f_start_hz,
        f_stop=m.f_stop_hz,
        duration=m.sweep_duration_s,
        sample_rate=float(samplerate),
        taper=taper,
    )


#: Seconds of a recording read after the end of its sweep (the closing chirp and tail);
#: anything later is not analysed, so a long file costs no more than a short one.
ANALYSIS_TAIL_S = 2.0
#: Seconds allowed before the sweep when the metadata does not say where it starts.
UNKNOWN_ONSET_S = 2.0


def _load_for_analysis(path: str | os.PathLike[str]) -> WavRecording:
    """Read the part of a recording that the analysis uses.

    That is up to the sweep's end plus :data:`ANALYSIS_TAIL_S` (the whole file when the
    metadata does not describe the sweep beyond :data:`UNKNOWN_ONSET_S` + the paper's sweep).
    """
    fh, layout = open_recording(path)
    with fh:
        meta = read_metadata(layout.info)
    duration = meta.sweep_duration_s or PAPER_SWEEP.duration
    onset = meta.sweep_onset_s if meta.sweep_onset_s is not None else UNKNOWN_ONSET_S
    end = onset + duration + ANALYSIS_TAIL_S
    # nonsense metadata (a negative onset...): read it all, analyze() says what is wrong
    stop_s = end if 0 < end < math.inf else None
    frames = min(layout.frames, (stop_s or math.inf) * layout.samplerate)
    # the detection works on a few float64 copies of the samples it is given
    check_memory(
        frames * 8 * 24,
        f"analysing {frames / layout.samplerate:.1f} s of {os.fspath(path)!r}",
        "cut the recording to the measurement",
    )
    return load_recording(path, stop_s=stop_s)


def analyze(
    recording: WavRecording | str | os.PathLike[str],
    *,
    temperature_c: float | None = None,
    sweep: LinearSweep | None = None,
    temperature_uncertainty_c: float = DEFAULT_TEMPERATURE_UNCERTAINTY_C,
    speed_model: SpeedModel = "paper",
    methods: Sequence[str] = METHODS,
) -> Analysis:
    """Resonances and level of a recording (a WAV file or a :class:`WavRecording`).

    Parameters
    ----------
    recording : WavRecording or path-like
        Made by :func:`measure` / :func:`simulate_measurement`, or any mono WAV of a sweep.
    temperature_c : float, optional
        Air temperature, °C; default the one in the metadata. One of the two is needed.
    sweep : LinearSweep, optional
        The played sweep; default the metadata's, else the paper's (1000 → 2400 Hz, 5 s).
    temperature_uncertainty_c : float
        Standard uncertainty of the temperature, °C.
    speed_model : {"paper", "ideal_gas", "cramer"}
        How c follows from the temperature (:func:`dstoolkit.gauge.speed_of_sound`).
    methods : sequence of str
        Methods of Table 3 whose level to add (:func:`filter_levels`); () for none.

    Returns
    -------
    Analysis
        The resonances, the level with its uncertainty, the levels by method and notes.

    Notes
    -----
    Where the metadata gives the sweep's onset and the latency, the recording is cut at
    the moment the sweep was played and the latency is corrected; otherwise the sweep is
    assumed to start near the beginning and the latency is estimated from the sweep itself.

    Raises
    ------
    DetectionError
        Silence, clipping, a recording too short for the sweep, no tube echo, or too few
        resonances (:func:`dstoolkit.gauge.detect_resonances`); missed resonances do
        not raise: they are listed and the level uses those that remain.
    RecordingFileError, FileNotFoundError
        An unreadable file.
    InvalidInputError
        No temperature (also a ValueError).

    See Also
    --------
    measure : Record, then analyse.
    simulate_measurement : A recording without a sound device.

    References
    ----------
    The paper's §4: the resonances of the tube, eqs. 32 (speed of sound) and 35 (the
    level from the fundamental).

    Examples
    --------
    >>> from dstoolkit.audio import analyze, simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> found = analyze(rec, methods=())
    >>> round(found.level.level_m, 2), found.detection.frequencies.size
    (9.6, 77)
    >>> abs(found.error_m) < found.level.uncertainty_m
    True
    """
    rec = recording if isinstance(recording, WavRecording) else _load_for_analysis(recording)
    meta = rec.metadata
    notes: list[str] = []
    if temperature_c is None:
        temperature_c = meta.temperature_c
    if temperature_c is None:
        raise InvalidInputError(
            "the temperature is unknown: the recording does not say and none was given; "
            "pass temperature_c (--temperature T on the command line), in °C"
        )
    if sweep is None:
        sweep = sweep_from_metadata(meta, rec.samplerate)
        if sweep is None:
            sweep = LinearSweep(sample_rate=float(rec.samplerate))
            notes.append(
                "note: the recording does not describe its sweep; assumed the "
                "paper's 1000 -> 2400 Hz in 5 s"
            )
    if sweep.sample_rate != rec.samplerate:
        raise InvalidInputError(
            f"the sweep's sample rate {sweep.sample_rate} Hz differs from the "
            f"recording's {rec.samplerate} Hz"
        )
    fs = rec.samplerate
    if meta.sweep_onset_s is not None and meta.latency_s is not None:
        latency: float | None = meta.latency_s
        start_s = meta.sweep_onset_s - meta.latency_s
        if not 0 <= start_s <= rec.duration_s or not 0 <= meta.latency_s < 60:
            raise RecordingFileError(
                f"inconsistent metadata: sweep onset {meta.sweep_onset_s:g} s and latency "
                f"{meta.latency_s:g} s put the sweep's start outside the recording "
                f"(0 to {rec.duration_s:.2f} s)"
            )
        start = int(round(start_s * fs))
    else:
        latency, start = None, 0
    samples = rec.samples[start:]
    needed = (latency or 0.0) + sweep.duration
    if samples.size / fs < needed:
        raise DetectionError(
            f"the recording is too short for the sweep: a {sweep.duration:g} s sweep"
            + (f" after {latency:.3f} s of latency" if latency else "")
            + f" needs {needed:.3g} s from the sweep's start, the recording holds "
            f"{samples.size / fs:.2f} s. Record longer (a tail of silence after the sweep)."
        )
    gauge_rec = Recording(samples=samples, sweep=sweep)
    detection = detect_resonances(gauge_rec, latency_s=latency)
    if detection.missed.size:
        notes.append(
            f"warning: {detection.missed.size} resonance(s) missed near "
            + ", ".join(f"{f:.0f}" for f in detection.missed)
            + " Hz; the level uses the others"
        )
    level = estimate_level(
        detection,
        float(temperature_c),
        temperature_uncertainty_c=temperature_uncertainty_c,
        speed_model=speed_model,
    )
    by_method = filter_levels(detection, level.speed_of_sound, methods) if methods else {}
    return Analysis(
        recording=rec,
        gauge_recording=gauge_rec,
        detection=detection,
        level=level,
        temperature_c=float(temperature_c),
        latency_s=detection.latency_s,
        true_level_m=meta.level_m,
        filter_levels=by_method,
        notes=tuple(notes),
    )


# -- measuring -------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Programme:
    """What a measurement plays after the lead-in: chirp, gap, drive, gap, chirp."""

    signal: np.ndarray
    chirp: np.ndarray
    sweep_offset: int  # index of the drive's first sample in ``signal``
    closing_offset: int  # index of the closing chirp's first sample


def _programme(sweep: LinearSweep, drive: np.ndarray) -> _Programme:
    fs = sweep.sample_rate
    chirp = audio.calibration_chirp(fs)
    gap = np.zeros(int(round(CALIBRATION_GAP_S * fs)))
    sweep_offset = chirp.size + gap.size
    return _Programme(
        np.concatenate([chirp, gap, drive, gap, chirp]),
        chirp,
        sweep_offset,
        sweep_offset + drive.size + gap.size,
    )


def _drive(sweep: LinearSweep, virtual_tube: TubeSetup | None, amplitude: float) -> np.ndarray:
    if virtual_tube is not None:
        return virtual_tube_signal(virtual_tube, sweep, amplitude=amplitude)
    if not 0 < amplitude <= 1:
        raise InvalidInputError(f"amplitude must be in (0, 1], got {amplitude}")
    return amplitude * sweep.waveform()


def _calibrate(
    recorded: np.ndarray, fs: int, lead: int, programme: _Programme
) -> tuple[audio.LatencyEstimate, audio.LatencyEstimate]:
    """Latency at the opening and at the closing chirp.

    Raises DetectionError when neither chirp is heard (the input does not hear the output),
    AudioDropoutError when only one of them is heard (the same wiring carried the other, so
    the stream lost or silenced samples in between) or when their latencies disagree by more
    than MAX_LATENCY_DRIFT_S (samples were lost or inserted in between).
    """
    found = [
        audio.estimate_latency(
            programme.chirp, recorded, fs, offset=lead + offset, max_latency_s=audio.MIN_PADDING_S
        )
        for offset in (0, programme.closing_offset)
    ]
    missing = []
    for name, estimate in zip(("opening", "closing"), found, strict=True):
        try:
            audio.check_calibration(estimate)
        except DetectionError as exc:
            missing.append((name, estimate.correlation, exc))
    if len(missing) == len(found):
        raise missing[0][2]
    if missing:
        name, correlation, _ = missing[0]
        heard = "closing" if name == "opening" else "opening"
        raise AudioDropoutError(
            f"the audio stream lost samples during the measurement: the {heard} calibration "
            f"chirp was heard but the {name} one was not (correlation {correlation:.2f})"
        )
    opening, closing = found
    if abs(closing.seconds - opening.seconds) > MAX_LATENCY_DRIFT_S:
        raise AudioDropoutError(
            f"the audio stream lost or inserted samples during the measurement: the latency "
            f"was {1e3 * opening.seconds:.1f} ms at the start and {1e3 * closing.seconds:.1f} "
            f"ms at the end (more than {1e3 * MAX_LATENCY_DRIFT_S:g} ms apart)"
        )
    return opening, closing


def _recording(
    recorded: np.ndarray,
    fs: int,
    lead: int,
    programme: _Programme,
    sweep: LinearSweep,
    temperature_c: float,
    virtual_tube: TubeSetup | None,
    source: str,
    extra: dict[str, object],
) -> WavRecording:
    opening, closing = _calibrate(recorded, fs, lead, programme)
    onset = (lead + programme.sweep_offset + opening.lag) / fs
    metadata = RecordingMetadata(
        temperature_c=temperature_c,
        f_start_hz=sweep.f_start,
        f_stop_hz=sweep.f_stop,
        sweep_duration_s=sweep.duration,
        sweep_taper_s=sweep.taper,
        sweep_onset_s=onset,
        latency_s=opening.seconds,
        level_m=None if virtual_tube is None else virtual_tube.level_m,
        source=source,
        extra={
            "calibration_correlation": round(opening.correlation, 6),
            "latency_at_end_s": closing.seconds,
            **extra,
        },
    )
    return WavRecording(samples=recorded, samplerate=fs, metadata=metadata)


def _samplerate(sweep: LinearSweep) -> int:
    if sweep.sample_rate != int(sweep.sample_rate):
        raise InvalidInputError(
            f"the sweep's sample rate must be a whole number of Hz for audio, "
            f"got {sweep.sample_rate}"
        )
    return int(sweep.sample_rate)


def record_measurement(
    temperature_c: float | None = None,
    *,
    sweep: LinearSweep = PAPER_SWEEP,
    input_device: int | str | None = None,
    output_device: int | str | None = None,
    virtual_tube: TubeSetup | None = None,
    amplitude: float = DEFAULT_AMPLITUDE,
    latency: float | Literal["low", "high"] = audio.DEFAULT_LATENCY_S,
    save: str | os.PathLike[str] | None = None,
    overwrite: bool = False,
    attempts: int = 3,
) -> WavRecording:
    """Play the programme (module docstring) and record it; return the recording.

    A recording in which the stream dropped samples (PortAudio reports an xrun, or the two
    chirps give different latencies) is discarded and the measurement repeated, up to
    ``attempts`` times in all. A silent recording (all zeros) is tried once more within
    those attempts: a busy sound server may deliver one silent take while it starts a
    stream; a second silent take raises :class:`~dstoolkit.errors.DetectionError` with the
    reason.

    Parameters
    ----------
    temperature_c : float, optional
        What the thermometer says, °C (stored in the metadata); with a ``virtual_tube`` it
        defaults to the tube's.
    sweep : LinearSweep
        The sweep to play (default the paper's, 1000 → 2400 Hz in 5 s); its sample rate
        must be a whole number of Hz.
    input_device, output_device : int or str, optional
        Index or (part of a) name, see :func:`list_devices`; None for the defaults.
    virtual_tube : TubeSetup, optional
        Play the sweep as heard through this tube (with a loopback the recording is then
        a tube's); None plays the bare sweep.
    amplitude : float
        Peak of the played signal, full scale.
    latency : float or str
        PortAudio's suggested latency, s (or "low"/"high").
    save : path-like, optional
        Write the recording there (WAV with metadata).
    overwrite : bool
        Replace an existing ``save`` file; otherwise it is refused before anything is
        played.
    attempts : int
        How many recordings to try in all when samples are dropped.

    Returns
    -------
    WavRecording
        The samples from the start of the programme and their metadata (temperature,
        sweep, onset, latency, the true level of a virtual tube).

    Raises
    ------
    AudioUnavailableError
        No sounddevice/PortAudio, or no device (the message says what to do).
    DetectionError
        A calibration chirp is not in the recording: the input does not hear the output
        (or two takes were silent).
    AudioDropoutError
        Samples were dropped in every attempt.
    InvalidInputError
        No temperature, fewer than one attempt, or a sweep whose sample rate is not a whole
        number; checked before any device is opened.
    OutputExistsError
        ``save`` exists and ``overwrite`` is False.

    See Also
    --------
    simulate_measurement : The same recording through a simulated loopback.
    measure : Record, then analyse.

    Examples
    --------
    The settings are checked before any device is opened (without a sound device, use
    :func:`simulate_measurement`):

    >>> from dstoolkit.audio import record_measurement
    >>> record_measurement()
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: give the air temperature (temperature_c, °C)
    """
    if temperature_c is None:
        if virtual_tube is None:
            raise InvalidInputError("give the air temperature (temperature_c, °C)")
        temperature_c = virtual_tube.temperature_c
    if save is not None:
        check_outputs({"the recording": save}, overwrite=overwrite)
    if attempts < 1:
        raise InvalidInputError(f"attempts must be at least 1, got {attempts}")
    fs = _samplerate(sweep)
    programme = _programme(sweep, _drive(sweep, virtual_tube, amplitude))
    problems: list[str] = []
    silent_takes = 0
    for attempt in range(1, attempts + 1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", audio.AudioDropoutWarning)
            result = audio.play_record(
                programme.signal,
                fs,
                input_device=input_device,
                output_device=output_device,
                latency=latency,
            )
        names = {d.index: d.name for d in audio.list_devices()}
        source = (
            f"{'virtual tube via ' if virtual_tube is not None else ''}"
            f"{names.get(result.output_device, result.output_device)} -> "
            f"{names.get(result.input_device, result.input_device)}"
        )
        try:
            if result.dropped_samples:
                raise AudioDropoutError(f"PortAudio reported {result.status}")
            recording = _recording(
                result.recorded,
                fs,
                result.signal_start,
                programme,
                sweep,
                float(temperature_c),
                virtual_tube,
                source,
                {
                    "latency_setting": result.latency_setting,
                    "stream_status": result.status,
                    "attempt": attempt,
                },
            )
        except AudioDropoutError as exc:
            problems.append(f"attempt {attempt}: {exc}")
            continue
        except DetectionError:
            audio.check_sound_server()  # a dead server is not a wiring problem
            if np.any(result.recorded) or attempt == attempts or silent_takes:
                raise
            # One silent take is tried again: a sound server under load may deliver silence
            # for a take while it (re)starts a stream; a second silent take is the wiring.
            silent_takes += 1
            problems.append(f"attempt {attempt}: the recording was silent")
            continue
        if save is not None:
            save_recording(save, recording.samples, fs, recording.metadata, overwrite=overwrite)
        return recording
    raise AudioDropoutError(
        "the audio stream dropped samples in every attempt (" + "; ".join(problems) + "). "
        "Use a larger latency setting (e.g. 0.5 s) and close other programs using audio "
        "or the processor."
    )


def measure(
    temperature_c: float | None = None,
    *,
    sweep: LinearSweep = PAPER_SWEEP,
    input_device: int | str | None = None,
    output_device: int | str | None = None,
    virtual_tube: TubeSetup | None = None,
    amplitude: float = DEFAULT_AMPLITUDE,
    latency: float | Literal["low", "high"] = audio.DEFAULT_LATENCY_S,
    save: str | os.PathLike[str] | None = None,
    overwrite: bool = False,
    temperature_uncertainty_c: float = DEFAULT_TEMPERATURE_UNCERTAINTY_C,
) -> Analysis:
    """Measure a level: :func:`record_measurement` then :func:`analyze`.

    Parameters
    ----------
    temperature_c : float, optional
        What the thermometer says, °C; with a ``virtual_tube`` it defaults to the tube's.
    sweep : LinearSweep
        The sweep to play (default the paper's).
    input_device, output_device : int or str, optional
        Index or (part of a) name, see :func:`list_devices`; None for the defaults.
    virtual_tube : TubeSetup, optional
        Play the sweep as heard through this tube; None plays the bare sweep.
    amplitude : float
        Peak of the played signal, full scale.
    latency : float or str
        PortAudio's suggested latency, s (or "low"/"high").
    save : path-like, optional
        Write the recording there; never replaces an existing file unless
        ``overwrite=True``.
    overwrite : bool
        Replace an existing ``save`` file.
    temperature_uncertainty_c : float
        Standard uncertainty of the temperature, °C.

    Returns
    -------
    Analysis
        The level with its uncertainty and the resonances.

    Raises
    ------
    AudioUnavailableError
        No sounddevice/PortAudio, or no device.
    DetectionError
        The input does not hear the output, or too few resonances.
    AudioDropoutError
        Samples were dropped in every attempt.
    InvalidInputError
        No temperature; checked before any device is opened.

    See Also
    --------
    record_measurement, analyze : Its two steps.
    simulate_measurement : A recording without a sound device.

    Examples
    --------
    Without a sound device, the same two steps run on a simulated recording:

    >>> from dstoolkit.audio import analyze, simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> found = analyze(simulate_measurement(TubeSetup(level_m=4.0, temperature_c=15.0)),
    ...                 methods=())
    >>> round(found.level.level_m, 2)
    4.0
    """
    recording = record_measurement(
        temperature_c,
        sweep=sweep,
        input_device=input_device,
        output_device=output_device,
        virtual_tube=virtual_tube,
        amplitude=amplitude,
        latency=latency,
        save=save,
        overwrite=overwrite,
    )
    return analyze(recording, temperature_uncertainty_c=temperature_uncertainty_c)


def simulate_measurement(
    virtual_tube: TubeSetup,
    *,
    temperature_c: float | None = None,
    sweep: LinearSweep = PAPER_SWEEP,
    latency_s: float = 0.1,
    noise_rms: float = 0.0,
    amplitude: float = DEFAULT_AMPLITUDE,
    seed: int = 0,
) -> WavRecording:
    """Simulate the recording :func:`record_measurement` would make through a perfect loopback.

    The loopback has latency ``latency_s`` (a pure delay, plus white noise of ``noise_rms``
    full scale), with no audio at all. Same programme, same latency estimation, same
    metadata.

    Parameters
    ----------
    virtual_tube : TubeSetup
        The tube the sweep is heard through (its level is stored as the true level).
    temperature_c : float, optional
        The temperature stored in the metadata, °C; default the tube's.
    sweep : LinearSweep
        The sweep played (default the paper's).
    latency_s : float
        The loopback's delay, s, in [0, ``MIN_PADDING_S``).
    noise_rms : float
        RMS of the white noise added, full scale.
    amplitude : float
        Peak of the played signal, full scale.
    seed : int
        Seed of the noise.

    Returns
    -------
    WavRecording
        The samples from the start of the programme and their metadata.

    Raises
    ------
    InvalidInputError
        A latency outside [0, ``MIN_PADDING_S``).

    See Also
    --------
    record_measurement : The same with a sound device.
    analyze : Finds the level in it.

    Examples
    --------
    >>> from dstoolkit.audio import simulate_measurement
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> rec.samplerate, rec.metadata.level_m, rec.metadata.latency_s
    (44100, 9.6, 0.1)
    """
    if not 0 <= latency_s < audio.MIN_PADDING_S:
        raise InvalidInputError(
            f"latency_s must be in [0, {audio.MIN_PADDING_S}) s, got {latency_s}"
        )
    fs = _samplerate(sweep)
    programme = _programme(sweep, _drive(sweep, virtual_tube, amplitude))
    lead = tail = int(round(audio.MIN_PADDING_S * fs))
    # the programme between silences of lead and tail, heard delay samples late (delay ≤ tail)
    delay = int(round(latency_s * fs))
    recorded = np.zeros(lead + programme.signal.size + tail)
    recorded[delay + lead : delay + lead + programme.signal.size] = programme.signal
    if noise_rms > 0:
        recorded += noise_rms * np.random.default_rng(seed).standard_normal(recorded.size)
    return _recording(
        recorded,
        fs,
        lead,
        programme,
        sweep,
        virtual_tube.temperature_c if temperature_c is None else temperature_c,
        virtual_tube,
        "virtual tube, simulated audio (no device)",
        {"simulated_latency_s": latency_s},
    )


# -- command line ----------------------------------------------------------------------------


def _device(text: str | None) -> int | str | None:
    return int(text) if text is not None and text.strip().isdigit() else text


def add_measure_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of ``python -m dstoolkit measure`` to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Gains ``--temperature`` (required), ``--input``, ``--output``, ``--save``,
        ``--figure``, ``--virtual-level``, ``--latency``, ``--list-devices`` and
        ``--overwrite``.

    See Also
    --------
    measure_command : Runs the parsed options.

    Examples
    --------
    >>> import argparse
    >>> from dstoolkit.audio import add_measure_arguments
    >>> parser = argparse.ArgumentParser()
    >>> add_measure_arguments(parser)
    >>> args = parser.parse_args(["--temperature", "20", "--virtual-level", "9.6"])
    >>> args.temperature, args.virtual_level, args.figure
    (20.0, 9.6, 'measurement.png')
    """
    parser.add_argument(
        "--temperature",
        type=float,
        required=True,
        metavar="T",
        help="air temperature in the tube, °C",
    )
    parser.add_argument("--input", metavar="DEV", help="input device index or name")
    parser.add_argument("--output", metavar="DEV", help="output device index or name")
    parser.add_argument("--save", metavar="REC.wav", help="save the recording (WAV + metadata)")
    parser.add_argument(
        "--figure",
        default="measurement.png",
        metavar="PATH",
        help="where to save the figure (default: %(default)s)",
    )
    parser.add_argument(
        "--virtual-level",
        type=float,
        metavar="L",
        help="play through a virtual tube of level L m instead of the bare "
        "sweep (with a loopback: scripts/audio-loopback.sh)",
    )
    parser.add_argument(
        "--latency",
        type=float,
        default=audio.DEFAULT_LATENCY_S,
        metavar="S",
        help="PortAudio latency setting, s (default %(default)s)",
    )
    parser.add_argument(
        "--list-devices", action="store_true", help="list the sound devices and exit"
    )
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace existing files (the recording, the figure)",
    )


def add_analyze_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of ``python -m dstoolkit analyze`` to ``parser``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Gains the positional ``recording`` and ``--temperature``, ``--figure`` and
        ``--overwrite``.

    See Also
    --------
    analyze_command : Runs the parsed options.

    Examples
    --------
    >>> import argparse
    >>> from dstoolkit.audio import add_analyze_arguments
    >>> parser = argparse.ArgumentParser()
    >>> add_analyze_arguments(parser)
    >>> args = parser.parse_args(["rec.wav", "--temperature", "18.5"])
    >>> args.recording, args.temperature, args.figure
    ('rec.wav', 18.5, None)
    """
    parser.add_argument("recording", metavar="REC.wav", help="a recording (WAV)")
    parser.add_argument(
        "--temperature",
        type=float,
        metavar="T",
        help="air temperature, °C (default: the recording's metadata)",
    )
    parser.add_argument(
        "--figure", metavar="PATH", help="where to save the figure (default: REC.png)"
    )
    parser.add_argument("--overwrite", action="store_true", help="replace an existing figure")


def _report(analysis: Analysis, figure: Path, command: str) -> None:
    print(analysis.summary())
    fig = analysis.figure()
    atomic_write(
        figure, lambda fh: fig.savefig(fh, format="png", dpi=120, metadata=figure_tag(command))
    )
    print(f"figure saved to {figure}")


def _fail(exc: BaseException) -> int:
    print(f"error: {exc}", file=sys.stderr)
    return 1


def _figure_check(command: str) -> Callable[[Path], bool]:
    """Allow replacing an existing figure when the same command made it."""
    return lambda path: path.suffix.lower() == ".png" and made_by(path, command)


def measure_command(args: argparse.Namespace) -> int:
    """``python -m dstoolkit measure``: measure, print level ± uncertainty, save a figure.

    The output paths are checked before the measurement starts; none replaces a file
    unless ``--overwrite`` (a figure an earlier ``measure`` made may be replaced).

    Parameters
    ----------
    args : argparse.Namespace
        Options parsed by a parser that :func:`add_measure_arguments` set up.

    Returns
    -------
    int
        The exit status: 0 done, 1 with a one-line message on stderr.

    See Also
    --------
    measure : What it runs.

    Examples
    --------
    An existing recording is not replaced: the command stops before it plays anything.

    >>> import argparse, os, tempfile
    >>> from dstoolkit.audio import add_measure_arguments, measure_command
    >>> parser = argparse.ArgumentParser()
    >>> add_measure_arguments(parser)
    >>> folder = tempfile.mkdtemp()
    >>> kept = os.path.join(folder, "rec.wav")
    >>> open(kept, "w").close()
    >>> measure_command(parser.parse_args(["--temperature", "20", "--save", kept,
    ...                                    "--figure", os.path.join(folder, "m.png")]))
    1
    >>> os.path.getsize(kept)
    0
    """
    try:
        if args.list_devices:
            for device in audio.list_devices():
                print(device)
            return 0
        outputs = {"the figure (--figure)": args.figure}
        if args.save:
            outputs = {"the recording (--save)": args.save, **outputs}
        paths = check_outputs(
            outputs, overwrite=args.overwrite, replaceable=_figure_check("measure")
        )
        setup = (
            None
            if args.virtual_level is None
            else TubeSetup(level_m=args.virtual_level, temperature_c=args.temperature)
        )
        analysis = measure(
            args.temperature,
            input_device=_device(args.input),
            output_device=_device(args.output),
            virtual_tube=setup,
            latency=args.latency,
            save=args.save,
            overwrite=True,
        )
        if args.save:
            print(f"recording saved to {args.save}")
        _report(analysis, paths["the figure (--figure)"], "measure")
    except (DstoolkitError, OSError) as exc:
        return _fail(exc)
    return 0


def analysis_figure_path(recording: str | os.PathLike[str]) -> Path:
    """Return the default figure of ``analyze REC``.

    That is REC with the suffix .png, or REC.png when the recording itself ends in .png (an
    output never replaces its input).
    """
    path = Path(recording)
    figure = path.with_suffix(".png")
    return path.with_name(path.name + ".png") if figure.name == path.name else figure


def analyze_command(args: argparse.Namespace) -> int:
    """``python -m dstoolkit analyze REC.wav``: print level ± uncertainty, save a figure.

    The figure never replaces the recording, nor an existing file unless ``--overwrite``
    (or an earlier ``analyze`` made it); it is checked before the analysis starts.

    Parameters
    ----------
    args : argparse.Namespace
        Options parsed by a parser that :func:`add_analyze_arguments` set up.

    Returns
    -------
    int
        The exit status: 0 done, 1 with a one-line message on stderr.

    See Also
    --------
    analyze : What it runs.

    Examples
    --------
    A simulated recording, saved and analysed (no sound device):

    >>> import argparse, os, tempfile
    >>> from dstoolkit.audio import (add_analyze_arguments, analyze_command,
    ...                              save_recording, simulate_measurement)
    >>> from dstoolkit.gauge import TubeSetup
    >>> rec = simulate_measurement(TubeSetup(level_m=9.6, temperature_c=20.0))
    >>> path = os.path.join(tempfile.mkdtemp(), "rec.wav")
    >>> save_recording(path, rec.samples, rec.samplerate, rec.metadata)
    >>> parser = argparse.ArgumentParser()
    >>> add_analyze_arguments(parser)
    >>> analyze_command(parser.parse_args([path]))
    level L = 9.59... m ± 0.00... m (1 sigma; ...)
    ...
    figure saved to ...rec.png
    0
    """
    try:
        figure = args.figure or analysis_figure_path(args.recording)
        paths = check_outputs(
            {"the figure": figure},
            inputs=[args.recording],
            overwrite=args.overwrite,
            replaceable=_figure_check("analyze"),
        )
        analysis = analyze(args.recording, temperature_c=args.temperature)
        _report(analysis, paths["the figure"], "analyze")
    except (DstoolkitError, OSError) as exc:
        return _fail(exc)
    return 0
