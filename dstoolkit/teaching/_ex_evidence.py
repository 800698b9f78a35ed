"""Checked exercises of the evidence chapters: why bounded noise, mass functions,
combining evidence, dependent evidence, noise to evidence, random sets."""

from __future__ import annotations

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

# -- why bounded noise (book/why_bounded_noise.md, notebooks/00_why_bounded_noise.ipynb) --

#: Bounded-error step: the state is known to lie in BOX; v ∈ V, reading z with w ∈ W.
BOUNDED_BOX, BOUNDED_V, BOUNDED_W, BOUNDED_Z = (1.2, 2.0), (-0.3, 0.3), (-0.5, 0.5), 2.6
BOUNDED_W_TIGHT = (-0.2, 0.2)


def _box(lo: float, hi: float) -> IntervalEvidence:
    """A set as categorical evidence: the interval [lo, hi] with mass 1."""
    return IntervalEvidence.vacuous(lo, hi)


def _predicted() -> IntervalEvidence:
    return _box(BOUNDED_BOX[0] + BOUNDED_V[0], BOUNDED_BOX[1] + BOUNDED_V[1])


def _updated(w: tuple[float, float]) -> IntervalEvidence:
    # x = z + w (the paper's sign convention of eq. 21 makes no difference for symmetric w)
    return dempster(_predicted(), _box(BOUNDED_Z + w[0], BOUNDED_Z + w[1]))


@exercise("bounded.predict", hint="Add the noise bounds to the ends: [a + v_a, b + v_b].",
          mistakes=((lambda: BOUNDED_BOX, "That is X_k itself: the state moves by v before "
                     "the next reading, so widen the box by v."),))
def _() -> tuple[float, float]:
    ev = _predicted()
    return float(ev.lo_1d[0]), float(ev.hi_1d[0])


@exercise("bounded.update",
          hint="The reading says x ∈ [z − 0.5, z + 0.5]; keep what both intervals share.",
          mistakes=((lambda: (BOUNDED_Z + BOUNDED_W[0], BOUNDED_Z + BOUNDED_W[1]),
                     "That is what the reading alone allows; the state must also lie in the "
                     "prediction: intersect the two."),
                    (lambda: (BOUNDED_BOX[0] + BOUNDED_V[0], BOUNDED_Z + BOUNDED_W[1]),
                     "That is the hull (union) of prediction and reading; the state lies in "
                     "both, so intersect.")))
def _() -> tuple[float, float]:
    ev = _updated(BOUNDED_W)
    return float(ev.lo_1d[0]), float(ev.hi_1d[0])


@exercise("bounded.too-tight",
          hint="Compare the upper end of the prediction with the lower end of [z − 0.2, z + 0.2].")
def _() -> bool:
    try:
        _updated(BOUNDED_W_TIGHT)
    except TotalConflictError:
        return True
    return False


# -- mass functions (book/mass_functions.md, notebooks/01_mass_functions.ipynb) ----------

FRAME = ("low", "mid", "high")


def level_mass() -> MassFunction:
    """The chapter's running example: m({low}) = 0.5, m({low, mid}) = 0.3, m(Θ) = 0.2."""
    return MassFunction({"low": 0.5, ("low", "mid"): 0.3, FRAME: 0.2}, FRAME)


@exercise("mass.bel", hint="Bel(A) adds the masses of the focal elements contained in A.",
          mistakes=((lambda: level_mass().plausibility(("low", "mid")),
                     "That is Pl({low, mid}): it also counts Θ, which meets {low, mid} "
                     "without lying inside it."),
                    (lambda: level_mass().mass_of(("low", "mid")),
                     "That is m({low, mid}) alone; Bel adds every focal element inside the "
                     "set, {low} too.")))
def _() -> float:
    return level_mass().belief(("low", "mid"))


@exercise("mass.pl", hint="Pl(A) adds the masses of the focal elements that meet A.",
          mistakes=((lambda: level_mass().belief("mid"),
                     "That is Bel({mid}); plausibility also counts the sets that only "
                     "overlap {mid}."),))
def _() -> float:
    return level_mass().plausibility("mid")


@exercise("mass.betp", hint="Share each focal element's mass equally among its members.",
          mistakes=((lambda: level_mass().plausibility("mid"),
                     "That is Pl({mid}): each mass must be divided by the size of its set."),))
def _() -> float:
    return level_mass().pignistic()["mid"]


@exercise("mass.duality", hint="Pl(A) = 1 − Bel(complement of A).",
          mistakes=((lambda: level_mass().belief("high"),
                     "That is Bel({high}); Pl({high}) = 1 − Bel({low, mid})."),
                    (lambda: level_mass().belief(("low", "mid")),
                     "That is Bel({low, mid}) itself; subtract it from 1.")))
