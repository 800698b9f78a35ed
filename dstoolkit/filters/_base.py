"""The interface every filter shares, and what each one would otherwise repeat.

Every filter in dstoolkit (:class:`~dstoolkit.filters.DependentEvidenceFilter`,
:class:`~dstoolkit.filters.NassreddineFilter`, :class:`~dstoolkit.filters.BoundedErrorFilter`,
:class:`~dstoolkit.filters.KalmanFilter`, :class:`~dstoolkit.filters.ParticleFilter`)
derives from :class:`Filter`. A filter writes only its own parts:

- a typed state (a frozen dataclass deriving from :class:`FilterState`, holding what step
  k passes to step k + 1) and a typed record of a step (a frozen dataclass: the step's
  evidence, boxes, particles...);
- :meth:`Filter.initialize` (x̂_1 from the first reading z_1) and :meth:`Filter.step`
  (one recursion k → k + 1 of eq. 21's model): the public single step.

That is enough: :meth:`Filter.run`, ``run(..., record=True)`` and :meth:`Filter.run_batch`
loop over the runs and the steps (:meth:`Filter.step_loop`), in blocks of runs that fit the
memory budget. A filter may add a fast path, ``_engine``: the same recursion vectorised
over a block of runs (with ``_bytes_per_run``, its memory per run); ``run`` and
``run_batch`` then use it, and it gives the numbers of the step loop (tested).

:class:`Filter` writes the rest once: the checks of the model, readings and inputs at the
door; the option checks shared by all filters (``kernel``, boxes, frames Θ, α-cuts); the
run axis; chunks of runs that fit the memory budget
(:func:`dstoolkit.evidence.memory_budget`); the refusal of non-finite estimates, naming the
step and the run; and the result types, :class:`~dstoolkit.filters.FilterResult` (one run,
arrays (T, n)) and :class:`~dstoolkit.filters.BatchResult` (runs, arrays (R, T, n)).
"""

from __future__ import annotations

import importlib.util
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, Literal, NamedTuple, TypeVar

import numpy as np

from dstoolkit.errors import EvidenceError, require_extra
from dstoolkit.utils.budget import rows_per_chunk
from dstoolkit.utils.checks import real_array, real_number, whole_number

from ._model import (
    BatchResult,
    FilterResult,
    StateSpaceModel,
    at_step,
    batch_readings,
    guarded,
    single_readings,
)

#: The values of every filter's ``kernel`` option: ``"numpy"``; ``"numba"``, compiled
#: kernels (extra ``speed``) where the filter has them, giving the numpy numbers; ``"auto"``,
#: numba when it is installed.
KernelChoice = Literal["numpy", "numba", "auto"]
KERNELS: tuple[str, ...] = ("numpy", "numba", "auto")

StateT = TypeVar("StateT", bound="FilterState")
RecordT = TypeVar("RecordT")


class Block(NamedTuple):
    """What a filter's vectorised engine returns for a block of R runs of T steps."""

    estimates: np.ndarray
    """(R, T, n)"""
    lower: np.ndarray
    """(R, T, n)"""
    upper: np.ndarray
    """(R, T, n)"""
    diagnostics: dict[str, np.ndarray]
    """each (R, T)"""


@dataclass(frozen=True)
class FilterState:
    """What every filter's state holds: the model, the step and its estimate.

    Parameters
    ----------
    model : StateSpaceModel
        The model the filter runs on.
    k : int
        The step whose estimate this is (1 for the first reading).
    estimate : ndarray, shape (n,)
        x̂_k.
    lower : ndarray, shape (n,)
        Bounds of step k's final belief (see
        :class:`~dstoolkit.filters.FilterResult`).
    upper : ndarray, shape (n,)
        Bounds of step k's final belief (see
        :class:`~dstoolkit.filters.FilterResult`).
    """

    model: StateSpaceModel
    k: int
    estimate: np.ndarray
    lower: np.ndarray
    upper: np.ndarray


