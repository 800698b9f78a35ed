"""The unscented Kalman filter fed with the means and variances of the bounded noises.

The Kalman filter (:class:`~dstoolkit.filters.KalmanFilter`) linearises f and g at the
estimate; the unscented filter instead sends 2n + 1 sigma points through them and reads
the mean and covariance off the images (Julier and Uhlmann; the scaled points of Wan and
van der Merwe). Like the Kalman filter, it gets the means and variances of the triangular
noises of eq. 21 (Q = diag Var[v], R = diag Var[w]), not their bounds.

One step, from (x̂, P) (the paper's sign convention g(x) = z + w, so z = g(x) − w):

    points      χ_0 = x̂,  χ_i = x̂ ± (√((n + λ) P))_i,        λ = α²(n + κ) − n
    prediction  x⁻ = Σ W_i^m f(χ_i, u) + E[v],   P⁻ = Σ W_i^c (f(χ_i) − x⁻)(…)ᵀ + Q
    points      χ⁻_i drawn again from (x⁻, P⁻)
    reading     ẑ = Σ W_i^m g(χ⁻_i) − E[w],     S = Σ W_i^c (g(χ⁻_i) − ẑ)(…)ᵀ + R
    update      C = Σ W_i^c (χ⁻_i − x⁻)(g(χ⁻_i) − ẑ)ᵀ,  K = C S⁻¹,
                x̂ = x⁻ + K (z − ẑ),  P = P⁻ − K S Kᵀ

with W_0^m = λ/(n + λ), W_0^c = W_0^m + 1 − α² + β and W_i^m = W_i^c = 1/(2(n + λ)).
For linear f and g the sigma points carry the mean and covariance exactly and the step
is the Kalman filter's. The start and the band are the Kalman filter's: x̂_1 =
g⁻¹(z_1 + E[w]), P_1 the covariance of the uniform distribution on the reading's box of
states, and ``lower``/``upper`` x̂ ± 3σ.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from dstoolkit.errors import EvidenceError, InconsistentDataError
from dstoolkit.utils.checks import real_number

from ._base import Block, Filter, FilterState, KernelChoice
from ._kalman import KalmanFilter, _inverse
from ._model import StateSpaceModel, at_step, own_state, step_input, with_input


def sigma_weights(
    n: int, alpha: float, beta: float, kappa: float
) -> tuple[float, np.ndarray, np.ndarray]:
    """Return the scale n + λ and the weights W^m, W^c of the 2n + 1 scaled sigma points.

    Parameters
    ----------
    n : int
        The state's dimension.
    alpha, beta, kappa : float
        The spread α, the prior-knowledge term β (2 is optimal for a Gaussian) and the
        secondary scale κ; λ = α²(n + κ) − n.

    Returns
    -------
    scale : float
        n + λ.
    mean_weights, cov_weights : ndarray, shape (2n + 1,)
        W^m and W^c.

    Examples
    --------
    >>> scale, wm, wc = sigma_weights(1, 1.0, 2.0, 2.0)
    >>> scale, wm.tolist(), wc.tolist()
    (3.0, [0.6666666666666666, 0.16666666666666666, 0.16666666666666666], \
[2.6666666666666665, 0.16666666666666666, 0.16666666666666666])
    """
    lam = alpha * alpha * (n + kappa) - n
    scale = n + lam
    wm = np.full(2 * n + 1, 0.5 / scale)
    wc = wm.copy()
    wm[0] = lam / scale
    wc[0] = lam / scale + 1.0 - alpha * alpha + beta
    return float(scale), wm, wc


def sigma_points(mean: np.ndarray, cov: np.ndarray, scale: float) -> np.ndarray:
    """Return the 2n + 1 sigma points of (mean, cov): x, x + L_i, x − L_i.

    L is the lower Cholesky factor of ``scale`` · cov (any square root gives the same
    mean and covariance through a linear map). A covariance that is not positive
    definite (a noise-free model) falls back on the symmetric square root of its
    eigen-decomposition, its negative rounding errors set to 0.

    Parameters
    ----------
    mean : ndarray, shape (..., n)
        The centre (one per run of a batch).
    cov : ndarray, shape (..., n, n)
        The covariance.
    scale : float
        n + λ.

    Returns
    -------
    ndarray, shape (..., 2n + 1, n)
        The points, the centre first.

    Examples
    --------
    >>> sigma_points(np.array([1.0]), np.array([[4.0]]), 1.0)[:, 0].tolist()
    [1.0, 3.0, -1.0]
    """
    scaled = scale * cov
    try:
        root = np.linalg.cholesky(scaled)
    except np.linalg.LinAlgError:
        values, vectors = np.linalg.eigh(0.5 * (scaled + np.swapaxes(scaled, -1, -2)))
        root = vectors * np.sqrt(np.clip(values, 0.0, None))[..., None, :]
    spread = np.swapaxes(root, -1, -2)
    centre = mean[..., None, :]
    return np.concatenate([centre, centre + spread, centre - spread], axis=-2)


def _advance(
    model: StateSpaceModel,
    weights: tuple[float, np.ndarray, np.ndarray],
    x: np.ndarray,
    cov: np.ndarray,
    z: np.ndarray,
    u: np.ndarray | None,
    k: int,
) -> tuple[np.ndarray, ...]:
    """Advance step k − 1 → k (counting from 0) of the module docstring's recursion for R runs.

    x (R, n), P (R, n, n), z (R, m), u (R, q) or None. Returns x⁻, P⁻, the innovation, S,
    the gain K, x̂, P and the NIS (R,).
    """
    scale, wm, wc = weights
    q_cov = np.diag(model.state_noise.variance)
    r_cov = np.diag(model.obs_noise.variance)
    # prediction: the images of the sigma points of (x̂, P) under f
    chi = sigma_points(x, cov, scale)
    fx = np.asarray(with_input(model.f, u)(chi), dtype=float)
    f_mean = wm @ fx
    x_pred = f_mean + model.state_noise.mean
    dx = fx - f_mean[:, None]
    cov_pred = np.swapaxes(wc[:, None] * dx, -1, -2) @ dx + q_cov
    # reading: the images under g of sigma points drawn again from (x⁻, P⁻)
    chi_pred = sigma_points(x_pred, cov_pred, scale)
    gx = np.asarray(model.g(chi_pred), dtype=float)
    z_mean = wm @ gx
    dz = gx - z_mean[:, None]
    weighted = np.swapaxes(wc[:, None] * dz, -1, -2)
    s_cov = weighted @ dz + r_cov
    cross = np.swapaxes(wc[:, None] * (chi_pred - x_pred[:, None]), -1, -2) @ dz
    innovation = z - (z_mean - model.obs_noise.mean)
    singular = ~np.any(s_cov != 0.0, axis=(-2, -1))
    bad = singular & np.any(innovation != 0.0, axis=-1)
    if bad.any():
        run = int(np.flatnonzero(bad)[0])
        raise InconsistentDataError(
            f"the unscented filter's reading at step {k} (counting from 0)"
            + (f" of run {run}" if bad.size > 1 else "")
            + " differs from its prediction, but the model leaves no room for a "
            "difference (innovation covariance S = 0: zero-width noises v and w); give the "
            "noises a width, or check the readings"
        )
    s_inv = _inverse(s_cov)
    gain = cross @ s_inv
    x_new = x_pred + (gain @ innovation[..., None])[..., 0]
    cov_new = cov_pred - gain @ s_cov @ np.swapaxes(gain, -1, -2)
    cov_new = 0.5 * (cov_new + np.swapaxes(cov_new, -1, -2))
    nis = np.einsum("ri,rij,rj->r", innovation, s_inv, innovation)
    return x_pred, cov_pred, innovation, s_cov, gain, x_new, cov_new, nis


@dataclass(frozen=True)
class UnscentedState(FilterState):
    """The unscented filter's state: x̂_k, P_k and the band x̂_k ± 3σ.

    Parameters
    ----------
    model : StateSpaceModel
        The model the filter runs on.
    k : int
        The step whose estimate this is (1 for the first reading).
    estimate : ndarray, shape (n,)
        x̂_k.
    lower, upper : ndarray, shape (n,)
        The band x̂_k ± 3σ.
    covariance : ndarray, shape (n, n)
        P_k.
    """

    covariance: np.ndarray


@dataclass(frozen=True)
class UnscentedRecord:
    """One step of the unscented filter (the terms of the module docstring).

    Parameters
    ----------
    step : int
        k, counting the first reading as 1.
    prediction : ndarray or None
        x⁻ (n,); None at the start.
    prediction_covariance : ndarray or None
        P⁻ (n, n); None at the start.
    innovation : ndarray or None
        z − ẑ (m,); None at the start.
    innovation_covariance : ndarray or None
        S (m, m); None at the start.
    gain : ndarray or None
        K (n, m); None at the start.
    estimate : ndarray
        x̂_k (n,).
    covariance : ndarray
        P_k (n, n).
    nis : float
        The normalised innovation squared νᵀ S⁻¹ ν (NaN at the start).
    """

    step: int
    prediction: np.ndarray | None
    prediction_covariance: np.ndarray | None
    innovation: np.ndarray | None
    innovation_covariance: np.ndarray | None
    gain: np.ndarray | None
    estimate: np.ndarray
    covariance: np.ndarray
    nis: float


@dataclass(frozen=True)
class UnscentedKalmanFilter(Filter[UnscentedState, UnscentedRecord]):
    """Unscented Kalman filter on the noises' means and variances.

    Parameters
    ----------
    alpha : float, optional
        Spread of the sigma points around the mean, 0 < α (default 1).
    beta : float, optional
        Weight of the centre in the covariance (default 2, optimal for a Gaussian).
    kappa : float, optional
        Secondary scale; n + κ > 0 (default 0).
    initial_box : tuple of array_like, optional
        A box ``(lo, hi)`` known to hold x_1, as :class:`KalmanFilter`'s.
    kernel : {"numpy", "auto"}
        The unscented recursion has no compiled kernel: both run numpy, and
        ``"numba"`` is refused.

    See Also
    --------
    KalmanFilter : linearises f and g instead of sampling them.

    Examples
    --------
    On a linear model the unscented filter is the Kalman filter:

    >>> import numpy as np
    >>> from dstoolkit.filters import KalmanFilter, UnscentedKalmanFilter, random_walk
    >>> model, z = random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1]
    >>> ukf = UnscentedKalmanFilter().run(model, z).estimates[:, 0]
    >>> ukf.round(3).tolist()
    [1.0, 1.134, 1.037, 1.057]
    >>> bool(np.allclose(ukf, KalmanFilter().run(model, z).estimates[:, 0], atol=1e-12))
    True
    """

    alpha: float = 1.0
    beta: float = 2.0
    kappa: float = 0.0
    initial_box: tuple[Any, Any] | None = None
    kernel: KernelChoice = "numpy"
    name: ClassVar[str] = "unscented"
    DIAGNOSTICS: ClassVar[dict[str, str]] = {
        "nis": "normalised innovation squared, the innovation ν weighted by S⁻¹ on both "
        "sides (about m on average when the noise statistics are right; NaN at the "
        "first step)",
    }

    def __post_init__(self) -> None:
        self._own(
            "alpha", real_number(self.alpha, "alpha", low=0.0, low_open=True, error=EvidenceError)
        )
        self._own("beta", real_number(self.beta, "beta", error=EvidenceError))
        self._own("kappa", real_number(self.kappa, "kappa", error=EvidenceError))
        self._own_box()
        self._compiled(self.kernel, "the unscented Kalman filter")

    def _check_model(self, model: StateSpaceModel) -> None:
        self._check_box_dim(self._box(self.initial_box), model)
        if model.state_dim + self.kappa <= 0.0:
            raise EvidenceError(
                f"kappa = {self.kappa:g} leaves n + κ = {model.state_dim + self.kappa:g} "
                "<= 0: the sigma points' scale must be positive; use kappa > "
                f"{-model.state_dim}"
            )

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        n = model.state_dim
        return 16.0 * n_steps * (n * n + n + 1)

    def initialize(self, model: StateSpaceModel, z1: Any) -> UnscentedState:
        """x̂_1 = g⁻¹(z_1 + E[w]) and P_1 from the reading's box (the Kalman filter's start).

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading z_1.

        Returns
        -------
        UnscentedState
            The state of step 1; ``estimate`` is x̂_1, shape (n,).

        See Also
        --------
        Filter.initialize : the interface every filter shares.
        """
        self._check_model(model)
        z, _ = self._one(model, z1, transition=False)
        model = self._guarded(model)
        x, cov = KalmanFilter(initial_box=self.initial_box)._start(model, z)
        return _state(model, 1, x[0], cov[0])

    def step(
        self, state: UnscentedState, z: Any, u: Any = None
    ) -> tuple[UnscentedState, UnscentedRecord]:
        """Predict through the sigma points of f, update through those of g.

        Parameters
        ----------
        state : UnscentedState
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the transition k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state : UnscentedState
            The state of step k + 1; ``estimate`` is x̂_{k+1}, shape (n,).
        record : UnscentedRecord
            What the step computed.

        Raises
        ------
        InconsistentDataError
            S = 0 (noise-free model) and yet the reading differs from its prediction.

        See Also
        --------
        Filter.step : the interface every filter shares.
        """
        own_state(state, UnscentedState, self._title)
        model = state.model
        zz, uu = self._one(model, z, u)
        at_step(model, state.k)
        weights = sigma_weights(model.state_dim, self.alpha, self.beta, self.kappa)
        x_pred, cov_pred, innovation, s_cov, gain, new_x, new_cov, nis = _advance(
            model, weights, state.estimate[None], state.covariance[None], zz, uu, state.k
        )
        record = UnscentedRecord(
            state.k + 1,
            x_pred[0],
            cov_pred[0],
            innovation[0],
            s_cov[0],
            gain[0],
            new_x[0],
            new_cov[0],
            float(nis[0]),
        )
        return _state(model, state.k + 1, new_x[0], new_cov[0]), record

    def _start_record(self, state: UnscentedState) -> UnscentedRecord:
        return UnscentedRecord(
            1, None, None, None, None, None, state.estimate, state.covariance, float("nan")
        )

    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        """Run the recursion of :meth:`step`, vectorised over the block's runs."""
        count, n_steps, _ = Z.shape
        n = model.state_dim
        weights = sigma_weights(n, self.alpha, self.beta, self.kappa)
        x, cov = KalmanFilter(initial_box=self.initial_box)._start(model, Z[:, 0])
        xs, covs = np.empty((count, n_steps, n)), np.empty((count, n_steps, n, n))
        nis = np.full((count, n_steps), np.nan)
        xs[:, 0], covs[:, 0] = x, cov
        for k in range(1, n_steps):
            at_step(model, k)
            *_, x, cov, nis[:, k] = _advance(model, weights, x, cov, Z[:, k], step_input(U, k), k)
            xs[:, k], covs[:, k] = x, cov
        sigma = np.sqrt(np.clip(np.diagonal(covs, axis1=-2, axis2=-1), 0.0, None))
        return Block(xs, xs - 3 * sigma, xs + 3 * sigma, {"nis": nis})


def _state(model: StateSpaceModel, k: int, x: np.ndarray, cov: np.ndarray) -> UnscentedState:
    sigma = np.sqrt(np.clip(np.diagonal(cov), 0.0, None))
    return UnscentedState(model, k, x, x - 3 * sigma, x + 3 * sigma, cov)