def _() -> float:
    return level_mass().plausibility("high")


@exercise("mass.vacuous-betp", hint="Total ignorance spreads the mass of Θ evenly.")
def _() -> dict[str, float]:
    return MassFunction.vacuous(FRAME).pignistic()


# -- combining evidence (book/combining_evidence.md, notebooks/02_combining_evidence.ipynb) --


def sensor_masses() -> tuple[MassFunction, MassFunction]:
    """Two level sensors: m1({low}) = 0.6, m1(Θ) = 0.4; m2({high}) = 0.7,
    m2({mid, high}) = 0.2, m2(Θ) = 0.1."""
    m1 = MassFunction({"low": 0.6, FRAME: 0.4}, FRAME)
    m2 = MassFunction({"high": 0.7, ("mid", "high"): 0.2, FRAME: 0.1}, FRAME)
    return m1, m2


@exercise("combine.conflict", hint="K adds m1(B)·m2(C) over the pairs with B ∩ C = ∅.",
          mistakes=((lambda: sensor_masses()[0].mass_of("low") * sensor_masses()[1].mass_of(
              "high"), "You counted {low} ∩ {high} only; {low} ∩ {mid, high} is empty too."),))
def _() -> float:
    return conflict(*sensor_masses())


@exercise("combine.low",
          hint="Only {low} ∩ Θ gives {low}; divide its product by 1 − K.",
          mistakes=((lambda: sensor_masses()[0].mass_of("low") * sensor_masses()[1].mass_of(FRAME),
                     "You forgot to renormalise: divide by 1 − K."),))
def _() -> float:
    return dempster(*sensor_masses()).mass_of("low")


def zadeh(x: float = 0.99, y: float = 0.99) -> tuple[MassFunction, MassFunction]:
    """Zadeh's doctors: m1(meningitis) = x, m1(tumour) = 1 − x; m2(concussion) = y,
    m2(tumour) = 1 − y."""
    frame = ("meningitis", "concussion", "tumour")
    return (MassFunction({"meningitis": x, "tumour": 1 - x}, frame),
            MassFunction({"concussion": y, "tumour": 1 - y}, frame))


@exercise("combine.zadeh", hint="Which product is the only non-empty intersection?")
def _() -> float:
    return dempster(*zadeh()).mass_of("tumour")


@exercise("combine.zadeh-conflict", hint="1 − K is the product of the two small masses.",
          mistakes=((lambda: 0.99 * 0.99, "That is only meningitis × concussion; the "
                     "products with tumour on one side are in conflict too."),))
def _() -> float:
    return conflict(*zadeh())


def once() -> MassFunction:
    """One source: m({low}) = 0.5, m(Θ) = 0.5 (combined with itself in combine.twice)."""
    return MassFunction({"low": 0.5, FRAME: 0.5}, FRAME)


@exercise("combine.twice", hint="Combine m = {low: 0.5, Θ: 0.5} with itself by eq. (1).",
          mistakes=((lambda: once().mass_of("low"), "That is m({low}) before combining: "
                     "Dempster's rule counts the same source twice."),))
def _() -> float:
    return dempster(once(), once()).mass_of("low")


# -- dependent evidence (book/dependent_evidence.md, notebooks/03_dependent_evidence.ipynb) --


def dependent_pair() -> tuple[MassFunction, MassFunction]:
    """E1 = level_mass(); E2 = {low: 0.4, mid: 0.4, Θ: 0.2}: they share {low} and Θ."""
    return level_mass(), MassFunction({"low": 0.4, "mid": 0.4, FRAME: 0.2}, FRAME)


@exercise("dependent.energy", hint="Eq. (2): Σ m(A)/|A| over the focal elements other than Θ.",
          mistakes=((lambda: float(sum(m / len(a) for a, m in level_mass().as_dict().items())),
                     "Θ is left out of the energy: its mass carries no information."),))
def _() -> float:
    return energy(level_mass())


@exercise("dependent.joint", hint="Eq. (3) sums min(m1(D), m2(D))/|D| over the shared "
          "focal elements D other than Θ.",
          mistakes=((lambda: joint_energy(*dependent_pair(), mass_rule="m1"),
                     "You took E1's mass of the shared {low}; eq. 3 takes the smaller of the "
                     "two, min(m1, m2)."),))
def _() -> float:
    return joint_energy(*dependent_pair())


@exercise("dependent.degree", hint="D = 2 En(E1,E2) / (En(E1) + En(E2)).",
          mistakes=((lambda: dependence(*dependent_pair()).degree / 2,
                     "You forgot the factor 2: D = 2 En(E1, E2)/(En(E1) + En(E2)), so that "
                     "a source with itself has D = 1."),))
