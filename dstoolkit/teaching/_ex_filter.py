"""Checked exercises of the chapter on the recursive filter."""

from __future__ import annotations

from typing import Any

from dstoolkit.evidence import triangular_evidence

from ._checking import exercise
from ._ex_evidence import STATE_NOISE, box_image
from ._variants import book_data, data

# -- the recursive filter (book/recursive_filter.md, notebooks/06_recursive_filter.ipynb) ----

#: The chapter's sequence: the paper's 9.6 m case (level m, °C) and the seed of its readings.
FILTER_CASE, FILTER_SEED = (9.6, 23.9), 0
#: The paper's first reading at 4.6 m (§4.3, Fig. 7), Hz.
PAPER_Z1 = 1023.3
#: Step 2 by hand: estimate x̂_k (Hz) and order n_k.
PREDICT_XHAT, PREDICT_ORDER = 1000.0, 55
#: Discount of the conflict exercise, and the cuts of the counting exercise.
CONFLICT_EPSILON, COUNT_CUTS = 0.1, 5
#: The hand example's x̂_k, z_{k+1} and ε (the rest of it is fixed, see hand_step).
HAND_XHAT, HAND_Z, HAND_EPSILON = 1.0, 1.7, 0.2
book_data(
    "filter",
    {
        "hand_xhat": HAND_XHAT,
        "hand_z": HAND_Z,
        "hand_epsilon": HAND_EPSILON,
        "count_cuts": COUNT_CUTS,
        "predict_xhat": PREDICT_XHAT,
        "predict_order": PREDICT_ORDER,
        "z1": PAPER_Z1,
        "conflict_epsilon": CONFLICT_EPSILON,
    },
)


def _gauge_model() -> Any:
    from dstoolkit.gauge import gauge_state_space_model

    return gauge_state_space_model()


@exercise(
    "filter.counts",
    atol=0.0,
    rtol=0.0,
    varies=True,
    hint="With p cuts a noise evidence has p + 1 focal elements (Θ included); the "
    "prediction pairs every state focal element with every noise one, Step 4 every "
    "predicted one with every observation one, Step 6 every Step-4 product with every "
    "predicted one. Answer (state, prediction, Step-4 products, Step-6 products).",
    mistakes=(
        (
            lambda: (lambda p: (p, p**2, p**3, p**5))(data("filter")["count_cuts"]),
            "Do not forget Θ: the discount adds one focal element to each noise evidence (eq. 26).",
        ),
    ),
)
def _() -> tuple[int, int, int, int]:
    from dstoolkit.filters import DependentEvidenceFilter

    cuts = data("filter")["count_cuts"]
    noise = DependentEvidenceFilter(p=cuts).noise_evidence(_gauge_model())
    nv, nw = len(noise.state), len(noise.observation)
    return nv, nv * nv, nv * nv * nw, nv * nv * nw * nv * nv


def _innermost_prediction(twice: bool = True) -> tuple[float, float]:
    d = data("filter")
    xhat, order = d["predict_xhat"], d["predict_order"]
    v = triangular_evidence(*STATE_NOISE)  # innermost cut first (Table 1)
    lo, hi = box_image(
        [xhat + v.lo_1d[0]], [xhat + v.hi_1d[0]], lambda x: _gauge_model().f(x, order), monotone=[1]
    )
    extra = (float(v.lo_1d[0]), float(v.hi_1d[0])) if twice else (0.0, 0.0)
    return float(lo[0]) + extra[0], float(hi[0]) + extra[1]


@exercise(
    "filter.prediction",
    atol=5e-3,
    rtol=0.0,
    varies=True,
    hint="Step 2: map the state box x̂ + [−0.1, 0.1] through eq. (39) (increasing: map "
    "the ends), then add the noise box [−0.1, 0.1]. Answer (lo, hi).",
    mistakes=(
        (
            lambda: _innermost_prediction(twice=False),
            "The noise enters twice in Step 2 (paper §3.2): once in the state evidence "
            "x̂ + V, once as v in x_{k+1} = f(x_k) + v_k. Add [−0.1, 0.1] again.",
        ),
    ),
)
def _() -> tuple[float, float]:
    return _innermost_prediction()


