"""A tube with losses and two reflecting ends, and the microphone recording of a sweep.

The speaker and the microphone sit at the top of the tube; the liquid surface is L below.
The speaker's wave s(t) runs down, is reflected by the surface (coefficient R_s), comes back
Δ = 2L/c later (eqs. 27–28), is partly reflected again by the top (R_t), and so on. The
microphone, flush with the top, hears the outgoing wave plus each returning wave times
(1 + R_t) (incident plus reflected pressure):

    p(t) = P0 [ s(t) + Σ_{m≥1} a_m(f) s(t − mΔ) ],   a_m = (1 + R_t) R_s^m R_t^(m−1) e^(−2mLα(f)),

whose amplitude peaks where 2L = nλ (eqs. 29–30). α(f) is Kirchhoff's visco-thermal wall loss
∝ sqrt(f)/radius, times a roughness factor, plus an optional constant. Below the plane-wave
cutoff (2.7 kHz for d = 75 mm) the 1-D model holds.

Each echo is the analytic sweep evaluated at the delayed time (an exact fractional delay);
its loss is taken at the instantaneous frequency it carries, which is exact to first order
because the sweep changes frequency slowly (k Δ² ≪ 1 cycle per echo period). A 5 s,
44.1 kHz recording synthesises in a few hundredths of a second
(``benchmarks/gauge_synthesis.py``); the noise draws of an integer seed are kept for the
next recording with that seed.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np

from dstoolkit._reprs import short_repr
from dstoolkit.errors import InvalidInputError
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import real_number

from ._acoustics import (
    DEFAULT_BAND,
    SpeedModel,
    fundamental_frequency,
    resonance_frequencies,
    speed_of_sound,
)
from ._sweep import PAPER_SWEEP, LinearSweep

#: Reference pressure of sound pressure level, Pa.
P_REF = 20e-6


def spl_to_pa(spl_db: float) -> float:
    """RMS pressure (Pa) of a sound pressure level in dB re 20 µPa."""
    return float(P_REF * 10.0 ** (spl_db / 20.0))


def wall_attenuation(
    frequency_hz: Any, diameter_m: float, temperature_c: float, pressure_pa: float = 101325.0,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Kirchhoff's visco-thermal attenuation of a plane wave in a rigid tube, Np/m.

    α = sqrt(π f η/ρ) (1 + (γ − 1)/sqrt(Pr)) / (r c), with Sutherland's viscosity η(T),
    ρ = p/(R T), γ = 1.4, Pr = 0.71. For d = 75 mm at 1700 Hz: 0.032 Np/m, so a 9.6 m round
    trip (19.2 m) keeps e^(−0.62) ≈ 54 % of the amplitude. Into ``out`` when given (it may
    be the frequencies' own array).
    """
    tk = temperature_c + 273.15
    eta = 1.458e-6 * tk**1.5 / (tk + 110.4)
    rho = pressure_pa / (287.05 * tk)
    c = 331.3 * np.sqrt(tk / 273.15)
    gamma, prandtl = 1.4, 0.71
    f = np.asarray(frequency_hz, dtype=float)
    # one array, then in place (the synthesis calls this on 10⁵ samples per echo)
    alpha = np.abs(f, out=np.empty_like(f) if out is None else out)
    alpha *= np.pi
    alpha *= eta
    alpha /= rho
    np.sqrt(alpha, out=alpha)
    alpha *= 1.0 + (gamma - 1.0) / np.sqrt(prandtl)
    alpha /= 0.5 * diameter_m * c
    return alpha if alpha.ndim else alpha[()]


