"""The (extended) Kalman filter fed with the means and variances of the bounded noises.

The paper's introduction sets its method against the Kalman filter and the EKF, which
assume noises with known statistics. This rival gets exactly the information the
evidential filters get, in the only form it can use: the mean and variance of each
triangular noise (:attr:`BoundedNoise.mean`, :attr:`BoundedNoise.variance`). The bounds
themselves are lost; that is the point of the comparison.

Model (eq. 21, the paper's sign convention g(x) = z + w, so z = g(x) − w):

    prediction   x⁻ = f(x̂, u) + E[v],          P⁻ = F P Fᵀ + Q,   F = ∂f/∂x at x̂
    reading      ẑ = g(x⁻) − E[w],              S = H P⁻ Hᵀ + R,   H = ∂g/∂x at x⁻
    update       K = P⁻ Hᵀ S⁻¹,  x̂ = x⁻ + K (z − ẑ),  P = (I − KH) P⁻ (I − KH)ᵀ + K R Kᵀ

with Q = diag Var[v], R = diag Var[w] (Var[w] = Var[−w]). For linear f and g this is the
Kalman filter; otherwise the extended Kalman filter, with the model's Jacobians or central
finite differences.

Start: x̂_1 = g⁻¹(z_1 + E[w]) and P_1 the covariance of the uniform distribution on the
box of states consistent with z_1, g⁻¹(z_1 + [w_lo, w_hi]) (a conservative prior: the
reading is all the filter knows). ``lower``/``upper`` of the result are x̂ ± 3σ from P: the
Kalman filter has no evidence, and this band is its closest analogue.

For a scalar state and reading (the gauge, eqs. 39–40) every matrix is 1 × 1 and the
recursion runs term by term: on Python floats for one run and on arrays of runs for a
batch, with the same operations in the same order, so both give the same numbers. Each
step calls the model's own array maps once per value and slope (a central difference is
one call on three points), so a model written by a user runs as fast as the package's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from dstoolkit.errors import EvidenceError, InconsistentDataError

from ._base import Block, Filter, FilterState, KernelChoice
from ._model import (
    StateSpaceModel,
    at_step,
    first_reading_box,
    own_state,
    step_input,
    unchecked,
    with_input,
)

#: Relative step of the central finite differences (≈ cube root of machine epsilon).
FD_STEP = 6e-6
#: The dtype of float arrays (a singleton for native float64, so ``is`` can test it).
_FLOAT64 = np.dtype(np.float64)


def finite_difference_jacobian(fn: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """Central-difference Jacobian of a vectorised map: x (..., n) → (..., m, n).

    ``fn`` must accept arrays with one extra axis before the last, (..., n, n), and act
    row by row; the step of component i is ``FD_STEP · max(1, |x_i|)``.

    Parameters
    ----------
    fn : callable
        The map, (..., n) → (..., m), vectorised over leading axes.
    x : ndarray, shape (..., n)
        Where to differentiate.

    Returns
    -------
    ndarray, shape (..., m, n)
        ∂fn/∂x, the Jacobian the extended Kalman filter uses when the model has none.

    Examples
    --------
    >>> import numpy as np
    >>> finite_difference_jacobian(lambda x: x ** 2, np.array([3.0])).round(6)
    array([[6.]])
    """
    n = x.shape[-1]
    step = FD_STEP * np.maximum(1.0, np.abs(x))
    delta = np.eye(n) * step[..., None, :]
    plus, minus = fn(x[..., None, :] + delta), fn(x[..., None, :] - delta)
    return np.swapaxes((plus - minus) / (2.0 * step[..., :, None]), -1, -2)


def _inverse(s_cov: np.ndarray) -> np.ndarray:
    """Invert S for a stack of innovation covariances; the pseudo-inverse where S is singular.

    Noise-free models: zero variances give S = 0 and the gain 0.
    """
    try:
        return np.linalg.inv(s_cov)
    except np.linalg.LinAlgError:
        return np.linalg.pinv(s_cov)


def _reciprocal(s: np.ndarray) -> np.ndarray:
    """1/s of an array, 0 where s = 0 (the pseudo-inverse of a 1 × 1 matrix)."""
    return np.divide(1.0, s, out=np.zeros_like(s), where=s != 0.0)


class _MapsAndSlopes:
    """f and ∂f/∂x, g and ∂g/∂x of a model with one state and one reading (n = m = 1).

    On one run's state as a Python float or a batch's states as an (R,) array:
    ``predict(x, u)`` gives f(x, u) and ∂f/∂x at x, ``observe(x, None)`` gives g(x) and
    ∂g/∂x.

    Each value and its slope come from the model's own array maps: the map and its
    Jacobian when the model has one, otherwise the map once on the three points x,
    x + h and x − h (the central difference of :func:`finite_difference_jacobian`, the
    same arithmetic). The results are checked here as the guard would check them (NaN,
    complex, non-numbers), on the floats, so that one run costs two or four small numpy
    calls a step and nothing else: no float copy of the maps in the model. One run hands
    the maps its state in one (1, 1) or (3, 1) array made once and refilled at each call
    (its values are read before the next call), not a new array a call.
    """

    def __init__(self, model: StateSpaceModel, runs: int) -> None:
        self.runs = runs
        f, self.guard = unchecked(model.f)
        g, _ = unchecked(model.g)
        self.jacobian_f = model.jacobian_f
        self.step = 0  # the step being filtered (counting from 0), for the guard's message
        jacobian_g = model.jacobian_g
        self.predict = self._evaluator(f, model.jacobian_f, "f")
        # g takes no input; it gets f's signature (x, u), u unused, so that one evaluator
        # serves both with a fixed number of arguments (a call with *u costs more)
        self.observe = self._evaluator(
            lambda x, _: g(x), None if jacobian_g is None else lambda x, _: jacobian_g(x), "g"
        )

    def rows(self, inputs: np.ndarray | None, transitions: int) -> list[Any]:
        """Return each transition's inputs in the form :meth:`predict` takes.

        (R, q) rows, or (3R, q) (the rows three times over) when f's slope is a central
        difference; None without inputs.
        """
        if inputs is None:
            return [None] * transitions
        if self.jacobian_f is None:
            inputs = np.concatenate([inputs, inputs, inputs])
        return list(np.swapaxes(inputs, 0, 1))

    def _evaluator(
        self, fn: Callable[..., Any], jacobian: Callable[..., Any] | None, name: str
    ) -> Callable[..., tuple[Any, Any]]:
        """Return ``(x, u) ↦ (fn(x, u), ∂fn/∂x at x)`` for this number of runs."""
        if self.runs != 1:
            if jacobian is None:
                return lambda x, u: self._central_batch(fn, name, x, u)
            return lambda x, u: self._analytic_batch(fn, jacobian, name, x, u)
        if jacobian is None:
            points = np.empty((3, 1))

            def central(x: float, u: Any) -> tuple[float, float]:
                step = FD_STEP * max(1.0, abs(x))
                points[0, 0], points[1, 0], points[2, 0] = x, x + step, x - step
                out = fn(points, u)
                if type(out) is not np.ndarray or out.dtype is not _FLOAT64 or out.shape != (3, 1):
                    out = self._conform(out, name, (3, 1))
                (value,), (plus,), (minus,) = out.tolist()
                if value != value or plus != plus or minus != minus:  # NaN
                    self._refuse(out, name)
                return value, (plus - minus) / (2.0 * step)

            return central
        point = np.empty((1, 1))

        def analytic(x: float, u: Any) -> tuple[float, float]:
            point[0, 0] = x
            out = fn(point, u)
            if type(out) is not np.ndarray or out.dtype is not _FLOAT64 or out.shape != (1, 1):
                out = self._conform(out, name, (1, 1))
            value = out.item()
            if value != value:  # NaN
                self._refuse(out, name)
            slope = jacobian(point, u)
            if type(slope) is not np.ndarray or slope.dtype is not _FLOAT64 or slope.size != 1:
                slope = _slopes(slope, name, 1)
            return value, slope.item()

        return analytic

    def _analytic_batch(
        self, fn: Callable[..., Any], jacobian: Callable[..., Any], name: str, x: Any, u: Any
    ) -> tuple[Any, Any]:
        column = x[:, None]
        slopes = jacobian(column, u)
        if (
            type(slopes) is not np.ndarray
            or slopes.dtype is not _FLOAT64
            or slopes.size != self.runs
        ):
            slopes = _slopes(slopes, name, self.runs)
        return self._values(fn(column, u), name, column.shape), slopes.reshape(self.runs)

    def _central_batch(self, fn: Callable[..., Any], name: str, x: Any, u: Any) -> tuple[Any, Any]:
        step = FD_STEP * np.maximum(1.0, np.abs(x))
        points = np.concatenate([x, x + step, x - step])[:, None]
        out = self._values(fn(points, u), name, points.shape)
        value, plus, minus = out[: self.runs], out[self.runs : -self.runs], out[-self.runs :]
        with np.errstate(invalid="ignore"):  # inf − inf: NaN, refused by the recursion
            return value, (plus - minus) / (2.0 * step)

    def _conform(self, out: Any, name: str, shape: tuple[int, ...]) -> np.ndarray:
        """Check a map's result that is not a float array of the states' shape, and give it that."""
        self._refuse(out, name)
        return np.broadcast_to(np.asarray(out, dtype=float), shape)

    def _values(self, out: Any, name: str, shape: tuple[int, ...]) -> np.ndarray:
        """Check a batch's map results (k, 1) and return them flat, (k,).

        Checked: real numbers, NaN nowhere (±inf allowed).
        """
        if type(out) is not np.ndarray or out.dtype is not _FLOAT64 or out.shape != shape:
            out = self._conform(out, name, shape)
        flat = out.ravel()
        if self.guard is not None and np.isnan(flat).any():
            self._refuse(out, name)
        return flat

    def _refuse(self, out: Any, name: str) -> None:
        """Raise the guard's error if ``out`` holds NaN, complex or non-numbers, naming the step.

        Nothing without a guard (a model that is not guarded).
        """
        if self.guard is not None:
            self.guard.step = self.step
            self.guard.check(out, name)


def _scalar_recursion(
    maps: _MapsAndSlopes,
    x: Any,
    cov: Any,
    readings: Any,
    inputs: Any,
    q: float,
    r: float,
    v_mean: float,
    w_mean: float,
    first: int = 1,
) -> tuple[list[Any], list[Any], list[Any]]:
    """Run the module docstring's recursion for n = m = 1 from the start (x̂_1, P_1).

    Eq. 21: F = ∂f/∂x, H = ∂g/∂x, Q = Var[v], R = Var[w]; on floats or (R,) arrays alike:
    estimates, variances and NIS of steps 2..T, one entry per (reading, input) pair
    (inputs as :meth:`_MapsAndSlopes.rows` gives them). Steps count from 0; the first is
    ``first`` (the maps are told it, to name it if a map returns NaN).
    """
    out_x: list[Any] = []
    out_cov: list[Any] = []
    out_nis: list[Any] = []
    one = maps.runs == 1
    for k, (z, u) in enumerate(zip(readings, inputs, strict=True), start=first):
        maps.step = k
        fx, slope = maps.predict(x, u)
        if not _finite(fx, slope, one):
            _refuse_infinite("f", fx, slope, x, k)
        x_pred = fx + v_mean
        cov_pred = slope * cov * slope + q
        gx, h = maps.observe(x_pred, None)
        if not _finite(gx, h, one):
            _refuse_infinite("g", gx, h, x_pred, k)
        innovation = z - (gx - w_mean)
        ph = cov_pred * h
        s = h * ph + r
        if not one or s == 0.0:
            _refuse_contradiction(np.asarray(s == 0.0), np.asarray(innovation != 0.0), k)
        # 1/S, 0 where S = 0 (the pseudo-inverse of a 1 × 1 matrix)
        s_inv = (1.0 / s if s != 0.0 else 0.0) if one else _reciprocal(s)
        gain = ph * s_inv
        x = x_pred + gain * innovation
        joseph = 1.0 - gain * h
        cov = joseph * cov_pred * joseph + gain * r * gain
        out_x.append(x)
        out_cov.append(cov)
        out_nis.append(innovation * s_inv * innovation)
    return out_x, out_cov, out_nis


@dataclass(frozen=True)
class KalmanState(FilterState):
    """The Kalman filter's state: x̂_k, P_k and the band x̂_k ± 3σ.

    x̂_k is ``estimate``, P_k ``covariance`` ((n, n)) and the band ``lower``, ``upper``.

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
class KalmanRecord:
    """One step of the Kalman filter (the terms of the module docstring's recursion).

    Parameters
    ----------
    step : int
        k, counting the first reading as 1.
    prediction : ndarray or None
        x⁻ (n,) and P⁻ (n, n); None at the start.
    prediction_covariance : ndarray or None
        x⁻ (n,) and P⁻ (n, n); None at the start.
    innovation : ndarray or None
        z − ẑ (m,) and S (m, m); None at the start.
    innovation_covariance : ndarray or None
        z − ẑ (m,) and S (m, m); None at the start.
    gain : ndarray or None
        K (n, m); None at the start.
    estimate : ndarray
        x̂_k (n,) and P_k (n, n).
    covariance : ndarray
        x̂_k (n,) and P_k (n, n).
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
class KalmanFilter(Filter[KalmanState, KalmanRecord]):
    """Kalman / extended Kalman filter on the noises' means and variances.

    Parameters
    ----------
    initial_box : tuple of array_like, optional
        A box ``(lo, hi)`` known to hold x_1;
        intersected with the states consistent with
        the first reading (needed when g is not invertible).
    kernel : {"numpy", "auto"}
        The Kalman recursion has no compiled kernel: both run numpy, and
        ``"numba"`` is refused.

    See Also
    --------
    ParticleFilter : uses the whole triangular densities, not only their moments.

    Examples
    --------
    >>> from dstoolkit.filters import KalmanFilter, random_walk
    >>> result = KalmanFilter().run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
    >>> result.estimates[:, 0].round(3).tolist()
    [1.0, 1.134, 1.037, 1.057]
    """

    initial_box: tuple[Any, Any] | None = None
    kernel: KernelChoice = "numpy"
    name: ClassVar[str] = "kalman"
    DIAGNOSTICS: ClassVar[dict[str, str]] = {
        "nis": "normalised innovation squared, the innovation ν weighted by S⁻¹ on both "
        "sides (about m on average when the noise statistics are right; NaN at the "
        "first step)",
    }

    def __post_init__(self) -> None:
        self._own_box()
        self._compiled(self.kernel, "the Kalman filter")

    def _check_model(self, model: StateSpaceModel) -> None:
        self._check_box_dim(self._box(self.initial_box), model)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        n = model.state_dim
        return 16.0 * n_steps * (n * n + n + 1)

    # -- the public step -----------------------------------------------------------------------
    def initialize(self, model: StateSpaceModel, z1: Any) -> KalmanState:
        """x̂_1 = g⁻¹(z_1 + E[w]) and P_1 from the reading's box.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading z_1.

        Returns
        -------
        KalmanState
            The state of step 1; ``estimate`` is x̂_1, shape (n,).

        See Also
        --------
        Filter.initialize : the interface every filter shares.
        """
        self._check_model(model)
        z, _ = self._one(model, z1, transition=False)
        model = self._guarded(model)
        x, cov = self._start(model, z)
        return _state(model, 1, x[0], cov[0])

    def step(self, state: KalmanState, z: Any, u: Any = None) -> tuple[KalmanState, KalmanRecord]:
        """Predict with f, update with the reading.

        Parameters
        ----------
        state : KalmanState
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the transition
            k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state : KalmanState
            The state of step k + 1; ``estimate`` is x̂_{k+1}, shape (n,).
        record : KalmanRecord
            What the step computed.

        See Also
        --------
        Filter.step : the interface every filter shares.
        """
        own_state(state, KalmanState, self._title)
        model = state.model
        zz, uu = self._one(model, z, u)
        at_step(model, state.k)
        # eq. 21 for one run: prediction, reading, update (the module docstring's recursion)
        x_pred, cov_pred, innovation, s_cov, gain, new_x, new_cov, nis = _advance(
            model, state.estimate[None], state.covariance[None], zz, uu, state.k
        )
        record = KalmanRecord(
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

    def _start_record(self, state: KalmanState) -> KalmanRecord:
        return KalmanRecord(
            1, None, None, None, None, None, state.estimate, state.covariance, float("nan")
        )

    # -- the recursion, vectorised over runs ------------------------------------------------
    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        if _scalar(model):
            x, cov, nis = self._filter_scalar(model, Z, U)
        else:
            x, cov, nis = self._filter(model, Z, U)
        sigma = np.sqrt(np.diagonal(cov, axis1=-2, axis2=-1))
        return Block(x, x - 3 * sigma, x + 3 * sigma, {"nis": nis})

    def _start(self, model: StateSpaceModel, z1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = first_reading_box(model, z1, self.initial_box)
        if (lo > hi).any():
            raise EvidenceError(
                "the first reading is inconsistent with initial_box under the observation "
                "noise bounds; widen initial_box or check the first reading"
            )
        if not (np.isfinite(lo) & np.isfinite(hi)).all():
            raise EvidenceError(
                "the first reading does not bound every state component (g is not "
                "invertible there); give the filter an initial_box"
            )
        mean_z = z1 + model.obs_noise.mean
        p_lo, p_hi = model.inverse()(mean_z, mean_z, lo, hi)
        point = 0.5 * (p_lo + p_hi)
        usable = (np.isfinite(point) & (p_lo <= p_hi)).all(axis=-1, keepdims=True)
        x = np.where(usable, point, 0.5 * (lo + hi))
        cov = np.eye(model.state_dim) * ((hi - lo) ** 2 / 12.0)[:, None, :]
        return x, cov

    def _filter_scalar(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Run the recursion of :meth:`_filter` for a scalar state and reading, term by term.

        Every matrix is 1 × 1: on Python floats for one run, on (R,) arrays for a batch,
        with the same operations in the same order, so a batch equals single runs exactly.
        Each step calls the model's array maps two or four times (:class:`_MapsAndSlopes`).
        """
        runs, n_steps, _ = Z.shape
        x0, cov0 = self._start(model, Z[:, 0])
        xs, covs = np.empty((runs, n_steps, 1)), np.empty((runs, n_steps, 1, 1))
        nis = np.full((runs, n_steps), np.nan)
        xs[:, 0], covs[:, 0] = x0, cov0
        if n_steps == 1:
            return xs, covs, nis
        maps = _MapsAndSlopes(model, runs)
        if runs == 1:
            start, readings = (x0.item(), cov0.item()), Z[0, 1:, 0].tolist()
        else:
            start, readings = (x0[:, 0], cov0[:, 0, 0]), list(Z[:, 1:, 0].T)
        out = _scalar_recursion(
            maps,
            *start,
            readings,
            maps.rows(U, n_steps - 1),
            *_scalar_noise(model),
        )
        xs[:, 1:, 0], covs[:, 1:, 0, 0], nis[:, 1:] = (np.array(o).T for o in out)
        return xs, covs, nis

    def _filter(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Estimates (R, T, n), covariances (R, T, n, n) and NIS (R, T) of R runs."""
        runs, n_steps, _ = Z.shape
        n = model.state_dim
        x, cov = self._start(model, Z[:, 0])
        xs, covs = np.empty((runs, n_steps, n)), np.empty((runs, n_steps, n, n))
        nis = np.full((runs, n_steps), np.nan)
        xs[:, 0], covs[:, 0] = x, cov
        for k in range(1, n_steps):
            at_step(model, k)
            *_, x, cov, nis[:, k] = _advance(model, x, cov, Z[:, k], step_input(U, k), k)
            xs[:, k], covs[:, k] = x, cov
        return xs, covs, nis


def _scalar(model: StateSpaceModel) -> bool:
    """Whether every matrix of the recursion is 1 × 1 (the term-by-term path).

    Why two paths: :func:`_advance` is the recursion for any n and m, with matrices (the
    public :meth:`KalmanFilter.step` runs it); for n = m = 1 (the gauge) its dozen small
    matrix calls a step would cost far more than the arithmetic, so the batch engine runs
    the same recursion term by term (:func:`_scalar_recursion`). Both are tested against
    each other and against the public step.
    """
    return model.state_dim == 1 and model.obs_dim == 1


def _scalar_noise(model: StateSpaceModel) -> tuple[float, float, float, float]:
    """Q = Var[v], R = Var[w], E[v] and E[w] of a scalar model, as floats."""
    return (
        float(model.state_noise.variance[0]),
        float(model.obs_noise.variance[0]),
        float(model.state_noise.mean[0]),
        float(model.obs_noise.mean[0]),
    )


def _state(model: StateSpaceModel, k: int, x: np.ndarray, cov: np.ndarray) -> KalmanState:
    sigma = np.sqrt(np.diagonal(cov))
    return KalmanState(model, k, x, x - 3 * sigma, x + 3 * sigma, cov)


def _slopes(slopes: Any, name: str, runs: int) -> np.ndarray:
    """Return a Jacobian's result as a float array of ``runs`` slopes, or say what is wrong.

    For n = 1 the Jacobian of ``name`` at a (runs, 1) column of states is one slope per run.
    """
    try:
        out = np.asarray(slopes, dtype=float)
    except (TypeError, ValueError):
        out = None
    if out is None or out.size != runs:
        shown = "not numbers" if out is None else f"shape {out.shape}"
        raise EvidenceError(
            f"the model's jacobian_{name} gave {shown} for {runs} state(s) of one dimension; "
            f"it must return one real slope ∂{name}/∂x per state, shape ({runs}, 1, 1) or "
            f"({runs},)"
        )
    return out


def _finite(value: Any, slope: Any, one: bool) -> bool:
    """Tell whether a map's value and slope (floats of one run, or arrays of a batch) are finite."""
    if one:
        return math.isfinite(value) and math.isfinite(slope)
    return bool(np.isfinite(value).all() and np.isfinite(slope).all())


def _refuse_infinite(name: str, value: Any, slope: Any, x: Any, k: int) -> None:
    """Raise for a map that gave ±inf (or a slope that is not finite) where the filter needs it.

    Eq. 21 linearises f and g at the estimate: an infinite value or slope there would turn
    every later estimate into NaN.
    """
    bad = np.flatnonzero(~(np.isfinite(value) & np.isfinite(slope)))
    run = int(bad[0]) if bad.size else 0
    batch = np.ndim(value) > 0

    def pick(a: Any) -> float:
        return float(np.ravel(a)[run])

    raise EvidenceError(
        f"the model's {name} gave {pick(value):.6g} with the slope {pick(slope):.6g} at the "
        f"state {pick(x):.6g}, at step {k} (counting from 0)"
        + (f" of run {run}" if batch else "")
        + f"; the Kalman filter linearises {name} there (eq. 21) and needs a finite value and "
        f"slope: check {name} near that state, or use a filter of bounded boxes "
        "(BoundedErrorFilter, DependentEvidenceFilter)"
    )


def _refuse_contradiction(singular: np.ndarray, surprised: np.ndarray, k: int) -> None:
    """Raise where S = 0 (no noise can explain a difference) and yet the reading differs.

    The reading differs from its prediction: the pseudo-inverse would give the gain 0 and
    ignore the reading.
    """
    bad = np.atleast_1d(singular & surprised)
    if bad.any():
        run = int(np.flatnonzero(bad)[0])
        raise InconsistentDataError(
            f"the Kalman filter's reading at step {k} (counting from 0)"
            + (f" of run {run}" if bad.size > 1 else "")
            + " differs from its prediction, "
            "but the model leaves no room for a difference (innovation covariance S = 0: "
            "zero-width noises v and w); give the noises a width, or check the readings"
        )


def _advance(
    model: StateSpaceModel,
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
    q_cov = np.diag(model.state_noise.variance)
    r_cov = np.diag(model.obs_noise.variance)
    f_u = with_input(model.f, u)
    jac_f = (
        model.jacobian_f(x, u)
        if model.jacobian_f is not None
        else finite_difference_jacobian(f_u, x)
    )
    x_pred = f_u(x) + model.state_noise.mean
    cov_pred = jac_f @ cov @ np.swapaxes(jac_f, -1, -2) + q_cov
    jac_g = (
        model.jacobian_g(x_pred)
        if model.jacobian_g is not None
        else finite_difference_jacobian(model.g, x_pred)
    )
    innovation = z - (model.g(x_pred) - model.obs_noise.mean)
    ph = cov_pred @ np.swapaxes(jac_g, -1, -2)
    s_cov = jac_g @ ph + r_cov
    _refuse_contradiction(
        ~np.any(s_cov != 0.0, axis=(-2, -1)), np.any(innovation != 0.0, axis=-1), k
    )
    s_inv = _inverse(s_cov)
    gain = ph @ s_inv
    x_new = x_pred + (gain @ innovation[..., None])[..., 0]
    joseph = np.eye(x.shape[-1]) - gain @ jac_g
    cov_new = joseph @ cov_pred @ np.swapaxes(joseph, -1, -2) + gain @ r_cov @ np.swapaxes(
        gain, -1, -2
    )
    nis = np.einsum("ri,rij,rj->r", innovation, s_inv, innovation)
    return x_pred, cov_pred, innovation, s_cov, gain, x_new, cov_new, nis
