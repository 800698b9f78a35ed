"""The paper's dependent-evidence filter (§3.2, Steps 1–6) and its array kernels."""

import importlib.util
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit import (
    EvidenceError,
    IntervalEvidence,
    NotMonotoneError,
    TotalConflictError,
    conflict,
    decorrelate,
    dempster,
    dependence,
)
from dstoolkit.evidence import Boxes, cartesian_product, image
from dstoolkit.evidence import boxes as bk
from dstoolkit.filters import (
    DIAGNOSTICS,
    BoundedNoise,
    DependentEvidenceFilter,
    StateSpaceModel,
    simulate_lotka_volterra,
    with_input,
)
from dstoolkit.filters._dependent_arrays import predict  # Step 2 on the filter's own maps
from dstoolkit.gauge import (
    GAUGE_OBS_NOISE,
    PAPER_THETA,
    gauge_state_space_model,
    simulate_gauge,
)

MODEL = gauge_state_space_model()
FILTER = DependentEvidenceFilter()


@pytest.fixture(scope="module")
def gauge():
    return simulate_gauge(seed=11)


@pytest.fixture(scope="module")
def gauge_runs():
    return simulate_gauge(runs=6, seed=12)


# -- systems with a known truth ---------------------------------------------------------------
def test_noise_free_readings_give_the_truth_back():
    """Zero-width noises: every focal element is a point, the truth comes back exactly."""
    silent = BoundedNoise.symmetric(0.0)
    model = gauge_state_space_model(silent, silent)
    orders = simulate_gauge().true_inputs
    truth, z = model.simulate([1008.5], orders.size + 1, np.random.default_rng(0), orders)
    for result in (FILTER.run(model, z, orders), FILTER.run(model, z, orders, record=True)):
        # the truth up to the rounding of a few operations per step (other CPUs: other ulps)
        np.testing.assert_allclose(result.estimates, truth, rtol=1e-12)
        np.testing.assert_allclose(result.upper - result.lower, 0.0, atol=1e-12)


def test_nearly_noise_free_readings_give_the_truth_back():
    quiet = BoundedNoise.symmetric(1e-9)
    seq = simulate_gauge(seed=1, obs_noise=quiet)  # physical resonances, readings ± 1 nHz
    result = FILTER.run(gauge_state_space_model(quiet, quiet), seq.readings, seq.true_inputs)
    np.testing.assert_allclose(result.estimates, seq.truth, rtol=0, atol=1e-7)


def test_the_filter_beats_the_readings_on_the_gauge(gauge_runs):
    """Not the paper's Table 3, only bounds a broken filter would miss."""
    raw = np.abs(gauge_runs.readings - gauge_runs.truth).mean()  # biased by −E[w] = 6.9 Hz
    corrected = np.abs(gauge_runs.readings + GAUGE_OBS_NOISE.mean - gauge_runs.truth).mean()
    paper = FILTER.run_batch(
        MODEL, gauge_runs.readings, gauge_runs.inputs
    ).estimates  # eq. 43 orders
    assert np.abs(paper - gauge_runs.truth).mean() < 0.5 * raw
    true_orders = np.broadcast_to(gauge_runs.true_inputs, gauge_runs.inputs.shape)
    best = (
        DependentEvidenceFilter(start="mean_corrected")
        .run_batch(MODEL, gauge_runs.readings, true_orders)
        .estimates
    )
    assert np.abs(best - gauge_runs.truth).mean() < 0.5 * corrected


def test_estimate_lies_within_the_hull_of_its_final_evidence(gauge, gauge_runs):
    for result in (
        FILTER.run(MODEL, gauge.readings, gauge.inputs),
        FILTER.run(MODEL, gauge.readings, gauge.inputs, record=True),
        FILTER.run_batch(MODEL, gauge_runs.readings, gauge_runs.inputs),
    ):
        assert np.all(result.lower <= result.estimates)
        assert np.all(result.estimates <= result.upper)
        assert np.all(result.upper - result.lower < 60.0)  # bounded by the discounted Θs


