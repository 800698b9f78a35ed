"""The paper's rivals.

Nassreddine's filter and its restart variant, the bounded-error filter, the (extended)
Kalman filter and the bootstrap particle filter.
"""

import dataclasses

import numpy as np
import pytest

from dstoolkit import EvidenceError, InconsistentDataError, TotalConflictError
from dstoolkit.errors import WorkLimitError
from dstoolkit.evidence import Boxes
from dstoolkit.evidence.boxes import cluster_boxes, merge_equal_boxes
from dstoolkit.filters import (
    BoundedErrorFilter,
    BoundedNoise,
    FilterResult,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    StateSpaceModel,
    finite_difference_jacobian,
    lotka_volterra,
    simulate_lotka_volterra,
    systematic_resample,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge

RIVALS = [
    NassreddineFilter(max_focal=16),
    NassreddineFilter(restart=True),
    BoundedErrorFilter(),
    KalmanFilter(),
    ParticleFilter(n_particles=300, seed=4),
]
IDS = ["nassreddine", "nassreddine_restart", "bounded_error", "kalman", "particle"]


def _random_walk(half_width_v: float, half_width_w: float) -> StateSpaceModel:
    """x_{k+1} = x_k + v, g(x) = x: the simplest model with a known answer."""

    def g_inverse(lo, hi, x_lo, x_hi):
        return np.maximum(lo, x_lo), np.minimum(hi, x_hi)

    return StateSpaceModel(
        f=lambda x, u=None: np.asarray(x, dtype=float),
        g=lambda x: np.asarray(x, dtype=float),
        g_inverse=g_inverse,
        state_noise=BoundedNoise.symmetric(half_width_v),
        obs_noise=BoundedNoise.symmetric(half_width_w),
        f_monotone=(1, 1),
        g_monotone=(1,),
        name="random walk",
    )


@pytest.fixture(scope="module")
def lv_data():
    return simulate_lotka_volterra(40, runs=3, seed=21)


# -- known truth ------------------------------------------------------------------------------
@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_noise_free_gauge_gives_the_truth_back(flt):
    """Zero-width noises on the gauge model (g = identity): every estimate is the truth."""
    silent = BoundedNoise.symmetric(0.0)
    model = gauge_state_space_model(silent, silent)
    orders = simulate_gauge().true_inputs
    truth, z = model.simulate([1008.5], orders.size + 1, np.random.default_rng(0), orders)
    result = flt.run(model, z, orders)
    # the truth up to the rounding of a few operations per step (other CPUs: other ulps)
    np.testing.assert_allclose(result.estimates, truth, rtol=1e-12)


@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_nearly_noise_free_lotka_volterra_gives_the_truth_back(flt):
    """Noise-free data, bounds of ±1e-7: the nonlinear 2-D truth comes back within 1e-5."""
    tiny = BoundedNoise.symmetric([1e-7, 1e-7])
    model = lotka_volterra(state_noise=tiny, obs_noise=tiny)
    silent = lotka_volterra(
        state_noise=BoundedNoise.symmetric([0.0, 0.0]), obs_noise=BoundedNoise.symmetric([0.0, 0.0])
    )
    _, x, z = simulate_lotka_volterra(30, model=silent, seed=0)
    result = flt.run(model, z)
    np.testing.assert_allclose(result.estimates, x, atol=1e-5)


@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_estimate_lies_within_the_hull_of_its_final_evidence(flt, lv_data):
    model, _, z = lv_data
    result = flt.run(model, z[0])
    assert isinstance(result, FilterResult) and result.method == flt.name
    assert result.estimates.shape == result.lower.shape == result.upper.shape == (40, 2)
    assert np.all(np.isfinite(result.estimates))
    assert np.all(result.lower <= result.estimates)
    assert np.all(result.estimates <= result.upper)


@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_batch_equals_single_runs(flt, lv_data):
    model, _, z = lv_data
    batch = flt.run_batch(model, z).estimates
    assert batch.shape == (3, 40, 2)
    for r in range(3):
        # run r of a particle batch draws from stream r, as a single run with stream=r
        single = (
            dataclasses.replace(flt, stream=r).run(model, z[r])
            if isinstance(flt, ParticleFilter)
            else flt.run(model, z[r])
        )
        np.testing.assert_array_equal(batch[r], single.estimates)


@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_batch_equals_single_runs_with_inputs(flt):
    model = gauge_state_space_model()
    seq = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=3, seed=5)
    batch = flt.run_batch(model, seq.readings, seq.inputs).estimates
    for r in range(3):
        one = dataclasses.replace(flt, stream=r) if isinstance(flt, ParticleFilter) else flt
        single = one.run(model, seq.readings[r], seq.inputs[r])
        np.testing.assert_array_equal(batch[r], single.estimates)


