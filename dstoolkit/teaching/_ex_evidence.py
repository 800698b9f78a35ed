"""Checked exercises of the evidence chapters.

Why bounded noise, mass functions, combining evidence, dependent evidence, noise to evidence, random
sets.
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np

from dstoolkit.errors import TotalConflictError
from dstoolkit.evidence import (
    APPENDIX_A2,
    PAPER_A6,
    PAPER_EN1,
    IntervalEvidence,
    MassFunction,
    alpha_cuts,
    appendix_pair,
    combine_dependent,
    conflict,
    decorrelate,
    default_theta,
    dempster,
    dependence,
    energy,
    joint_energy,
    triangular_evidence,
)

from ._checking import exercise
from ._variants import book_data, data

# -- why bounded noise (book/why_bounded_noise.md, notebooks/00_why_bounded_noise.ipynb) --

#: Bounded-error step: the state is known to lie in BOX; v ∈ V, reading z with w ∈ W.
BOUNDED_BOX, BOUNDED_V, BOUNDED_W, BOUNDED_Z = (1.2, 2.0), (-0.3, 0.3), (-0.5, 0.5), 2.6
BOUNDED_W_TIGHT = (-0.2, 0.2)


def _box(lo: float, hi: float) -> IntervalEvidence:
    """Return a set as categorical evidence: the interval [lo, hi] with mass 1."""
    return IntervalEvidence.vacuous(lo, hi)


def _predicted() -> IntervalEvidence:
    return _box(BOUNDED_BOX[0] + BOUNDED_V[0], BOUNDED_BOX[1] + BOUNDED_V[1])


def _updated(w: tuple[float, float]) -> IntervalEvidence:
    # x = z + w (the paper's sign convention of eq. 21 makes no difference for symmetric w)
    return dempster(_predicted(), _box(BOUNDED_Z + w[0], BOUNDED_Z + w[1]))


@exercise(
    "bounded.predict",
    hint="Add the noise bounds to the ends: [a + v_a, b + v_b].",
    mistakes=(
        (
            lambda: BOUNDED_BOX,
            "That is X_k itself: the state moves by v before "
            "the next reading, so widen the box by v.",
        ),
    ),
)
def _() -> tuple[float, float]:
    ev = _predicted()
    return float(ev.lo_1d[0]), float(ev.hi_1d[0])


@exercise(
    "bounded.update",
    hint="The reading says x ∈ [z − 0.5, z + 0.5]; keep what both intervals share.",
    mistakes=(
        (
            lambda: (BOUNDED_Z + BOUNDED_W[0], BOUNDED_Z + BOUNDED_W[1]),
            "That is what the reading alone allows; the state must also lie in the "
            "prediction: intersect the two.",
        ),
        (
            lambda: (BOUNDED_BOX[0] + BOUNDED_V[0], BOUNDED_Z + BOUNDED_W[1]),
            "That is the hull (union) of prediction and reading; the state lies in "
            "both, so intersect.",
        ),
    ),
)
def _() -> tuple[float, float]:
    ev = _updated(BOUNDED_W)
    return float(ev.lo_1d[0]), float(ev.hi_1d[0])


@exercise(
    "bounded.too-tight",
    hint="Compare the upper end of the prediction with the lower end of [z − 0.2, z + 0.2].",
)
def _() -> bool:
    try:
        _updated(BOUNDED_W_TIGHT)
    except TotalConflictError:
        return True
    return False


# -- mass functions (book/mass_functions.md, notebooks/01_mass_functions.ipynb) ----------

FRAME = ("low", "mid", "high")
book_data("mass", {"m_low": 0.5, "m_low_mid": 0.3, "m_theta": 0.2})


def level_mass() -> MassFunction:
    """Return the chapter's running example.

    m({low}) = 0.5, m({low, mid}) = 0.3, m(Θ) = 0.2 (in a variant, its own masses).
    """
    d = data("mass")
    return MassFunction(
        {"low": d["m_low"], ("low", "mid"): d["m_low_mid"], FRAME: d["m_theta"]}, FRAME
    )


@exercise(
    "mass.bel",
    varies=True,
    hint="Bel(A) adds the masses of the focal elements contained in A.",
    mistakes=(
        (
            lambda: level_mass().plausibility(("low", "mid")),
            "That is Pl({low, mid}): it also counts Θ, which meets {low, mid} "
            "without lying inside it.",
        ),
        (
            lambda: level_mass().mass_of(("low", "mid")),
            "That is m({low, mid}) alone; Bel adds every focal element inside the set, {low} too.",
        ),
    ),
)
def _() -> float:
    return level_mass().belief(("low", "mid"))


@exercise(
    "mass.pl",
    varies=True,
    hint="Pl(A) adds the masses of the focal elements that meet A.",
    mistakes=(
        (
            lambda: level_mass().belief("mid"),
            "That is Bel({mid}); plausibility also counts the sets that only overlap {mid}.",
        ),
    ),
)
def _() -> float:
    return level_mass().plausibility("mid")


@exercise(
    "mass.betp",
    varies=True,
    hint="Share each focal element's mass equally among its members.",
    mistakes=(
        (
            lambda: level_mass().plausibility("mid"),
            "That is Pl({mid}): each mass must be divided by the size of its set.",
        ),
    ),
)
def _() -> float:
    return level_mass().pignistic()["mid"]


@exercise(
    "mass.duality",
    varies=True,
    hint="Pl(A) = 1 − Bel(complement of A).",
    mistakes=(
        (
            lambda: level_mass().belief("high"),
            "That is Bel({high}); Pl({high}) = 1 − Bel({low, mid}).",
        ),
        (
            lambda: level_mass().belief(("low", "mid")),
            "That is Bel({low, mid}) itself; subtract it from 1.",
        ),
    ),
)
def _() -> float:
    return level_mass().plausibility("high")


@exercise("mass.vacuous-betp", hint="Total ignorance spreads the mass of Θ evenly.")
def _() -> dict[str, float]:
    return {str(k): v for k, v in MassFunction.vacuous(FRAME).pignistic().items()}


# -- combining evidence (book/combining_evidence.md, notebooks/02_combining_evidence.ipynb) --


book_data(
    "combine",
    {
        "m1_low": 0.6,
        "m1_theta": 0.4,
        "m2_high": 0.7,
        "m2_mid_high": 0.2,
        "m2_theta": 0.1,
        "zadeh_x": 0.99,
        "zadeh_x_rest": 0.01,
        "zadeh_y": 0.99,
        "zadeh_y_rest": 0.01,
        "once_low": 0.5,
        "once_theta": 0.5,
    },
)


def sensor_masses() -> tuple[MassFunction, MassFunction]:
    """Two level sensors.

    m1({low}) = 0.6, m1(Θ) = 0.4; m2({high}) = 0.7, m2({mid, high}) = 0.2, m2(Θ) = 0.1 (in a
    variant, its own masses).
    """
    d = data("combine")
    m1 = MassFunction({"low": d["m1_low"], FRAME: d["m1_theta"]}, FRAME)
    m2 = MassFunction(
        {"high": d["m2_high"], ("mid", "high"): d["m2_mid_high"], FRAME: d["m2_theta"]}, FRAME
    )
    return m1, m2


@exercise(
    "combine.conflict",
    varies=True,
    hint="K adds m1(B)·m2(C) over the pairs with B ∩ C = ∅.",
    mistakes=(
        (
            lambda: sensor_masses()[0].mass_of("low") * sensor_masses()[1].mass_of("high"),
            "You counted {low} ∩ {high} only; {low} ∩ {mid, high} is empty too.",
        ),
    ),
)
def _() -> float:
    return conflict(*sensor_masses())


@exercise(
    "combine.low",
    varies=True,
    hint="Only {low} ∩ Θ gives {low}; divide its product by 1 − K.",
    mistakes=(
        (
            lambda: sensor_masses()[0].mass_of("low") * sensor_masses()[1].mass_of(FRAME),
            "You forgot to renormalise: divide by 1 − K.",
        ),
    ),
)
def _() -> float:
    return dempster(*sensor_masses()).mass_of("low")


def zadeh(x: float = 0.99, y: float = 0.99) -> tuple[MassFunction, MassFunction]:
    """Zadeh's doctors.

    m1(meningitis) = x, m1(tumour) = 1 − x; m2(concussion) = y, m2(tumour) = 1 − y.

    Parameters
    ----------
    x, y : float
        Each doctor's mass on their own diagnosis, in [0, 1].

    Returns
    -------
    (MassFunction, MassFunction)
        The two doctors' evidence on the frame (meningitis, concussion, tumour).

    Examples
    --------
    >>> from dstoolkit import dempster
    >>> from dstoolkit.teaching import zadeh
    >>> round(dempster(*zadeh()).mass_of("tumour"), 6)
    1.0
    """
    frame = ("meningitis", "concussion", "tumour")
    return (
        MassFunction({"meningitis": x, "tumour": 1 - x}, frame),
        MassFunction({"concussion": y, "tumour": 1 - y}, frame),
    )


@exercise("combine.zadeh", hint="Which product is the only non-empty intersection?")
def _() -> float:
    return dempster(*_zadeh()).mass_of("tumour")


def _zadeh() -> tuple[MassFunction, MassFunction]:
    """Zadeh's doctors with the sheet's x and y."""
    d = data("combine")
    return zadeh(d["zadeh_x"], d["zadeh_y"])


@exercise(
    "combine.zadeh-conflict",
    hint="1 − K is the product of the two small masses.",
    varies=True,
    mistakes=(
        (
            lambda: data("combine")["zadeh_x"] * data("combine")["zadeh_y"],
            "That is only meningitis × concussion; the products with tumour on "
            "one side are in conflict too.",
        ),
    ),
)
def _() -> float:
    return conflict(*_zadeh())


def once() -> MassFunction:
    """Return one source: m({low}) = 0.5, m(Θ) = 0.5.

    It is combined with itself in combine.twice; in a variant, it has its own masses.

    Returns
    -------
    MassFunction
        The source, on the frame ``FRAME`` (low, mid, high).

    Examples
    --------
    >>> from dstoolkit.teaching import once
    >>> once().mass_of("low")
    0.5
    """
    d = data("combine")
    return MassFunction({"low": d["once_low"], FRAME: d["once_theta"]}, FRAME)


@exercise(
    "combine.twice",
    hint="Combine m with itself by eq. (1).",
    varies=True,
    mistakes=(
        (
            lambda: once().mass_of("low"),
            "That is m({low}) before combining: Dempster's rule counts the same source twice.",
        ),
    ),
)
def _() -> float:
    return dempster(once(), once()).mass_of("low")


# -- dependent evidence (book/dependent_evidence.md, notebooks/03_dependent_evidence.ipynb) --


book_data(
    "dependent",
    {
        "e1_low": 0.5,
        "e1_low_mid": 0.3,
        "e1_theta": 0.2,
        "e2_low": 0.4,
        "e2_mid": 0.4,
        "e2_theta": 0.2,
    },
)


def dependent_pair() -> tuple[MassFunction, MassFunction]:
    """Return the two dependent pieces of evidence E1 and E2: they share {low} and Θ.

    E1 = {low: 0.5, {low, mid}: 0.3, Θ: 0.2}; E2 = {low: 0.4, mid: 0.4, Θ: 0.2} (in a
    variant, its own masses).
    """
    d = data("dependent")
    return (
        MassFunction(
            {"low": d["e1_low"], ("low", "mid"): d["e1_low_mid"], FRAME: d["e1_theta"]}, FRAME
        ),
        MassFunction({"low": d["e2_low"], "mid": d["e2_mid"], FRAME: d["e2_theta"]}, FRAME),
    )


@exercise(
    "dependent.energy",
    hint="Eq. (2): Σ m(A)/|A| over the focal elements other than Θ.",
    varies=True,
    mistakes=(
        (
            lambda: float(sum(m / len(a) for a, m in dependent_pair()[0].as_dict().items())),
            "Θ is left out of the energy: its mass carries no information.",
        ),
    ),
)
def _() -> float:
    return energy(dependent_pair()[0])


@exercise(
    "dependent.joint",
    varies=True,
    hint="Eq. (3) sums min(m1(D), m2(D))/|D| over the shared focal elements D other than Θ.",
    mistakes=(
        (
            lambda: joint_energy(*dependent_pair(), mass_rule="m1"),
            "You took E1's mass of the shared {low}; eq. 3 takes the smaller of the "
            "two, min(m1, m2).",
        ),
    ),
)
def _() -> float:
    return joint_energy(*dependent_pair())


@exercise(
    "dependent.degree",
    varies=True,
    hint="D = 2 En(E1,E2) / (En(E1) + En(E2)).",
    mistakes=(
        (
            lambda: dependence(*dependent_pair()).degree / 2,
            "You forgot the factor 2: D = 2 En(E1, E2)/(En(E1) + En(E2)), so that "
            "a source with itself has D = 1.",
        ),
    ),
)
def _() -> float:
    return dependence(*dependent_pair()).degree


@exercise(
    "dependent.coefficients",
    varies=True,
    hint="R12 = 1 − (D/2)·En(E2)/En(E1); swap for R21. Answer (R12, R21).",
    mistakes=(
        (
            lambda: (dependence(*dependent_pair()).r21, dependence(*dependent_pair()).r12),
            "R12 and R21 are swapped: R12 = 1 − (D/2)·En(E2)/En(E1).",
        ),
    ),
)
def _() -> tuple[float, float]:
    dep = dependence(*dependent_pair())
    return dep.r12, dep.r21


@exercise(
    "dependent.combined-low",
    varies=True,
    hint="Discount E1 by R12 and E2 by R21 (mass 1 − R to Θ), then apply Dempster's rule.",
    mistakes=(
        (
            lambda: dependent_pair()[0].belief("low"),
            "That is Bel({low}) of E1 alone, before combining: the combination "
            "must also take in what E2 says.",
        ),
        (
            lambda: dempster(*dependent_pair()).belief("low"),
            "That is plain Dempster's rule, which counts the shared {low} twice: "
            "discount each source by its dependency coefficient first.",
        ),
        (
            lambda: dependent_pair()[1].belief("low"),
            "That is Bel({low}) of E2 alone; combine both sources.",
        ),
    ),
)
def _() -> float:
    return combine_dependent(*dependent_pair()).mass_of("low")


@exercise("dependent.a2", hint="Eq. (A1): Σ m(A_i)·w_min/w(A_i); here w_min = 1.6.")
def _() -> float:
    return energy(IntervalEvidence.from_pairs(APPENDIX_A2))


@exercise(
    "dependent.en1-exact",
    atol=5e-5,
    rtol=0.0,
    hint="Three focal elements now: the third, [0.32, 1.93], counts 0.1·1.6/1.61.",
    mistakes=(
        (
            lambda: PAPER_EN1,
            "That is the value the paper prints: it is the energy of the two-element "
            "example (A2), not of E1.",
        ),
    ),
)
def _() -> float:
    return energy(appendix_pair()[0])


@exercise(
    "dependent.a6",
    atol=2e-4,
    rtol=0.0,
    hint="A6 = A2' ∩ B3': m1'([0.3,1.9]) · m2'([0.3,1.9]) = (R12·0.6)(R21·0.6); use the "
    "paper's En'(E1) = 0.8655 and no conflict arises.",
    mistakes=(
        (
            lambda: PAPER_A6,
            "That is the paper's printed value, a slip: compute 0.36·R12·R21 yourself.",
        ),
    ),
)
def _() -> float:
    e1, e2 = appendix_pair()
    return float(combine_dependent(e1, e2, energy1=PAPER_EN1, merge=False).mass[5])


@exercise(
    "dependent.theta-merges",
    hint="Θ of each evidence is the hull of its focal "
    "elements (eqs. A7–A8). Is the hull one of the focal elements?",
)
def _() -> bool:
    e1, e2 = appendix_pair()
    d1, d2, _ = decorrelate(e1, e2)
    return len(d1) == len(e1) and len(d2) == len(e2)


# -- from noise to evidence (book/noise_to_evidence.md, notebooks/04_noise_to_evidence.ipynb) --

#: The paper's state noise (Table 1) and observation noise (Table 2): lower, mode, upper.
STATE_NOISE = (-0.3, 0.0, 0.3)
OBS_NOISE = (-10.59, -6.9, -3.21)
#: Θ as printed in the paper's Table 2.
PAPER_THETA2 = (-129.7, 115.7)
book_data(
    "noise",
    {
        "state": STATE_NOISE,
        "obs": OBS_NOISE,
        "p": 4,
        "epsilon": 0.1,
        "pbox_x": 0.15,
        "pbox_p": 3,
        "pbox_epsilon": 0.05,
        "state_note": " (Table 1)",
        "obs_note": " (Table 2)",
    },
)


def _noise(name: str) -> tuple[float, float, float]:
    """Return the sheet's state (``"state"``) or observation (``"obs"``) noise.

    Lower, mode, upper.
    """
    return data("noise")[name]


@exercise(
    "noise.cut",
    hint="Eq. (24): [a + α(c − a), b − α(b − c)] with α = 1/3.",
    varies=True,
    mistakes=(
        (
            lambda: tuple(float(v[0]) for v in alpha_cuts(*_noise("state"), p=3)),
            "That is the cut at α = 2/3, the innermost; α = 1/3 lies a third of the "
            "way from the support to the mode.",
        ),
    ),
)
def _() -> tuple[float, float]:
    lo, hi = alpha_cuts(*_noise("state"), p=3)
    return float(lo[1]), float(hi[1])


@exercise(
    "noise.mass",
    hint="Each of the p cuts gets (1 − ε)/p.",
    varies=True,
    mistakes=(
        (
            lambda: 1.0 / data("noise")["p"],
            "That is 1/p: Θ takes ε first, so each cut gets (1 − ε)/p.",
        ),
    ),
)
def _() -> float:
    d = data("noise")
    a, c, b = d["state"]
    return float(triangular_evidence(a, c, b, p=d["p"], epsilon=d["epsilon"]).mass[0])


@exercise(
    "noise.theta2",
    hint="σ = (b − a)/6, and Θ = c ± 100σ.",
    varies=True,
    mistakes=(
        (
            lambda: PAPER_THETA2,
            "That is what the paper prints; c ± 100σ gives "
            "another interval. Recompute σ from the bounds.",
        ),
    ),
)
def _() -> tuple[float, float]:
    return default_theta(*_noise("obs"))


@exercise(
    "noise.expectation", hint="Eq. (20): Σ m·(midpoint). Where are the midpoints?", varies=True
)
def _() -> float:
    return float(triangular_evidence(*_noise("obs")).pignistic_expectation_1d())


@exercise(
    "noise.pbox",
    hint="Bel((−∞, x]) counts focal elements entirely left of x; "
    "Pl((−∞, x]) those that start left of x. Answer (lower, upper).",
    varies=True,
    mistakes=(
        (
            lambda: tuple(reversed(_pbox())),
            "Lower and upper are swapped: the lower bound Bel counts only the "
            "intervals entirely left of x.",
        ),
    ),
)
def _pbox() -> tuple[float, float]:
    d = data("noise")
    a, c, b = d["state"]
    evidence = triangular_evidence(
        a, c, b, p=d["pbox_p"], epsilon=d["pbox_epsilon"], theta=(-10, 10)
    )
    lower, upper = evidence.cdf_bounds(d["pbox_x"])
    return float(lower), float(upper)


# -- random sets (book/random_sets.md, notebooks/05_random_sets.ipynb) ----------------------

#: Marginals of the chapter's random relation, rows (lo, hi, mass); the box asked about.
RELATION_X1 = ((0.0, 1.0, 0.6), (1.5, 3.0, 0.4))
RELATION_X2 = ((0.0, 2.0, 0.7), (1.0, 4.0, 0.3))
RELATION_BOX = ((1.5, 0.0), (3.0, 2.0))
#: f(ξ) = ξ1 + 2ξ2 − ξ3 on this box (the paper's case in point after Prop. 2).
MONOTONE_BOX = ((0.0, 1.0, 2.0), (1.0, 2.0, 4.0))
MONOTONE_SIGNS = (1, 1, -1)
#: The box of x² that straddles 0, and the evidence whose image merges (eq. 14).
SQUARE_BOX = (-1.0, 2.0)
FOLDED_X = ((-2.0, -1.0, 0.3), (1.0, 2.0, 0.3), (-1.0, 1.0, 0.4))
#: Boxes and dimension of the evaluation count (Step 2 of the filter: 16 boxes in 2-D).
COUNT_BOXES, COUNT_DIM = 16, 2
book_data(
    "random",
    {
        "x1_a": RELATION_X1[0][2],
        "x1_b": RELATION_X1[1][2],
        "x2_a": RELATION_X2[0][2],
        "x2_b": RELATION_X2[1][2],
        "mono_lo": MONOTONE_BOX[0],
        "mono_hi": MONOTONE_BOX[1],
        "square_lo": SQUARE_BOX[0],
        "square_hi": SQUARE_BOX[1],
        "fold_a": FOLDED_X[0][2],
        "fold_b": FOLDED_X[1][2],
        "fold_c": FOLDED_X[2][2],
        "boxes": COUNT_BOXES,
        "dim": COUNT_DIM,
    },
)


def _monotone_f(xi: np.ndarray) -> np.ndarray:
    return xi[..., 0] + 2.0 * xi[..., 1] - xi[..., 2]


def _square(x: np.ndarray) -> np.ndarray:
    return x[..., 0] ** 2


def _folded_x() -> tuple[tuple[float, float, float], ...]:
    """FOLDED_X with the sheet's masses."""
    d = data("random")
    return tuple(
        (lo, hi, d[key])
        for (lo, hi, _), key in zip(FOLDED_X, ("fold_a", "fold_b", "fold_c"), strict=True)
    )


