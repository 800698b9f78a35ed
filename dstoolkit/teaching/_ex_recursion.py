"""The exercises of the chapter on the one recursion (book/one_recursion.md).

Checked answers (the χ² band, a NEES by hand, the unscented mean, the consistency
predictions) and two coding exercises (the unscented transform in one dimension, the
scalar RTS smoother), each computed with dstoolkit.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dstoolkit.filters import chi2_band, nees, rts_smoother, sigma_points, sigma_weights

from ._checking import exercise
from ._coding import Case, coding_exercise, seeded

#: The band exercise: runs N averaged, degrees of freedom, probability.
BAND_RUNS, BAND_DOF, BAND_PROBABILITY = 20, 1, 0.95
#: The NEES by hand: an error and a covariance with a correlation.
HAND_ERROR = (1.0, 2.0)
HAND_COVARIANCE = ((2.0, 1.0), (1.0, 2.0))
#: The unscented mean by hand: f(x) = x² at x̂ = 2, P = 0.5, with (α, β, κ) = (1, 2, 2).
UT_MEAN, UT_VAR, UT_PARAMETERS = 2.0, 0.5, (1.0, 2.0, 2.0)
#: The consistency prediction: the scale of the assumed bounds, and the study's settings.
PREDICT_SCALE, PREDICT_RUNS = 0.5, 50
#: The answers of the choice exercises.
BAND_PLACES = ("above", "inside", "below")
STATISTICS = ("nees", "nis")


def _square(x: Any) -> Any:
    """f(x) = x², the nonlinear map of the unscented exercise."""
    return x * x


def _ut(f: Any, mean: float, var: float, alpha: float, beta: float, kappa: float) -> tuple:
    """Return the unscented mean and variance of f(x) with dstoolkit's sigma points (n = 1)."""
    scale, wm, wc = sigma_weights(1, alpha, beta, kappa)
    points = sigma_points(np.array([mean]), np.array([[var]]), float(scale))[:, 0]
    images = np.array([f(float(p)) for p in points])
    m = float(wm @ images)
    return m, float(wc @ (images - m) ** 2)


@exercise(
    "recursion.band",
    atol=2e-3,
    hint="The sum of N independent χ²(n) values is χ²(N n); take its 2.5 % and 97.5 % "
    "quantiles (scipy.stats.chi2.ppf) and divide both by N.",
    mistakes=(
        (
            lambda: chi2_band(BAND_DOF, 1, BAND_PROBABILITY),
            "That is the band of one value: the average of N values is N times narrower "
            "around n in relative terms — use χ²(N n) and divide by N.",
        ),
    ),
)
def _() -> tuple[float, float]:
    return chi2_band(BAND_DOF, BAND_RUNS, BAND_PROBABILITY)


@exercise(
    "recursion.nees",
    atol=1e-6,
    hint="Invert P (a 2 × 2 matrix: swap the diagonal, negate the rest, divide by the "
    "determinant), then form eᵀ P⁻¹ e.",
    mistakes=(
        (
            lambda: sum(e * e / HAND_COVARIANCE[i][i] for i, e in enumerate(HAND_ERROR)),
            "You divided each component by its own variance: that ignores the correlation "
            "(the off-diagonal 1) of the errors.",
        ),
    ),
)
def _() -> float:
    return float(nees(HAND_ERROR, HAND_COVARIANCE))


@exercise(
    "recursion.ut-mean",
    atol=1e-6,
    hint="λ = α²(n + κ) − n; the points are x̂ and x̂ ± √((n + λ) P); weigh f at each with "
    "W^m: λ/(n + λ) at the centre, 1/(2(n + λ)) on each side.",
    mistakes=(
        (
            lambda: _square(UT_MEAN),
            "That is f(x̂), the extended Kalman filter's prediction: the unscented points "
            "also see the curvature of f over the spread P.",
        ),
    ),
)
def _() -> float:
    return _ut(_square, UT_MEAN, UT_VAR, *UT_PARAMETERS)[0]


def _predicted_place() -> str:
    from dstoolkit.studies import gauge_consistency

    study = gauge_consistency(runs=PREDICT_RUNS, scale=PREDICT_SCALE)
    value = float(study.nees["kalman"].mean())
    low, high = study.nees_band
    return "above" if value > high else "below" if value < low else "inside"


@exercise(
    "recursion.predict-choice",
    hint=f"Answer one of {BAND_PLACES}. A filter that assumes smaller noises reports a "
    "smaller P; the errors stay what they are.",
    mistakes=(
        (
            lambda: "below",
            "Below the band means P too large: a filter that assumes half the bounds "
            "reports a quarter of the variance.",
        ),
    ),
)
def _() -> str:
    return _predicted_place()


@exercise(
    "recursion.statistic-choice",
    hint=f"Answer one of {STATISTICS}. Which one compares the estimate with the truth, "
    "and which one compares the reading with a prediction that already used it?",
    mistakes=(
        (
            lambda: "nis",
            "The NIS compares z_{k+1} with a prediction made from eq. 43's order, which was "
            "computed from z_{k+1} itself: it cannot see the error that shares its cause.",
        ),
    ),
)
def _() -> str:
    from dstoolkit.studies import gauge_consistency

    study = gauge_consistency(runs=PREDICT_RUNS, orders="eq43")
    # the statistic that flags the filter: the one outside its band, above
    return "nees" if study.share("kalman", "above") > 0.5 else "nis"


