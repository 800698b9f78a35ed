"""Every filter through the same lines.

The shared options, the public step, run and run_batch, the result types and their shapes.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import re
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from dstoolkit.errors import EvidenceError
from dstoolkit.filters import (
    KERNELS,
    BatchResult,
    BoundedErrorFilter,
    ComparisonSettings,
    DependentEvidenceFilter,
    Filter,
    FilterResult,
    FilterState,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    UnscentedKalmanFilter,
    lotka_volterra,
    random_walk,
    registered_filters,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

README = Path(__file__).resolve().parents[1] / "README.md"


def readme_filter() -> type[Filter]:
    """Return the README's alpha–beta filter: only ``initialize`` and ``step`` (no _engine)."""
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    code = next(b for b in blocks if "class AlphaBetaFilter" in b)
    code = code[: code.index("model, z = ")]  # the classes, not the example's prints
    module = types.ModuleType("readme_alpha_beta")  # a module, as a user's file would be
    sys.modules[module.__name__] = module
    exec(compile(code, str(README), "exec", dont_inherit=True), module.__dict__)
    return module.AlphaBetaFilter


AlphaBetaFilter = readme_filter()

MAKERS = {
    "dependent_evidence": lambda **kw: DependentEvidenceFilter(p=2, **kw),
    "nassreddine": lambda **kw: NassreddineFilter(max_focal=16, **kw),
    "nassreddine_restart": lambda **kw: NassreddineFilter(restart=True, **kw),
    "bounded_error": lambda **kw: BoundedErrorFilter(on_inconsistent="reset", **kw),
    "kalman": lambda **kw: KalmanFilter(**kw),
    "particle": lambda **kw: ParticleFilter(n_particles=200, seed=3, **kw),
    "unscented": lambda **kw: UnscentedKalmanFilter(**kw),
    # a filter that writes only initialize and step: Filter runs, records and batches it
    "alpha_beta": lambda kernel="numpy": AlphaBetaFilter(),
}
#: The package's filters (they take ``kernel=``).
BUILT_IN = [name for name in MAKERS if name != "alpha_beta"]
#: The paper's filter steps on IntervalEvidence objects (equal focal elements merged,
#: eq. 14), its vectorised run on arrays: the same numbers up to the order of additions.
TOLERANCE = {"dependent_evidence": 1e-12}


def gauge_case():
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=3, seed=7)
    return gauge_state_space_model(), seq.readings[:, :15], seq.inputs[:, :14]


def walk_case():
    model = random_walk(0.1, 0.5)
    _, z = model.simulate([1.0], 12, np.random.default_rng(2), runs=3)
    return model, z, None


def lotka_case():
    model = lotka_volterra()
    _, z = model.simulate([0.2, -0.1], 8, np.random.default_rng(5), runs=2)
    return model, z, None


@pytest.mark.parametrize(
    "case", [gauge_case, walk_case, lotka_case], ids=["gauge", "random_walk", "lotka_volterra"]
)
@pytest.mark.parametrize("name", list(MAKERS))
def test_every_filter_through_the_same_lines(name, case):
    model, Z, U = case()
    flt = MAKERS[name](kernel="numpy")
    state = flt.initialize(model, Z[0, 0])
    for k in range(1, Z.shape[1]):
        state, record = flt.step(state, Z[0, k], None if U is None else U[0, k - 1])
    result = flt.run(model, Z[0], None if U is None else U[0])
    batch = flt.run_batch(model, Z, U)

    assert isinstance(flt, Filter) and isinstance(state, FilterState)
    assert isinstance(result, FilterResult) and isinstance(batch, BatchResult)
    assert result.method == batch.method == flt.name == name.replace("_restart", "")
    runs, steps, n = Z.shape[0], Z.shape[1], model.state_dim
    assert result.estimates.shape == result.lower.shape == result.upper.shape == (steps, n)
    assert batch.estimates.shape == batch.lower.shape == batch.upper.shape == (runs, steps, n)
    assert set(result.diagnostics) == set(batch.diagnostics) == set(flt.DIAGNOSTICS)
    assert all(v.shape == (steps,) for v in result.diagnostics.values())
    assert all(v.shape == (runs, steps) for v in batch.diagnostics.values())
    assert state.k == steps and state.estimate.shape == (n,)
    assert record.step == steps and dataclasses.is_dataclass(record)

    tol = TOLERANCE.get(name, 0.0)
    np.testing.assert_allclose(state.estimate, result.estimates[-1], rtol=tol, atol=0)
    np.testing.assert_allclose(state.lower, result.lower[-1], rtol=tol, atol=0)
    np.testing.assert_allclose(state.upper, result.upper[-1], rtol=tol, atol=0)
    np.testing.assert_array_equal(batch.estimates[0], result.estimates)
    np.testing.assert_array_equal(batch[0].estimates, result.estimates)


