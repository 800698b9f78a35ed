"""The second, nonlinear example (predator–prey in log-populations) and every filter on it."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit.evidence import box_image, image_subdivision
from dstoolkit.filters import (
    LOTKA_VOLTERRA_X0,
    BoundedErrorFilter,
    BoundedNoise,
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    lotka_volterra,
    simulate_lotka_volterra,
)

MODEL = lotka_volterra()


def test_model_shape_and_defaults():
    assert MODEL.state_dim == MODEL.obs_dim == 2
    assert MODEL.g_monotone == (1, 1) and MODEL.f_monotone is None
    np.testing.assert_allclose(MODEL.obs_noise.mean, [-0.02, -0.02])
    # equilibrium P = Q = 1 (log 0) is a fixed point of f
    # exact in floating point (exp(0) = 1 on every CPU); the tolerance only names "zero"
    np.testing.assert_allclose(MODEL.f(np.zeros(2)), [0.0, 0.0], atol=1e-15)


def test_simulation_follows_the_model_within_the_noise_bounds():
    model, x, z = simulate_lotka_volterra(80, runs=5, seed=3)
    assert x.shape == z.shape == (5, 80, 2)
    np.testing.assert_allclose(x[:, 0], np.broadcast_to(LOTKA_VOLTERRA_X0, (5, 2)))
    v = x[:, 1:] - model.f(x[:, :-1])
    w = model.g(x) - z
    assert np.all((v >= model.state_noise.lower) & (v <= model.state_noise.upper))
    assert np.all((w >= model.obs_noise.lower) & (w <= model.obs_noise.upper))
    _, x2, z2 = simulate_lotka_volterra(80, runs=5, seed=3)
    np.testing.assert_array_equal(z, z2)
    populations = np.exp(x)
    assert populations.min() > 0.1 and populations.max() > 2.5  # a real cycle, wide range


@settings(max_examples=60, deadline=None)
@given(
    a=st.floats(-1.0, 4.0),
    width=st.floats(0.0, 3.0),
    p_lo=st.floats(-3.0, 1.0),
    p_width=st.floats(0.0, 4.0),
)
def test_g_inverse_is_the_exact_preimage_within_the_prior(a, width, p_lo, p_width):
    lo, hi = np.array([a, a + 0.5]), np.array([a + width, a + 0.5 + width])
    x_lo, x_hi = np.full(2, p_lo), np.full(2, p_lo + p_width)
    c_lo, c_hi = MODEL.g_inverse(lo, hi, x_lo, x_hi)
    grid = np.linspace(p_lo, p_lo + p_width, 401)
    for d in range(2):
        inside = grid[(np.exp(grid) >= lo[d]) & (np.exp(grid) <= hi[d])]
        if inside.size == 0:
            # empty, or a sliver narrower than the grid spacing
            assert c_lo[d] > c_hi[d] or c_hi[d] - c_lo[d] <= p_width / 400 + 1e-12
        else:
            assert c_lo[d] <= inside.min() + 1e-12 and inside.max() <= c_hi[d] + 1e-12
            assert c_lo[d] >= x_lo[d] and c_hi[d] <= x_hi[d]
            assert np.exp(c_lo[d]) >= lo[d] - 1e-12 and np.exp(c_hi[d]) <= hi[d] * (1 + 1e-12)


def test_g_inverse_of_non_positive_readings():
    """g⁻¹ of a census box reaching below 0 says nothing about the lower end.

    One wholly below 0 is impossible (empty).
    """
    lo, hi = MODEL.g_inverse(
        np.array([-1.0, -2.0]), np.array([2.0, -0.5]), np.array([-5.0, -5.0]), np.array([5.0, 5.0])
    )
    assert lo[0] == -5.0 and hi[0] == pytest.approx(np.log(2.0))
    assert lo[1] > hi[1]


def test_vertex_images_are_exact_even_on_wide_boxes():
    """The vertex method (4 evaluations) equals a fine subdivision, even on wide boxes.

    Each component of f is monotone in each argument on the whole plane, so the two agree,
    with no warning, on boxes as wide as the frames Θ of the discount.
    """
    rng = np.random.default_rng(0)
    centre = rng.uniform(-2, 1.5, size=(200, 2))
    half = rng.uniform(0.0, 1.0, size=(200, 2))
    lo, hi = centre - half, centre + half
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v_lo, v_hi = box_image(MODEL.f, lo, hi, MODEL.f_monotone)
    s_lo, s_hi = image_subdivision(lo, hi, MODEL.f)
    np.testing.assert_allclose(v_lo, s_lo, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(v_hi, s_hi, rtol=1e-12, atol=1e-12)


def test_jacobians_match_central_differences():
    x = np.array([[0.2, -0.4], [1.1, 0.7]])
    h = 1e-6
    for fn, jac in ((MODEL.f, MODEL.jacobian_f), (MODEL.g, MODEL.jacobian_g)):
        numeric = np.stack([(fn(x + h * e) - fn(x - h * e)) / (2 * h) for e in np.eye(2)], axis=-1)
        np.testing.assert_allclose(jac(x), numeric, rtol=1e-7)


def test_bad_parameters_are_reported():
    with pytest.raises(ValueError, match="positive"):
        lotka_volterra(h=-0.1)
    with pytest.raises(ValueError, match="two-dimensional"):
        lotka_volterra(state_noise=BoundedNoise.symmetric(0.03))


# -- every filter on the 2-D example ---------------------------------------------------------
FILTERS = [
    DependentEvidenceFilter(p=2),  # p = 3 costs about 0.1 s per step in 2-D
    NassreddineFilter(),
    NassreddineFilter(restart=True),
    BoundedErrorFilter(),
    KalmanFilter(),
    ParticleFilter(n_particles=500, seed=0),
]


@pytest.fixture(scope="module")
def lv_runs():
    model, x, z = simulate_lotka_volterra(60, runs=4, seed=33)
    return model, x, z


@pytest.mark.parametrize("flt", FILTERS, ids=lambda f: f.name)
def test_every_filter_tracks_the_two_dimensional_example(flt, lv_runs):
    """Every filter stays within bounds a broken filter misses, in log-population units.

    The bounds, on the RMSE over 4 × 60 steps:

    - below 0.9 × the RMSE of inverting each reading alone, g⁻¹(z + E[w]): a filter that
      ignores the dynamics (or its prediction) only matches it;
    - below 1/10 of holding the first estimate: a filter that ignores the readings drifts;
    - a mean error below half the bias a sign error in g(x) = z + w would cause,
      |E[w]| · mean(1/P) (reading z − w instead of z + w shifts the census by 2|E[w]|).
    """
    model, x, z = lv_runs
    est = flt.run_batch(model, z).estimates
    assert est.shape == x.shape
    rmse = np.sqrt(np.mean((est - x) ** 2, axis=(0, 1)))
    direct = np.log(np.maximum(z + model.obs_noise.mean, 1e-9))
    rmse_direct = np.sqrt(np.mean((direct - x) ** 2, axis=(0, 1)))
    rmse_hold = np.sqrt(np.mean((est[:, :1] - x) ** 2, axis=(0, 1)))
    bias = np.abs(np.mean(est - x, axis=(0, 1)))
    sign_error_bias = 2 * np.abs(model.obs_noise.mean) * np.mean(np.exp(-x), axis=(0, 1))
    assert np.all(rmse < 0.9 * rmse_direct), (rmse, rmse_direct)
    assert np.all(rmse < rmse_hold / 10), (rmse, rmse_hold)
    assert np.all(bias < sign_error_bias / 2), (bias, sign_error_bias)