@dataclass(frozen=True)
class TubeSetup:
    """The gauge: a tube of given diameter with the liquid ``level_m`` below the speaker.

    Parameters
    ----------
    level_m
        L, distance from the speaker platform to the liquid surface, m.
    temperature_c
        Air temperature, °C; sets c by ``speed_model``.
    diameter_m
        Inner diameter (the paper's PVC tube: 75 mm).
    surface_reflection
        R_s, pressure reflection coefficient of the liquid surface (water: ≈ 1).
    top_reflection
        R_t, reflection coefficient of the speaker end (0 = anechoic top, 1 = rigid). The
        default 0.3 is an assumption (the paper does not say); it makes later echoes move
        the resonances by 1–3 Hz (see :func:`dstoolkit.gauge.model_peak_frequencies`).
    wall_loss_factor
        Multiplies Kirchhoff's wall loss (rough or jointed tubes lose more: 1–2).
    extra_attenuation_np_per_m
        Frequency-independent loss added to the wall loss, Np/m.
    speed_model
        "paper", "ideal_gas" or "cramer" (see :func:`dstoolkit.gauge.speed_of_sound`).
    relative_humidity
        Used by the "cramer" model only.
    """

    level_m: float
    temperature_c: float = 20.0
    diameter_m: float = 0.075
    surface_reflection: float = 0.98
    top_reflection: float = 0.3
    wall_loss_factor: float = 1.0
    extra_attenuation_np_per_m: float = 0.0
    speed_model: SpeedModel = "paper"
    relative_humidity: float = 0.5

    def __post_init__(self) -> None:
        for name in ("level_m", "temperature_c", "diameter_m", "surface_reflection",
                     "top_reflection", "wall_loss_factor", "extra_attenuation_np_per_m",
                     "relative_humidity"):
            real_number(getattr(self, name), name)  # a finite real number, not a string
        if not (np.isfinite(self.level_m) and self.level_m > 0):
            raise InvalidInputError(
                f"level_m must be a positive distance in metres, got {self.level_m}")
        if not self.diameter_m > 0:
            raise InvalidInputError(f"diameter_m must be positive, got {self.diameter_m}")
        for name in ("surface_reflection", "top_reflection"):
            r = getattr(self, name)
            if not 0 <= r <= 1:
                raise InvalidInputError(f"{name} is a reflection coefficient in [0, 1], got {r}")
        if self.wall_loss_factor < 0 or self.extra_attenuation_np_per_m < 0:
            raise InvalidInputError("wall_loss_factor and extra_attenuation_np_per_m must be >= 0")

    @property
    def speed_of_sound(self) -> float:
        """c at this temperature, m/s."""
        kw = {"relative_humidity": self.relative_humidity} if self.speed_model == "cramer" else {}
        return float(speed_of_sound(self.temperature_c, self.speed_model, **kw))

    @property
    def fundamental_hz(self) -> float:
        """f_F = c/(2L) (eq. 35)."""
        return float(fundamental_frequency(self.level_m, self.speed_of_sound))

    @property
    def round_trip_s(self) -> float:
        """Δ = 2L/c, delay of the first surface echo."""
        return 2.0 * self.level_m / self.speed_of_sound

    def resonances(self, band: tuple[float, float] = DEFAULT_BAND) -> tuple[np.ndarray, np.ndarray]:
        """Orders n and frequencies n c/(2L) in ``band`` (eqs. 31–32)."""
        return resonance_frequencies(self.level_m, self.speed_of_sound, band)

    def attenuation(self, frequency_hz: Any, out: np.ndarray | None = None) -> np.ndarray:
        """α(f), Np/m: wall loss × ``wall_loss_factor`` + ``extra_attenuation_np_per_m``;
        into ``out`` when given (it may be ``frequency_hz`` itself)."""
        alpha = wall_attenuation(frequency_hz, self.diameter_m, self.temperature_c, out=out)
        alpha *= self.wall_loss_factor  # in place for an array (a new one: ours to change)
        alpha += self.extra_attenuation_np_per_m
        return alpha

    def echo_gain(self, m: int, frequency_hz: Any, out: np.ndarray | None = None
                  ) -> np.ndarray:
        """a_m(f) = (1 + R_t) R_s^m R_t^(m−1) e^(−2mLα(f)) at the microphone; a_0 = 1. Into
        ``out`` when given (it may be ``frequency_hz`` itself)."""
        f = np.asarray(frequency_hz, dtype=float)
        if m == 0:
            if out is None:
                return np.ones_like(f)
            out.fill(1.0)
            return out
        rs, rt = self.surface_reflection, self.top_reflection
        gain = self.attenuation(f, out=out)
        gain *= -2.0 * m * self.level_m  # in place for an array, as in attenuation
        gain = np.exp(gain, out=gain) if isinstance(gain, np.ndarray) else np.exp(gain)
        gain *= (1.0 + rt) * rs**m * rt ** (m - 1)
        return gain

    def echo_count(self, f_min: float, floor: float = 1e-4, limit: int = 200) -> int:
        """Number of echoes whose gain at ``f_min`` (least loss) exceeds ``floor``."""
        m = np.arange(1, limit + 1)
        rs, rt = self.surface_reflection, self.top_reflection
        loss = float(np.exp(-2.0 * self.level_m * self.attenuation(f_min)))
        with np.errstate(divide="ignore"):
            log_gain = (np.log1p(rt) + m * np.log(rs * loss + 1e-300)
                        + (m - 1) * np.log(rt + 1e-300))
        above = np.nonzero(log_gain > np.log(floor))[0]
        return int(above[-1] + 1) if above.size else 0


