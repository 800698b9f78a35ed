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

Two implementations: the public step (:meth:`DependentEvidenceFilter.step`, which
``run(..., record=True)`` loops) runs Steps 2, 3 and 5 with :func:`predict`,
:func:`observe`, :func:`map_back`, merges equal focal elements (eq. 14) and fuses with
:mod:`dstoolkit.evidence`'s combination; ``run`` and ``run_batch`` run every step of a
block of runs on preallocated buffers (:class:`~dstoolkit.filters._dependent_arrays.
StepArrays`, the same Step 5 snapping) and fuse with the batch kernels without merging,
or with the optional compiled kernel (``kernel="numba"``). They give the same numbers to
rounding (tested).

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

import functools
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from dstoolkit.errors import EvidenceError, TotalConflictError
from dstoolkit.evidence import (
    IMAGE_METHODS,
    MASS_RULES,
    THETA_RULES,
    Boxes,
    ImageMethod,
    IntervalEvidence,
    MassRule,
    ThetaRule,
    conflict,
    decorrelate,
    dempster,
    product_sources,
)
from dstoolkit.evidence import boxes as bk
from dstoolkit.evidence.boxes import parse_signs, resolve_method, state_signs
from dstoolkit.utils.budget import check_memory
from dstoolkit.utils.checks import real_array

from ._base import Block, Filter, FilterState, KernelChoice
from ._dependent_arrays import StepArrays, map_back, observe, predict
from ._model import FilterResult, StateSpaceModel, at_step, own_state, with_input

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
#: Focal-element counts per step that ``run(..., record=True)`` adds to the diagnostics.
COUNTS: tuple[str, ...] = (
    "n_state",
    "n_prediction",
    "n_observation_prediction",
    "n_observation",
    "n_fused",
    "n_mapped_back",
    "n_final",
    "n_products_step4",
    "n_products_step6",
)


@dataclass(frozen=True)
class NoiseEvidence:
    """Step 1: the evidence of v and w (eqs. 24–26) and their arrays with a run axis.

    Parameters
    ----------
    state : IntervalEvidence
        E_v, the evidence of the state noise v.
    observation : IntervalEvidence
        E_w, the evidence of the observation noise w.
    v, w : Boxes
        The same as one-run arrays, boxes (1, N, n) and (1, N, m).
    prediction_mass : ndarray, shape (1, N_v²)
        The masses of the predicted boxes,
        ρ_ij = m_v(i)·m_v(j) (eq. 16).
    """

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


@dataclass(frozen=True)
class DependentState(FilterState):
    """The paper's filter's state: x̂_k, step k's final hull and Step 1's noise evidence.

    The hull of step k's final evidence is ``final`` (None at the start) and Step 1's noise
    evidence ``noise``, from the model's bounded noises; replace it with
    ``dataclasses.replace`` to step with other evidence. Each step restarts from the point
    estimate (Step 2), so nothing else passes on.

    Parameters
    ----------
    model : StateSpaceModel
        The model the filter runs on.
    k : int
        The step whose estimate this is (1 for the first reading).
    estimate : ndarray, shape (n,)
        x̂_k.
    lower, upper : ndarray, shape (n,)
        The hull of step k's final evidence (x̂_1 at the start).
    noise : NoiseEvidence
        Step 1's evidence of v and w (eqs. 24–26).
    final : IntervalEvidence or None
        Step k's final evidence; None at the start.
    """

    noise: NoiseEvidence
    final: IntervalEvidence | None = None