def _() -> float:
    return dependence(*dependent_pair()).degree


@exercise("dependent.coefficients", hint="R12 = 1 − (D/2)·En(E2)/En(E1); swap for R21. "
          "Answer (R12, R21).",
          mistakes=((lambda: (dependence(*dependent_pair()).r21,
                              dependence(*dependent_pair()).r12),
                     "R12 and R21 are swapped: R12 = 1 − (D/2)·En(E2)/En(E1)."),))
def _() -> tuple[float, float]:
    dep = dependence(*dependent_pair())
    return dep.r12, dep.r21


@exercise("dependent.combined-low", hint="Discount E1 by R12 and E2 by R21 (mass 1 − R to Θ), "
          "then apply Dempster's rule.",
          mistakes=((lambda: dependent_pair()[0].belief("low"),
                     "That is Bel({low}) of E1 alone, before combining: the combination "
                     "must also take in what E2 says."),
                    (lambda: dempster(*dependent_pair()).belief("low"),
                     "That is plain Dempster's rule, which counts the shared {low} twice: "
                     "discount each source by its dependency coefficient first."),
                    (lambda: dependent_pair()[1].belief("low"),
                     "That is Bel({low}) of E2 alone; combine both sources.")))
def _() -> float:
    return combine_dependent(*dependent_pair()).mass_of("low")






@exercise("dependent.a2", hint="Eq. (A1): Σ m(A_i)·w_min/w(A_i); here w_min = 1.6.")
def _() -> float:
    return energy(IntervalEvidence.from_pairs(APPENDIX_A2))


@exercise("dependent.en1-exact", atol=5e-5, rtol=0.0,
          hint="Three focal elements now: the third, [0.32, 1.93], counts 0.1·1.6/1.61.",
          mistakes=((lambda: PAPER_EN1,
                     "That is the value the paper prints: it is the energy of the two-element "
                     "example (A2), not of E1."),))
def _() -> float:
    return energy(appendix_pair()[0])


@exercise("dependent.a6", atol=2e-4, rtol=0.0,
          hint="A6 = A2' ∩ B3': m1'([0.3,1.9]) · m2'([0.3,1.9]) = (R12·0.6)(R21·0.6); use the "
          "paper's En'(E1) = 0.8655 and no conflict arises.",
          mistakes=((lambda: PAPER_A6, "That is the paper's printed value, a slip: compute "
                     "0.36·R12·R21 yourself."),))
def _() -> float:
    e1, e2 = appendix_pair()
    return float(combine_dependent(e1, e2, energy1=PAPER_EN1, merge=False).mass[5])


@exercise("dependent.theta-merges", hint="Θ of each evidence is the hull of its focal "
          "elements (eqs. A7–A8). Is the hull one of the focal elements?")
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


@exercise("noise.cut", hint="Eq. (24): [a + α(c − a), b − α(b − c)] with α = 1/3.",
          mistakes=((lambda: tuple(float(v[0]) for v in alpha_cuts(*STATE_NOISE, p=3)),
                     "That is the cut at α = 2/3, the innermost; α = 1/3 lies a third of the "
                     "way from the support to the mode."),))
def _() -> tuple[float, float]:
    lo, hi = alpha_cuts(*STATE_NOISE, p=3)
    return float(lo[1]), float(hi[1])


@exercise("noise.mass", hint="Each of the p cuts gets (1 − ε)/p; here p = 4 and ε = 0.1.",
          mistakes=((lambda: 0.25, "That is 1/p: Θ takes ε = 0.1 first, so each cut gets "
                     "(1 − ε)/p."),))
def _() -> float:
    return float(triangular_evidence(*STATE_NOISE, p=4, epsilon=0.1).mass[0])


@exercise("noise.theta2", hint="σ = (b − a)/6, and Θ = c ± 100σ.",
          mistakes=((lambda: PAPER_THETA2, "That is what the paper prints; c ± 100σ gives "
                     "another interval. Recompute σ from the bounds."),))
def _() -> tuple[float, float]:
    return default_theta(*OBS_NOISE)


@exercise("noise.expectation", hint="Eq. (20): Σ m·(midpoint). Where are the midpoints?")
def _() -> float:
    return triangular_evidence(*OBS_NOISE).pignistic_expectation_1d()


@exercise("noise.pbox", hint="Bel((−∞, x]) counts focal elements entirely left of x; "
          "Pl((−∞, x]) those that start left of x. Answer (lower, upper).",
          mistakes=((lambda: tuple(reversed(_pbox())),
                     "Lower and upper are swapped: the lower bound Bel counts only the "
                     "intervals entirely left of x."),))