@pytest.mark.parametrize(
    "flt",
    [ParticleFilter(n_particles=200, seed=9), NassreddineFilter(max_focal=8)],
    ids=["particle", "nassreddine"],
)
def test_batch_rows_do_not_depend_on_chunking(flt, monkeypatch, lv_data):
    import dstoolkit.filters._nassreddine as nf_module
    import dstoolkit.filters._particle as pf_module

    model, _, z = lv_data
    whole = flt.run_batch(model, z).estimates
    for module in (pf_module, nf_module):
        monkeypatch.setattr(module, "CHUNK_BYTES", 1)  # one run per chunk
    np.testing.assert_array_equal(flt.run_batch(model, z).estimates, whole)


# -- the bounded-error filter -------------------------------------------------------------
def test_bounded_error_box_is_the_intersection_of_prediction_and_reading():
    model = _random_walk(0.1, 0.5)
    z = np.array([0.0, 0.3, -0.2])
    result = BoundedErrorFilter().run(model, z, record=True)
    # X1 = [−0.5, 0.5]; X2 = [−0.6, 0.6] ∩ [−0.2, 0.8] = [−0.2, 0.6];
    # X3 = [−0.3, 0.7] ∩ [−0.7, 0.3] = [−0.3, 0.3]
    np.testing.assert_allclose(result.lower[:, 0], [-0.5, -0.2, -0.3])
    np.testing.assert_allclose(result.upper[:, 0], [0.5, 0.6, 0.3])
    # midpoints of boxes with decimal ends: exact up to the rounding of 0.1, 0.3, …
    np.testing.assert_allclose(result.estimates[:, 0], [0.0, 0.2, 0.0], atol=1e-12)
    np.testing.assert_allclose(result.steps[2].prediction[0], [-0.3])


def test_bounded_error_reports_too_tight_bounds_with_the_step():
    model = _random_walk(0.1, 0.5)
    z = np.array([0.0, 0.3, 2.5, 2.6])  # step 2 jumps further than the bounds allow
    with pytest.raises(InconsistentDataError, match=r"step 2\b.*too tight"):
        BoundedErrorFilter().run(model, z)
    with pytest.raises(
        InconsistentDataError, match=r"step 2 \(reading z\[2\], counting from 0\) of run 1\b"
    ):
        BoundedErrorFilter().run_batch(model, np.stack([z * 0, z])[..., None])


def test_bounded_error_detects_tight_bounds_on_simulated_data():
    """Data drawn with the real noise, filtered with bounds ten times too tight."""
    model, _, z = simulate_lotka_volterra(60, seed=3)
    tight = lotka_volterra(
        state_noise=BoundedNoise.symmetric([0.003, 0.003]),
        obs_noise=BoundedNoise([-0.008] * 2, [-0.002] * 2, [0.004] * 2),
    )
    with pytest.raises(InconsistentDataError, match="probably too tight"):
        BoundedErrorFilter().run(tight, z)
    BoundedErrorFilter().run(model, z)  # the right bounds: no error


def test_bounded_error_reset_restarts_from_the_reading():
    model = _random_walk(0.1, 0.5)
    z = np.array([0.0, 0.3, 2.5, 2.6])
    result = BoundedErrorFilter(on_inconsistent="reset").run(model, z)
    np.testing.assert_array_equal(result.diagnostics["resets"], [False, False, True, False])
    np.testing.assert_allclose([result.lower[2, 0], result.upper[2, 0]], [2.0, 3.0])
    np.testing.assert_allclose([result.lower[3, 0], result.upper[3, 0]], [2.1, 3.1])


