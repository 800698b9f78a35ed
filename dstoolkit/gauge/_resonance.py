"""Resonance frequencies from a recording of the sweep (paper eqs. 27–30, §4.3, Figs. 6–7).

The chain: check the recording (silence, clipping); find the latency τ (cross-correlation
with the sweep); take the envelope; read time as instantaneous frequency; find the peaks
with sub-sample precision; place them on the lattice of spacing f_F to find missed and
spurious ones; remove the two offsets below.

Offsets (paper §4.1). With the speaker's phase φ(u) = 2π(f₀u + κu²/2) and the surface echo
Δ = 2L/c later, the microphone hears cos φ(u) + a cos φ(u − Δ), whose envelope is
|1 + a e^(−iθ)| with θ(u) = φ(u) − φ(u − Δ) = 2πΔ (f(u) − κΔ/2). It peaks at θ = 2πn, where
the instantaneous frequency is

    f(u) = n/Δ + κΔ/2 = n c/(2L) + κ L/c.

The recording starts τ before the sweep (audio latency), so recording time t = u + τ read
as f₀ + κ t is a further κ τ high. Both offsets are common to every resonance: the spacing
f_F is unchanged, and since κL/c = κ/(2 f_F) the first is known from the spacing alone.
With κ = 280 Hz/s it is 1.0 Hz at 1.3 m and 7.8 Hz at 9.6 m; 10 ms of latency adds 2.8 Hz.
Later echoes (m ≥ 2, :mod:`dstoolkit.gauge`) carry θ_m = m θ − π κ Δ² m(m − 1): their own
peaks sit at m κ L/c, and they pull the envelope's peak by a systematic amount this
first-order correction leaves (with R_t = 0.3: +1.4, +2.3, −0.6 Hz at 1.3, 4.6, 9.6 m;
:func:`model_peak_frequencies` computes it). Tolerances: tests/test_tube_and_detection.py.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from dstoolkit.errors import DetectionError

from ._latency import estimate_latency
from ._sweep import LinearSweep
from ._tube import Recording, RecordingConditions, TubeSetup, model_envelope

#: Speed of sound bounds used only to turn a level range into a spacing range, m/s.
_C_RANGE = (300.0, 370.0)


@dataclass(frozen=True)
class DetectionResult:
    """Resonances found in one recording, made by :func:`detect_resonances`.

    Parameters
    ----------
    frequencies : numpy.ndarray, shape (K,)
        The resonance frequencies z_k, Hz, ascending, with spurious peaks removed and the
        selected offsets subtracted: the observations of eq. (40).
    steps : numpy.ndarray of int, shape (K,)
        Their relative orders 0, 1, 2, … with a jump where a resonance was missed.
    amplitudes : numpy.ndarray, shape (K,)
        The envelope at each peak, full-scale units.
    raw_frequencies : numpy.ndarray, shape (K,)
        f_0 + κ t at the peak times, Hz, before any correction.
    peak_times : numpy.ndarray, shape (K,)
        Recording times of the peaks, s.
    fundamental_hz : float
        The spacing f_F of the resonances, Hz.
    sweep_rate_offset_hz : float
        κ/(2 f_F), Hz: how far above n f_F the envelope of a sweep peaks.
    latency_offset_hz : float
        κ τ, Hz: how far the latency moves the readings.
    latency_s : float
        The latency τ, s.
    missed : numpy.ndarray, shape (M,)
        Frequencies where a resonance was expected but not found (a gap of about 2 f_F), Hz.
    spurious : numpy.ndarray, shape (S,)
        Rejected peaks (off the lattice, or a second peak of one order), Hz.
    envelope_times : numpy.ndarray, shape (E,)
        Times of the envelope's samples, s.
    envelope : numpy.ndarray, shape (E,)
        The envelope, full-scale units.
    sweep : LinearSweep
        The sweep that was played.
    corrected : tuple of bool, optional
        Whether the sweep-rate and the latency offsets were subtracted.

    See Also
    --------
    detect_resonances : Makes it.
    fit_resonance_series : Uses ``frequencies`` and ``steps``.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.1 and §4.3, Figs. 6–7.
    """

    frequencies: np.ndarray
    steps: np.ndarray
    amplitudes: np.ndarray
    raw_frequencies: np.ndarray
    peak_times: np.ndarray
    fundamental_hz: float
    sweep_rate_offset_hz: float
    latency_offset_hz: float
    latency_s: float
    missed: np.ndarray
    spurious: np.ndarray
    envelope_times: np.ndarray = field(repr=False)
    envelope: np.ndarray = field(repr=False)
    sweep: LinearSweep = field(repr=False)
    corrected: tuple[bool, bool] = (True, True)

    @property
    def complete(self) -> bool:
        """True when no resonance is missing between the first and the last."""
        return self.missed.size == 0

    @property
    def offset_hz(self) -> float:
        """Total offset subtracted from ``raw_frequencies``, Hz."""
        return (
            self.sweep_rate_offset_hz * self.corrected[0]
            + self.latency_offset_hz * self.corrected[1]
        )

    def summary(self) -> str:
        """One line: the number of resonances, f_F, the offsets, τ, the missed and spurious peaks.

        Returns
        -------
        str
            The line.
        """
        return (
            f"{self.frequencies.size} resonances, f_F = {self.fundamental_hz:.3f} Hz, "
            f"offsets κ/(2f_F) = {self.sweep_rate_offset_hz:.3f} Hz, "
            f"κτ = {self.latency_offset_hz:.3f} Hz (τ = {1e3 * self.latency_s:.2f} ms), "
            f"{self.missed.size} missed, {self.spurious.size} spurious"
        )


def sweep_rate_offset(rate_hz_per_s: float, fundamental_hz: Any) -> np.ndarray | float:
    """Compute the sweep-rate offset κ L/c = κ/(2 f_F): how far above n f_F the envelope peaks.

    Parameters
    ----------
    rate_hz_per_s : float
        The sweep rate κ, Hz/s.
    fundamental_hz : float or array_like, any shape
        The spacing f_F of the resonances, Hz.

    Returns
    -------
    numpy.ndarray or float
        The offset, Hz, shaped as ``fundamental_hz``.

    See Also
    --------
    latency_offset : The other offset of a detected resonance.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.1 (the offset of the detected resonances).

    Examples
    --------
    The paper's sweep (280 Hz/s) at 9.6 m (f_F = 18 Hz):

    >>> from dstoolkit.gauge import sweep_rate_offset
    >>> round(float(sweep_rate_offset(280.0, 18.0)), 2)
    7.78
    """
    return rate_hz_per_s / (2.0 * np.asarray(fundamental_hz, dtype=float))


def latency_offset(rate_hz_per_s: float, latency_s: float) -> float:
    """Compute the latency offset κ τ: how far τ moves frequencies read as f_0 + κ t.

    Parameters
    ----------
    rate_hz_per_s : float
        The sweep rate κ, Hz/s.
    latency_s : float
        The latency τ, s.

    Returns
    -------
    float
        The offset, Hz.

    See Also
    --------
    sweep_rate_offset : The other offset.
    estimate_latency : Measures τ.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.

    Examples
    --------
    >>> from dstoolkit.gauge import latency_offset
    >>> round(latency_offset(280.0, 0.01), 6)
    2.8
    """
    return rate_hz_per_s * latency_s


def parabolic_peak(y: np.ndarray, i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sub-sample position and height of peaks from the parabola through three samples.

    Parameters
    ----------
    y : numpy.ndarray, shape (N,)
        The sampled curve.
    i : numpy.ndarray of int, shape (P,)
        Indices of the peaks.

    Returns
    -------
    position : numpy.ndarray, shape (P,)
        Fractional indices of the vertices.
    height : numpy.ndarray, shape (P,)
        Heights of the vertices.
    """
    i = np.clip(np.asarray(i, dtype=int), 1, y.size - 2)
    a, b, c = y[i - 1], y[i], y[i + 1]
    den = a - 2.0 * b + c
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(den < 0, 0.5 * (a - c) / den, 0.0)
    d = np.clip(d, -0.5, 0.5)
    return i + d, b - 0.25 * (a - c) * d


