"""The unscented filter, the RTS smoother and the NEES/NIS checks against outside peers.

filterpy's UnscentedKalmanFilter (with MerweScaledSigmaPoints) and KalmanFilter.rts_smoother
are the peers of the filter and the smoother; scipy.stats.chi2 of the χ² band; hand
computations of NEES and NIS.
"""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter as PeerKalman
from filterpy.kalman import MerweScaledSigmaPoints
from filterpy.kalman import UnscentedKalmanFilter as PeerUnscented
from scipy.stats import chi2

from dstoolkit.errors import EvidenceError, InconsistentDataError
from dstoolkit.filters import (
    BoundedNoise,
    KalmanFilter,
    KalmanState,
    StateSpaceModel,
    UnscentedKalmanFilter,
    UnscentedState,
    chi2_band,
    nees,
    nis,
    random_walk,
    rts_smoother,
    sigma_points,
    sigma_weights,
    smooth_kalman,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge
from dstoolkit.studies import gauge_consistency
from dstoolkit.teaching import consistency_explorer
from dstoolkit.teaching._explorers_recursion import verdict

#: Two implementations of the same arithmetic in different orders (Cholesky factors of
#: different triangles, sums over sigma points in different orders) agree to rounding,
#: about 1e-13 relative on these well-conditioned cases; 1e-9 is the brief's bar.
PEER_TOL = 1e-9
CASES = 50


def linear_case(seed: int):
    """Return a random linear-Gaussian model x' = F x + v, z = H x − w, n = 2 or 3, m = 1 or 2."""
    rng = np.random.default_rng(seed)
    n, m = int(rng.integers(2, 4)), int(rng.integers(1, 3))
    f_mat = np.eye(n) + 0.3 * rng.standard_normal((n, n))
    h_mat = rng.standard_normal((m, n))
    v_half, w_half = rng.uniform(0.1, 1.0, n), rng.uniform(0.2, 2.0, m)
    model = StateSpaceModel(
        f=lambda x, u: x @ f_mat.T,
        g=lambda x: x @ h_mat.T,
        state_noise=BoundedNoise(-v_half, np.zeros(n), v_half),
        obs_noise=BoundedNoise(-w_half, np.zeros(m), w_half),
    )
    x0 = rng.standard_normal(n)
    p0 = np.diag(rng.uniform(0.5, 2.0, n))
    z = rng.standard_normal((20, m)) * 2.0
    return model, f_mat, h_mat, x0, p0, z


def start(model, x0, p0):
    """Return the unscented filter's state at (x0, P0) (as filterpy is started)."""
    sigma = np.sqrt(np.diag(p0))
    return UnscentedState(model, 1, x0, x0 - 3 * sigma, x0 + 3 * sigma, p0)


@pytest.mark.parametrize("seed", range(CASES))
def test_the_unscented_filter_is_filterpys(seed):
    model, f_mat, h_mat, x0, p0, z = linear_case(seed)
    rng = np.random.default_rng(1000 + seed)
    alpha, beta, kappa = rng.uniform(0.5, 1.5), rng.uniform(0.0, 3.0), rng.uniform(0.0, 2.0)
    n, m = f_mat.shape[0], h_mat.shape[0]
    peer = PeerUnscented(
        dim_x=n,
        dim_z=m,
        dt=1.0,
        fx=lambda x, dt: f_mat @ x,
        hx=lambda x: h_mat @ x,
        points=MerweScaledSigmaPoints(n, alpha=alpha, beta=beta, kappa=kappa),
    )
    peer.x, peer.P = x0.copy(), p0.copy()
    peer.Q = np.diag(model.state_noise.variance)
    peer.R = np.diag(model.obs_noise.variance)
    flt = UnscentedKalmanFilter(alpha=alpha, beta=beta, kappa=kappa)
    state = start(model, x0, p0)
    for reading in z:
        peer.predict()
        peer.update(reading)
        state, record = flt.step(state, reading)
        np.testing.assert_allclose(state.estimate, peer.x, rtol=PEER_TOL, atol=PEER_TOL)
        np.testing.assert_allclose(state.covariance, peer.P, rtol=PEER_TOL, atol=PEER_TOL)
        np.testing.assert_allclose(record.innovation_covariance, peer.S, rtol=PEER_TOL)


@pytest.mark.parametrize("seed", range(CASES))
def test_the_rts_smoother_is_filterpys(seed):
    model, f_mat, h_mat, x0, p0, z = linear_case(seed)
    n, m = f_mat.shape[0], h_mat.shape[0]
    q_cov, r_cov = np.diag(model.state_noise.variance), np.diag(model.obs_noise.variance)
    peer = PeerKalman(dim_x=n, dim_z=m)
    peer.x, peer.P, peer.F, peer.H, peer.Q, peer.R = (
        x0.copy(),
        p0.copy(),
        f_mat,
        h_mat,
        q_cov,
        r_cov,
    )
    xs, ps = [], []
    for reading in z:
        peer.predict()
        peer.update(reading)
        xs.append(peer.x.copy())
        ps.append(peer.P.copy())
    xs, ps = np.array(xs), np.array(ps)
    want_x, want_p, want_gain, _ = peer.rts_smoother(xs, ps)
    got = rts_smoother(xs, ps, f_mat, q_cov)
    np.testing.assert_allclose(got.estimates, want_x, rtol=PEER_TOL, atol=PEER_TOL)
    np.testing.assert_allclose(got.covariances, want_p, rtol=PEER_TOL, atol=PEER_TOL)
    np.testing.assert_allclose(got.gains[:-1], want_gain[:-1], rtol=PEER_TOL, atol=PEER_TOL)


def test_the_unscented_filter_is_the_kalman_filter_on_the_linear_gauge():
    """Eq. 39 is linear in x and g(x) = x: the sigma points carry mean and covariance exactly."""
    seq = simulate_gauge(4.6, 26.5, seed=3)
    model = gauge_state_space_model()
    ukf = UnscentedKalmanFilter(alpha=0.5, kappa=2.0).run(model, seq.readings, seq.inputs)
    kf = KalmanFilter().run(model, seq.readings, seq.inputs)
    # rounding of sums over three sigma points of frequencies near 2 kHz
    np.testing.assert_allclose(ukf.estimates, kf.estimates, rtol=1e-12)
    np.testing.assert_allclose(ukf.diagnostics["nis"][1:], kf.diagnostics["nis"][1:], rtol=1e-8)


def test_on_a_nonlinear_map_the_unscented_mean_is_the_second_order_one():
    """f(x) = x²: the unscented prediction has the true mean x̂² + P; the EKF's misses P."""
    model = StateSpaceModel(
        f=lambda x, u: x**2,
        g=lambda x: x,
        state_noise=BoundedNoise.symmetric(0.0),
        obs_noise=BoundedNoise.symmetric(1.0),
    )
    state = start(model, np.array([2.0]), np.array([[0.5]]))
    _, record = UnscentedKalmanFilter().step(state, 4.5)
    assert record.prediction[0] == pytest.approx(4.5, rel=1e-14)  # x̂² + P
    kalman_state = KalmanState(
        model, 1, np.array([2.0]), np.array([0.0]), np.array([4.0]), np.array([[0.5]])
    )
    _, kalman_record = KalmanFilter().step(kalman_state, 4.5)
    assert kalman_record.prediction[0] == pytest.approx(4.0, rel=1e-14)


def test_sigma_points_carry_the_mean_and_covariance():
    rng = np.random.default_rng(5)
    a = rng.standard_normal((3, 3))
    cov, mean = a @ a.T + np.eye(3), rng.standard_normal(3)
    scale, wm, wc = sigma_weights(3, 0.7, 2.0, 1.0)
    pts = sigma_points(mean, cov, float(scale))
    assert pts.shape == (7, 3)
    np.testing.assert_allclose(wm @ pts, mean, atol=1e-12)
    d = pts - mean
    # W^c_0 differs from W^m_0 but multiplies a zero deviation
    np.testing.assert_allclose((wc * d.T) @ d, cov, atol=1e-12)
    assert wm.sum() == pytest.approx(1.0, abs=1e-15)


def test_the_unscented_filter_refuses_bad_options_and_states():
    with pytest.raises(EvidenceError, match="alpha"):
        UnscentedKalmanFilter(alpha=0.0)
    with pytest.raises(EvidenceError, match="kappa"):
        UnscentedKalmanFilter(kappa=-1.0).run(random_walk(0.1, 0.5), [1.0, 1.1])
    with pytest.raises(EvidenceError, match="UnscentedState"):
        UnscentedKalmanFilter().step(KalmanFilter().initialize(random_walk(0.1, 0.5), 1.0), 1.0)


def test_a_noise_free_model_refuses_a_reading_it_cannot_explain():
    model = random_walk(0.0, 0.0)
    flt = UnscentedKalmanFilter()
    state = flt.initialize(model, 1.0)
    assert flt.step(state, 1.0)[0].estimate.tolist() == [1.0]
    with pytest.raises(InconsistentDataError, match="S = 0"):
        flt.step(state, 2.0)


def test_nees_and_nis_by_hand():
    # e = (1, 2), P = [[2, 1], [1, 2]]: P⁻¹ = [[2, −1], [−1, 2]]/3, eᵀP⁻¹e = (2 − 4 + 8)/3 = 2
    assert nees([1.0, 2.0], [[2.0, 1.0], [1.0, 2.0]]) == pytest.approx(2.0, rel=1e-15)
    # scalar: ν = 3, S = 4 → 9/4, vectorised over steps
    np.testing.assert_allclose(nis([[3.0], [1.0]], [4.0, 0.5]), [2.25, 2.0], rtol=1e-15)
    with pytest.raises(EvidenceError, match="positive definite"):
        nees([1.0], [[0.0]])
    with pytest.raises(EvidenceError, match="must have shape"):
        nees([1.0, 2.0], [[1.0]])


@pytest.mark.parametrize(("dof", "runs", "p"), [(1, 1, 0.95), (2, 50, 0.95), (1, 100, 0.99)])
def test_the_chi2_band_is_scipys(dof, runs, p):
    low, high = chi2_band(dof, runs, p)
    assert low == chi2.ppf((1 - p) / 2, dof * runs) / runs
    assert high == chi2.ppf((1 + p) / 2, dof * runs) / runs
    # the band holds its probability: the χ² cdf between the ends, times N
    mass = chi2.cdf(high * runs, dof * runs) - chi2.cdf(low * runs, dof * runs)
    assert mass == pytest.approx(p, abs=1e-9)  # ppf/cdf round trip
    with pytest.raises(EvidenceError, match="probability"):
        chi2_band(1, 1, 1.0)


def test_a_consistent_filter_keeps_its_nees_in_the_band():
    """Monte Carlo on a random walk with Gaussian noises: the average NEES lies in the band."""
    rng = np.random.default_rng(11)
    runs, steps = 200, 30
    q, r = 0.04, 0.25
    truth = np.cumsum(rng.normal(0.0, np.sqrt(q), (runs, steps)), axis=1)
    z = truth + rng.normal(0.0, np.sqrt(r), (runs, steps))
    xs, ps = np.zeros((runs, steps)), np.zeros((runs, steps))
    x, p = z[:, 0], np.full(runs, r)
    xs[:, 0], ps[:, 0] = x, p
    for k in range(1, steps):
        p_pred = p + q
        gain = p_pred / (p_pred + r)
        x = x + gain * (z[:, k] - x)
        p = (1 - gain) * p_pred
        xs[:, k], ps[:, k] = x, p
    eps = nees((truth - xs)[..., None], ps)
    low, high = chi2_band(1, runs * steps, 0.999)
    assert low < eps.mean() < high
    # the same filter told a quarter of the noise is overconfident
    assert (eps * 4).mean() > high


def test_the_smoother_of_the_gauge_is_at_least_as_sure_as_the_filter():
    seq = simulate_gauge(9.6, 23.9, seed=0)
    filtered, smoothed = smooth_kalman(gauge_state_space_model(), seq.readings, seq.inputs)
    filt_var = np.array([s.covariance[0, 0] for s in filtered.steps])
    assert smoothed.covariances.shape == (seq.readings.shape[0], 1, 1)
    # the smoothed variance never exceeds the filtered (P_{k|T} = P_k − G(P⁻ − P_{k+1|T})Gᵀ)
    assert np.all(smoothed.covariances[:, 0, 0] <= filt_var * (1 + 1e-12))
    assert smoothed.covariances[0, 0, 0] < filt_var[0]
    assert smoothed.estimates[-1] == pytest.approx(filtered.estimates[-1], rel=0.0)


def test_the_smoother_refuses_bad_shapes():
    with pytest.raises(EvidenceError, match="covariances must have shape"):
        rts_smoother([[0.0], [1.0]], [[[1.0]]], [[1.0]], [[1.0]])
    with pytest.raises(EvidenceError, match="transitions must have shape"):
        rts_smoother([[0.0], [1.0]], [[[1.0]], [[1.0]]], [[1.0, 0.0]], [[1.0]])
    with pytest.raises(EvidenceError, match="singular"):
        rts_smoother([[0.0], [1.0]], [[[0.0]], [[1.0]]], [[1.0]], [[0.0]])
    with pytest.raises(EvidenceError, match="KalmanFilter"):
        smooth_kalman(random_walk(0.1, 0.5), [1.0, 2.0], flt=UnscentedKalmanFilter())


def test_gauge_consistency_with_true_orders_and_the_papers_orders():
    """With the model's own noises and true orders the Kalman NEES averages near n = 1.

    With eq. 43's orders, computed from the next reading, the NEES leaves its band upwards
    while the NIS falls below 1: the reading is used twice.
    """
    true = gauge_consistency(4.6, 26.5, runs=20, orders="true")
    eq43 = gauge_consistency(4.6, 26.5, runs=20, orders="eq43")
    low, high = true.nees_band
    assert low < float(true.nees["kalman"].mean()) < high
    assert float(eq43.nees["kalman"].mean()) > high
    assert float(eq43.nis["kalman"][1:].mean()) < 1.0
    assert eq43.share("kalman", "above") > 0.5
    with pytest.raises(EvidenceError, match="orders"):
        gauge_consistency(orders="guess")
    with pytest.raises(EvidenceError, match="no registered filter"):
        gauge_consistency(methods=("nope",))


def test_an_assumed_noise_too_small_makes_the_nees_overconfident():
    small = gauge_consistency(4.6, 26.5, runs=20, scale=0.5)
    large = gauge_consistency(4.6, 26.5, runs=20, scale=2.0)
    assert verdict(float(small.nees["kalman"].mean()), small.nees_band) == "overconfident"
    assert verdict(float(large.nees["kalman"].mean()), large.nees_band) == "conservative"


@pytest.mark.slow  # renders the explorer's figures
def test_the_consistency_explorer_answers_on_the_static_site():
    ex = consistency_explorer(runs=5)
    assert ex.numbers["NEES says"] == "consistent"
    ex.controls["scale"].value = 0.5
    assert ex.numbers["NEES says"] == "overconfident"
    site = consistency_explorer(runs=5)
    assert site.live["orders"] == ("true", "eq43")
    assert len(site.live["scale"]) == 16 and 0.5 in site.live["scale"]
