"""The linear frequency sweep that drives the speaker (paper §4.3).

f(t) = f_start + k t with rate k = (f_stop − f_start)/duration, phase
φ(t) = 2π (f_start t + k t²/2). The paper swept 1000 → 2400 Hz in 5 s at 44.1 kHz
(k = 280 Hz/s); the filter's band (paper §4.1) is 1000–2500 Hz. Both are parameters.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.utils.checks import real_number


@dataclass(frozen=True)
class LinearSweep:
    """An upward linear sweep.

    Parameters
    ----------
    f_start, f_stop
        Band of the sweep, Hz, ``f_start < f_stop < sample_rate/2``.
    duration
        Seconds from f_start to f_stop.
    sample_rate
        Samples per second of the played and recorded signals.
    taper
        Seconds of raised-cosine fade at each end (avoids clicks; 0 for none).
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
                f"need duration > 0 and 0 <= taper <= duration/2, got {self.duration}, "
                f"{self.taper}"
            )

    @property
    def rate(self) -> float:
        """k = (f_stop − f_start)/duration, Hz per second."""
        return (self.f_stop - self.f_start) / self.duration

    @property
    def band(self) -> tuple[float, float]:
        return (self.f_start, self.f_stop)

    @property
    def n_samples(self) -> int:
        return int(round(self.duration * self.sample_rate))

    def times(self, n: int | None = None) -> np.ndarray:
        """Sample times 0, 1/fs, ... (``n`` samples, default the sweep's length)."""
        return np.arange(self.n_samples if n is None else n) / self.sample_rate

    def frequency_at(self, t: Any, out: np.ndarray | None = None) -> np.ndarray:
        """Instantaneous frequency f(t) = f_start + k t (not clipped to the band); into
        ``out`` when given (the gauge's synthesis: 10⁵ samples per echo)."""
        f = np.multiply(self.rate, np.asarray(t, dtype=float), out=out)
        f += self.f_start
        return f

    def time_at(self, f: Any) -> np.ndarray:
        """Inverse of :meth:`frequency_at`: t = (f − f_start)/k."""
        return (np.asarray(f, dtype=float) - self.f_start) / self.rate

    def phase(self, t: Any, out: np.ndarray | None = None) -> np.ndarray:
        """φ(t) = 2π (f_start t + k t²/2), radians; into ``out`` when given."""
        t = np.asarray(t, dtype=float)
        phi, f_mean = np.multiply(2.0 * np.pi, t, out=out), 0.5 * self.rate * t
        f_mean += self.f_start  # in place, as in frequency_at
        phi *= f_mean
        return phi

    def gate(self, t: Any) -> np.ndarray:
        """Amplitude window: 1 inside, raised-cosine ends of ``taper`` s, 0 outside."""
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
        """The speaker drive cos φ(t) times :meth:`gate`, at ``t`` (default :meth:`times`)."""
        t = self.times() if t is None else np.asarray(t, dtype=float)
        return self.gate(t) * np.cos(self.phase(t))


#: The paper's experiment: 1000 → 2400 Hz in 5 s at 44.1 kHz (§4.3).
PAPER_SWEEP = LinearSweep()