def fitted_peak(
    y: np.ndarray, i: np.ndarray, half_width: int, iterations: int = 2
) -> tuple[np.ndarray, np.ndarray]:
    """Sub-sample peaks from a parabola fitted by least squares within ±``half_width`` samples.

    With ``half_width`` = 1 this is the 3-point :func:`parabolic_peak`; a wider window averages
    the envelope's noise over the top of the peak.

    Parameters
    ----------
    y : numpy.ndarray, shape (N,)
        The sampled curve.
    i : numpy.ndarray of int, shape (P,)
        Indices of the peaks.
    half_width : int
        Half-width of the fit window, samples.
    iterations : int, optional
        Times the window is recentred on the vertex (default 2).

    Returns
    -------
    position : numpy.ndarray, shape (P,)
        Fractional indices of the vertices.
    height : numpy.ndarray, shape (P,)
        Heights of the vertices.
    """
    h = max(1, int(half_width))
    offsets = np.arange(-h, h + 1)
    design = np.stack([offsets**2, offsets, np.ones_like(offsets)], axis=1).astype(float)
    solve = np.linalg.pinv(design)  # (3, 2h+1), shared by every peak
    centre = np.asarray(i, dtype=int)
    pos = centre.astype(float)
    height = y[np.clip(centre, 0, y.size - 1)]
    for _ in range(max(1, iterations)):
        centre = np.clip(np.round(pos).astype(int), h, y.size - 1 - h)
        a, b, c = solve @ y[centre[:, None] + offsets[None, :]].T
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(a < 0, -b / (2.0 * a), 0.0)
        d = np.clip(d, -h, h)
        pos, height = centre + d, c + b * d + a * d * d
    return pos, height