def _marginals() -> tuple[tuple[tuple[float, float, float], ...], ...]:
    """RELATION_X1 and RELATION_X2 with the sheet's masses."""
    d = data("random")
    return tuple(
        tuple(
            (lo, hi, d[key])
            for (lo, hi, _), key in zip(rows, (f"{name}_a", f"{name}_b"), strict=True)
        )
        for rows, name in ((RELATION_X1, "x1"), (RELATION_X2, "x2"))
    )


def _monotone_box() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """MONOTONE_BOX, or the sheet's box."""
    d = data("random")
    return tuple(map(float, d["mono_lo"])), tuple(map(float, d["mono_hi"]))


def _square_box() -> tuple[float, float]:
    """SQUARE_BOX, or the sheet's interval."""
    d = data("random")
    return float(d["square_lo"]), float(d["square_hi"])


def box_image(lo: Any, hi: Any, f: Any, **options: Any) -> tuple[np.ndarray, np.ndarray]:
    """Return the image of the box [lo, hi] through ``f`` (``dstoolkit.evidence.image``)."""
    from dstoolkit.evidence import image

    return cast(tuple[np.ndarray, np.ndarray], image((lo, hi), f, **options))


def folded_image(merge: bool = True) -> IntervalEvidence:
    """Return the image of FOLDED_X through x² (subdivision: one focal element straddles 0)."""
    from dstoolkit.evidence import image

    return cast(
        IntervalEvidence,
        image(
            IntervalEvidence.from_pairs(_folded_x(), merge=False),
            _square,
            method="subdivision",
            merge=merge,
        ),
    )


