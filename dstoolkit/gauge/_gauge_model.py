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

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.filters import BoundedNoise, StateSpaceModel
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
#: The dtype of the arrays the filters pass to the maps (a singleton for native float64).
_FLOAT64 = np.dtype(np.float64)
#: Θ of E_v and E_w as printed in Tables 1–2; mode ± 100σ gives [−129.9, 116.1] for w.
PAPER_THETA: tuple[tuple[tuple[float, float]], tuple[tuple[float, float]]] = (
    ((-10.0, 10.0),),
    ((-129.7, 115.7),),
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


def _one_each(x: Any, u: Any) -> tuple[float, float] | None:
    """Return x and the order n as floats when both are one float64 number, else None.

    That is: x an array of size 1 (not 0-d) and u one valid order (positive, finite) with no
    more axes than x, the shapes the filters pass for one run. Eq. 39's arithmetic then runs
    on the two floats: the same IEEE operations in the same order as on the arrays, so the
    same numbers, without three numpy calls on one element; the result is an array of x's
    shape, the shape x and n broadcast to. Anything else gives None: the array path, with
    its checks.
    """
    if not (type(x) is np.ndarray and type(u) is np.ndarray):
        return None
    if x.size != 1 or u.size != 1 or x.ndim == 0 or u.ndim > x.ndim:
        return None
    if x.dtype is not _FLOAT64 or u.dtype is not _FLOAT64:
        return None
    n = u.item()
    return (x.item(), n) if 0.0 < n < math.inf else None


def _f(x: np.ndarray, u: Any = None) -> np.ndarray:
    pair = _one_each(x, u)
    if pair is not None:
        state, order = pair
        return np.array(next_resonance(state, order), ndmin=x.ndim)
    return state_transition(x, _orders(u))


def _jacobian_f(x: np.ndarray, u: Any = None) -> np.ndarray:
    pair = _one_each(x, u)
    if pair is not None:
        return np.array(resonance_ratio(pair[1]), ndmin=x.ndim + 1)
    return state_transition_derivative(x, _orders(u))[..., None]


def _jacobian_g(x: np.ndarray) -> np.ndarray:
    if type(x) is np.ndarray and x.size == 1:  # one state: a one-element array, made at once
        return np.array(1.0, ndmin=x.ndim + 1)
    return np.ones(np.shape(x) + (1,))


def _g_inverse(
    lo: np.ndarray, hi: np.ndarray, x_lo: np.ndarray, x_hi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """States in [x_lo, x_hi] whose reading lies in [lo, hi]: g is the identity."""
    pre_lo, pre_hi = observation_inverse(lo, hi)
    return np.maximum(pre_lo, x_lo), np.minimum(pre_hi, x_hi)


def gauge_state_space_model(
    state_noise: BoundedNoise = GAUGE_STATE_NOISE, obs_noise: BoundedNoise = GAUGE_OBS_NOISE
) -> StateSpaceModel:
    """Build the gauge's state-space model: x_{k+1} = x_k (n_k + 1)/n_k + v_k, g(x) = x.

    The state x_k is the resonance frequency being tracked (Hz) and the input u_k its order
    n_k. f is increasing in x (n_k > 0) and in v, and g is increasing, so the paper's Prop. 2
    applies to both.

    Parameters
    ----------
    state_noise : dstoolkit.filters.BoundedNoise, optional
        The state noise v, Hz, one-dimensional (default :data:`GAUGE_STATE_NOISE`: mode 0,
        bounds ±0.3 Hz, Table 1).
    obs_noise : dstoolkit.filters.BoundedNoise, optional
        The observation noise w, Hz, one-dimensional (default :data:`GAUGE_OBS_NOISE`: mode
        −6.9 Hz, bounds [−10.59, −3.21] Hz, Table 2).

    Returns
    -------
    dstoolkit.filters.StateSpaceModel
        The model; its maps take the orders n_k as inputs, shape (T−1,) or (runs, T−1).

    Raises
    ------
    EvidenceError
        A noise that is not one-dimensional. The maps raise it too when called without the
        orders, or with orders that are not positive.

    See Also
    --------
    simulate_gauge : Readings to run the model on.
    state_transition, observation : The maps of eqs. (39)–(40).
    dstoolkit.filters.DependentEvidenceFilter : The paper's filter, which runs on it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (36)–(43), Tables 1–2.

    Examples
    --------
    >>> from dstoolkit.gauge import gauge_state_space_model, simulate_gauge
    >>> from dstoolkit.filters import DependentEvidenceFilter
    >>> seq = simulate_gauge(9.6, 23.9, seed=0)
    >>> model = gauge_state_space_model()
    >>> result = DependentEvidenceFilter().run(model, seq.readings, seq.inputs)
    >>> result.estimates.shape
    (83, 1)
    """
    for name, noise in (("state_noise", state_noise), ("obs_noise", obs_noise)):
        if noise.dim != 1:
            raise EvidenceError(f"the gauge state is scalar: {name} must be 1-D, got {noise.dim}")
    return StateSpaceModel(
        f=_f,
        g=observation,
        g_inverse=_g_inverse,
        state_noise=state_noise,
        obs_noise=obs_noise,
        f_monotone=(1, 1),
        g_monotone=(1,),
        jacobian_f=_jacobian_f,
        jacobian_g=_jacobian_g,
        name="gauge",
        description="resonance frequency x_k (Hz) of an acoustic level gauge, eqs. 39–40",
    )


def orders_from_readings(z: Any) -> np.ndarray:
    """Compute the paper's orders n_k of every sequence of readings: the filter's inputs.

    Parameters
    ----------
    z : array_like, shape (T,), (T, 1), (runs, T) or (runs, T, 1)
        Readings, Hz, each sequence strictly increasing.

    Returns
    -------
    numpy.ndarray of int, shape (T−1,) or (runs, T−1)
        The orders of eq. (43).

    Raises
    ------
    EvidenceError
        Readings of another shape.
    InvalidInputError
        A sequence that does not increase strictly.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (43).
    """
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
    """A simulated sweep: the true resonances, the noisy readings and the filter's inputs.

    Made by :func:`simulate_gauge`.

    Parameters
    ----------
    level_m : float
        L, m.
    temperature_c : float
        Air temperature, °C.
    speed_of_sound : float
        c, m/s (the paper's law).
    fundamental_hz : float
        f_F = c/(2L), Hz.
    orders : numpy.ndarray of int, shape (T,)
        True orders n_k of the resonances in the band.
    truth : numpy.ndarray, shape (T, 1)
        True resonance frequencies f_k = n_k c/(2L), Hz.
    readings : numpy.ndarray, shape (T, 1) or (runs, T, 1)
        z_k = f_k − w_k, Hz.
    inputs : numpy.ndarray of int, shape (T−1,) or (runs, T−1)
        Orders from the readings by eq. (43), what the paper feeds eq. (39).

    See Also
    --------
    simulate_gauge : Makes it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (31)–(35), (40) and (43).
    """

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
        """The true orders n_1..n_{T−1}, shape (T−1,)."""
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
    """Gauge-like readings: the resonances of a band read with the paper's noise w.

    The resonances f_k = n_k c/(2L), c = 331.3 + 0.606 T, are read as z_k = f_k − w_k with w
    drawn from the triangle of ``obs_noise``. The truth follows eq. (39) exactly (v = 0): the
    resonances are physical. At the paper's 9.6 m, 23.9 °C and [1000, 2500] Hz: f_F =
    18.01 Hz, 83 resonances (n = 56..138).

    Parameters
    ----------
    level_m : float, optional
        L, m (default 9.6, the paper's longest level).
    temperature_c : float, optional
        Air temperature, °C (default 23.9).
    band : tuple of float, optional
        (low, high) in Hz (default :data:`DEFAULT_BAND`).
    runs : int, optional
        Number of independent runs; None (default) gives one run without the leading axis.
    seed : int, optional
        Seed of the noise draws.
    obs_noise : dstoolkit.filters.BoundedNoise, optional
        The noise w, Hz (default :data:`GAUGE_OBS_NOISE`, Table 2's triangle).

    Returns
    -------
    GaugeSequence
        Truth (T, 1), readings (T, 1) or (runs, T, 1) and the orders of eq. (43).

    Raises
    ------
    EvidenceError
        Fewer than two resonances in the band.
    InvalidInputError
        A level, temperature or number of runs that is not valid.
    MemoryBudgetError
        ``runs`` would exceed the memory budget.

    See Also
    --------
    gauge_state_space_model : The model to filter the readings with.
    synthesize_recording : Readings from a simulated recording instead.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (31)–(35), (40), (43) and §4.3.

    Examples
    --------
    >>> from dstoolkit.gauge import simulate_gauge
    >>> seq = simulate_gauge(9.6, 23.9, seed=0)
    >>> round(seq.fundamental_hz, 2), seq.readings.shape, seq.inputs.shape
    (18.01, (83, 1), (82,))
    >>> simulate_gauge(9.6, 23.9, runs=5).readings.shape
    (5, 83, 1)
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
        check_memory(
            runs * orders.size * 8.0 * 6,
            f"simulating {runs} runs of {orders.size} readings",
            "simulate fewer runs",
        )
    rng = np.random.default_rng(seed)
    size = (orders.size,) if runs is None else (runs, orders.size)
    readings = freqs[:, None] - obs_noise.sample(rng, size)
    return GaugeSequence(
        level_m=float(level_m),
        temperature_c=float(temperature_c),
        speed_of_sound=c,
        fundamental_hz=float(fundamental_frequency(level_m, c)),
        orders=orders,
        truth=freqs[:, None],
        readings=readings,
        inputs=orders_from_readings(readings),
    )
