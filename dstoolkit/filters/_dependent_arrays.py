"""The array path of the paper's filter: Steps 2–6 for a block of runs, buffers allocated once.

Why this engine exists beside the public step. The public step
(:meth:`~dstoolkit.filters.DependentEvidenceFilter.step`) is the reference: it runs Steps
2–6 on evidence objects, one run at a time, and it is what a learner reads. It cannot be
the engine of ``run`` and ``run_batch``: it handles one run, and it builds objects and
merges focal elements (eq. 14) at every step. A step works on arrays of 4–1,100 elements,
so its cost is numpy's per-call overhead (``benchmarks/filter_profile.py`` measures it);
:class:`StepArrays` runs a whole block of runs at once in a few dozen numpy calls a step
and is what the speed of ``run_batch`` rests on. The compiled Step 6
(:func:`~dstoolkit.filters._compiled.fuse_dependent`, ``kernel="numba"``) is the one
fast kernel beside it. The three give the same numbers to rounding (tested). How:

- everything constant over a run is computed once: the noise boxes laid out for each
  step's broadcasts, the product masses of Steps 2 and 4 (ρ_ij = m_v(i) m_v(j), ρ_ij m_w(l),
  eq. 16), the reading boxes z_k + W of every step, the monotone end points of f's images
  (Prop. 2, eqs. 18–19);
- every array of a step is a preallocated buffer written with ``out=``, through views
  made once: a step creates almost no array;
- the boxes of Step 6 are the *columns* of one buffer (R, 3, n, N): lo, hi and centre on
  axis 1, the focal elements last, in the order [Θ1, E1, E2, Θ2] — E1 = Step 5's
  evidence, column 1 + l·N_p + i for the product of predicted box i with noise box l of
  Step 4, and E2 = the prediction, column 1 + N_1 + i·N_v + j. E1 and E2 together are the
  operand of :class:`~dstoolkit.evidence.boxes.DependenceKernel` (both energies in
  one pass, m1(D) and m2(D) of eq. A3 in one matrix product), and [Θ1, E1] × [E2, Θ2] the
  operands of :class:`~dstoolkit.evidence.boxes.ProductKernel` (Dempster's rule
  and the pignistic expectation, eqs. 1, 20); every comparison and product runs along
  the long last axis; E2's columns with their centres are also the points where g is
  evaluated (Step 3);
- for one run, the figures of the dependence (eqs. A1–A6) and the checks are computed on
  Python floats (one numpy call on one element costs more than a float operation); a block of
  runs computes the same operations on arrays, so a batch equals single runs exactly;
- the monotonicity checks of the images (Prop. 2) keep every step's values and run once
  per block, and before any other error is raised.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from dstoolkit.errors import EvidenceError, NotMonotoneError
from dstoolkit.evidence import CONFLICT_TOLERANCE, Boxes
from dstoolkit.evidence.boxes import (
    CHECK_RTOL,
    DependenceKernel,
    ProductKernel,
    coefficient_error,
    image_boxes,
    least,
    per_run,
)

from ._compiled import fuse_dependent
from ._model import with_input

if TYPE_CHECKING:
    from ._dependent import DependentEvidenceFilter, ModelMaps, NoiseEvidence

#: Relative distance below which a mapped-back bound is snapped to its predicted box (Step 5).
SNAP_RTOL = 1e-12


def _view(array: np.ndarray, *shape: int) -> np.ndarray:
    """Reshape ``array`` without a copy (an error if that needs one).

    Writes through the result reach ``array``.
    """
    view = array.view()
    view.shape = shape
    return view


def _pairs(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Boxes (..., n) twice → (..., n, 2), (lo, hi) last."""
    return np.stack([lo, hi], axis=-1)