@pytest.mark.parametrize("name", list(MAKERS))
def test_the_step_loop_is_what_run_records(name):
    """run(record=True) is the public loop: it gives what initialize and step give.

    The same estimates, bounds and diagnostics, and one typed record per step.
    """
    model, Z, U = gauge_case()
    flt = MAKERS[name]()
    recorded = flt.run(model, Z[1], U[1], record=True)
    fast = flt.run(model, Z[1], U[1])
    assert recorded.steps is not None and len(recorded.steps) == Z.shape[1]
    assert len({type(r) for r in recorded.steps[1:]}) == 1
    # the start's record: the filter's own, or None where it writes none (the README's)
    assert type(recorded.steps[0]) is type(recorded.steps[1]) or (
        recorded.steps[0] is None and name == "alpha_beta"
    )
    tol = TOLERANCE.get(name, 0.0)
    np.testing.assert_allclose(recorded.estimates, fast.estimates, rtol=tol, atol=0)
    for key in flt.DIAGNOSTICS:
        np.testing.assert_allclose(
            np.asarray(recorded.diagnostics[key], dtype=float),
            np.asarray(fast.diagnostics[key], dtype=float),
            rtol=max(tol, 1e-9) if tol else 0,
            atol=1e-12 if tol else 0,
            err_msg=key,
        )


@pytest.mark.parametrize("name", BUILT_IN)
def test_kernel_numba_only_where_a_compiled_kernel_exists(name):
    """Every filter takes "numpy" and "auto"; "numba" only with compiled kernels."""
    have_numba = importlib.util.find_spec("numba") is not None
    flt = MAKERS[name]()
    for kernel in ("numpy", "auto"):
        MAKERS[name](kernel=kernel)
    if not flt.COMPILED_KERNEL:
        with pytest.raises(EvidenceError, match="has no compiled kernel; use kernel='numpy'"):
            MAKERS[name](kernel="numba")
    elif have_numba:
        MAKERS[name](kernel="numba")
    else:
        with pytest.raises(Exception, match="speed"):
            MAKERS[name](kernel="numba")
    with pytest.raises(EvidenceError, match="kernel must be one of 'numpy', 'numba', 'auto'"):
        MAKERS[name](kernel="fortran")


def test_every_registered_filter_goes_through_these_lines():
    """The registry's filters are those MAKERS runs (with options that keep the tests short).

    A filter registered without a maker here fails: add it to MAKERS.
    """
    registered = {entry.name: entry for entry in registered_filters()}
    assert set(registered) <= set(MAKERS)
    settings = ComparisonSettings()
    for name, entry in registered.items():
        made = entry.make(settings)
        assert isinstance(made, Filter) and made.name == name
        assert type(made) is type(MAKERS[name]())


def test_the_filters_with_compiled_kernels():
    compiled = {name for name in BUILT_IN if MAKERS[name]().COMPILED_KERNEL}
    assert compiled == {"dependent_evidence", "nassreddine", "nassreddine_restart", "particle"}
    assert set(KERNELS) == {"numpy", "numba", "auto"}


def test_the_noise_frames_have_one_name():
    theta = ((-20.0, 20.0), (-30.0, 30.0))
    for flt in (DependentEvidenceFilter(theta=theta), NassreddineFilter(theta=theta)):
        assert flt.theta == (((-20.0, 20.0),), ((-30.0, 30.0),))  # one (lo, hi) per component
    with pytest.raises(EvidenceError, match="theta must be a pair"):
        NassreddineFilter(theta=5.0)


def test_a_step_refuses_a_reading_of_the_wrong_size():
    flt = KalmanFilter()
    state = flt.initialize(random_walk(0.1, 0.5), 1.0)
    with pytest.raises(EvidenceError, match="component"):
        flt.step(state, [1.0, 2.0, 3.0])


