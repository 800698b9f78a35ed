"""The array path of the paper's filter: Steps 2–6 for a block of runs, buffers allocated once.

A step works on arrays of 4–1,100 elements, so its cost is numpy's per-call overhead;
:class:`StepArrays` does each step in few, larger calls:

- everything constant over a run is computed once: the noise boxes laid out for each
  step's broadcasts, the product masses of Steps 2 and 4 (ρ_ij = m_v(i) m_v(j), ρ_ij m_w(l),
  eq. 16), the monotone end points of f's images (Prop. 2, eqs. 18–19), ``g_inverse``;
- every array of a step is a preallocated buffer written with ``out=``;
- boxes are stored as (..., n, 2) with (lo, hi) last, so that one call handles both ends;
- E1 = the mapped-back evidence (Step 5) and E2 = the prediction (Step 2) share one buffer
  ``[E1, Θ1, E2, Θ2]``: :func:`~dstoolkit.evidence._batch_kernels.dependence_rows` gets
  both energies (eq. A1) in one pass and m1(D), m2(D) of eq. A3 in one matrix product, and
  Step 6's operands, E1 and E2 discounted onto Θ1 and Θ2 (eqs. A7–A8), are its two halves
  (:func:`~dstoolkit.evidence.dempster_expectation` with reused buffers);
- the monotonicity checks of the images (Prop. 2) keep every step's values and run once
  per block, and before any other error is raised.

The kernels are those of :mod:`dstoolkit.evidence._batch_kernels`, and nothing depends on
the number of runs in a block, so a batch equals single runs exactly (tested).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from dstoolkit.errors import EvidenceError, NotMonotoneError
from dstoolkit.evidence._batch_kernels import (
    ProductWork,
    _coefficient_error,
    dempster_expectation,
    dependence_rows,
)
from dstoolkit.evidence._boxes import Boxes, hull
from dstoolkit.evidence._combination import CONFLICT_TOLERANCE
from dstoolkit.evidence._compiled import fuse_dependent
from dstoolkit.evidence._extension import CHECK_RTOL, image_boxes

if TYPE_CHECKING:
    from ._dependent import DependentEvidenceFilter, ModelMaps, NoiseEvidence

#: Relative distance below which a mapped-back bound is snapped to its predicted box (Step 5).
SNAP_RTOL = 1e-12


def _pairs(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Boxes (..., n) twice → (..., n, 2), (lo, hi) last."""
    return np.stack([lo, hi], axis=-1)