@exercise(
    "filter.mean-corrected",
    atol=0.01,
    rtol=0.0,
    varies=True,
    hint="g(x) = z + w (eq. 21, 'adding noise to z'): the reading is high when w < 0; "
    "correct z_1 by the mean of w, (a + b + c)/3.",
    mistakes=(
        (
            lambda: data("filter")["z1"] - float(_gauge_model().obs_noise.mean[0]),
            "Check the sign: with g(x) = z + w the state is z + w, so add E[w] "
            "(which is negative).",
        ),
        (lambda: data("filter")["z1"], "That is the paper's start, z_1 itself."),
    ),
)
def _() -> float:
    return data("filter")["z1"] + float(_gauge_model().obs_noise.mean[0])


@exercise(
    "filter.conflict-start",
    atol=1e-6,
    varies=True,
    hint="With the paper's start every cut of the prediction misses every cut of the "
    "observation: only products with a Θ survive. K is the mass of the others.",
    mistakes=(
        (
            lambda: (1.0 - 0.05) ** 3,
            "That is K for the chapter's ε = 0.05; the question asks for another ε.",
        ),
    ),
)
def _() -> float:
    from dstoolkit.studies import filter_case

    epsilon = data("filter")["conflict_epsilon"]
    _, _, result = filter_case(*FILTER_CASE, epsilon=epsilon, seed=FILTER_SEED)
    return float(result.diagnostics["conflict_step4"][1])


@exercise(
    "filter.mass-rule",
    hint="Which choice of m(D) can make the energy of the "
    "intersection exceed the energies themselves, so that D > 1?",
)
def _() -> str:
    from dstoolkit.errors import EvidenceError
    from dstoolkit.studies import filter_case

    for rule in ("min", "m1", "m2"):
        try:
            filter_case(*FILTER_CASE, mass_rule=rule, seed=FILTER_SEED)
        except EvidenceError:
            return rule
    raise AssertionError("no m(D) rule fails on the chapter's sequence")


# -- one update by hand (the chapter's first exercise) -------------------------------------


def hand_step() -> tuple:
    """Return the hand example's step with the sheet's x̂_k, z_{k+1} and ε.

    The step is (x̂_k, z_{k+1}, f, g, g⁻¹, v rows, w rows); the book's is
    ``_ex_coding.HAND_STEP``.
    """
    from ._ex_coding import HAND_STEP, noise_rows

    d = data("filter")
    rows = noise_rows(-0.5, 0.0, 0.5, 1, d["hand_epsilon"], (-2.0, 2.0))
    return (float(d["hand_xhat"]), float(d["hand_z"]), *HAND_STEP[2:5], rows, rows)


def _hand(name: str) -> Any:
    from ._ex_coding import filter_record

    if name == "noise":
        return hand_step()[5]
    step = filter_record(*hand_step())
    if name == "dependence":
        dep = step.dependence_terms
        return dep.degree, dep.r12, dep.r21
    if name == "estimate":
        return float(step.estimate[0])
    return getattr(step, name).to_rows().tolist()


def _hand_plain_dempster() -> list:
    from ._ex_coding import _plain_dempster_step6

    return _plain_dempster_step6(*hand_step())[0]


def _hand_once() -> list:
    """f(x̂ + V) without the second V: the prediction with the noise entering once."""
    xhat, _, f, _, _, v_rows, _ = hand_step()
    return [(float(f(xhat + lo)), float(f(xhat + hi)), m) for lo, hi, m in v_rows]


def _rows_canonical(value: Any) -> list:
    from ._ex_coding import sorted_rows

    return sorted_rows(value)