@dataclass(frozen=True)
class DependentRecord:
    """One step of the paper's filter (Steps 2–6).

    The fields named as the keys of :data:`DIAGNOSTICS` (``conflict_step4`` to
    ``fallback``) and of :data:`COUNTS` (``n_state`` to ``n_products_step6``) hold the
    step's numbers, as floats (NaN where a step has none, e.g. at the start).

    Parameters
    ----------
    step : int
        k + 1, counting the first reading as 1.
    estimate : ndarray, shape (n,)
        x̂_{k+1}, the pignistic expectation of ``final`` (eq. 20).
    state : IntervalEvidence or None
        x̂_k + E_v (Step 2); None at the start.
    prediction : IntervalEvidence or None
        E_{k+1|k}, the image of (x̂_k + V) × V (Step 2).
    observation_prediction : IntervalEvidence or None
        g(E_{k+1|k}) (Step 3).
    observation : IntervalEvidence or None
        z_{k+1} + E_w (Step 4).
    fused : IntervalEvidence or None
        Step 4's fusion by Dempster's rule; None where total
        conflict made the prediction final.
    mapped_back : IntervalEvidence or None
        Step 5's evidence mapped back through g⁻¹ (E1).
    final : IntervalEvidence or None
        Step 6's dependent combination (or the prediction
        after total conflict).
    dependence_terms : Dependence or None
        En′(E1), En′(E2), En′(E1, E2), D, R12 and R21 of Step 6
        (eqs. A1–A6).
    conflict_step4, conflict_step6 : float
        K of Dempster's rule in Steps 4 and 6 (eq. 1).
    energy_mapped_back, energy_prediction, joint_energy : float
        En′(E1), En′(E2) and En′(E1, E2) (eqs. A1, A3).
    dependence, r12, r21 : float
        D, R12 and R21 (eqs. A4–A6).
    fallback : float
        1 where total conflict made the prediction final, else 0.
    n_state, n_prediction, n_observation_prediction, n_observation : float
        The focal elements of Steps 2–4's evidence (:data:`COUNTS`).
    n_fused, n_mapped_back, n_final : float
        The focal elements of Steps 4–6's results.
    n_products_step4, n_products_step6 : float
        The products Dempster's rule forms in Steps 4 and 6.
    """

    step: int
    estimate: np.ndarray
    state: IntervalEvidence | None = None
    prediction: IntervalEvidence | None = None
    observation_prediction: IntervalEvidence | None = None
    observation: IntervalEvidence | None = None
    fused: IntervalEvidence | None = None
    mapped_back: IntervalEvidence | None = None
    final: IntervalEvidence | None = None
    dependence_terms: Any = None
    conflict_step4: float = np.nan
    conflict_step6: float = np.nan
    energy_mapped_back: float = np.nan
    energy_prediction: float = np.nan
    joint_energy: float = np.nan
    dependence: float = np.nan
    r12: float = np.nan
    r21: float = np.nan
    fallback: float = np.nan
    n_state: float = np.nan
    n_prediction: float = np.nan
    n_observation_prediction: float = np.nan
    n_observation: float = np.nan
    n_fused: float = np.nan
    n_mapped_back: float = np.nan
    n_final: float = np.nan
    n_products_step4: float = np.nan
    n_products_step6: float = np.nan


