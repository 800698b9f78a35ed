"""The linear frequency sweep that drives the speaker (paper §4.3).

f(t) = f_start + κ t with rate κ = (f_stop − f_start)/duration, phase
φ(t) = 2π (f_start t + κ t²/2). The paper swept 1000 → 2400 Hz in 5 s at 44.1 kHz
(κ = 280 Hz/s); the filter's band (paper §4.1) is 1000–2500 Hz. Both are parameters.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.utils.checks import real_number


@dataclass(frozen=True)
class LinearSweep:
    """An upward linear sweep f(t) = f_start + κ t, the signal that drives the speaker.

    Parameters
    ----------
    f_start, f_stop : float, optional
        Band of the sweep, Hz, ``0 < f_start < f_stop < sample_rate/2`` (default 1000 and
        2400, the paper's).
    duration : float, optional
        Seconds from f_start to f_stop (default 5).
    sample_rate : float, optional
        Samples per second of the played and recorded signals, Hz (default 44100).
    taper : float, optional
        Seconds of raised-cosine fade at each end (avoids clicks; 0 for none), at most
        ``duration/2`` (default 0.01).

    Raises
    ------
    InvalidInputError
        A field that is not a finite real number, a band that does not rise or reaches the
        Nyquist frequency, a duration that is not positive or a taper longer than half of it.

    See Also
    --------
    PAPER_SWEEP : The paper's sweep.
    synthesize_recording : What a microphone in the tube records of it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §4.3.

    Examples
    --------
    >>> from dstoolkit.gauge import LinearSweep
    >>> sweep = LinearSweep(1000.0, 2400.0, duration=5.0)
    >>> sweep.rate, sweep.n_samples
    (280.0, 220500)
    >>> float(sweep.frequency_at(2.5))
    1700.0
    """

    f_start: float = 1000.0
    f_stop: float = 2400.0
    duration: float = 5.0
    sample_rate: float = 44100.0
    taper: float = 0.01

    def __post_init__(self) -> None:
        for name in ("f_start", "f_stop", "duration", "sample_rate", "taper"):
            real_number(getattr(self, name), name)  # a finite real number, not a string
        if not 0 < self.f_start < self.f_stop:
            raise InvalidInputError(
                f"need 0 < f_start < f_stop (an upward sweep), got {self.f_start}, {self.f_stop}"
            )
        if self.f_stop >= self.sample_rate / 2:
            raise InvalidInputError(
                f"f_stop = {self.f_stop} Hz must lie below the Nyquist frequency "
                f"{self.sample_rate / 2} Hz; raise sample_rate"
            )
        if self.duration <= 0 or not 0 <= 2 * self.taper <= self.duration:
            raise InvalidInputError(
                f"need duration > 0 and 0 <= taper <= duration/2, got {self.duration}, {self.taper}"
            )

    @property
    def rate(self) -> float:
        """The sweep rate κ = (f_stop − f_start)/duration, Hz per second."""
        return (self.f_stop - self.f_start) / self.duration

    @property
    def band(self) -> tuple[float, float]:
        """(f_start, f_stop), Hz."""
        return (self.f_start, self.f_stop)

    @property
    def n_samples(self) -> int:
        """Number of samples of the sweep, round(duration × sample_rate)."""
        return int(round(self.duration * self.sample_rate))

    def times(self, n: int | None = None) -> np.ndarray:
        """Sample times 0, 1/fs, 2/fs, ….

        Parameters
        ----------
        n : int, optional
            Number of samples (default the sweep's length, :attr:`n_samples`).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Times, s.
        """
        return np.arange(self.n_samples if n is None else n) / self.sample_rate

    def frequency_at(self, t: Any, out: np.ndarray | None = None) -> np.ndarray:
        """Instantaneous frequency f(t) = f_start + κ t (not clipped to the band).

        Parameters
        ----------
        t : float or array_like, any shape
            Times since the sweep started, s.
        out : numpy.ndarray, optional
            Float array of the shape of ``t`` to write into (it may be ``t`` itself).

        Returns
        -------
        numpy.ndarray
            f(t), Hz, shaped as ``t`` (``out`` when given).

        See Also
        --------
        time_at : The inverse.
        """
        f = np.multiply(self.rate, np.asarray(t, dtype=float), out=out)
        f += self.f_start
        return f

    def time_at(self, f: Any) -> np.ndarray:
        """Time at which the sweep reaches frequency f, t = (f − f_start)/κ.

        Parameters
        ----------
        f : float or array_like, any shape
            Frequencies, Hz.

        Returns
        -------
        numpy.ndarray
            Times since the sweep started, s, shaped as ``f``.

        See Also
        --------
        frequency_at : The inverse.
        """
        return (np.asarray(f, dtype=float) - self.f_start) / self.rate

    def phase(self, t: Any, out: np.ndarray | None = None) -> np.ndarray:
        """Phase φ(t) = 2π (f_start t + κ t²/2) of the sweep.

        Parameters
        ----------
        t : float or array_like, any shape
            Times since the sweep started, s.
        out : numpy.ndarray, optional
            Float array of the shape of ``t`` to write into.

        Returns
        -------
        numpy.ndarray
            φ(t), radians, shaped as ``t``.
        """
        t = np.asarray(t, dtype=float)
        phi, f_mean = np.multiply(2.0 * np.pi, t, out=out), 0.5 * self.rate * t
        f_mean += self.f_start  # in place, as in frequency_at
        phi *= f_mean
        return phi

    def gate(self, t: Any) -> np.ndarray:
        """Amplitude window: 1 inside the sweep, raised-cosine ends of ``taper`` s, 0 outside.

        Parameters
        ----------
        t : float or array_like, any shape
            Times since the sweep started, s.

        Returns
        -------
        numpy.ndarray
            The window in [0, 1], shaped as ``t``.
        """
        t = np.asarray(t, dtype=float)
        inside = (t >= 0) & (t <= self.duration)
        if self.taper <= 0:
            return inside.astype(float)
        edge = np.minimum(t, self.duration - t) / self.taper
        out = inside.astype(float)
        ramp = inside & (edge < 1.0)  # the cosine only where the fade is
        out[ramp] = 0.5 - 0.5 * np.cos(np.pi * edge[ramp])
        return out

    def waveform(self, t: Any = None) -> np.ndarray:
        """Compute the speaker's drive signal, cos φ(t) times :meth:`gate`.

        Parameters
        ----------
        t : array_like, optional
            Times since the sweep started, s (default :meth:`times`).

        Returns
        -------
        numpy.ndarray
            Samples in [−1, 1], shaped as ``t``.
        """
        t = self.times() if t is None else np.asarray(t, dtype=float)
        return self.gate(t) * np.cos(self.phase(t))


#: The paper's experiment: 1000 → 2400 Hz in 5 s at 44.1 kHz (§4.3).
PAPER_SWEEP = LinearSweep()