def _prominent_peaks(
    env: np.ndarray, distance: int, expected: int, rel_prominence: float, inside: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Prominent local maxima of ``env``: indices and prominences.

    The maxima lie at least ``distance`` samples apart and ``inside`` (a mask), and their
    prominence reaches ``rel_prominence`` × the median prominence of the ``expected`` most
    prominent ones. Prominences are taken on the whole envelope, so a peak near the edge
    of the mask keeps its true valleys.
    """
    cand, props = signal.find_peaks(env, distance=distance, prominence=0.0)
    prom = props["prominences"]
    cand, prom = cand[inside[cand]], prom[inside[cand]]
    strongest = np.sort(prom)[::-1][:expected]
    thr = rel_prominence * (float(np.median(strongest)) if strongest.size else 0.0)
    sel = prom >= thr
    return cand[sel], prom[sel]


def _check_levels(
    x: np.ndarray, silence_dbfs: float, clip_level: float, max_clipped_fraction: float
) -> None:
    if x.ndim != 1 or x.size == 0:
        raise DetectionError(f"expected a 1-D recording, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise DetectionError("the recording contains NaN or infinite samples")
    rms = float(np.sqrt(np.mean(x * x)))
    level = 20.0 * np.log10(rms) if rms > 0 else -np.inf
    if level < silence_dbfs:
        raise DetectionError(
            f"silence: the recording's RMS level is {level:.1f} dBFS, below {silence_dbfs} "
            "dBFS; check that the speaker plays, the microphone is connected and the input "
            "gain is up"
        )
    clipped = float(np.mean(np.abs(x) >= clip_level))
    if clipped > max_clipped_fraction:
        raise DetectionError(
            f"clipping: {100 * clipped:.2f} % of the samples reach full scale "
            f"(|x| >= {clip_level}); lower the speaker volume or the input gain and record "
            "again"
        )


@functools.lru_cache(maxsize=1)
def _demodulator(sweep: LinearSweep, n: int, latency_s: float) -> np.ndarray:
    """Compute the demodulator e^(−iφ(t − τ)) at the ``n`` sample times t of a recording.

    It moves the sweep to 0 Hz (:func:`envelope`). Kept for the next recording of the same
    length and latency (read-only): an explorer's next render. Only the last one is kept,
    16 bytes a sample (5 MiB for a measurement at 44.1 kHz).
    """
    carrier = np.exp(-1j * sweep.phase(np.arange(n) / sweep.sample_rate - latency_s))
    carrier.flags.writeable = False
    return carrier


@functools.lru_cache(maxsize=2)
def _sweep_waveform(sweep: LinearSweep) -> np.ndarray:
    """Compute the sweep's drive signal (:meth:`LinearSweep.waveform`), kept (read-only).

    It is the reference in which :func:`detect_resonances` finds the latency.
    """
    waveform = sweep.waveform()
    waveform.flags.writeable = False
    return waveform


def envelope(
    samples: np.ndarray,
    sweep: LinearSweep,
    latency_s: float = 0.0,
    bandwidth_hz: float = 200.0,
    envelope_rate_hz: float = 1000.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Envelope of a recording of the sweep, tracking the sweep's frequency.

    The recording is multiplied by e^(−iφ(t − τ)) (the sweep moves to 0 Hz, the echoes to
    beats at m κ Δ Hz), low-passed at ``bandwidth_hz`` (zero-phase Butterworth, order 4) and
    its magnitude doubled: the Hilbert envelope restricted to a band that follows the sweep,
    which rejects noise outside ±``bandwidth_hz`` of the instantaneous frequency.

    Parameters
    ----------
    samples : numpy.ndarray, shape (n,)
        The recording, full-scale units.
    sweep : LinearSweep
        The sweep that was played.
    latency_s : float, optional
        The latency τ, s (default 0).
    bandwidth_hz : float, optional
        Bandwidth of the low-pass, Hz (default 200).
    envelope_rate_hz : float, optional
        About how many envelope samples per second to return (default 1000).

    Returns
    -------
    times : numpy.ndarray, shape (E,)
        Recording times of the envelope's samples, s.
    envelope : numpy.ndarray, shape (E,)
        The envelope, full-scale units.

    See Also
    --------
    detect_resonances : Finds the resonances as the envelope's peaks.
    model_envelope : The noise-free envelope of the model.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(29), Figs. 6–7.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.gauge import LinearSweep, envelope
    >>> sweep = LinearSweep(1000.0, 1200.0, duration=0.5, sample_rate=8000.0)
    >>> t, env = envelope(0.5 * sweep.waveform(), sweep)
    >>> round(float(np.median(env)), 3)
    0.5
    """
    fs = sweep.sample_rate
    carrier = _demodulator(sweep, samples.size, latency_s)
    sos = signal.butter(4, bandwidth_hz, fs=fs, output="sos")
    step = max(1, int(fs // max(envelope_rate_hz, 4.0 * bandwidth_hz)))
    # the filter is real and linear: the real and imaginary parts of the demodulated
    # recording are filtered one after the other (the same numbers, half the memory)
    base = np.empty(-(-samples.size // step), dtype=complex)
    base.real = signal.sosfiltfilt(sos, samples * carrier.real)[::step]
    base.imag = signal.sosfiltfilt(sos, samples * carrier.imag)[::step]
    return np.arange(0, samples.size, step) / fs, 2.0 * np.abs(base)


def _spacing_from_envelope(
    freqs: np.ndarray, env: np.ndarray, fF_range: tuple[float, float], min_line: float
) -> tuple[float, float]:
    """Spacing f_F of the envelope's periodic pattern, and the pattern's strength.

    The spacing is the strongest line of the pattern; its strength is relative to the
    median line in the search range.
    """
    df = freqs[1] - freqs[0]
    y = env**2
    y = (y - np.polyval(np.polyfit(freqs, y, 2), freqs)) * np.hanning(y.size)
    nfft = sp_fft.next_fast_len(8 * y.size)
    power = np.abs(np.fft.rfft(y, nfft)) ** 2
    q = np.fft.rfftfreq(nfft, df)  # "quefrency": periods per Hz, = Δ in seconds
    band = np.nonzero((q >= 1.0 / fF_range[1]) & (q <= 1.0 / fF_range[0]))[0]
    if band.size < 3:
        raise DetectionError(
            "the swept band is too narrow to see the resonance pattern for the level range "
            "asked; widen the sweep or narrow level_range_m"
        )
    i = band[np.argmax(power[band])]
    strength = float(power[i] / max(np.median(power[band]), 1e-300))
    if strength < min_line:
        raise DetectionError(
            f"no tube echo: the envelope has no periodic resonance pattern (strongest line "
            f"{strength:.1f} times the median, need {min_line}); no echo from the liquid "
            "surface reaches the microphone, or noise drowns it. Check that the tube is "
            "closed by the liquid within the level range and that the sweep is loud enough"
        )
    pos, _ = parabolic_peak(np.log(power + 1e-300), np.array([i]))
    return 1.0 / (pos[0] * (q[1] - q[0])), strength


def _lattice(
    freqs: np.ndarray, weights: np.ndarray, f_f: float, tol: float
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Orders j and a mask of peaks that sit on the lattice f_F j + b; refined f_F and b."""
    phase = np.angle(np.sum(weights * np.exp(2j * np.pi * freqs / f_f)))
    b = phase / (2.0 * np.pi) * f_f
    keep = np.ones(freqs.size, bool)
    for _ in range(3):
        j = np.round((freqs - b) / f_f)
        resid = (freqs - b) / f_f - j
        keep = np.abs(resid) <= tol
        # one peak per order: the one nearest the lattice
        order = np.lexsort((np.abs(resid), j))
        first = np.ones(order.size, bool)
        first[1:] = j[order][1:] != j[order][:-1]
        unique = np.zeros(freqs.size, bool)
        unique[order[first]] = True
        keep &= unique
        if keep.sum() >= 2:
            f_f, b = np.polyfit(j[keep], freqs[keep], 1)
    j = np.round((freqs - b) / f_f)
    return j.astype(int), keep, float(f_f), float(b)


def detect_resonances(
    recording: Recording | np.ndarray,
    sweep: LinearSweep | None = None,
    *,
    latency_s: float | None = None,
    correct_sweep_rate: bool = True,
    correct_latency: bool = True,
    level_range_m: tuple[float, float] = (0.5, 15.0),
    bandwidth_hz: float = 200.0,
    rel_prominence: float = 0.3,
    peak_window: float = 0.125,
    lattice_tolerance: float = 0.25,
    min_resonances: int = 5,
    min_line: float = 20.0,
    min_modulation: float = 0.05,
    silence_dbfs: float = -70.0,
    clip_level: float = 0.999,
    max_clipped_fraction: float = 1e-4,
) -> DetectionResult:
    """Resonance frequencies z_k of a recorded sweep: the observations of eq. (40).

    The chain: check the recording (silence, clipping); find the latency τ by matched
    filtering with the sweep; take the envelope; read time as instantaneous frequency; find the
    peaks with sub-sample precision; place them on the lattice of spacing f_F to find missed and
    spurious ones; remove the offsets κ/(2 f_F) and κ τ.

    Parameters
    ----------
    recording : Recording or numpy.ndarray, shape (n,)
        A :class:`Recording`, or samples in full-scale units with ``sweep``.
    sweep : LinearSweep, optional
        The played sweep (default: the recording's).
    latency_s : float, optional
        τ, s, if known; None (default) estimates it (:func:`estimate_latency`).
    correct_sweep_rate, correct_latency : bool, optional
        Subtract κ/(2 f_F) and κ τ (default True). False for both mimics a detector that reads
        f_0 + κ t, as the paper's (its w has mode −6.9 Hz).
    level_range_m : tuple of float, optional
        Levels considered possible, m; bounds the spacing search (default 0.5–15).
    bandwidth_hz : float, optional
        Envelope bandwidth around the sweep, Hz (:func:`envelope`); must exceed a few k/f_F.
    rel_prominence : float, optional
        A peak counts when its prominence exceeds this fraction of the median prominence of
        the strongest expected peaks.
    peak_window : float, optional
        Half-width of the parabola fitted at each peak, as a fraction of f_F (0.125: the top
        ±45° of the beat, where the envelope is nearly parabolic).
    lattice_tolerance : float, optional
        Peaks further than this fraction of f_F from the lattice are spurious.
    min_resonances : int, optional
        Fewer resonances raise :class:`~dstoolkit.errors.DetectionError`.
    min_line : float, optional
        Required strength of the envelope's periodic pattern; weaker: "no tube echo".
    min_modulation : float, optional
        Required spread (5th to 95th percentile) of the envelope relative to its median;
        flatter: "no tube echo".
    silence_dbfs, clip_level, max_clipped_fraction : float, optional
        Thresholds of the silence (dBFS) and clipping (full scale, fraction of samples) checks.

    Returns
    -------
    DetectionResult
        The readings z_k (K,), Hz, their relative orders, the offsets, the missed and spurious
        peaks, and the envelope.

    Raises
    ------
    DetectionError
        Silence, clipping, no sweep, no tube echo, or too few resonances; the message says
        which and what to do.

    See Also
    --------
    synthesize_recording : A simulated recording to detect.
    fit_resonance_series : The orders and the level from the result.
    characterise_observation_noise : The error of this detector.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(30), §4.1, §4.3, Figs. 6–7.

    Examples
    --------
    >>> from dstoolkit.gauge import (TubeSetup, detect_resonances, synthesize_recording,
    ...                              typical_conditions)
    >>> rec = synthesize_recording(TubeSetup(4.6, 26.5), conditions=typical_conditions())
    >>> det = detect_resonances(rec)
    >>> round(det.fundamental_hz, 1), det.complete
    (37.7, True)
    """
    if isinstance(recording, Recording):
        samples, sweep = recording.samples, sweep or recording.sweep
    else:
        samples = recording
        if sweep is None:
            raise DetectionError("pass the played sweep with a bare array of samples")
    x = np.asarray(samples, dtype=float)
    _check_levels(x, silence_dbfs, clip_level, max_clipped_fraction)
    k = sweep.rate
    if latency_s is None:  # the sweep itself is the reference; τ ≤ 1 s
        tau = estimate_latency(
            _sweep_waveform(sweep), x, sweep.sample_rate, max_latency_s=1.0, min_significance=8.0
        ).seconds
    else:
        tau = float(latency_s)

    t_env, env = envelope(x, sweep, tau, bandwidth_hz)
    u = t_env - tau  # time since the sweep started
    f_nom = sweep.frequency_at(u)
    fF_range = (_C_RANGE[0] / (2 * level_range_m[1]), _C_RANGE[1] / (2 * level_range_m[0]))
    settle = sweep.taper + 2.0 / bandwidth_hz
    valid = (u >= settle) & (u <= sweep.duration - settle)
    if valid.sum() < 16:
        raise DetectionError("the recording does not cover the sweep; record longer")
    lo, mid, hi = np.percentile(env[valid], [5, 50, 95])
    if not hi - lo >= min_modulation * mid:
        raise DetectionError(
            f"no tube echo: the envelope varies by only {100 * (hi - lo) / max(mid, 1e-300):.1f}"
            f" % (need {100 * min_modulation:g} %); no echo from the liquid surface reaches "
            "the microphone. Check that the tube is closed by the liquid"
        )
    f_f0, _ = _spacing_from_envelope(f_nom[valid], env[valid], fF_range, min_line)

    # Keep the part where the first echo is present over a whole fit window.
    half = peak_window * f_f0 / k + settle  # the fit window must see the echo
    valid &= (u >= 1.0 / f_f0 + half) & (u <= sweep.duration - half)
    idx = np.nonzero(valid)[0]
    step_hz = k * (t_env[1] - t_env[0])
    expected = max(1, int((f_nom[idx[-1]] - f_nom[idx[0]]) / f_f0))
    cand, prom = _prominent_peaks(
        env, max(1, int(0.35 * f_f0 / step_hz)), expected, rel_prominence, valid
    )
    if cand.size < min_resonances:
        raise DetectionError(
            f"too few resonances: found {cand.size}, need at least {min_resonances}; the "
            "level may be too short for this band (f_F > band/5), or noise hides the peaks"
        )
    pos, amp = fitted_peak(env, cand, int(peak_window * f_f0 / step_hz))
    t_peak = np.interp(pos, np.arange(env.size), t_env)
    raw = sweep.frequency_at(t_peak)  # f₀ + κ t, the uncorrected reading

    j, on, f_f, _ = _lattice(raw, prom, f_f0, lattice_tolerance)
    sweep_off = float(sweep_rate_offset(k, f_f))
    lat_off = latency_offset(k, tau)
    offset = sweep_off * correct_sweep_rate + lat_off * correct_latency
    z = raw[on] - offset
    jj = j[on]
    if z.size < min_resonances:
        raise DetectionError(
            f"too few resonances: {z.size} on a regular lattice (need {min_resonances}); "
            f"{int((~on).sum())} peaks were irregular. Noise or a second reflector may be "
            "present"
        )
    missing = np.setdiff1d(np.arange(jj.min(), jj.max() + 1), jj)
    missed = np.polyval(np.polyfit(jj, z, 1), missing) if missing.size else np.empty(0)
    return DetectionResult(
        frequencies=z,
        steps=jj - jj.min(),
        amplitudes=amp[on],
        raw_frequencies=raw[on],
        peak_times=t_peak[on],
        fundamental_hz=f_f,
        sweep_rate_offset_hz=sweep_off,
        latency_offset_hz=lat_off,
        latency_s=tau,
        missed=missed,
        spurious=raw[~on] - offset,
        envelope_times=t_env,
        envelope=env,
        sweep=sweep,
        corrected=(correct_sweep_rate, correct_latency),
    )


def model_peak_frequencies(
    setup: TubeSetup,
    sweep: LinearSweep,
    peak_window: float = 0.125,
    resolution_hz: float = 0.05,
    echo_floor: float = 1e-4,
) -> np.ndarray:
    """Resonances of the noise-free model, found as :func:`detect_resonances` finds them.

    The peaks of :func:`model_envelope`, read as the sweep's frequency f(u), Hz (no latency,
    no correction). Only peaks with the first echo present and away from the sweep's ends are
    returned. With one echo (R_t = 0) they sit at n f_F + κ/(2 f_F); each later echo m adds
    k π Δ² m(m − 1) of phase and moves them by up to a few Hz.

    Parameters
    ----------
    setup : TubeSetup
        The simulated gauge.
    sweep : LinearSweep
        The sweep.
    peak_window : float, optional
        Half-width of the fitted parabola, fraction of f_F (default 0.125).
    resolution_hz : float, optional
        Step of the envelope in sweep frequency, Hz (default 0.05).
    echo_floor : float, optional
        Echoes weaker than this (relative to the direct wave) are left out (default 1e-4).

    Returns
    -------
    numpy.ndarray, shape (K,)
        The model's peak frequencies, Hz, ascending.

    See Also
    --------
    detect_resonances, model_envelope

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(30), §4.1.

    Examples
    --------
    With one echo the peaks sit κ/(2 f_F) above the resonances n f_F:

    >>> import numpy as np
    >>> from dstoolkit.gauge import (LinearSweep, TubeSetup, model_peak_frequencies,
    ...                              sweep_rate_offset)
    >>> setup = TubeSetup(1.3, top_reflection=0.0)
    >>> sweep = LinearSweep(1000.0, 1600.0, duration=2.0)
    >>> f = model_peak_frequencies(setup, sweep)
    >>> offset = sweep_rate_offset(sweep.rate, setup.fundamental_hz)
    >>> n = np.rint((f - offset) / setup.fundamental_hz)
    >>> bool(np.allclose(f, n * setup.fundamental_hz + offset, atol=0.05))
    True
    """
    u = np.arange(0.0, sweep.duration, resolution_hz / sweep.rate)
    env = model_envelope(setup, sweep, u, echo_floor)
    f_f = setup.fundamental_hz
    expected = int((sweep.f_stop - sweep.f_start) / f_f) + 1
    half = peak_window * f_f / sweep.rate + sweep.taper
    inside = (u >= setup.round_trip_s + half) & (u <= sweep.duration - half)
    idx, _ = _prominent_peaks(env, max(1, int(0.35 * f_f / resolution_hz)), expected, 0.3, inside)
    pos, _ = fitted_peak(env, idx, int(peak_window * f_f / resolution_hz))
    t = pos * (u[1] - u[0])
    keep = (t >= setup.round_trip_s + half) & (t <= sweep.duration - half)
    return sweep.frequency_at(t[keep])


def detection_precision_hz(
    setup: TubeSetup,
    conditions: RecordingConditions,
    sweep: LinearSweep,
    frequency_hz: Any,
    bandwidth_hz: float = 200.0,
    peak_window: float = 0.125,
    include_speaker: bool = True,
) -> np.ndarray:
    """Predicted standard deviation of a detected resonance at ``frequency_hz``.

    Single-echo approximation. The envelope E = |1 + a e^(iθ)|, θ = 2π f/f_F, has curvature
    κ = P0 a/(1 + a) (2π/f_F)² at its peaks; a parabola fitted over ±h = ±``peak_window`` f_F
    to N = (2h/k)(2B) independent envelope samples of noise σ_e places the vertex within
    σ_e sqrt(3/N)/(h κ). The envelope's noise is σ_e = sqrt(2 B G(f)), G the one-sided
    spectral density (Pa²/Hz) of microphone, background (pink) and quantisation noise at f.
    The speaker's frequency error moves the peak one for one: its σ adds in quadrature.

    Parameters
    ----------
    setup : TubeSetup
        The simulated gauge.
    conditions : RecordingConditions
        Noise levels of the recording.
    sweep : LinearSweep
        The sweep.
    frequency_hz : float or array_like, any shape
        Frequencies of the resonances, Hz.
    bandwidth_hz : float, optional
        The envelope's bandwidth B, Hz (default 200, as the detector's).
    peak_window : float, optional
        Half-width of the fitted parabola, fraction of f_F (default 0.125).
    include_speaker : bool, optional
        Add the speaker's jitter in quadrature (default True).

    Returns
    -------
    numpy.ndarray
        The standard deviation, Hz, shaped as ``frequency_hz``.

    See Also
    --------
    detect_resonances : The detector whose precision this predicts.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3 (the noise w of the detected resonances).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.gauge import (PAPER_SWEEP, TubeSetup, detection_precision_hz,
    ...                              typical_conditions)
    >>> sd = detection_precision_hz(TubeSetup(4.6), typical_conditions(), PAPER_SWEEP,
    ...                             [1000.0, 2000.0])
    >>> sd.shape, bool(np.all(sd >= 0.1))
    ((2,), True)
    """
    f = np.asarray(frequency_hz, dtype=float)
    c = conditions
    fs, k, f_f = sweep.sample_rate, sweep.rate, setup.fundamental_hz
    quant = 0.0 if c.bits is None else c.full_scale_pa / 2.0 ** (c.bits - 1) / np.sqrt(12.0)
    white = 2.0 * (c.microphone_noise_pa**2 + quant**2) / fs
    pink = c.background_noise_pa**2 / (np.maximum(f, 20.0) * (1.0 + np.log(fs / 40.0)))
    sigma_e = np.sqrt(2.0 * bandwidth_hz * (white + pink))
    a = setup.echo_gain(1, f)
    h = peak_window * f_f
    kappa = c.source_pressure_pa * a / (1.0 + a) * (2.0 * np.pi / f_f) ** 2
    n_eff = np.maximum(3.0, 2.0 * h / k * 2.0 * bandwidth_hz)
    sigma = sigma_e * np.sqrt(3.0 / n_eff) / (h * kappa)
    return np.hypot(sigma, c.speaker_jitter_hz if include_speaker else 0.0)
