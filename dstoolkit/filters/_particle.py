"""A bootstrap particle filter (Gordon–Salmond SIR) whose likelihood respects the bounds.

The paper's introduction cites the particle filter as the method of choice when noises
are non-Gaussian and their statistics known. Here it gets the full triangular densities of
the same bounded noises: particles move with state noise drawn from
:meth:`BoundedNoise.sample`, and a particle's weight is the density of the observation
noise it implies, w = g(x) − z (eq. 21's sign convention), by :meth:`BoundedNoise.pdf`,
which is zero outside the support. A particle whose reading would need a noise beyond the
bounds is therefore ruled out, as in the bounded-error filter.

Each step: systematic resampling of the previous cloud, propagation x' = f(x, u) + v,
weighting by p_w(g(x') − z), estimate = weighted mean. Start: particles drawn uniformly
in the box of states consistent with the first reading, g⁻¹(z_1 + [w_lo, w_hi]), and
weighted by its likelihood (a flat prior on that box).

Degeneracy policy
-----------------
When every particle gets weight 0 (the cloud has moved where no state agrees with the
reading within the noise bounds, e.g. bounds too tight or an outlier), the cloud is
**re-initialised from the reading**: particles are drawn uniformly in
g⁻¹(z_k + [w_lo, w_hi]) (∩ ``initial_box``) and weighted by their likelihood, exactly as at
the start. The step is flagged in ``diagnostics["reinitialised"]``; the filter forgets its
past there.

Random numbers
--------------
Every run has its own stream, ``SeedSequence(seed, spawn_key=(r,))`` for run r, drawn in a
fixed order (start, noises, resampling offsets), so row r of :meth:`run_batch` equals
:meth:`run` with ``run_index=r`` whatever the batch size. A re-initialisation draws from
the stream ``spawn_key=(r, k)``. Batches are processed in chunks of runs so the pre-drawn
noise stays within :data:`CHUNK_BYTES`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence._checks import whole_number

from ._base import FilterBase, KernelChoice
from ._model import (
    BoundedNoise,
    FilterResult,
    StateSpaceModel,
    first_reading_box,
    step_input,
    with_input,
)

#: Memory budget of the random numbers pre-drawn for one chunk of runs.
CHUNK_BYTES = 64 * 2**20
#: Pre-drawn numbers of a chunk up to this size are kept for the next batch (two chunks).
KEPT_DRAWS_BYTES = 16 * 2**20
#: Resampling works on cumulative weights quantised to 2⁻⁴⁰ (whole numbers of quanta, exact).
_QUANTUM = 2.0**40


def systematic_resample(weights: np.ndarray, offsets: np.ndarray, *, compiled: bool = False
                        ) -> np.ndarray:
    """Indices chosen by systematic resampling, one row per run.

    Parameters
    ----------
    weights
        Normalised weights (runs, N), each row summing to 1.
    offsets
        One uniform number in [0, 1) per run.
    compiled
        Search with the compiled kernel (extra ``speed``): the same indices.

    Returns
    -------
    Indices (runs, N): particle i is chosen about N·w_i times, never when w_i = 0.
    Cumulative weights and positions are quantised to whole multiples of 2⁻⁴⁰ (exact in
    floating point), and each row is searched on its own, so a row's result does not depend
    on the other rows.
    """
    runs, n = weights.shape
    cum = np.floor(np.cumsum(weights, axis=1) * _QUANTUM)
    cum[:, -1] = _QUANTUM
    pos = np.floor((offsets[:, None] + np.arange(n)) / n * _QUANTUM)
    idx = np.empty((runs, n), dtype=np.intp)
    if compiled:  # the same indices in one pass per row (extra speed)
        from ._compiled import resample_search

        resample_search(cum, pos, idx)
    else:
        for r in range(runs):  # one search per row: shorter, and faster than one on all rows
            idx[r] = np.searchsorted(cum[r], pos[r], side="right")
    return np.minimum(idx, n - 1, out=idx)


def _normalised(weights: np.ndarray) -> np.ndarray:
    """Weights (runs, N) divided by their sum; a run whose weights are all 0 gets 1/N each."""
    total = weights.sum(axis=1, keepdims=True)
    if not np.all(total > 0):
        weights = np.where(total > 0, weights, 1.0)
        total = weights.sum(axis=1, keepdims=True)
    return weights / total


def _stream(seed: int, *key: int) -> np.random.Generator:
    """The random stream of run ``key[0]`` (and of a re-initialisation at step ``key[1]``)."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=key))


