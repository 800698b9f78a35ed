"""The one latency estimator (dstoolkit.gauge.estimate_latency).

It is tested on the sweep in a tube and on the lab's calibration chirp: the resonance
detector and the audio layer use the same one.
"""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.errors import DetectionError
from dstoolkit.gauge import (
    FIRST_ARRIVAL,
    PAPER_SWEEP,
    LinearSweep,
    RecordingConditions,
    TubeSetup,
    detect_resonances,
    estimate_latency,
    synthesize_recording,
)

SHORT = LinearSweep(f_start=1000.0, f_stop=2400.0, duration=1.0, sample_rate=16000.0)


def _tube(latency_s: float, **setup: float) -> np.ndarray:
    conditions = RecordingConditions(latency_s=latency_s)
    return synthesize_recording(TubeSetup(1.3, 27.0, **setup), SHORT, conditions).samples


@pytest.mark.parametrize("latency_s", [0.0, 0.0375, 0.4])
def test_sweep_latency_in_a_tube_recording(latency_s: float) -> None:
    est = estimate_latency(SHORT.waveform(), _tube(latency_s), SHORT.sample_rate)
    assert est.lag == round(latency_s * SHORT.sample_rate)
    assert est.seconds == pytest.approx(latency_s, abs=1 / SHORT.sample_rate)
    assert est.correlation > 0.5 and est.significance > 50


def test_the_direct_wave_wins_over_the_stronger_first_echo() -> None:
    # a rigid top: the first echo (2L/c = 7.6 ms later) is about 1.9 times the direct wave
    rec = _tube(0.1, top_reflection=1.0)
    first = estimate_latency(SHORT.waveform(), rec, SHORT.sample_rate)
    strongest = estimate_latency(SHORT.waveform(), rec, SHORT.sample_rate, first_arrival=None)
    assert first.seconds == pytest.approx(0.1, abs=1 / SHORT.sample_rate)
    assert strongest.seconds == pytest.approx(0.1 + 2 * 1.3 / 347.6, abs=3e-4)
    # the direct wave is about 1/1.9 of the echo: a threshold above that misses it
    assert FIRST_ARRIVAL < 1 / 1.9
    late = estimate_latency(SHORT.waveform(), rec, SHORT.sample_rate, first_arrival=0.6)
    assert late.lag == strongest.lag


def test_min_significance_rejects_a_recording_without_the_sweep() -> None:
    noise = np.random.default_rng(1).normal(0.0, 0.1, 2 * SHORT.n_samples)
    est = estimate_latency(SHORT.waveform(), noise, SHORT.sample_rate)
    assert est.significance < 8 and abs(est.correlation) < 0.1
    with pytest.raises(DetectionError, match="no sweep"):
        estimate_latency(SHORT.waveform(), noise, SHORT.sample_rate, min_significance=8.0)


def test_detector_uses_the_estimator_on_the_sweep() -> None:
    rec = synthesize_recording(
        TubeSetup(1.3, 27.0), PAPER_SWEEP, RecordingConditions(latency_s=0.0123), seed=3
    )
    detection = detect_resonances(rec)
    direct = estimate_latency(PAPER_SWEEP.waveform(), rec.samples, PAPER_SWEEP.sample_rate)
    assert detection.latency_s == direct.seconds
    assert detection.latency_s == pytest.approx(0.0123, abs=1 / PAPER_SWEEP.sample_rate)
    # a given latency is used as is, not estimated
    assert detect_resonances(rec, latency_s=0.02).latency_s == 0.02


def test_errors_are_detection_errors_and_value_errors() -> None:
    ref = SHORT.waveform()
    for call, match in (
        (lambda: estimate_latency(ref, ref[:10], SHORT.sample_rate), "shorter than"),
        (lambda: estimate_latency(ref, np.zeros(ref.size), SHORT.sample_rate), "silent"),
        (lambda: estimate_latency(ref, ref, -1.0), "samplerate"),
        (lambda: estimate_latency(ref, ref, SHORT.sample_rate, offset=-3), "offset"),
    ):
        with pytest.raises(DetectionError, match=match) as info:
            call()
        assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("n", [7, 8, 1001, 4096, 300_007])
def test_the_analytic_signal_is_scipys_hilbert_at_a_fast_length(n: int) -> None:
    from scipy import fft, signal

    from dstoolkit.gauge._latency import _analytic_signal

    x = np.random.default_rng(n).standard_normal(n)
    size = fft.next_fast_len(n)
    assert (size > n) == (n in (1001, 300_007))  # 1001 = 7 · 11 · 13 and a prime are padded
    # the two libraries' FFTs round differently: a few ulps of the signal's scale
    np.testing.assert_allclose(
        _analytic_signal(x), signal.hilbert(x, N=size)[:n], rtol=0, atol=1e-11
    )


def test_the_matched_filter_keeps_no_fft_plans(monkeypatch: pytest.MonkeyPatch) -> None:
    # scipy.fft keeps the plans of its last transforms; a long transform of an awkward
    # length (every recording has its own) holds tens of MiB in a student's kernel
    import scipy.fft
    import scipy.signal

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("a long transform went through scipy.fft")

    for name in ("fft", "ifft", "rfft", "irfft"):
        monkeypatch.setattr(scipy.fft, name, refuse)
    monkeypatch.setattr(scipy.signal, "hilbert", refuse)
    est = estimate_latency(SHORT.waveform(), _tube(0.0375), SHORT.sample_rate)
    assert est.lag == round(0.0375 * SHORT.sample_rate)
    det = detect_resonances(synthesize_recording(TubeSetup(1.3, 27.0), SHORT))
    assert det.frequencies.size >= 5