class Filter(ABC, Generic[StateT, RecordT]):
    """A recursive filter of the bounded-noise model of eq. 21.

    Subclasses are frozen dataclasses of their options. Each one has the same public
    methods, with the same meaning:

    ``initialize(model, z1)``
        The state after the first reading z_1 (its estimate x̂_1).
    ``step(state, z, u=None)``
        One recursion: the state after reading ``z`` (the input ``u`` drives f(x, u) from the
        previous step), and the typed record of that step.
    ``run(model, z, inputs=None, record=False)``
        The same loop over a whole sequence, as a :class:`~dstoolkit.filters.FilterResult`.
    ``run_batch(model, Z, inputs=None)``
        Many independent sequences at once, vectorised over runs, as a
        :class:`~dstoolkit.filters.BatchResult`; run r gives the numbers of ``run``.

    Every filter takes ``kernel`` (``"numpy"``, ``"numba"`` or ``"auto"``, see
    ``KERNELS``) and reports its per-step numbers under the keys of its
    ``DIAGNOSTICS``.

    Examples
    --------
    The public step gives what :meth:`run` gives:

    >>> import numpy as np
    >>> from dstoolkit.filters import KalmanFilter, random_walk
    >>> model, z = random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1]
    >>> flt = KalmanFilter()
    >>> state = flt.initialize(model, z[0])
    >>> for reading in z[1:]:
    ...     state, record = flt.step(state, reading)
    >>> last = flt.run(model, z).estimates[-1]
    >>> bool(np.array_equal(state.estimate, last))
    True
    """

    #: Short name of the method, the key of studies and plots (e.g. ``"kalman"``).
    name: ClassVar[str]
    #: Per-step diagnostics of a run (the keys of ``FilterResult.diagnostics``), explained.
    DIAGNOSTICS: ClassVar[dict[str, str]] = {}
    #: Whether the filter has compiled kernels (extra ``speed``): only then does it accept
    #: ``kernel="numba"``.
    COMPILED_KERNEL: ClassVar[bool] = False

    # -- what each filter writes -------------------------------------------------------------
    @abstractmethod
    def initialize(self, model: StateSpaceModel, z1: Any) -> StateT:
        """Return the state after the first reading.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading.

        Returns
        -------
        state
            The filter's state (its ``State`` class); ``state.estimate`` is x̂_1, shape (n,).
        """

    @abstractmethod
    def step(self, state: StateT, z: Any, u: Any = None) -> tuple[StateT, RecordT]:
        """One recursion of the filter: from the state of step k to that of step k + 1.

        Parameters
        ----------
        state
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the
            transition k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state
            The state of step k + 1; ``state.estimate`` is x̂_{k+1}.
        record
            The filter's typed record of the step (its ``Record`` class).
        """

    # -- optional: a fast path, and the record of the start ------------------------------------
    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        """Run the recursion on a block of runs, Z (R, T, m), U (R, T − 1, q) or None.

        ``runs`` are the runs' indices in the batch (their random streams, if any). By
        default the public step loop (:meth:`step_loop`); a filter may override it with a
        vectorised fast path that gives the same numbers.
        """
        return self.step_loop(model, Z, U)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        """Memory of one run's working arrays in :meth:`_engine`, bytes.

        By default what the step loop keeps of a run: its estimates, bounds and diagnostics.
        """
        return 8.0 * n_steps * (3 * model.state_dim + len(self.DIAGNOSTICS) + 1)

    def _start_record(self, state: StateT) -> RecordT | None:
        """Return the record of the first step (what :meth:`initialize` found); default None.

        Without one, the diagnostics of the first step are empty: NaN, False or 0.
        """
        return None

    def _check_model(self, model: StateSpaceModel) -> None:
        """Refuse a model this filter cannot use (e.g. without g⁻¹); default: accept."""

    def _check_runs(self, runs: int) -> None:
        """Refuse options that do not fit a batch of ``runs`` runs; default: accept."""

    def _chunk_cap(self, model: StateSpaceModel, n_steps: int) -> int | None:
        """Return the most runs per block (None: as many as the memory budget allows)."""
        return None

    @property
    def _title(self) -> str:
        """The name in messages: ``"dependent-evidence"`` for ``"dependent_evidence"``."""
        return self.name.replace("_", "-")

    #: What to do when one run does not fit the memory budget.
    _budget_advice: ClassVar[str] = "filter fewer steps at once"

    # -- what the base writes once ------------------------------------------------------------
    def run(
        self, model: StateSpaceModel, z: Any, inputs: Any = None, record: bool = False
    ) -> FilterResult:
        """Filter one sequence of readings.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z : array_like, shape (T, m), or (T,) when m = 1
            The readings z_1 … z_T.
        inputs : array_like, shape (T − 1, q), optional
            ``inputs[k - 1]`` drives f(x,
            u) from step k − 1 to step k.
        record : bool, optional
            Keep the typed record of every step in
            ``result.steps`` (runs the public
            :meth:`step` loop).

        Returns
        -------
        FilterResult
            Estimates, bounds (T, n) and diagnostics (T,).

        Raises
        ------
        EvidenceError
            Readings, inputs or model of the wrong shape or not finite, or an estimate that
            is not a finite number (the model's f or g gave NaN or ±inf).
        MemoryBudgetError
            One run does not fit the memory budget.
        """
        zz, uu = single_readings(_checked_model(model), z, inputs)
        self._check_model(model)
        model = self._guarded(model)
        if record:
            return self._run_steps(model, zz[0], None if uu is None else uu[0])
        self._chunks(1, self._bytes_per_run(model, zz.shape[1]))
        block = self._engine(model, zz, uu, np.zeros(1, dtype=np.intp))
        self._finite(block.estimates)
        return FilterResult(
            self.name,
            block.estimates[0],
            block.lower[0],
            block.upper[0],
            {key: value[0] for key, value in block.diagnostics.items()},
        )

    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None) -> BatchResult:
        """Filter many independent sequences at once, vectorised over runs.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        Z : array_like, shape (R, T, m), or (R, T) when m = 1
            R sequences of T readings.
        inputs : array_like, shape (R, T − 1, q), optional
            One input sequence per run.

        Returns
        -------
        BatchResult
            Estimates and bounds (R, T, n), diagnostics (R, T); run r holds the numbers
            :meth:`run` gives on ``Z[r]`` (for the particle filter, with run r's random
            stream).

        Raises
        ------
        EvidenceError, MemoryBudgetError
            As :meth:`run`; a batch is cut into blocks that fit the memory budget.
        """
        zz, uu = batch_readings(_checked_model(model), Z, inputs)
        self._check_model(model)
        model = self._guarded(model)
        runs, n_steps = zz.shape[:2]
        self._check_runs(runs)
        ids = np.arange(runs)
        blocks = [
            self._engine(model, zz[sel], None if uu is None else uu[sel], ids[sel])
            for sel in self._chunks(
                runs, self._bytes_per_run(model, n_steps), self._chunk_cap(model, n_steps)
            )
        ]
        est = self._finite(np.concatenate([b.estimates for b in blocks]))
        return BatchResult(
            self.name,
            est,
            np.concatenate([b.lower for b in blocks]),
            np.concatenate([b.upper for b in blocks]),
            {
                key: np.concatenate([b.diagnostics[key] for b in blocks])
                for key in blocks[0].diagnostics
            },
        )

    def _guarded(self, model: StateSpaceModel) -> StateSpaceModel:
        """Return the model whose maps refuse NaN and complex results, naming the step."""
        return guarded(model, self._title)

    def _run_steps(
        self, model: StateSpaceModel, z: np.ndarray, u: np.ndarray | None
    ) -> FilterResult:
        """``run(record=True)``: the public :meth:`initialize` and :meth:`step` in a loop."""
        states, records = self._steps(model, z, u)
        est = self._finite(np.stack([s.estimate for s in states])[None])[0]
        return FilterResult(
            self.name,
            est,
            np.stack([s.lower for s in states]),
            np.stack([s.upper for s in states]),
            self._diagnostics(records, (*self.DIAGNOSTICS, *self.RECORDED)),
            tuple(records),
        )

    def _steps(
        self, model: StateSpaceModel, z: np.ndarray, u: np.ndarray | None
    ) -> tuple[list[StateT], list[Any]]:
        """Return the states and records of :meth:`initialize` then :meth:`step` over ``z``."""
        state = self.initialize(model, z[0])
        states, records = [state], [self._start_record(state)]
        for k in range(1, z.shape[0]):
            at_step(model, k)  # a map's NaN is reported with its step
            state, rec = self.step(state, z[k], None if u is None else u[k - 1])
            states.append(state)
            records.append(rec)
        return states, records

    @staticmethod
    def _diagnostics(records: Sequence[Any], keys: Sequence[str]) -> dict[str, np.ndarray]:
        """Return each key's values over the records; a missing start record gives NaN/False/0."""
        out = {}
        for key in keys:
            if records[0] is not None:
                out[key] = np.array([getattr(r, key) for r in records])
            else:
                later = np.array([getattr(r, key) for r in records[1:]])
                out[key] = np.concatenate([np.array([_empty(later.dtype)]), later])
        return out

    def step_loop(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None = None
    ) -> Block:
        """Run :meth:`initialize` and :meth:`step` over every run of a block, one after another.

        This is what :meth:`run` and :meth:`run_batch` use when the filter has no vectorised
        ``_engine``, and what a fast path is tested against.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21 (checked, as :meth:`run` passes it).
        Z : ndarray, shape (R, T, m)
            The readings of R runs.
        U : ndarray, shape (R, T − 1, q), optional
            Their inputs.

        Returns
        -------
        Block
            Estimates and bounds (R, T, n) and the diagnostics of ``DIAGNOSTICS`` (R, T).
        """
        est, lower, upper, diagnostics = [], [], [], []
        for r in range(Z.shape[0]):
            states, records = self._steps(model, Z[r], None if U is None else U[r])
            est.append(np.stack([s.estimate for s in states]))
            lower.append(np.stack([s.lower for s in states]))
            upper.append(np.stack([s.upper for s in states]))
            diagnostics.append(self._diagnostics(records, tuple(self.DIAGNOSTICS)))
        return Block(
            np.stack(est),
            np.stack(lower),
            np.stack(upper),
            {key: np.stack([d[key] for d in diagnostics]) for key in self.DIAGNOSTICS},
        )

    #: Keys that ``run(..., record=True)`` adds to the diagnostics from the records.
    RECORDED: ClassVar[tuple[str, ...]] = ()

    @staticmethod
    def _one(
        model: StateSpaceModel, z: Any, u: Any = None, *, transition: bool = True
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Check one reading z and the input u of the transition into it as :meth:`run` does.

        ``transition=False``: the first reading, which has none. They are checked as a
        block of one run, (1, m) and (1, q) (or None).
        """
        _checked_model(model)
        reading = real_array(z, "z", ndim=(0, 1), error=EvidenceError)
        try:
            zz = np.broadcast_to(reading, (2, model.obs_dim))
        except ValueError:
            raise EvidenceError(
                f"a reading must have {model.obs_dim} component(s), got shape {np.shape(z)}"
            ) from None
        if not transition:
            return single_readings(model, zz[:1])[0][:, 0], None
        uu = (
            None
            if u is None
            else np.atleast_1d(real_array(u, "u", ndim=(0, 1), error=EvidenceError))[None]
        )
        zz_, uu_ = single_readings(model, zz, uu)
        return zz_[:, 1], None if uu_ is None else uu_[:, 0]

    # -- options -----------------------------------------------------------------------------
    @staticmethod
    def _policy(value: Any, allowed: Sequence[str], name: str, other: str = "") -> None:
        """Refuse a policy (``on_conflict``, ``mass_rule``...) that is not one of ``allowed``.

        ``other`` names what else is accepted, e.g. "a state vector".
        """
        if not isinstance(value, str) or value not in allowed:
            raise EvidenceError(
                f"{name} must be one of {', '.join(repr(a) for a in allowed)}"
                + (f" or {other}" if other else "")
                + f", got {value!r}"
            )

    @classmethod
    def _compiled(cls, kernel: Any, purpose: str) -> bool:
        """Tell whether ``kernel`` asks for the compiled kernels (extra ``speed``).

        ``kernel`` is ``"numpy"``, ``"numba"`` or ``"auto"`` (numba when it is installed);
        the compiled kernels give the numpy path's numbers bit for bit. Refuses another
        value, ``"numba"`` for a filter without compiled kernels (``COMPILED_KERNEL``), or
        ``"numba"`` without numba. ``"auto"`` runs numpy where nothing is compiled.
        """
        cls._policy(kernel, ("numpy", "numba", "auto"), "kernel")
        if kernel == "numba" and not cls.COMPILED_KERNEL:
            raise EvidenceError(
                f"kernel='numba': {purpose} has no compiled kernel; use kernel='numpy' "
                "(or 'auto', which compiles only where a filter has compiled kernels)"
            )
        if kernel == "numba":
            require_extra("numba", "speed", f"kernel='numba' of {purpose}")
        return cls.COMPILED_KERNEL and (
            kernel == "numba"
            or (kernel == "auto" and importlib.util.find_spec("numba") is not None)
        )

    def _own(self, name: str, value: Any) -> None:
        """Keep ``value`` as the option ``name`` (the frozen dataclass's field).

        The checked and converted form is kept, so that later edits of the caller's objects
        change nothing.
        """
        object.__setattr__(self, name, value)

    def _whole(self, name: str, low: int = 0, high: int | None = None) -> None:
        """Check the integer option ``name`` (whole floats accepted) and keep it as an int."""
        self._own(
            name, whole_number(getattr(self, name), name, low=low, high=high, error=EvidenceError)
        )

    def _own_box(self, name: str = "initial_box") -> None:
        """Check the box option ``name`` and keep it as a pair of tuples of floats."""
        box = self._box(getattr(self, name), name)
        if box is not None:
            self._own(name, (tuple(box[0].tolist()), tuple(box[1].tolist())))

    def _own_frames(self) -> None:
        """Check ``theta`` (see :meth:`_frames`) and keep it as nested tuples of floats."""
        theta = self.theta  # type: ignore[attr-defined]
        self._frames(theta)
        if theta is not None:
            self._own(
                "theta",
                tuple(
                    None
                    if part is None
                    else tuple(map(tuple, np.asarray(part, float).reshape(-1, 2).tolist()))
                    for part in theta
                ),
            )

    @staticmethod
    def _box(box: Any, name: str = "initial_box") -> tuple[np.ndarray, np.ndarray] | None:
        """``(lo, hi)`` as two float vectors with lo <= hi (±inf allowed), or None."""
        if box is None:
            return None
        try:
            lo_raw, hi_raw = box
        except (TypeError, ValueError):
            raise EvidenceError(f"{name} must be a pair (lo, hi), got {box!r}") from None
        lo = np.atleast_1d(
            real_array(lo_raw, f"{name}[0]", allow_inf=True, ndim=(0, 1), error=EvidenceError)
        )
        hi = np.atleast_1d(
            real_array(hi_raw, f"{name}[1]", allow_inf=True, ndim=(0, 1), error=EvidenceError)
        )
        if lo.shape != hi.shape:
            raise EvidenceError(
                f"{name}: lo and hi must have the same length, got {lo.size} and {hi.size}"
            )
        if np.any(lo > hi):
            raise EvidenceError(
                f"{name} = ({lo.tolist()}, {hi.tolist()}) is empty: need "
                "lo <= hi in every component"
            )
        return lo, hi

    @staticmethod
    def _frame(theta: Any, name: str) -> None:
        """Check a frame Θ: None, or (lo, hi) pairs of finite numbers with lo < hi."""
        if theta is None:
            return
        arr = real_array(theta, name, ndim=(1, 2), error=EvidenceError)
        if arr.shape[-1] != 2:
            raise EvidenceError(
                f"{name} must be one (lo, hi) pair per component, got shape {arr.shape}"
            )
        if np.any(arr[..., 0] >= arr[..., 1]):
            raise EvidenceError(f"{name} = {arr.tolist()}: each frame needs lo < hi")

    @classmethod
    def _frames(cls, theta: Any) -> None:
        """Check ``theta``: None, or a pair (theta_v, theta_w) of frames (see :meth:`_frame`)."""
        if theta is None:
            return
        try:
            theta_v, theta_w = theta
        except (TypeError, ValueError):
            raise EvidenceError(
                "theta must be a pair (theta_v, theta_w), each None or one "
                f"(lo, hi) pair per component; got {theta!r}"
            ) from None
        cls._frame(theta_v, "theta_v")
        cls._frame(theta_w, "theta_w")

    @staticmethod
    def _cuts(p: Any, epsilon: Any) -> None:
        """Check the noise evidence's number of α-cuts p and discount ε (eqs. 24–26)."""
        whole_number(p, "p (number of α-cuts)", low=1, high=1000, error=EvidenceError)
        real_number(epsilon, "epsilon", low=0.0, high=1.0, high_open=True, error=EvidenceError)

    @staticmethod
    def _check_box_dim(
        box: tuple[np.ndarray, np.ndarray] | None, model: StateSpaceModel, name: str = "initial_box"
    ) -> None:
        if box is not None and box[0].size not in (1, model.state_dim):
            raise EvidenceError(
                f"{name} has {box[0].size} components; the model's state has {model.state_dim}"
            )

    # -- batching and results ------------------------------------------------------------------
    def _chunks(self, runs: int, bytes_per_run: float, cap: int | None = None) -> list[slice]:
        """Slices of the runs, each fitting the memory budget (and at most ``cap`` runs)."""
        size = rows_per_chunk(bytes_per_run, runs, f"the {self._title} filter", self._budget_advice)
        if cap is not None:
            size = max(1, min(size, cap))
        return [slice(i, min(runs, i + size)) for i in range(0, runs, size)]

    def _finite(self, values: np.ndarray, what: str = "estimate") -> np.ndarray:
        """Return ``values`` (runs, steps, n) or raise when one is NaN or infinite."""
        bad = ~np.isfinite(values)
        if bad.any():
            run, step = (int(i) for i in np.argwhere(bad)[0][:2])
            raise EvidenceError(
                f"the {self._title} filter's {what} at step {step} "
                f"(counting from 0) of run {run} is not a finite number: the model's f or g "
                "gave NaN or ±inf for these readings and inputs; check the inputs (e.g. "
                "orders n_k must be positive) and that the readings lie where f and g are "
                "defined"
            )
        return values


def _empty(dtype: np.dtype) -> Any:
    """Return the value of a diagnostic at a step that has none: NaN, False or 0 by type."""
    if dtype.kind == "b":
        return False
    return 0 if dtype.kind in "iu" else np.nan


def _checked_model(model: Any) -> StateSpaceModel:
    if not isinstance(model, StateSpaceModel):
        raise EvidenceError(
            f"model must be a StateSpaceModel, got {type(model).__name__}; build one with "
            "dstoolkit.filters.StateSpaceModel(f, g, state_noise, obs_noise, ...)"
        )
    return model