@exercise(
    "random.product",
    hint="Eq. (16): the mass of a box is the product of the masses of its sides in the marginals.",
    varies=True,
    mistakes=(
        (
            lambda: (_marginals()[0][1][2] + _marginals()[1][0][2]) / 2,
            "You averaged the two masses; independent marginals multiply (eq. 16).",
        ),
    ),
)
def _() -> float:
    from dstoolkit.evidence import cartesian_product

    rel = cartesian_product([IntervalEvidence.from_pairs(rows) for rows in _marginals()])
    lo, hi = np.array(RELATION_BOX)
    row = np.flatnonzero(np.all(rel.boxes_lo == lo, axis=1) & np.all(rel.boxes_hi == hi, axis=1))
    return float(rel.mass[row[0]])


@exercise(
    "random.monotone",
    varies=True,
    hint="Prop. 2: for v_min take the lower end where f increases and the upper end "
    "where it decreases; v_max the opposite. Answer (lo, hi).",
    mistakes=(
        (
            lambda: tuple(float(_monotone_f(np.array(v))) for v in _monotone_box()),
            "You evaluated f at the lower and upper corners; f decreases in ξ3, so "
            "v_min takes ξ3's upper end.",
        ),
    ),
)
def _() -> tuple[float, float]:
    box = _monotone_box()
    lo, hi = box_image(
        np.array(box[0]), np.array(box[1]), _monotone_f, method="monotone", monotone=MONOTONE_SIGNS
    )
    return float(lo[0]), float(hi[0])


