"""The audio latency τ: where a known signal sits in a recording (paper §4.3).

Between the first sample handed to the sound card and its arrival at the microphone lies
the delay τ of the audio path. For a linear sweep of rate κ Hz/s it moves every detected
resonance by κ τ, so it is measured and corrected, by one estimator used everywhere: the
resonance detector finds τ from the sweep itself, the lab's measurement from a short
calibration chirp played in the same stream (:mod:`dstoolkit.audio`).

The estimator is a matched filter: the recording is cross-correlated with what was
played, and the correlation's envelope has one bump per arrival of the signal. At a tube
the microphone also hears the signal's echoes from the surface, and the first one can be
louder than the direct sound (up to 1 + R_t times at a reflecting top), so the *first*
arrival is taken: the first place where the envelope reaches :data:`FIRST_ARRIVAL` of its
maximum, refined to the largest |correlation| within the next :data:`ARRIVAL_WINDOW_S`.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import fft as sp_fft

from dstoolkit.errors import DetectionError
from dstoolkit.utils.checks import as_signal

#: Fraction of the strongest arrival that counts as an arrival. A direct sound followed by
#: an echo 1 + R_t ≤ 2 times louder still reaches half of the maximum; 0.4 leaves room.
FIRST_ARRIVAL = 0.4
#: Width of one arrival in the matched filter's envelope, s. Echoes in a tube come at least
#: 2L/c later (2.9 ms for L = 0.5 m).
ARRIVAL_WINDOW_S = 0.002


@dataclass(frozen=True)
class LatencyEstimate:
    """Delay of a recording behind what was played.

    ``recorded[offset + lag + i]`` is ``reference[i]`` played at ``offset``. Made by
    :func:`estimate_latency`.

    Parameters
    ----------
    lag : int
        The delay in samples (negative when the input stream started after the output).
    samplerate : float
        Sample rate, Hz.
    correlation : float
        Normalised correlation (cosine of the angle) between the reference and the recording
        at the lag, in [−1, 1]: 1 is a perfect copy, near 0 means the reference was not found
        (negative: the microphone inverts polarity).
    significance : float
        The matched filter's peak over its median in the searched range: far above 1 where
        the reference is present.

    See Also
    --------
    estimate_latency : Makes it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3 (the sweep and the recording).
    """

    lag: int
    samplerate: float
    correlation: float
    significance: float

    @property
    def seconds(self) -> float:
        """The latency τ = lag / samplerate, s."""
        return self.lag / self.samplerate


def _energy(x: np.ndarray) -> float:
    """Σ x², by ``einsum``.

    A BLAS dot of a long vector starts threads, whose start-up outweighs the arithmetic on
    a busy machine.
    """
    return float(np.einsum("i,i->", x, x))


def valid_correlation(recorded: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Compute the matched filter ``c[j] = Σ_i recorded[j + i] reference[i]`` by FFT.

    For j = 0 .. len(recorded) − len(reference): ``scipy.signal.correlate(recorded,
    reference, "valid")``.

    Parameters
    ----------
    recorded : numpy.ndarray, shape (n,)
        The recording.
    reference : numpy.ndarray, shape (m,)
        What was played, m ≤ n.

    Returns
    -------
    numpy.ndarray, shape (n − m + 1,)
        The correlation at every lag where the reference lies inside the recording.

    See Also
    --------
    estimate_latency : Finds the reference's first arrival in it.

    Notes
    -----
    A circular correlation of length L ≥ len(recorded) does not wrap around at these lags,
    so the transforms need only that length, not len(recorded) + len(reference) − 1: half
    the size, and one real transform fewer per signal. By ``numpy.fft``, which keeps no plans
    between calls (as does the envelope's analytic signal).

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3 (the sweep and its recording).

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.gauge import valid_correlation
    >>> valid_correlation(np.array([0.0, 1.0, 2.0, 0.0]), np.array([1.0, 2.0])).round(6)
    array([2., 5., 2.])
    """
    size = sp_fft.next_fast_len(recorded.size, real=True)
    spectrum = np.fft.rfft(recorded, size)
    spectrum *= _reference_spectrum(reference, size)
    return np.fft.irfft(spectrum, size)[: recorded.size - reference.size + 1]