def test_bounded_error_rejects_unknown_policy():
    with pytest.raises(EvidenceError, match="on_inconsistent"):
        BoundedErrorFilter(on_inconsistent="ignore")


# -- Nassreddine's filter ---------------------------------------------------------------------
def test_nassreddine_first_step_is_the_reading_mapped_back():
    model = _random_walk(0.1, 0.3)
    result = NassreddineFilter(p=3, epsilon=0.05).run(model, [1.0, 1.0], record=True)
    post = result.steps[0].posterior
    # α-cuts of w: [−0.1, 0.1], [−0.2, 0.2], [−0.3, 0.3]; Θ becomes the last one (merged)
    np.testing.assert_allclose(np.sort(post.hi_1d), [1.1, 1.2, 1.3])
    np.testing.assert_allclose(np.sort(post.mass), [0.95 / 3, 0.95 / 3, 0.95 / 3 + 0.05])
    assert result.estimates[0, 0] == pytest.approx(1.0)


def test_nassreddine_diagnostics_stay_in_range(lv_data):
    model, _, z = lv_data
    result = NassreddineFilter(max_focal=16).run(model, z[1], record=True)
    k = result.diagnostics["conflict"]
    assert np.isnan(k[0]) and np.all((k[1:] >= 0) & (k[1:] < 1))
    assert np.all(result.diagnostics["focal_elements"] >= 1)
    merged = result.diagnostics["merged_mass"]
    assert np.all((merged >= 0) & (merged <= 1 + 1e-12)) and merged.max() > 0
    for step in result.steps:
        assert step.posterior.mass.sum() == pytest.approx(1.0)
    assert all(
        getattr(result.steps[1], key) is not None
        for key in ("state", "prediction", "observation", "posterior", "estimate")
    )
    assert len(result.steps[1].state) <= 16


@pytest.mark.parametrize("kernel", ["numpy", pytest.param("numba", marks=pytest.mark.extras)])
def test_nassreddine_total_conflict_raises_or_resets(kernel):
    model = _random_walk(0.1, 0.5)
    z = np.array([0.0, 0.3, 2.5, 2.6])
    with pytest.raises(TotalConflictError, match=r"step 2\b"):
        NassreddineFilter(epsilon=0.0, kernel=kernel).run(model, z)
    result = NassreddineFilter(epsilon=0.0, on_conflict="reset", kernel=kernel).run(model, z)
    np.testing.assert_array_equal(result.diagnostics["resets"], [False, False, True, False])
    assert result.estimates[2, 0] == pytest.approx(2.5)
    batch = np.stack([z, z + 0.05, np.array([0.0, 0.3, 0.4, 0.5])])[..., None]
    # one run in conflict, one not: the same numbers
    both = [
        NassreddineFilter(epsilon=0.0, on_conflict="reset", kernel=k)
        .run_batch(model, batch)
        .estimates
        for k in ("numpy", kernel)
    ]
    np.testing.assert_array_equal(*both)


def test_merge_equal_boxes_adds_masses_per_run():
    lo = np.array([[[0.0], [1.0], [0.0], [2.0]], [[5.0], [5.0], [5.0], [6.0]]])
    hi = lo + 1.0
    mass = np.array([[0.25, 0.25, 0.5, 0.0], [0.1, 0.2, 0.3, 0.4]])
    out = merge_equal_boxes(lo, hi, mass)
    assert out.mass.shape == (2, 2)
    got = {
        (r, float(a)): float(m)
        for r in range(2)
        for a, m in zip(out.lo[r, :, 0], out.mass[r], strict=True)
        if m > 0
    }
    assert got == pytest.approx({(0, 0.0): 0.75, (0, 1.0): 0.25, (1, 5.0): 0.6, (1, 6.0): 0.4})


