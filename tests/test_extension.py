"""Random relations and the extension principle (paper §2.3, eqs. 11–20, Props. 1–2)."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit import EvidenceError, IntervalEvidence, NotMonotoneError
from dstoolkit.evidence import (
    VertexMethodWarning,
    box_image,
    cartesian_product,
    image,
    projection,
    vertices,
)
from dstoolkit.filters import with_input

E1 = IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])
E2 = IntervalEvidence([0.0, 1.0, -1.0], [1.0, 2.0, 3.0], [0.2, 0.3, 0.5])


def square(x):
    return x[..., 0] ** 2


# -- random relations -------------------------------------------------------------------------
def test_cartesian_product_has_product_masses_in_product_order():
    rel = cartesian_product([E1, E2])
    assert rel.dim == 2 and len(rel) == 6
    expected = np.multiply.outer(E1.mass, E2.mass).reshape(-1)  # eq. 16
    np.testing.assert_allclose(rel.mass, expected)
    np.testing.assert_array_equal(rel.boxes_lo[1], [-0.3, 1.0])  # first marginal slowest
    np.testing.assert_array_equal(rel.boxes_hi[5], [1.9, 3.0])


def test_projection_of_a_product_gives_back_the_marginals():
    rel = cartesian_product([E1, E2, E1])
    for axes, marginal in (([0], E1), ([1], E2), ([2], E1)):
        proj = projection(rel, axes)  # eqs. 11–12
        np.testing.assert_array_equal(proj.lo, marginal.lo)
        np.testing.assert_allclose(proj.mass, marginal.mass)


def test_cartesian_product_refuses_bad_input():
    with pytest.raises(EvidenceError, match="IntervalEvidence"):
        cartesian_product([])
    with pytest.raises(EvidenceError, match="IntervalEvidence"):
        cartesian_product([E1, [0.0, 1.0]])


def test_vertices_enumerate_every_corner():
    v = vertices(np.array([0.0, 10.0, 100.0]), np.array([1.0, 11.0, 101.0]))
    assert v.shape == (8, 3)
    assert {tuple(row) for row in v} == {
        (a, b, c) for a in (0, 1) for b in (10, 11) for c in (100, 101)
    }


# -- agreement where every method applies -------------------------------------------------------
@st.composite
def boxes(draw, n):
    lo = np.array(draw(st.lists(st.floats(-3, 3), min_size=n, max_size=n)))
    width = np.array(draw(st.lists(st.floats(0, 2), min_size=n, max_size=n)))
    return lo, lo + width


@settings(max_examples=60, deadline=None, derandomize=True)
@given(data=st.data(), n=st.integers(1, 3))
def test_monotone_vertex_and_subdivision_agree_on_monotone_functions(data, n):
    lo, hi = data.draw(boxes(n))
    signs = np.array(data.draw(st.lists(st.sampled_from([-1, 1]), min_size=n, max_size=n)))
    scale = np.arange(1.0, n + 1)

    def f(x):  # monotone in each argument with the drawn signs, nonlinear
        return np.sum(signs * scale * (x + np.exp(0.3 * x)), axis=-1)

    with warnings.catch_warnings():
        warnings.simplefilter("error", VertexMethodWarning)  # no false alarm
        results = [
            image((lo[None], hi[None]), f, method, monotone=signs)
            for method in ("monotone", "vertex", "subdivision")
        ]
    for out_lo, out_hi in results[1:]:
        np.testing.assert_allclose(out_lo, results[0][0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(out_hi, results[0][1], rtol=1e-12, atol=1e-12)
    # and the image really is [f(v_min), f(v_max)] (eqs. 18–19)
    v_min, v_max = np.where(signs > 0, lo, hi), np.where(signs > 0, hi, lo)
    np.testing.assert_allclose(results[0][0][0, 0], f(v_min), rtol=1e-12)
    np.testing.assert_allclose(results[0][1][0, 0], f(v_max), rtol=1e-12)


def test_vector_function_with_one_sign_row_per_output():
    lo, hi = np.array([[-1.0, -0.5]]), np.array([[1.0, 2.0]])

    def f(x):
        return np.stack([x[..., 0] + x[..., 1], x[..., 0] - x[..., 1]], axis=-1)

    mono = image((lo, hi), f, "monotone", monotone=[[1, 1], [1, -1]])
    vert = image((lo, hi), f, "vertex")
    sub = image((lo, hi), f, "subdivision")
    for out in (vert, sub):
        np.testing.assert_allclose(out[0], mono[0])
        np.testing.assert_allclose(out[1], mono[1])
    np.testing.assert_allclose(mono[0], [[-1.5, -3.0]])
    np.testing.assert_allclose(mono[1], [[3.0, 1.5]])


# -- where the vertex method is wrong -------------------------------------------------------------
@pytest.mark.parametrize(
    ("f", "lo", "hi", "true_lo", "true_hi"),
    [
        (square, -1.0, 2.0, 0.0, 4.0),  # x² on a box straddling 0
        (lambda x: np.sin(x[..., 0]), 0.0, 3.0, 0.0, 1.0),  # max at π/2 inside
        (lambda x: np.sin(x[..., 0]), -2.0, 6.0, -1.0, 1.0),  # both extrema inside
        (lambda x: (x[..., 0] ** 2 - 1) ** 2, -2.0, 2.0, 0.0, 9.0),  # two equal minima
    ],
)
def test_subdivision_is_right_where_the_vertex_method_is_not(f, lo, hi, true_lo, true_hi):
    box = (np.array([[lo]]), np.array([[hi]]))
    with pytest.warns(VertexMethodWarning, match="extremum inside"):
        v_lo, v_hi = image(box, f, "vertex")
    assert v_lo[0, 0] > true_lo + 1e-3 or v_hi[0, 0] < true_hi - 1e-3  # too narrow
    s_lo, s_hi = image(box, f, "subdivision")
    assert s_lo[0, 0] == pytest.approx(true_lo, abs=1e-12)
    assert s_hi[0, 0] == pytest.approx(true_hi, abs=1e-12)


def test_subdivision_finds_the_global_extremum_among_rival_basins_in_2d():
    lo, hi = np.array([[-1.0, -0.5]]), np.array([[1.0, 2.0]])

    def f(x):  # the second output has a boundary minimum (−0.997) and an inner one (−1)
        return np.stack([x[..., 0] ** 2 + x[..., 1] ** 2, np.sin(3 * x[..., 1])], axis=-1)

    s_lo, s_hi = image((lo, hi), f, "subdivision")
    np.testing.assert_allclose(s_lo, [[0.0, -1.0]], atol=1e-12)
    np.testing.assert_allclose(s_hi, [[5.0, 1.0]], atol=1e-12)


def test_subdivision_matches_the_exact_image_of_cos_3x():
    rng = np.random.default_rng(7)
    lo = rng.uniform(-3, 3, (50, 1))
    hi = lo + rng.uniform(0, 3, (50, 1))
    s_lo, s_hi = image((lo, hi), lambda x: np.cos(3 * x[..., 0]), "subdivision")
    for i in range(50):  # exact: the ends and the extrema k·π/3 inside
        k = np.arange(np.ceil(3 * lo[i, 0] / np.pi), np.floor(3 * hi[i, 0] / np.pi) + 1)
        values = np.cos(3 * np.concatenate([lo[i], hi[i], k * np.pi / 3]))
        assert s_lo[i, 0] == pytest.approx(values.min(), abs=1e-12)
        assert s_hi[i, 0] == pytest.approx(values.max(), abs=1e-12)


# -- checks of the hypotheses ------------------------------------------------------------------
def test_wrong_monotone_declaration_raises():
    box = (np.array([[-1.0]]), np.array([[2.0]]))
    with pytest.raises(NotMonotoneError, match=r"declared monotone .* f\(centre\)"):
        image(box, square, "monotone", monotone=[1])
    with pytest.raises(NotMonotoneError, match="declared monotone"):
        image(box, lambda x: -x[..., 0], "monotone", monotone=[1])  # decreasing, said +1
    # a correct declaration passes, and so does a wrong one when the check is off
    image(box, lambda x: -x[..., 0], "monotone", monotone=[-1])
    image(box, square, "monotone", monotone=[1], check=False)


def test_vertex_check_is_silent_on_a_box_without_extremum():
    with warnings.catch_warnings():
        warnings.simplefilter("error", VertexMethodWarning)
        out = image((np.array([[0.5]]), np.array([[2.0]])), square, "vertex")
    np.testing.assert_allclose(out, ([[0.25]], [[4.0]]))


def test_auto_picks_monotone_only_with_every_sign_known():
    box = (np.array([[-1.0]]), np.array([[2.0]]))
    with pytest.raises(NotMonotoneError):
        image(box, square, monotone=[1])  # auto → monotone → the check fires
    with pytest.warns(VertexMethodWarning):
        image(box, square, monotone=[0])  # unknown sign → vertex → warning


def test_bad_arguments_are_explained():
    box = (np.array([[0.0]]), np.array([[1.0]]))
    with pytest.raises(EvidenceError, match="method must be one of"):
        image(box, square, "interval")
    with pytest.raises(EvidenceError, match="needs the signs"):
        image(box, square, "monotone")
    with pytest.raises(EvidenceError, match="even integer"):
        image(box, square, "subdivision", subdivisions=5)
    with pytest.raises(EvidenceError, match="lo > hi"):
        image((np.array([[1.0]]), np.array([[0.0]])), square)
    with pytest.raises(EvidenceError, match="one sign per argument"):
        image(box, square, monotone=[1, 1])
    with pytest.raises(EvidenceError, match="returned shape"):
        image(box, lambda x: np.zeros(3), "vertex")


# -- evidence in, evidence out --------------------------------------------------------------------
def test_equal_images_merge_their_masses():
    ev = IntervalEvidence([-2.0, 1.0, 0.0], [-1.0, 2.0, 0.5], [0.2, 0.5, 0.3])
    out = image(ev, square, "subdivision")  # [−2, −1] and [1, 2] both map to [1, 4] (eq. 14)
    assert len(out) == 2
    np.testing.assert_allclose(out.to_rows(), [[1.0, 4.0, 0.7], [0.0, 0.25, 0.3]], atol=1e-12)
    kept = image(ev, square, "subdivision", merge=False)
    assert len(kept) == 3


def test_image_of_a_random_relation_and_its_expectation():
    rel = cartesian_product([E1, E2])
    out = image(rel, lambda x: x[..., 0] + 2 * x[..., 1], monotone=[1, 1])
    assert out.dim == 1 and out.mass.sum() == pytest.approx(1.0)
    # E[x + 2y] = E[x] + 2E[y] for the pignistic expectation of a product relation (eq. 20)
    expected = E1.pignistic_expectation_1d() + 2 * E2.pignistic_expectation_1d()
    assert out.pignistic_expectation_1d() == pytest.approx(expected, rel=1e-12)


def test_box_image_reads_a_models_signs_and_broadcasts_run_inputs():
    lo = np.array([[[1.0], [2.0]], [[1.0], [2.0]]])  # (runs, N, n)
    hi = lo + 1.0
    u = np.array([[2.0], [-3.0]])  # one input per run, (runs, q)

    def f(x, u):
        return x * u

    # f_monotone lists the state signs, then the noise signs (2n entries): auto → monotone
    out_lo, out_hi = box_image(with_input(f, u[:1]), lo[:1], hi[:1], (1, 1))
    np.testing.assert_allclose(out_lo[0, :, 0], [2.0, 4.0])
    np.testing.assert_allclose(out_hi[0, :, 0], [4.0, 6.0])
    for method in ("vertex", "subdivision"):  # run 1 has u < 0: f decreasing there
        out_lo, out_hi = box_image(with_input(f, u), lo, hi, method=method)
        np.testing.assert_allclose(out_lo[:, :, 0], [[2.0, 4.0], [-6.0, -9.0]], atol=1e-12)
        np.testing.assert_allclose(out_hi[:, :, 0], [[4.0, 6.0], [-3.0, -6.0]], atol=1e-12)
