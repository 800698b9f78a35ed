"""The pure bounded-error (set-membership) filter: one box, predicted and intersected.

The paper's introduction describes this family (its refs. 9–14, Gning's interval
constraint propagation): every noise lies in a known box, and the filter keeps the box of
states consistent with all the data so far,

    prediction   X⁻_k = f(X_{k−1}, u) + [v_lo, v_hi]      (interval image, Props. 1–2)
    correction   X_k  = X⁻_k ∩ g⁻¹(z_k + [w_lo, w_hi])     (eq. 21: g(x) = z + w)

and estimates the state by the centre of X_k. It starts from the box of states consistent
with the first reading, X_1 = g⁻¹(z_1 + [w_lo, w_hi]) (∩ ``initial_box``).

Inconsistent data
-----------------
The paper (after Nassreddine et al.) names its weakness: when the bounds are too tight,
X⁻_k ∩ g⁻¹(z_k + W) can be empty and there is no answer. The filter detects it and, with
``on_inconsistent="raise"`` (the default), raises :class:`~dstoolkit.errors.InconsistentDataError`
saying at which step (and run) and that the bounds are probably too tight. With
``on_inconsistent="reset"`` it restarts from the states consistent with that reading
alone, g⁻¹(z_k + W), as at the first step, and flags the step in
``diagnostics["resets"]``; the enclosure guarantee is lost at a reset.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from dstoolkit.errors import EvidenceError, InconsistentDataError
from dstoolkit.evidence import box_image

from ._base import Block, Filter, FilterState, KernelChoice
from ._model import (
    StateSpaceModel,
    at_step,
    first_reading_box,
    own_state,
    with_input,
)

InconsistencyPolicy = Literal["raise", "reset"]


@dataclass(frozen=True)
class BoundedErrorState(FilterState):
    """The bounded-error filter's state: the box X_k = [lower, upper], centre ``estimate``.

    Parameters
    ----------
    model : StateSpaceModel
        The model the filter runs on.
    k : int
        The step whose estimate this is (1 for the first reading).
    estimate : ndarray, shape (n,)
        x̂_k.
    lower, upper : ndarray, shape (n,)
        The box X_k = [lower, upper].
    """


@dataclass(frozen=True)
class BoundedErrorRecord:
    """One step of the bounded-error filter.

    Parameters
    ----------
    step : int
        k, counting the first reading as 1.
    prediction : tuple of ndarray, or None
        The predicted box X⁻_k = f(X_{k−1}, u) + [v_lo,
        v_hi] as (lo, hi); None at the start.
    reading : tuple of ndarray, or None
        X⁻_k ∩ g⁻¹(z_k + W) before any reset (empty where
        lo > hi); None at the start.
    box : tuple of ndarray
        The final box X_k as (lo, hi).
    resets : bool
        Whether the box was rebuilt from the reading alone (``on_inconsistent="reset"``).
    """

    step: int
    prediction: tuple[np.ndarray, np.ndarray] | None
    reading: tuple[np.ndarray, np.ndarray] | None
    box: tuple[np.ndarray, np.ndarray]
    resets: bool


@dataclass(frozen=True)
class BoundedErrorFilter(Filter[BoundedErrorState, BoundedErrorRecord]):
    """Set-membership filter with one box (see the module docstring).

    Parameters
    ----------
    on_inconsistent : {"raise", "reset"}
        ``"raise"``: raise
        :class:`~dstoolkit.errors.InconsistentDataError` when the box
        becomes empty; ``"reset"``: restart from the current reading and flag the step.
    initial_box : tuple of array_like, optional
        A box ``(lo, hi)`` known to hold the state at
        the first step (needed when g is not
        invertible); it also bounds the restart boxes.
    kernel : {"numpy", "auto"}
        The box recursion has no compiled kernel: both run numpy, and
        ``"numba"`` is refused.

    See Also
    --------
    DependentEvidenceFilter : the paper's filter, which keeps a mass function instead of a box.

    Examples
    --------
    >>> from dstoolkit.filters import BoundedErrorFilter, random_walk
    >>> result = BoundedErrorFilter().run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
    >>> result.lower[-1].round(2).tolist(), result.upper[-1].round(2).tolist()
    ([0.6], [1.5])
    """

    on_inconsistent: InconsistencyPolicy = "raise"
    initial_box: tuple[Any, Any] | None = None
    kernel: KernelChoice = "numpy"
    name: ClassVar[str] = "bounded_error"
    DIAGNOSTICS: ClassVar[dict[str, str]] = {
        "resets": "True where the box was rebuilt from the reading (on_inconsistent='reset')",
    }

    def __post_init__(self) -> None:
        self._policy(self.on_inconsistent, ("raise", "reset"), "on_inconsistent")
        self._own_box()
        self._compiled(self.kernel, "the bounded-error filter")

    def _check_model(self, model: StateSpaceModel) -> None:
        self._check_box_dim(self._box(self.initial_box), model)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        return float(8 * n_steps * (4 * model.state_dim + 1))

    # -- the public step -----------------------------------------------------------------------
    def initialize(self, model: StateSpaceModel, z1: Any) -> BoundedErrorState:
        """X_1 = g⁻¹(z_1 + [w_lo, w_hi]) (∩ ``initial_box``).

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading z_1.

        Returns
        -------
        BoundedErrorState
            The state of step 1; ``estimate`` is x̂_1, shape (n,).

        See Also
        --------
        Filter.initialize : the interface every filter shares.
        """
        self._check_model(model)
        z, _ = self._one(model, z1, transition=False)
        model = self._guarded(model)
        lo, hi = self._reading_box(model, z, 0)
        return BoundedErrorState(model, 1, 0.5 * (lo[0] + hi[0]), lo[0], hi[0])

    def step(
        self, state: BoundedErrorState, z: Any, u: Any = None
    ) -> tuple[BoundedErrorState, BoundedErrorRecord]:
        """Predict the box through f, intersect with g⁻¹(z + W).

        Parameters
        ----------
        state : BoundedErrorState
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the transition
            k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state : BoundedErrorState
            The state of step k + 1; ``estimate`` is x̂_{k+1}, shape (n,).
        record : BoundedErrorRecord
            What the step computed.

        See Also
        --------
        Filter.step : the interface every filter shares.
        """
        own_state(state, BoundedErrorState, self._title)
        model = state.model
        zz, uu = self._one(model, z, u)
        at_step(model, state.k)
        out = self._advance(model, state.lower[None], state.upper[None], zz, uu, state.k)
        p_lo, p_hi, r_lo, r_hi, lo, hi, reset = out
        record = BoundedErrorRecord(
            state.k + 1, (p_lo[0], p_hi[0]), (r_lo[0], r_hi[0]), (lo[0], hi[0]), bool(reset[0])
        )
        return BoundedErrorState(model, state.k + 1, 0.5 * (lo[0] + hi[0]), lo[0], hi[0]), record

    def _start_record(self, state: BoundedErrorState) -> BoundedErrorRecord:
        return BoundedErrorRecord(1, None, None, (state.lower, state.upper), False)

    # -- the recursion, vectorised over runs -----------------------------------------------------
    def _advance(
        self,
        model: StateSpaceModel,
        lo: np.ndarray,
        hi: np.ndarray,
        z: np.ndarray,
        u: np.ndarray | None,
        k: int,
    ) -> tuple[np.ndarray, ...]:
        """Step k → k + 1 for R runs: boxes (R, n), readings z (R, m), inputs (R, q).

        Returns the predicted box, the reading's box within it, the final box and the
        resets (R,).
        """
        f_lo, f_hi = box_image(with_input(model.f, u), lo, hi, model.f_monotone)
        p_lo = f_lo + model.state_noise.lower
        p_hi = f_hi + model.state_noise.upper
        r_lo, r_hi = model.inverse()(
            z + model.obs_noise.lower, z + model.obs_noise.upper, p_lo, p_hi
        )
        r_lo, r_hi = np.broadcast_to(r_lo, p_lo.shape), np.broadcast_to(r_hi, p_hi.shape)
        empty = np.any(r_lo > r_hi, axis=-1)
        lo, hi = r_lo, r_hi
        if np.any(empty):
            if self.on_inconsistent == "raise":
                r = int(np.flatnonzero(empty)[0])
                raise InconsistentDataError(self._message(model, z, k, r, p_lo, p_hi))
            n_lo, n_hi = self._reading_box(model, z[empty], k)
            lo, hi = r_lo.copy(), r_hi.copy()
            lo[empty], hi[empty] = n_lo, n_hi
        return p_lo, p_hi, r_lo, r_hi, lo, hi, empty

    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        n_runs, n_steps, _ = Z.shape
        n = model.state_dim
        los, his = np.empty((n_runs, n_steps, n)), np.empty((n_runs, n_steps, n))
        resets = np.zeros((n_runs, n_steps), dtype=bool)
        lo, hi = self._reading_box(model, Z[:, 0], 0)
        los[:, 0], his[:, 0] = lo, hi
        for k in range(1, n_steps):
            at_step(model, k)
            *_, lo, hi, resets[:, k] = self._advance(
                model, lo, hi, Z[:, k], None if U is None else U[:, k - 1], k
            )
            los[:, k], his[:, k] = lo, hi
        return Block(0.5 * (los + his), los, his, {"resets": resets})

    # -- internals -------------------------------------------------------------------------
    def _reading_box(
        self, model: StateSpaceModel, z: np.ndarray, k: int
    ) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = first_reading_box(model, z, self.initial_box)
        empty = np.any(lo > hi, axis=-1)
        if np.any(empty):
            raise InconsistentDataError(
                f"step {k} (run {int(np.flatnonzero(empty)[0])}): no state in initial_box "
                "is consistent with the reading under the observation noise bounds; "
                "widen initial_box or the observation noise bounds"
            )
        if not np.all(np.isfinite(lo) & np.isfinite(hi)):
            raise EvidenceError(
                f"step {k}: the reading does not bound every state component (g is not "
                "invertible there); give the bounded-error filter an initial_box"
            )
        return lo, hi

    @staticmethod
    def _message(
        model: StateSpaceModel, z: np.ndarray, k: int, r: int, p_lo: np.ndarray, p_hi: np.ndarray
    ) -> str:
        where = f"step {k} (reading z[{k}], counting from 0)" + (
            f" of run {r}" if z.shape[0] > 1 else ""
        )

        def num(x: np.ndarray) -> str:  # 6 significant digits: 1923.84 Hz, not 1923.84244
            return np.array2string(np.asarray(x), formatter={"float_kind": "{:.6g}".format})

        def fmt(lo: np.ndarray, hi: np.ndarray) -> str:
            return f"lower {num(lo)}, upper {num(hi)}"

        return (
            f"inconsistent data at {where}: the predicted box ({fmt(p_lo[r], p_hi[r])}) "
            "contains no state whose observation agrees with the reading "
            f"z = {num(z[r])} within the observation noise "
            f"bounds ({fmt(model.obs_noise.lower, model.obs_noise.upper)}). The noise bounds "
            f"(state noise {fmt(model.state_noise.lower, model.state_noise.upper)}) are "
            "probably too tight for these data: widen them, or use "
            "on_inconsistent='reset' to restart from the reading"
        )