def test_cluster_boxes_is_an_outer_approximation_within_the_cap():
    rng = np.random.default_rng(2)
    centre = rng.normal(size=(2, 200, 2))
    half = rng.uniform(0.01, 0.5, size=(2, 200, 2))
    mass = rng.uniform(size=(2, 200))
    mass /= mass.sum(axis=1, keepdims=True)
    bm = Boxes(centre - half, centre + half, mass)
    out, merged = cluster_boxes(bm, 12)
    assert np.all((out.mass > 0).sum(axis=1) <= 12)
    np.testing.assert_allclose(out.mass.sum(axis=1), 1.0)
    assert np.all((merged > 0) & (merged <= 1 + 1e-12))
    for r in range(2):  # every original box lies in some output box
        keep = out.mass[r] > 0
        inside = (
            (bm.lo[r][:, None] >= out.lo[r][keep][None])
            & (bm.hi[r][:, None] <= out.hi[r][keep][None])
        ).all(-1)
        assert inside.any(axis=1).all()
        # belief never grows: each output box's mass covers the boxes it contains
        contained = inside.T @ bm.mass[r]
        assert np.all(out.mass[r, keep] <= contained + 1e-12)


def test_restart_variant_rebuilds_from_the_estimate(lv_data):
    model, _, z = lv_data
    result = NassreddineFilter(restart=True).run(model, z[0], record=True)
    state = result.steps[5].state
    v = model.state_noise.evidence(3, 0.05)
    np.testing.assert_allclose(state.boxes_lo, v.boxes_lo + result.estimates[4])
    assert result.method == "nassreddine"


# -- Kalman and particle filters ---------------------------------------------------------------
def test_kalman_on_a_linear_model_matches_the_textbook_recursion():
    model = _random_walk(0.3, 0.6)
    z = np.array([0.1, 0.4, -0.2, 0.3])
    result = KalmanFilter().run(model, z)
    q, r = model.state_noise.variance[0], model.obs_noise.variance[0]
    x, p = z[0], (1.2**2) / 12  # start: centre and uniform variance of [z − 0.6, z + 0.6]
    for k in range(1, 4):
        p = p + q
        gain = p / (p + r)
        x, p = x + gain * (z[k] - x), (1 - gain) * p
        assert result.estimates[k, 0] == pytest.approx(x, rel=1e-12)
    assert result.upper[3, 0] - result.lower[3, 0] == pytest.approx(6 * np.sqrt(p))


def test_kalman_uses_the_noise_means_with_the_sign_convention():
    """g(x) = z + w: with E[w] = −0.2 the reading is 0.2 high on average."""
    model = StateSpaceModel(
        f=lambda x, u=None: x,
        g=lambda x: x,
        g_inverse=lambda lo, hi, a, b: (np.maximum(lo, a), np.minimum(hi, b)),
        state_noise=BoundedNoise.symmetric(1e-6),
        obs_noise=BoundedNoise(-0.4, -0.2, 0.0),
    )
    result = KalmanFilter().run(model, np.full(200, 5.2))
    assert result.estimates[-1, 0] == pytest.approx(5.0, abs=1e-3)


def _plain_gauge_model():
    """Eqs. 39–40 as a user writes them: plain numpy maps, no Jacobians."""
    package = gauge_state_space_model()
    return StateSpaceModel(
        f=lambda x, u: x * (u + 1.0) / u,
        g=lambda x: x + 0.0,
        g_inverse=lambda lo, hi, a, b: (np.maximum(lo, a), np.minimum(hi, b)),
        state_noise=package.state_noise,
        obs_noise=package.obs_noise,
    )


@pytest.mark.parametrize("plain", [False, True], ids=["package", "plain"])
def test_kalman_one_run_equals_its_run_in_a_batch_exactly(plain):
    """One run (floats) and a batch ((R,) arrays) run the same recursion: the same numbers.

    So they do with the model's Jacobians (the package's gauge) or central differences (a
    user's).
    """
    model = _plain_gauge_model() if plain else gauge_state_space_model()
    seq = simulate_gauge(9.6, runs=4, seed=2)
    batch = KalmanFilter().run_batch(model, seq.readings, seq.inputs)
    for r in range(4):
        one = KalmanFilter().run(model, seq.readings[r], seq.inputs[r])
        for name in ("estimates", "lower", "upper"):
            np.testing.assert_array_equal(getattr(one, name), getattr(batch[r], name))
        np.testing.assert_array_equal(one.diagnostics["nis"], batch.diagnostics["nis"][r])


