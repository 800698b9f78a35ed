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
from dstoolkit.evidence._extension import box_image

from ._base import FilterBase
from ._model import (
    FilterResult,
    StateSpaceModel,
    first_reading_box,
    step_input,
    with_input,
)

InconsistencyPolicy = Literal["raise", "reset"]


@dataclass(frozen=True)
class BoundedErrorFilter(FilterBase):
    """Set-membership filter with one box (see the module docstring).

    Parameters
    ----------
    on_inconsistent
        ``"raise"``: raise :class:`~dstoolkit.errors.InconsistentDataError` when the box
        becomes empty; ``"reset"``: restart from the current reading and record the step.
    initial_box
        Optional box ``(lo, hi)`` known to hold the state at the first step (needed when g
        is not invertible); it also bounds the restart boxes.
    """

    on_inconsistent: InconsistencyPolicy = "raise"
    initial_box: tuple[Any, Any] | None = None
    name: ClassVar[str] = "bounded-error"

    def __post_init__(self) -> None:
        self._policy(self.on_inconsistent, ("raise", "reset"), "on_inconsistent")
        self._box(self.initial_box)

    def run(
        self, model: StateSpaceModel, z: Any, inputs: Any = None, record: bool = False
    ) -> FilterResult:
        """Filter one sequence ``z`` (steps, m): estimates are box centres, ``lower`` and
        ``upper`` the boxes. ``record=True`` keeps each step's ``prediction`` box, the
        ``reading`` box g⁻¹(z_k + W) ∩ prediction before any reset, and the final ``box``.
        Diagnostics: ``resets`` (steps,), True where the box was rebuilt from the reading."""
        Z, U = self._single(model, z, inputs)
        self._check_box_dim(self._box(self.initial_box), model)
        lo, hi, resets, steps = self._filter(model, Z, U, record)
        self._finite(0.5 * (lo + hi))
        return FilterResult(
            method=self.name, estimates=0.5 * (lo[0] + hi[0]), lower=lo[0], upper=hi[0],
            steps=steps, diagnostics={"resets": resets[0]},
        )

    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None, *,
                  return_result: bool = False) -> np.ndarray | FilterResult:
        """Box centres (runs, steps, n) of independent sequences Z (runs, steps, m);
        ``return_result=True`` returns a FilterResult whose arrays carry the leading run
        axis, with the boxes and ``diagnostics["resets"]`` (runs, steps)."""
        Z, U = self._batch(model, Z, inputs)
        self._check_box_dim(self._box(self.initial_box), model)
        lo, hi, resets, _ = self._filter(model, Z, U, False)
        est = self._finite(0.5 * (lo + hi))
        if not return_result:
            return est
        return FilterResult(method=self.name, estimates=est, lower=lo, upper=hi,
                            diagnostics={"resets": resets})

    # -- internals -------------------------------------------------------------------------
    def _reading_box(self, model: StateSpaceModel, z: np.ndarray, k: int
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

    def _filter(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, record: bool
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]] | None]:
        runs, n_steps, _ = Z.shape
        n = model.state_dim
        v_lo, v_hi = model.state_noise.lower, model.state_noise.upper
        w_lo, w_hi = model.obs_noise.lower, model.obs_noise.upper
        los, his = np.empty((runs, n_steps, n)), np.empty((runs, n_steps, n))
        resets = np.zeros((runs, n_steps), dtype=bool)

        lo, hi = self._reading_box(model, Z[:, 0], 0)
        los[:, 0], his[:, 0] = lo, hi
        steps = [{"box": (lo[0].copy(), hi[0].copy())}] if record else None
        for k in range(1, n_steps):
            f_lo, f_hi = box_image(with_input(model.f, step_input(U, k)), lo, hi, model.f_monotone)
            p_lo, p_hi = f_lo + v_lo, f_hi + v_hi
            lo, hi = model.inverse()(Z[:, k] + w_lo, Z[:, k] + w_hi, p_lo, p_hi)
            lo, hi = np.broadcast_to(lo, p_lo.shape), np.broadcast_to(hi, p_hi.shape)
            if steps is not None:
                steps.append({"prediction": (p_lo[0].copy(), p_hi[0].copy()),
                              "reading": (lo[0].copy(), hi[0].copy())})
            empty = np.any(lo > hi, axis=-1)
            if np.any(empty):
                if self.on_inconsistent == "raise":
                    r = int(np.flatnonzero(empty)[0])
                    raise InconsistentDataError(self._message(model, Z, k, r, p_lo, p_hi))
                r_lo, r_hi = self._reading_box(model, Z[empty, k], k)
                lo, hi = lo.copy(), hi.copy()
                lo[empty], hi[empty] = r_lo, r_hi
                resets[empty, k] = True
            los[:, k], his[:, k] = lo, hi
            if steps is not None:
                steps[-1]["box"] = (lo[0].copy(), hi[0].copy())
        return los, his, resets, steps

    @staticmethod
    def _message(model: StateSpaceModel, Z: np.ndarray, k: int, r: int,
                 p_lo: np.ndarray, p_hi: np.ndarray) -> str:
        where = (f"step {k} (reading z[{k}], counting from 0)"
                 + (f" of run {r}" if Z.shape[0] > 1 else ""))

        def num(x: np.ndarray) -> str:  # 6 significant digits: 1923.84 Hz, not 1923.84244
            return np.array2string(np.asarray(x), formatter={"float_kind": "{:.6g}".format})

        def fmt(lo: np.ndarray, hi: np.ndarray) -> str:
            return f"lower {num(lo)}, upper {num(hi)}"

        return (
            f"inconsistent data at {where}: the predicted box ({fmt(p_lo[r], p_hi[r])}) "
            "contains no state whose observation agrees with the reading "
            f"z = {num(Z[r, k])} within the observation noise "
            f"bounds ({fmt(model.obs_noise.lower, model.obs_noise.upper)}). The noise bounds "
            f"(state noise {fmt(model.state_noise.lower, model.state_noise.upper)}) are "
            "probably too tight for these data: widen them, or use "
            "on_inconsistent='reset' to restart from the reading"
        )