# -- Steps 2, 3, 5 on arrays (the object path calls them; StepArrays for other models) -----
def predict(maps: ModelMaps, noise: NoiseEvidence, xhat: np.ndarray,
            f_u: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
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
    """Step 5's last touch, in place on boxes (..., n, 2): a bound within
    :data:`SNAP_RTOL` · max(|lo|, |hi|) of its predicted box's is set to it, and boxes not
    ``live`` (mass 0; None: all live) take the predicted box. ``prior`` broadcasts."""
    scale = np.abs(prior).max(axis=-1, keepdims=True)
    scale *= SNAP_RTOL
    near = np.abs(back - prior) <= scale
    if live is not None:
        near |= ~live[..., None, None]
    np.copyto(back, prior, where=near)


def empty_box_error(back: np.ndarray, lo: np.ndarray, hi: np.ndarray, step: int
                    ) -> EvidenceError | None:
    """The error for a mapped-back box (..., n, 2) that came out empty, or None."""
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


def map_back(maps: ModelMaps, fused: Boxes, prior_lo: np.ndarray, prior_hi: np.ndarray,
             step: int) -> Boxes:
    """Step 5: g⁻¹ of each fused box within its predicted box; placeholders (mass 0) take
    the predicted box so that every box stays finite.

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
    """The image of boxes through a function declared monotone with one row of signs (Prop.
    2): the end points are chosen by the signs, the centre is evaluated in the same call and
    the values are kept for the check (:meth:`check`)."""

    def __init__(self, signs: np.ndarray, what: str, values: np.ndarray) -> None:
        self.signs = signs
        self.increasing = bool(np.all(signs > 0))
        self.what = what
        self.values = values  # (R, T, B, 3, m): every step's f(v_min), f(v_max), f(centre)

    def points(self, lo: np.ndarray, hi: np.ndarray, out: np.ndarray) -> np.ndarray:
        """v_min, v_max and the centre of boxes (R, B, n) into ``out`` (R, B, 3, n)."""
        if self.increasing:
            out[:, :, 0], out[:, :, 1] = lo, hi
        else:
            inc = self.signs > 0
            np.copyto(out[:, :, 0], np.where(inc, lo, hi))
            np.copyto(out[:, :, 1], np.where(inc, hi, lo))
        np.add(lo, hi, out=out[:, :, 2])
        out[:, :, 2] *= 0.5
        return out

    def keep(self, t: int, values: np.ndarray) -> np.ndarray:
        """Store step t's values (R, B, 3, m) (or (R, B, 3) for a scalar function)."""
        kept = self.values[:, t]
        kept[...] = values if values.ndim == kept.ndim else values[..., None]
        return kept

    def check(self, steps: int) -> None:
        """NotMonotoneError when a centre value left [f(v_min), f(v_max)] in steps < t."""
        values = self.values[:, 1:steps]
        out_lo, out_hi, centre = values[..., 0, :], values[..., 1, :], values[..., 2, :]
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
    """Buffers and constants of Steps 2–6 for ``runs`` runs of ``steps`` steps.

    ``step(t, est, z_t, f_u)`` writes x̂ of step t into ``est`` (R, T, n) and returns
    the step's diagnostics; see the module notes for the layout.
    """

    def __init__(self, flt: DependentEvidenceFilter, maps: ModelMaps, noise: NoiseEvidence,
                 runs: int, steps: int) -> None:
        model = maps.model
        n, m = model.state_dim, model.obs_dim
        nv, nw = noise.v.lo.shape[1], noise.w.lo.shape[1]
        np_, n1 = nv * nv, nv * nv * nw
        self.flt, self.maps, self.noise, self.runs = flt, maps, noise, runs
        self.g_inverse = model.inverse()
        self.n, self.m, self.nv, self.nw, self.np, self.n1 = n, m, nv, nw, np_, n1
        self.v = _pairs(noise.v.lo[0], noise.v.hi[0])  # (Nv, n, 2)
        self.w = _pairs(noise.w.lo[0], noise.w.hi[0])  # (Nw, m, 2)
        self.rho = noise.prediction_mass[0]  # (Np,)
        self.rho_w = np.multiply.outer(self.rho, noise.w.mass[0])  # (Np, Nw), Step 4
        self.rho_w_positive = bool(np.all(self.rho_w > 0))

        def image(signs: np.ndarray | None, method: str, what: str, boxes: int, dim: int
                  ) -> _MonotoneImage | None:
            if method != "monotone" or signs is None or signs.ndim != 1:
                return None
            return _MonotoneImage(signs, what, np.empty((runs, steps, boxes, 3, dim)))

        self.f_image = image(maps.f_signs, maps.f_method, "f", nv, n)
        self.g_image = image(maps.g_signs, maps.g_method, "g", np_, m)
        if self.f_image is not None:  # x̂ + V's end points and centre, without x̂
            inc = self.f_image.signs > 0
            v_lo, v_hi = noise.v.lo[0], noise.v.hi[0]
            self.f_offsets = np.stack([np.where(inc, v_lo, v_hi), np.where(inc, v_hi, v_lo),
                                       0.5 * (v_lo + v_hi)], axis=1)  # (Nv, 3, n)
            self.f_points = np.empty((runs, nv, 3, n))
        self.g_points = np.empty((runs, np_, 3, n))
        # E1 = mapped back (N1), Θ1, E2 = prediction (Np), Θ2: one buffer
        self.boxes = np.zeros((runs, n1 + np_ + 2, n, 2))
        self.back = self.boxes[:, :n1]
        self.back_by_origin = self.back.reshape(runs, np_, nw, n, 2)
        self.theta1 = self.boxes[:, n1]
        self.pred = self.boxes[:, n1 + 1:n1 + 1 + np_]
        self.theta2 = self.boxes[:, n1 + 1 + np_]
        self.a_boxes, self.b_boxes = self.boxes[:, :n1 + 1], self.boxes[:, n1 + 1:]
        # masses: row 0 = E1 (then Θ1 = 0), row 1 = E2 (Θ2 = 0) — for m1(D), m2(D)
        self.masses = np.zeros((runs, 2, n1 + np_ + 2))
        self.masses[:, 1, n1 + 1:n1 + 1 + np_] = self.rho
        self.back_mass = self.masses[:, 0, :n1]
        self.e2_rows = slice(n1 + 1, n1 + 1 + np_)
        self.prior = np.empty((runs, np_, nw, n, 2))
        self.zw = np.empty((runs, nw, m, 2))
        self.fused = np.empty((runs, np_, nw, m, 2))
        self.nonempty4 = np.empty((runs, np_, nw), dtype=bool)
        # Step 6: discounted masses, and the stack [nonempty, centres] of the products
        self.a_mass = np.empty((runs, n1 + 1))
        self.b_mass = np.empty((runs, np_ + 1))
        self.theta_mass = np.empty((runs, 2))
        self.compiled = flt.kernel == "numba"
        if self.compiled:
            self.kernel_out = (np.empty((runs, 7)), np.empty((runs, n)), np.empty((runs, n)))
        else:
            self.work = ProductWork.allocate(runs, n, n1 + 1, np_ + 1)

    # -- Steps 2 and 3 -----------------------------------------------------------------------
    def _predict(self, t: int, xhat: np.ndarray, f_u: Callable[[np.ndarray], np.ndarray]
                 ) -> None:
        """Step 2 into ``self.pred``: f(x̂ + V_i) + V_j, row i·N_v + j (eqs. 13, 16–19)."""
        runs, nv, n = self.runs, self.nv, self.n
        pred = self.pred.reshape(runs, nv, nv, n, 2)
        fi = self.f_image
        if fi is not None:
            np.add(xhat[:, None, None, :], self.f_offsets, out=self.f_points)
            values = fi.keep(t, np.asarray(f_u(self.f_points), dtype=float))
            ends = values[:, :, :2].swapaxes(-1, -2)  # (R, Nv, n, 2)
            np.add(ends[:, :, None], self.v, out=pred)
        else:
            lo, hi = predict(self.maps, self.noise, xhat, f_u)
            self.pred[..., 0], self.pred[..., 1] = lo, hi

    def _observe(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        """Step 3: g of every predicted box, (lo, hi) of shape (R, Np, m)."""
        lo, hi = self.pred[..., 0], self.pred[..., 1]
        gi = self.g_image
        if gi is None:
            return observe(self.maps, lo, hi)
        values = gi.keep(t, np.asarray(self.maps.model.g(gi.points(lo, hi, self.g_points)),
                                       dtype=float))
        return values[:, :, 0], values[:, :, 1]

    def check_images(self, steps: int) -> None:
        """The deferred monotonicity checks of steps 2..``steps`` (Prop. 2)."""
        for image in (self.f_image, self.g_image):
            if image is not None:
                image.check(steps)

    # -- one step ----------------------------------------------------------------------------
    def step(self, t: int, est: np.ndarray, z_t: np.ndarray,
             f_u: Callable[[np.ndarray], np.ndarray], diag: np.ndarray, bounds: bool
             ) -> tuple[np.ndarray, tuple[np.ndarray, tuple[np.ndarray, np.ndarray] | None]]:
        """Steps 2–6 of estimate t + 1 from x̂ = est[:, t − 1]; writes est[:, t] and the
        diagnostics (k4, k6, En'(E1), En'(E2), En'(E1, E2), D, R12, R21) into ``diag``
        (R, 8). Returns the masks of runs where Steps 4 and 6 exist, and with ``bounds``
        the hull of the final evidence.
        """
        runs, m = self.runs, self.m
        self._predict(t, est[:, t - 1], f_u)
        pz_lo, pz_hi = self._observe(t)
        # Step 4: Dempster's rule of g(E_{k+1|k}) and z + W, products i·N_w + l (eq. 1)
        zw, fused = self.zw, self.fused
        np.add(z_t[:, None, :, None], self.w, out=zw)
        np.maximum(pz_lo[:, :, None], zw[:, None, :, :, 0], out=fused[..., 0])
        np.minimum(pz_hi[:, :, None], zw[:, None, :, :, 1], out=fused[..., 1])
        nonempty = self.nonempty4
        if m == 1:
            np.less_equal(fused[..., 0, 0], fused[..., 0, 1], out=nonempty)
        else:
            np.logical_and.reduce(fused[..., 0] <= fused[..., 1], axis=-1, out=nonempty)
        back_mass = self.back_mass
        np.multiply(self.rho_w.reshape(1, -1), nonempty.reshape(runs, -1), out=back_mass)
        kept4 = np.add.reduce(back_mass, axis=1)
        ok4 = kept4 > CONFLICT_TOLERANCE
        all_ok4 = bool(ok4.all())
        np.subtract(1.0, kept4, out=diag[:, 0])
        if all_ok4:
            back_mass /= kept4[:, None]
        else:
            self._check_conflict(ok4, t, 4)
            back_mass /= np.where(ok4, kept4, 1.0)[:, None]
            back_mass[~ok4] = 0.0
        with np.errstate(invalid="ignore", divide="ignore") if not all_ok4 else _NO_CONTEXT:
            self._map_back(t)
            if self.compiled:
                result = self._fuse_compiled(t, est, diag, bounds)
            else:
                self._dependence(t, diag)
                result = self._combine(t, est, diag, bounds)
        return ok4, result

    def _fuse_compiled(self, t: int, est: np.ndarray, diag: np.ndarray, bounds: bool
                       ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
        """Step 6 by the compiled kernel (``kernel="numba"``, extra ``speed``)."""
        kernel_diag, hull_lo, hull_hi = self.kernel_out
        ok = fuse_dependent(self.boxes, self.back_mass, self.rho, self.n1, self.flt.mass_rule,
                            est[:, t], kernel_diag, (hull_lo, hull_hi))
        diag[:, 1:] = kernel_diag
        if diag[:, 6:8].min() < 0.0:
            self.check_images(t + 1)
            _coefficient_error(diag[:, 6], diag[:, 7], diag[:, 5], self.flt.mass_rule)
        return ok, (hull_lo.copy(), hull_hi.copy()) if bounds else None

    def _map_back(self, t: int) -> None:
        """Step 5 into ``self.back``: g⁻¹ of each fused box within its predicted box, bounds
        within :data:`SNAP_RTOL` snapped to the predicted box's, placeholders (mass 0) set to
        the predicted box (see :func:`dstoolkit.filters.map_back`)."""
        runs, n1, n = self.runs, self.n1, self.n
        prior, back = self.prior, self.back_by_origin
        np.copyto(prior, self.pred[:, :, None])
        fused = self.fused.reshape(runs, n1, self.m, 2)
        flat_prior = prior.reshape(runs, n1, n, 2)
        lo, hi = self.g_inverse(fused[..., 0], fused[..., 1], flat_prior[..., 0],
                                flat_prior[..., 1])
        self.back[..., 0], self.back[..., 1] = lo, hi
        # live = positive mass: the nonempty products of Step 4 unless a mass is 0
        live = self.nonempty4 if self.rho_w_positive else self.back_mass > 0
        snap_to_prior(back, self.pred[:, :, None], None if live.all() else live)
        error = empty_box_error(self.back, lo, hi, t + 1)
        if error is not None:
            self.check_images(t + 1)
            raise error

    def _dependence(self, t: int, diag: np.ndarray) -> None:
        """En'(E1), En'(E2), En'(E1, E2), D, R12, R21 into ``diag[:, 2:]`` (Def. 5, eqs.
        A1, A3–A6) by :func:`~dstoolkit.evidence._batch_kernels.dependence_rows` on the
        rows [E1, Θ1, E2, Θ2] (the Θ rows carry no mass yet)."""
        boxes = self.boxes
        dependence_rows(boxes[..., 0], boxes[..., 1], self.masses, self.e2_rows,
                        self.flt.mass_rule, diag[:, 2:])
        if diag[:, 6:8].min() < 0.0:
            self.check_images(t + 1)
            _coefficient_error(diag[:, 6], diag[:, 7], diag[:, 5], self.flt.mass_rule)

    def _combine(self, t: int, est: np.ndarray, diag: np.ndarray, bounds: bool
                 ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
        """Step 6: E1, E2 discounted onto their hulls Θ1, Θ2 by R12, R21 (eqs. A7–A8),
        Dempster's rule (eq. 1) and the pignistic expectation (eq. 20) into est[:, t], by
        :func:`~dstoolkit.evidence.dempster_expectation`; returns the mask of runs with
        K < 1 and with ``bounds`` the hull of the combination."""
        n1, np_ = self.n1, self.np
        r12, r21 = diag[:, 6], diag[:, 7]
        back, pred = self.back, self.pred
        for theta, part in ((self.theta1, Boxes(back[..., 0], back[..., 1], self.back_mass)),
                            (self.theta2, Boxes(pred[..., 0], pred[..., 1], self.rho[None]))):
            hull(part, out=(theta[..., 0], theta[..., 1]))
        a_mass, b_mass, theta_mass = self.a_mass, self.b_mass, self.theta_mass
        np.multiply(self.back_mass, r12[:, None], out=a_mass[:, :n1])
        np.multiply(self.rho, r21[:, None], out=b_mass[:, :np_])
        np.subtract(1.0, diag[:, 6:8], out=theta_mass)
        a_mass[:, n1], b_mass[:, np_] = theta_mass.T
        a, b = self.a_boxes, self.b_boxes
        est[:, t], diag[:, 1], ok, result = dempster_expectation(
            Boxes(a[..., 0], a[..., 1], a_mass), Boxes(b[..., 0], b[..., 1], b_mass), bounds,
            work=self.work, theta_last=True)
        return ok, result

    def _check_conflict(self, ok: np.ndarray, t: int, step: int) -> None:
        if self.flt.on_conflict == "raise" and not ok.all():
            self.check_images(t + 1)
        self.flt._check_conflict(ok, t, step)


class _NoContext:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *args: object) -> None:
        return None


_NO_CONTEXT = _NoContext()
