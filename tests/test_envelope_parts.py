"""The envelope filters the demodulated recording's real and imaginary parts one at a time."""

import numpy as np
from scipy import signal

from dstoolkit.gauge import LinearSweep, envelope
from dstoolkit.gauge._resonance import _demodulator


def test_the_envelope_is_that_of_the_complex_demodulated_recording():
    """The filter is real and linear: part by part it gives the same bits as all at once."""
    sweep = LinearSweep(1000.0, 1400.0, duration=0.5, sample_rate=8000.0)
    rng = np.random.default_rng(4)
    samples = 0.5 * sweep.waveform() + 0.01 * rng.standard_normal(sweep.waveform().size)
    for latency, rate in ((0.0, 1000.0), (0.013, 250.0)):
        times, env = envelope(samples, sweep, latency, envelope_rate_hz=rate)
        sos = signal.butter(4, 200.0, fs=sweep.sample_rate, output="sos")
        step = max(1, int(sweep.sample_rate // max(rate, 800.0)))
        complex_base = samples * _demodulator(sweep, samples.size, latency)
        whole = 2.0 * np.abs(signal.sosfiltfilt(sos, complex_base)[::step])
        np.testing.assert_array_equal(env, whole)
        np.testing.assert_array_equal(times, np.arange(0, samples.size, step) / 8000.0)
