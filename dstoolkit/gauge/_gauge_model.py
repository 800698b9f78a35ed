"""The gauge as a state-space model (paper §4.2, eqs. 36–43) and a gauge-like sequence.

The state is the resonance frequency being tracked, x_k = f_k (Hz); the input is its order
n_k. From f_k = n_k c/(2L) and f_{k+1} = (n_k + 1) c/(2L) (eqs. 36–38):

    x_{k+1} = x_k (n_k + 1)/n_k + v_k     (eq. 39)
    g(x_k) = x_k = z_k + w_k               (eq. 40, the reading; "adding noise to z")

with n_k = [z_k/(z_{k+1} − z_k)] from the readings (eq. 43). Noise figures (paper §4.3):
v has σ = 0.1 Hz, support [−0.3, 0.3], mode 0; w has σ = 1.23 Hz, mode −6.9 Hz, support
[−10.59, −3.21] (a reading is 3.2–10.6 Hz above the resonance). The physics (c, f_n) comes
from :mod:`dstoolkit.gauge`, eqs. 32/39/40/43 from :mod:`dstoolkit.gauge`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.filters import BoundedNoise, ScalarMaps, StateSpaceModel
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import real_array, whole_number

from ._acoustics import DEFAULT_BAND, fundamental_frequency, resonance_frequencies, speed_of_sound
from ._level import (
    next_resonance,
    observation,
    observation_inverse,
    orders_eq43,
    resonance_ratio,
    state_transition,
    state_transition_derivative,
)

#: State noise v (Hz): σ 0.1, bounds ±3σ, mode 0 (§4.3, Fig. 8, Table 1).
GAUGE_STATE_NOISE = BoundedNoise(-0.3, 0.0, 0.3)
#: Observation noise w (Hz): σ 1.23, mode −6.9, bounds mode ± 3σ (§4.3, Fig. 9, Table 2).
GAUGE_OBS_NOISE = BoundedNoise(-10.59, -6.9, -3.21)
#: Θ of E_v and E_w as printed in Tables 1–2; mode ± 100σ gives [−129.9, 116.1] for w.
PAPER_THETA: tuple[tuple[tuple[float, float]], tuple[tuple[float, float]]] = (
    ((-10.0, 10.0),), ((-129.7, 115.7),)
)


def _orders(u: Any) -> np.ndarray:
    # the filters call this at every step with checked float orders: one test, then go
    if isinstance(u, np.ndarray) and u.dtype == np.float64 and u.size:
        if u.size == 1 and 0.0 < u.item() < np.inf:
            return u
        if u.size > 1 and 0.0 < u.min() and u.max() < np.inf:
            return u
    if u is None:
        raise EvidenceError(
            "the gauge model needs the order n_k of each resonance as input (eq. 39): pass "
            "inputs=orders_from_readings(z) (eq. 43) or the true orders"
        )
    orders = real_array(u, "inputs (orders n_k)", error=EvidenceError)
    if np.any(orders <= 0):
        raise EvidenceError(
            f"orders n_k must be positive (eq. 39 divides by n_k), got {orders.min():g}; "
            "give the orders of eq. 43 (orders_from_readings) or the true ones"
        )
    return orders


def _f(x: np.ndarray, u: Any = None) -> np.ndarray:
    return state_transition(x, _orders(u))


def _jacobian_f(x: np.ndarray, u: Any = None) -> np.ndarray:
    return state_transition_derivative(x, _orders(u))[..., None]


def _jacobian_g(x: np.ndarray) -> np.ndarray:
    return np.ones(np.shape(x) + (1,))


#: Eqs. 39–40 on Python floats (u = [n_k], checked at the door): the same arithmetic as the
#: array maps above, for the Kalman filter's single runs.
GAUGE_SCALAR_MAPS = ScalarMaps(
    f=lambda x, u: next_resonance(x, u[0]),
    jacobian_f=lambda x, u: resonance_ratio(u[0]),
    g=lambda x: x,
    jacobian_g=lambda x: 1.0,
)


def _g_inverse(lo: np.ndarray, hi: np.ndarray, x_lo: np.ndarray, x_hi: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """States in [x_lo, x_hi] whose reading lies in [lo, hi]: g is the identity."""
    pre_lo, pre_hi = observation_inverse(lo, hi)
    return np.maximum(pre_lo, x_lo), np.minimum(pre_hi, x_hi)


def gauge_state_space_model(
    state_noise: BoundedNoise = GAUGE_STATE_NOISE, obs_noise: BoundedNoise = GAUGE_OBS_NOISE
) -> StateSpaceModel:
    """Eqs. 39–40: x_{k+1} = x_k (n_k + 1)/n_k + v_k, g(x) = x, input u_k = n_k.

    f is increasing in x (n_k > 0) and in v, g increasing: Prop. 2 applies to both.
    """
    for name, noise in (("state_noise", state_noise), ("obs_noise", obs_noise)):
        if noise.dim != 1:
            raise EvidenceError(f"the gauge state is scalar: {name} must be 1-D, got {noise.dim}")
    return StateSpaceModel(
        f=_f, g=observation, g_inverse=_g_inverse, state_noise=state_noise,
        obs_noise=obs_noise, f_monotone=(1, 1), g_monotone=(1,), jacobian_f=_jacobian_f,
        jacobian_g=_jacobian_g, name="gauge",
        description="resonance frequency x_k (Hz) of an acoustic level gauge, eqs. 39–40",
        scalar_maps=GAUGE_SCALAR_MAPS,
    )


def orders_from_readings(z: Any) -> np.ndarray:
    """Eq. 43 for one sequence (T,) or (T, 1) → (T−1,), or a batch (runs, T[, 1]) →
    (runs, T−1): the filter's inputs."""
    arr = np.asarray(z, dtype=float)
    if arr.ndim and arr.shape[-1] == 1 and arr.ndim >= 2:
        arr = arr[..., 0]
    if arr.ndim == 1:
        return orders_eq43(arr)
    if arr.ndim == 2:
        return np.stack([orders_eq43(row) for row in arr])  # data preparation, not a hot path
    raise EvidenceError(
        f"readings must be (T,), (T, 1), (runs, T) or (runs, T, 1), got {arr.shape}"
    )


