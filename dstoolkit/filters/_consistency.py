"""Consistency checks of a Gaussian filter and the Rauch–Tung–Striebel smoother.

A filter that reports a covariance P_k claims that its error e_k = x_k − x̂_k is about
that large. Two numbers test the claim (Bar-Shalom, Li and Kirubarajan, ch. 5.4):

- the normalised estimation error squared, NEES ε_k = e_kᵀ P_k⁻¹ e_k (needs the truth:
  a simulation);
- the normalised innovation squared, NIS ν_kᵀ S_k⁻¹ ν_k (needs only the readings).

If the filter's claims are right and the errors Gaussian, ε_k is χ² with n degrees of
freedom (the NIS with m), so the average of N independent runs' values, times N, is χ²
with N·n: :func:`chi2_band` gives the two-sided band that average falls in with the
given probability. Above the band the filter is overconfident (P too small), below it
conservative (P too large).

The smoother (:func:`rts_smoother`) runs backwards over a filter's estimates with the
linear(ised) transition x_{k+1} = F_k x_k + b_k + v_k of eq. 21, turning each filtered
estimate (data up to k) into a smoothed one (data up to T); :func:`smooth_kalman` runs the
Kalman filter on a model and smooths it (the extended RTS smoother when f is nonlinear).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from scipy.stats import chi2

from dstoolkit.errors import EvidenceError
from dstoolkit.utils.checks import real_array, real_number, whole_number

from ._kalman import KalmanFilter, finite_difference_jacobian
from ._model import StateSpaceModel, single_readings, with_input


def _pairs(errors: Any, covariances: Any, what: str, cov_name: str) -> tuple[np.ndarray, ...]:
    """Check errors (..., n) and covariances (..., n, n) of the same leading shape."""
    e = real_array(errors, what, error=EvidenceError)
    p = real_array(covariances, cov_name, error=EvidenceError)
    if e.ndim == 0:
        e = e[None]
    if e.shape[-1] == 1 and p.shape == e.shape[:-1]:  # variances of scalar errors
        p = p[..., None, None]
    if p.ndim < 2 or p.shape[-2:] != (e.shape[-1], e.shape[-1]) or p.shape[:-2] != e.shape[:-1]:
        raise EvidenceError(
            f"{cov_name} must have shape {(*e.shape[:-1], e.shape[-1], e.shape[-1])} for "
            f"{what} of shape {e.shape} (one n × n matrix per vector), got {p.shape}"
        )
    return e, p


def _normalised_squares(e: np.ndarray, p: np.ndarray, cov_name: str) -> np.ndarray:
    """eᵀ P⁻¹ e for each vector, refusing a covariance that is not positive definite."""
    try:
        np.linalg.cholesky(p)
    except np.linalg.LinAlgError:
        raise EvidenceError(
            f"every matrix of {cov_name} must be symmetric positive definite (a variance "
            "of zero leaves the error unnormalised); check the filter's covariances"
        ) from None
    return np.einsum("...i,...i->...", e, np.linalg.solve(p, e[..., None])[..., 0])


def nees(errors: Any, covariances: Any) -> np.ndarray:
    """Return the normalised estimation error squared ε = eᵀ P⁻¹ e of each estimate.

    Parameters
    ----------
    errors : array_like, shape (..., n)
        The errors x − x̂ (truth minus estimate).
    covariances : array_like
        The covariances P the filter reported for those estimates; shape (..., n, n), or
        (...) when n = 1.

    Returns
    -------
    ndarray, shape (...)
        ε for each estimate: χ² with n degrees of freedom when the filter is consistent.

    Raises
    ------
    EvidenceError
        Shapes that do not match, values that are not finite, or a covariance that is not
        positive definite.

    Examples
    --------
    >>> nees([[2.0, 0.0], [0.0, 3.0]], [[[4.0, 0.0], [0.0, 1.0]]] * 2).tolist()
    [1.0, 9.0]
    """
    e, p = _pairs(errors, covariances, "errors", "covariances")
    return _normalised_squares(e, p, "covariances")


def nis(innovations: Any, innovation_covariances: Any) -> np.ndarray:
    """Return the normalised innovation squared νᵀ S⁻¹ ν of each reading.

    Parameters
    ----------
    innovations : array_like, shape (..., m)
        The innovations ν = z − ẑ.
    innovation_covariances : array_like
        Their covariances S; shape (..., m, m), or (...) when m = 1.

    Returns
    -------
    ndarray, shape (...)
        The NIS: χ² with m degrees of freedom when the filter is consistent.

    Raises
    ------
    EvidenceError
        As :func:`nees`.

    Examples
    --------
    >>> nis([[3.0]], [9.0]).tolist()
    [1.0]
    """
    e, p = _pairs(innovations, innovation_covariances, "innovations", "innovation_covariances")
    return _normalised_squares(e, p, "innovation_covariances")


def chi2_band(dof: Any, runs: Any = 1, probability: Any = 0.95) -> tuple[float, float]:
    """Return the band that the average of ``runs`` χ²(dof) values falls in with ``probability``.

    The sum of N independent χ²(n) values is χ²(N·n), so the average lies in
    [χ²_{N n}((1 − p)/2), χ²_{N n}((1 + p)/2)] / N with probability p.

    Parameters
    ----------
    dof : int
        Degrees of freedom of one value (n for the NEES, m for the NIS).
    runs : int, optional
        N, the number of independent values averaged (runs, or steps of one run).
    probability : float, optional
        p, the probability of the two-sided band, in (0, 1) (default 0.95).

    Returns
    -------
    tuple of float
        (low, high).

    Raises
    ------
    EvidenceError
        dof or runs not a whole number >= 1, or p outside (0, 1).

    Examples
    --------
    >>> [round(b, 3) for b in chi2_band(1, 50)]
    [0.647, 1.428]
    """
    n = whole_number(dof, "dof", low=1, error=EvidenceError)
    count = whole_number(runs, "runs", low=1, error=EvidenceError)
    p = real_number(
        probability,
        "probability",
        low=0.0,
        high=1.0,
        low_open=True,
        high_open=True,
        error=EvidenceError,
    )
    total = n * count
    tail = 0.5 * (1.0 - p)
    return float(chi2.ppf(tail, total) / count), float(chi2.isf(tail, total) / count)


class SmootherResult(NamedTuple):
    """The smoothed estimates of a fixed-interval smoother.

    Parameters
    ----------
    estimates : ndarray, shape (T, n)
        x̂_{k|T}, the estimate of x_k from all T readings.
    covariances : ndarray, shape (T, n, n)
        P_{k|T}.
    gains : ndarray, shape (T, n, n)
        The smoother gains J_k (zero at the last step, where nothing follows).

    Examples
    --------
    >>> out = rts_smoother([[0.0], [1.0]], [[[1.0]], [[0.5]]], [[1.0]], [[1.0]])
    >>> out.gains[:, 0, 0].tolist()
    [0.5, 0.0]
    """

    estimates: np.ndarray
    covariances: np.ndarray
    gains: np.ndarray


def rts_smoother(
    estimates: Any,
    covariances: Any,
    transitions: Any,
    process_noise: Any,
    offsets: Any = None,
) -> SmootherResult:
    """Smooth filtered estimates backwards: the Rauch–Tung–Striebel recursion.

    With x⁻_{k+1} = F_k x̂_k + b_k and P⁻_{k+1} = F_k P_k F_kᵀ + Q_k, from k = T − 1 down:

        J_k = P_k F_kᵀ (P⁻_{k+1})⁻¹,
        x̂_{k|T} = x̂_k + J_k (x̂_{k+1|T} − x⁻_{k+1}),
        P_{k|T} = P_k + J_k (P_{k+1|T} − P⁻_{k+1}) J_kᵀ.

    Parameters
    ----------
    estimates : array_like, shape (T, n)
        The filtered estimates x̂_k (data up to step k).
    covariances : array_like, shape (T, n, n)
        Their covariances P_k.
    transitions : array_like, shape (T − 1, n, n) or (n, n)
        F_k of the transition k → k + 1 (one matrix for all of them, or one each).
    process_noise : array_like, shape (T − 1, n, n) or (n, n)
        Q_k.
    offsets : array_like, shape (T − 1, n) or (n,), optional
        b_k (default 0): the part of the prediction that does not depend on x.

    Returns
    -------
    SmootherResult
        x̂_{k|T}, P_{k|T} and the gains.

    Raises
    ------
    EvidenceError
        Shapes that do not match, values that are not finite, or a predicted covariance
        that cannot be inverted.

    Examples
    --------
    A random walk read twice: the first estimate learns from the second reading.

    >>> out = rts_smoother([[0.0], [1.0]], [[[1.0]], [[0.5]]], [[1.0]], [[1.0]])
    >>> out.estimates[:, 0].tolist(), out.covariances[:, 0, 0].tolist()
    ([0.5, 1.0], [0.625, 0.5])
    """
    x = real_array(estimates, "estimates", ndim=(2,), error=EvidenceError)
    steps, n = x.shape
    p = real_array(covariances, "covariances", ndim=(3,), error=EvidenceError)
    if p.shape != (steps, n, n):
        raise EvidenceError(
            f"covariances must have shape {(steps, n, n)} for estimates of shape {x.shape}, "
            f"got {p.shape}"
        )
    f_mats = _per_transition(transitions, "transitions", steps, (n, n))
    q_mats = _per_transition(process_noise, "process_noise", steps, (n, n))
    b = (
        np.zeros((steps - 1, n))
        if offsets is None
        else _per_transition(offsets, "offsets", steps, (n,))
    )
    xs, ps = x.copy(), p.copy()
    gains = np.zeros((steps, n, n))
    for k in range(steps - 2, -1, -1):
        f_k = f_mats[k]
        x_pred = f_k @ x[k] + b[k]
        p_pred = f_k @ p[k] @ f_k.T + q_mats[k]
        try:
            gain = np.linalg.solve(p_pred.T, (p[k] @ f_k.T).T).T
        except np.linalg.LinAlgError:
            raise EvidenceError(
                f"the predicted covariance of step {k + 1} (counting from 0) is singular: "
                "the smoother cannot weigh the later estimate; give the process noise a "
                "variance"
            ) from None
        xs[k] = x[k] + gain @ (xs[k + 1] - x_pred)
        ps[k] = p[k] + gain @ (ps[k + 1] - p_pred) @ gain.T
        gains[k] = gain
    return SmootherResult(xs, ps, gains)


def _per_transition(value: Any, name: str, steps: int, shape: tuple[int, ...]) -> np.ndarray:
    """Return ``value`` as one array of ``shape`` per transition, (T − 1, *shape)."""
    arr = real_array(value, name, error=EvidenceError)
    if arr.shape == shape:
        return np.broadcast_to(arr, (steps - 1, *shape))
    if arr.shape != (steps - 1, *shape):
        raise EvidenceError(
            f"{name} must have shape {shape} or {(steps - 1, *shape)} (one per transition "
            f"of {steps} steps), got {arr.shape}"
        )
    return arr


def smooth_kalman(
    model: StateSpaceModel, z: Any, inputs: Any = None, flt: KalmanFilter | None = None
) -> tuple[Any, SmootherResult]:
    """Run the Kalman filter on one sequence and smooth it with :func:`rts_smoother`.

    f is linearised at each filtered estimate, F_k = ∂f/∂x (the model's Jacobian or a
    central difference), with b_k = f(x̂_k, u_k) + E[v] − F_k x̂_k and Q = diag Var[v]
    (eq. 21): exact for a linear f (the gauge's eq. 39), the extended RTS smoother
    otherwise.

    Parameters
    ----------
    model : StateSpaceModel
        The model of eq. 21.
    z : array_like
        The readings; shape (T, m), or (T,) when m = 1.
    inputs : array_like, shape (T − 1, q), optional
        The inputs of f.
    flt : KalmanFilter, optional
        The filter to smooth (default ``KalmanFilter()``).

    Returns
    -------
    filtered : FilterResult
        The filter's run (with its step records, ``steps``).
    smoothed : SmootherResult
        The smoothed estimates and covariances.

    Examples
    --------
    >>> from dstoolkit.filters import random_walk
    >>> filtered, smoothed = smooth_kalman(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
    >>> smoothed.estimates[:, 0].round(3).tolist()
    [1.058, 1.059, 1.055, 1.057]
    """
    flt = KalmanFilter() if flt is None else flt
    if not isinstance(flt, KalmanFilter):
        raise EvidenceError(
            f"flt must be a KalmanFilter, got {type(flt).__name__}; the smoother needs its "
            "covariances"
        )
    filtered = flt.run(model, z, inputs, record=True)
    _, uu = single_readings(model, z, inputs)
    x = filtered.estimates
    cov = np.stack([step.covariance for step in filtered.steps or ()])
    steps = x.shape[0]
    f_mats, offsets = [], []
    for k in range(steps - 1):
        u = None if uu is None else uu[:, k]
        f_u = with_input(model.f, u)
        at = x[k][None]
        jac = (
            np.asarray(model.jacobian_f(at, u), dtype=float).reshape(
                model.state_dim, model.state_dim
            )
            if model.jacobian_f is not None
            else finite_difference_jacobian(f_u, at)[0]
        )
        f_mats.append(jac)
        offsets.append(f_u(at)[0] + model.state_noise.mean - jac @ x[k])
    if steps == 1:
        return filtered, SmootherResult(x.copy(), cov.copy(), np.zeros_like(cov))
    smoothed = rts_smoother(
        x, cov, np.array(f_mats), np.diag(model.state_noise.variance), np.array(offsets)
    )
    return filtered, smoothed