def test_a_start_per_run_must_match_the_batch():
    model, Z, U = gauge_case()
    starts = Z[:, 0] + 6.9
    batch = DependentEvidenceFilter(start=starts, chunk_size=1).run_batch(model, Z, U)
    for r in range(Z.shape[0]):
        one = DependentEvidenceFilter(start=starts[r]).run(model, Z[r], U[r])
        np.testing.assert_array_equal(batch.estimates[r], one.estimates)
    with pytest.raises(EvidenceError, match="batch has 2"):
        DependentEvidenceFilter(start=starts).run_batch(model, Z[:2], U[:2])
    edited = starts.copy()
    flt = DependentEvidenceFilter(start=edited)
    edited += 100.0  # the filter keeps its own copy
    np.testing.assert_array_equal(flt.start, starts)


def test_options_are_kept_checked_and_converted():
    """Whole floats become ints at construction, and the filter keeps copies of its inputs.

    The copies are its own, of the boxes and frames it is given.
    """
    flt = ParticleFilter(n_particles=100.0, seed=5.0, stream=2.0)
    assert (flt.n_particles, flt.seed, flt.stream) == (100, 5, 2)
    assert all(type(v) is int for v in (flt.n_particles, flt.seed, flt.stream))
    assert type(NassreddineFilter(max_focal=32.0, p=2.0).max_focal) is int
    assert type(DependentEvidenceFilter(chunk_size=8.0).chunk_size) is int
    with pytest.raises(EvidenceError, match="n_particles must be a whole number"):
        ParticleFilter(n_particles=100.5)
    lo, hi = np.array([0.0]), np.array([10.0])
    kalman = KalmanFilter(initial_box=(lo, hi))
    lo[0] = 5.0  # the caller edits its array afterwards
    assert kalman.initial_box == ((0.0,), (10.0,))
    assert hash(kalman) == hash(KalmanFilter(initial_box=([0.0], [10.0])))


@pytest.mark.parametrize("name", list(MAKERS))
@pytest.mark.parametrize("broken", ["nan", "complex"])
def test_a_map_that_returns_nan_or_complex_is_named_with_its_step(name, broken):
    """Every path refuses a model whose f returns NaN, or complex numbers, above 1.05.

    The paths are run, run_batch and the public step; the error names the map and the
    step. Before, the particle filter returned finite estimates and the others dropped
    imaginary parts.
    """
    walk = random_walk(0.1, 0.5)

    def f(x, u=None):
        x = np.asarray(x, dtype=float)
        bad = np.full(x.shape, np.nan) if broken == "nan" else x + 1e-3j
        return np.where(x > 1.05, bad, x)

    model = dataclasses.replace(walk, f=f)
    z = np.array([1.0, 1.2, 1.6, 1.7, 1.8])
    flt = MAKERS[name]()
    what = "NaN" if broken == "nan" else "complex numbers"
    pattern = rf"model's f returned {what} while the .* filter was at step \d \(counting from 0\)"
    with pytest.raises(EvidenceError, match=pattern):
        flt.run(model, z)
    with pytest.raises(EvidenceError, match=pattern):
        flt.run_batch(model, np.stack([z, z]))
    if name == "alpha_beta":
        return  # the README's step calls the model it is given: run and run_batch guard it
    state = flt.initialize(model, z[0])
    with pytest.raises(EvidenceError, match=pattern):
        for reading in z[1:]:
            state, _ = flt.step(state, reading)


def test_kalman_refuses_readings_a_noise_free_model_cannot_explain():
    """Zero-width noises leave S = 0: readings 2.0, 2.1, 2.2 of a constant cannot all be right.

    Before, the pseudo-inverse gave the gain 0: estimates 2, 2, 2 and NIS 0.
    """
    from dstoolkit.errors import InconsistentDataError

    model, flt = random_walk(0.0, 0.0), KalmanFilter()
    with pytest.raises(InconsistentDataError, match=r"step 1 \(counting from 0\).*S = 0"):
        flt.run(model, [2.0, 2.1, 2.2])
    with pytest.raises(InconsistentDataError, match=r"step 1 \(counting from 0\) of run 1"):
        flt.run_batch(model, np.array([[2.0, 2.0, 2.0], [2.0, 2.1, 2.2]]))
    state = flt.initialize(model, 2.0)
    with pytest.raises(InconsistentDataError, match=r"step 1 \(counting from 0\)"):
        flt.step(state, 2.1)
    np.testing.assert_array_equal(flt.run(model, [2.0, 2.0, 2.0]).estimates[:, 0], 2.0)