# -- coding -----------------------------------------------------------------------------------


def _cube(x: float) -> float:
    """f(x) = x³ (odd: the unscented mean of a symmetric spread is exact)."""
    return x**3


def _sine(x: float) -> float:
    """f(x) = sin x."""
    return float(np.sin(x))


def _line(x: float) -> float:
    """f(x) = 3x − 1 (linear: the transform is exact)."""
    return 3.0 * x - 1.0


def _ut_cases() -> list[Case]:
    rng = seeded(131)
    cases = [
        Case("x² at 2, P = 0.5, (1, 2, 2)", (_square, 2.0, 0.5, 1.0, 2.0, 2.0)),
        Case("a line (exact)", (_line, 1.0, 4.0, 1.0, 2.0, 0.0)),
        Case("zero variance (a point)", (_square, 1.5, 0.0, 0.5, 2.0, 1.0)),
    ]
    for i, f in enumerate((_cube, _sine, _square)):
        cases.append(
            Case(
                f"random {i + 1}",
                (
                    f,
                    float(rng.uniform(-2, 2)),
                    float(rng.uniform(0.1, 2.0)),
                    float(rng.uniform(0.5, 1.5)),
                    float(rng.uniform(0.0, 3.0)),
                    float(rng.uniform(0.0, 2.0)),
                ),
            )
        )
    return cases


coding_exercise(
    "recursion.ut-code",
    reference=_ut,
    cases=_ut_cases,
    arg_names=("f", "mean", "var", "alpha", "beta", "kappa"),
    hint="Three points: mean and mean ± √((1 + λ) var), λ = α²(1 + κ) − 1. The mean "
    "weights are λ/(1 + λ), 1/(2(1 + λ)), 1/(2(1 + λ)); the variance weights the same but "
    "the centre's gets + 1 − α² + β.",
    mistakes=(
        (
            lambda f, mean, var, alpha, beta, kappa: (f(mean), 0.0),
            "You returned f at the mean: the transform averages f over the sigma points.",
        ),
        (
            lambda f, mean, var, alpha, beta, kappa: (
                _ut(f, mean, var, alpha, 0.0, kappa)[:1] + (_ut(f, mean, var, 1.0, 0.0, kappa)[1],)
            ),
            "The centre's variance weight is the mean weight plus 1 − α² + β.",
        ),
    ),
)


def _rts_reference(x: list, p: list, a: float, q: float) -> tuple[list, list]:
    out = rts_smoother(np.array(x)[:, None], np.array(p)[:, None, None], [[a]], [[q]])
    return out.estimates[:, 0].tolist(), out.covariances[:, 0, 0].tolist()


def _rts_cases() -> list[Case]:
    rng = seeded(132)
    cases = [
        Case("two steps of a random walk", ([0.0, 1.0], [1.0, 0.5], 1.0, 1.0)),
        Case("one step (nothing to smooth)", ([2.0], [0.3], 1.0, 0.1)),
        Case(
            "the gauge's growth a = (n + 1)/n",
            ([1000.0, 1037.9, 1075.1], [2.0, 1.1, 0.9], 28.0 / 27.0, 0.015),
        ),
    ]
    for i in range(3):
        t = int(rng.integers(3, 8))
        cases.append(
            Case(
                f"random {i + 1}",
                (
                    [float(v) for v in rng.normal(0, 2, t)],
                    [float(v) for v in rng.uniform(0.2, 2.0, t)],
                    float(rng.uniform(0.5, 1.5)),
                    float(rng.uniform(0.05, 1.0)),
                ),
            )
        )
    return cases


coding_exercise(
    "recursion.rts-code",
    reference=_rts_reference,
    cases=_rts_cases,
    arg_names=("x", "p", "a", "q"),
    hint="Go backwards from k = T − 2: predict a x[k] with variance a² p[k] + q, the gain "
    "J = p[k] a / (a² p[k] + q), then correct with the smoothed value of step k + 1.",
    mistakes=(
        (
            lambda x, p, a, q: (list(x), list(p)),
            "You returned the filtered run unchanged: each step must learn from the "
            "smoothed step after it.",
        ),
        (
            lambda x, p, a, q: _forward_smoothing(x, p, a, q),
            "You corrected with the filtered x[k + 1], not the smoothed one: run the "
            "recursion backwards and use the value you have just smoothed.",
        ),
    ),
)


def _forward_smoothing(x: list, p: list, a: float, q: float) -> tuple[list, list]:
    """Smooth each step with the filtered (not the smoothed) next step: the named mistake."""
    xs, ps = list(x), list(p)
    for k in range(len(x) - 1):
        p_pred = a * a * p[k] + q
        gain = p[k] * a / p_pred
        xs[k] = x[k] + gain * (x[k + 1] - a * x[k])
        ps[k] = p[k] + gain * gain * (p[k + 1] - p_pred)
    return xs, ps
