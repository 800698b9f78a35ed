"""The paper's filter: extension principle and dependent evidence fusion (§3.2, Steps 1–6).

For x_{k+1} = f(x_k, u_k) + v_k and g(x_k) = z_k + w_k (eq. 21, :class:`StateSpaceModel`):

1. noise evidence E_v, E_w from the triangular possibilities (eqs. 22–26);
2. state evidence x̂_k + V; prediction E_{k+1|k}: the image of the random relation
   (x̂_k + V) × V through F(x, v) = f(x, u_k) + v (eqs. 13–16; the noise enters twice);
3. observation prediction g(E_{k+1|k}), without observation noise;
4. observation evidence z_{k+1} + W, fused with step 3 by Dempster's rule (eq. 1);
5. mapped back through g⁻¹ (extension principle);
6. step 5 (E1) fused with step 2 (E2) by the combination of dependent evidence
   (eqs. A1–A8, Θ = hull of each), and x̂_{k+1} = the pignistic expectation (eq. 20).

With p cuts each noise evidence has p + 1 focal elements (Θ included): for p = 3 and a
scalar state, 4 state focal elements, 16 predicted, 64 after step 4 and 64 × 16 = 1024
products in step 6 before the discounting adds Θ. Nothing grows from step to step,
because each step restarts from the point estimate.

Two implementations share Steps 1–3 and 5 (:func:`predict`, :func:`observe`,
:func:`map_back`): the object path (``record=True``) merges equal focal elements (eq. 14)
and fuses with :mod:`dstoolkit.evidence`; the array path (``record=False`` and
:meth:`DependentEvidenceFilter.run_batch`) fuses with :mod:`dstoolkit.evidence`
without merging, vectorised over runs. Both give the same numbers (tested).

Choices the paper leaves open: ``mass_rule`` for m(D) in eq. A3; the start
x̂_1 (``"observation"``: g⁻¹(z_1) as the paper; ``"mean_corrected"``: g⁻¹(z_1 + E[w]);
or an explicit vector); p, ε and Θ of Step 1. Step 5 maps each fused box back within the
predicted box it came from, g⁻¹(g(P_i) ∩ Z_j) ∩ P_i: for an invertible g that is the
paper's g⁻¹ exactly (g⁻¹(g(P_i) ∩ Z_j) ⊆ P_i), and it keeps non-injective g usable;
bounds within a rounding error of P_i's are snapped to them (:func:`map_back`), since the
dependence of Step 6 rests on exact equality of focal elements (eq. A3).
Total conflict (K = 1): ``on_conflict="raise"`` (default) raises TotalConflictError naming
the step; ``"predict"`` takes the prediction as that step's final evidence (and its
estimate), flagged in ``diagnostics["fallback"]``.
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass
from typing import Any, ClassVar, Literal, overload

import numpy as np

from dstoolkit.errors import EvidenceError, TotalConflictError
from dstoolkit.evidence import _batch_kernels as bk
from dstoolkit.evidence._batch_kernels import Boxes
from dstoolkit.evidence._combination import MASS_RULES, MassRule, conflict, decorrelate, dempster
from dstoolkit.evidence._extension import (
    IMAGE_METHODS,
    ImageMethod,
    image_boxes,
    parse_signs,
    resolve_method,
    state_signs,
)
from dstoolkit.evidence._intervals import IntervalEvidence

from ._model import FilterResult, StateSpaceModel, batch_readings, step_input, with_input

StartRule = Literal["observation", "mean_corrected"]
ConflictPolicy = Literal["raise", "predict"]

#: The per-step diagnostics of a run (keys of ``FilterResult.diagnostics``), explained.
DIAGNOSTICS: dict[str, str] = {
    "conflict_step4": "K of Dempster's rule between observation prediction and observation",
    "conflict_step6": "K of Dempster's rule in the dependent combination (after discounting)",
    "energy_mapped_back": "En'(E1), E1 = step-5 evidence mapped back (eq. A1)",
    "energy_prediction": "En'(E2), E2 = step-2 prediction (eq. A1)",
    "joint_energy": "En'(E1, E2), energy of the intersection (eq. A3)",
    "dependence": "degree of dependence D (eq. A4)",
    "r12": "dependency coefficient R12 (eq. A5)",
    "r21": "dependency coefficient R21 (eq. A6)",
    "fallback": "1 where total conflict made the prediction the final evidence, else 0",
}
#: Relative distance below which a mapped-back bound is snapped to its predicted box (Step 5).
SNAP_RTOL = 1e-12
#: Focal-element counts per step that ``run(..., record=True)`` adds to the diagnostics.
COUNTS: tuple[str, ...] = (
    "n_state", "n_prediction", "n_observation_prediction", "n_observation", "n_fused",
    "n_mapped_back", "n_final", "n_products_step4", "n_products_step6",
)


@dataclass(frozen=True)
class NoiseEvidence:
    """Step 1: the evidence of v and w (eqs. 24–26) and their arrays with a run axis."""

    state: IntervalEvidence
    observation: IntervalEvidence
    v: Boxes
    w: Boxes
    prediction_mass: np.ndarray
    """Masses of the predicted boxes, ρ_{ij} = m_v(i)·m_v(j), shape (1, N_v²) (eq. 16)."""


@dataclass(frozen=True)
class ModelMaps:
    """What the filter needs from the model, parsed once: methods and signs of f and g."""

    model: StateSpaceModel
    f_method: str
    f_signs: np.ndarray | None
    g_method: str
    g_signs: np.ndarray | None


# -- Steps 2, 3, 5 on arrays (shared by both paths) --------------------------------------
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


def map_back(maps: ModelMaps, fused: Boxes, prior_lo: np.ndarray, prior_hi: np.ndarray,
             step: int) -> Boxes:
    """Step 5: g⁻¹ of each fused box within its predicted box; placeholders (mass 0) take
    the predicted box so that every box stays finite.

    g⁻¹(g(P)) is P up to rounding, but dependence is found by *exact* equality with the
    predicted boxes (eq. A3): a bound within :data:`SNAP_RTOL` of its predicted box's bound
    is set to it, so that rounding in g and g⁻¹ does not decide what is common.
    """
    lo, hi = maps.model.inverse()(fused.lo, fused.hi, prior_lo, prior_hi)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    scale = SNAP_RTOL * np.maximum(np.abs(prior_lo), np.abs(prior_hi))
    lo = np.where(np.abs(lo - prior_lo) <= scale, prior_lo, lo)
    hi = np.where(np.abs(hi - prior_hi) <= scale, prior_hi, hi)
    live = (fused.mass > 0)[..., None]
    empty = live & (lo > hi)
    if empty.any():
        run, row = (int(i) for i in np.argwhere(empty.any(-1))[0])
        raise EvidenceError(
            f"Step 5 of estimate {step}: g_inverse returned an empty box [{lo[run, row]}, "
            f"{hi[run, row]}] for a fused focal element of positive mass (run {run}); "
            "g_inverse(lo, hi, x_lo, x_hi) must return the states in [x_lo, x_hi] whose "
            "image meets [lo, hi], and the predicted box always holds some"
        )
    return Boxes(np.where(live, lo, prior_lo), np.where(live, hi, prior_hi), fused.mass)


@dataclass(frozen=True)
class DependentEvidenceFilter:
    """The dependent-evidence filter of Xu et al. (§3.2, Steps 1–6).

    Parameters
    ----------
    mass_rule
        m(D) in the energy of the intersection (eq. A3): ``"min"`` (default), ``"m1"``,
        ``"m2"``.
    start
        x̂_1: ``"observation"`` (g⁻¹(z_1), the paper), ``"mean_corrected"``
        (g⁻¹(z_1 + E[w])), or a state vector.
    p, epsilon, theta
        Step 1: number of α-cuts, discount rate ε, and Θ as ``(theta_v, theta_w)``, each
        None (mode ± 100σ) or one (lo, hi) pair per component.
    on_conflict
        Total conflict in Step 4 or 6: ``"raise"`` TotalConflictError (default) or
        ``"predict"``: the prediction becomes the final evidence of that step.
    image_method
        How images are computed: ``"auto"`` (monotone where the model declares every sign,
        else vertex), ``"vertex"``, ``"monotone"``, ``"subdivision"`` (see
        :func:`dstoolkit.evidence.image`).
    chunk_size
        Runs per vectorised block in :meth:`run_batch` (memory ∝ chunk × N1 × N2).
    """

    mass_rule: MassRule = "min"
    start: StartRule | Any = "observation"
    p: int = 3
    epsilon: float = 0.05
    theta: Any = None
    on_conflict: ConflictPolicy = "raise"
    image_method: ImageMethod = "auto"
    chunk_size: int = 64

    name: ClassVar[str] = "dependent-evidence"

    def __post_init__(self) -> None:
        if self.mass_rule not in MASS_RULES:
            raise EvidenceError(f"mass_rule must be one of {MASS_RULES}, got {self.mass_rule!r}")
        if isinstance(self.start, str) and self.start not in ("observation", "mean_corrected"):
            raise EvidenceError(
                f"start must be 'observation', 'mean_corrected' or a state vector, got "
                f"{self.start!r}"
            )
        if self.on_conflict not in ("raise", "predict"):
            raise EvidenceError(
                f"on_conflict must be 'raise' or 'predict', got {self.on_conflict!r}"
            )
        if self.image_method not in IMAGE_METHODS:
            raise EvidenceError(
                f"image_method must be one of {IMAGE_METHODS}, got {self.image_method!r}"
            )
        if int(self.chunk_size) < 1:
            raise EvidenceError(f"chunk_size must be a positive integer, got {self.chunk_size}")

    # -- Step 1 and model parsing ----------------------------------------------------------
    def noise_evidence(self, model: StateSpaceModel) -> NoiseEvidence:
        """Step 1: E_v and E_w from the model's bounded noises (eqs. 22–26, Tables 1–2)."""
        theta_v, theta_w = (None, None) if self.theta is None else self.theta
        ev = model.state_noise.evidence(self.p, self.epsilon, _theta(theta_v, model.state_dim))
        ew = model.obs_noise.evidence(self.p, self.epsilon, _theta(theta_w, model.obs_dim))
        v = Boxes(ev.boxes_lo[None], ev.boxes_hi[None], ev.mass[None])
        w = Boxes(ew.boxes_lo[None], ew.boxes_hi[None], ew.mass[None])
        return NoiseEvidence(ev, ew, v, w, np.multiply.outer(ev.mass, ev.mass).reshape(1, -1))

    def _maps(self, model: StateSpaceModel) -> ModelMaps:
        if model.g_inverse is None:
            raise EvidenceError(
                "the dependent-evidence filter maps evidence back through g⁻¹ (Step 5): give "
                "the model a g_inverse(lo, hi, x_lo, x_hi)"
            )
        f_signs = state_signs(model.f_monotone, model.state_dim)
        g_signs = parse_signs(model.g_monotone, model.state_dim)
        return ModelMaps(model, resolve_method(self.image_method, f_signs), f_signs,
                         resolve_method(self.image_method, g_signs), g_signs)

    def _start(self, model: StateSpaceModel, z1: np.ndarray) -> np.ndarray:
        """x̂_1 for every run, (R, n)."""
        runs, n = z1.shape[0], model.state_dim
        if not isinstance(self.start, str):
            x0 = np.asarray(self.start, dtype=float)
            if x0.shape not in ((n,), (runs, n)) and not (n == 1 and x0.ndim == 0):
                raise EvidenceError(f"start must be a state vector of length {n}, got {x0.shape}")
            return np.broadcast_to(x0.reshape(-1, n) if x0.ndim else x0, (runs, n)).copy()
        reading = z1 + (model.obs_noise.mean if self.start == "mean_corrected" else 0.0)
        point = reading[:, None]
        inf = np.full((runs, 1, n), np.inf)
        lo, hi = model.inverse()(point, point, -inf, inf)
        x = 0.5 * (np.asarray(lo, dtype=float) + np.asarray(hi, dtype=float))[:, 0]
        if not np.all(np.isfinite(x)):
            raise EvidenceError(
                f"start={self.start!r} needs g⁻¹ to pin the state down from z_1, but "
                "g_inverse returned an unbounded box (g is not injective); pass start= an "
                "initial state vector"
            )
        return x

    # -- the array path -------------------------------------------------------------------
    def _run_arrays(
        self, maps: ModelMaps, noise: NoiseEvidence, z: np.ndarray, inputs: np.ndarray | None,
        bounds: bool = True,
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, dict[str, np.ndarray]]:
        """Steps 2–6 for R runs at once (no merging); z (R, T, m). ``bounds`` also returns
        the hull of each final evidence."""
        runs, steps, _ = z.shape
        est = np.empty((runs, steps, maps.model.state_dim))
        lower, upper = (np.empty_like(est), np.empty_like(est)) if bounds else (None, None)
        est[:, 0] = self._start(maps.model, z[:, 0])
        if lower is not None and upper is not None:
            lower[:, 0] = upper[:, 0] = est[:, 0]
        rho, w, nw = noise.prediction_mass, noise.w, noise.w.lo.shape[1]
        rows: list[tuple[np.ndarray, ...]] = []
        for t in range(1, steps):
            f_u = with_input(maps.model.f, step_input(inputs, t))
            p_lo, p_hi = predict(maps, noise, est[:, t - 1], f_u)
            pred = Boxes(p_lo, p_hi, rho)
            pz_lo, pz_hi = observe(maps, p_lo, p_hi)
            zt = z[:, t, None]
            fused, k4, ok4 = bk.dempster(Boxes(pz_lo, pz_hi, rho),
                                         Boxes(zt + w.lo, zt + w.hi, w.mass))
            all_ok = bool(ok4.all())
            if not all_ok:
                self._check_conflict(ok4, t, 4)
            # runs in total conflict carry mass-0 placeholders: silence their 0/0 and 0·∞
            with nullcontext() if all_ok else np.errstate(invalid="ignore", divide="ignore"):
                back = map_back(maps, fused, p_lo.repeat(nw, axis=1), p_hi.repeat(nw, axis=1),
                                t + 1)
                dep = bk.dependence(back, pred, self.mass_rule)
                est[:, t], k6, ok6, hull = bk.dempster_expectation(
                    bk.discount_onto_hull(back, dep.r12), bk.discount_onto_hull(pred, dep.r21),
                    bounds)
                if hull is not None and lower is not None and upper is not None:
                    lower[:, t], upper[:, t] = hull
            ok = ok4 & ok6
            if not (all_ok and ok6.all()):
                self._check_conflict(ok6, t, 6)
                self._fall_back(ok, t, pred, est, lower, upper)
            rows.append((k4, k6, *dep, ~ok, ~ok4))
        return est, lower, upper, self._diagnostics(rows, runs)

    @staticmethod
    def _fall_back(ok: np.ndarray, t: int, pred: Boxes, est: np.ndarray,
                   lower: np.ndarray | None, upper: np.ndarray | None) -> None:
        """on_conflict="predict": the prediction is the final evidence of failed runs."""
        bad = ~ok
        est[bad, t] = bk.pignistic_expectation(pred)[bad]
        if lower is not None and upper is not None:
            p_lo, p_hi = bk.hull(pred)
            lower[bad, t], upper[bad, t] = p_lo[bad], p_hi[bad]

    @staticmethod
    def _diagnostics(rows: list[tuple[np.ndarray, ...]], runs: int) -> dict[str, np.ndarray]:
        """Per-step rows (diagnostics, then "Step 4 failed") → (R, T) arrays; NaN at step 1
        and, after Step 4, where Step 4 failed."""
        table = np.full((len(DIAGNOSTICS) + 1, runs, len(rows) + 1), np.nan)
        if rows:
            table[:, :, 1:] = np.array(rows, dtype=float).transpose(1, 2, 0)
            step4_failed = table[-1] > 0
            table[1:-2, step4_failed] = np.nan
        return dict(zip(DIAGNOSTICS, table[:-1], strict=True))

    def _check_conflict(self, ok: np.ndarray, t: int, step: int) -> None:
        if self.on_conflict == "raise" and not ok.all():
            run = int(np.flatnonzero(~ok)[0])
            raise TotalConflictError(
                f"total conflict (K = 1) in Step {step} of estimate {t + 1} (run {run}): "
                + ("the observation contradicts the prediction entirely" if step == 4 else
                   "the mapped-back evidence contradicts the prediction entirely")
                + "; widen the noise bounds, raise epsilon, or use on_conflict='predict' to "
                "keep the prediction at such steps"
            )

    # -- the object path (record=True) ------------------------------------------------------
    def _run_objects(
        self, maps: ModelMaps, noise: NoiseEvidence, z: np.ndarray, inputs: np.ndarray | None
    ) -> FilterResult:
        """Steps 2–6 on IntervalEvidence objects for one run (z shape (1, T, m))."""
        steps, n = z.shape[1], maps.model.state_dim
        est = np.empty((steps, n))
        lower, upper = np.empty_like(est), np.empty_like(est)
        diag = {key: np.full(steps, np.nan) for key in (*DIAGNOSTICS, *COUNTS)}
        est[0] = lower[0] = upper[0] = self._start(maps.model, z[:, 0])[0]
        record: list[dict[str, Any]] = [{"step": 1, "estimate": est[0].copy(),
                                         "start": self.start}]
        for t in range(1, steps):
            entry: dict[str, Any] = {"step": t + 1}
            state = noise.state.shift(est[t - 1])
            p_lo, p_hi = predict(maps, noise, est[t - 1][None],
                                 with_input(maps.model.f, step_input(inputs, t)))
            pred = IntervalEvidence(p_lo[0], p_hi[0], noise.prediction_mass[0])
            pz_lo, pz_hi = observe(maps, pred.boxes_lo[None], pred.boxes_hi[None])
            obs_pred = IntervalEvidence(pz_lo[0], pz_hi[0], pred.mass, merge=False)
            obs = noise.observation.shift(z[0, t])
            entry.update(state=state, prediction=pred, observation=obs,
                         observation_prediction=IntervalEvidence(pz_lo[0], pz_hi[0], pred.mass))
            diag["n_products_step4"][t] = len(obs_pred) * len(obs)
            diag["conflict_step4"][t] = conflict(obs_pred, obs)
            final = self._fuse_objects(maps, pred, obs_pred, obs, t, entry, diag)
            if final is None:
                final = pred
                diag["fallback"][t] = 1.0
            else:
                diag["fallback"][t] = 0.0
            est[t] = final.pignistic_expectation()
            lower[t], upper[t] = final.hull()
            entry.update(final=final, estimate=est[t].copy())
            for key, name in zip(COUNTS[:7], ("state", "prediction", "observation_prediction",
                                               "observation", "fused", "mapped_back", "final"),
                                 strict=True):
                diag[key][t] = len(entry[name]) if entry.get(name) is not None else np.nan
            record.append(entry)
        return FilterResult(self.name, est, lower, upper, record, diag)

    def _fuse_objects(self, maps: ModelMaps, pred: IntervalEvidence,
                      obs_pred: IntervalEvidence, obs: IntervalEvidence, t: int,
                      entry: dict[str, Any], diag: dict[str, np.ndarray]
                      ) -> IntervalEvidence | None:
        """Steps 4–6 with dstoolkit.evidence; None when total conflict falls back."""
        try:
            fused = dempster(obs_pred, obs, merge=False)
        except TotalConflictError:
            self._check_conflict(np.zeros(1, bool), t, 4)
            return None
        # the predicted box behind each kept product (rows i·N_w + j, as dempster keeps them)
        _, nonempty = obs_pred._intersect(obs)
        live = nonempty & (np.multiply.outer(obs_pred.mass, obs.mass).reshape(-1) > 0)
        origin = np.flatnonzero(live) // len(obs)
        back = map_back(maps, Boxes(fused.boxes_lo[None], fused.boxes_hi[None],
                                    fused.mass[None]),
                        pred.boxes_lo[origin][None], pred.boxes_hi[origin][None], t + 1)
        mapped = IntervalEvidence(back.lo[0], back.hi[0], back.mass[0])  # eq. 14 merges
        entry.update(fused=IntervalEvidence(fused.boxes_lo, fused.boxes_hi, fused.mass),
                     mapped_back=mapped)
        a2, b2, dep = decorrelate(mapped, pred, mass_rule=self.mass_rule)
        entry["dependence"] = dep
        for key, value in (("energy_mapped_back", dep.energy1), ("energy_prediction",
                           dep.energy2), ("joint_energy", dep.joint_energy),
                           ("dependence", dep.degree), ("r12", dep.r12), ("r21", dep.r21)):
            diag[key][t] = value
        diag["n_products_step6"][t] = len(mapped) * len(pred)
        diag["conflict_step6"][t] = conflict(a2, b2)
        try:
            return dempster(a2, b2)
        except TotalConflictError:
            self._check_conflict(np.zeros(1, bool), t, 6)
            return None

    # -- public API ---------------------------------------------------------------------------
    def run(self, model: StateSpaceModel, z: Any, inputs: Any = None, record: bool = False
            ) -> FilterResult:
        """Filter one sequence of readings z (T, m) or (T,) with inputs u_1..u_{T−1}.

        Returns estimates, the hull of each step's final evidence (lower/upper) and the
        diagnostics of :data:`DIAGNOSTICS` (NaN at step 1). ``record=True`` runs the
        object path and adds every step's evidence (``steps``: state, prediction,
        observation_prediction, observation, fused, mapped_back, final, dependence) and
        the focal-element counts of :data:`COUNTS`.

        Examples
        --------
        A random walk with |v| ≤ 0.1 read with |w| ≤ 0.5 (eq. 21):

        >>> from dstoolkit.filters import random_walk
        >>> result = DependentEvidenceFilter().run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
        >>> result.estimates[:, 0].round(3).tolist()
        [1.0, 1.02, 1.009, 1.017]
        >>> bool(result.lower[2, 0] < result.estimates[2, 0] < result.upper[2, 0])
        True
        """
        maps, noise = self._maps(model), self.noise_evidence(model)
        zz, uu = batch_readings(model, np.asarray(z, dtype=float)[None],
                                None if inputs is None else np.asarray(inputs, dtype=float)[None])
        if record:
            return self._run_objects(maps, noise, zz, uu)
        est, lower, upper, diag = self._run_arrays(maps, noise, zz, uu, bounds=True)
        assert lower is not None and upper is not None  # bounds=True returns them
        return FilterResult(self.name, est[0], lower[0], upper[0], None,
                            {key: value[0] for key, value in diag.items()})

    @overload
    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None, *,
                  return_result: Literal[False] = False) -> np.ndarray: ...

    @overload
    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None, *,
                  return_result: Literal[True]) -> FilterResult: ...

    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None, *,
                  return_result: bool = False) -> np.ndarray | FilterResult:
        """Filter many independent sequences Z (runs, T, m) or (runs, T) at once.

        ``inputs`` is (runs, T−1, ...) or None. Returns estimates (runs, T, n), equal to
        :meth:`run` on each sequence; ``return_result=True`` returns a FilterResult whose
        arrays carry the leading run axis.
        """
        maps, noise = self._maps(model), self.noise_evidence(model)
        zz, uu = batch_readings(model, Z, inputs)
        size = int(self.chunk_size)
        parts = [self._run_arrays(maps, noise, zz[i:i + size],
                                  None if uu is None else uu[i:i + size], return_result)
                 for i in range(0, zz.shape[0], size)]
        est = np.concatenate([part[0] for part in parts])
        if not return_result:
            return est
        return FilterResult(
            self.name, est, np.concatenate([part[1] for part in parts]),
            np.concatenate([part[2] for part in parts]), None,
            {key: np.concatenate([part[3][key] for part in parts]) for key in DIAGNOSTICS},
        )


def _theta(theta: Any, dim: int) -> np.ndarray | None:
    if theta is None:
        return None
    arr = np.asarray(theta, dtype=float)
    if arr.size != 2 * dim:
        raise EvidenceError(f"Θ needs one (lo, hi) pair per component ({dim}), got {theta!r}")
    return arr.reshape(dim, 2)


def run_dependent_filter(model: StateSpaceModel, z: Any, inputs: Any = None, *,
                         record: bool = False, **options: Any) -> FilterResult:
    """Shorthand for ``DependentEvidenceFilter(**options).run(model, z, inputs, record)``."""
    return DependentEvidenceFilter(**options).run(model, z, inputs, record)


__all__: list[str] = [
    "COUNTS", "DIAGNOSTICS", "DependentEvidenceFilter", "NoiseEvidence", "map_back",
    "observe", "predict", "run_dependent_filter",
]