@dataclass(frozen=True)
class RecordingConditions:
    """Noise, gain and timing of one recording, in physical units.

    Parameters
    ----------
    source_pressure_pa
        Amplitude of the outgoing (direct) wave at the microphone, Pa (1 Pa ≈ 91 dB SPL rms).
    speaker_jitter_hz
        RMS error of the frequency the speaker actually emits, Hz: the paper's state noise v
        was measured this way (σ_v = 0.1 Hz, §4.3). A slowly wandering Gaussian process.
    speaker_jitter_bandwidth_hz
        Bandwidth of that wander (a Gaussian spectrum of this standard deviation), Hz.
    microphone_noise_pa
        RMS self-noise of the microphone (white over the full band), Pa.
    background_noise_pa
        RMS ambient noise reaching the microphone (pink, 1/f power above 20 Hz), Pa.
    latency_s
        τ: the sweep starts τ after the recording (audio output + input latency), s.
    full_scale_pa
        Pressure that reaches digital full scale 1.0; louder samples clip.
    bits
        Quantisation of the converter (None: no quantisation).
    tail_s
        Recording time after the sweep ends (and after τ), s.
    """

    source_pressure_pa: float = 1.0
    speaker_jitter_hz: float = 0.0
    speaker_jitter_bandwidth_hz: float = 5.0
    microphone_noise_pa: float = 0.0
    background_noise_pa: float = 0.0
    latency_s: float = 0.0
    full_scale_pa: float = 10.0
    bits: int | None = 16
    tail_s: float = 0.1

    def __repr__(self) -> str:
        return short_repr(self)

    def __post_init__(self) -> None:
        for name in ("speaker_jitter_hz", "microphone_noise_pa", "background_noise_pa",
                     "latency_s", "tail_s", "source_pressure_pa"):
            if not getattr(self, name) >= 0:
                raise InvalidInputError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not self.full_scale_pa > 0 or not self.speaker_jitter_bandwidth_hz > 0:
            raise InvalidInputError("full_scale_pa and speaker_jitter_bandwidth_hz must be > 0")
        if self.bits is not None and not 2 <= self.bits <= 32:
            raise InvalidInputError(f"bits must be None or in 2..32, got {self.bits}")


def typical_conditions(**changes: Any) -> RecordingConditions:
    """A laptop-and-PVC-tube recording: speaker jitter σ 0.1 Hz (the paper's σ_v), a 30 dB SPL
    microphone, 50 dB SPL room noise and 10 ms of audio latency; ``changes`` override."""
    base = {"speaker_jitter_hz": 0.1, "microphone_noise_pa": spl_to_pa(30.0),
            "background_noise_pa": spl_to_pa(50.0), "latency_s": 0.01}
    return RecordingConditions(**{**base, **changes})