@pytest.mark.parametrize("level", [0.6, 9.6])
def test_kalman_on_a_users_plain_maps_gives_the_package_numbers(level):
    """Central differences of a user's eqs. 39–40 give the package's analytic slopes' numbers.

    They agree to 1e-9 Hz: the model needs no Jacobians and no float copy of its maps.
    """
    seq = simulate_gauge(level, seed=2)
    package = KalmanFilter().run(gauge_state_space_model(), seq.readings, seq.inputs)
    plain = KalmanFilter().run(_plain_gauge_model(), seq.readings, seq.inputs)
    for name in ("estimates", "lower", "upper"):
        np.testing.assert_allclose(getattr(plain, name), getattr(package, name), rtol=0, atol=1e-9)


@pytest.mark.parametrize("flt", RIVALS, ids=IDS)
def test_every_transition_input_is_checked_before_the_run(flt):
    """A non-positive order n_k at the last transition, or no orders at all, is refused.

    The gauge's f refuses it at the door (eq. 39 divides by n_k), whatever path the filter
    takes.
    """
    model = gauge_state_space_model()
    seq = simulate_gauge(seed=0)
    orders = seq.inputs.astype(float)
    orders[-1] = 0.0
    with pytest.raises(EvidenceError, match="orders n_k must be positive"):
        flt.run(model, seq.readings, orders)
    with pytest.raises(EvidenceError, match="needs the order n_k"):
        flt.run(model, seq.readings)


def test_finite_difference_jacobian_matches_the_model_jacobian():
    model = lotka_volterra()
    x = np.array([[0.3, -0.2], [1.0, 0.5]])
    np.testing.assert_allclose(
        finite_difference_jacobian(lambda y: model.f(y), x), model.jacobian_f(x), rtol=1e-8
    )
    np.testing.assert_allclose(
        finite_difference_jacobian(model.g, x), model.jacobian_g(x), rtol=1e-8
    )


def test_systematic_resampling_counts_and_zero_weights():
    w = np.array([[0.5, 0.0, 0.25, 0.25], [0.0, 0.0, 1.0, 0.0]])
    idx = systematic_resample(w, np.array([0.3, 0.9]))
    np.testing.assert_array_equal(np.bincount(idx[0], minlength=4), [2, 0, 1, 1])
    np.testing.assert_array_equal(idx[1], [2, 2, 2, 2])


def test_particle_likelihood_respects_the_bounded_support():
    """Every weighted particle implies an observation noise inside its support."""
    model, _, z = simulate_lotka_volterra(20, seed=8)
    result = ParticleFilter(n_particles=400, seed=1).run(model, z, record=True)
    for k, step in enumerate(result.steps):
        live = step.weights > 0
        w = model.g(step.particles[live]) - z[k]
        assert np.all((w >= model.obs_noise.lower) & (w <= model.obs_noise.upper))


def test_particle_degeneracy_reinitialises_from_the_reading():
    model = _random_walk(0.1, 0.5)
    z = np.array([0.0, 0.3, 2.5, 2.6])  # no particle can reach the reading at step 2
    result = ParticleFilter(n_particles=200, seed=0).run(model, z)
    np.testing.assert_array_equal(result.diagnostics["reinitialised"], [False, False, True, False])
    assert 2.0 <= result.lower[2, 0] and result.upper[2, 0] <= 3.0
    assert result.estimates[2, 0] == pytest.approx(2.5, abs=0.1)


def test_particle_filter_is_reproducible_and_seeded():
    model, _, z = simulate_lotka_volterra(15, seed=2)
    a = ParticleFilter(n_particles=100, seed=3).run(model, z).estimates
    b = ParticleFilter(n_particles=100, seed=3).run(model, z).estimates
    c = ParticleFilter(n_particles=100, seed=4).run(model, z).estimates
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_bad_readings_are_reported():
    model = lotka_volterra()
    with pytest.raises(EvidenceError, match="shape"):
        KalmanFilter().run(model, np.zeros((5, 3)))
    with pytest.raises(EvidenceError, match="not a finite number"):
        BoundedErrorFilter().run_batch(model, np.full((2, 4, 2), np.nan))