def _analytic_signal(x: np.ndarray) -> np.ndarray:
    """Compute the analytic signal x + i H(x) of a real signal (its envelope is its modulus).

    ``scipy.signal.hilbert`` on ``x`` padded with zeros to a fast length, cut back: a
    transform of the signal's own length (any length: a recording's) goes through a chirp
    transform twice as long, whose work arrays are several times the signal. By
    ``numpy.fft``, which keeps nothing between calls: ``scipy.fft`` keeps the plans of its
    last transforms.
    """
    n = x.size
    size = sp_fft.next_fast_len(n)
    # one complex array, transformed in place (fft(x, size) would first cast x to a
    # complex copy); the weights 1, 2 (positive frequencies), 1 (Nyquist), 0 (negative)
    # applied by slice
    spectrum = np.zeros(size, complex)
    spectrum[:n] = x
    np.fft.fft(spectrum, out=spectrum)
    spectrum[1 : (size + 1) // 2] *= 2.0
    spectrum[size // 2 + 1 :] *= 0.0
    return np.fft.ifft(spectrum, out=spectrum)[:n]


def _within(size: int, offset: int, reach: float) -> np.ndarray:
    """Mark the j in [0, ``size``) whose lag j − ``offset`` lies within ±``reach`` samples.

    A whole number k has |k| ≤ reach exactly when |k| ≤ ⌊reach⌋: one slice, no array of
    lags (none for a negative or NaN ``reach``).
    """
    allowed = np.zeros(size, bool)
    if reach >= 0:
        whole = int(min(np.floor(reach), size + abs(offset)))  # a finite bound for ±inf
        allowed[max(0, offset - whole) : max(0, offset + whole + 1)] = True
    return allowed


#: Conjugate spectra of read-only references, by (id, size), each with a weak reference to
#: its array (an id is reused once its array is gone).
_SPECTRA: dict[tuple[int, int], tuple[weakref.ref[np.ndarray], np.ndarray]] = {}


def _reference_spectrum(reference: np.ndarray, size: int) -> np.ndarray:
    """Compute conj(rfft(reference, size)), kept for a read-only array.

    Only an array that owns its memory is kept (it cannot change): the sweep that
    :func:`~dstoolkit.gauge.detect_resonances` looks for in every recording.
    """
    if reference.flags.writeable or reference.base is not None:
        return np.conj(np.fft.rfft(reference, size))
    key = (id(reference), size)
    kept = _SPECTRA.get(key)
    if kept is None or kept[0]() is not reference:
        if len(_SPECTRA) >= 4:
            _SPECTRA.clear()
        kept = _SPECTRA[key] = (weakref.ref(reference), np.conj(np.fft.rfft(reference, size)))
    return kept[1]


def estimate_latency(
    reference: ArrayLike,
    recorded: ArrayLike,
    samplerate: float,
    *,
    offset: int = 0,
    max_latency_s: float | None = None,
    first_arrival: float | None = FIRST_ARRIVAL,
    min_significance: float | None = None,
) -> LatencyEstimate:
    """Find a played reference in a recording: the audio latency, by matched filtering.

    The reference (the sweep, or a calibration chirp) was played starting at sample
    ``offset`` of the output; the recording started with the output. The matched filter
    ``c[j] = Σ_i recorded[j + i] reference[i]`` (``valid_correlation``) peaks in
    absolute value where the reference sits in the recording (absolute, so an inverted
    polarity still works), at ``j = offset + lag``. The first arrival is taken, not the
    strongest: in a tube the first echo can be louder than the direct sound (up to 1 + R_t
    times). Pure array function: no audio device needed.

    Parameters
    ----------
    reference, recorded : array_like, 1-D
        What was played and what was recorded, same sample rate. The recording must be at
        least as long as the reference.
    samplerate : float
        Sample rate in Hz, to express the lag in seconds.
    offset : int
        Where the reference started in the played output, in samples.
    max_latency_s : float, optional
        Search only ``|lag| <= max_latency_s``. Negative lags are allowed (an input stream
        can start after the output stream).
    first_arrival : float or None
        Fraction of the strongest arrival that counts as an arrival (default
        :data:`FIRST_ARRIVAL`); None takes the strongest.
    min_significance : float, optional
        Raise :class:`~dstoolkit.errors.DetectionError` when the matched filter's peak is
        not this many times its median (the reference is not in the recording).

    Returns
    -------
    LatencyEstimate
        The lag in samples and seconds, the normalised correlation there and the
        significance of the match.

    Raises
    ------
    DetectionError
        Bad arrays (not 1-D, empty, non-finite), a silent reference or recording, a
        recording shorter than the reference, no lag in the search range, or a peak below
        ``min_significance``. It is a ``ValueError``.

    See Also
    --------
    detect_resonances : Finds the latency of a recorded sweep with this estimator.
    latency_offset : How far a latency moves the detected resonances, κ τ.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3 (the sweep and its recording).

    Examples
    --------
    A chirp recorded 441 samples (10 ms at 44.1 kHz) late, at half the amplitude:

    >>> import numpy as np
    >>> from dstoolkit.gauge import estimate_latency
    >>> from scipy.signal import chirp
    >>> fs = 44100
    >>> t = np.arange(2205) / fs
    >>> ref = chirp(t, 500, t[-1], 5000)
    >>> rec = np.zeros(fs)
    >>> rec[441:441 + ref.size] = 0.5 * ref
    >>> est = estimate_latency(ref, rec, fs)
    >>> est.lag, round(1e3 * est.seconds, 3), round(est.correlation, 6)
    (441, 10.0, 1.0)
    """
    ref = as_signal(reference, "reference")
    rec = as_signal(recorded, "recording")
    if not samplerate > 0:
        raise DetectionError(f"samplerate must be positive, got {samplerate}")
    if offset < 0:
        raise DetectionError(f"offset must be >= 0 samples, got {offset}")
    ref_energy = _energy(ref)
    if ref_energy == 0.0:
        raise DetectionError("the reference is silent (all zeros): nothing to look for")
    if rec.size < ref.size:
        raise DetectionError(
            f"the recording ({rec.size} samples) is shorter than the reference "
            f"({ref.size} samples): record longer (add a tail of silence)"
        )
    if not np.any(rec):
        raise DetectionError(
            "the recording is silent (all zeros): nothing reached the input. Check that the "
            "input device is the microphone (or the loopback monitor) and is not muted."
        )
    c = valid_correlation(rec, ref)
    # the lag at j is j − offset (scipy.signal.correlation_lags(..., "valid") − offset)
    allowed = np.ones(c.size, bool)
    if max_latency_s is not None:
        allowed = _within(c.size, offset, max_latency_s * samplerate)
        if not allowed.any():
            raise DetectionError(
                f"no lag within ±{max_latency_s} s fits the recording ({rec.size} samples, "
                f"reference of {ref.size} at offset {offset}); widen max_latency_s"
            )
    # the envelope of the matched filter: one smooth bump per arrival of the reference
    envelope = np.abs(_analytic_signal(c))
    envelope[~allowed] = 0.0
    top = float(envelope.max())
    significance = top / max(float(np.median(envelope[allowed])), 1e-300)
    if min_significance is not None and not significance >= min_significance:
        raise DetectionError(
            f"no sweep (or chirp) found in the recording: the best match with the played "
            f"signal is only {significance:.1f} times the median match (need "
            f"{min_significance}); is the speaker connected, and is this the signal that was "
            "played?"
        )
    score = np.abs(c)
    score[~allowed] = -1.0
    if first_arrival is None:
        j = int(np.argmax(score))
    else:
        start = int(np.flatnonzero(envelope >= first_arrival * top)[0])
        stop = min(start + int(np.ceil(ARRIVAL_WINDOW_S * samplerate)) + 1, c.size)
        j = start + int(np.argmax(score[start:stop]))
    window = rec[j : j + ref.size]
    norm = np.sqrt(ref_energy * _energy(window))
    correlation = float(c[j] / norm) if norm > 0 else 0.0
    return LatencyEstimate(
        lag=j - offset,
        samplerate=float(samplerate),
        correlation=correlation,
        significance=significance,
    )