def test_a_high_dimensional_state_is_refused_before_step_1_allocates():
    """The memory budget refuses seven state components before the masses ρ are made.

    Seven state components give 4^7 noise focal elements and a prediction of 4^14 boxes
    (eq. 16); nothing of it is kept in the Step-1 cache.
    """
    import tracemalloc

    from dstoolkit.errors import MemoryBudgetError
    from dstoolkit.filters import BoundedNoise, StateSpaceModel

    half = [0.1] * 7
    model = StateSpaceModel(
        f=lambda x, u=None: x,
        g=lambda x: x,
        g_inverse=lambda lo, hi, a, b: (np.maximum(lo, a), np.minimum(hi, b)),
        state_noise=BoundedNoise.symmetric(half),
        obs_noise=BoundedNoise.symmetric(half),
    )
    tracemalloc.start()
    try:
        with pytest.raises(MemoryBudgetError, match=r"16384 × 16384 boxes, eq\. 16"):
            DependentEvidenceFilter().run(model, np.zeros((3, 7)))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 256 * 2**20


def test_the_energy_without_theta_is_an_option_of_the_papers_filter():
    """energy_theta="left_out" changes Step 6's dependence (eqs. A1–A6) only.

    The estimates move a little, every path agrees, and the paper's definition stays the
    default.
    """
    model, Z, U = gauge_case()
    paper = DependentEvidenceFilter(start="mean_corrected")
    left_out = dataclasses.replace(paper, energy_theta="left_out")
    assert paper.energy_theta == "paper"
    a = paper.run_batch(model, Z[:2], U[:2])
    b = left_out.run_batch(model, Z[:2], U[:2])
    gap = np.abs(a.estimates - b.estimates)
    assert 0 < gap.max() < 1e-2
    np.testing.assert_array_equal(b.estimates[1], left_out.run(model, Z[1], U[1]).estimates)
    rec = left_out.run(model, Z[0], U[0], record=True)
    np.testing.assert_array_equal(rec.estimates, b.estimates[0])
    assert not np.allclose(
        rec.diagnostics["r12"][1:], paper.run(model, Z[0], U[0]).diagnostics["r12"][1:]
    )
    with pytest.raises(EvidenceError, match="energy_theta"):
        DependentEvidenceFilter(energy_theta="none")


@pytest.mark.parametrize("name", BUILT_IN)
def test_each_fast_path_gives_what_the_step_loop_gives(name):
    """A filter's vectorised _engine is a fast path of the base's step loop: the same numbers.

    The particle filter's runs of a batch draw from their own streams, and its public step
    from run 0's: one run is compared.
    """
    model, Z, U = gauge_case()
    flt = MAKERS[name]()
    runs = 1 if name == "particle" else Z.shape[0]
    guarded = flt._guarded(model)
    Z, U = Z[:runs], U[:runs, :, None]  # (R, T, m) and (R, T - 1, q), as run passes them
    fast = flt._engine(guarded, Z, U, np.arange(runs))
    loop = flt.step_loop(guarded, Z, U)
    assert type(flt)._engine is not Filter._engine  # a fast path of its own
    tol = TOLERANCE.get(name, 0.0)
    for got, want in zip(loop[:3], fast[:3], strict=True):
        np.testing.assert_allclose(got, want, rtol=tol, atol=0)
    assert set(loop.diagnostics) == set(fast.diagnostics) == set(flt.DIAGNOSTICS)


def test_a_filter_with_only_initialize_and_step_needs_nothing_else():
    """The README's filter defines neither _engine nor _bytes_per_run: the base runs it."""
    for hook in ("_engine", "_bytes_per_run", "_start_record"):
        assert hook not in vars(AlphaBetaFilter)
    model, Z, _ = walk_case()
    flt = AlphaBetaFilter()
    batch = flt.run_batch(model, Z)
    for r in range(Z.shape[0]):
        state = flt.initialize(model, Z[r, 0])
        for k in range(1, Z.shape[1]):
            state, record = flt.step(state, Z[r, k])
        np.testing.assert_array_equal(state.estimate, batch.estimates[r, -1])
        assert batch.diagnostics["residual"][r, -1] == record.residual
    assert np.isnan(batch.diagnostics["residual"][:, 0]).all()  # no start record: NaN