def test_nassreddine_keeps_unit_mass_under_heavy_conflict():
    """Regression: renormalising by 1 − K let rounding losses grow by 1/(1 − K) per step.

    The posterior then held half its mass and the estimate was pulled towards 0.
    """
    from dstoolkit.gauge import GAUGE_OBS_NOISE, GAUGE_STATE_NOISE, gauge_state_space_model
    from dstoolkit.studies import scaled_noise, tracking_data

    data = tracking_data(runs=3, seed=0)
    model = gauge_state_space_model(
        scaled_noise(GAUGE_STATE_NOISE, 0.25), scaled_noise(GAUGE_OBS_NOISE, 0.25)
    )
    run = NassreddineFilter(on_conflict="reset").run(
        model, data.readings[2][:, None], inputs=data.orders[2], record=True
    )
    for k, step in enumerate(run.steps):
        assert run.estimates[k, 0] == pytest.approx(
            step.posterior.pignistic_expectation_1d(), rel=1e-9
        )
    assert np.all(run.lower[:, 0] <= run.estimates[:, 0] + 1e-9)
    assert np.all(run.estimates[:, 0] <= run.upper[:, 0] + 1e-9)


# -- Nassreddine's kernels: numpy, compiled (extra "speed"), or whichever is installed ------


def test_nassreddine_kernel_must_be_named():
    with pytest.raises(EvidenceError, match="kernel"):
        NassreddineFilter(kernel="fortran")


def test_nassreddine_auto_kernel_falls_back_to_numpy_without_numba(monkeypatch):
    import importlib.util

    from dstoolkit.filters import _nassreddine

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "numba" else real(name, *a)
    )
    combine, cluster, _ = NassreddineFilter(kernel="auto")._kernels()
    assert combine is _nassreddine.contracted_posterior
    assert cluster is cluster_boxes


@pytest.mark.extras  # numba, the extra "speed"
def test_compiled_kernels_raise_the_numpy_errors():
    from dstoolkit.evidence.boxes import cluster_boxes_compiled

    lo = np.array([[[0.0], [1.0], [2.0]]])
    hi = np.array([[[1.0], [np.inf], [3.0]]])
    bm = Boxes(lo, hi, np.array([[0.3, 0.3, 0.4]]))
    with pytest.raises(EvidenceError, match="bounded boxes"):
        cluster_boxes_compiled(bm, 2, 100)
    wide = Boxes(
        np.arange(40.0)[None, :, None],
        np.arange(40.0)[None, :, None] + 0.5,
        np.full((1, 40), 1 / 40),
    )
    with pytest.raises(WorkLimitError, match="did not reach"):
        cluster_boxes_compiled(wide, 2, 1)
    (capped, moved), (want, want_moved) = (
        cluster_boxes_compiled(wide, 2, 100),
        cluster_boxes(wide, 2),
    )
    np.testing.assert_array_equal(capped.mass, want.mass)
    assert moved[0] == want_moved[0] > 0


def test_particle_draws_kept_for_the_same_runs_give_the_same_numbers():
    """The pre-drawn numbers of a small batch are kept for the next batch of the same runs.

    Kept for the same runs and state noise (an explorer moving the observation noise's
    bounds): the estimates are those of fresh draws, and the kept arrays cannot be changed.
    """
    from dstoolkit.filters import _particle

    gauge = simulate_gauge(4.6, 26.5, runs=3, seed=4)
    flt = ParticleFilter(n_particles=200, seed=5)
    models = [
        gauge_state_space_model(obs_noise=BoundedNoise(-10.59, -6.9, upper))
        for upper in (-3.21, -2.0)
    ]
    _particle._kept_draws.cache_clear()
    kept = [flt.run_batch(m, gauge.readings, gauge.inputs).estimates for m in models]
    assert _particle._kept_draws.cache_info().hits == 1
    for model, estimates in zip(models, kept, strict=True):
        _particle._kept_draws.cache_clear()
        np.testing.assert_array_equal(
            estimates, flt.run_batch(model, gauge.readings, gauge.inputs).estimates
        )
    arrays = _particle._kept_draws(5, (0, 1, 2), ((-0.3,), (0.0,), (0.3,)), 4, 10)
    assert not any(a.flags.writeable for a in arrays)


