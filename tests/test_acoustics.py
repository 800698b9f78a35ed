"""Speed of sound, resonances and the sweep (paper §4.1, §4.3)."""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.gauge import (
    PAPER_SWEEP,
    LinearSweep,
    fundamental_frequency,
    plane_wave_cutoff,
    resonance_frequencies,
    round_trip_time,
    speed_of_sound,
    speed_of_sound_cramer,
    speed_of_sound_ideal_gas,
    speed_of_sound_paper,
)


def test_paper_speed_of_sound_at_26_5_c() -> None:
    # The paper prints 347.3 m/s (331.3 + 0.606 × 26.5 = 347.359).
    assert speed_of_sound_paper(26.5) == pytest.approx(347.359, abs=1e-9)
    assert abs(speed_of_sound(26.5) - 347.3) < 0.1


def test_fundamental_at_9_6_m_and_23_9_c_is_18_hz() -> None:
    f_f = fundamental_frequency(9.6, speed_of_sound(23.9))
    assert f_f == pytest.approx(18.0, abs=0.02)
    assert round_trip_time(9.6, speed_of_sound(23.9)) == pytest.approx(1.0 / f_f)


def test_paper_line_is_the_tangent_of_the_ideal_gas_law() -> None:
    t = np.linspace(0.0, 30.0, 31)
    paper, ideal = speed_of_sound_paper(t), speed_of_sound_ideal_gas(t)
    assert ideal[0] == pytest.approx(paper[0])
    slope0 = (speed_of_sound_ideal_gas(1e-4) - speed_of_sound_ideal_gas(-1e-4)) / 2e-4
    assert slope0 == pytest.approx(0.6065, abs=1e-4)
    # concave: the line lies above, by 0.35 m/s at 26.5 °C and less than 0.5 m/s up to 30 °C
    assert np.all(paper[1:] > ideal[1:]) and np.all(paper - ideal < 0.5)
    assert speed_of_sound_paper(26.5) - speed_of_sound_ideal_gas(26.5) == pytest.approx(
        0.36, abs=0.01
    )


def test_cramer_reference_values() -> None:
    # Dry air, 0 °C, 101.325 kPa, 314 ppm CO2: 331.45 m/s (Cramer 1993);
    # 20 °C, 50 % RH, 400 ppm: 343.99 m/s.
    assert speed_of_sound_cramer(0.0, 0.0, 101325.0, 314e-6) == pytest.approx(331.45, abs=0.01)
    assert speed_of_sound_cramer(20.0, 0.5) == pytest.approx(343.99, abs=0.01)
    assert speed_of_sound_cramer(25.0, 0.5) > speed_of_sound_cramer(25.0, 0.0) + 0.8
    assert speed_of_sound(20.0, "cramer", relative_humidity=0.5) == speed_of_sound_cramer(20.0)
    with pytest.raises(ValueError, match="0–30 °C"):
        speed_of_sound_cramer(40.0)
    with pytest.raises(ValueError, match="unknown speed-of-sound model"):
        speed_of_sound(20.0, "magic")  # type: ignore[arg-type]


def test_resonances_in_the_band() -> None:
    c = speed_of_sound(23.9)
    n, f = resonance_frequencies(9.6, c, (1000.0, 2500.0))
    # the paper counts 82 (n = 56..137); n = 138 (2488 Hz) lies in the band too
    assert (n[0], n[-1], n.size) == (56, 138, 83)
    assert np.allclose(np.diff(f), c / (2 * 9.6))
    assert f[0] >= 1000.0 and f[-1] <= 2500.0
    n46, _ = resonance_frequencies(4.6, speed_of_sound(26.5), (1000.0, 2500.0))
    # the paper sees "39 adjacent standing waves" at 4.6 m (§4.3, Fig. 7); the model puts
    # 40 in 1000–2500 Hz (n = 27..66) and 37 in the swept 1000–2400 Hz
    assert n46.size == 40
    assert resonance_frequencies(4.6, speed_of_sound(26.5), PAPER_SWEEP.band)[0].size == 37


def test_band_is_below_the_plane_wave_cutoff_of_the_75_mm_tube() -> None:
    assert 2500.0 < plane_wave_cutoff(0.075, speed_of_sound(20.0)) < 2800.0


def test_bad_inputs_raise() -> None:
    with pytest.raises(ValueError, match="level_m"):
        fundamental_frequency(-1.0, 343.0)
    with pytest.raises(ValueError, match="band"):
        resonance_frequencies(1.0, 343.0, (2500.0, 1000.0))


def test_paper_sweep() -> None:
    s = PAPER_SWEEP
    assert (s.f_start, s.f_stop, s.duration, s.sample_rate) == (1000.0, 2400.0, 5.0, 44100.0)
    assert s.rate == pytest.approx(280.0)
    assert s.n_samples == 220500
    f = np.array([1000.0, 1234.5, 2400.0])
    assert np.allclose(s.frequency_at(s.time_at(f)), f)
    # the phase's derivative is 2π f(t)
    t, h = 2.345, 1e-6
    assert (s.phase(t + h) - s.phase(t - h)) / (2 * h) == pytest.approx(
        2 * np.pi * s.frequency_at(t), rel=1e-7
    )
    w = s.waveform()
    assert w.shape == (220500,) and w[0] == 0.0 and np.max(np.abs(w)) <= 1.0
    assert LinearSweep(1000.0, 2500.0).rate == pytest.approx(300.0)


def test_sweep_rejects_bad_parameters() -> None:
    with pytest.raises(ValueError, match="upward"):
        LinearSweep(2400.0, 1000.0)
    with pytest.raises(ValueError, match="Nyquist"):
        LinearSweep(1000.0, 30000.0)
