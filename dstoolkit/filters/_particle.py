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
When every particle gets weight 0 although the cloud was drawn from the previous reading
alone (at the start, or just re-initialised: it spans every state that reading allows), and
the prediction (the box of f(x) over the resampled cloud, widened by the state noise bounds)
holds no state consistent with the reading, the model contradicts the data (f wrong, or
bounds too tight): the filter raises an :class:`~dstoolkit.errors.InconsistentDataError`,
as the bounded-error filter does, unless ``on_inconsistent="reset"``. Otherwise (a cloud
that had narrowed merely missed the consistent states, e.g. after an outlier), the cloud
is **re-initialised from the reading**: particles are drawn uniformly in
g⁻¹(z_k + [w_lo, w_hi]) (∩ ``initial_box``) and weighted by their likelihood, exactly as at
the start. The step is flagged in ``diagnostics["reinitialised"]``; the filter forgets its
past there.

Random numbers
--------------
Every run has its own streams: ``SeedSequence(seed, spawn_key=(r,))`` for run r's start
uniforms and then its state noise, step after step, and ``spawn_key=(r, 0)`` for its
resampling offsets, one a step. So run r of :meth:`run_batch` does not depend on the
batch size and equals
:meth:`run` with ``stream=r``, and :meth:`initialize` and :meth:`step` draw the same
numbers one step at a time (the state carries the stream). A re-initialisation draws from the stream
``spawn_key=(r, k)``. Batches are processed in chunks of runs so the pre-drawn noise stays
within :data:`CHUNK_BYTES`.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from dstoolkit.errors import EvidenceError, InconsistentDataError

from ._base import Block, Filter, FilterState, KernelChoice
from ._bounded_error import BoundedErrorFilter, InconsistencyPolicy
from ._model import (
    BoundedNoise,
    StateSpaceModel,
    at_step,
    first_reading_box,
    own_state,
    step_input,
    with_input,
)

#: Memory budget of the random numbers pre-drawn for one chunk of runs.
CHUNK_BYTES = 64 * 2**20
#: Pre-drawn numbers of a chunk up to this size are kept for the next batch (two chunks).
KEPT_DRAWS_BYTES = 16 * 2**20
#: Resampling works on cumulative weights quantised to 2⁻⁴⁰ (whole numbers of quanta, exact).
_QUANTUM = 2.0**40


def systematic_resample(
    weights: np.ndarray, offsets: np.ndarray, *, compiled: bool = False
) -> np.ndarray:
    """Choose indices by systematic resampling, one row per run.

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
    ndarray of int, shape (runs, N)
        Particle i is chosen about N·w_i times, never when w_i = 0. Cumulative weights
        and positions are quantised to whole multiples of 2⁻⁴⁰ (exact in floating
        point), and each row is searched on its own, so a row's result does not depend
        on the other rows.

    Examples
    --------
    >>> import numpy as np
    >>> systematic_resample(np.array([[0.1, 0.2, 0.7]]), np.array([0.5]))
    array([[1, 2, 2]])
    """
    if compiled:  # the same indices in one pass per row (extra speed)
        from ._compiled import resample_compiled

        return resample_compiled(weights, offsets, _QUANTUM)
    runs, n = weights.shape
    cum = np.floor(np.cumsum(weights, axis=1) * _QUANTUM)
    cum[:, -1] = _QUANTUM
    pos = np.floor((offsets[:, None] + np.arange(n)) / n * _QUANTUM)
    idx = np.empty((runs, n), dtype=np.intp)
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
    """Return run ``key[0]``'s random stream (and a re-initialisation's at step ``key[1]``)."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=key))


def _draws(
    seed: int, run_ids: Any, state_noise: BoundedNoise, n_steps: int, big_n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pre-draw every run's numbers from its own streams.

    The start's uniforms (runs, N, n), the state noise (runs, steps − 1, N, n) and the
    resampling offsets (runs, steps − 1). Each stream is read in the order of the steps, so
    :meth:`ParticleFilter.step`, drawing one step's numbers at a time, draws the same ones.
    """
    runs, n = len(run_ids), state_noise.dim
    start_u = np.empty((runs, big_n, n))
    noise = np.empty((runs, max(n_steps - 1, 0), big_n, n))
    offsets = np.empty((runs, max(n_steps - 1, 0)))
    for i, r in enumerate(run_ids):
        rng, offset_rng = _stream(seed, int(r)), _stream(seed, int(r), 0)
        start_u[i] = rng.random((big_n, n))
        noise[i] = state_noise.sample(rng, (n_steps - 1, big_n))
        offsets[i] = offset_rng.random(max(n_steps - 1, 0))
    return start_u, noise, offsets