@pytest.mark.extras  # numba, the extra "speed"
def test_particle_compiled_resampling_gives_the_same_indices_and_estimates():
    rng = np.random.default_rng(8)
    for case in range(200):
        runs, n = int(rng.integers(1, 6)), int(rng.integers(1, 600))
        w = rng.random((runs, n)) ** (1 + case % 7) * (rng.random((runs, n)) > 0.5 * (case % 2))
        w[:, 0] += 1e-9
        w /= w.sum(axis=1, keepdims=True)
        offsets = rng.random(runs) * (case % 5 != 0)  # some offsets 0
        np.testing.assert_array_equal(
            systematic_resample(w, offsets, compiled=True), systematic_resample(w, offsets)
        )
    gauge = simulate_gauge(4.6, 26.5, runs=4, seed=3)
    model = gauge_state_space_model()
    np.testing.assert_array_equal(
        ParticleFilter(n_particles=300, kernel="numba")
        .run_batch(model, gauge.readings, gauge.inputs)
        .estimates,
        ParticleFilter(n_particles=300).run_batch(model, gauge.readings, gauge.inputs).estimates,
    )


@pytest.mark.parametrize("plain", [False, True], ids=["package", "plain"])
def test_kalman_scalar_recursion_equals_the_matrix_recursion(plain):
    """For n = m = 1 the term-by-term recursion gives the matrix recursion's numbers.

    The same operations, grouped differently: equal to rounding.
    """
    model = _plain_gauge_model() if plain else gauge_state_space_model()
    seq = simulate_gauge(9.6, runs=3, seed=4)
    flt = KalmanFilter()
    from dstoolkit.filters._model import batch_readings

    z, u = batch_readings(model, seq.readings, seq.inputs)
    guarded = flt._guarded(model)
    x1, p1, nis1 = flt._filter_scalar(guarded, z, u)
    x2, p2, nis2 = flt._filter(guarded, z, u)
    np.testing.assert_allclose(x1, x2, rtol=1e-12)
    np.testing.assert_allclose(p1, p2, rtol=1e-9)
    np.testing.assert_allclose(nis1[:, 1:], nis2[:, 1:], rtol=1e-8)


@pytest.mark.parametrize("infinite", ["f", "g"])
def test_kalman_names_a_map_that_turns_infinite_where_it_linearises(infinite: str) -> None:
    """An infinite value of f or g at the estimate is refused by name, not as a later NaN."""

    def f(x, u=None):
        return np.full_like(x, np.inf) if infinite == "f" else x

    def g(x, u=None):
        return np.full_like(x, np.inf) if infinite == "g" else 2.0 * x

    model = StateSpaceModel(
        f,
        g,
        BoundedNoise(-0.1, 0.0, 0.1),
        BoundedNoise(-1.0, 0.0, 1.0),
        g_inverse=lambda lo, hi, x_lo, x_hi: (lo / 2.0, hi / 2.0),
    )
    readings = np.linspace(2.0, 3.0, 6)[:, None]
    for call in (
        lambda: KalmanFilter().run(model, readings),
        lambda: KalmanFilter().run_batch(model, np.stack([readings, readings])),
    ):
        with pytest.raises(EvidenceError, match=f"the model's {infinite} gave inf"):
            call()


@pytest.mark.parametrize(
    "jacobian",
    [lambda x, u=None: [[1.0]], lambda x, u=None: "one", lambda x, u=None: [1.0, 1.0, 1.0]],
)
def test_kalman_names_a_jacobian_of_the_wrong_shape(jacobian) -> None:
    """A Jacobian with too few, too many or no numbers is refused by the package's error."""
    model = StateSpaceModel(
        lambda x, u=None: x,
        lambda x, u=None: 2.0 * x,
        BoundedNoise(-0.1, 0.0, 0.1),
        BoundedNoise(-1.0, 0.0, 1.0),
        g_inverse=lambda lo, hi, x_lo, x_hi: (lo / 2.0, hi / 2.0),
        jacobian_f=jacobian,
    )
    readings = np.linspace(2.0, 3.0, 6)[:, None]
    with pytest.raises(EvidenceError, match="jacobian_f gave"):
        KalmanFilter().run_batch(model, np.stack([readings, readings]))
    if jacobian(None) != [[1.0]]:  # one slope is right for one run
        with pytest.raises(EvidenceError, match="jacobian_f gave"):
            KalmanFilter().run(model, readings)