@exercise(
    "random.square",
    hint="Where is the minimum of x² on the interval? Answer (lo, hi).",
    varies=True,
    mistakes=(
        (
            lambda: tuple(sorted(float(_square(np.array([end]))) for end in _square_box())),
            "That is the vertex method's answer: x² has its minimum inside the box "
            "(Prop. 1 does not apply).",
        ),
    ),
)
def _() -> tuple[float, float]:
    box = _square_box()
    lo, hi = box_image([box[0]], [box[1]], _square, method="subdivision")
    return float(lo[0]), float(hi[0])


@exercise(
    "random.merge",
    hint="Which focal elements of X have the image [1, 4]? Eq. (14) adds their masses.",
    varies=True,
    mistakes=(
        (
            lambda: _folded_x()[0][2],
            "That is the mass of one of the two focal elements that map to [1, 4]; "
            "equal images merge and their masses add up (eq. 14).",
        ),
    ),
)
def _() -> float:
    im = folded_image()
    return float(im.mass[(im.lo_1d == 1.0) & (im.hi_1d == 4.0)][0])


@exercise(
    "random.expectation",
    hint="Eq. (20): Σ ρ(R_j)·(midpoint of R_j) over the image [1, 4], [0, 1].",
    varies=True,
    mistakes=(
        (
            lambda: IntervalEvidence.from_pairs(_folded_x()).pignistic_expectation_1d() ** 2,
            "That is f(E[X]); the expectation of the image is taken over the image intervals.",
        ),
    ),
)
def _() -> float:
    return float(folded_image().pignistic_expectation_1d())


@exercise(
    "random.evaluations",
    atol=0.0,
    rtol=0.0,
    varies=True,
    hint="The vertex method evaluates f at the 2^n corners of every box, the monotone "
    "shortcut at 2. Answer (vertex, monotone).",
    mistakes=(
        (
            lambda: (2 ** data("random")["dim"], 2),
            "That is per box; count the evaluations of every box of the relation.",
        ),
    ),
)
def _() -> tuple[int, int]:
    from dstoolkit.evidence import image

    counts = []
    for method in ("vertex", "monotone"):
        seen = [0]

        def f(x: np.ndarray, seen: list[int] = seen) -> np.ndarray:
            seen[0] += int(np.prod(x.shape[:-1]))
            return x.sum(axis=-1)

        boxes, dim = data("random")["boxes"], data("random")["dim"]
        box = np.zeros((boxes, dim))
        image((box, box + 1.0), f, method=method, monotone=np.ones(dim), check=False)
        counts.append(seen[0])
    return counts[0], counts[1]
