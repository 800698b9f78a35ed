"""What every filter repeats: input checks at the door, batching in chunks, conflict policy.

Each filter in dstoolkit (:class:`~dstoolkit.filters.DependentEvidenceFilter`,
:class:`~dstoolkit.filters.NassreddineFilter`, :class:`~dstoolkit.filters.BoundedErrorFilter`,
:class:`~dstoolkit.filters.KalmanFilter`, :class:`~dstoolkit.filters.ParticleFilter`)
derives from :class:`FilterBase` and so

- checks the model, the readings z and the inputs u (orders n_k of the gauge, eq. 39)
  before any work: shapes, real finite numbers, inputs that f(x, u) accepts;
- checks its options the same way: a conflict policy among the allowed ones, a start
  vector, a box ``initial_box`` and frames Θ of the right shape, with lo <= hi;
- cuts a batch of runs into chunks that fit the memory budget
  (:func:`dstoolkit.evidence.memory_budget`), refusing when one run alone does not fit;
- refuses to return an estimate that is not a finite number (a model whose f or g gave
  NaN or ±inf for these inputs), naming the step and the run.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np

from dstoolkit.errors import EvidenceError, require_extra
from dstoolkit.evidence._checks import real_array, real_number, whole_number
from dstoolkit.evidence._limits import rows_per_chunk

from ._model import StateSpaceModel, batch_readings, single_readings

#: The kernels of a filter whose compiled kernels give its numpy numbers bit for bit.
KernelChoice = Literal["numpy", "numba", "auto"]


class FilterBase:
    """Mixin of the shared checks and batching; see the module docstring."""

    # -- readings and inputs -----------------------------------------------------------------
    def _single(self, model: StateSpaceModel, z: Any, inputs: Any
                ) -> tuple[np.ndarray, np.ndarray | None]:
        """One sequence, checked, as a batch of one run: (1, T, m) and (1, T − 1, q)."""
        return single_readings(_checked_model(model), z, inputs)

    def _batch(self, model: StateSpaceModel, Z: Any, inputs: Any
               ) -> tuple[np.ndarray, np.ndarray | None]:
        """A batch of sequences, checked: (R, T, m) and (R, T − 1, q)."""
        return batch_readings(_checked_model(model), Z, inputs)

    # -- options -----------------------------------------------------------------------------
    @staticmethod
    def _policy(value: Any, allowed: Sequence[str], name: str, other: str = "") -> None:
        """Refuse a policy (``on_conflict``, ``mass_rule``...) that is not one of ``allowed``
        (``other`` names what else is accepted, e.g. "a state vector")."""
        if not isinstance(value, str) or value not in allowed:
            raise EvidenceError(
                f"{name} must be one of {', '.join(repr(a) for a in allowed)}"
                + (f" or {other}" if other else "") + f", got {value!r}"
            )

    @classmethod
    def _compiled(cls, kernel: Any, purpose: str) -> bool:
        """Whether ``kernel`` (``"numpy"``, ``"numba"`` or ``"auto"``: numba when it is
        installed) asks for the compiled kernels (extra ``speed``) that give the numpy
        path's numbers bit for bit; refuses another value, or ``"numba"`` without numba."""
        cls._policy(kernel, ("numpy", "numba", "auto"), "kernel")
        if kernel == "numba":
            require_extra("numba", "speed", f"kernel='numba' of {purpose}")
        return kernel == "numba" or (kernel == "auto"
                                     and importlib.util.find_spec("numba") is not None)

    @staticmethod
    def _box(box: Any, name: str = "initial_box") -> tuple[np.ndarray, np.ndarray] | None:
        """``(lo, hi)`` as two float vectors with lo <= hi (±inf allowed), or None."""
        if box is None:
            return None
        try:
            lo_raw, hi_raw = box
        except (TypeError, ValueError):
            raise EvidenceError(f"{name} must be a pair (lo, hi), got {box!r}") from None
        lo = np.atleast_1d(real_array(lo_raw, f"{name}[0]", allow_inf=True, ndim=(0, 1),
                                        error=EvidenceError))
        hi = np.atleast_1d(real_array(hi_raw, f"{name}[1]", allow_inf=True, ndim=(0, 1),
                                        error=EvidenceError))
        if lo.shape != hi.shape:
            raise EvidenceError(f"{name}: lo and hi must have the same length, got "
                                    f"{lo.size} and {hi.size}")
        if np.any(lo > hi):
            raise EvidenceError(f"{name} = ({lo.tolist()}, {hi.tolist()}) is empty: need "
                                    "lo <= hi in every component")
        return lo, hi

    @staticmethod
    def _frame(theta: Any, name: str) -> None:
        """Check a frame Θ: None, or (lo, hi) pairs of finite numbers with lo < hi."""
        if theta is None:
            return
        arr = real_array(theta, name, ndim=(1, 2), error=EvidenceError)
        if arr.shape[-1] != 2:
            raise EvidenceError(f"{name} must be one (lo, hi) pair per component, got "
                                    f"shape {arr.shape}")
        if np.any(arr[..., 0] >= arr[..., 1]):
            raise EvidenceError(f"{name} = {arr.tolist()}: each frame needs lo < hi")

    @staticmethod
    def _cuts(p: Any, epsilon: Any) -> None:
        """The noise evidence's number of α-cuts p and discount ε (eqs. 24–26)."""
        whole_number(p, "p (number of α-cuts)", low=1, high=1000, error=EvidenceError)
        real_number(epsilon, "epsilon", low=0.0, high=1.0, high_open=True,
                    error=EvidenceError)

    @staticmethod
    def _check_box_dim(box: tuple[np.ndarray, np.ndarray] | None, model: StateSpaceModel,
                       name: str = "initial_box") -> None:
        if box is not None and box[0].size not in (1, model.state_dim):
            raise EvidenceError(f"{name} has {box[0].size} components; the model's state "
                                    f"has {model.state_dim}")

    # -- batching and results ------------------------------------------------------------------
    @staticmethod
    def _chunks(runs: int, bytes_per_run: float, what: str, advice: str,
                cap: int | None = None) -> list[slice]:
        """Slices of the runs, each fitting the memory budget (and at most ``cap`` runs)."""
        size = rows_per_chunk(bytes_per_run, runs, what, advice)
        if cap is not None:
            size = max(1, min(size, cap))
        return [slice(i, min(runs, i + size)) for i in range(0, runs, size)]

    def _finite(self, values: np.ndarray, what: str = "estimate") -> np.ndarray:
        """Return ``values`` (runs, steps, n) or raise when one is NaN or infinite."""
        bad = ~np.isfinite(values)
        if bad.any():
            run, step = (int(i) for i in np.argwhere(bad)[0][:2])
            raise EvidenceError(
                f"the {getattr(self, 'name', 'filter')} filter's {what} at step {step} "
                f"(counting from 0) of run {run} is not a finite number: the model's f or g "
                "gave NaN or ±inf for these readings and inputs; check the inputs (e.g. "
                "orders n_k must be positive) and that the readings lie where f and g are "
                "defined"
            )
        return values


def _checked_model(model: Any) -> StateSpaceModel:
    if not isinstance(model, StateSpaceModel):
        raise EvidenceError(
            f"model must be a StateSpaceModel, got {type(model).__name__}; build one with "
            "dstoolkit.filters.StateSpaceModel(f, g, state_noise, obs_noise, ...)"
        )
    return model