def _draws(seed: int, run_ids: Any, state_noise: BoundedNoise, n_steps: int, big_n: int
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every run's numbers, pre-drawn from its own stream in a fixed order: the start's
    uniforms (runs, N, n), the state noise (runs, steps − 1, N, n), the resampling offsets
    (runs, steps)."""
    runs, n = len(run_ids), state_noise.dim
    start_u = np.empty((runs, big_n, n))
    noise = np.empty((runs, max(n_steps - 1, 0), big_n, n))
    offsets = np.empty((runs, n_steps))
    for i, r in enumerate(run_ids):
        rng = _stream(seed, int(r))
        start_u[i] = rng.random((big_n, n))
        noise[i] = state_noise.sample(rng, (n_steps - 1, big_n))
        offsets[i] = rng.random(n_steps)
    return start_u, noise, offsets


@functools.lru_cache(maxsize=2)
def _kept_draws(seed: int, run_ids: tuple[int, ...],
                noise: tuple[tuple[float, ...], ...], n_steps: int, big_n: int
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_draws`, kept (read-only) for the next batch of the same runs with the same
    state noise: an explorer that re-filters them under other bounds of the observation
    noise draws nothing again."""
    arrays = _draws(seed, run_ids, BoundedNoise(*map(np.array, noise)), n_steps, big_n)
    for a in arrays:
        a.flags.writeable = False
    return arrays


@dataclass(frozen=True)
class ParticleFilter(FilterBase):
    """Bootstrap particle filter with bounded-support likelihood (see the module docstring).

    Parameters
    ----------
    n_particles
        Particles per run.
    seed
        Seed of the random streams (one per run).
    initial_box
        Optional box ``(lo, hi)`` known to hold the state; needed when g is not
        invertible, since the start and re-initialisations draw in the reading's box.
    kernel
        The resampling's search: ``"numpy"`` (default), ``"numba"`` (compiled, extra
        ``speed``; the same indices), ``"auto"`` (numba when it is installed).
    """

    n_particles: int = 1000
    seed: int = 0
    initial_box: tuple[Any, Any] | None = None
    kernel: KernelChoice = "numpy"
    name: ClassVar[str] = "particle"

    def __post_init__(self) -> None:
        whole_number(self.n_particles, "n_particles", low=1, high=10**8, error=EvidenceError)
        whole_number(self.seed, "seed", low=0, error=EvidenceError)
        self._box(self.initial_box)
        self._compiled(self.kernel, "the particle filter")

    def run(
        self, model: StateSpaceModel, z: Any, inputs: Any = None, record: bool = False,
        run_index: int = 0,
    ) -> FilterResult:
        """Filter one sequence ``z`` (steps, m) with the random stream of run ``run_index``.

        ``record=True`` keeps each step's weighted particles (before resampling), weights
        and effective sample size. Diagnostics: ``ess`` (steps,), the effective sample size
        1/Σw², and ``reinitialised`` (steps,), True where the degeneracy policy acted.
        """
        Z, U = self._single(model, z, inputs)
        self._check_box_dim(self._box(self.initial_box), model)
        run_index = whole_number(run_index, "run_index", low=0, error=EvidenceError)
        self._chunks(1, self._bytes_per_run(model, Z.shape[1]), "the particle filter",
                     "use fewer particles or steps")
        out = self._filter_chunk(model, Z, U, np.array([run_index]), record, details=True)
        est, lo, hi, ess, reinit, steps = out
        self._finite(est)
        return FilterResult(
            method=self.name, estimates=est[0], lower=lo[0], upper=hi[0], steps=steps,
            diagnostics={"ess": ess[0], "reinitialised": reinit[0]},
        )

    def run_batch(self, model: StateSpaceModel, Z: Any, inputs: Any = None) -> np.ndarray:
        """Estimates (runs, steps, n); row r equals ``run(model, Z[r], run_index=r)``."""
        Z, U = self._batch(model, Z, inputs)
        self._check_box_dim(self._box(self.initial_box), model)
        runs, n_steps, _ = Z.shape
        per_run = self._bytes_per_run(model, n_steps)
        est = np.empty((runs, n_steps, model.state_dim))
        for sel in self._chunks(runs, per_run, "the particle filter",
                                "use fewer particles or steps",
                                cap=max(1, int(CHUNK_BYTES // per_run))):
            est[sel] = self._filter_chunk(
                model, Z[sel], None if U is None else U[sel], np.arange(runs)[sel], False,
                details=False,
            )[0]
        return self._finite(est)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        """Memory of one run's pre-drawn noise and working arrays, bytes."""
        return float(8 * n_steps * int(self.n_particles) * (model.state_dim + 1))

    # -- internals ---------------------------------------------------------------------------
    def _reading_box(self, model: StateSpaceModel, z: np.ndarray, step: int
                     ) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = first_reading_box(model, z, self.initial_box)
        if np.any(lo > hi) or not np.all(np.isfinite(lo) & np.isfinite(hi)):
            raise EvidenceError(
                f"step {step}: the states consistent with the reading do not form a bounded "
                "non-empty box (g not invertible, or initial_box inconsistent with the "
                "reading); give the particle filter an initial_box that bounds the state"
            )
        return lo, hi

    def _weigh(self, model: StateSpaceModel, particles: np.ndarray, z: np.ndarray
               ) -> np.ndarray:
        return model.obs_noise.pdf(model.g(particles) - z[:, None, :])

    def _draw_in_reading_box(
        self, model: StateSpaceModel, z: np.ndarray, uniforms: np.ndarray, step: int
    ) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self._reading_box(model, z, step)
        particles = lo[:, None, :] + uniforms * (hi - lo)[:, None, :]
        return particles, self._weigh(model, particles, z)

    def _filter_chunk(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None,
        run_ids: np.ndarray, record: bool, details: bool,
    ) -> tuple[Any, ...]:
        runs, n_steps, _ = Z.shape
        n, big_n = model.state_dim, self.n_particles
        noise_key = tuple(tuple(a.tolist()) for a in (model.state_noise.lower,
                                                      model.state_noise.mode,
                                                      model.state_noise.upper))
        start_u, noise, offsets = (
            _kept_draws(self.seed, tuple(run_ids.tolist()), noise_key, n_steps, big_n)
            if self._bytes_per_run(model, n_steps) * runs <= KEPT_DRAWS_BYTES
            else _draws(self.seed, run_ids, model.state_noise, n_steps, big_n))

        compiled = self._compiled(self.kernel, "the particle filter")
        est = np.empty((runs, n_steps, n))
        lo, hi = np.empty_like(est), np.empty_like(est)
        ess = np.empty((runs, n_steps))
        reinit = np.zeros((runs, n_steps), dtype=bool)
        steps: list[dict[str, Any]] | None = [] if record else None

        particles, weights = self._draw_in_reading_box(model, Z[:, 0], start_u, 0)
        first_row = (np.arange(runs) * big_n)[:, None]  # each run's first particle, flattened
        w = _normalised(weights)
        for k in range(n_steps):
            if k > 0:
                idx = systematic_resample(w, offsets[:, k - 1], compiled=compiled) + first_row
                chosen = np.take(particles.reshape(-1, n), idx.ravel(), axis=0)
                particles = (with_input(model.f, step_input(U, k))(chosen.reshape(runs, big_n, n))
                             + noise[:, k - 1])
                weights = self._weigh(model, particles, Z[:, k])
                dead = ~(weights.sum(axis=1) > 0)
                if np.any(dead):
                    for i in np.flatnonzero(dead).tolist():
                        u = _stream(self.seed, int(run_ids[i]), k).random((1, big_n, n))
                        p_new, w_new = self._draw_in_reading_box(model, Z[i : i + 1, k], u, k)
                        particles[i], weights[i] = p_new[0], w_new[0]
                    reinit[dead, k] = True
                w = _normalised(weights)
            est[:, k] = np.einsum("rp,rpi->ri", w, particles)
            if not details:
                continue
            alive = (w > 0)[..., None]
            lo[:, k] = np.where(alive, particles, np.inf).min(axis=1)
            hi[:, k] = np.where(alive, particles, -np.inf).max(axis=1)
            ess[:, k] = 1.0 / np.sum(w * w, axis=1)
            if steps is not None:
                steps.append({"particles": particles[0].copy(), "weights": w[0].copy(),
                              "ess": float(ess[0, k]), "reinitialised": bool(reinit[0, k])})
        return est, lo, hi, ess, reinit, steps