def test_record_keeps_every_step_with_the_papers_sizes(gauge):
    result = FILTER.run(MODEL, gauge.readings[:6], gauge.inputs[:5], record=True)
    assert len(result.steps) == 6 and result.steps[0].estimate == pytest.approx(gauge.readings[0])
    step = result.steps[3]
    for key in (
        "state",
        "prediction",
        "observation_prediction",
        "observation",
        "fused",
        "mapped_back",
        "final",
    ):
        assert isinstance(getattr(step, key), IntervalEvidence), key
        assert getattr(step, key).mass.sum() == pytest.approx(1.0)
    assert step.estimate == pytest.approx(step.final.pignistic_expectation_1d())  # eq. 20
    d = result.diagnostics  # with p = 3: 4, 16, 64 and 64 × 16 products
    assert np.all(d["n_state"][1:] == 4) and np.all(d["n_prediction"][1:] == 16)
    assert np.all(d["n_observation"][1:] == 4) and np.all(d["n_products_step4"][1:] == 64)
    assert np.all(d["n_products_step6"][1:] == d["n_mapped_back"][1:] * 16)
    assert np.all(d["n_mapped_back"][1:] <= 64)


def test_array_path_has_the_unmerged_sizes_of_spec_5(gauge):
    noise = FILTER.noise_evidence(MODEL)
    maps = FILTER._maps(MODEL)
    assert noise.v.lo.shape == (1, 4, 1) and noise.w.lo.shape == (1, 4, 1)
    f_u = with_input(MODEL.f, np.array([[gauge.inputs[0]]]))
    p_lo, _ = predict(maps, noise, gauge.readings[:1], f_u)
    assert p_lo.shape == (1, 16, 1)  # 4 state boxes × 4 noise boxes
    assert p_lo.shape[1] * noise.w.lo.shape[1] == 64  # Step 4 products
    assert p_lo.shape[1] * noise.w.lo.shape[1] * p_lo.shape[1] == 1024  # Step 6 products


def test_prediction_is_the_extension_principle_over_the_random_relation(gauge):
    """Step 2 images f on the state boxes and adds V, as the literal eq. 13 does.

    The literal eq. 13 over (x̂ + V) × V through F(x, v) = f(x, u) + v gives the same
    evidence.
    """
    noise = FILTER.noise_evidence(MODEL)
    x_hat, order = gauge.readings[3], gauge.inputs[3]
    p_lo, p_hi = predict(
        FILTER._maps(MODEL), noise, x_hat[None], with_input(MODEL.f, np.array([[order]]))
    )
    ours = IntervalEvidence(p_lo[0], p_hi[0], noise.prediction_mass[0])
    relation = cartesian_product([noise.state.shift(x_hat), noise.state])  # eq. 16
    literal = image(relation, lambda xv: MODEL.f(xv[..., :1], order) + xv[..., 1:], monotone=[1, 1])
    # two code paths (batched boxes vs the extension principle): equal up to rounding
    np.testing.assert_allclose(ours.to_rows(), literal.to_rows(), rtol=1e-12)


# -- the two implementations agree -------------------------------------------------------------
def test_batch_equals_single_runs(gauge_runs):
    flt = DependentEvidenceFilter(chunk_size=4)  # two chunks, one partial
    batch = flt.run_batch(MODEL, gauge_runs.readings, gauge_runs.inputs).estimates
    assert batch.shape == (6, gauge_runs.orders.size, 1)
    single = np.stack(
        [
            flt.run(MODEL, z, u).estimates
            for z, u in zip(gauge_runs.readings, gauge_runs.inputs, strict=True)
        ]
    )
    np.testing.assert_array_equal(batch, single)


def test_object_path_equals_array_path(gauge):
    """The object path gives the array path's estimates, hulls and diagnostics.

    record=True merges focal elements and fuses with dstoolkit.evidence; the array path
    does not merge.
    """
    for flt in (
        FILTER,
        DependentEvidenceFilter(mass_rule="m1", start="mean_corrected", p=2, theta=PAPER_THETA),
    ):
        fast = flt.run(MODEL, gauge.readings, gauge.inputs)
        rec = flt.run(MODEL, gauge.readings, gauge.inputs, record=True)
        np.testing.assert_allclose(rec.estimates, fast.estimates, rtol=1e-12)
        np.testing.assert_allclose(rec.lower, fast.lower, rtol=1e-12)
        np.testing.assert_allclose(rec.upper, fast.upper, rtol=1e-12)
        for key in DIAGNOSTICS:
            np.testing.assert_allclose(
                rec.diagnostics[key], fast.diagnostics[key], rtol=1e-9, atol=1e-12, err_msg=key
            )


