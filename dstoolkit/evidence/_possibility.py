"""From a bounded noise to evidence (paper §3.1 Step 1, eqs. 22–26; Tables 1–2).

A bounded noise with support [a, b] and most likely value c is described by the
triangular possibility distribution π; its α-cuts, taken at α_i = i/p, are p nested
intervals that become focal elements of mass 1/p each, and a discount ε puts some mass on
a wide frame Θ so that unexpected values are not ruled out.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from dstoolkit._reprs import short_repr
from dstoolkit.errors import EvidenceError
from dstoolkit.utils.checks import real_array, real_number, whole_number

from ._combination import discount
from ._intervals import IntervalEvidence


class TriangularBounds(NamedTuple):
    """Support [lower, upper] and mode of a triangular possibility distribution.

    Parameters
    ----------
    lower, mode, upper : float
        Support [lower, upper] and mode of the triangle (the noise's unit),
        lower <= mode <= upper.

    Examples
    --------
    >>> TriangularBounds(-0.3, 0.0, 0.3).sigma
    0.09999999999999999
    """

    lower: float
    mode: float
    upper: float

    def __repr__(self) -> str:
        return short_repr(self)

    @property
    def sigma(self) -> float:
        """σ implied by bounds taken at ±3σ (the paper's convention)."""
        return (self.upper - self.lower) / 6.0


def _check_triangle(lower: Any, mode: Any, upper: Any) -> tuple[float, float, float]:
    """Return the triangle's ends and mode as floats: finite, ordered, with a finite 100σ frame."""
    lower, mode, upper = (
        real_number(v, name, error=EvidenceError)
        for v, name in ((lower, "lower"), (mode, "mode"), (upper, "upper"))
    )
    if not lower <= mode <= upper:
        raise EvidenceError(
            f"need lower <= mode <= upper, got lower={lower}, mode={mode}, upper={upper}; "
            "check the order of the arguments"
        )
    if not math.isfinite(100.0 * (upper - lower)) or not math.isfinite(
        abs(mode) + 100.0 * (upper - lower)
    ):
        raise EvidenceError(
            f"the triangle [{lower:g}, {upper:g}] is too wide to compute "
            "with (its frame overflows); rescale the variable"
        )
    return lower, mode, upper


def possibility(x: Any, lower: float, mode: float, upper: float) -> np.ndarray:
    """Evaluate the triangular possibility distribution π(x) with support [lower, upper] (eq. 22).

    Parameters
    ----------
    x : array_like
        Where to evaluate (the noise's unit).
    lower, mode, upper : float
        Support [lower, upper] and mode of the triangle (the noise's unit),
        lower <= mode <= upper.

    Returns
    -------
    ndarray, shape of ``x``
        π(x) in [0, 1]: 1 at the mode, 0 outside the support.

    Raises
    ------
    EvidenceError
        For non-finite numbers or lower > mode or mode > upper.

    See Also
    --------
    alpha_cuts : its level sets.

    References
    ----------
    The paper's eq. (22).

    Examples
    --------
    >>> possibility([0.0, 0.15, 0.5], -0.3, 0.0, 0.3)
    array([1. , 0.5, 0. ])
    """
    lower, mode, upper = _check_triangle(lower, mode, upper)
    x = real_array(x, "x", allow_inf=True, error=EvidenceError)
    with np.errstate(divide="ignore", invalid="ignore"):
        left = np.where(mode > lower, (x - lower) / (mode - lower), 1.0)
        right = np.where(upper > mode, (upper - x) / (upper - mode), 1.0)
    pi = np.where(x <= mode, left, right)
    return np.clip(np.where((x < lower) | (x > upper), 0.0, pi), 0.0, 1.0)


def alpha_cuts(lower: float, mode: float, upper: float, p: int) -> tuple[np.ndarray, np.ndarray]:
    """Compute the α-cuts [a + α(c − a), b − α(b − c)] at α_i = i/p, i = 0..p−1 (eqs. 23–24).

    Returned innermost first, as in the paper's Tables 1–2.

    Parameters
    ----------
    lower, mode, upper : float
        Support [lower, upper] and mode of the triangle (the noise's unit),
        lower <= mode <= upper.
    p : int
        The number of cuts, p >= 1.

    Returns
    -------
    lo, hi : ndarray, shape (p,)
        The ends of the cuts, innermost first.

    Raises
    ------
    EvidenceError
        For non-finite numbers or lower > mode or mode > upper.

    See Also
    --------
    triangular_evidence : gives the cuts their masses.

    References
    ----------
    The paper's eqs. (23)–(24).

    Examples
    --------
    >>> lo, hi = alpha_cuts(-0.3, 0.0, 0.3, 3)
    >>> lo.round(4).tolist(), hi.round(4).tolist()
    ([-0.1, -0.2, -0.3], [0.1, 0.2, 0.3])
    """
    lower, mode, upper = _check_triangle(lower, mode, upper)
    p = whole_number(p, "the number of cuts p", low=1, high=10_000, error=EvidenceError)
    alpha = np.arange(p)[::-1] / p
    return lower + alpha * (mode - lower), upper - alpha * (upper - mode)


def default_theta(lower: float, mode: float, upper: float) -> tuple[float, float]:
    """Θ = mode ± 100σ with σ = (upper − lower)/6 (the paper's choice in Tables 1–2).

    Parameters
    ----------
    lower, mode, upper : float
        Support [lower, upper] and mode of the triangle (the noise's unit),
        lower <= mode <= upper.

    Returns
    -------
    tuple of float
        (lo, hi) of Θ.

    Examples
    --------
    >>> default_theta(-0.3, 0.0, 0.3)
    (-10.0, 10.0)
    """
    sigma = (upper - lower) / 6.0
    return mode - 100.0 * sigma, mode + 100.0 * sigma


def triangular_evidence(
    lower: float,
    mode: float,
    upper: float,
    p: int = 3,
    epsilon: float = 0.05,
    theta: tuple[float, float] | None = None,
) -> IntervalEvidence:
    """Evidence of a bounded noise from its triangular possibility distribution (eqs. 24–26).

    p α-cuts get mass (1 − ε)/p each; Θ gets ε. With the paper's state noise
    (−0.3, 0, 0.3), p = 3, ε = 0.05 and Θ = [−10, 10] this is Table 1.

    Parameters
    ----------
    lower, mode, upper
        Support and mode of the triangle.
    p
        Number of α-cuts (focal elements besides Θ).
    epsilon
        Discount rate ε in [0, 1); 0 gives the p cuts alone.
    theta
        The frame (lo, hi) that receives ε. Default :func:`default_theta`.

    Returns
    -------
    IntervalEvidence
        p nested cuts (innermost first) and Θ, scalar (d = 1).

    Raises
    ------
    EvidenceError
        For a bad triangle, p < 1, or ε outside [0, 1).

    References
    ----------
    The paper's eqs. (24)–(26) and Tables 1–2.

    Examples
    --------
    The state noise of the paper's gauge (Table 1):

    >>> e = triangular_evidence(-0.3, 0.0, 0.3, p=3, epsilon=0.05, theta=(-10.0, 10.0))
    >>> e.lo_1d.round(4).tolist(), e.hi_1d.round(4).tolist()
    ([-0.1, -0.2, -0.3, -10.0], [0.1, 0.2, 0.3, 10.0])
    >>> e.mass.round(4).tolist()
    [0.3167, 0.3167, 0.3167, 0.05]
    """
    lower, mode, upper = _check_triangle(lower, mode, upper)
    lo, hi = alpha_cuts(lower, mode, upper, p)
    epsilon = real_number(
        epsilon, "epsilon", low=0.0, high=1.0, high_open=True, error=EvidenceError
    )
    cuts = IntervalEvidence(lo, hi, np.full(lo.size, 1.0 / lo.size), merge=False)
    if epsilon == 0.0:
        return cuts
    if theta is None:
        t_lo, t_hi = default_theta(lower, mode, upper)
    else:
        pair = real_array(theta, "theta", error=EvidenceError).reshape(-1)
        if pair.size != 2:
            raise EvidenceError(f"theta must be one pair (lo, hi), got {theta!r}")
        t_lo, t_hi = float(pair[0]), float(pair[1])
    if not (t_lo <= lower and upper <= t_hi):
        raise EvidenceError(f"Θ = [{t_lo}, {t_hi}] must contain the support [{lower}, {upper}]")
    return discount(cuts, epsilon, theta=np.array([t_lo, t_hi]))


def triangular_from_samples(samples: Any, k: float = 3.0) -> TriangularBounds:
    """Bounds mean ± kσ and mode at the mean of measured errors (the paper's Figs. 8–9).

    Parameters
    ----------
    samples : array_like, shape (N,)
        Measured errors (the noise's unit), N >= 2.
    k : float
        How many standard deviations the bounds lie away, finite, >= 0.

    Returns
    -------
    TriangularBounds
        mean − kσ, the mean, mean + kσ.

    Raises
    ------
    EvidenceError
        For fewer than two samples, non-finite ones, or a bad ``k``.

    Examples
    --------
    >>> triangular_from_samples([-0.1, 0.0, 0.1])
    TriangularBounds(lower=-0.3, mode=0.0, upper=0.3)
    """
    x = real_array(samples, "error samples", finite=False, error=EvidenceError).reshape(-1)
    k = real_number(k, "k", low=0.0, error=EvidenceError)
    if x.size < 2:
        raise EvidenceError(f"need at least 2 error samples to estimate σ, got {x.size}")
    if not np.all(np.isfinite(x)):
        raise EvidenceError("error samples contain NaN or infinite values; remove them first")
    with np.errstate(over="ignore", invalid="ignore"):
        mean, sigma = float(x.mean()), float(x.std(ddof=1))
        lower, upper = mean - k * sigma, mean + k * sigma
    if not (math.isfinite(mean) and math.isfinite(lower) and math.isfinite(upper)):
        raise EvidenceError(
            "the error samples are too large to compute with (their mean or "
            "spread overflows); rescale them"
        )
    return TriangularBounds(lower, mean, upper)