def _copied(rng: np.random.Generator) -> np.random.Generator:
    """Return a generator in the same state as ``rng``, to draw from without advancing ``rng``."""
    copy = np.random.Generator(type(rng.bit_generator)())
    copy.bit_generator.state = rng.bit_generator.state
    return copy


@functools.lru_cache(maxsize=2)
def _kept_draws(
    seed: int,
    run_ids: tuple[int, ...],
    noise: tuple[tuple[float, ...], ...],
    n_steps: int,
    big_n: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return :func:`_draws`, kept (read-only) for the next batch of the same runs.

    Kept for the same state noise: an explorer that re-filters them under other bounds of
    the observation noise draws nothing again.
    """
    arrays = _draws(seed, run_ids, BoundedNoise(*map(np.array, noise)), n_steps, big_n)
    for a in arrays:
        a.flags.writeable = False
    return arrays


@dataclass(frozen=True)
class ParticleState(FilterState):
    """The particle filter's state: the weighted cloud after the reading and the random streams.

    The run's random streams are ``rng`` for the state noise, ``offset_rng`` for the
    resampling; copied by :meth:`ParticleFilter.step`, never advanced in place.

    ``particles`` is (N, n) and ``weights`` (N,), summing to 1; ``estimate`` is their
    weighted mean and ``lower``/``upper`` the hull of the particles with weight.

    Parameters
    ----------
    model : StateSpaceModel
        The model the filter runs on.
    k : int
        The step whose estimate this is (1 for the first reading).
    estimate : ndarray, shape (n,)
        x̂_k.
    lower, upper : ndarray, shape (n,)
        The hull of the particles with weight.
    particles : ndarray, shape (N, n)
        The cloud after the reading.
    weights : ndarray, shape (N,)
        Their weights, summing to 1.
    rng, offset_rng : numpy.random.Generator
        The run's streams: state noise, resampling offsets.
    run : int
        The run's index (its streams).
    redrawn : bool
        Whether the cloud was drawn from the reading alone at this step (the start, or a
        re-initialisation).
    """

    particles: np.ndarray
    weights: np.ndarray
    rng: np.random.Generator
    offset_rng: np.random.Generator
    run: int = 0
    redrawn: bool = False


@dataclass(frozen=True)
class ParticleRecord:
    """One step of the particle filter.

    Parameters
    ----------
    step : int
        k, counting the first reading as 1.
    particles : ndarray, shape (N, n)
        The cloud after propagation (before the next resampling).
    weights : ndarray, shape (N,)
        Their normalised weights p_w(g(x) − z).
    ess : float
        The effective sample size 1/Σw².
    reinitialised : bool
        Whether every weight was 0 and the cloud was drawn again from the reading.
    estimate : ndarray, shape (n,)
        The weighted mean.
    """

    step: int
    particles: np.ndarray
    weights: np.ndarray
    ess: float
    reinitialised: bool
    estimate: np.ndarray


@dataclass(frozen=True)
class ParticleFilter(Filter[ParticleState, ParticleRecord]):
    """Bootstrap particle filter with bounded-support likelihood (see the module docstring).

    Parameters
    ----------
    n_particles : int
        Particles per run.
    seed : int
        Seed of the random streams (one per run).
    stream : int
        Index of the first run's random stream: :meth:`Filter.run` and :meth:`initialize` use
        stream ``stream``, run r of :meth:`Filter.run_batch` stream ``stream + r`` (so
        ``replace(flt, stream=r).run(Z[r])`` repeats run r of a batch).
    initial_box : tuple of array_like, optional
        A box ``(lo, hi)`` known to hold the state;
        needed when g is not invertible, since
        the start and re-initialisations draw in the reading's box.
    kernel : {"numpy", "numba", "auto"}
        The resampling's search: ``"numpy"`` (default),
        ``"numba"`` (compiled, extra
        ``speed``; the same indices), ``"auto"`` (numba when it is installed).
    on_inconsistent : {"raise", "reset"}
        When a cloud drawn from the previous reading alone predicts
        no state consistent with the reading (see the module docstring): ``"raise"``
        (default) an :class:`~dstoolkit.errors.InconsistentDataError`, as the bounded-error
        filter does; ``"reset"`` redraw the cloud from the reading. A narrowed cloud that
        merely missed the consistent states is redrawn either way.

    See Also
    --------
    systematic_resample : the resampling step.

    Examples
    --------
    >>> from dstoolkit.filters import ParticleFilter, random_walk
    >>> result = ParticleFilter(n_particles=200).run(random_walk(0.1, 0.5), [1.0, 1.2, 0.9])
    >>> result.estimates.shape, bool(result.diagnostics["ess"][0] > 100)
    ((3, 1), True)
    """

    n_particles: int = 1000
    seed: int = 0
    stream: int = 0
    initial_box: tuple[Any, Any] | None = None
    kernel: KernelChoice = "numpy"
    on_inconsistent: InconsistencyPolicy = "raise"
    name: ClassVar[str] = "particle"
    COMPILED_KERNEL: ClassVar[bool] = True
    DIAGNOSTICS: ClassVar[dict[str, str]] = {
        "ess": "effective sample size 1/Σw² of the weights after the reading",
        "reinitialised": "True where every weight was 0 and the cloud was redrawn",
    }
    _budget_advice: ClassVar[str] = "use fewer particles or steps"

    def __post_init__(self) -> None:
        self._whole("n_particles", low=1, high=10**8)
        self._whole("seed")
        self._whole("stream")
        self._own_box()
        self._compiled(self.kernel, "the particle filter")
        self._policy(self.on_inconsistent, ("raise", "reset"), "on_inconsistent")

    def _check_model(self, model: StateSpaceModel) -> None:
        self._check_box_dim(self._box(self.initial_box), model)

    def _bytes_per_run(self, model: StateSpaceModel, n_steps: int) -> float:
        """Memory of one run's pre-drawn noise and working arrays, bytes."""
        return float(8 * n_steps * int(self.n_particles) * (model.state_dim + 1))

    def _chunk_cap(self, model: StateSpaceModel, n_steps: int) -> int | None:
        return max(1, int(CHUNK_BYTES // self._bytes_per_run(model, n_steps)))

    # -- the public step -----------------------------------------------------------------------
    def initialize(self, model: StateSpaceModel, z1: Any) -> ParticleState:
        """Draw particles uniform in the reading's box, weighted by their likelihood.

        They are drawn from the stream ``stream``.

        Parameters
        ----------
        model : StateSpaceModel
            The model of eq. 21.
        z1 : array_like, shape (m,) or scalar when m = 1
            The first reading z_1.

        Returns
        -------
        ParticleState
            The state of step 1; ``estimate`` is x̂_1, shape (n,).

        See Also
        --------
        Filter.initialize : the interface every filter shares.
        """
        self._check_model(model)
        z, _ = self._one(model, z1, transition=False)
        model = self._guarded(model)
        rng = _stream(int(self.seed), int(self.stream))
        uniforms = rng.random((int(self.n_particles), model.state_dim))[None]
        particles, weights = self._draw_in_reading_box(model, z, uniforms, 0)
        return self._state(
            model,
            1,
            particles[0],
            _normalised(weights)[0],
            rng,
            _stream(int(self.seed), int(self.stream), 0),
            int(self.stream),
        )

    def step(
        self, state: ParticleState, z: Any, u: Any = None
    ) -> tuple[ParticleState, ParticleRecord]:
        """Resample, propagate through f with drawn state noise, weigh by the reading.

        Parameters
        ----------
        state : ParticleState
            What :meth:`initialize` or the previous :meth:`step` returned.
        z : array_like, shape (m,) or scalar when m = 1
            The reading z_{k+1}.
        u : array_like, shape (q,), optional
            The input of f(x, u) on the transition
            k → k + 1 (the gauge's order n_k).

        Returns
        -------
        state : ParticleState
            The state of step k + 1; ``estimate`` is x̂_{k+1}, shape (n,).
        record : ParticleRecord
            What the step computed.

        See Also
        --------
        Filter.step : the interface every filter shares.
        """
        own_state(state, ParticleState, self._title)
        model = state.model
        zz, uu = self._one(model, z, u)
        at_step(model, state.k)
        rng, offset_rng = _copied(state.rng), _copied(state.offset_rng)
        noise = model.state_noise.sample(rng, (1, int(self.n_particles)))
        particles, w, reinit = self._advance(
            model,
            state.particles[None],
            state.weights[None],
            offset_rng.random(1),
            noise,
            zz,
            uu,
            np.array([state.run]),
            state.k,
            np.array([state.k == 1 or state.redrawn]),
        )
        new = self._state(model, state.k + 1, particles[0], w[0], rng, offset_rng, state.run)
        new = dataclasses.replace(new, redrawn=bool(reinit[0]))
        return new, self._record(new, bool(reinit[0]))

    def _start_record(self, state: ParticleState) -> ParticleRecord:
        return self._record(state, False)

    @staticmethod
    def _record(state: ParticleState, reinitialised: bool) -> ParticleRecord:
        w = state.weights
        return ParticleRecord(
            state.k, state.particles, w, float(1.0 / np.sum(w * w)), reinitialised, state.estimate
        )

    @staticmethod
    def _state(
        model: StateSpaceModel,
        k: int,
        particles: np.ndarray,
        w: np.ndarray,
        rng: np.random.Generator,
        offset_rng: np.random.Generator,
        run: int,
    ) -> ParticleState:
        est = np.einsum("rp,rpi->ri", w[None], particles[None])[0]
        alive = (w > 0)[:, None]
        return ParticleState(
            model,
            k,
            est,
            np.where(alive, particles, np.inf).min(axis=0),
            np.where(alive, particles, -np.inf).max(axis=0),
            particles,
            w,
            rng,
            offset_rng,
            run,
        )

    # -- internals ---------------------------------------------------------------------------
    def _reading_box(
        self, model: StateSpaceModel, z: np.ndarray, step: int
    ) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = first_reading_box(model, z, self.initial_box)
        if np.any(lo > hi) or not np.all(np.isfinite(lo) & np.isfinite(hi)):
            raise EvidenceError(
                f"step {step}: the states consistent with the reading do not form a bounded "
                "non-empty box (g not invertible, or initial_box inconsistent with the "
                "reading); give the particle filter an initial_box that bounds the state"
            )
        return lo, hi

    def _weigh(self, model: StateSpaceModel, particles: np.ndarray, z: np.ndarray) -> np.ndarray:
        return model.obs_noise.pdf(model.g(particles) - z[:, None, :])

    def _draw_in_reading_box(
        self, model: StateSpaceModel, z: np.ndarray, uniforms: np.ndarray, step: int
    ) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self._reading_box(model, z, step)
        particles = lo[:, None, :] + uniforms * (hi - lo)[:, None, :]
        return particles, self._weigh(model, particles, z)

    def _advance(
        self,
        model: StateSpaceModel,
        particles: np.ndarray,
        w: np.ndarray,
        offsets: np.ndarray,
        noise: np.ndarray,
        z: np.ndarray,
        u: np.ndarray | None,
        run_ids: np.ndarray,
        k: int,
        redrawn: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Advance step k → k + 1 (k counting from 1) for R runs.

        Clouds (R, N, n) with weights (R, N), the step's offsets (R,) and state noise
        (R, N, n), readings (R, m). Returns the new clouds, their normalised weights and the
        re-initialised runs. ``redrawn`` (R,) tells the runs whose cloud was drawn from the
        previous reading alone: for them, a prediction that contradicts the reading is refused
        (``on_inconsistent="raise"``), since the cloud then spans every state that reading
        allows, and the model, not the cloud, is at fault.
        """
        runs, big_n, n = particles.shape
        first_row = (np.arange(runs) * big_n)[:, None]  # each run's first particle, flattened
        compiled = self._compiled(self.kernel, "the particle filter")
        idx = systematic_resample(w, offsets, compiled=compiled) + first_row
        chosen = np.take(particles.reshape(-1, n), idx.ravel(), axis=0)
        moved = with_input(model.f, u)(chosen.reshape(runs, big_n, n))
        particles = moved + noise
        weights = self._weigh(model, particles, z)
        dead = ~(weights.sum(axis=1) > 0)
        if (dead & redrawn).any() and self.on_inconsistent == "raise":
            self._refuse_contradiction(model, moved, z, dead & redrawn, k)
        for i in np.flatnonzero(dead).tolist():
            fresh = _stream(int(self.seed), int(run_ids[i]), k).random((1, big_n, n))
            p_new, w_new = self._draw_in_reading_box(model, z[i : i + 1], fresh, k)
            particles[i], weights[i] = p_new[0], w_new[0]
        return particles, _normalised(weights), dead

    @staticmethod
    def _refuse_contradiction(
        model: StateSpaceModel, moved: np.ndarray, z: np.ndarray, dead: np.ndarray, k: int
    ) -> None:
        """Refuse a step whose prediction holds no state consistent with the reading.

        The prediction is the box of f(x) over the resampled cloud widened by the state
        noise bounds (eq. 21), as the bounded-error filter predicts; a cloud that merely
        missed the consistent states (all weights 0 by chance) is redrawn instead.
        """
        with np.errstate(invalid="ignore"):
            p_lo = moved.min(axis=1) + model.state_noise.lower
            p_hi = moved.max(axis=1) + model.state_noise.upper
        r_lo, r_hi = model.inverse()(
            z + model.obs_noise.lower, z + model.obs_noise.upper, p_lo, p_hi
        )
        r_lo, r_hi = np.broadcast_to(r_lo, p_lo.shape), np.broadcast_to(r_hi, p_hi.shape)
        finite = np.isfinite(p_lo).all(axis=-1) & np.isfinite(p_hi).all(axis=-1)
        contradicted = dead & (~finite | np.any(~(r_lo <= r_hi), axis=-1))
        if contradicted.any():
            r = int(np.flatnonzero(contradicted)[0])
            raise InconsistentDataError(
                BoundedErrorFilter._message(model, z, k, r, p_lo, p_hi).replace(
                    "restart from the reading",
                    "redraw the particles from the reading (the filter then forgets its past)",
                )
            )

    def _engine(
        self, model: StateSpaceModel, Z: np.ndarray, U: np.ndarray | None, runs: np.ndarray
    ) -> Block:
        n_runs, n_steps, _ = Z.shape
        n, big_n = model.state_dim, int(self.n_particles)
        runs = runs + int(self.stream)
        noise_key = tuple(
            tuple(a.tolist())
            for a in (model.state_noise.lower, model.state_noise.mode, model.state_noise.upper)
        )
        start_u, noise, offsets = (
            _kept_draws(int(self.seed), tuple(runs.tolist()), noise_key, n_steps, big_n)
            if self._bytes_per_run(model, n_steps) * n_runs <= KEPT_DRAWS_BYTES
            else _draws(int(self.seed), runs, model.state_noise, n_steps, big_n)
        )
        est = np.empty((n_runs, n_steps, n))
        lo, hi = np.empty_like(est), np.empty_like(est)
        ess = np.empty((n_runs, n_steps))
        reinit = np.zeros((n_runs, n_steps), dtype=bool)
        particles, weights = self._draw_in_reading_box(model, Z[:, 0], start_u, 0)
        w = _normalised(weights)
        for k in range(n_steps):
            at_step(model, k)
            if k > 0:
                particles, w, reinit[:, k] = self._advance(
                    model,
                    particles,
                    w,
                    offsets[:, k - 1],
                    noise[:, k - 1],
                    Z[:, k],
                    step_input(U, k),
                    runs,
                    k,
                    reinit[:, k - 1] | (k == 1),
                )
            est[:, k] = np.einsum("rp,rpi->ri", w, particles)
            alive = (w > 0)[..., None]
            lo[:, k] = np.where(alive, particles, np.inf).min(axis=1)
            hi[:, k] = np.where(alive, particles, -np.inf).max(axis=1)
            ess[:, k] = 1.0 / np.sum(w * w, axis=1)
        return Block(est, lo, hi, {"ess": ess, "reinitialised": reinit})