def _pbox() -> tuple[float, float]:
    lower, upper = triangular_evidence(*STATE_NOISE, theta=(-10, 10)).cdf_bounds(0.15)
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


def _monotone_f(xi: np.ndarray) -> np.ndarray:
    return xi[..., 0] + 2.0 * xi[..., 1] - xi[..., 2]


def _square(x: np.ndarray) -> np.ndarray:
    return x[..., 0] ** 2


def folded_image(merge: bool = True) -> IntervalEvidence:
    """The image of FOLDED_X through x² (subdivision: one focal element straddles 0)."""
    from dstoolkit.evidence import image

    return image(IntervalEvidence.from_pairs(FOLDED_X, merge=False), _square,
                 method="subdivision", merge=merge)


@exercise("random.product", hint="Eq. (16): the mass of a box is the product of the masses "
          "of its sides in the marginals.",
          mistakes=((lambda: (RELATION_X1[1][2] + RELATION_X2[0][2]) / 2,
                     "You averaged the two masses; independent marginals multiply (eq. 16)."),))
def _() -> float:
    from dstoolkit.evidence import cartesian_product

    rel = cartesian_product([IntervalEvidence.from_pairs(RELATION_X1),
                             IntervalEvidence.from_pairs(RELATION_X2)])
    lo, hi = np.array(RELATION_BOX)
    row = np.flatnonzero(np.all(rel.boxes_lo == lo, axis=1) & np.all(rel.boxes_hi == hi, axis=1))
    return float(rel.mass[row[0]])


@exercise("random.monotone",
          hint="Prop. 2: for v_min take the lower end where f increases and the upper end "
          "where it decreases; v_max the opposite. Answer (lo, hi).",
          mistakes=((lambda: tuple(float(_monotone_f(np.array(v))) for v in MONOTONE_BOX),
                     "You evaluated f at the lower and upper corners; f decreases in ξ3, so "
                     "v_min takes ξ3's upper end."),))
def _() -> tuple[float, float]:
    from dstoolkit.evidence import image

    lo, hi = image((np.array(MONOTONE_BOX[0]), np.array(MONOTONE_BOX[1])), _monotone_f,
                   method="monotone", monotone=MONOTONE_SIGNS)
    return float(lo[0]), float(hi[0])


@exercise("random.square", hint="Where is the minimum of x² on [−1, 2]? Answer (lo, hi).",
          mistakes=((lambda: (float(_square(np.array([SQUARE_BOX[0]]))),
                              float(_square(np.array([SQUARE_BOX[1]])))),
                     "That is the vertex method's answer: x² has its minimum inside the box "
                     "(Prop. 1 does not apply)."),))
def _() -> tuple[float, float]:
    from dstoolkit.evidence import image

    lo, hi = image(([SQUARE_BOX[0]], [SQUARE_BOX[1]]), _square, method="subdivision")
    return float(lo[0]), float(hi[0])


@exercise("random.merge", hint="Which focal elements of X have the image [1, 4]? Eq. (14) "
          "adds their masses.",
          mistakes=((lambda: FOLDED_X[0][2],
                     "That is the mass of one of the two focal elements that map to [1, 4]; "
                     "equal images merge and their masses add up (eq. 14)."),))
def _() -> float:
    im = folded_image()
    return float(im.mass[(im.lo_1d == 1.0) & (im.hi_1d == 4.0)][0])


@exercise("random.expectation", hint="Eq. (20): Σ ρ(R_j)·(midpoint of R_j) over the image "
          "[1, 4], [0, 1].",
          mistakes=((lambda: IntervalEvidence.from_pairs(FOLDED_X).pignistic_expectation_1d() ** 2,
                     "That is f(E[X]); the expectation of the image is taken over the image "
                     "intervals."),))
def _() -> float:
    return folded_image().pignistic_expectation_1d()


@exercise("random.evaluations", atol=0.0, rtol=0.0,
          hint="The vertex method evaluates f at the 2^n corners of every box, the monotone "
          "shortcut at 2. Answer (vertex, monotone).",
          mistakes=((lambda: (2 ** COUNT_DIM, 2),
                     "That is per box; the relation has 16 boxes."),))
def _() -> tuple[int, int]:
    from dstoolkit.evidence import image

    counts = []
    for method in ("vertex", "monotone"):
        seen = [0]

        def f(x: np.ndarray, seen: list[int] = seen) -> np.ndarray:
            seen[0] += int(np.prod(x.shape[:-1]))
            return x.sum(axis=-1)

        box = np.zeros((COUNT_BOXES, COUNT_DIM))
        image((box, box + 1.0), f, method=method, monotone=np.ones(COUNT_DIM), check=False)
        counts.append(seen[0])
    return counts[0], counts[1]
