"""State-space models with bounded noise (paper eq. 21) and the result type shared by filters.

x_{k+1} = f(x_k, u_k) + v_k,   g(x_k) = z_k + w_k

with the paper's sign convention ("adding noise to z"): a reading z is high when w < 0, and
the evidence about g(x_k) is z_k + W. Every filter in dstoolkit takes a
:class:`StateSpaceModel` and returns a :class:`FilterResult`.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import IntervalEvidence, triangular_evidence
from dstoolkit.utils.checks import real_array

ArrayFn = Callable[..., np.ndarray]
#: ``g_inverse(lo, hi, x_lo, x_hi) -> (lo, hi)``: the states in [x_lo, x_hi] whose image meets
#: the observation box [lo, hi] (see :class:`StateSpaceModel`).
BoxInverse = Callable[
    [np.ndarray, np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]
]


def _read_only(values: np.ndarray) -> np.ndarray:
    """Return ``values`` made read-only (a noise's moments, shared by every caller)."""
    values.flags.writeable = False
    return values


@dataclass(frozen=True, init=False)
class BoundedNoise:
    """Independent triangular noises, one per component: support [lower, upper], mode.

    The same description feeds every filter: possibility → evidence for the evidential
    filters (eqs. 22–26), bounds for the bounded-error filter, mean and variance for the
    Kalman filter, the density for the particle filter. ``lower``, ``mode`` and ``upper``
    are scalars or equal-length vectors; they are stored as read-only float arrays.

    Parameters
    ----------
    lower, mode, upper : float or array_like, shape (d,)
        Support and mode of each component (the
        variable's unit), lower <= mode <= upper.

    Raises
    ------
    EvidenceError
        For non-finite numbers, shapes that differ, or lower > mode or mode > upper.

    References
    ----------
    The paper's eqs. (22)–(26) turn it into evidence.

    Examples
    --------
    >>> v = BoundedNoise(-0.3, 0.0, 0.3)
    >>> v.dim, round(float(v.variance[0]), 6)
    (1, 0.015)
    """

    lower: np.ndarray
    mode: np.ndarray
    upper: np.ndarray

    def __init__(self, lower: ArrayLike, mode: ArrayLike, upper: ArrayLike) -> None:
        lo, c, hi = (
            np.atleast_1d(np.array(real_array(a, name, finite=False, error=EvidenceError)))
            for a, name in ((lower, "lower"), (mode, "mode"), (upper, "upper"))
        )
        if not (lo.shape == c.shape == hi.shape) or lo.ndim != 1:
            raise EvidenceError("lower, mode and upper must be scalars or equal-length vectors")
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(np.isfinite(c))):
            raise EvidenceError("noise bounds and mode must be finite numbers")
        with np.errstate(over="ignore"):
            wide = ~np.isfinite(hi - lo)
        if wide.any():
            raise EvidenceError(
                f"noise bounds {lo.tolist()}, {hi.tolist()} are too far apart "
                "to compute with (their width overflows); rescale the variable"
            )
        if np.any(lo > c) or np.any(c > hi):
            raise EvidenceError(
                f"need lower <= mode <= upper for every component, got lower={lo.tolist()}, "
                f"mode={c.tolist()}, upper={hi.tolist()}"
            )
        for name, value in (("lower", lo), ("mode", c), ("upper", hi)):
            value.flags.writeable = False
            object.__setattr__(self, name, value)

    def __eq__(self, other: object) -> bool:
        """Equal bounds and modes, component by component."""
        if not isinstance(other, BoundedNoise):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, name), getattr(other, name))
            for name in ("lower", "mode", "upper")
        )

    def __hash__(self) -> int:
        return hash(
            tuple(tuple(getattr(self, name).tolist()) for name in ("lower", "mode", "upper"))
        )

    def __reduce__(self) -> tuple[Any, ...]:
        """Rebuild the noise through the constructor in pickle, copy and deepcopy.

        Its checks run again and the copy's arrays are read-only too.
        """
        return (BoundedNoise, (self.lower.tolist(), self.mode.tolist(), self.upper.tolist()))

    def __setstate__(self, state: Any) -> None:
        """Restore a pickle in the plain form (attributes, no constructor call).

        It goes through the constructor's checks too.
        """
        try:
            lower, mode, upper = state["lower"], state["mode"], state["upper"]
        except (KeyError, TypeError, IndexError):
            raise EvidenceError(
                "cannot unpickle a BoundedNoise from this state; pickle it with dstoolkit"
            ) from None
        BoundedNoise.__init__(self, lower, mode, upper)

    @classmethod
    def symmetric(cls, half_width: Any) -> BoundedNoise:
        """Noise in [−h, h] with mode 0.

        Parameters
        ----------
        half_width : float or array_like, shape (d,)
            h, one per component.

        Returns
        -------
        BoundedNoise
            The symmetric noise.
        """
        h = np.atleast_1d(np.asarray(half_width, dtype=float))
        return cls(-h, np.zeros_like(h), h)

    @property
    def dim(self) -> int:
        """Number of components."""
        return int(self.lower.size)

    @functools.cached_property
    def mean(self) -> np.ndarray:
        """Mean of the triangular density, (a + b + c)/3 (read-only, computed once)."""
        return _read_only((self.lower + self.mode + self.upper) / 3.0)

    @functools.cached_property
    def variance(self) -> np.ndarray:
        """Variance of the triangular density, (a² + b² + c² − ab − ac − bc)/18.

        Read-only, computed once.
        """
        a, c, b = self.lower, self.mode, self.upper
        return _read_only((a * a + b * b + c * c - a * b - a * c - b * c) / 18.0)

    def sample(self, rng: np.random.Generator, size: tuple[int, ...] = ()) -> np.ndarray:
        """Draws from the triangular densities.

        Parameters
        ----------
        rng : numpy.random.Generator
            The source.
        size : tuple of int
            The leading shape.

        Returns
        -------
        ndarray, shape ``size + (dim,)``
            The draws.
        """
        shape = (*tuple(size), self.dim)
        degenerate = self.upper == self.lower
        hi = np.where(degenerate, self.lower + 1.0, self.upper)
        if self.dim == 1:  # scalar bounds take numpy's fast loop; the same draws
            draws = rng.triangular(
                float(self.lower[0]), float(self.mode[0]), float(hi[0]), size=shape
            )
        else:
            draws = rng.triangular(self.lower, self.mode, hi, size=shape)
        return np.where(degenerate, self.lower, draws) if degenerate.any() else draws

    def pdf(self, x: np.ndarray) -> np.ndarray:
        """Product of the triangular densities of the components; 0 outside the support.

        Parameters
        ----------
        x : array_like, shape (..., dim)
            Where to evaluate.

        Returns
        -------
        ndarray, shape (...)
            The density (the inverse of the variable's unit to the power dim).
        """
        x = np.asarray(x, dtype=float)
        a, c, b = self.lower, self.mode, self.upper
        width = np.where(b > a, b - a, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(c > a, 2 * (x - a) / (width * (c - a)), 2 / width)
            down = np.where(b > c, 2 * (b - x) / (width * (b - c)), 2 / width)
        dens = np.where(x <= c, up, down)
        dens = np.where((x < a) | (x > b), 0.0, dens)
        return np.prod(dens, axis=-1)

    def evidence(self, p: int = 3, epsilon: float = 0.05, theta: Any = None) -> IntervalEvidence:
        """Evidence of the noise vector (eqs. 24–26 per component, product masses eq. 16).

        Parameters
        ----------
        p : int
            The number of α-cuts.
        epsilon : float
            The mass of Θ.
        theta : array_like, shape (dim, 2), optional
            One (lo, hi) pair per component,
            default mode ± 100σ.

        Returns
        -------
        IntervalEvidence
            p + 1 focal elements per component (p when ``epsilon`` is 0), their
            product for dim > 1.
        """
        parts = [
            triangular_evidence(
                self.lower[i],
                self.mode[i],
                self.upper[i],
                p,
                epsilon,
                None if theta is None else tuple(np.asarray(theta)[i]),
            )
            for i in range(self.dim)
        ]
        if self.dim == 1:
            return parts[0]
        from dstoolkit.evidence import cartesian_product

        return cartesian_product(parts)


@dataclass(frozen=True)
class StateSpaceModel:
    """x_{k+1} = f(x_k, u_k) + v_k and g(x_k) = z_k + w_k (eq. 21).

    Parameters
    ----------
    f
        State map ``f(x, u)``; ``x`` has shape (..., n), ``u`` is the step's input (or None);
        vectorised over leading axes.
    g
        Observation map ``g(x)`` → shape (..., m), vectorised.
    g_inverse
        Image of a box of observations under g⁻¹ (Step 5): ``g_inverse(lo, hi, x_lo, x_hi)``
        returns ``(lo, hi)`` of the states whose image lies in the box, intersected with the
        prior box [x_lo, x_hi]; vectorised over leading axes (the arguments may be read-only
        views: return new arrays). Required by the paper's filter.
    state_noise
        The bounded noises v and w.
    obs_noise
        The bounded noises v and w.
    f_monotone
        Per argument, +1 (increasing), −1 (decreasing) or 0 (neither or unknown). Arguments of
        f are the n state components followed by the n noise components; of g, the state
        components. ``None`` means unknown: the vertex method (Prop. 1) is used.
    g_monotone
        Per argument, +1 (increasing), −1 (decreasing) or 0 (neither or unknown). Arguments of
        f are the n state components followed by the n noise components; of g, the state
        components. ``None`` means unknown: the vertex method (Prop. 1) is used.
    jacobian_f
        Optional Jacobians for the (extended) Kalman filter, ``(x, u) -> (n, n)`` and
        ``x -> (m, n)``; finite differences are used when absent.
    jacobian_g
        Optional Jacobians for the (extended) Kalman filter, ``(x, u) -> (n, n)`` and
        ``x -> (m, n)``; finite differences are used when absent.
    name : str
        A short name for messages and tables.
    description : str
        What the state is, in words (not compared).
    """

    f: ArrayFn
    g: ArrayFn
    state_noise: BoundedNoise
    obs_noise: BoundedNoise
    g_inverse: BoxInverse | None = None
    f_monotone: tuple[int, ...] | None = None
    g_monotone: tuple[int, ...] | None = None
    jacobian_f: ArrayFn | None = None
    jacobian_g: ArrayFn | None = None
    name: str = "model"
    description: str = field(default="", compare=False)

    @property
    def state_dim(self) -> int:
        """n, the dimension of the state."""
        return self.state_noise.dim

    def inverse(self) -> BoxInverse:
        """Return the model's g⁻¹ on boxes.

        Returns
        -------
        callable
            ``g_inverse(lo, hi, x_lo, x_hi) -> (lo, hi)``.

        Raises
        ------
        EvidenceError
            When the model has none (every filter maps readings back to states through it).
        """
        if self.g_inverse is None:
            raise EvidenceError(
                f"model {self.name!r} has no g_inverse(lo, hi, x_lo, x_hi), which the filters "
                "use to map readings back to states; add it to the model"
            )
        return self.g_inverse

    @property
    def obs_dim(self) -> int:
        """m, the dimension of the observation."""
        return self.obs_noise.dim

    def simulate(
        self,
        x0: Any,
        steps: int,
        rng: np.random.Generator,
        inputs: Any = None,
        runs: int | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Draw a truth and its readings, z_k = g(x_k) − w_k (eq. 21).

        Parameters
        ----------
        x0 : array_like, shape (n,)
            The first state x_1.
        steps : int
            T, the number of states and readings.
        rng : numpy.random.Generator
            The source of the noises.
        inputs : array_like, shape (T − 1, q), optional
            u_k of each transition.
        runs : int, optional
            Draw this many independent runs at once.

        Returns
        -------
        x : ndarray, shape (T, n) or (runs, T, n)
            The true states.
        z : ndarray, shape (T, m) or (runs, T, m)
            The readings.
        """
        lead = () if runs is None else (runs,)
        x = np.broadcast_to(np.asarray(x0, dtype=float), (*lead, self.state_dim)).copy()
        xs, zs = [], []
        for k in range(steps):
            if k > 0:
                u = None if inputs is None else inputs[k - 1]
                x = self.f(x, u) + self.state_noise.sample(rng, lead)
            xs.append(x)
            zs.append(self.g(x) - self.obs_noise.sample(rng, lead))
        axis = 0 if runs is None else 1
        return np.stack(xs, axis=axis), np.stack(zs, axis=axis)


@dataclass(frozen=True)
class FilterResult:
    """What :meth:`Filter.run` returns: one run of a filter over T steps.

    Parameters
    ----------
    method : str
        The filter's :attr:`Filter.name`, e.g. ``"dependent_evidence"``.
    estimates : ndarray, shape (T, n)
        The point estimate x̂_k of every step (for the paper's
        filter, the pignistic
        expectation of eq. 20).
    lower : ndarray, shape (T, n)
        Bounds of each step's final belief: the hull of the
        final evidence for the
        evidential filters, the box of the bounded-error filter, ±3σ for Kalman, the hull of
        the living particles for the particle filter.
    upper : ndarray, shape (T, n)
        Bounds of each step's final belief: the hull of the
        final evidence for the
        evidential filters, the box of the bounded-error filter, ±3σ for Kalman, the hull of
        the living particles for the particle filter.
    diagnostics : dict of str to ndarray, shape (T,)
        Per-step numbers, each filter's own keys
        (its ``DIAGNOSTICS``); NaN where a key has
        no value at a step (e.g. a conflict at the first step).
    steps : tuple of records, or None
        With ``record=True``, the typed record of every
        step (the filter's ``Record``
        class), the same records :meth:`Filter.step` returns; ``steps[0]`` is the start.
    """

    method: str
    estimates: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    diagnostics: dict[str, np.ndarray] = field(default_factory=dict)
    steps: tuple[Any, ...] | None = None


@dataclass(frozen=True)
class BatchResult:
    """What :meth:`Filter.run_batch` returns: R independent runs of T steps each.

    Parameters
    ----------
    method : str
        The filter's :attr:`Filter.name`.
    estimates : ndarray, shape (R, T, n)
        As in :class:`FilterResult`, with a leading run axis.
    lower : ndarray, shape (R, T, n)
        As in :class:`FilterResult`, with a leading run axis.
    upper : ndarray, shape (R, T, n)
        As in :class:`FilterResult`, with a leading run axis.
    diagnostics : dict of str to ndarray, shape (R, T)
        As in :class:`FilterResult`, with a
        leading run axis.

    Examples
    --------
    >>> import numpy as np
    >>> from dstoolkit.filters import BoundedErrorFilter, random_walk
    >>> batch = BoundedErrorFilter().run_batch(random_walk(0.1, 0.5), np.zeros((3, 4)))
    >>> batch.estimates.shape, batch[1].estimates.shape
    ((3, 4, 1), (4, 1))
    """

    method: str
    estimates: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    diagnostics: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def runs(self) -> int:
        """R, the number of runs."""
        return int(self.estimates.shape[0])

    def __len__(self) -> int:
        return self.runs

    def __getitem__(self, run: int) -> FilterResult:
        """Run ``run`` of the batch as a :class:`FilterResult` (without records)."""
        return FilterResult(
            self.method,
            self.estimates[run],
            self.lower[run],
            self.upper[run],
            {key: value[run] for key, value in self.diagnostics.items()},
        )


#: How the filters call a model's maps, for the message when one does not take its arguments.
_SIGNATURES = {
    "f": "f(x, u) takes the states (..., n) and the inputs (or None)",
    "g": "g(x) takes the states (..., n)",
    "g_inverse": "g_inverse(lo, hi, x_lo, x_hi) takes a box of readings and a box of states "
    "and returns a pair (lo, hi) of state boxes",
}


class _MapGuard:
    """Checks what a model's maps return while a filter runs, and where it is."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.step = 0  # the step being filtered, counting from 0

    def wrap(self, fn: Callable[..., Any], name: str, dim: int | None = None) -> Callable[..., Any]:
        """Check ``fn``'s results: real numbers, and (with ``dim``) of shape (..., dim).

        The leading axes are those of its arguments, broadcast; ``g_inverse`` must return a
        pair.
        """

        def checked(*args: Any) -> Any:
            try:
                out = fn(*args)
            except TypeError as exc:  # called as the filters call it: a wrong signature
                raise EvidenceError(
                    f"the model's {name} failed while the {self.title} filter was at step "
                    f"{self.step} (counting from 0): TypeError: {exc}; {_SIGNATURES[name]}"
                ) from exc
            parts = out if isinstance(out, tuple) else (out,)
            if name == "g_inverse" and (not isinstance(out, tuple | list) or len(out) != 2):
                size = f" of length {len(out)}" if isinstance(out, tuple | list) else ""
                raise EvidenceError(
                    f"the model's g_inverse returned {type(out).__name__}{size} "
                    f"while the {self.title} filter was at step {self.step} (counting from 0); "
                    "g_inverse(lo, hi, x_lo, x_hi) must return a pair (lo, hi) of state boxes"
                )
            for part in parts:
                self.check(part, name)
                if dim is not None:
                    lead = np.broadcast_shapes(*(np.shape(a)[:-1] for a in args if a is not None))
                    self.check_shape(part, name, (*lead, dim))
            return out

        checked._guard = self  # type: ignore[attr-defined]
        checked._unchecked = fn  # type: ignore[attr-defined]
        return checked

    def check_shape(self, value: Any, name: str, want: tuple[int, ...]) -> None:
        """Refuse a result that does not broadcast to ``want`` (a wrong last axis, say)."""
        try:
            fits = np.broadcast_shapes(np.shape(value), want) == want
        except ValueError:
            fits = False
        if not fits:
            raise EvidenceError(
                f"the model's {name} returned shape {np.shape(value)} where {want} was due "
                f"(the last axis: {want[-1]} component(s)) while the {self.title} filter was "
                f"at step {self.step} (counting from 0); {name} must keep the leading axes of "
                "its argument and give the model's number of components on the last one"
            )

    def check(self, value: Any, name: str) -> None:
        arr = np.asarray(value)
        what = (
            "complex numbers"
            if arr.dtype.kind == "c"
            else "values that are not numbers"
            if arr.dtype.kind not in "biuf"
            else "NaN"
            if np.isnan(arr).any()
            else ""
        )
        if what:
            raise EvidenceError(
                f"the model's {name} returned {what} while the {self.title} filter was at step "
                f"{self.step} (counting from 0); {name} must return real numbers (±inf only "
                "where a bound is unbounded): check it on the states and inputs of that step"
            )


def guarded(model: StateSpaceModel, title: str) -> StateSpaceModel:
    """Return the model with f, g and g⁻¹ that refuse NaN, complex and non-numeric results.

    They name the map and the step (:func:`at_step` tells the step); already guarded models
    pass.
    """
    if getattr(model.f, "_guard", None) is not None:
        return model
    guard = _MapGuard(title)
    _probe_g_shape(model, guard)
    return dataclasses.replace(
        model,
        f=guard.wrap(model.f, "f", model.state_dim),
        g=guard.wrap(model.g, "g", model.obs_dim),
        g_inverse=None
        if model.g_inverse is None
        else guard.wrap(model.g_inverse, "g_inverse", model.state_dim),
    )


def _probe_g_shape(model: StateSpaceModel, guard: _MapGuard) -> None:
    """Refuse, before any work, a g whose result has the wrong number of components.

    g is evaluated once at the zero state; a g that fails there is left to the filter, which
    calls it where the states are.
    """
    try:
        with np.errstate(all="ignore"):
            out = model.g(np.zeros((1, model.state_dim)))
    except Exception:  # noqa: BLE001 - a g undefined at 0 is checked where it is used
        return
    guard.check_shape(out, "g", (1, model.obs_dim))


def unchecked(fn: Callable[..., Any]) -> tuple[Callable[..., Any], _MapGuard | None]:
    """Return a guarded map's own function and its guard.

    This is for a caller that checks the results itself (the Kalman filter's scalar
    recursion checks floats, not arrays); a map that is not guarded comes back as it is,
    with no guard.
    """
    return getattr(fn, "_unchecked", fn), getattr(fn, "_guard", None)


def own_state(state: Any, kind: type, title: str) -> None:
    """Refuse a state that is not the one this filter's ``initialize`` or ``step`` made.

    Another filter's state (or anything else) would fail deep inside with an AttributeError.
    """
    if not isinstance(state, kind):
        raise EvidenceError(
            f"the {title} filter's step() needs the {kind.__name__} that its initialize() or "
            f"step() returned, got {type(state).__name__}; start with initialize(model, z1)"
        )


def at_step(model: StateSpaceModel, k: int) -> None:
    """Tell a guarded model's maps that the filter is at step ``k`` (counting from 0)."""
    guard = getattr(model.f, "_guard", None)
    if guard is not None:
        guard.step = k


def batch_readings(
    model: StateSpaceModel, Z: Any, inputs: Any = None
) -> tuple[np.ndarray, np.ndarray | None]:
    """Check a batch of readings and inputs and give them their batch shapes.

    Returns ``Z`` as (runs, steps, m) floats and ``inputs`` as (runs, transitions, q) (or
    None), raising a clear error for wrong shapes, non-numbers, non-finite readings or
    inputs, and inputs that the model's f(x, u) does not accept.
    """
    z = real_array(Z, "readings", finite=False, error=EvidenceError)
    if z.ndim == 2 and model.obs_dim == 1:
        z = z[..., None]
    if z.ndim != 3 or z.shape[2] != model.obs_dim:
        raise EvidenceError(
            f"readings must have shape (runs, steps, {model.obs_dim}), got {z.shape}; "
            "a single sequence goes to run(), not run_batch()"
        )
    if z.shape[0] == 0 or z.shape[1] == 0:
        raise EvidenceError(f"no readings (shape {z.shape}): give at least one run of one step")
    if not np.isfinite(z).all():
        bad = np.argwhere(~np.isfinite(z))[0]
        raise EvidenceError(
            f"reading at run {bad[0]}, step {bad[1]} is not a finite number; remove or "
            "replace missing readings before filtering"
        )
    if inputs is None:
        if z.shape[1] > 1:
            _probe_inputs(model, None, z.shape[:2])
        return z, None
    u = real_array(inputs, "inputs", finite=False, error=EvidenceError)
    if u.ndim == 2:
        u = u[..., None]
    if u.ndim != 3 or u.shape[0] != z.shape[0] or u.shape[1] < z.shape[1] - 1:
        raise EvidenceError(
            f"inputs must have shape (runs, transitions, q) with runs = {z.shape[0]} and "
            f"transitions >= steps − 1 = {z.shape[1] - 1}, got {u.shape}"
        )
    u = u[:, : max(z.shape[1] - 1, 0)]
    if not np.isfinite(u).all():
        bad = np.argwhere(~np.isfinite(u))[0]
        raise EvidenceError(
            f"input at run {bad[0]}, transition {bad[1]} is not a finite number; give every "
            "transition its input (e.g. the orders n_k of eq. 43)"
        )
    if u.shape[1]:
        _probe_inputs(model, u, u.shape[:2])
    return z, u


def _probe_inputs(model: StateSpaceModel, u: np.ndarray | None, shape: tuple[int, ...]) -> None:
    """Evaluate f once on the inputs of every transition, u (runs, transitions, q) or None.

    ``shape`` = (runs, transitions). An input of the wrong shape or value, or a missing one,
    is thus reported here, before any work, and not deep inside (the gauge's f refuses
    orders n_k <= 0 and missing orders here).
    """
    x = np.zeros((*shape, model.state_dim))
    try:
        with np.errstate(all="ignore"):
            out = np.asarray(model.f(x, u))
        if out.shape != x.shape:
            np.broadcast_to(out, x.shape)  # raises when f's result does not fit the states
    except EvidenceError:
        raise
    except (ValueError, TypeError, IndexError) as exc:
        given = (
            "without inputs"
            if u is None
            else f"on inputs of shape {u.shape} (runs, transitions, q)"
        )
        raise EvidenceError(
            f"the model's f(x, u) fails {given}: {type(exc).__name__}: {exc}; give one input "
            "row per transition of the length f expects"
        ) from exc


def single_readings(
    model: StateSpaceModel, z: Any, inputs: Any = None
) -> tuple[np.ndarray, np.ndarray | None]:
    """Check and shape one sequence z (steps, m) (or (steps,) for m = 1) as a batch of one run.

    Its inputs are (transitions, q).
    """
    z = real_array(z, "readings", finite=False, error=EvidenceError)
    if z.ndim == 1 and model.obs_dim == 1:
        z = z[:, None]
    if z.ndim != 2:
        raise EvidenceError(
            f"readings must have shape (steps, {model.obs_dim}), got {z.shape}; "
            "a batch of sequences goes to run_batch()"
        )
    u = None if inputs is None else real_array(inputs, "inputs", finite=False, error=EvidenceError)
    if u is not None and u.ndim == 1:
        u = u[:, None]
    return batch_readings(model, z[None], None if u is None else u[None])


def step_input(inputs: np.ndarray | None, k: int) -> np.ndarray | None:
    """Return the inputs u (runs, q) of the transition into step k (None without inputs)."""
    return None if inputs is None else inputs[:, k - 1]


def with_input(f: ArrayFn, u: np.ndarray | None) -> Callable[[np.ndarray], np.ndarray]:
    """``x ↦ f(x, u)`` for state arrays x (runs, …, n).

    Parameters
    ----------
    f : callable
        The model's ``f(x, u)``.
    u : ndarray, shape (runs, q), or None
        One input row per run; it is reshaped to
        (runs, 1, …, 1, q) so that it broadcasts against x whatever axes lie between.

    Returns
    -------
    callable
        ``x ↦ f(x, u)``.

    Examples
    --------
    >>> import numpy as np
    >>> with_input(lambda x, u: x * u, np.array([[2.0]]))(np.array([[3.0]]))
    array([[6.]])
    """
    if u is None:
        return lambda x: f(x, None)
    return lambda x: f(x, u.reshape(u.shape[0], *([1] * (np.ndim(x) - 2)), u.shape[-1]))


def first_reading_box(
    model: StateSpaceModel, z: np.ndarray, prior: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """Find the states consistent with a reading: g⁻¹(z + [w_lo, w_hi]) ∩ prior (eq. 21).

    ``z`` has shape (..., m); ``prior`` is a box ``(lo, hi)`` of the state, default the
    whole space. Returns (lo, hi) of shape (..., n); empty boxes have lo > hi somewhere.
    """
    g_inverse = model.inverse()
    shape = (*z.shape[:-1], model.state_dim)
    if prior is None:
        p_lo, p_hi = np.full(shape, -np.inf), np.full(shape, np.inf)
    else:
        p_lo = np.broadcast_to(np.asarray(prior[0], dtype=float), shape)
        p_hi = np.broadcast_to(np.asarray(prior[1], dtype=float), shape)
    noise = model.obs_noise
    lo, hi = g_inverse(z + noise.lower, z + noise.upper, p_lo, p_hi)
    return _float_copy(lo, shape), _float_copy(hi, shape)


def _float_copy(side: Any, shape: tuple[int, ...]) -> np.ndarray:
    """Return a new float array of ``shape`` holding ``side`` (broadcast to it if needed)."""
    if type(side) is np.ndarray and side.shape == shape:
        return side.astype(float)  # what broadcasting to its own shape and copying gives
    return np.broadcast_to(side, shape).astype(float)