@dataclass(frozen=True)
class GaugeSequence:
    """A simulated sweep: true resonances, noisy readings and the filter's inputs."""

    level_m: float
    temperature_c: float
    speed_of_sound: float
    fundamental_hz: float
    orders: np.ndarray
    """True orders n_k of the resonances in the band, (T,)."""
    truth: np.ndarray
    """True resonance frequencies f_k = n_k c/(2L), (T, 1)."""
    readings: np.ndarray
    """z_k = f_k − w_k, (T, 1) or (runs, T, 1)."""
    inputs: np.ndarray
    """Orders from the readings by eq. 43 (what the paper feeds eq. 39), (T−1,) or (runs, T−1)."""

    @property
    def true_inputs(self) -> np.ndarray:
        """The true orders n_1..n_{T−1}, (T−1,)."""
        return self.orders[:-1]


def simulate_gauge(
    level_m: float = 9.6,
    temperature_c: float = 23.9,
    band: tuple[float, float] = DEFAULT_BAND,
    *,
    runs: int | None = None,
    seed: int = 0,
    obs_noise: BoundedNoise = GAUGE_OBS_NOISE,
) -> GaugeSequence:
    """Gauge-like readings: the resonances of the band (eqs. 31–35, c = 331.3 + 0.606 T)
    read with triangular noise w, z_k = f_k − w_k.

    At the paper's 9.6 m, 23.9 °C and [1000, 2500] Hz: f_F = 18.01 Hz, 83 resonances
    (n = 56..138). The truth follows eq. 39 exactly (v = 0): the resonances are physical.
    """
    c = float(speed_of_sound(temperature_c))
    orders, freqs = resonance_frequencies(level_m, c, band)
    if orders.size < 2:
        raise EvidenceError(
            f"only {orders.size} resonance(s) in {band} Hz at L = {level_m} m: widen the band"
        )
    if runs is not None:
        runs = whole_number(runs, "runs", low=1)
        # the readings, the noise draws (three arrays) and the orders, 8 bytes each
        check_memory(runs * orders.size * 8.0 * 6, f"simulating {runs} runs of "
                     f"{orders.size} readings", "simulate fewer runs")
    rng = np.random.default_rng(seed)
    size = (orders.size,) if runs is None else (runs, orders.size)
    readings = freqs[:, None] - obs_noise.sample(rng, size)
    return GaugeSequence(
        level_m=float(level_m), temperature_c=float(temperature_c), speed_of_sound=c,
        fundamental_hz=float(fundamental_frequency(level_m, c)), orders=orders,
        truth=freqs[:, None], readings=readings, inputs=orders_from_readings(readings),
    )
