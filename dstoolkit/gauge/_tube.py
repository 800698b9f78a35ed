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
because the sweep changes frequency slowly (κ Δ² ≪ 1 cycle per echo period). The
synthesis works in place on a few reused arrays, and the noise draws of an integer seed
are kept for the next recording with that seed (``benchmarks/gauge_synthesis.py`` times
it).
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
    """RMS pressure of a sound pressure level in dB re 20 µPa.

    Parameters
    ----------
    spl_db : float
        The sound pressure level, dB SPL.

    Returns
    -------
    float
        The RMS pressure, Pa.

    See Also
    --------
    RecordingConditions : Takes its noise levels in Pa.

    Examples
    --------
    >>> from dstoolkit.gauge import spl_to_pa
    >>> round(spl_to_pa(94.0), 4)
    1.0024
    """
    return float(P_REF * 10.0 ** (spl_db / 20.0))


def wall_attenuation(
    frequency_hz: Any,
    diameter_m: float,
    temperature_c: float,
    pressure_pa: float = 101325.0,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Kirchhoff's visco-thermal attenuation of a plane wave in a rigid tube.

    α = sqrt(π f η/ρ) (1 + (γ − 1)/sqrt(Pr)) / (r c), with Sutherland's viscosity η(T),
    ρ = p/(R T), γ = 1.4, Pr = 0.71. For d = 75 mm at 1700 Hz: 0.032 Np/m, so a 9.6 m round
    trip (19.2 m) keeps e^(−0.62) ≈ 54 % of the amplitude.

    Parameters
    ----------
    frequency_hz : float or array_like, any shape
        Frequencies, Hz.
    diameter_m : float
        Inner diameter of the tube, m.
    temperature_c : float
        Air temperature, °C.
    pressure_pa : float, optional
        Static pressure, Pa (default 101325).
    out : numpy.ndarray, optional
        Float array of the shape of ``frequency_hz`` to write into (it may be the
        frequencies' own array).

    Returns
    -------
    numpy.ndarray or float
        α, Np/m, shaped as ``frequency_hz``.

    See Also
    --------
    TubeSetup.attenuation : This loss with a roughness factor and a constant added.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.1 (the tube).
    G. Kirchhoff, "Über den Einfluss der Wärmeleitung in einem Gase auf die
    Schallbewegung", Ann. Phys. 134:177 (1868).

    Examples
    --------
    >>> from dstoolkit.gauge import wall_attenuation
    >>> round(float(wall_attenuation(1700.0, 0.075, 20.0)), 3)
    0.032
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
    level_m : float
        L, distance from the speaker platform to the liquid surface, m; positive.
    temperature_c : float, optional
        Air temperature, °C (default 20); sets c by ``speed_model``.
    diameter_m : float, optional
        Inner diameter, m (default 0.075, the paper's PVC tube).
    surface_reflection : float, optional
        R_s, pressure reflection coefficient of the liquid surface, in [0, 1] (water: ≈ 1).
    top_reflection : float, optional
        R_t, reflection coefficient of the speaker end, in [0, 1] (0 = anechoic top, 1 =
        rigid). The default 0.3 is an assumption (the paper does not say); it makes later
        echoes move the resonances by 1–3 Hz (see :func:`model_peak_frequencies`).
    wall_loss_factor : float, optional
        Multiplies Kirchhoff's wall loss (rough or jointed tubes lose more: 1–2); ≥ 0.
    extra_attenuation_np_per_m : float, optional
        Frequency-independent loss added to the wall loss, Np/m; ≥ 0.
    speed_model : {"paper", "ideal_gas", "cramer"}, optional
        The law of c (see :func:`speed_of_sound`).
    relative_humidity : float, optional
        Fraction in [0, 1], used by the "cramer" model only.

    Raises
    ------
    InvalidInputError
        A field that is not a finite real number, a level or diameter that is not positive, a
        reflection coefficient outside [0, 1] or a negative loss.

    See Also
    --------
    synthesize_recording : Records a sweep in the tube.
    resonance_frequencies : Its resonances.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(35), §4.1.

    Examples
    --------
    >>> from dstoolkit.gauge import TubeSetup
    >>> tube = TubeSetup(9.6, temperature_c=23.9)
    >>> round(tube.fundamental_hz, 2), round(tube.round_trip_s, 4)
    (18.01, 0.0555)
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
        for name in (
            "level_m",
            "temperature_c",
            "diameter_m",
            "surface_reflection",
            "top_reflection",
            "wall_loss_factor",
            "extra_attenuation_np_per_m",
            "relative_humidity",
        ):
            real_number(getattr(self, name), name)  # a finite real number, not a string
        if not (np.isfinite(self.level_m) and self.level_m > 0):
            raise InvalidInputError(
                f"level_m must be a positive distance in metres, got {self.level_m}"
            )
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
        """The speed of sound c at this temperature by ``speed_model``, m/s."""
        kw = {"relative_humidity": self.relative_humidity} if self.speed_model == "cramer" else {}
        return float(speed_of_sound(self.temperature_c, self.speed_model, **kw))

    @property
    def fundamental_hz(self) -> float:
        """f_F = c/(2L), the paper's eq. (35), Hz."""
        return float(fundamental_frequency(self.level_m, self.speed_of_sound))

    @property
    def round_trip_s(self) -> float:
        """Δ = 2L/c, the delay of the first surface echo, s."""
        return 2.0 * self.level_m / self.speed_of_sound

    def resonances(self, band: tuple[float, float] = DEFAULT_BAND) -> tuple[np.ndarray, np.ndarray]:
        """Orders n and frequencies n c/(2L) of the resonances in ``band``.

        Parameters
        ----------
        band : tuple of float, optional
            (low, high) in Hz (default :data:`DEFAULT_BAND`).

        Returns
        -------
        orders : numpy.ndarray of int, shape (K,)
            n, ascending.
        frequencies : numpy.ndarray, shape (K,)
            f_n, Hz.

        See Also
        --------
        resonance_frequencies

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (31)–(32).
        """
        return resonance_frequencies(self.level_m, self.speed_of_sound, band)

    def attenuation(self, frequency_hz: Any, out: np.ndarray | None = None) -> np.ndarray:
        """α(f): the wall loss times ``wall_loss_factor`` plus ``extra_attenuation_np_per_m``.

        Parameters
        ----------
        frequency_hz : float or array_like, any shape
            Frequencies, Hz.
        out : numpy.ndarray, optional
            Float array to write into (it may be ``frequency_hz`` itself).

        Returns
        -------
        numpy.ndarray or float
            α, Np/m, shaped as ``frequency_hz``.

        See Also
        --------
        wall_attenuation
        """
        alpha = wall_attenuation(frequency_hz, self.diameter_m, self.temperature_c, out=out)
        alpha *= self.wall_loss_factor  # in place for an array (a new one: ours to change)
        alpha += self.extra_attenuation_np_per_m
        return alpha

    def echo_gain(self, m: int, frequency_hz: Any, out: np.ndarray | None = None) -> np.ndarray:
        """a_m(f) = (1 + R_t) R_s^m R_t^(m−1) e^(−2mLα(f)), the gain of echo m at the microphone.

        Parameters
        ----------
        m : int
            The echo's number, ≥ 0; a_0 = 1 is the direct wave.
        frequency_hz : float or array_like, any shape
            Frequencies the echo carries, Hz.
        out : numpy.ndarray, optional
            Float array to write into (it may be ``frequency_hz`` itself).

        Returns
        -------
        numpy.ndarray or float
            a_m(f), relative to the direct wave, shaped as ``frequency_hz``.

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(29).
        """
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
        """Count the echoes whose gain at ``f_min`` (the least loss) exceeds ``floor``.

        Parameters
        ----------
        f_min : float
            The lowest frequency of the sweep, Hz.
        floor : float, optional
            Smallest gain counted, relative to the direct wave (default 1e-4).
        limit : int, optional
            Most echoes counted (default 200).

        Returns
        -------
        int
            The number of echoes, in [0, ``limit``].
        """
        m = np.arange(1, limit + 1)
        rs, rt = self.surface_reflection, self.top_reflection
        loss = float(np.exp(-2.0 * self.level_m * self.attenuation(f_min)))
        with np.errstate(divide="ignore"):
            log_gain = np.log1p(rt) + m * np.log(rs * loss + 1e-300) + (m - 1) * np.log(rt + 1e-300)
        above = np.nonzero(log_gain > np.log(floor))[0]
        return int(above[-1] + 1) if above.size else 0


@dataclass(frozen=True)
class RecordingConditions:
    """Noise, gain and timing of one recording, in physical units.

    Parameters
    ----------
    source_pressure_pa : float, optional
        Amplitude of the outgoing (direct) wave at the microphone, Pa (1 Pa ≈ 91 dB SPL rms).
    speaker_jitter_hz : float, optional
        RMS error of the frequency the speaker actually emits, Hz: the paper's state noise v
        was measured this way (σ_v = 0.1 Hz, §4.3). A slowly wandering Gaussian process.
    speaker_jitter_bandwidth_hz : float, optional
        Bandwidth of that wander (a Gaussian spectrum of this standard deviation), Hz.
    microphone_noise_pa : float, optional
        RMS self-noise of the microphone (white over the full band), Pa.
    background_noise_pa : float, optional
        RMS ambient noise reaching the microphone (pink, 1/f power above 20 Hz), Pa.
    latency_s : float, optional
        τ: the sweep starts τ after the recording (audio output + input latency), s.
    full_scale_pa : float, optional
        Pressure that reaches digital full scale 1.0, Pa; louder samples clip.
    bits : int or None, optional
        Quantisation of the converter, 2–32 bits (None: no quantisation).
    tail_s : float, optional
        Recording time after the sweep ends (and after τ), s.

    Raises
    ------
    InvalidInputError
        A negative noise, latency, tail or source pressure, a full scale or jitter bandwidth
        that is not positive, or ``bits`` outside 2–32.

    See Also
    --------
    typical_conditions : A laptop-and-PVC-tube recording.
    synthesize_recording : Uses them.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.

    Examples
    --------
    >>> from dstoolkit.gauge import RecordingConditions
    >>> RecordingConditions(latency_s=0.01).latency_s
    0.01
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
        for name in (
            "speaker_jitter_hz",
            "microphone_noise_pa",
            "background_noise_pa",
            "latency_s",
            "tail_s",
            "source_pressure_pa",
        ):
            if not getattr(self, name) >= 0:
                raise InvalidInputError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not self.full_scale_pa > 0 or not self.speaker_jitter_bandwidth_hz > 0:
            raise InvalidInputError("full_scale_pa and speaker_jitter_bandwidth_hz must be > 0")
        if self.bits is not None and not 2 <= self.bits <= 32:
            raise InvalidInputError(f"bits must be None or in 2..32, got {self.bits}")


def typical_conditions(**changes: Any) -> RecordingConditions:
    """Describe a laptop-and-PVC-tube recording, with optional changes.

    Speaker jitter σ 0.1 Hz (the paper's σ_v), a 30 dB SPL microphone, 50 dB SPL room noise
    and 10 ms of audio latency.

    Parameters
    ----------
    **changes
        Fields of :class:`RecordingConditions` to override.

    Returns
    -------
    RecordingConditions
        The conditions.

    Raises
    ------
    InvalidInputError
        An override that is not valid.

    See Also
    --------
    RecordingConditions

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3 (σ_v = 0.1 Hz).

    Examples
    --------
    >>> from dstoolkit.gauge import typical_conditions
    >>> typical_conditions().speaker_jitter_hz
    0.1
    >>> typical_conditions(latency_s=0.0).latency_s
    0.0
    """
    base = {
        "speaker_jitter_hz": 0.1,
        "microphone_noise_pa": spl_to_pa(30.0),
        "background_noise_pa": spl_to_pa(50.0),
        "latency_s": 0.01,
    }
    return RecordingConditions(**{**base, **changes})


@dataclass(frozen=True)
class Recording:
    """A microphone recording in digital full-scale units, with the truth when simulated.

    Parameters
    ----------
    samples : numpy.ndarray, shape (n,)
        The samples, full-scale units in [−1, 1].
    sweep : LinearSweep
        The sweep that was played.
    setup : TubeSetup, optional
        The simulated tube (None for a real recording).
    conditions : RecordingConditions, optional
        The simulated conditions.
    speaker_error_times : numpy.ndarray, shape (J,), optional
        Times of the speaker's frequency error, s since the sweep started.
    speaker_error_hz : numpy.ndarray, shape (J,), optional
        The speaker's frequency error δf at those times, Hz.

    See Also
    --------
    synthesize_recording : Makes one.
    detect_resonances : Reads its resonances.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.
    """

    samples: np.ndarray
    sweep: LinearSweep
    setup: TubeSetup | None = None
    conditions: RecordingConditions | None = None
    speaker_error_times: np.ndarray | None = field(default=None, repr=False)
    speaker_error_hz: np.ndarray | None = field(default=None, repr=False)

    @property
    def sample_rate(self) -> float:
        """Samples per second, Hz (the sweep's)."""
        return self.sweep.sample_rate

    @property
    def times(self) -> np.ndarray:
        """Times of the samples since the recording started, s, shape (n,)."""
        return np.arange(self.samples.size) / self.sweep.sample_rate

    def speaker_error_at(self, emission_time_s: Any) -> np.ndarray:
        """Interpolate the speaker's frequency error δf at times since the sweep started.

        Parameters
        ----------
        emission_time_s : float or array_like, any shape
            Times since the sweep started, s.

        Returns
        -------
        numpy.ndarray
            δf, Hz, shaped as ``emission_time_s`` (zeros for a real recording).
        """
        t = np.asarray(emission_time_s, dtype=float)
        if self.speaker_error_hz is None or self.speaker_error_times is None:
            return np.zeros_like(t)
        return np.interp(t, self.speaker_error_times, self.speaker_error_hz)


def model_envelope(
    setup: TubeSetup, sweep: LinearSweep, emission_time_s: Any, echo_floor: float = 1e-4
) -> np.ndarray:
    """Compute the noise-free envelope of the microphone's pressure over the source's.

    |Σ_m a_m gate(u − mΔ) e^(−iθ_m(u))| with θ_m(u) = φ(u) − φ(u − mΔ): every echo of the
    sweep, at times u since the sweep started.

    Parameters
    ----------
    setup : TubeSetup
        The simulated gauge.
    sweep : LinearSweep
        The sweep.
    emission_time_s : float or array_like, any shape
        Times u since the sweep started, s.
    echo_floor : float, optional
        Echoes weaker than this (relative to the direct wave) are left out (default 1e-4).

    Returns
    -------
    numpy.ndarray
        The envelope, relative to the direct wave, shaped as ``emission_time_s``.

    See Also
    --------
    envelope : The envelope of a recording.
    model_peak_frequencies : The peaks of this envelope.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (29).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.gauge import LinearSweep, TubeSetup, model_envelope
    >>> sweep = LinearSweep(1000.0, 1200.0, duration=1.0)
    >>> env = model_envelope(TubeSetup(1.3), sweep, np.linspace(0.1, 0.9, 5))
    >>> env.shape, bool(np.all(env > 0))
    ((5,), True)
    """
    u = np.asarray(emission_time_s, dtype=float)
    delta = setup.round_trip_s
    total = np.zeros(u.shape, complex)
    for m in range(setup.echo_count(sweep.f_start, echo_floor) + 1):
        e = u - m * delta
        total += (
            setup.echo_gain(m, sweep.frequency_at(e))
            * sweep.gate(e)
            * np.exp(-1j * (sweep.phase(u) - sweep.phase(e)))
        )
    return np.abs(total)


def _shaped_draw(rng: np.random.Generator, n: int, shape: np.ndarray) -> tuple[np.ndarray, float]:
    """One draw of Gaussian noise of amplitude spectrum ``shape``, and its process's RMS.

    ``shape`` is on rfftfreq(n). The RMS of the *process* the draw comes from is the root
    energy of its impulse response: the draw times ``rms`` / that RMS has the process RMS
    ``rms``.
    """
    x = np.fft.irfft(np.fft.rfft(rng.standard_normal(n)) * shape, n)
    impulse = np.fft.irfft(shape.astype(complex), n)  # x = white ⊛ impulse (circular)
    return x, float(np.sqrt(np.sum(impulse**2)))


def _shaped_noise(
    rng: np.random.Generator, n: int, dt: float, shape: np.ndarray, rms: float
) -> np.ndarray:
    """Stationary Gaussian noise whose amplitude spectrum is ``shape`` (on rfftfreq(n, dt)).

    It is scaled so that the *process* has RMS ``rms`` (not each draw: draws vary as they
    should).
    """
    x, process_rms = _shaped_draw(rng, n, shape)
    return x * (rms / process_rms)


def _gaussian_shape(n: int, dt: float, bandwidth_hz: float) -> np.ndarray:
    """Make a Gaussian amplitude spectrum of width ``bandwidth_hz`` on rfftfreq(n, dt)."""
    return np.exp(-0.5 * (np.fft.rfftfreq(n, dt) / bandwidth_hz) ** 2)


def _gaussian_process(
    rng: np.random.Generator, n: int, dt: float, sigma: float, bandwidth_hz: float
) -> np.ndarray:
    """Zero-mean Gaussian series of RMS ``sigma``, Gaussian spectrum of ``bandwidth_hz``."""
    return _shaped_noise(rng, n, dt, _gaussian_shape(n, dt, bandwidth_hz), sigma)


def _jitter_grid(sweep: LinearSweep, bandwidth_hz: float) -> tuple[np.ndarray, float]:
    """Make the times of the speaker's frequency error (s since the sweep started), and step."""
    dt = min(1e-3, 0.1 / bandwidth_hz)
    return np.arange(-0.01, sweep.duration + 0.01 + dt, dt), dt


def speaker_frequency_error(
    sweep: LinearSweep, conditions: RecordingConditions, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Draw the speaker's frequency error δf(t) over the sweep.

    Parameters
    ----------
    sweep : LinearSweep
        The sweep.
    conditions : RecordingConditions
        Its ``speaker_jitter_hz`` and ``speaker_jitter_bandwidth_hz``.
    rng : numpy.random.Generator
        Source of the draw (none is made without jitter).

    Returns
    -------
    times : numpy.ndarray, shape (J,)
        Times since the sweep started, s, on a grid of at most 1 ms.
    error : numpy.ndarray, shape (J,)
        δf, Hz; zero when ``conditions.speaker_jitter_hz`` is 0.
    """
    t, dt = _jitter_grid(sweep, conditions.speaker_jitter_bandwidth_hz)
    if conditions.speaker_jitter_hz <= 0:
        return t, np.zeros(t.size)
    return t, _gaussian_process(
        rng, t.size, dt, conditions.speaker_jitter_hz, conditions.speaker_jitter_bandwidth_hz
    )


def _pink_shape(n: int, fs: float) -> np.ndarray:
    """Make the amplitude spectrum of 1/f power above 20 Hz (flat below, no DC)."""
    f = np.fft.rfftfreq(n, 1.0 / fs)
    shape = 1.0 / np.sqrt(np.maximum(f, 20.0))
    shape[0] = 0.0
    return shape


class _Draws(NamedTuple):
    """The random draws of one recording, before they are scaled to the conditions.

    The speaker's frequency error, the microphone's white noise, the pink background (each
    None when its level is 0: then no draw is made). Shaped draws come with the RMS of
    their process (:func:`_shaped_draw`).
    """

    jitter_times: np.ndarray
    jitter: tuple[np.ndarray, float] | None
    microphone: np.ndarray | None
    background: tuple[np.ndarray, float] | None


def _draw(
    rng: np.random.Generator,
    sweep: LinearSweep,
    n: int,
    jitter_bandwidth_hz: float,
    jitter: bool,
    microphone: bool,
    background: bool,
) -> _Draws:
    """Draw the noises of a recording of ``n`` samples, in the generator's order."""
    t_j, dt = _jitter_grid(sweep, jitter_bandwidth_hz)
    shaped = (
        _shaped_draw(rng, t_j.size, _gaussian_shape(t_j.size, dt, jitter_bandwidth_hz))
        if jitter
        else None
    )
    white = rng.standard_normal(n) if microphone else None
    pink = _shaped_draw(rng, n, _pink_shape(n, sweep.sample_rate)) if background else None
    return _Draws(t_j, shaped, white, pink)


@functools.lru_cache(maxsize=2)
def _seeded_draws(
    seed: int,
    sweep: LinearSweep,
    n: int,
    jitter_bandwidth_hz: float,
    jitter: bool,
    microphone: bool,
    background: bool,
) -> _Draws:
    """:func:`_draw` with a fresh generator of an integer ``seed``, kept.

    Kept for the next recording with the same seed (an explorer moving the level redraws
    the same noise); the last two draws only, each up to two arrays of the recording's
    length. The arrays are read-only.
    """
    draws = _draw(
        np.random.default_rng(seed), sweep, n, jitter_bandwidth_hz, jitter, microphone, background
    )
    for array in (
        draws.jitter_times,
        draws.microphone,
        *(draws.jitter or ()),
        *(draws.background or ()),
    ):
        if isinstance(array, np.ndarray):
            array.flags.writeable = False
    return draws


def _gated(values: np.ndarray, sweep: LinearSweep, e: np.ndarray) -> np.ndarray:
    """``values`` times :meth:`LinearSweep.gate` at the ascending times ``e``, in place.

    ``e`` is in s since the sweep started, within it. The gate is computed only near the
    sweep's ends, where it is not 1, so the product is the same number for number.
    """
    margin = 2.0 * sweep.taper + 2.0 / sweep.sample_rate
    a = int(np.searchsorted(e, margin))
    b = max(a, int(np.searchsorted(e, sweep.duration - margin)))
    values[:a] *= sweep.gate(e[:a])
    values[b:] *= sweep.gate(e[b:])
    return values


def _jitter_phase(draws: _Draws, jitter_hz: float) -> tuple[np.ndarray, np.ndarray | None]:
    """Scale the speaker's frequency error δf (Hz) on ``draws.jitter_times``; add its phase.

    The phase is ψ = 2π ∫ δf (trapezoids), None without jitter.
    """
    t_j = draws.jitter_times
    if draws.jitter is None:
        return np.zeros(t_j.size), None
    df = draws.jitter[0] * (jitter_hz / draws.jitter[1])
    return df, 2.0 * np.pi * np.concatenate(
        ([0.0], np.cumsum(0.5 * (df[1:] + df[:-1]) * np.diff(t_j)))
    )


def _echo_span(u: np.ndarray, delay_s: float, duration_s: float) -> tuple[int, int]:
    """Find the samples (``lo:hi`` of the times ``u``) that an echo ``delay_s`` late covers."""
    return (
        int(np.searchsorted(u, delay_s)),
        int(np.searchsorted(u, delay_s + duration_s, side="right")),
    )


def _echo_wave(
    sweep: LinearSweep,
    e: np.ndarray,
    gain: np.ndarray,
    t_j: np.ndarray,
    psi_j: np.ndarray | None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """One echo at the times ``e`` since it left the speaker: gain × gate × cos(φ + ψ).

    The arithmetic is in place (``gain`` is overwritten) and into ``out`` when given.
    """
    gain = _gated(gain, sweep, e)
    wave = sweep.phase(e, out=out)
    if psi_j is not None:
        wave += np.interp(e, t_j, psi_j)
    wave = np.cos(wave, out=wave)
    wave *= gain
    return wave


@functools.lru_cache(maxsize=1)
def _seeded_direct_wave(
    seed: int,
    sweep: LinearSweep,
    n: int,
    latency_s: float,
    jitter_hz: float,
    kinds: tuple[float, bool, bool, bool],
) -> np.ndarray:
    """Compute the direct wave (m = 0, a_0 = 1) of a recording with an integer seed, kept.

    It is the same in every tube, so it is kept (read-only) for the next recording with
    these conditions.
    """
    u = np.arange(n) / sweep.sample_rate - latency_s
    draws = _seeded_draws(seed, sweep, n, *kinds)
    lo, hi = _echo_span(u, 0.0, sweep.duration)
    e = u[lo:hi] - 0.0  # as the echoes' e = u − mΔ, m = 0
    wave = _echo_wave(
        sweep, e, np.ones_like(e), draws.jitter_times, _jitter_phase(draws, jitter_hz)[1]
    )
    wave.flags.writeable = False
    return wave


def synthesize_recording(
    setup: TubeSetup,
    sweep: LinearSweep = PAPER_SWEEP,
    conditions: RecordingConditions | None = None,
    seed: int | np.random.Generator = 0,
    echo_floor: float = 1e-4,
) -> Recording:
    """Synthesise the microphone recording of ``sweep`` in the tube ``setup``.

    p(t) = P0 [s(u) + Σ_m a_m(f(u − mΔ)) s(u − mΔ)] + noises, u = t − τ, with
    s(u) = gate(u) cos(φ(u) + ψ(u)) and ψ the phase of the speaker's frequency error. Echoes
    weaker than ``echo_floor`` are dropped. Seeded: equal arguments give equal recordings.

    Parameters
    ----------
    setup : TubeSetup
        The simulated gauge.
    sweep : LinearSweep, optional
        The sweep (default :data:`PAPER_SWEEP`).
    conditions : RecordingConditions, optional
        Noise, gain and timing (default: no noise, no latency).
    seed : int or numpy.random.Generator, optional
        Seed or generator of the noises (default 0).
    echo_floor : float, optional
        Echoes weaker than this (relative to the direct wave) are left out (default 1e-4).

    Returns
    -------
    Recording
        Samples / full scale, shape (n,), clipped to [−1, 1] and quantised; n covers the
        latency, the sweep and the tail.

    Raises
    ------
    MemoryBudgetError
        A recording that would exceed the memory budget.

    See Also
    --------
    detect_resonances : Reads the resonances of the recording.
    virtual_tube_signal : The same pressure, to play through a real audio path.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (27)–(29), §4.3.

    Examples
    --------
    >>> from dstoolkit.gauge import LinearSweep, TubeSetup, synthesize_recording
    >>> sweep = LinearSweep(1000.0, 1200.0, duration=0.5, sample_rate=8000.0)
    >>> rec = synthesize_recording(TubeSetup(1.3), sweep)
    >>> rec.samples.shape, rec.sample_rate
    ((4800,), 8000.0)
    """
    cond = RecordingConditions() if conditions is None else conditions
    fs = sweep.sample_rate
    n = int(round((sweep.duration + cond.latency_s + cond.tail_s) * fs))
    # the pressure, three work arrays, the time axis, the noises' draws and the samples
    check_memory(
        n * 8.0 * 12,
        f"synthesising a recording of {n} samples",
        "shorten the sweep or lower its sample rate",
    )
    kinds = (
        cond.speaker_jitter_bandwidth_hz,
        cond.speaker_jitter_hz > 0,
        cond.microphone_noise_pa > 0,
        cond.background_noise_pa > 0,
    )
    if isinstance(seed, int | np.integer):
        draws = _seeded_draws(int(seed), sweep, n, *kinds)
        # the noises' levels do not move the sound: a change of them only adds other noise
        sound = _seeded_sound(
            setup, sweep, int(seed), echo_floor, n, kinds, _sound_conditions(cond)
        )
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
    return Recording(
        samples=samples,
        sweep=sweep,
        setup=setup,
        conditions=cond,
        speaker_error_times=draws.jitter_times.copy(),
        speaker_error_hz=df,
    )


def _sound_conditions(cond: RecordingConditions) -> RecordingConditions:
    """``cond`` without the levels of the noises (what the sound in the tube depends on)."""
    return replace(cond, microphone_noise_pa=0.0, background_noise_pa=0.0)


@functools.lru_cache(maxsize=1)
def _seeded_sound(
    setup: TubeSetup,
    sweep: LinearSweep,
    seed: int,
    echo_floor: float,
    n: int,
    kinds: tuple[float, bool, bool, bool],
    cond: RecordingConditions,
) -> np.ndarray:
    """:func:`_sound` of a recording with an integer seed, kept (read-only).

    Kept for the next recording that differs only in the noises' levels (``cond``:
    :func:`_sound_conditions`).
    """
    sound = _sound(
        setup,
        sweep,
        _seeded_draws(seed, sweep, n, *kinds),
        echo_floor,
        n,
        cond,
        direct=_seeded_direct_wave(seed, sweep, n, cond.latency_s, cond.speaker_jitter_hz, kinds),
    )
    sound.flags.writeable = False
    return sound


def _sound(
    setup: TubeSetup,
    sweep: LinearSweep,
    draws: _Draws,
    echo_floor: float,
    n: int,
    cond: RecordingConditions,
    direct: np.ndarray | None = None,
) -> np.ndarray:
    """Compute the pressure of the sweep and its echoes at the microphone, without noise.

    P0 [s(u) + Σ_m a_m(f(u − mΔ)) s(u − mΔ)] (eqs. 27–29); ``direct``: the wave m = 0 if
    known.
    """
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