_ROWS = "Answer a list of rows (lo, hi, mass), in any order; equal intervals merge."
_ONCE = (
    (
        _hand_once,
        "That is f(x̂ + V): the noise enters twice in Step 2; add V again to every box "
        "(eq. 16: the masses multiply).",
    ),
)


@exercise(
    "filter.hand-noise",
    varies=True,
    canonical=_rows_canonical,
    hint="Eqs. 24–26 with p = 1: a single cut, at α = 0, shares 1 − ε; what is left "
    "goes to the frame Θ given in the statement. " + _ROWS,
)
def _() -> list:
    return _hand("noise")


@exercise(
    "filter.hand-prediction",
    varies=True,
    canonical=_rows_canonical,
    mistakes=_ONCE,
    hint="Step 2: every state box x̂ + V_i, through f (here f(x) = x), plus every noise "
    "box V_j, with mass m_i·m_j; boxes that come out equal merge. " + _ROWS,
)
def _() -> list:
    return _hand("prediction")


@exercise(
    "filter.hand-observation-prediction",
    varies=True,
    canonical=_rows_canonical,
    hint="Step 3: g of every predicted box, masses unchanged; here g(x) = x. " + _ROWS,
)
def _() -> list:
    return _hand("observation_prediction")


@exercise(
    "filter.hand-fused",
    varies=True,
    canonical=_rows_canonical,
    hint="Step 4: the reading's evidence is z + W (every row of Step 1 moved by z); "
    "intersect every box of Step 3 with every one of it (eq. 1). " + _ROWS,
    mistakes=(
        (
            lambda: _hand("observation_prediction"),
            "That is Step 3 again: Step 4 intersects it with the reading's evidence z + W.",
        ),
    ),
)
def _() -> list:
    return _hand("fused")


@exercise(
    "filter.hand-mapped",
    varies=True,
    canonical=_rows_canonical,
    hint="Step 5: g⁻¹ of every fused box, within the predicted box it came from; "
    "with g(x) = x nothing moves, and equal boxes merge. " + _ROWS,
)
def _() -> list:
    return _hand("mapped_back")


@exercise(
    "filter.hand-dependence",
    varies=True,
    atol=1e-3,
    hint="Eqs. A1–A6: En′ of each evidence (w_min its own narrowest width), the joint "
    "energy over the shared [0, 2] with unit min(w_min(E1), w_min(E2)), then D, R12, "
    "R21. Answer (D, R12, R21).",
    mistakes=(
        (
            lambda: (lambda d, r12, r21: (d, r21, r12))(*_hand("dependence")),
            "R12 and R21 are swapped: R12 = 1 − (D/2)·En′(E2)/En′(E1).",
        ),
    ),
)
def _() -> tuple[float, float, float]:
    return _hand("dependence")


@exercise(
    "filter.hand-final",
    varies=True,
    canonical=_rows_canonical,
    hint="Step 6: discount E1 at 1 − R12 and E2 at 1 − R21 onto their hulls (eqs. "
    "A7–A8), then Dempster's rule. " + _ROWS,
    mistakes=(
        (
            _hand_plain_dempster,
            "That is plain Dempster of E1 and E2: Step 6 decorrelates them first "
            "(they share [0, 2]).",
        ),
    ),
)
def _() -> list:
    return _hand("final")


@exercise(
    "filter.hand-estimate",
    varies=True,
    atol=1e-3,
    hint="Eq. 20: Σ m·(midpoint) over the final focal elements.",
    mistakes=(
        (
            lambda: hand_step()[1],
            "That is the reading z itself; the estimate weighs it against the prediction.",
        ),
        (
            lambda: hand_step()[2](hand_step()[0]),
            "That is the prediction's expectation f(x̂); the estimate takes the reading in.",
        ),
        (
            lambda: float(sum(m * (lo + hi) / 2 for lo, hi, m in _hand_plain_dempster())),
            "That is the expectation after plain Dempster in Step 6; decorrelate first.",
        ),
    ),
)
def _() -> float:
    return _hand("estimate")