@dataclass(frozen=True)
class DependentEvidenceFilter(Filter[DependentState, DependentRecord]):
    """The dependent-evidence filter of Xu et al. (§3.2, Steps 1–6, eqs. 13–20, A1–A8).

    Parameters
    ----------
    mass_rule : {"min", "m1", "m2"}
        m(D) in the energy of the intersection (eq. A3, which
        leaves it open).
    start : {"observation", "mean_corrected"} or array_like, shape (n,) or (R, n)
        x̂_1:
        g⁻¹(z_1) as the paper, g⁻¹(z_1 + E[w]), or a state vector (one per run).
    p : int
        Step 1's number of α-cuts (eqs. 24–25).
    epsilon : float
        Step 1's discount rate ε (eq. 26).
    theta : tuple, optional
        Step 1's frames Θ as ``(theta_v, theta_w)``, each None (mode
        ± 100σ) or one
        (lo, hi) pair per component.
    on_conflict : {"raise", "predict"}
        Total conflict in Step 4 or 6: raise
        :class:`~dstoolkit.errors.TotalConflictError`
        (default), or take the prediction as the step's final evidence (``fallback`` = 1).
    image_method : {"auto", "vertex", "monotone", "subdivision"}
        How images are computed (see
        :func:`dstoolkit.evidence.image`): ``"auto"`` is
        monotone where the model declares every sign, else vertex (Prop. 1).
    chunk_size : int
        Runs per vectorised block in :meth:`Filter.run_batch` (memory ∝ chunk × N1 × N2).
    kernel : {"numpy", "numba", "auto"}
        Step 6 of the vectorised path: numpy, or a
        compiled kernel (extra ``speed``; the
        same numbers to rounding); ``"auto"`` takes numba when it is installed.
    energy_theta : {"paper", "left_out"}
        The energy En′ of Step 6's dependence (eqs. A1–A6):
        ``"paper"`` counts every focal element, the frame Θ included, as the paper defines
        it; ``"left_out"`` leaves Θ out, as on finite frames (see
        :func:`dstoolkit.evidence.energy`). With ``"left_out"`` every path runs the
        reference step on evidence objects (the vectorised kernels implement the paper's
        energy only), which is slower.

    See Also
    --------
    NassreddineFilter : propagates the posterior instead of restarting from x̂_k.
    dstoolkit.evidence.combine_dependent : Step 6's combination on its own.

    References
    ----------
    Xu, Li, Li, Zhou, Sensors 17(4):924 (2017), §3.2 and Appendix A.

    Examples
    --------
    A random walk with |v| ≤ 0.1 read with |w| ≤ 0.5 (eq. 21):

    >>> from dstoolkit.filters import DependentEvidenceFilter, random_walk
    >>> result = DependentEvidenceFilter().run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9, 1.1])
    >>> result.estimates[:, 0].round(3).tolist()
    [1.0, 1.02, 1.009, 1.017]
    >>> bool(result.lower[2, 0] < result.estimates[2, 0] < result.upper[2, 0])
    True
    """

    mass_rule: MassRule = "min"
    start: StartRule | Any = "observation"
    p: int = 3
    epsilon: float = 0.05
    theta: Any = None
    on_conflict: ConflictPolicy = "raise"
    image_method: ImageMethod = "auto"
    chunk_size: int = 64
    kernel: KernelChoice = "numpy"
    energy_theta: ThetaRule = "paper"

    name: ClassVar[str] = "dependent_evidence"
    COMPILED_KERNEL: ClassVar[bool] = True
    DIAGNOSTICS: ClassVar[dict[str, str]] = DIAGNOSTICS
    RECORDED: ClassVar[tuple[str, ...]] = COUNTS
    _budget_advice: ClassVar[str] = "use fewer α-cuts p"

    def __post_init__(self) -> None:
        self._policy(self.mass_rule, MASS_RULES, "mass_rule")
        self._policy(self.on_conflict, ("raise", "predict"), "on_conflict")
        self._policy(self.image_method, IMAGE_METHODS, "image_method")
        if isinstance(self.start, str):
            self._policy(self.start, ("observation", "mean_corrected"), "start", "a state vector")
        else:
            start = np.array(real_array(self.start, "start", ndim=(0, 1, 2), error=EvidenceError))
            start.flags.writeable = False  # a copy: later edits of the caller's array
            object.__setattr__(self, "start", start)  # change nothing here
        self._cuts(self.p, self.epsilon)
        self._whole("p", low=1)
        self._own("epsilon", float(self.epsilon))
        self._own_frames()
        self._whole("chunk_size", low=1, high=10**6)
        self._compiled(self.kernel, "the paper's filter")
        self._policy(self.energy_theta, THETA_RULES, "energy_theta")

    def _check_model(self, model: StateSpaceModel) -> None:
        self._maps(model)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int = 0) -> float:
        """Memory of one run's Step 6 buffers (the largest arrays), bytes."""
        noise = self.noise_evidence(model)
        n_pred = noise.prediction_mass.shape[1]
        return StepArrays.bytes_per_run(
            noise.v.lo.shape[-1], n_pred, n_pred * noise.w.mass.shape[1]
        )

    def _chunk_cap(self, model: StateSpaceModel, n_steps: int) -> int | None:
        return int(self.chunk_size)

    # -- Step 1 and model parsing ----------------------------------------------------------
    def noise_evidence(self, model: StateSpaceModel) -> NoiseEvidence:
        """Step 1: E_v and E_w from the model's bounded noises (eqs. 22–26, Tables 1–2).

        Computed once per noise and setting (cached): a run reuses it at every step, and
        runs of the same model reuse it too.

        Parameters
        ----------
        model : StateSpaceModel
            The model whose bounded noises v and w are turned into
            evidence with the filter's ``p``, ``epsilon`` and ``theta``.

        Returns
        -------
        NoiseEvidence
            E_v, E_w and their arrays.

        Examples
        --------
        >>> from dstoolkit.filters import DependentEvidenceFilter, random_walk
        >>> noise = DependentEvidenceFilter(p=3).noise_evidence(random_walk(0.1, 0.5))
        >>> len(noise.state), noise.prediction_mass.shape
        (4, (1, 16))
        """
        return _noise_evidence(_Step1(self, model))

    def _maps(self, model: StateSpaceModel) -> ModelMaps:
        if model.g_inverse is None:
            raise EvidenceError(
                "the dependent-evidence filter maps evidence back through g⁻¹ (Step 5): give "
                "the model a g_inverse(lo, hi, x_lo, x_hi)"
            )
        f_signs = state_signs(model.f_monotone, model.state_dim)
        g_signs = parse_signs(model.g_monotone, model.state_dim)
        return ModelMaps(
            model,
            resolve_method(self.image_method, f_signs),
            f_signs,
            resolve_method(self.image_method, g_signs),
            g_signs,
        )

    # -- the public step: Steps 2-6 on IntervalEvidence objects ------------------------------
    def initialize(self, model: StateSpaceModel, z1: Any) -> DependentState:
        """x̂_1 by the ``start`` rule.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading z_1.

        Returns
        -------
        DependentState
            The state of step 1; ``estimate`` is x̂_1, shape (n,).

        See Also
        --------
        Filter.initialize : the interface every filter shares.
        """
        self._check_model(model)
        z, _ = self._one(model, z1, transition=False)
        model = self._guarded(model)
        x = self._start(model, z)[0]
        return DependentState(model, 1, x, x, x, self.noise_evidence(model))

    def step(
        self, state: DependentState, z: Any, u: Any = None
    ) -> tuple[DependentState, DependentRecord]:
        """Run Steps 2–6 from x̂_k with the reading z_{k+1}.

        Runs the reference path on :class:`~dstoolkit.evidence.IntervalEvidence` (equal
        focal elements merged, eq. 14), which records every evidence of the step.

        Parameters
        ----------
        state : DependentState
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the transition
            k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state : DependentState
            The state of step k + 1; ``estimate`` is x̂_{k+1}, shape (n,).
        record : DependentRecord
            What the step computed.

        See Also
        --------
        Filter.step : the interface every filter shares.
        """
        own_state(state, DependentState, self._title)
        model, noise = state.model, state.noise
        maps = self._maps(model)
        zz, uu = self._one(model, z, u)
        t = state.k  # the step's index counting from 0, as in the messages of run()
        at_step(model, t)
        x = state.estimate
        entry: dict[str, Any] = {"step": t + 1, "state": noise.state.shift(x)}
        # Step 2: (x̂_k + V) × V through F(x, v) = f(x, u_k) + v (eqs. 13–16), equal boxes
        # merged (eq. 14)
        p_lo, p_hi = predict(maps, noise, x[None], with_input(model.f, uu))
        pred = IntervalEvidence(p_lo[0], p_hi[0], noise.prediction_mass[0])
        # Step 3: g(E_{k+1|k}), one box per predicted box (kept unmerged: Step 5 maps each
        # back within its own predicted box)
        pz_lo, pz_hi = observe(maps, pred.boxes_lo[None], pred.boxes_hi[None])
        obs_pred = IntervalEvidence(pz_lo[0], pz_hi[0], pred.mass, merge=False)
        # Step 4: the reading's evidence z_{k+1} + W, fused by Dempster's rule (eq. 1)
        obs = noise.observation.shift(zz[0])
        entry.update(
            prediction=pred,
            observation=obs,
            observation_prediction=IntervalEvidence(pz_lo[0], pz_hi[0], pred.mass),
            n_products_step4=float(len(obs_pred) * len(obs)),
            conflict_step4=conflict(obs_pred, obs),
        )
        final = None
        try:
            fused = dempster(obs_pred, obs, merge=False)
        except TotalConflictError:
            self._check_conflict(np.zeros(1, bool), t, 4)
        else:
            # Step 5: each product back through g⁻¹ within the predicted box it came from
            origin, _ = product_sources(obs_pred, obs)
            back = map_back(
                maps,
                Boxes(fused.boxes_lo[None], fused.boxes_hi[None], fused.mass[None]),
                pred.boxes_lo[origin][None],
                pred.boxes_hi[origin][None],
                t + 1,
            )
            mapped = IntervalEvidence(back.lo[0], back.hi[0], back.mass[0])  # eq. 14 merges
            # Step 6: discount E1 (mapped back) and E2 (the prediction) by their dependence
            # (eqs. A1–A8), then Dempster's rule
            a2, b2, dep = decorrelate(
                mapped, pred, mass_rule=self.mass_rule, theta=self.energy_theta
            )
            entry.update(
                fused=IntervalEvidence(fused.boxes_lo, fused.boxes_hi, fused.mass),
                mapped_back=mapped,
                dependence_terms=dep,
                energy_mapped_back=dep.energy1,
                energy_prediction=dep.energy2,
                joint_energy=dep.joint_energy,
                dependence=dep.degree,
                r12=dep.r12,
                r21=dep.r21,
                n_products_step6=float(len(mapped) * len(pred)),
                conflict_step6=conflict(a2, b2),
            )
            try:
                final = dempster(a2, b2)
            except TotalConflictError:
                self._check_conflict(np.zeros(1, bool), t, 6)
        # total conflict with on_conflict="predict": the prediction is the step's evidence
        entry["fallback"] = 0.0 if final is not None else 1.0
        final = pred if final is None else final
        # x̂_{k+1}: the pignistic expectation (eq. 20)
        est = np.atleast_1d(np.asarray(final.pignistic_expectation(), dtype=float))
        lower, upper = final.hull()
        entry.update(final=final, estimate=est)
        for key, name in zip(
            COUNTS[:7],
            (
                "state",
                "prediction",
                "observation_prediction",
                "observation",
                "fused",
                "mapped_back",
                "final",
            ),
            strict=True,
        ):
            entry[key] = float(len(entry[name])) if entry.get(name) is not None else np.nan
        record = DependentRecord(**entry)
        return DependentState(
            model,
            t + 1,
            est,
            np.asarray(lower, dtype=float).reshape(-1),
            np.asarray(upper, dtype=float).reshape(-1),
            noise,
            final,
        ), record

    def _start_record(self, state: DependentState) -> DependentRecord:
        return DependentRecord(1, state.estimate)

    def _engine_by_steps(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        """Run the recursion of R runs by the reference :meth:`step`, run after run.

        This serves the options the vectorised kernels do not implement.
        """
        n_runs, n_steps, _ = Z.shape
        n, noise = model.state_dim, self.noise_evidence(model)
        est, lower, upper = (np.empty((n_runs, n_steps, n)) for _ in range(3))
        keys = tuple(DIAGNOSTICS)
        diag = {key: np.full((n_runs, n_steps), np.nan) for key in keys}
        starts = self._start(model, Z[:, 0], runs)
        for r in range(n_runs):
            state = DependentState(model, 1, starts[r], starts[r], starts[r], noise)
            est[r, 0] = lower[r, 0] = upper[r, 0] = starts[r]
            for k in range(1, n_steps):
                state, record = self.step(state, Z[r, k], None if U is None else U[r, k - 1])
                est[r, k], lower[r, k], upper[r, k] = state.estimate, state.lower, state.upper
                for key in keys:
                    diag[key][r, k] = getattr(record, key)
        return Block(est, lower, upper, diag)

    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        if self.energy_theta != "paper":
            return self._engine_by_steps(model, Z, U, runs)
        est, lower, upper, diag = self._run_arrays(
            self._maps(model), self.noise_evidence(model), Z, U, runs
        )
        assert lower is not None and upper is not None  # bounds=True returns them
        return Block(est, lower, upper, diag)

    def _check_runs(self, runs: int) -> None:
        """Check that a start per run, (R, n), has one row for each run of the batch."""
        if (
            not isinstance(self.start, str)
            and np.ndim(self.start) == 2
            and np.shape(self.start)[0] != runs
        ):
            raise EvidenceError(
                f"start gives x̂_1 for {np.shape(self.start)[0]} runs, but the batch has "
                f"{runs}; give one row per run, or one state vector for all"
            )

    def _start(
        self, model: StateSpaceModel, z1: np.ndarray, runs: np.ndarray | None = None
    ) -> np.ndarray:
        """Return x̂_1 for every run, (R, n).

        ``runs`` are the runs' indices in the batch (None for a single run), which pick
        their rows of a start given per run.
        """
        n = model.state_dim
        if not isinstance(self.start, str):
            x0 = np.asarray(self.start, dtype=float)
            if x0.ndim == 2 and x0.shape[1] == n and (runs is not None or len(x0) == 1):
                return x0[np.zeros(1, dtype=np.intp) if runs is None else runs].copy()
            if x0.shape != (n,) and not (n == 1 and x0.ndim == 0):
                raise EvidenceError(
                    f"start must be a state vector of length {n}"
                    + ("" if runs is None else f" or one per run, ({len(runs)}, {n})")
                    + f", got shape {x0.shape}"
                )
            return np.broadcast_to(x0.reshape(n), (z1.shape[0], n)).copy()
        runs_here = z1.shape[0]
        reading = z1 + (model.obs_noise.mean if self.start == "mean_corrected" else 0.0)
        point = reading[:, None]
        inf = np.full((runs_here, 1, n), np.inf)
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
        self,
        maps: ModelMaps,
        noise: NoiseEvidence,
        z: np.ndarray,
        inputs: np.ndarray | None,
        run_ids: np.ndarray | None = None,
        bounds: bool = True,
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, dict[str, np.ndarray]]:
        """Run Steps 2–6 for R runs at once (no merging).

        z (R, T, m), ``run_ids`` the runs' indices in the batch. ``bounds`` also returns the
        hull of each final evidence.
        """
        runs, steps, _ = z.shape
        est = np.empty((runs, steps, maps.model.state_dim))
        hulls = np.empty((runs, steps, 2, est.shape[2])) if bounds else None
        est[:, 0] = self._start(maps.model, z[:, 0], run_ids)
        if hulls is not None:
            hulls[:, 0] = est[:, 0, None]
        arrays = StepArrays(self, maps, noise, z)
        table = np.full((steps, len(DIAGNOSTICS), runs), np.nan)  # step first: one copy a step
        table[1:, 8] = 0.0
        # u_k shaped as with_input shapes it for f's points (R, 3, N_v, n)
        u = None if inputs is None else inputs.reshape(runs, steps - 1, 1, 1, -1)
        for t in range(1, steps):
            at_step(maps.model, t)
            ok4, ok6 = arrays.step(t, est, None if u is None else u[:, t - 1], hulls)
            table[t, :8] = arrays.diag
            if ok4 is None and ok6 is None:
                continue
            ok = np.ones(runs, dtype=bool) if ok4 is None else ok4.copy()
            if ok6 is not None:
                arrays._check_conflict(ok6, t, 6)
                ok &= ok6
            self._fall_back(ok, t, arrays.prediction(), est, hulls)
            table[t, 8] = ~ok
            if ok4 is not None:
                table[t, 1:8, ~ok4] = np.nan
        arrays.check_images(steps)
        np.subtract(1.0, table[:, :2], out=table[:, :2])  # K = 1 − the mass kept (eq. 1)
        lower, upper = (None, None) if hulls is None else (hulls[:, :, 0], hulls[:, :, 1])
        diagnostics = np.ascontiguousarray(table.transpose(1, 2, 0))  # (keys, R, T)
        return est, lower, upper, dict(zip(DIAGNOSTICS, diagnostics, strict=True))

    @staticmethod
    def _fall_back(
        ok: np.ndarray, t: int, pred: Boxes, est: np.ndarray, hulls: np.ndarray | None
    ) -> None:
        """on_conflict="predict": the prediction is the final evidence of failed runs."""
        bad = ~ok
        est[bad, t] = bk.pignistic_expectation(pred)[bad]
        if hulls is not None:
            p_lo, p_hi = bk.hull(pred)
            hulls[bad, t, 0], hulls[bad, t, 1] = p_lo[bad], p_hi[bad]

    def _check_conflict(self, ok: np.ndarray, t: int, step: int) -> None:
        if self.on_conflict == "raise" and not ok.all():
            run = int(np.flatnonzero(~ok)[0])
            raise TotalConflictError(
                f"total conflict (K = 1) in Step {step} of estimate {t + 1} (run {run}): "
                + (
                    "the observation contradicts the prediction entirely"
                    if step == 4
                    else "the mapped-back evidence contradicts the prediction entirely"
                )
                + "; widen the noise bounds, raise epsilon, or use on_conflict='predict' to "
                "keep the prediction at such steps"
            )