@dataclass(frozen=True)
class Recording:
    """A microphone recording in digital full-scale units, with the truth when simulated."""

    samples: np.ndarray
    sweep: LinearSweep
    setup: TubeSetup | None = None
    conditions: RecordingConditions | None = None
    speaker_error_times: np.ndarray | None = field(default=None, repr=False)
    speaker_error_hz: np.ndarray | None = field(default=None, repr=False)

    @property
    def sample_rate(self) -> float:
        return self.sweep.sample_rate

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.samples.size) / self.sweep.sample_rate

    def speaker_error_at(self, emission_time_s: Any) -> np.ndarray:
        """The speaker's frequency error δf (Hz) at times since the sweep started."""
        t = np.asarray(emission_time_s, dtype=float)
        if self.speaker_error_hz is None or self.speaker_error_times is None:
            return np.zeros_like(t)
        return np.interp(t, self.speaker_error_times, self.speaker_error_hz)


def model_envelope(setup: TubeSetup, sweep: LinearSweep, emission_time_s: Any,
                   echo_floor: float = 1e-4) -> np.ndarray:
    """Noise-free envelope |Σ_m a_m gate(u − mΔ) e^(−iθ_m(u))| of the microphone pressure
    over the source amplitude, θ_m(u) = φ(u) − φ(u − mΔ), at times u since the sweep
    started (eq. 29 with every echo)."""
    u = np.asarray(emission_time_s, dtype=float)
    delta = setup.round_trip_s
    total = np.zeros(u.shape, complex)
    for m in range(setup.echo_count(sweep.f_start, echo_floor) + 1):
        e = u - m * delta
        total += (setup.echo_gain(m, sweep.frequency_at(e)) * sweep.gate(e)
                  * np.exp(-1j * (sweep.phase(u) - sweep.phase(e))))
    return np.abs(total)


def _shaped_draw(rng: np.random.Generator, n: int, shape: np.ndarray
                 ) -> tuple[np.ndarray, float]:
    """One draw of Gaussian noise whose amplitude spectrum is ``shape`` (on rfftfreq(n)),
    and the RMS of the *process* it comes from (the root energy of its impulse response):
    the draw times ``rms`` / that RMS has the process RMS ``rms``."""
    x = np.fft.irfft(np.fft.rfft(rng.standard_normal(n)) * shape, n)
    impulse = np.fft.irfft(shape.astype(complex), n)  # x = white ⊛ impulse (circular)
    return x, float(np.sqrt(np.sum(impulse**2)))


def _shaped_noise(rng: np.random.Generator, n: int, dt: float, shape: np.ndarray,
                  rms: float) -> np.ndarray:
    """Stationary Gaussian noise whose amplitude spectrum is ``shape`` (on rfftfreq(n, dt)),
    scaled so that the *process* has RMS ``rms`` (not each draw: draws vary as they should).
    """
    x, process_rms = _shaped_draw(rng, n, shape)
    return x * (rms / process_rms)


def _gaussian_shape(n: int, dt: float, bandwidth_hz: float) -> np.ndarray:
    """A Gaussian amplitude spectrum of width ``bandwidth_hz`` on rfftfreq(n, dt)."""
    return np.exp(-0.5 * (np.fft.rfftfreq(n, dt) / bandwidth_hz) ** 2)


def _gaussian_process(rng: np.random.Generator, n: int, dt: float, sigma: float,
                      bandwidth_hz: float) -> np.ndarray:
    """Zero-mean Gaussian series of RMS ``sigma`` with a Gaussian spectrum of width
    ``bandwidth_hz``."""
    return _shaped_noise(rng, n, dt, _gaussian_shape(n, dt, bandwidth_hz), sigma)