def test_two_dimensional_nonlinear_system():
    model, truth, z = simulate_lotka_volterra(steps=25, runs=3, seed=4)
    flt = DependentEvidenceFilter(p=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the vertex method must not warn on this system
        batch = flt.run_batch(model, z).estimates
        rec = flt.run(model, z[0], record=True)
    np.testing.assert_allclose(rec.estimates, batch[0], rtol=1e-12, atol=1e-12)
    direct = np.log(np.maximum(z + model.obs_noise.mean, 1e-9))
    assert np.sqrt(np.mean((batch - truth) ** 2)) < 0.06
    assert np.sqrt(np.mean((batch - truth) ** 2)) < np.sqrt(np.mean((direct - truth) ** 2))


# -- diagnostics --------------------------------------------------------------------------------
def test_every_diagnostic_stays_in_its_range(gauge_runs):
    result = FILTER.run_batch(MODEL, gauge_runs.readings, gauge_runs.inputs)
    d = {key: value[:, 1:] for key, value in result.diagnostics.items()}
    assert np.all(np.isnan(result.diagnostics["dependence"][:, 0]))  # no fusion at step 1
    for key in ("conflict_step4", "conflict_step6"):
        assert np.all((d[key] >= -1e-12) & (d[key] < 1.0)), key
    for key in ("energy_mapped_back", "energy_prediction"):
        assert np.all((d[key] > 0.0) & (d[key] <= 1.0)), key
    assert np.all(d["joint_energy"] >= 0.0)
    assert np.all(d["dependence"] >= 0.0) and np.nanmax(d["dependence"]) > 0.1
    for key in ("r12", "r21"):
        assert np.all((d[key] > 0.0) & (d[key] <= 1.0)), key
    assert np.all(d["fallback"] == 0.0)


def test_mass_rule_m2_is_refused_when_it_breaks_the_coefficients(gauge):
    """m(D) = m2(D) can make D > 1 and R < 0 (eq. A3 leaves m(D) open): both paths refuse it."""
    flt = DependentEvidenceFilter(mass_rule="m2")
    with pytest.raises(EvidenceError, match=r"outside \[0, 1\].*mass_rule='min'"):
        flt.run(MODEL, gauge.readings, gauge.inputs)
    with pytest.raises(EvidenceError, match=r"outside \[0, 1\]"):
        flt.run(MODEL, gauge.readings, gauge.inputs, record=True)


# -- options and failures --------------------------------------------------------------------------
def test_start_options(gauge):
    z = gauge.readings[:3]
    u = gauge.inputs[:2]
    assert FILTER.run(MODEL, z, u).estimates[0, 0] == z[0, 0]
    corrected = DependentEvidenceFilter(start="mean_corrected").run(MODEL, z, u)
    assert corrected.estimates[0, 0] == pytest.approx(z[0, 0] + GAUGE_OBS_NOISE.mean[0])
    assert DependentEvidenceFilter(start=[1000.0]).run(MODEL, z, u).estimates[0, 0] == 1000.0
    with pytest.raises(EvidenceError, match="start must be"):
        DependentEvidenceFilter(start="truth")


def test_without_discount_the_papers_start_conflicts_at_once(gauge):
    """With ε = 0 (no Θ) the first prediction and observation share nothing.

    x̂_1 = z_1 is off by −E[w] = 6.9 Hz, far beyond v's ±0.3 Hz.
    """
    with pytest.raises(TotalConflictError, match="Step 4 of estimate 2"):
        DependentEvidenceFilter(epsilon=0.0).run(MODEL, gauge.readings, gauge.inputs)


def _conflicting(gauge):
    z = gauge.readings[:8].copy()
    z[4:] += 500.0  # far outside every focal element without Θ (epsilon = 0)
    return z


def test_total_conflict_raises_with_the_step(gauge):
    flt = DependentEvidenceFilter(epsilon=0.0, start="mean_corrected")
    with pytest.raises(TotalConflictError, match="Step 4 of estimate 5"):
        flt.run(MODEL, _conflicting(gauge), gauge.inputs[:7])
    with pytest.raises(TotalConflictError, match="Step 4 of estimate 5"):
        flt.run(MODEL, _conflicting(gauge), gauge.inputs[:7], record=True)


def test_total_conflict_can_fall_back_to_the_prediction(gauge):
    flt = DependentEvidenceFilter(epsilon=0.0, start="mean_corrected", on_conflict="predict")
    z, u = _conflicting(gauge), gauge.inputs[:7]
    fast = flt.run(MODEL, z, u)
    rec = flt.run(MODEL, z, u, record=True)
    assert fast.diagnostics["fallback"][4] == 1.0 and np.isnan(fast.diagnostics["r12"][4])
    prediction = rec.steps[4].prediction
    assert rec.steps[4].final is prediction
    assert fast.estimates[4, 0] == pytest.approx(prediction.pignistic_expectation_1d(), rel=1e-14)
    np.testing.assert_allclose(fast.estimates, rec.estimates, rtol=1e-12)
    both = flt.run_batch(
        MODEL, np.stack([z, gauge.readings[:8]]), np.stack([u, gauge.inputs[:7]])
    ).estimates
    np.testing.assert_array_equal(both[0], fast.estimates)
    np.testing.assert_array_equal(both[1], flt.run(MODEL, gauge.readings[:8], u).estimates)


def test_wrong_monotone_declaration_is_caught_in_the_filter(gauge):
    wrong = StateSpaceModel(
        f=MODEL.f,
        g=MODEL.g,
        g_inverse=MODEL.g_inverse,
        state_noise=MODEL.state_noise,
        obs_noise=MODEL.obs_noise,
        f_monotone=(-1, 1),
        g_monotone=(1,),
    )
    with pytest.raises(NotMonotoneError, match="declared monotone"):
        FILTER.run(wrong, gauge.readings[:4], gauge.inputs[:3])


def _emptying(model: StateSpaceModel) -> StateSpaceModel:
    """Return the model with a g⁻¹ that returns every box empty (lo above hi)."""

    def g_inverse(lo, hi, x_lo, x_hi):
        return np.maximum(hi, x_hi) + 1.0, np.minimum(lo, x_lo)

    return StateSpaceModel(
        f=model.f,
        g=model.g,
        g_inverse=g_inverse,
        state_noise=model.state_noise,
        obs_noise=model.obs_noise,
        f_monotone=model.f_monotone,
        g_monotone=model.g_monotone,
    )


def test_an_empty_box_from_g_inverse_is_refused_on_every_path(gauge):
    """Step 5 refuses a g⁻¹ that returns an empty box for a focal element of positive mass.

    So do the array path (one run, a batch, the compiled kernel) and the object path, for
    n = 1 and 2.
    """
    start = gauge.readings[0] + GAUGE_OBS_NOISE.mode
    lv, _, z_lv = simulate_lotka_volterra(steps=4, runs=2, seed=4)
    cases = [
        (_emptying(MODEL), gauge.readings[:4], gauge.inputs[:3], start),
        (_emptying(lv), z_lv[0], None, [1.0, 1.0]),
    ]
    kernels = ["numpy", "numba"] if importlib.util.find_spec("numba") else ["numpy"]
    for model, z, u, x0 in cases:
        batch = np.stack([z, z]), None if u is None else np.stack([u, u])
        for kernel in kernels:
            flt = DependentEvidenceFilter(start=x0, p=1, kernel=kernel)
            for record in (False, True):
                with pytest.raises(EvidenceError, match="g_inverse returned an empty box"):
                    flt.run(model, z, u, record=record)
            with pytest.raises(EvidenceError, match="g_inverse returned an empty box"):
                flt.run_batch(model, *batch)


def test_bad_models_and_data_are_explained(gauge):
    no_inverse = StateSpaceModel(
        f=MODEL.f, g=MODEL.g, state_noise=MODEL.state_noise, obs_noise=MODEL.obs_noise
    )
    with pytest.raises(EvidenceError, match="g_inverse"):
        FILTER.run(no_inverse, gauge.readings, gauge.inputs)
    with pytest.raises(EvidenceError, match="order n_k"):
        FILTER.run(MODEL, gauge.readings)
    with pytest.raises(EvidenceError, match="inputs must have shape"):
        FILTER.run_batch(MODEL, gauge.readings[None], gauge.inputs[None, :3])
    with pytest.raises(EvidenceError, match="mass_rule"):
        DependentEvidenceFilter(mass_rule="max")
    with pytest.raises(EvidenceError, match="on_conflict"):
        DependentEvidenceFilter(on_conflict="ignore")


# -- the kernels against dstoolkit.evidence ----------------------------------------------------
POOL = np.array([[0.0, 1.0], [0.0, 2.0], [0.5, 1.5], [1.0, 3.0], [-1.0, 0.5], [2.5, 4.0]])


@st.composite
def unmerged(draw, allow_zero):
    """Interval evidence drawn from a small pool, so that copies of a focal element occur."""
    n = draw(st.integers(1, 7))
    rows = draw(st.lists(st.integers(0, len(POOL) - 1), min_size=n, max_size=n))
    weights = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    if allow_zero:
        zero = np.array(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
        zero[np.argmax(weights)] = False
        weights[zero] = 0.0
    weights /= weights.sum()
    return POOL[rows, :1], POOL[rows, 1:], weights


@settings(max_examples=80, deadline=None, derandomize=True)
@given(a=unmerged(True), b=unmerged(False), rule=st.sampled_from(["min", "m1", "m2"]))
def test_kernels_equal_the_merged_object_path(a, b, rule):
    ba, bb = Boxes(a[0][None], a[1][None], a[2][None]), Boxes(b[0][None], b[1][None], b[2][None])
    ea, eb = IntervalEvidence(*a), IntervalEvidence(*b)  # merges equal focal elements
    obj = dependence(ea, eb, mass_rule=rule)
    ker = bk.dependence(ba, bb, rule, check=False)
    for name in ("energy1", "energy2", "joint_energy", "degree", "r12", "r21"):
        assert getattr(ker, name)[0] == pytest.approx(getattr(obj, name), abs=1e-12), name
    try:
        a2, b2, _ = decorrelate(ea, eb, mass_rule=rule)
    except EvidenceError:
        with pytest.raises(EvidenceError, match="outside"):
            bk.dependence(ba, bb, rule)
        return
    try:
        combined = dempster(a2, b2)
    except TotalConflictError:
        assert not bk.dempster_expectation(
            bk.discount_onto_hull(ba, ker.r12), bk.discount_onto_hull(bb, ker.r21)
        )[2][0]
        return
    for da, db in (
        (ba, bb),
        (bk.discount_onto_hull(ba, ker.r12), bk.discount_onto_hull(bb, ker.r21)),
    ):
        x, k, ok, (lo, hi) = bk.dempster_expectation(da, db, bounds=True)
        live = (da.mass[0] > 0, db.mass[0] > 0)
        objects = [
            IntervalEvidence(e.lo[0][keep], e.hi[0][keep], e.mass[0][keep])
            for e, keep in zip((da, db), live, strict=True)
        ]
        try:
            both = dempster(*objects)
        except TotalConflictError:
            assert not ok[0]
            continue
        assert ok[0] and k[0] == pytest.approx(conflict(*objects), abs=1e-12)
        assert x[0, 0] == pytest.approx(both.pignistic_expectation_1d(), abs=1e-12)
        assert (lo[0, 0], hi[0, 0]) == pytest.approx(tuple(h[0] for h in both.hull()))
    assert x[0, 0] == pytest.approx(combined.pignistic_expectation_1d(), abs=1e-12)
    assert (lo[0, 0], hi[0, 0]) == pytest.approx(tuple(h[0] for h in combined.hull()))


def test_kernels_on_the_appendix_a_example():
    e1 = IntervalEvidence([-0.30, 0.30, 0.32], [2.60, 1.90, 1.93], [0.3, 0.6, 0.1])
    e2 = IntervalEvidence([0.21, 0.41, 0.30], [3.50, 1.61, 1.90], [0.1, 0.3, 0.6])
    obj = dependence(e1, e2)
    ker = bk.dependence(
        Boxes(e1.boxes_lo[None], e1.boxes_hi[None], e1.mass[None]),
        Boxes(e2.boxes_lo[None], e2.boxes_hi[None], e2.mass[None]),
    )
    assert ker.joint_energy[0] == pytest.approx(0.45)  # eq. A9
    assert ker.energy2[0] == pytest.approx(0.7865, abs=1e-4)
    assert ker.degree[0] == pytest.approx(obj.degree, rel=1e-14)
    assert (ker.r12[0], ker.r21[0]) == pytest.approx((obj.r12, obj.r21), rel=1e-14)


# -- the optional compiled kernel (extra "speed") ---------------------------------------------
@pytest.mark.extras  # numba, the extra "speed"
def test_compiled_kernel_does_a_step_as_the_numpy_path(gauge):
    """One step of kernel="numba" gives the numpy path's numbers to rounding.

    From the same state (start = the numpy path's x̂_k), the estimate, hull and diagnostics
    agree at every k (K is 1 minus a sum of some 1,100 products in another order: equal to
    1e-12).
    """
    ref = FILTER.run(MODEL, gauge.readings, gauge.inputs)
    for k in range(len(gauge.readings) - 1):
        z, u = gauge.readings[k : k + 2], gauge.inputs[k : k + 1]
        fast = DependentEvidenceFilter(kernel="numba", start=ref.estimates[k]).run(MODEL, z, u)
        slow = DependentEvidenceFilter(start=ref.estimates[k]).run(MODEL, z, u)
        for name in ("estimates", "lower", "upper"):
            np.testing.assert_allclose(
                getattr(fast, name), getattr(slow, name), rtol=1e-13, err_msg=name
            )
        for key in DIAGNOSTICS:
            np.testing.assert_allclose(
                fast.diagnostics[key], slow.diagnostics[key], rtol=1e-13, atol=1e-12, err_msg=key
            )


@pytest.mark.extras  # numba, the extra "speed"
def test_compiled_kernel_agrees_with_the_numpy_path(gauge):
    """Whole runs of kernel="numba" agree with the numpy path.

    On the gauge (p = 3; p = 2 with the paper's Θ and m(D) = m1), on the 2-D Lotka–Volterra
    system, and through a total conflict kept as the prediction. The sums run in another
    order, so x̂ differs by an ulp and the runs drift apart by rounding; the estimates and
    hulls stay equal to 1e-12, the diagnostics to 1e-7 (an energy divides by the smallest
    focal element, which can be 1e-4 Hz wide: an ulp of a 2,000 Hz bound, 2e-13 Hz, is 2e-9
    of it).
    """
    model, _, z_lv = simulate_lotka_volterra(steps=25, runs=3, seed=4)
    cases = [
        ({}, MODEL, gauge.readings, gauge.inputs),
        (
            dict(mass_rule="m1", start="mean_corrected", p=2, theta=PAPER_THETA),
            MODEL,
            gauge.readings,
            gauge.inputs,
        ),
        (dict(p=1), model, z_lv[0], None),
        (
            dict(epsilon=0.0, start="mean_corrected", on_conflict="predict"),
            MODEL,
            _conflicting(gauge),
            gauge.inputs[:7],
        ),
    ]
    for options, mdl, z, u in cases:
        fast = DependentEvidenceFilter(kernel="numba", **options).run(mdl, z, u)
        ref = DependentEvidenceFilter(**options).run(mdl, z, u)
        for name in ("estimates", "lower", "upper"):
            np.testing.assert_allclose(
                getattr(fast, name), getattr(ref, name), rtol=1e-12, atol=1e-12, err_msg=name
            )
        for key in DIAGNOSTICS:
            np.testing.assert_allclose(
                fast.diagnostics[key], ref.diagnostics[key], rtol=1e-7, atol=1e-12, err_msg=key
            )


@pytest.mark.extras  # numba, the extra "speed"
def test_compiled_kernel_batch_equals_single_runs(gauge_runs):
    flt = DependentEvidenceFilter(kernel="numba", chunk_size=4)
    batch = flt.run_batch(MODEL, gauge_runs.readings, gauge_runs.inputs).estimates
    single = np.stack(
        [
            flt.run(MODEL, z, u).estimates
            for z, u in zip(gauge_runs.readings, gauge_runs.inputs, strict=True)
        ]
    )
    np.testing.assert_array_equal(batch, single)


@pytest.mark.extras  # numba, the extra "speed"
def test_compiled_kernel_refuses_what_the_numpy_path_refuses(gauge):
    with pytest.raises(EvidenceError, match=r"outside \[0, 1\].*mass_rule='min'"):
        DependentEvidenceFilter(kernel="numba", mass_rule="m2").run(
            MODEL, gauge.readings, gauge.inputs
        )
    with pytest.raises(TotalConflictError, match="Step 4 of estimate 5"):
        DependentEvidenceFilter(kernel="numba", epsilon=0.0, start="mean_corrected").run(
            MODEL, _conflicting(gauge), gauge.inputs[:7]
        )
    with pytest.raises(EvidenceError, match="kernel must be one of"):
        DependentEvidenceFilter(kernel="fortran")


@pytest.mark.parametrize("rate", [1.5, -0.1, float("nan")])
def test_discounting_refuses_a_rate_outside_0_1(rate):
    e = bk.Boxes(np.array([[[0.0], [1.0]]]), np.array([[[2.0], [3.0]]]), np.array([[0.5, 0.5]]))
    assert bk.discount_onto_hull(e, np.array([0.25])).mass[0, -1] == pytest.approx(0.75)
    with pytest.raises(EvidenceError, match=r"discount rates must be one number in \[0, 1\]"):
        bk.discount_onto_hull(e, np.array([rate]))