class _Step1:
    """The inputs of Step 1, hashable by value (bounds, modes, Θ, p, ε) for the cache."""

    def __init__(self, flt: DependentEvidenceFilter, model: StateSpaceModel) -> None:
        theta_v, theta_w = (None, None) if flt.theta is None else flt.theta
        self.state, self.obs = model.state_noise, model.obs_noise
        self.theta_v = _theta(theta_v, model.state_dim)
        self.theta_w = _theta(theta_w, model.obs_dim)
        self.p, self.epsilon = int(flt.p), float(flt.epsilon)
        self.key = (
            self.p,
            self.epsilon,
            *(
                None if a is None else a.tobytes()
                for a in (
                    self.state.lower,
                    self.state.mode,
                    self.state.upper,
                    self.obs.lower,
                    self.obs.mode,
                    self.obs.upper,
                    self.theta_v,
                    self.theta_w,
                )
            ),
        )

    def __hash__(self) -> int:
        return hash(self.key)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Step1) and other.key == self.key


@functools.lru_cache(maxsize=64)
def _noise_evidence(step1: _Step1) -> NoiseEvidence:
    ev = step1.state.evidence(step1.p, step1.epsilon, step1.theta_v)
    ew = step1.obs.evidence(step1.p, step1.epsilon, step1.theta_w)
    n_v = len(ev)
    check_memory(
        8.0 * n_v * n_v * (2 * ev.boxes_lo.shape[-1] + 1),
        f"the paper's filter's prediction E_(k+1|k) ({n_v} × {n_v} boxes, eq. 16)",
        "use fewer α-cuts p, or a model with fewer state components",
    )
    v = Boxes(ev.boxes_lo[None], ev.boxes_hi[None], ev.mass[None])
    w = Boxes(ew.boxes_lo[None], ew.boxes_hi[None], ew.mass[None])
    rho = np.multiply.outer(ev.mass, ev.mass).reshape(1, -1)
    for array in (*v, *w, rho):
        array.flags.writeable = False
    return NoiseEvidence(ev, ew, v, w, rho)


def _theta(theta: Any, dim: int) -> np.ndarray | None:
    if theta is None:
        return None
    arr = np.asarray(theta, dtype=float)
    if arr.size != 2 * dim:
        raise EvidenceError(f"Θ needs one (lo, hi) pair per component ({dim}), got {theta!r}")
    return arr.reshape(dim, 2)


def run_dependent_filter(
    model: StateSpaceModel, z: Any, inputs: Any = None, *, record: bool = False, **options: Any
) -> FilterResult:
    """Shorthand for ``DependentEvidenceFilter(**options).run(model, z, inputs, record)``."""
    return DependentEvidenceFilter(**options).run(model, z, inputs, record)


__all__: list[str] = [
    "COUNTS",
    "DIAGNOSTICS",
    "DependentEvidenceFilter",
    "NoiseEvidence",
    "map_back",
    "observe",
    "predict",
    "run_dependent_filter",
]