# -- Steps 2, 3, 5 on arrays (the object path calls them; StepArrays for other models) -----
def predict(
    maps: ModelMaps, noise: NoiseEvidence, xhat: np.ndarray, f_u: Callable[[np.ndarray], np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """Step 2: boxes of F(x, v) = f(x, u) + v over (x̂ + V_i) × V_j, row i·N_v + j.

    F is separable in v, so F(X × V) = f(X) + V exactly: f (``f_u`` = x ↦ f(x, u)) is
    imaged on the N_v state boxes only (eqs. 13, 16–19), then each noise box is added.
    ``xhat`` (R, n) → (R, N_v², n).
    """
    x_lo, x_hi = xhat[:, None] + noise.v.lo, xhat[:, None] + noise.v.hi
    fx_lo, fx_hi = image_boxes(x_lo, x_hi, f_u, maps.f_method, maps.f_signs)
    runs, n = fx_lo.shape[0], fx_lo.shape[-1]
    lo = (fx_lo[:, :, None] + noise.v.lo[:, None]).reshape(runs, -1, n)
    hi = (fx_hi[:, :, None] + noise.v.hi[:, None]).reshape(runs, -1, n)
    return lo, hi


def observe(maps: ModelMaps, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step 3: g of every predicted box (eqs. 13–14), row for row."""
    return image_boxes(lo, hi, maps.model.g, maps.g_method, maps.g_signs)


def snap_to_prior(back: np.ndarray, prior: np.ndarray, live: np.ndarray | None) -> None:
    """Apply Step 5's last touch, in place on boxes (..., n, 2).

    A bound within :data:`SNAP_RTOL` · max(|lo|, |hi|) of its predicted box's is set to
    it, and boxes not ``live`` (mass 0; None: all live) take the predicted box. ``prior``
    broadcasts.
    """
    scale = np.abs(prior).max(axis=-1, keepdims=True)
    scale *= SNAP_RTOL
    near = np.abs(back - prior) <= scale
    if live is not None:
        near |= ~live[..., None, None]
    np.copyto(back, prior, where=near)


def empty_box_error(
    back: np.ndarray, lo: np.ndarray, hi: np.ndarray, step: int
) -> EvidenceError | None:
    """Return the error for a mapped-back box (..., n, 2) that came out empty, or None."""
    empty = back[..., 0] > back[..., 1]
    if not empty.any():
        return None
    run, row = (int(i) for i in np.argwhere(empty.any(-1))[0])
    return EvidenceError(
        f"Step 5 of estimate {step}: g_inverse returned an empty box [{lo[run, row]}, "
        f"{hi[run, row]}] for a fused focal element of positive mass (run {run}); "
        "g_inverse(lo, hi, x_lo, x_hi) must return the states in [x_lo, x_hi] whose "
        "image meets [lo, hi], and the predicted box always holds some"
    )


def map_back(
    maps: ModelMaps, fused: Boxes, prior_lo: np.ndarray, prior_hi: np.ndarray, step: int
) -> Boxes:
    """Step 5: map each fused box back by g⁻¹ within its predicted box.

    Placeholders (mass 0) take the predicted box so that every box stays finite.

    g⁻¹(g(P)) is P up to rounding, but dependence is found by *exact* equality with the
    predicted boxes (eq. A3): a bound within :data:`SNAP_RTOL` of its predicted box's bound
    is set to it, so that rounding in g and g⁻¹ does not decide what is common.
    """
    lo, hi = maps.model.inverse()(fused.lo, fused.hi, prior_lo, prior_hi)
    back = _pairs(np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))
    live = fused.mass > 0
    snap_to_prior(back, _pairs(prior_lo, prior_hi), None if live.all() else live)
    error = empty_box_error(back, lo, hi, step)
    if error is not None:
        raise error
    return Boxes(back[..., 0], back[..., 1], fused.mass)


class _MonotoneImage:
    """The image of boxes through a function declared monotone with one row of signs.

    Prop. 2: the end points are chosen by the signs, the centre is evaluated in the same
    call and the values are kept for the check (:meth:`check`). Points and values have the
    layout (R, 3, B, dim): v_min, v_max, centre of each of B boxes.
    """

    def __init__(self, signs: np.ndarray, what: str, values: np.ndarray) -> None:
        self.signs = signs
        self.increasing = min(signs.tolist()) > 0  # tiny: plain Python is faster
        self.what = what
        self.values = values  # (R, T, 3, B, m): every step's f(v_min), f(v_max), f(centre)

    def points(self, lo: np.ndarray, hi: np.ndarray, out: np.ndarray) -> np.ndarray:
        """v_min, v_max and the centre of boxes (R, B, n) into ``out`` (R, 3, B, n)."""
        inc = self.signs > 0
        np.copyto(out[:, 0], np.where(inc, lo, hi))
        np.copyto(out[:, 1], np.where(inc, hi, lo))
        np.add(lo, hi, out=out[:, 2])
        out[:, 2] *= 0.5
        return out

    def keep(self, t: int, values: np.ndarray) -> np.ndarray:
        """Store step t's values (R, 3, B, m) (or (R, 3, B) for a scalar function)."""
        kept = self.values[:, t]
        kept[...] = values if values.ndim == kept.ndim else values[..., None]
        return kept

    def check(self, steps: int) -> None:
        """NotMonotoneError when a centre value left [f(v_min), f(v_max)] in steps < t."""
        values = self.values[:, 1:steps]
        out_lo, out_hi, centre = values[:, :, 0], values[:, :, 1], values[:, :, 2]
        with np.errstate(invalid="ignore"):
            slack = CHECK_RTOL * np.abs(centre)
            bad = (centre < out_lo - slack) | (centre > out_hi + slack)
        if bad.any():
            run, step, box, out = (int(i) for i in np.argwhere(bad)[0])
            where = (run, step, box, out)
            raise NotMonotoneError(
                f"{self.what} was declared monotone with signs {self.signs.tolist()} (Prop. 2) "
                f"but is not, at estimate {step + 2} (run {run}, box {box}, output {out}): "
                f"{self.what}(v_min) = {out_lo[where]:.6g}, {self.what}(v_max) = "
                f"{out_hi[where]:.6g}, {self.what}(centre) = {centre[where]:.6g} is not "
                f"between them ({int(bad.sum())} such case(s)); fix the signs, or use "
                "image_method='vertex' (no extremum inside) or 'subdivision' (any continuous "
                "function)"
            )


class StepArrays:
    """Buffers, constants and views of Steps 2–6 for the readings ``z`` (R, T, m) of R runs.

    ``step(t, est, u, bounds)`` writes x̂ of step t into ``est`` (R, T, n), the step's
    diagnostics into :attr:`diag` (8, R) and with ``bounds`` the hull of the final
    evidence into ``bounds`` (R, T, 2, n); see the module notes for the layout.
    """

    def __init__(
        self, flt: DependentEvidenceFilter, maps: ModelMaps, noise: NoiseEvidence, z: np.ndarray
    ) -> None:
        model = maps.model
        runs, steps, m = z.shape
        n = model.state_dim
        nv, nw = noise.v.lo.shape[1], noise.w.lo.shape[1]
        self.flt, self.maps, self.noise, self.runs = flt, maps, noise, runs
        self.f, self.g, self.g_inverse = model.f, model.g, model.inverse()
        self.n, self.m, self.nv, self.nw, self.np, self.n1 = n, m, nv, nw, nv * nv, nw * nv * nv
        self._constants(z)
        self._columns()
        self._step_buffers()
        self.compiled = flt._compiled(flt.kernel, "the paper's filter")
        if self.compiled:
            self.kernel_out = (np.empty((runs, 7)), np.empty((runs, 2, n)))
        else:
            self._kernels()

    def _constants(self, z: np.ndarray) -> None:
        """Step 1 laid out for the broadcasts of every step, and the images' checks."""
        runs, steps, _ = z.shape
        noise, maps, n, m, nv, np_ = self.noise, self.maps, self.n, self.m, self.nv, self.np
        v_lo, v_hi = noise.v.lo[0], noise.v.hi[0]  # (Nv, n)
        self.v = np.array([v_lo.T, v_hi.T])[:, None]  # (2, 1, n, Nv)
        self.rho = noise.prediction_mass[0]  # (Np,)
        # Step 4's products, row l·Np + i: ρ_i m_w(l), and the reading boxes z_t + W
        self.rho_w = np.multiply.outer(noise.w.mass[0], self.rho).reshape(-1)  # (N1,)
        self.rho_w_positive = least(self.rho_w) > 0.0
        w = np.array([noise.w.lo[0], noise.w.hi[0]])[:, :, None]  # (2, Nw, 1, m)
        self.zw = z.transpose(1, 0, 2)[:, None, :, None, None] + w[:, None]  # (T, 2, R, Nw, 1, m)

        def image(
            signs: np.ndarray | None, method: str, what: str, boxes: int, dim: int
        ) -> _MonotoneImage | None:
            if method != "monotone" or signs is None or signs.ndim != 1:
                return None
            return _MonotoneImage(signs, what, np.empty((runs, steps, 3, boxes, dim)))

        self.f_image = image(maps.f_signs, maps.f_method, "f", nv, n)
        self.g_image = image(maps.g_signs, maps.g_method, "g", np_, m)
        if self.f_image is not None:  # x̂ + V's end points and centre, without x̂
            inc = self.f_image.signs > 0
            self.f_offsets = np.array(
                [np.where(inc, v_lo, v_hi), np.where(inc, v_hi, v_lo), 0.5 * (v_lo + v_hi)]
            )  # (3, Nv, n)
            self.f_points = np.empty((runs, 3, nv, n))
        if self.g_image is not None and not self.g_image.increasing:
            self.g_points = np.empty((runs, 3, np_, n))

    def _columns(self) -> None:
        """Lay out the columns [Θ1, E1, E2, Θ2] of Step 6 and their views.

        Each box has lo, hi and centre; every step writes or reads the views.
        """
        runs, n, nv, nw, np_, n1 = self.runs, self.n, self.nv, self.nw, self.np, self.n1
        na, size = n1 + 1, n1 + np_ + 2
        self.boxes = boxes = np.zeros((runs, 3, n, size))
        e1, e2 = boxes[:, :2, :, 1:na], boxes[:, :2, :, na : na + np_]
        self.e1, self.e1_grid = e1, _view(e1, runs, 2, n, nw, np_)  # column 1 + l·Np + i
        self.e1_lo, self.e1_hi = e1[:, 0].transpose(0, 2, 1), e1[:, 1].transpose(0, 2, 1)
        self.e1_grid_lo = self.e1_grid[:, 0].transpose(0, 2, 3, 1)  # (R, Nw, Np, n)
        self.e1_grid_hi = self.e1_grid[:, 1].transpose(0, 2, 3, 1)
        self.e2, self.e2_ends = e2, (e2[:, 0], e2[:, 1])
        self.e2_lo, self.e2_hi = e2[:, 0].transpose(0, 2, 1), e2[:, 1].transpose(0, 2, 1)
        self.e2_by_origin = e2[:, :, :, None]  # (R, 2, n, 1, Np): the prior of E1's boxes
        self.e2_pairs = _view(e2, runs, 2, n, nv, nv).transpose(0, 1, 3, 2, 4)
        self.e2_points = boxes[:, :, :, na : na + np_].transpose(0, 1, 3, 2)  # (R, 3, Np, n)
        self.centre = boxes[:, 2, :, na : na + np_]
        self.theta1, self.theta2 = boxes[:, :2, :, 0], boxes[:, :2, :, size - 1]
        self.hull_views = (
            (e1[:, 0], e1[:, 1]),
            (e2[:, 0], e2[:, 1]),
            (self.theta1[:, 0], self.theta1[:, 1]),
            (self.theta2[:, 0], self.theta2[:, 1]),
        )

    def _step_buffers(self) -> None:
        """Buffers of Steps 4 and 5, and the masses of Step 6."""
        runs, n, m, nw, np_, n1 = self.runs, self.n, self.m, self.nw, self.np, self.n1
        na, size = n1 + 1, self.boxes.shape[-1]
        self.fused = np.empty((runs, 2, nw, np_, m))
        self.fused_lo, self.fused_hi = self.fused[:, 0], self.fused[:, 1]
        self.fused_1d = (self.fused_lo[..., 0], self.fused_hi[..., 0])  # m = 1
        self.nonempty4 = np.empty((runs, nw, np_), dtype=bool)
        self.nonempty_rows = _view(self.nonempty4, runs, n1)
        self.live = (
            _view(self.nonempty4, runs, n1)
            if self.rho_w_positive
            else np.empty((runs, n1), dtype=bool)
        )
        self.live_grid = _view(self.live, runs, 1, 1, nw, np_)
        # the predicted box of each of E1's boxes (R, Nw, Np, n), read-only views of E2
        self.prior = (
            np.broadcast_to(self.e2_lo[:, None], (runs, nw, np_, n)),
            np.broadcast_to(self.e2_hi[:, None], (runs, nw, np_, n)),
        )
        self.snap_signs = np.array([-SNAP_RTOL, SNAP_RTOL])[:, None, None]
        self.magnitude = np.empty((2, runs, n, np_))  # −lo, hi of E2 times SNAP_RTOL
        self.magnitude_out = self.magnitude.transpose(1, 0, 2, 3)
        self.snap_scale = np.empty((runs, n, np_))
        self.snap_scale_grid = self.snap_scale[:, None, :, None]
        self.distance = np.empty((runs, 2, n, nw, np_))
        self.near = np.empty((runs, 2, n, nw, np_), dtype=bool)
        # -- Step 6: masses [E1, E2] for the dependence, [Θ1, E1, E2, Θ2] for Dempster's rule
        self.masses = np.zeros((runs, 2, n1 + np_))
        self.masses[:, 1, n1:] = self.rho
        self.back_mass = self.masses[:, 0, :n1]
        self.ab_mass = np.empty((runs, size))
        self.e1_mass, self.e2_mass = self.ab_mass[:, 1:na], self.ab_mass[:, na : na + np_]
        self.diag = np.full((8, runs), np.nan)
        """1 − k4, 1 − k6, En'(E1), En'(E2), En'(E1, E2), D, R12, R21 of the last step (the
        masses kept by Dempster's rule in Steps 4 and 6 rather than K), (8, R)."""
        self.r12, self.r21 = self.diag[6, :, None], self.diag[7, :, None]
        self.kept4, self.kept6 = self.diag[0], self.diag[1]
        self.live_cols = self.live[:, None]

    def _kernels(self) -> None:
        """Step 6's kernels, bound to the columns, the masses and :attr:`diag`."""
        boxes, n1, np_ = self.boxes, self.n1, self.np
        na, size = n1 + 1, boxes.shape[-1]
        self.dependence = DependenceKernel(
            boxes[:, :2, :, 1 : size - 1],
            self.masses,
            n1,
            self.flt.mass_rule,
            self.diag[2:],
            self.ab_mass[:, :: size - 1],
            self.live,
        )
        # an empty box of E1 has a negative width: for n = 1 the smallest live one (placeholders
        # are predicted boxes), else any width of any box
        self.e1_least_width = (
            self.dependence.units[:, 0] if self.n == 1 else self.dependence.width[..., :n1]
        )
        self.products = ProductKernel(
            boxes[:, :2, :, :na],
            boxes[:, :2, :, na:],
            self.ab_mass[:, :na],
            self.ab_mass[:, na:],
            theta=(0, np_),
        )

    @staticmethod
    def bytes_per_run(n: int, n_pred: int, n_back: int) -> float:
        """Memory of one run's largest buffers (Step 6's products and equality matrix)."""
        na, nb = n_back + 1, n_pred + 1
        return float(8 * na * nb * (3 * n + 1) + (n_back + n_pred) * n_pred * (2 * n + 8))

    # -- Steps 2 and 3 -----------------------------------------------------------------------
    def _predict(self, t: int, xhat: np.ndarray, u: np.ndarray | None) -> None:
        """Step 2 into E2's columns: f(x̂ + V_i) + V_j, column i·N_v + j (eqs. 13, 16–19).

        x̂ (R, 1, 1, n).
        """
        fi = self.f_image
        if fi is not None:
            np.add(xhat, self.f_offsets, out=self.f_points)
            values = fi.keep(t, np.asarray(self.f(self.f_points, u), dtype=float))
            np.add(values[:, :2, :, :, None], self.v, out=self.e2_pairs)
        else:
            lo, hi = predict(
                self.maps,
                self.noise,
                xhat[:, 0, 0],
                with_input(self.f, None if u is None else u[:, 0, 0]),
            )
            np.copyto(self.e2_lo, lo)
            np.copyto(self.e2_hi, hi)
        if self.g_image is not None and self.g_image.increasing:
            np.add(*self.e2_ends, out=self.centre)
            np.multiply(self.centre, 0.5, out=self.centre)

    def _observe(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        """Step 3: g of every predicted box, (lo, hi) of shape (R, 1, Np, m)."""
        gi = self.g_image
        if gi is None:
            lo, hi = observe(self.maps, self.e2_lo, self.e2_hi)
            return lo[:, None], hi[:, None]
        points = (
            self.e2_points if gi.increasing else gi.points(self.e2_lo, self.e2_hi, self.g_points)
        )
        values = gi.keep(t, np.asarray(self.g(points), dtype=float))
        return values[:, 0, None], values[:, 1, None]

    def check_images(self, steps: int) -> None:
        """Run the deferred monotonicity checks of steps 2..``steps`` (Prop. 2)."""
        for image in (self.f_image, self.g_image):
            if image is not None:
                image.check(steps)

    def prediction(self) -> Boxes:
        """Step 2's evidence of the last step, (R, N_p, n)."""
        return Boxes(self.e2_lo, self.e2_hi, self.rho[None])

    # -- one step ----------------------------------------------------------------------------
    def step(
        self, t: int, est: np.ndarray, u: np.ndarray | None, bounds: np.ndarray | None
    ) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Run Steps 2–6 of estimate t + 1 from x̂ = est[:, t − 1].

        Writes est[:, t], with ``bounds`` the hull of the final evidence into bounds[:, t],
        and the diagnostics (1 − k4, 1 − k6, En'(E1), En'(E2), En'(E1, E2), D, R12, R21)
        into :attr:`diag`. ``u`` is the input of f, shaped to broadcast against
        (R, 3, N_v, n). Returns the masks of the runs where Steps 4 and 6 exist (None: all
        of them).
        """
        self._predict(t, est[:, t - 1, None, None], u)
        ok4 = self._fuse_observation(t, *self._observe(t))
        if ok4 is None:
            return None, self._fuse_dependent(t, est, bounds)
        with np.errstate(invalid="ignore", divide="ignore"):
            return ok4, self._fuse_dependent(t, est, bounds)

    def _fuse_observation(self, t: int, pz_lo: np.ndarray, pz_hi: np.ndarray) -> np.ndarray | None:
        """Step 4: Dempster's rule of g(E_{k+1|k}) and z + W (eq. 1), products l·N_p + i.

        E1's masses and k4 go into :attr:`diag`. Returns None, or the mask of the runs whose
        combination exists (runs in total conflict get masses 0).
        """
        zw = self.zw[t]
        np.maximum(pz_lo, zw[0], out=self.fused_lo)
        np.minimum(pz_hi, zw[1], out=self.fused_hi)
        if self.m == 1:
            np.less_equal(*self.fused_1d, out=self.nonempty4)
        else:
            np.logical_and.reduce(self.fused_lo <= self.fused_hi, axis=-1, out=self.nonempty4)
        back_mass, kept4 = self.back_mass, self.kept4
        np.multiply(self.rho_w, self.nonempty_rows, out=back_mass)
        if not self.rho_w_positive:
            np.greater(back_mass, 0.0, out=self.live)
        np.add.reduce(back_mass, axis=1, out=kept4)
        if least(kept4) > CONFLICT_TOLERANCE:
            np.divide(back_mass, per_run(kept4), out=back_mass)
            return None
        ok4 = kept4 > CONFLICT_TOLERANCE
        self._check_conflict(ok4, t, 4)
        back_mass /= np.where(ok4, kept4, 1.0)[:, None]
        back_mass[~ok4] = 0.0
        if self.rho_w_positive:  # the live mask is Step 4's: make it the masses'
            self.live &= ok4[:, None]
        else:
            np.greater(back_mass, 0.0, out=self.live)
        return ok4

    def _map_back(self, t: int) -> None:
        """Step 5 into E1's columns: g⁻¹ of each fused box within its predicted box.

        Bounds within :data:`SNAP_RTOL` are snapped to the predicted box's, placeholders
        (mass 0) set to the predicted box (as :func:`dstoolkit.filters.map_back`).
        """
        lo, hi = self.g_inverse(self.fused_lo, self.fused_hi, *self.prior)
        np.copyto(self.e1_grid_lo, lo)
        np.copyto(self.e1_grid_hi, hi)
        # snap_to_prior on the columns: |back − prior| ≤ SNAP_RTOL · max(|lo|, |hi|) of the
        # prior, = SNAP_RTOL · max(−lo, hi) since lo ≤ hi
        np.multiply(self.e2, self.snap_signs, out=self.magnitude_out)
        np.maximum(self.magnitude[0], self.magnitude[1], out=self.snap_scale)
        np.subtract(self.e1_grid, self.e2_by_origin, out=self.distance)
        np.abs(self.distance, out=self.distance)
        np.less_equal(self.distance, self.snap_scale_grid, out=self.near)
        np.greater_equal(self.near, self.live_grid, out=self.near)  # near, or not live
        np.copyto(self.e1_grid, self.e2_by_origin, where=self.near)

    def _fuse_dependent(
        self, t: int, est: np.ndarray, bounds: np.ndarray | None
    ) -> np.ndarray | None:
        """Run Steps 5 and 6 into est[:, t].

        Returns None or the mask of the runs whose combination exists.
        """
        self._map_back(t)
        if self.compiled:
            return self._fuse_compiled(t, est, bounds)
        self._dependence(t)
        self._discount()
        return self._combine(est[:, t], None if bounds is None else bounds[:, t])

    def _dependence(self, t: int) -> None:
        """Step 6, first half: the degree of dependence of E1 and E2, and R12, R21.

        E1 = Step 5's evidence and E2 = the prediction (Def. 5, eqs. A1–A6); the results go
        into :attr:`diag`.
        """
        valid = self.dependence.compute()
        if least(self.e1_least_width) < 0.0:
            self._empty_box(t)
        if not valid:
            self._coefficients_error(t)  # only mass_rule="m2" can do that

    def _discount(self) -> None:
        """Discount E1 and E2 by R12, R21 onto their hulls Θ1, Θ2 (eqs. 9–10, A7–A8).

        This sets the masses of columns [Θ1, E1, E2, Θ2] (Θ's were set by
        :meth:`_dependence`) and the hulls of the live boxes.
        """
        np.multiply(self.back_mass, self.r12, out=self.e1_mass)
        np.multiply(self.rho, self.r21, out=self.e2_mass)
        (e1_lo, e1_hi), (e2_lo, e2_hi), (t1_lo, t1_hi), (t2_lo, t2_hi) = self.hull_views
        np.minimum.reduce(e1_lo, axis=-1, where=self.live_cols, initial=np.inf, out=t1_lo)
        np.maximum.reduce(e1_hi, axis=-1, where=self.live_cols, initial=-np.inf, out=t1_hi)
        np.minimum.reduce(e2_lo, axis=-1, out=t2_lo)
        np.maximum.reduce(e2_hi, axis=-1, out=t2_hi)

    def _combine(self, est: np.ndarray, bounds: np.ndarray | None) -> np.ndarray | None:
        """Step 6, second half: Dempster's rule (eq. 1) of the discounted E1 and E2.

        Its pignistic expectation (eq. 20) goes into ``est`` (R, n), 1 − k6 into
        :attr:`diag` and with ``bounds`` (R, 2, n) the hull of the combination; returns None
        or the mask of the runs whose combination exists.
        """
        products = self.products
        ok = products.combine(est, bounds)
        np.copyto(self.kept6, products.kept)
        return ok

    def _fuse_compiled(
        self, t: int, est: np.ndarray, bounds: np.ndarray | None
    ) -> np.ndarray | None:
        """Step 6 by the compiled kernel (``kernel="numba"``, extra ``speed``)."""
        if np.less(self.e1[:, 1], self.e1[:, 0]).any():
            self._empty_box(t)
        kernel_diag, hull = self.kernel_out
        ok = fuse_dependent(
            self.boxes,
            self.back_mass,
            self.rho,
            self.n1,
            self.flt.mass_rule,
            est[:, t],
            kernel_diag,
            hull,
        )
        self.diag[1:] = kernel_diag.T
        if self.diag[6:8].min() < 0.0:
            self._coefficients_error(t)
        if bounds is not None:
            bounds[:, t] = hull
        return None if ok.all() else ok

    def _empty_box(self, t: int) -> None:
        self.check_images(t + 1)
        error = empty_box_error(self.e1.transpose(0, 3, 2, 1), self.e1_lo, self.e1_hi, t + 1)
        assert error is not None  # a negative width is an empty box
        raise error

    def _coefficients_error(self, t: int) -> None:
        self.check_images(t + 1)
        diag = self.diag
        coefficient_error(diag[6], diag[7], diag[5], self.flt.mass_rule)

    def _check_conflict(self, ok: np.ndarray, t: int, step: int) -> None:
        if self.flt.on_conflict == "raise" and not ok.all():
            self.check_images(t + 1)
        self.flt._check_conflict(ok, t, step)
