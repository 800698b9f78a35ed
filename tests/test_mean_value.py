"""The mean-value form of the image of a box (dstoolkit.evidence.image, method="mean_value").

An outer enclosure: on random boxes and random functions with exact slope bounds (random
polynomials, sin, exp, and a map of two variables to two outputs), every value f takes at a
dense sample of the box lies inside it; its excess width over the true image shrinks at
least threefold when the pieces double (quadratic: about fourfold); bad slope bounds and a
missing one are refused.
"""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import IntervalEvidence, image


def _interval_square(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """{x² : x in [lo, hi]}."""
    a, b = lo**2, hi**2
    inner = (lo <= 0) & (hi >= 0)
    return np.where(inner, 0.0, np.minimum(a, b)), np.maximum(a, b)


def _polynomial(coeffs: np.ndarray):
    """p(x) = Σ c_i x^i with the slope bound from |p'| ≤ Σ i |c_i| max(|lo|, |hi|)^(i−1)."""

    def f(x: np.ndarray) -> np.ndarray:
        return np.polynomial.polynomial.polyval(x[..., 0], coeffs)

    def slope(lo: np.ndarray, hi: np.ndarray):
        r = np.maximum(np.abs(lo), np.abs(hi))
        bound = sum(i * abs(c) * r ** (i - 1) for i, c in enumerate(coeffs) if i)
        return -bound, bound

    return f, slope


def _sin(x: np.ndarray) -> np.ndarray:
    return np.sin(x[..., 0])


def _sin_slope(lo: np.ndarray, hi: np.ndarray):
    """Cos on [lo, hi]: the ends, and ±1 where a multiple of π lies inside."""
    a, b = np.cos(lo), np.cos(hi)
    top = np.floor(hi / (2 * np.pi)) * 2 * np.pi >= lo  # a maximum of cos inside
    bottom = np.floor((hi - np.pi) / (2 * np.pi)) * 2 * np.pi + np.pi >= lo
    return np.where(bottom, -1.0, np.minimum(a, b)), np.where(top, 1.0, np.maximum(a, b))


def _exp(x: np.ndarray) -> np.ndarray:
    return np.exp(-x[..., 0])


def _exp_slope(lo: np.ndarray, hi: np.ndarray):
    return -np.exp(-lo), -np.exp(-hi)


def _sampled_hull(f, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Min and max of f over 2001 points of each box (..., 1): an inner estimate."""
    t = np.linspace(0.0, 1.0, 2001)[:, None]
    points = lo[..., None, :] + (hi - lo)[..., None, :] * t  # (..., 2001, 1)
    values = f(points)
    return values.min(axis=-1), values.max(axis=-1)


CASES = {"sin": (_sin, _sin_slope), "exp(-x)": (_exp, _exp_slope)}


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("pieces", [1, 3, 16])
def test_never_narrower_than_the_image_on_sampled_functions(seed: int, pieces: int) -> None:
    rng = np.random.default_rng(seed)
    ends = np.sort(rng.uniform(-4.0, 4.0, size=(40, 2)), axis=1)
    lo, hi = ends[:, :1], ends[:, 1:]
    cases = dict(CASES, polynomial=_polynomial(rng.normal(size=rng.integers(2, 6))))
    for name, (f, slope) in cases.items():
        a, b = image((lo, hi), f, method="mean_value", slope=slope, subdivisions=pieces)
        s_lo, s_hi = _sampled_hull(f, lo, hi)
        assert np.all(a[:, 0] <= s_lo) and np.all(b[:, 0] >= s_hi), name


def test_a_linear_function_is_enclosed_exactly_up_to_rounding() -> None:
    lo, hi = np.array([[-1.3], [0.0]]), np.array([[2.9], [0.0]])  # a point box too
    a, b = image(
        (lo, hi),
        lambda x: 2.0 * x[..., 0] + 1.0,
        method="mean_value",
        slope=lambda lo, hi: (np.full_like(lo, 2.0), np.full_like(hi, 2.0)),
    )
    np.testing.assert_allclose(a[:, 0], [-1.6, 1.0], rtol=1e-12)
    np.testing.assert_allclose(b[:, 0], [6.8, 1.0], rtol=1e-12)
    assert np.all(a[:, 0] <= [-1.6, 1.0]) and np.all(b[:, 0] >= [6.8, 1.0])


def test_two_variables_two_outputs() -> None:
    """f(x, y) = (x², x y) on random boxes: slopes ∂/∂x = (2x, y), ∂/∂y = (0, x)."""

    def f(p: np.ndarray) -> np.ndarray:
        return np.stack([p[..., 0] ** 2, p[..., 0] * p[..., 1]], axis=-1)

    def slope(lo: np.ndarray, hi: np.ndarray):
        d_lo = np.stack(
            [
                np.stack([2 * lo[..., 0], np.zeros_like(lo[..., 0])], -1),
                np.stack([lo[..., 1], lo[..., 0]], -1),
            ],
            -2,
        )
        d_hi = np.stack(
            [
                np.stack([2 * hi[..., 0], np.zeros_like(hi[..., 0])], -1),
                np.stack([hi[..., 1], hi[..., 0]], -1),
            ],
            -2,
        )
        return d_lo, d_hi

    rng = np.random.default_rng(3)
    lo = rng.uniform(-2.0, 1.0, size=(25, 2))
    hi = lo + rng.uniform(0.0, 2.0, size=(25, 2))
    a, b = image((lo, hi), f, method="mean_value", slope=slope, subdivisions=4)
    grid = np.linspace(0.0, 1.0, 101)
    gx, gy = np.meshgrid(grid, grid, indexing="ij")
    unit = np.stack([gx.ravel(), gy.ravel()], -1)
    values = f(lo[:, None, :] + (hi - lo)[:, None, :] * unit)  # (25, 10201, 2)
    assert a.shape == b.shape == (25, 2)
    assert np.all(a <= values.min(axis=1)) and np.all(b >= values.max(axis=1))
    true_x2 = _interval_square(lo[:, 0], hi[:, 0])
    assert np.all(a[:, 0] <= true_x2[0]) and np.all(b[:, 0] >= true_x2[1])


def test_the_excess_width_shrinks_like_the_square_of_the_width() -> None:
    f, slope = _sin, _sin_slope
    lo, hi = np.array([0.0]), np.array([3.0])
    true = 1.0 - 0.0  # sin on [0, 3]: [0, 1]
    excess = [
        float(
            np.diff(np.ravel(image((lo, hi), f, method="mean_value", slope=slope, subdivisions=k)))[
                0
            ]
        )
        - true
        for k in (16, 32, 64)
    ]
    assert all(e > 0 for e in excess)
    ratios = [excess[0] / excess[1], excess[1] / excess[2]]
    assert all(r > 3.0 for r in ratios), ratios  # linear would halve it, quadratic quarter


def test_evidence_keeps_its_masses() -> None:
    ev = IntervalEvidence(np.array([[-1.0], [1.0]]), np.array([[0.5], [2.0]]), [0.4, 0.6])
    out = image(
        ev, lambda x: x[..., 0] ** 2, method="mean_value", slope=lambda lo, hi: (2 * lo, 2 * hi)
    )
    assert isinstance(out, IntervalEvidence)
    np.testing.assert_allclose(np.sort(out.mass), [0.4, 0.6])
    assert np.all(out.boxes_lo[:, 0] <= [0.0, 1.0]) and np.all(out.boxes_hi[:, 0] >= [1.0, 4.0])


def test_a_missing_or_bad_slope_bound_is_refused() -> None:
    box = (np.array([0.0]), np.array([1.0]))
    square = lambda x: x[..., 0] ** 2  # noqa: E731
    with pytest.raises(EvidenceError, match="needs slope="):
        image(box, square, method="mean_value")
    with pytest.raises(EvidenceError, match="d_lo > d_hi"):
        image(box, square, method="mean_value", slope=lambda lo, hi: (2 * hi, 2 * lo - 1))
    with pytest.raises(EvidenceError, match="must return two arrays of shape"):
        image(box, square, method="mean_value", slope=lambda lo, hi: (np.zeros(3), np.ones(3)))
    with pytest.raises(EvidenceError, match="pieces must be"):
        image(
            box, square, method="mean_value", slope=lambda lo, hi: (2 * lo, 2 * hi), subdivisions=0
        )
