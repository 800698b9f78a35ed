"""Level from resonance frequencies (paper eqs. 32–33, 39–40, 43) and a robust alternative.

The paper's chain: z_k, the observed k-th resonance, has order n_k = [z_k/(z_{k+1} − z_k)]
(eq. 43, [·] = nearest integer) and gives L = n_k c/(2 z_k) (eq. 32). Its state space
(eqs. 36–40), with x_k = f_k:

    x_{k+1} = f(x_k, n_k) + v_k,  f(x, n) = x (n + 1)/n     (39)
    g(x_k) = z_k + w_k,            g(x) = x                  (40)

Eq. 43 is fragile on long tubes: the spacing f_F is small (18 Hz at 9.6 m) and the
difference of two readings doubles their noise, so n_k is often off by several units, each
costing about L/n_k in eq. 32. The series fit below uses every reading at once:
z_k = f_F (n_1 + s_k) + b with the integer n_1 searched and f_F by least squares.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import real_array, whole_number

#: Largest order n_1 of the first resonance that :func:`fit_resonance_series` tries.
MAX_FIRST_ORDER = 100_000


def _as_increasing(z: Any, what: str = "resonance frequencies") -> np.ndarray:
    z = real_array(z, what, finite=False).reshape(-1)
    if z.size < 2:
        raise InvalidInputError(f"need at least 2 {what}, got {z.size}")
    if not np.all(np.isfinite(z)):
        raise InvalidInputError(f"{what} contain NaN or infinite values")
    if np.any(np.diff(z) <= 0):
        raise InvalidInputError(f"{what} must increase strictly (sort them, drop duplicates)")
    return z


def level_from_resonance(frequency_hz: Any, order: Any, c: Any) -> np.ndarray:
    """L = n c/(2 f): the level from one resonance and its order.

    Parameters
    ----------
    frequency_hz : float or array_like, any shape
        Resonance frequency f, Hz; positive.
    order : int or array_like, broadcastable with ``frequency_hz``
        Its order n; positive.
    c : float or array_like, broadcastable
        Speed of sound, m/s; positive.

    Returns
    -------
    numpy.ndarray
        L, m, with the broadcast shape of the arguments.

    Raises
    ------
    InvalidInputError
        An argument that is not positive and finite, or a level that overflows or underflows
        (frequencies or speeds far outside any tube's: not in Hz and m/s).

    See Also
    --------
    level_from_fundamental : L from the spacing of the resonances.
    orders_eq43 : The orders the paper uses.
    direct_levels : Eq. (32) with the orders of eq. (43), one level per reading.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (32).

    Examples
    --------
    The 10th resonance of a 1.3 m air column at 20 °C (c = 343.42 m/s):

    >>> from dstoolkit.gauge import level_from_resonance
    >>> f10 = 10 * 343.42 / (2 * 1.3)
    >>> round(float(level_from_resonance(f10, 10, 343.42)), 6)
    1.3
    """
    n, speed = _positive(order, "order"), _positive(c, "c")
    f = _positive(frequency_hz, "frequency_hz")
    with np.errstate(over="ignore", under="ignore"):
        return _finite_level(n * (speed / f) * 0.5)  # c/f first: 2 f may overflow


def _positive(value: Any, name: str) -> np.ndarray:
    v = real_array(value, name)
    if np.any(v <= 0):
        raise InvalidInputError(f"{name} must be positive, got {v.min():g}")
    return v


def level_from_fundamental(fundamental_hz: Any, c: Any) -> np.ndarray:
    """L = c/(2 f_F): the level from the spacing of the resonances.

    Parameters
    ----------
    fundamental_hz : float or array_like, any shape
        The fundamental f_F (the spacing of the resonances), Hz; positive.
    c : float or array_like, broadcastable
        Speed of sound, m/s; positive.

    Returns
    -------
    numpy.ndarray
        L, m, with the broadcast shape of the arguments.

    Raises
    ------
    InvalidInputError
        An argument that is not positive and finite, or a level that overflows or underflows.

    See Also
    --------
    fundamental_frequency : The inverse, f_F = c/(2L).
    fit_resonance_series : f_F fitted to a whole series of readings.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (35), solved for L.

    Examples
    --------
    >>> from dstoolkit.gauge import level_from_fundamental
    >>> float(level_from_fundamental(132.0, 343.2))
    1.3
    """
    speed, f = _positive(c, "c"), _positive(fundamental_hz, "fundamental_hz")
    with np.errstate(over="ignore", under="ignore"):
        return _finite_level((speed / f) * 0.5)  # c/f first: 2 f may overflow


def _finite_level(level: np.ndarray) -> np.ndarray:
    """Return the level, or refuse it when it overflowed or underflowed to 0.

    Such inputs lie far outside any tube's: the computed number would not be the level.
    """
    if not np.all(np.isfinite(level)) or np.any(level <= 0):
        raise InvalidInputError(
            "the level overflows or underflows: the frequencies and the "
            "speed of sound are far outside any tube's; give them in Hz "
            "and m/s"
        )
    return level


def orders_eq43(z: Any, extend: bool = False) -> np.ndarray:
    """Compute the paper's orders n_k = [z_k/(z_{k+1} − z_k)], [·] the nearest integer.

    Parameters
    ----------
    z : array_like, shape (K,)
        Resonance frequencies z_1..z_K, Hz, strictly increasing; K ≥ 2.
    extend : bool, optional
        If True, the last reading gets n_{K−1} + 1, so that every z_k has an order.

    Returns
    -------
    numpy.ndarray of int, shape (K−1,) or (K,) with ``extend``
        The orders n_k.

    Raises
    ------
    InvalidInputError
        Fewer than two readings, a reading that is not finite, or readings that do not
        increase strictly.

    See Also
    --------
    fit_resonance_series : A more robust estimate of the orders, from every reading at once.
    direct_levels : Eq. (32) with these orders.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (33) and (43).

    Examples
    --------
    Three successive resonances 132 Hz apart, from the 10th:

    >>> from dstoolkit.gauge import orders_eq43
    >>> orders_eq43([1320.0, 1452.0, 1584.0]).tolist()
    [10, 11]
    >>> orders_eq43([1320.0, 1452.0, 1584.0], extend=True).tolist()
    [10, 11, 12]
    """
    z = _as_increasing(z)
    n = np.rint(z[:-1] / np.diff(z)).astype(int)
    return np.append(n, n[-1] + 1) if extend else n


def direct_levels(z: Any, c: float) -> np.ndarray:
    """Measure the level directly, as the paper: eq. (32) with the orders of eq. (43).

    Parameters
    ----------
    z : array_like, shape (K,)
        Resonance frequencies z_1..z_K, Hz, strictly increasing; K ≥ 2.
    c : float
        Speed of sound, m/s; positive.

    Returns
    -------
    numpy.ndarray, shape (K−1,)
        One level per reading z_1..z_{K−1}, m.

    Raises
    ------
    InvalidInputError
        Fewer than two readings, readings that do not increase strictly, or a speed that is
        not positive.

    See Also
    --------
    orders_eq43, level_from_resonance
    dstoolkit.filters.DependentEvidenceFilter : Filters the readings before eq. (32).

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32)–(33) and (43); Table 3's "direct" column.

    Examples
    --------
    >>> from dstoolkit.gauge import direct_levels
    >>> direct_levels([1320.0, 1452.0, 1584.0], c=343.2).tolist()
    [1.3, 1.3]
    """
    z = _as_increasing(z)
    return level_from_resonance(z[:-1], orders_eq43(z), c)


def state_transition(x: Any, n: Any) -> np.ndarray:
    """Apply the gauge's state transition without noise, f(x, n) = x (n + 1)/n.

    The next resonance from this one: the state equation x_{k+1} = f(x_k, n_k) + v_k.

    Parameters
    ----------
    x : float or array_like, any shape
        The resonance frequency x_k, Hz.
    n : float or array_like, broadcastable with ``x``
        Its order n_k; positive.

    Returns
    -------
    numpy.ndarray
        f(x, n), Hz, with the broadcast shape.

    See Also
    --------
    state_transition_derivative : ∂f/∂x.
    gauge_state_space_model : The model this map belongs to.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (36)–(39).

    Examples
    --------
    >>> from dstoolkit.gauge import state_transition
    >>> float(state_transition(1320.0, 10))
    1452.0
    """
    return next_resonance(np.asarray(x, dtype=float), np.asarray(n, dtype=float))


def state_transition_derivative(x: Any, n: Any) -> np.ndarray:
    """∂f/∂x = (n + 1)/n > 0 for the gauge's state transition, for Kalman filters.

    f is increasing in x, so the paper's Prop. 2 (a monotone map sends a box's corners to the
    image's corners) applies.

    Parameters
    ----------
    x : float or array_like, any shape
        The resonance frequency x_k, Hz (only its shape is used).
    n : float or array_like, broadcastable with ``x``
        Its order n_k; positive.

    Returns
    -------
    numpy.ndarray
        (n + 1)/n, dimensionless, with the broadcast shape of ``x`` and ``n``.

    See Also
    --------
    state_transition : The map itself.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (39) and Prop. 2.

    Examples
    --------
    >>> from dstoolkit.gauge import state_transition_derivative
    >>> float(state_transition_derivative(1320.0, 10))
    1.1
    """
    ratio = resonance_ratio(np.asarray(n, dtype=float))
    return ratio + np.zeros_like(x, dtype=float)  # the shape x and n broadcast to


def next_resonance(x: Any, n: Any) -> Any:
    """Compute x (n + 1)/n, the arithmetic of eq. 39, on floats or float arrays (no checks).

    Parameters
    ----------
    x : float or numpy.ndarray
        The resonance frequency, Hz.
    n : float or numpy.ndarray
        Its order.

    Returns
    -------
    float or numpy.ndarray
        The next resonance, Hz.
    """
    return x * (n + 1.0) / n


def resonance_ratio(n: Any) -> Any:
    """(n + 1)/n, the slope ∂f/∂x of the state transition, on floats or float arrays (no checks).

    Parameters
    ----------
    n : float or numpy.ndarray
        The order.

    Returns
    -------
    float or numpy.ndarray
        The ratio, dimensionless.
    """
    return (n + 1.0) / n


def observation(x: Any) -> np.ndarray:
    """Apply the gauge's observation map g(x) = x: the reading of the state.

    The filter adds the noise w to the reading z, g(x_k) = z_k + w_k.

    Parameters
    ----------
    x : float or array_like, any shape
        The resonance frequency, Hz.

    Returns
    -------
    numpy.ndarray
        ``x`` as a float array, Hz.

    See Also
    --------
    observation_inverse : g⁻¹ of a box.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (40).

    Examples
    --------
    >>> from dstoolkit.gauge import observation
    >>> observation([1320.0, 1452.0]).tolist()
    [1320.0, 1452.0]
    """
    return np.asarray(x, dtype=float)


def observation_inverse(lower: Any, upper: Any) -> tuple[np.ndarray, np.ndarray]:
    """g⁻¹ of a box [lower, upper] of readings: the same box, since g is the identity.

    Parameters
    ----------
    lower, upper : float or array_like, same shape
        Ends of the box of readings, Hz.

    Returns
    -------
    lower : numpy.ndarray
        Lower ends of the states whose reading lies in the box, Hz.
    upper : numpy.ndarray
        Upper ends, Hz.

    See Also
    --------
    observation : g itself.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (40).

    Examples
    --------
    >>> from dstoolkit.gauge import observation_inverse
    >>> [a.tolist() for a in observation_inverse(1310.0, 1330.0)]
    [1310.0, 1330.0]
    """
    return np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)


@dataclass(frozen=True)
class ResonanceSeriesFit:
    """z_k = f_F (n_1 + s_k) + b fitted to a whole series of resonances.

    Made by :func:`fit_resonance_series`.

    Parameters
    ----------
    first_order : int
        n_1, the order of the first reading.
    fundamental_hz : float
        f_F, the spacing of the resonances, Hz.
    offset_hz : float
        b, Hz (given, or fitted when ``offset_free``).
    residual_rms_hz : float
        RMS misfit of the readings, Hz.
    orders : numpy.ndarray of int, shape (K,)
        n_1 + s_k, the order of each reading, for eq. (39).
    offset_free : bool
        Whether b was fitted.

    See Also
    --------
    fit_resonance_series : Makes it.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32) and (35).
    """

    first_order: int
    fundamental_hz: float
    offset_hz: float
    residual_rms_hz: float
    orders: np.ndarray
    offset_free: bool

    def level(self, c: float) -> float:
        """Compute the level of the fitted spacing, L = c/(2 f_F).

        Parameters
        ----------
        c : float
            Speed of sound, m/s; positive.

        Returns
        -------
        float
            L, m.

        See Also
        --------
        level_from_fundamental

        References
        ----------
        Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eq. (35).

        Examples
        --------
        >>> from dstoolkit.gauge import fit_resonance_series
        >>> fit = fit_resonance_series([1320.0, 1452.0, 1584.0, 1716.0])
        >>> fit.level(343.2)
        1.3
        """
        return float(level_from_fundamental(self.fundamental_hz, c))


def fit_resonance_series(
    z: Any,
    steps: Any = None,
    offset_hz: float | None = 0.0,
    max_first_order: int | None = None,
) -> ResonanceSeriesFit:
    """Fit z_k = f_F (n_1 + s_k) + b to a series of resonances, with an integer n_1 ≥ 1.

    For each candidate n_1, f_F = Σ m_k (z_k − b) / Σ m_k² with m_k = n_1 + s_k, and the n_1
    with the least squared misfit wins: a wrong n_1 leaves a misfit growing linearly across the
    band, about f_F (s_k − s̄)/n̄, which all K readings see at once. That makes the orders far
    more robust than eq. (43), which divides by the difference of two noisy readings.

    Parameters
    ----------
    z : array_like, shape (K,)
        Resonance frequencies, Hz, strictly increasing; K ≥ 2.
    steps : array_like of int, shape (K,), optional
        s_k, the relative orders (default 0, 1, 2, …); a jump of 2 marks a missed resonance
        (:attr:`DetectionResult.steps`).
    offset_hz : float or None, optional
        b when it is known, Hz (default 0: offsets already removed by the detector). None
        fits b as well: then n_1 cannot come from the misfit (every n_1 fits the same straight
        line), so f_F is the slope and n_1 = round(intercept/slope), which needs |b| < f_F/2.
    max_first_order : int, optional
        Largest n_1 tried (default 3 z_1/slope + 10).

    Returns
    -------
    ResonanceSeriesFit
        n_1, f_F, b, the RMS misfit and the order of every reading.

    Raises
    ------
    InvalidInputError
        Fewer than two readings, readings that do not increase, steps that are not increasing
        integers (one per reading), or orders beyond ``MAX_FIRST_ORDER`` (the readings are not
        one tube's resonances).
    MemoryBudgetError
        The search over n_1 would exceed the memory budget.

    See Also
    --------
    orders_eq43 : The paper's orders, from pairs of readings.
    level_from_fundamental : The level of the fitted spacing.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), eqs. (32), (35) and (43).

    Examples
    --------
    Four resonances 132 Hz apart, from the 10th, read 0.5 Hz high:

    >>> from dstoolkit.gauge import fit_resonance_series
    >>> fit = fit_resonance_series([1320.5, 1452.5, 1584.5, 1716.5], offset_hz=0.5)
    >>> fit.first_order, fit.fundamental_hz, fit.orders.tolist()
    (10, 132.0, [10, 11, 12, 13])
    """
    z = _as_increasing(z)
    s = np.arange(z.size) if steps is None else real_array(steps, "steps").reshape(-1)
    if s.shape != z.shape or np.any(np.diff(s) <= 0) or np.any(s != np.round(s)):
        raise InvalidInputError("steps must be increasing integers, one per frequency")
    s = s - s[0]
    slope, intercept = np.polyfit(s, z, 1)
    if not slope > 0:
        raise InvalidInputError(f"the resonances do not increase with their order (slope {slope})")
    if offset_hz is None:
        n1 = max(1, int(np.rint(intercept / slope)))
        b = float(intercept - slope * n1)
        resid = z - (slope * (n1 + s) + b)
        return ResonanceSeriesFit(
            n1, float(slope), b, float(np.sqrt(np.mean(resid**2))), (n1 + s).astype(int), True
        )
    top = (
        3 * z[0] / slope + 10
        if max_first_order is None
        else whole_number(max_first_order, "max_first_order", low=1)
    )
    if not top <= MAX_FIRST_ORDER:
        raise InvalidInputError(
            f"the first resonance would be of order up to {top:.3g}, more than "
            f"{MAX_FIRST_ORDER}: these frequencies do not look like one tube's resonances"
        )
    top = int(top)
    # the orders, the residuals and their squares: (top, K) floats each
    check_memory(
        max(top, 1) * z.size * 8.0 * 4,
        f"fitting {z.size} frequencies with up to {top} first orders",
        "give fewer frequencies, or max_first_order",
    )
    firsts = np.arange(1, max(top, 1) + 1)[:, None]  # candidate first orders n_1
    m = firsts + s[None, :]
    y = z - offset_hz
    f_f = (m @ y) / np.sum(m * m, axis=1)
    sse = np.sum((y[None, :] - f_f[:, None] * m) ** 2, axis=1)
    if not np.all(np.isfinite(f_f)):
        raise InvalidInputError(
            "the resonance frequencies are too large to fit (the sums overflow); give them in Hz"
        )
    best = int(np.argmin(sse))
    return ResonanceSeriesFit(
        int(firsts[best, 0]),
        float(f_f[best]),
        float(offset_hz),
        float(np.sqrt(sse[best] / z.size)),
        (firsts[best, 0] + s).astype(int),
        False,
    )
