"""Noise characterisation like the paper's Figs. 8–9 and Tables 1–2, from simulation."""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.gauge import (
    PAPER_SWEEP,
    NoiseCharacterisation,
    RecordingConditions,
    TubeSetup,
    characterise_observation_noise,
    characterise_state_noise,
)


def test_state_noise_recovers_the_speaker_jitter() -> None:
    v = characterise_state_noise(runs=20, points=100, seed=1)  # σ_v = 0.1 Hz simulated
    assert v.samples.shape == (2000,)
    # 20 runs of a process with ~25 correlation times each: σ within 15 %, mean near 0
    assert v.sigma == pytest.approx(0.1, rel=0.15)
    assert abs(v.mode) < 0.03
    assert v.lower == pytest.approx(v.mode - 3 * v.sigma)
    assert v.upper == pytest.approx(v.mode + 3 * v.sigma)
    assert v.possibility(v.mode) == pytest.approx(1.0) and v.possibility(v.upper + 1e-9) == 0.0


def test_evidence_has_the_shape_of_table_1() -> None:
    v = characterise_state_noise(runs=5, seed=0)
    ev = v.evidence(p=3, epsilon=0.05, theta=(-10.0, 10.0))
    assert np.allclose(np.sort(ev.mass), [0.05, 0.95 / 3, 0.95 / 3, 0.95 / 3])
    widths = np.sort(ev.hi_1d - ev.lo_1d)
    # nested cuts at α = 2/3, 1/3, 0 of a ±3σ triangle: widths 2σ, 4σ, 6σ, then Θ
    assert np.allclose(widths[:3], [2 * v.sigma, 4 * v.sigma, 6 * v.sigma])
    assert widths[3] == pytest.approx(20.0)


def test_paper_table_2_from_its_own_figures() -> None:
    # σ_w = 1.23, mode −6.9: samples with exactly that mean and σ reproduce Table 2's cuts
    x = np.array([-1.0, 1.0])
    samples = -6.9 + 1.23 * x / x.std(ddof=1)
    w = NoiseCharacterisation.from_samples("w", samples)
    ev = w.evidence()
    assert np.allclose(np.sort(ev.lo_1d)[1:], [-10.59, -9.36, -8.13], atol=0.01)


def test_observation_noise_sign_and_offsets() -> None:
    levels = [1.3, 5.6, 9.6]
    cond = RecordingConditions(speaker_jitter_hz=0.1, latency_s=0.01)
    paper_like = characterise_observation_noise(levels, 25.0, cond, seed=3)
    d = paper_like.details
    # w = true − detected (paper eq. 40): the uncorrected reading is high, so w < 0, by about
    # κ L/c + κ τ (1.0 to 7.8 Hz plus 2.8 Hz) give or take the multi-echo shift (< 3 Hz)
    assert np.allclose(paper_like.samples, d["true_hz"] - d["detected_hz"])
    k = PAPER_SWEEP.rate
    for level in levels:
        c = TubeSetup(level, 25.0).speed_of_sound
        w = paper_like.samples[d["level_m"] == level]
        assert w.size > 5
        expected = -(k * level / c + k * cond.latency_s)
        assert abs(w.mean() - expected) < 3.0
    assert paper_like.mode < -3.0
    corrected = characterise_observation_noise(
        levels, 25.0, cond, seed=3, correct_sweep_rate=True, correct_latency=True
    )
    assert abs(corrected.mode) < 3.0 and corrected.sigma < 2.0
    assert corrected.samples.size == paper_like.samples.size
