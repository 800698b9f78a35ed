"""A second, nonlinear example with a two-dimensional state: predator and prey.

The toolkit's filters take any :class:`~dstoolkit.filters.StateSpaceModel` (eq. 21); the gauge
of §4 is scalar and linear. This module gives a system that is neither, so that every
filter can be shown, tested and compared away from the gauge.

Why a Lotka–Volterra system in log-populations
----------------------------------------------
The state is x = (u, v) = (log P, log Q), the logarithms of a prey population P and a
predator population Q (in thousands of animals, say). One explicit Euler step of length h of
the Lotka–Volterra equations dP/dt = αP − βPQ, dQ/dt = δPQ − γQ, written for the logs, is

    u_{k+1} = u_k + h (α − β e^{v_k}) + v¹_k,
    v_{k+1} = v_k + h (δ e^{u_k} − γ) + v²_k,

and a census counts each population with a bounded additive error:

    g(x) = (e^u, e^v) = z + w        (the paper's sign convention, eq. 21).

The choice is deliberate:

* **Nonlinear in both equations.** f couples the components through exponentials and g is
  exponential, so the extended Kalman filter linearises and the evidential filters really
  need the extension principle. The populations sweep through a wide range (about 0.2 to 4)
  along the cycle, so the census is informative about log P when P is large and weak when P
  is small, which the filters handle very differently.
* **Exact box images everywhere.** Each component of f and of g is monotone in each argument
  on the whole plane (∂u'/∂u = 1, ∂u'/∂v < 0, ∂v'/∂u > 0, ∂v'/∂v = 1; g is increasing), so
  the vertex method (Prop. 1) is exact on every box, even on the wide frames Θ that the
  discount ε creates; the bounded-error filter's enclosures are guaranteed.
  The signs of ∂/∂v differ between the two outputs, so ``f_monotone`` (one sign per
  argument) is left unset and the vertex method (4 vertices) is used.
* **g is invertible on boxes**: g⁻¹ = log, component by component (Step 5 of the paper and
  the contraction step of Nassreddine's filter are exact). Readings below zero carry no
  information about a log-population's lower end: their preimage is unbounded below and is
  cut by the prior box.
* **Bounded noises that mean something.** Additive noise on log-populations is a bounded
  multiplicative fluctuation of the growth rates (environmental stochasticity); a census has
  a bounded counting error, skewed here towards over-counting (mode < 0 means z > g(x)),
  like the paper's observation noise with its mode at −6.9 Hz.

Defaults: α = β = γ = δ = 1 (equilibrium P = Q = 1, period ≈ 2π, about 63 steps of
h = 0.1), start (P, Q) = (2, 1), state noise ±0.03 (mode 0) on each log-population, census
error in [−0.08, 0.04] with mode −0.02 on each count.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dstoolkit.errors import InvalidInputError

from ._model import BoundedNoise, StateSpaceModel

#: Default start of the truth: log of (P, Q) = (2, 1).
LOTKA_VOLTERRA_X0: np.ndarray = np.log(np.array([2.0, 1.0]))
LOTKA_VOLTERRA_X0.flags.writeable = False


def lotka_volterra(
    h: float = 0.1,
    alpha: float = 1.0,
    beta: float = 1.0,
    gamma: float = 1.0,
    delta: float = 1.0,
    state_noise: BoundedNoise | None = None,
    obs_noise: BoundedNoise | None = None,
) -> StateSpaceModel:
    """Predator–prey model in log-populations with a census of both populations.

    Parameters
    ----------
    h
        Euler time step.
    alpha, beta, gamma, delta
        Prey growth, predation, predator death and predator growth rates (all > 0).
    state_noise
        Bounded noise added to (log P, log Q) each step; default ±0.03, mode 0.
    obs_noise
        Bounded census error w with g(x) = z + w; default [−0.08, 0.04], mode −0.02.

    Returns
    -------
    StateSpaceModel
        With f, g, the exact box inverse ``g_inverse`` and both Jacobians (vectorised).

    Examples
    --------
    >>> model = lotka_volterra()
    >>> model.state_dim, model.obs_dim
    (2, 2)
    """
    rates = np.array([h, alpha, beta, gamma, delta], dtype=float)
    if not np.all(np.isfinite(rates)) or np.any(rates <= 0):
        raise InvalidInputError(
            f"h, alpha, beta, gamma, delta must be positive numbers, got {rates.tolist()}"
        )
    if state_noise is None:
        state_noise = BoundedNoise.symmetric([0.03, 0.03])
    if obs_noise is None:
        obs_noise = BoundedNoise([-0.08, -0.08], [-0.02, -0.02], [0.04, 0.04])
    for name, noise in (("state_noise", state_noise), ("obs_noise", obs_noise)):
        if noise.dim != 2:
            raise InvalidInputError(f"{name} must be two-dimensional, got dimension {noise.dim}")

    def f(x: np.ndarray, u: Any = None) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        lp, lq = x[..., 0], x[..., 1]
        return np.stack(
            [lp + h * (alpha - beta * np.exp(lq)), lq + h * (delta * np.exp(lp) - gamma)],
            axis=-1,
        )

    def g(x: np.ndarray) -> np.ndarray:
        return np.exp(np.asarray(x, dtype=float))

    def g_inverse(
        lo: np.ndarray, hi: np.ndarray, x_lo: np.ndarray, x_hi: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        # log of a non-positive reading is −inf: such a bound says nothing (lower end) or
        # rules everything out (upper end, giving an empty box lo > hi).
        with np.errstate(divide="ignore"):
            pre_lo = np.log(np.maximum(np.asarray(lo, dtype=float), 0.0))
            pre_hi = np.log(np.maximum(np.asarray(hi, dtype=float), 0.0))
        return np.maximum(pre_lo, x_lo), np.minimum(pre_hi, x_hi)

    def jacobian_f(x: np.ndarray, u: Any = None) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        one = np.ones(x.shape[:-1])
        row0 = np.stack([one, -h * beta * np.exp(x[..., 1])], axis=-1)
        row1 = np.stack([h * delta * np.exp(x[..., 0]), one], axis=-1)
        return np.stack([row0, row1], axis=-2)

    def jacobian_g(x: np.ndarray) -> np.ndarray:
        e = np.exp(np.asarray(x, dtype=float))
        zero = np.zeros(e.shape[:-1])
        return np.stack(
            [np.stack([e[..., 0], zero], axis=-1), np.stack([zero, e[..., 1]], axis=-1)],
            axis=-2,
        )

    return StateSpaceModel(
        f=f,
        g=g,
        state_noise=state_noise,
        obs_noise=obs_noise,
        g_inverse=g_inverse,
        f_monotone=None,
        g_monotone=(1, 1),
        jacobian_f=jacobian_f,
        jacobian_g=jacobian_g,
        name="lotka-volterra",
        description=(
            "Predator-prey populations in log coordinates (explicit Euler step "
            f"h = {h:g}); a census of both populations with bounded error."
        ),
    )


def simulate_lotka_volterra(
    steps: int = 100,
    runs: int | None = None,
    seed: int = 0,
    model: StateSpaceModel | None = None,
    x0: Any = None,
) -> tuple[StateSpaceModel, np.ndarray, np.ndarray]:
    """Draw a truth and its census readings.

    Parameters
    ----------
    steps
        Number of time steps (readings) per sequence.
    runs
        ``None`` for one sequence; an integer for that many independent sequences.
    seed
        Seed of the random generator (the same seed gives the same data).
    model
        The model to simulate; default :func:`lotka_volterra` with its defaults.
    x0
        Start of the truth (log-populations); default :data:`LOTKA_VOLTERRA_X0`.

    Returns
    -------
    model, x, z
        The model, the true states (steps, 2) and readings (steps, 2), or with a leading
        ``runs`` axis. z_k = g(x_k) − w_k.

    Examples
    --------
    >>> model, x, z = simulate_lotka_volterra(steps=5, seed=0)
    >>> x.shape, z.shape
    ((5, 2), (5, 2))
    """
    model = lotka_volterra() if model is None else model
    start = LOTKA_VOLTERRA_X0 if x0 is None else np.asarray(x0, dtype=float)
    x, z = model.simulate(start, steps, np.random.default_rng(seed), runs=runs)
    return model, x, z


def random_walk(v_half: float, w_half: float) -> StateSpaceModel:
    """x_{k+1} = x_k + v_k read directly, g(x) = x = z + w (eq. 21).

    The demo system of the chapter on bounded noise.

    Parameters
    ----------
    v_half, w_half : float
        Half-widths of the symmetric triangular noises, |v| <= v_half and
        |w| <= w_half (the state's unit).

    Returns
    -------
    StateSpaceModel
        The model, n = m = 1, no input.

    Examples
    --------
    >>> random_walk(0.1, 0.5).name
    'random walk, |v| <= 0.1, |w| <= 0.5'
    """
    return StateSpaceModel(
        f=lambda x, u: x,
        g=lambda x: x,
        g_inverse=lambda lo, hi, x_lo, x_hi: (np.maximum(lo, x_lo), np.minimum(hi, x_hi)),
        state_noise=BoundedNoise.symmetric(v_half),
        obs_noise=BoundedNoise.symmetric(w_half),
        name=f"random walk, |v| <= {v_half:g}, |w| <= {w_half:g}",
    )