def _jitter_grid(sweep: LinearSweep, bandwidth_hz: float) -> tuple[np.ndarray, float]:
    """Times (s since the sweep started) of the speaker's frequency error, and their step."""
    dt = min(1e-3, 0.1 / bandwidth_hz)
    return np.arange(-0.01, sweep.duration + 0.01 + dt, dt), dt


def speaker_frequency_error(
    sweep: LinearSweep, conditions: RecordingConditions, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """The speaker's frequency error δf(t) (Hz) over the sweep: ``(times, δf)`` on a grid
    of at most 1 ms; zero when ``conditions.speaker_jitter_hz`` is 0 (no draw is made)."""
    t, dt = _jitter_grid(sweep, conditions.speaker_jitter_bandwidth_hz)
    if conditions.speaker_jitter_hz <= 0:
        return t, np.zeros(t.size)
    return t, _gaussian_process(rng, t.size, dt, conditions.speaker_jitter_hz,
                                conditions.speaker_jitter_bandwidth_hz)


def _pink_shape(n: int, fs: float) -> np.ndarray:
    """The amplitude spectrum of 1/f power above 20 Hz (flat below, no DC)."""
    f = np.fft.rfftfreq(n, 1.0 / fs)
    shape = 1.0 / np.sqrt(np.maximum(f, 20.0))
    shape[0] = 0.0
    return shape


class _Draws(NamedTuple):
    """The random draws of one recording, before they are scaled to the conditions: the
    speaker's frequency error, the microphone's white noise, the pink background (each
    None when its level is 0: then no draw is made). Shaped draws come with the RMS of
    their process (:func:`_shaped_draw`)."""

    jitter_times: np.ndarray
    jitter: tuple[np.ndarray, float] | None
    microphone: np.ndarray | None
    background: tuple[np.ndarray, float] | None


def _draw(rng: np.random.Generator, sweep: LinearSweep, n: int, jitter_bandwidth_hz: float,
          jitter: bool, microphone: bool, background: bool) -> _Draws:
    """The draws of a recording of ``n`` samples, in the order the generator makes them."""
    t_j, dt = _jitter_grid(sweep, jitter_bandwidth_hz)
    shaped = (_shaped_draw(rng, t_j.size, _gaussian_shape(t_j.size, dt, jitter_bandwidth_hz))
              if jitter else None)
    white = rng.standard_normal(n) if microphone else None
    pink = _shaped_draw(rng, n, _pink_shape(n, sweep.sample_rate)) if background else None
    return _Draws(t_j, shaped, white, pink)


@functools.lru_cache(maxsize=4)
def _seeded_draws(seed: int, sweep: LinearSweep, n: int, jitter_bandwidth_hz: float,
                  jitter: bool, microphone: bool, background: bool) -> _Draws:
    """:func:`_draw` with a fresh generator of an integer ``seed``, kept for the next
    recording with the same seed (an explorer moving the level redraws the same noise).
    The arrays are read-only."""
    draws = _draw(np.random.default_rng(seed), sweep, n, jitter_bandwidth_hz, jitter,
                  microphone, background)
    for array in (draws.jitter_times, draws.microphone, *(draws.jitter or ()),
                  *(draws.background or ())):
        if isinstance(array, np.ndarray):
            array.flags.writeable = False
    return draws


def _gated(values: np.ndarray, sweep: LinearSweep, e: np.ndarray) -> np.ndarray:
    """``values`` times :meth:`LinearSweep.gate` at the ascending times ``e`` (s since the
    sweep started, within it): the gate is computed only near the sweep's ends, where it is
    not 1, so the product is the same number for number."""
    margin = 2.0 * sweep.taper + 2.0 / sweep.sample_rate
    a = int(np.searchsorted(e, margin))
    b = max(a, int(np.searchsorted(e, sweep.duration - margin)))
    values[:a] *= sweep.gate(e[:a])
    values[b:] *= sweep.gate(e[b:])
    return values


def _jitter_phase(draws: _Draws, jitter_hz: float) -> tuple[np.ndarray, np.ndarray | None]:
    """The speaker's frequency error δf (Hz) on ``draws.jitter_times`` and its phase
    ψ = 2π ∫ δf (trapezoids), None without jitter."""
    t_j = draws.jitter_times
    if draws.jitter is None:
        return np.zeros(t_j.size), None
    df = draws.jitter[0] * (jitter_hz / draws.jitter[1])
    return df, 2.0 * np.pi * np.concatenate(([0.0], np.cumsum(0.5 * (df[1:] + df[:-1])
                                                             * np.diff(t_j))))


def _echo_span(u: np.ndarray, delay_s: float, duration_s: float) -> tuple[int, int]:
    """The samples (``lo:hi`` of the times ``u``) that an echo ``delay_s`` late covers."""
    return (int(np.searchsorted(u, delay_s)),
            int(np.searchsorted(u, delay_s + duration_s, side="right")))


def _echo_wave(sweep: LinearSweep, e: np.ndarray, gain: np.ndarray, t_j: np.ndarray,
               psi_j: np.ndarray | None, out: np.ndarray | None = None) -> np.ndarray:
    """One echo at the times ``e`` since it left the speaker: gain × gate × cos(φ + ψ), the
    arithmetic in place (``gain`` is overwritten) and into ``out`` when given."""
    gain = _gated(gain, sweep, e)
    wave = sweep.phase(e, out=out)
    if psi_j is not None:
        wave += np.interp(e, t_j, psi_j)
    wave = np.cos(wave, out=wave)
    wave *= gain
    return wave


@functools.lru_cache(maxsize=2)
def _seeded_direct_wave(seed: int, sweep: LinearSweep, n: int, latency_s: float,
                        jitter_hz: float, kinds: tuple[float, bool, bool, bool]) -> np.ndarray:
    """The direct wave (m = 0, a_0 = 1) of a recording with an integer seed: the same in
    every tube, so kept (read-only) for the next recording with these conditions."""
    u = np.arange(n) / sweep.sample_rate - latency_s
    draws = _seeded_draws(seed, sweep, n, *kinds)
    lo, hi = _echo_span(u, 0.0, sweep.duration)
    e = u[lo:hi] - 0.0  # as the echoes' e = u − mΔ, m = 0
    wave = _echo_wave(sweep, e, np.ones_like(e), draws.jitter_times,
                      _jitter_phase(draws, jitter_hz)[1])
    wave.flags.writeable = False
    return wave


def synthesize_recording(
    setup: TubeSetup,
    sweep: LinearSweep = PAPER_SWEEP,
    conditions: RecordingConditions | None = None,
    seed: int | np.random.Generator = 0,
    echo_floor: float = 1e-4,
) -> Recording:
    """The microphone recording of ``sweep`` in the tube ``setup`` (eqs. 27–29).

    p(t) = P0 [s(u) + Σ_m a_m(f(u − mΔ)) s(u − mΔ)] + noises, u = t − τ, with
    s(u) = gate(u) cos(φ(u) + ψ(u)) and ψ the phase of the speaker's frequency error.
    Echoes weaker than ``echo_floor`` are dropped. Returns samples / full scale, clipped to
    [−1, 1] and quantised. Seeded: equal arguments give equal recordings.
    """
    cond = RecordingConditions() if conditions is None else conditions
    fs = sweep.sample_rate
    n = int(round((sweep.duration + cond.latency_s + cond.tail_s) * fs))
    # the pressure, three work arrays, the time axis, the noises' draws and the samples
    check_memory(n * 8.0 * 12, f"synthesising a recording of {n} samples",
                 "shorten the sweep or lower its sample rate")
    kinds = (cond.speaker_jitter_bandwidth_hz, cond.speaker_jitter_hz > 0,
             cond.microphone_noise_pa > 0, cond.background_noise_pa > 0)
    if isinstance(seed, int | np.integer):
        draws = _seeded_draws(int(seed), sweep, n, *kinds)
        # the noises' levels do not move the sound: a change of them only adds other noise
        sound = _seeded_sound(setup, sweep, int(seed), echo_floor, n, kinds,
                              _sound_conditions(cond))
    else:
        draws = _draw(np.random.default_rng(seed), sweep, n, *kinds)
        sound = _sound(setup, sweep, draws, echo_floor, n, cond)
    df = _jitter_phase(draws, cond.speaker_jitter_hz)[0]
    pressure = sound.copy() if not sound.flags.writeable else sound  # the kept one stays
    if draws.microphone is not None:
        pressure += cond.microphone_noise_pa * draws.microphone
    if draws.background is not None:
        pink, process_rms = draws.background
        pressure += pink * (cond.background_noise_pa / process_rms)

    samples = np.clip(pressure / cond.full_scale_pa, -1.0, 1.0)
    if cond.bits is not None:
        q = 2.0 ** (cond.bits - 1)
        samples = np.clip(np.round(samples * q), -q, q - 1) / q
    return Recording(samples=samples, sweep=sweep, setup=setup, conditions=cond,
                     speaker_error_times=draws.jitter_times.copy(), speaker_error_hz=df)


def _sound_conditions(cond: RecordingConditions) -> RecordingConditions:
    """``cond`` without the levels of the noises (what the sound in the tube depends on)."""
    return replace(cond, microphone_noise_pa=0.0, background_noise_pa=0.0)


@functools.lru_cache(maxsize=2)
def _seeded_sound(setup: TubeSetup, sweep: LinearSweep, seed: int, echo_floor: float, n: int,
                  kinds: tuple[float, bool, bool, bool], cond: RecordingConditions
                  ) -> np.ndarray:
    """:func:`_sound` of a recording with an integer seed, kept (read-only) for the next
    recording that differs only in the noises' levels (``cond``: :func:`_sound_conditions`)."""
    sound = _sound(setup, sweep, _seeded_draws(seed, sweep, n, *kinds), echo_floor, n, cond,
                   direct=_seeded_direct_wave(seed, sweep, n, cond.latency_s,
                                              cond.speaker_jitter_hz, kinds))
    sound.flags.writeable = False
    return sound


def _sound(setup: TubeSetup, sweep: LinearSweep, draws: _Draws, echo_floor: float, n: int,
           cond: RecordingConditions, direct: np.ndarray | None = None) -> np.ndarray:
    """The pressure of the sweep and its echoes at the microphone, P0 [s(u) + Σ_m a_m(f(u −
    mΔ)) s(u − mΔ)] (eqs. 27–29), without noise; ``direct``: the wave m = 0 if known."""
    u = np.arange(n) / sweep.sample_rate - cond.latency_s
    t_j = draws.jitter_times
    psi_j = _jitter_phase(draws, cond.speaker_jitter_hz)[1]
    delta = setup.round_trip_s
    echoes = setup.echo_count(sweep.f_start, echo_floor)
    echoes = min(echoes, int(u[-1] / delta))
    pressure = np.zeros(n)
    # three work arrays for every echo: a new array of 10⁵ samples costs more than its
    # arithmetic (the memory is handed back and faulted in again)
    buffers = np.empty((3, n))
    for m in range(echoes + 1):
        lo, hi = _echo_span(u, m * delta, sweep.duration)
        if hi <= lo:
            continue
        if m == 0 and direct is not None:  # no control of the tube moves it
            wave = direct
        else:
            e, gain, wave = buffers[:, : hi - lo]
            np.subtract(u[lo:hi], m * delta, out=e)
            gain = setup.echo_gain(m, sweep.frequency_at(e, out=gain), out=gain)
            wave = _echo_wave(sweep, e, gain, t_j, psi_j, out=wave)
        pressure[lo:hi] += wave
    pressure *= cond.source_pressure_pa
    return pressure
