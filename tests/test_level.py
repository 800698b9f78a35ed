"""Level estimation: eqs. 32–33/43, the state space of eqs. 39–40, the series fit."""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.gauge import (
    direct_levels,
    fit_resonance_series,
    level_from_fundamental,
    level_from_resonance,
    observation,
    observation_inverse,
    orders_eq43,
    resonance_frequencies,
    speed_of_sound,
    state_transition,
    state_transition_derivative,
)

C_9_6 = float(speed_of_sound(23.9))


def test_eq32_and_eq43_on_exact_resonances() -> None:
    n, f = resonance_frequencies(4.6, float(speed_of_sound(26.5)))
    assert np.array_equal(orders_eq43(f), n[:-1])
    assert np.array_equal(orders_eq43(f, extend=True), n)
    assert np.allclose(level_from_resonance(f, n, speed_of_sound(26.5)), 4.6)
    assert np.allclose(direct_levels(f, float(speed_of_sound(26.5))), 4.6)
    assert level_from_fundamental(C_9_6 / 19.2, C_9_6) == pytest.approx(9.6)


def test_eq39_maps_each_resonance_to_the_next() -> None:
    n, f = resonance_frequencies(9.6, C_9_6)
    assert np.allclose(state_transition(f[:-1], n[:-1]), f[1:])
    assert np.allclose(state_transition_derivative(f[:-1], n[:-1]), (n[:-1] + 1) / n[:-1])
    # vectorised over a batch of states (e.g. box vertices) with one order
    x = np.array([[1000.0], [1001.0]])
    assert state_transition(x, 56).shape == (2, 1)
    assert np.all(np.diff(state_transition(np.linspace(990, 1010, 5), 56)) > 0)  # increasing


def test_eq40_is_the_identity() -> None:
    x = np.array([1023.3, 1061.0])
    assert np.array_equal(observation(x), x)
    lo, hi = observation_inverse([1.0, 2.0], [3.0, 4.0])
    assert np.array_equal(lo, [1.0, 2.0]) and np.array_equal(hi, [3.0, 4.0])


@pytest.mark.parametrize("offset", [0.0, None])
def test_series_fit_on_exact_data(offset: float | None) -> None:
    n, f = resonance_frequencies(9.6, C_9_6)
    fit = fit_resonance_series(f, offset_hz=offset)
    assert fit.first_order == 56 and np.array_equal(fit.orders, n)
    assert fit.level(C_9_6) == pytest.approx(9.6, abs=1e-9)
    assert fit.residual_rms_hz < 1e-9


def test_series_fit_with_a_missed_resonance() -> None:
    n, f = resonance_frequencies(2.6, float(speed_of_sound(26.5)))
    keep = np.arange(n.size) != 5
    fit = fit_resonance_series(f[keep], steps=(n - n[0])[keep])
    assert fit.first_order == n[0] and np.array_equal(fit.orders, n[keep])
    assert fit.level(float(speed_of_sound(26.5))) == pytest.approx(2.6, abs=1e-9)


def test_free_offset_fit_ignores_a_common_offset_that_the_fixed_fit_absorbs() -> None:
    n, f = resonance_frequencies(4.6, float(speed_of_sound(26.5)))
    c = float(speed_of_sound(26.5))
    shifted = f + 5.0  # an uncorrected κ L/c + κ τ
    free = fit_resonance_series(shifted, offset_hz=None)
    assert free.first_order == n[0] and free.offset_hz == pytest.approx(5.0)
    assert free.level(c) == pytest.approx(4.6, abs=1e-9)
    fixed = fit_resonance_series(shifted)  # assumes b = 0: biased by about L·5/z̄
    assert abs(fixed.level(c) - 4.6) == pytest.approx(4.6 * 5.0 / f.mean(), rel=0.2)
    assert fit_resonance_series(shifted, offset_hz=5.0).level(c) == pytest.approx(4.6)


def test_series_fit_beats_eq43_on_a_long_noisy_tube() -> None:
    # at 9.6 m, f_F = 18 Hz; readings with σ = 1.4 Hz make consecutive
    # differences carry 2 Hz of noise, so eq. 43 often picks a wrong n_k.
    rng = np.random.default_rng(2017)
    n, f = resonance_frequencies(9.6, C_9_6)
    z = f + rng.normal(0.0, 1.4, size=(50, f.size))
    eq43 = np.array([np.mean(np.abs(direct_levels(zi, C_9_6) - 9.6)) for zi in z])
    fixed = np.array([abs(fit_resonance_series(zi).level(C_9_6) - 9.6) for zi in z])
    free = np.array([abs(fit_resonance_series(zi, offset_hz=None).level(C_9_6) - 9.6) for zi in z])
    wrong_orders = np.mean([np.mean(orders_eq43(zi) != n[:-1]) for zi in z])
    assert wrong_orders > 0.5  # eq. 43 is wrong more often than right here
    assert eq43.mean() > 0.3  # tens of centimetres
    assert fixed.max() < 0.005 and free.max() < 0.015  # millimetres
    assert all(fit_resonance_series(zi).first_order == 56 for zi in z[:10])


def test_bad_series_raise() -> None:
    with pytest.raises(ValueError, match="increase strictly"):
        orders_eq43([1000.0, 990.0, 1020.0])
    with pytest.raises(ValueError, match="at least 2"):
        fit_resonance_series([1000.0])
    with pytest.raises(ValueError, match="steps"):
        fit_resonance_series([1000.0, 1018.0, 1036.0], steps=[0, 0, 1])
