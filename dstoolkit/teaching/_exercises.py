"""Check cells for the exercise sheets: ``check("mass.bel", answer)`` says right or wrong.

Every exercise is registered with a function that *computes* its solution with dstoolkit
(no typed-in numbers), a hint shown after a wrong answer, and a tolerance. Adding one is a
few lines anywhere below (or in another module imported by this one)::

    @exercise("gauge.fundamental", hint="f_F = c / (2L); c comes from eq. (31).")
    def _() -> float:
        return speed_of_sound(20.0) / (2 * 1.3)

Answers may be numbers, sequences or arrays of numbers (compared element by element with
``|answer − solution| ≤ atol + rtol·|solution|``), dicts of numbers, booleans, strings,
sets, :class:`~dstoolkit.evidence.MassFunction` or :class:`~dstoolkit.evidence.IntervalEvidence`.

``mistakes`` lists common wrong answers, each as a function computing it and the hint to
give when a learner's answer matches it; they are tested too (tests/test_exercises.py).
"""

from __future__ import annotations

import html
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dstoolkit.errors import TotalConflictError
from dstoolkit.evidence import APPENDIX_A2, PAPER_A6, PAPER_EN1, appendix_pair
from dstoolkit.evidence._combination import (
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    energy,
    joint_energy,
)
from dstoolkit.evidence._finite_frame import MassFunction
from dstoolkit.evidence._intervals import IntervalEvidence
from dstoolkit.evidence._possibility import alpha_cuts, default_theta, triangular_evidence
from dstoolkit.gauge._acoustics import fundamental_frequency, resonance_orders, speed_of_sound
from dstoolkit.gauge._level import level_from_resonance, orders_eq43
from dstoolkit.gauge._resonance import latency_offset, sweep_rate_offset

Solver = Callable[[], Any]


@dataclass(frozen=True)
class Exercise:
    """One exercise: how to compute its solution, a hint, a tolerance, common mistakes."""

    id: str
    solve: Solver
    hint: str
    atol: float = 5e-4
    rtol: float = 1e-3
    mistakes: tuple[tuple[Solver, str], ...] = ()

    @property
    def solution(self) -> Any:
        """The solution, computed now with dstoolkit."""
        return self.solve()


@dataclass(frozen=True)
class Feedback:
    """The verdict of :func:`check`; true when right. Shown as its message in a notebook."""

    exercise_id: str
    correct: bool
    message: str
    details: dict[str, Any] = field(default_factory=dict)

    def __bool__(self) -> bool:
        return self.correct

    def __repr__(self) -> str:
        return self.message

    def _repr_html_(self) -> str:
        colour = "#1b7f3b" if self.correct else "#b00020"
        return f"<p style='color:{colour}'>{html.escape(self.message)}</p>"


#: Every exercise by its key (``"chapter.name"``), filled by :func:`exercise`.
REGISTRY: dict[str, Exercise] = {}


def exercise(
    exercise_id: str,
    *,
    hint: str,
    atol: float = 5e-4,
    rtol: float = 1e-3,
    mistakes: tuple[tuple[Solver, str], ...] = (),
) -> Callable[[Solver], Solver]:
    """Register the decorated function as the solver of ``exercise_id``.

    Ids are ``"<chapter>.<name>"`` (e.g. ``"mass.bel"``); registering an id twice is an error.
    """
    if "." not in exercise_id:
        raise ValueError(f"exercise id {exercise_id!r} must look like 'chapter.name'")

    def register(solve: Solver) -> Solver:
        if exercise_id in REGISTRY:
            raise ValueError(f"exercise {exercise_id!r} is registered twice; rename one")
        REGISTRY[exercise_id] = Exercise(exercise_id, solve, hint, atol, rtol, mistakes)
        return solve

    return register


def exercises(prefix: str = "") -> list[str]:
    """The ids of the registered exercises, those starting with ``prefix`` only."""
    return sorted(k for k in REGISTRY if k.startswith(prefix))


def _get(exercise_id: str) -> Exercise:
    try:
        return REGISTRY[exercise_id]
    except KeyError:
        close = [k for k in REGISTRY if k.split(".")[0] == exercise_id.split(".")[0]]
        raise KeyError(
            f"no exercise {exercise_id!r}; exercises of that chapter: {close or exercises()}"
        ) from None


def solution(exercise_id: str) -> Any:
    """The solution of an exercise, computed with dstoolkit (for teachers and tests)."""
    return _get(exercise_id).solution


# -- comparison -------------------------------------------------------------------------


def _canonical(value: Any) -> Any:
    """Evidence → plain data; other values unchanged."""
    if isinstance(value, IntervalEvidence):
        return value.to_rows()
    if isinstance(value, MassFunction):
        return {frozenset(k): v for k, v in value.as_dict().items()}
    return value


def _compare(answer: Any, sol: Any, ex: Exercise) -> tuple[bool, str]:
    """(equal within tolerance?, reason when not)."""
    answer, sol = _canonical(answer), _canonical(sol)
    if isinstance(sol, bool | np.bool_):
        if not isinstance(answer, bool | np.bool_):
            return False, "the answer is True or False"
        return bool(answer) == bool(sol), ""
    if isinstance(sol, str):
        return str(answer).strip().lower() == sol.strip().lower(), ""
    if isinstance(sol, frozenset | set):
        got = frozenset([answer]) if isinstance(answer, str) else frozenset(answer)
        return got == frozenset(sol), ""
    if isinstance(sol, Mapping):
        if not isinstance(answer, Mapping):
            return False, f"give a dict with keys {sorted(map(str, sol))}"
        norm = {_key(k): v for k, v in answer.items()}
        missing = [k for k in sol if _key(k) not in norm]
        if missing:
            return False, f"keys missing: {[_show(k) for k in missing]}"
        return _close([norm[_key(k)] for k in sol], list(sol.values()), ex)
    return _close(answer, sol, ex)


def _key(k: Any) -> Any:
    if isinstance(k, set | frozenset | tuple | list):
        return frozenset(k)
    return k


def _show(k: Any) -> str:
    return "{" + ", ".join(sorted(map(str, k))) + "}" if isinstance(k, frozenset) else str(k)


def _close(answer: Any, sol: Any, ex: Exercise) -> tuple[bool, str]:
    try:
        a = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
        return False, f"expected a number or numbers, got {type(answer).__name__}"
    s = np.asarray(sol, dtype=float)
    if a.size != s.size:
        return False, f"expected {s.size} number(s), got {a.size}"
    a = a.reshape(s.shape)
    if np.all(np.isclose(a, s, atol=ex.atol, rtol=ex.rtol)):
        return True, ""
    off = float(np.max(np.abs(a - s)))
    if np.all(np.isclose(a, s, atol=20 * ex.atol, rtol=20 * ex.rtol)):
        return False, f"close, but off by {off:.2g}; keep more decimals in the intermediate steps"
    return False, ""


def check(exercise_id: str, answer: Any) -> Feedback:
    """Compare ``answer`` with the solution of ``exercise_id``: right, or wrong with a hint.

    In a notebook, end a cell with ``check("mass.bel", answer)`` to see the verdict.
    An answer left as ``...`` (or ``None``) is reported as not answered yet.
    """
    ex = _get(exercise_id)
    if answer is ... or answer is None:
        return Feedback(exercise_id, False,
                        f"{exercise_id}: not answered yet — replace ... by your answer.")
    ok, reason = _compare(answer, ex.solution, ex)
    if ok:
        return Feedback(exercise_id, True, f"✔ {exercise_id}: right.")
    for wrong, why in ex.mistakes:
        if _compare(answer, wrong(), ex)[0]:
            return Feedback(exercise_id, False, f"✘ {exercise_id}: wrong. {why}",
                            {"mistake": why})
    reason = f" ({reason})" if reason else ""
    return Feedback(exercise_id, False, f"✘ {exercise_id}: wrong{reason}. Hint: {ex.hint}")


# ============================================================================================
# The exercises, chapter by chapter. Keep the data of each problem in a named constant so
# the chapter, its notebook and the solver use the same numbers.
# ============================================================================================

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


@exercise("bounded.predict", hint="Add the noise bounds to the ends: [a + v_a, b + v_b].")
def _() -> tuple[float, float]:
    ev = _predicted()
    return float(ev.lo[0]), float(ev.hi[0])


@exercise("bounded.update",
          hint="The reading says x ∈ [z − 0.5, z + 0.5]; keep what both intervals share.")
def _() -> tuple[float, float]:
    ev = _updated(BOUNDED_W)
    return float(ev.lo[0]), float(ev.hi[0])


@exercise("bounded.too-tight",
          hint="Compare the upper end of the prediction with the lower end of [z − 0.2, z + 0.2].")
def _() -> bool:
    try:
        _updated(BOUNDED_W_TIGHT)
    except TotalConflictError:
        return True
    return False


# -- mass functions (book/mass_functions.md, notebooks/01_mass_functions.ipynb) ----------

#: The frame of the level exercises: the tank's level is low, mid or high.
FRAME = ("low", "mid", "high")


def level_mass() -> MassFunction:
    """The chapter's running example: m({low}) = 0.5, m({low, mid}) = 0.3, m(Θ) = 0.2."""
    return MassFunction({"low": 0.5, ("low", "mid"): 0.3, FRAME: 0.2}, FRAME)


@exercise("mass.bel", hint="Bel(A) adds the masses of the focal elements contained in A.")
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


@exercise("mass.duality", hint="Pl(A) = 1 − Bel(complement of A).")
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


@exercise("combine.conflict", hint="K adds m1(B)·m2(C) over the pairs with B ∩ C = ∅.")
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


@exercise("combine.zadeh-conflict", hint="1 − K is the product of the two small masses.")
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
          "focal elements D other than Θ.")
def _() -> float:
    return joint_energy(*dependent_pair())


@exercise("dependent.degree", hint="D = 2 En(E1,E2) / (En(E1) + En(E2)).")
def _() -> float:
    return dependence(*dependent_pair()).degree


@exercise("dependent.coefficients", hint="R12 = 1 − (D/2)·En(E2)/En(E1); swap for R21. "
          "Answer (R12, R21).")
def _() -> tuple[float, float]:
    dep = dependence(*dependent_pair())
    return dep.r12, dep.r21


@exercise("dependent.combined-low", hint="Discount E1 by R12 and E2 by R21 (mass 1 − R to Θ), "
          "then apply Dempster's rule.")
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


@exercise("noise.cut", hint="Eq. (24): [a + α(c − a), b − α(b − c)] with α = 1/3.")
def _() -> tuple[float, float]:
    lo, hi = alpha_cuts(*STATE_NOISE, p=3)
    return float(lo[1]), float(hi[1])


@exercise("noise.mass", hint="Each of the p cuts gets (1 − ε)/p; here p = 4 and ε = 0.1.")
def _() -> float:
    return float(triangular_evidence(*STATE_NOISE, p=4, epsilon=0.1).mass[0])


@exercise("noise.theta2", hint="σ = (b − a)/6, and Θ = c ± 100σ.",
          mistakes=((lambda: PAPER_THETA2, "That is what the paper prints; c ± 100σ gives "
                     "another interval. Recompute σ from the bounds."),))
def _() -> tuple[float, float]:
    return default_theta(*OBS_NOISE)


@exercise("noise.expectation", hint="Eq. (20): Σ m·(midpoint). Where are the midpoints?")
def _() -> float:
    return triangular_evidence(*OBS_NOISE).pignistic_expectation()


@exercise("noise.pbox", hint="Bel((−∞, x]) counts focal elements entirely left of x; "
          "Pl((−∞, x]) those that start left of x. Answer (lower, upper).")
def _() -> tuple[float, float]:
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
    from dstoolkit.evidence._extension import image

    return image(IntervalEvidence.from_pairs(FOLDED_X, merge=False), _square,
                 method="subdivision", merge=merge)


@exercise("random.product", hint="Eq. (16): the mass of a box is the product of the masses "
          "of its sides in the marginals.")
def _() -> float:
    from dstoolkit.evidence._extension import cartesian_product

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
    from dstoolkit.evidence._extension import image

    lo, hi = image((np.array(MONOTONE_BOX[0]), np.array(MONOTONE_BOX[1])), _monotone_f,
                   method="monotone", monotone=MONOTONE_SIGNS)
    return float(lo[0]), float(hi[0])


@exercise("random.square", hint="Where is the minimum of x² on [−1, 2]? Answer (lo, hi).",
          mistakes=((lambda: (float(_square(np.array([SQUARE_BOX[0]]))),
                              float(_square(np.array([SQUARE_BOX[1]])))),
                     "That is the vertex method's answer: x² has its minimum inside the box "
                     "(Prop. 1 does not apply)."),))
def _() -> tuple[float, float]:
    from dstoolkit.evidence._extension import image

    lo, hi = image(([SQUARE_BOX[0]], [SQUARE_BOX[1]]), _square, method="subdivision")
    return float(lo[0]), float(hi[0])


@exercise("random.merge", hint="Which focal elements of X have the image [1, 4]? Eq. (14) "
          "adds their masses.",
          mistakes=((lambda: FOLDED_X[0][2],
                     "That is the mass of one of the two focal elements that map to [1, 4]; "
                     "equal images merge and their masses add up (eq. 14)."),))
def _() -> float:
    im = folded_image()
    return float(im.mass[(im.lo == 1.0) & (im.hi == 4.0)][0])


@exercise("random.expectation", hint="Eq. (20): Σ ρ(R_j)·(midpoint of R_j) over the image "
          "[1, 4], [0, 1].",
          mistakes=((lambda: IntervalEvidence.from_pairs(FOLDED_X).pignistic_expectation() ** 2,
                     "That is f(E[X]); the expectation of the image is taken over the image "
                     "intervals."),))
def _() -> float:
    return folded_image().pignistic_expectation()


@exercise("random.evaluations", atol=0.0, rtol=0.0,
          hint="The vertex method evaluates f at the 2^n corners of every box, the monotone "
          "shortcut at 2. Answer (vertex, monotone).",
          mistakes=((lambda: (2 ** COUNT_DIM, 2),
                     "That is per box; the relation has 16 boxes."),))
def _() -> tuple[int, int]:
    from dstoolkit.evidence._extension import image

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


# -- the recursive filter (book/recursive_filter.md, notebooks/06_recursive_filter.ipynb) ----

#: The chapter's sequence: the paper's 9.6 m case (level m, °C) and the seed of its readings.
FILTER_CASE, FILTER_SEED = (9.6, 23.9), 0
#: The paper's first reading at 4.6 m (§4.3, Fig. 7), Hz.
PAPER_Z1 = 1023.3
#: Step 2 by hand: estimate x̂_k (Hz) and order n_k.
PREDICT_XHAT, PREDICT_ORDER = 1000.0, 55
#: Discount of the conflict exercise, and the cuts of the counting exercise.
CONFLICT_EPSILON, COUNT_CUTS = 0.1, 5


def _gauge_model() -> Any:
    from dstoolkit.gauge._gauge_model import gauge_state_space_model

    return gauge_state_space_model()


@exercise("filter.counts", atol=0.0, rtol=0.0,
          hint="With p cuts a noise evidence has p + 1 focal elements (Θ included); the "
          "prediction pairs every state focal element with every noise one, Step 4 every "
          "predicted one with every observation one, Step 6 every Step-4 product with every "
          "predicted one. Answer (state, prediction, Step-4 products, Step-6 products).",
          mistakes=((lambda: (COUNT_CUTS, COUNT_CUTS ** 2, COUNT_CUTS ** 3, COUNT_CUTS ** 5),
                     "Do not forget Θ: the discount adds one focal element to each noise "
                     "evidence (eq. 26)."),))
def _() -> tuple[int, int, int, int]:
    from dstoolkit.filters._dependent import DependentEvidenceFilter

    noise = DependentEvidenceFilter(p=COUNT_CUTS).noise_evidence(_gauge_model())
    nv, nw = len(noise.state), len(noise.observation)
    return nv, nv * nv, nv * nv * nw, nv * nv * nw * nv * nv


def _innermost_prediction(twice: bool = True) -> tuple[float, float]:
    from dstoolkit.evidence._extension import image

    v = triangular_evidence(*STATE_NOISE)  # innermost cut first (Table 1)
    lo, hi = image(([PREDICT_XHAT + v.lo[0]], [PREDICT_XHAT + v.hi[0]]),
                   lambda x: _gauge_model().f(x, PREDICT_ORDER), monotone=[1])
    extra = (float(v.lo[0]), float(v.hi[0])) if twice else (0.0, 0.0)
    return float(lo[0]) + extra[0], float(hi[0]) + extra[1]


@exercise("filter.prediction", atol=5e-3, rtol=0.0,
          hint="Step 2: map the state box x̂ + [−0.1, 0.1] through eq. (39) (increasing: map "
          "the ends), then add the noise box [−0.1, 0.1]. Answer (lo, hi).",
          mistakes=((lambda: _innermost_prediction(twice=False),
                     "The noise enters twice in Step 2: once in the state evidence "
                     "x̂ + V, once as v in x_{k+1} = f(x_k) + v_k. Add [−0.1, 0.1] again."),))
def _() -> tuple[float, float]:
    return _innermost_prediction()


@exercise("filter.mean-corrected", atol=0.01, rtol=0.0,
          hint="g(x) = z + w (eq. 21, 'adding noise to z'): the reading is high when w < 0; "
          "correct z_1 by the mean of w, (a + b + c)/3.",
          mistakes=((lambda: PAPER_Z1 - float(_gauge_model().obs_noise.mean[0]),
                     "Check the sign: with g(x) = z + w the state is z + w, so add E[w] "
                     "(which is negative)."),
                    (lambda: PAPER_Z1, "That is the paper's start, z_1 itself.")))
def _() -> float:
    return PAPER_Z1 + float(_gauge_model().obs_noise.mean[0])


@exercise("filter.conflict-start", atol=1e-6,
          hint="With the paper's start every cut of the prediction misses every cut of the "
          "observation: only products with a Θ survive. K is the mass of the others.",
          mistakes=((lambda: (1.0 - 0.05) ** 3,
                     "That is K for the chapter's ε = 0.05; the question asks for ε = 0.1."),))
def _() -> float:
    from ._explorers import filter_case

    _, _, result = filter_case(*FILTER_CASE, epsilon=CONFLICT_EPSILON, seed=FILTER_SEED)
    return float(result.diagnostics["conflict_step4"][1])


@exercise("filter.mass-rule", hint="Which choice of m(D) can make the energy of the "
          "intersection exceed the energies themselves, so that D > 1?")
def _() -> str:
    from dstoolkit.errors import EvidenceError

    from ._explorers import filter_case

    for rule in ("min", "m1", "m2"):
        try:
            filter_case(*FILTER_CASE, mass_rule=rule, seed=FILTER_SEED)
        except EvidenceError:
            return rule
    raise AssertionError("no m(D) rule fails on the chapter's sequence")


# -- the acoustic level gauge (book/level_gauge.md, notebooks/07_level_gauge.ipynb) -----------

#: Table 3's 4.6 m case (the paper's Figs. 6–7) and its longest, 9.6 m: (level m, °C).
GAUGE_CASE, LONG_CASE = (4.6, 26.5), (9.6, 23.9)
#: The filter's band and the paper's sweep rate (1000 → 2400 Hz in 5 s), Hz/s.
GAUGE_BAND, SWEEP_RATE = (1000.0, 2500.0), 280.0
#: Audio latency of the offset exercise, s.
GAUGE_LATENCY = 0.010
#: Errors (Hz) of the two readings in the eq. 43 exercise: z_1 = 57 f_F + e_1,
#: z_2 = 58 f_F + e_2 at LONG_CASE.
EQ43_ORDERS, EQ43_ERRORS = (57, 58), (0.2, -0.2)
#: Frequency (Hz) at which the eq. 43 tolerance is asked, at LONG_CASE.
EQ43_TOLERANCE_AT = 2000.0
#: Thermometer error (°C) of the temperature exercise, at LONG_CASE.
THERMOMETER_ERROR = 1.0


def _c(case: tuple[float, float]) -> float:
    return float(speed_of_sound(case[1]))


def _fundamental(case: tuple[float, float]) -> float:
    return float(fundamental_frequency(case[0], _c(case)))


def eq43_readings() -> np.ndarray:
    """The two readings of the eq. 43 exercise, Hz."""
    return np.array(EQ43_ORDERS) * _fundamental(LONG_CASE) + np.array(EQ43_ERRORS)


@exercise("gauge.speed", hint="The paper's law: c = 331.3 + 0.606 T, T in °C.",
          mistakes=((lambda: 331.3, "That is c at 0 °C; add 0.606 m/s per °C."),))
def _() -> float:
    return _c(GAUGE_CASE)


@exercise("gauge.fundamental", hint="f_F = c/(2L), c at 23.9 °C by the paper's law.",
          mistakes=((lambda: _c(LONG_CASE) / LONG_CASE[0],
                     "That is c/L: the echo travels down and back, 2L."),))
def _() -> float:
    return _fundamental(LONG_CASE)


@exercise("gauge.count", atol=0.0, rtol=0.0,
          hint="Count the whole numbers n with 1000 ≤ n f_F ≤ 2500: from ⌈1000/f_F⌉ to "
          "⌊2500/f_F⌋.",
          mistakes=((lambda: 82, "That is the paper's count (n = 56..137, with f_F rounded to "
                     "18 Hz); check whether 138 f_F is still below 2500 Hz."),))
def _() -> int:
    return int(resonance_orders(LONG_CASE[0], _c(LONG_CASE), GAUGE_BAND).size)


@exercise("gauge.offset", atol=5e-3,
          hint="The envelope peaks k L/c above n c/(2L); the latency adds k τ.",
          mistakes=((lambda: SWEEP_RATE * 2 * GAUGE_CASE[0] / _c(GAUGE_CASE)
                     + SWEEP_RATE * GAUGE_LATENCY,
                     "You used k·2L/c: the peak sits where the *mean* frequency of wave and "
                     "echo is n c/(2L), half a delay back: k L/c."),
                    (lambda: float(sweep_rate_offset(SWEEP_RATE, _fundamental(GAUGE_CASE))),
                     "That is the sweep's offset k L/c alone; the latency adds k τ.")))
def _() -> float:
    return (float(sweep_rate_offset(SWEEP_RATE, _fundamental(GAUGE_CASE)))
            + latency_offset(SWEEP_RATE, GAUGE_LATENCY))


@exercise("gauge.eq43", atol=5e-3,
          hint="n_1 = round(z_1/(z_2 − z_1)) (eq. 43), then L = n_1 c/(2 z_1) (eq. 32). "
          "Answer (n_1, L).",
          mistakes=((lambda: (EQ43_ORDERS[0], LONG_CASE[0]),
                     "That is the true order and level; eq. 43 only sees the two readings: "
                     "compute z_1/(z_2 − z_1)."),))
def _() -> tuple[int, float]:
    z = eq43_readings()
    n = int(orders_eq43(z)[0])
    return n, float(level_from_resonance(z[0], n, _c(LONG_CASE)))


@exercise("gauge.tolerance", atol=2e-3,
          hint="n = z/(f_F + δ) ≈ (z/f_F)(1 − δ/f_F) rounds to the right order while "
          "(z/f_F)·|δ|/f_F < 1/2.",
          mistakes=((lambda: 0.5 * _fundamental(LONG_CASE),
                     "f_F/2 is how far one reading may wander before it is matched to the "
                     "wrong resonance; eq. 43 divides by a difference, which must be far "
                     "more precise."),))
def _() -> float:
    return _fundamental(LONG_CASE) ** 2 / (2.0 * EQ43_TOLERANCE_AT)


@exercise("gauge.thermometer", atol=2e-4,
          hint="L = c/(2 f_F): a relative error of c is the same relative error of L.",
          mistakes=((lambda: -LONG_CASE[0] * 0.606 * THERMOMETER_ERROR / _c(LONG_CASE),
                     "Check the sign: a thermometer that reads high makes c, and so L, "
                     "too large."),))
def _() -> float:
    c_read = float(speed_of_sound(LONG_CASE[1] + THERMOMETER_ERROR))
    return LONG_CASE[0] * (c_read - _c(LONG_CASE)) / _c(LONG_CASE)


# -- the lab (book/lab.md, notebooks/08_lab.ipynb) ---------------------------------------------

#: Where the calibration chirp is found (samples after it was played) and the sample rate.
LAB_LAG_SAMPLES, LAB_SAMPLERATE = 6042, 44100
#: The paper's sweep, Hz, and the lab's air temperature in the exercises, °C.
LAB_BAND, LAB_TEMPERATURE = (1000.0, 2400.0), 20.0
#: Resonances the detector needs (dstoolkit.gauge.detect_resonances, min_resonances).
LAB_MIN_RESONANCES = 5
#: Inner diameter of the narrow pipe of the cutoff exercise, m.
LAB_CUTOFF_DIAMETER = 0.040
#: (level m, largest level error m) of the thermometer exercise.
LAB_TOLERANCE_CASE = (3.0, 0.005)
#: Parts of a level's uncertainty (fit, offsets, temperature), mm.
LAB_UNCERTAINTIES_MM = (0.4, 1.5, 2.2)


def _lab_c() -> float:
    return float(speed_of_sound(LAB_TEMPERATURE))


@exercise("lab.latency-offset", atol=5e-3,
          hint="τ = lag / f_s (in ms: × 1000); every reading moves by k τ with k = 280 Hz/s "
          "and τ in seconds. Answer (τ in ms, k τ in Hz).",
          mistakes=((lambda: (LAB_LAG_SAMPLES / LAB_SAMPLERATE,
                              SWEEP_RATE * LAB_LAG_SAMPLES / LAB_SAMPLERATE),
                     "Give τ in milliseconds (the offset k τ is right)."),))
def _() -> tuple[float, float]:
    tau = LAB_LAG_SAMPLES / LAB_SAMPLERATE
    return 1e3 * tau, latency_offset(SWEEP_RATE, tau)


@exercise("lab.shortest-tube",
          hint="Five spacings fit in the band when 5 f_F ≤ f_stop − f_start; then L = c/(2 f_F).",
          mistakes=((lambda: LAB_MIN_RESONANCES * _lab_c() / (LAB_BAND[1] - LAB_BAND[0]),
                     "That is c/f_F: the sound goes down and back, L = c/(2 f_F)."),))
def _() -> float:
    f_f = (LAB_BAND[1] - LAB_BAND[0]) / LAB_MIN_RESONANCES
    return _lab_c() / (2.0 * f_f)


@exercise("lab.cutoff", hint="The first cross mode of a round tube starts at 1.8412 c/(π d).",
          mistakes=((lambda: 1.8412 * _lab_c() / (np.pi * 2 * LAB_CUTOFF_DIAMETER),
                     "1.8412 c/(π d) takes the diameter d, not twice it."),
                    (lambda: 1.8412 * _lab_c() / (np.pi * 0.075),
                     "That is the cutoff of the paper's 75 mm tube; this pipe is narrower.")))
def _() -> float:
    from dstoolkit.gauge._acoustics import plane_wave_cutoff

    return plane_wave_cutoff(LAB_CUTOFF_DIAMETER, _lab_c())


@exercise("lab.thermometer-tolerance",
          hint="δL = L · 0.606 δT / c (c = 331.3 + 0.606 T): solve for δT.",
          mistakes=((lambda: LAB_TOLERANCE_CASE[1] * _lab_c() / LAB_TOLERANCE_CASE[0],
                     "c changes by 0.606 m/s per °C, not by 1: divide by 0.606 too."),))
def _() -> float:
    level, tolerance = LAB_TOLERANCE_CASE
    c_per_degree = float(speed_of_sound(LAB_TEMPERATURE + 1.0)) - _lab_c()
    return tolerance * _lab_c() / (c_per_degree * level)


@exercise("lab.uncertainty", hint="Independent parts of an uncertainty add in quadrature: "
          "the square root of the sum of their squares.",
          mistakes=((lambda: float(sum(LAB_UNCERTAINTIES_MM)),
                     "That is their plain sum: independent parts add in quadrature."),
                    (lambda: float(max(LAB_UNCERTAINTIES_MM)),
                     "That is only the largest part; the others add to it, in quadrature.")))
def _() -> float:
    return float(np.sqrt(np.sum(np.square(LAB_UNCERTAINTIES_MM))))


# -- estimating the level (book/estimating_level.md, notebooks/09_estimating_level.ipynb) -------

#: The paper's Figs. 6–11 case (L m, T °C), its first reading z_1 (Hz, §4.3) and that
#: reading's order n_1 (1023.3/37.76 ≈ 27).
FIG10_CASE, PAPER_Z1, PAPER_N1 = (4.6, 26.5), 1023.3, 27
#: A reading that is too high by the mode of the paper's w (Hz): z = f − w, w = −6.9.
READING_BIAS = 6.9
#: The paper's direct-measurement error at 1.3 m, 27 °C (Table 3), m.
PAPER_DIRECT_13 = 0.238
#: The Monte Carlo of the improvement exercise: runs, seed, case.
IMPROVEMENT_RUNS, IMPROVEMENT_SEED = 30, 0


def _level_of_reading(z: float, n: int, case: tuple[float, float]) -> float:
    return float(level_from_resonance(z, n, _c(case)))


@exercise("estimating.first-level", atol=5e-4,
          hint="Eq. 32: L = n c/(2 z) with c = 331.3 + 0.606 T at 26.5 °C.",
          mistakes=((lambda: 2 * _level_of_reading(PAPER_Z1, PAPER_N1, FIG10_CASE),
                     "The echo travels down and back: divide by 2 z, not z."),))
def _() -> float:
    return _level_of_reading(PAPER_Z1, PAPER_N1, FIG10_CASE)


@exercise("estimating.bias", atol=2e-4,
          hint="The 27th resonance is at 27 c/(2L); the reading is 6.9 Hz above it. Put the "
          "reading and the true order into eq. 32 and subtract 4.6 m.",
          mistakes=((lambda: -float(_bias_error()),
                     "Check the sign: a reading that is too high gives a level that is too "
                     "short."),))
def _bias_error() -> float:
    f = PAPER_N1 * _fundamental(FIG10_CASE)
    return _level_of_reading(f + READING_BIAS, PAPER_N1, FIG10_CASE) - FIG10_CASE[0]


@exercise("estimating.outlier-orders", rtol=1e-2, atol=0.0,
          hint="A unit error of n_k costs L/n_k in eq. 32. Average L/n over the orders of "
          "the resonances in [1000, 2500] Hz at 1.3 m and 27 °C, and divide 0.238 m by it.")
def _() -> float:
    case = (1.3, 27.0)
    orders = resonance_orders(case[0], _c(case), GAUGE_BAND)
    return PAPER_DIRECT_13 / float(np.mean(case[0] / orders))


def improvement_table() -> Any:
    """The Table 3 row of the improvement exercise: 4.6 m, true orders, the paper's filter
    and direct measurement, IMPROVEMENT_RUNS runs from seed IMPROVEMENT_SEED."""
    from dstoolkit.studies._experiments import run_table3

    return run_table3(runs=IMPROVEMENT_RUNS, seed=IMPROVEMENT_SEED, cases=[FIG10_CASE],
                      methods=("dependent_evidence", "direct"), order_rule="true",
                      progress=False)


@exercise("estimating.improvement", rtol=1e-6, atol=0.0,
          hint="Divide the direct measurement's mean level error by the paper's filter's, "
          "both from table.error(4.6, method).",
          mistakes=((lambda: 1.0 / float(_improvement()),
                     "That is the inverse: direct ÷ paper's filter is larger than 1."),))
def _improvement() -> float:
    table = improvement_table()
    return table.error(FIG10_CASE[0], "direct") / table.error(FIG10_CASE[0],
                                                              "dependent_evidence")


# -- beyond the paper (book/beyond_the_paper.md, notebooks/10_beyond_the_paper.ipynb) -----------

#: Bounds scale, runs and seed of the bounded-error failure exercise.
FAILURE_SCALE, FAILURE_RUNS, FAILURE_SEED = 0.75, 20, 0


def _paper_w() -> Any:
    """The paper's observation noise w (Table 2) as the filters take it."""
    from dstoolkit.gauge._gauge_model import GAUGE_OBS_NOISE

    return GAUGE_OBS_NOISE


@exercise("beyond.start-error", atol=1e-3,
          hint="z_1 = x_1 − w_1, so x̂_1 − x_1 = −w_1; take its expectation. The mean of a "
          "triangular density is (a + b + c)/3.",
          mistakes=((lambda: float(_paper_w().mean[0]),
                     "Check the sign: z = x − w, and w is negative, so the reading is high."),))
def _() -> float:
    return -float(_paper_w().mean[0])


@exercise("beyond.kalman-sigma", atol=1e-3,
          hint="Var = (a² + b² + c² − ab − ac − bc)/18 for the triangle with support [a, b] "
          "and mode c; take its square root.",
          mistakes=((lambda: 1.23, "That is the σ of the measured errors from which the paper "
                     "made the bounds (±3σ); the triangle on those bounds has another σ."),))
def _() -> float:
    return float(np.sqrt(_paper_w().variance[0]))


def _example_sizes(p: int) -> tuple[int, int]:
    """(focal elements of E_v, of E_w) of the predator–prey example with p cuts."""
    from dstoolkit.filters._dependent import DependentEvidenceFilter
    from dstoolkit.filters._example_systems import lotka_volterra

    noise = DependentEvidenceFilter(p=p).noise_evidence(lotka_volterra())
    return len(noise.state), len(noise.observation)


@exercise("beyond.products", atol=0.0, rtol=0.0,
          hint="Count per step: state boxes |E_v|, predicted boxes |E_v|·|E_v|, Step 4 "
          "products predicted × |E_w|, Step 6 products (Step 4's) × (predicted).",
          mistakes=((lambda: 1024, "That is the count for a scalar state (4 × 4 × 4 × 16): "
                     "in two dimensions every evidence has 4 × 4 = 16 boxes."),))
def _() -> int:
    n_v, n_w = _example_sizes(3)
    predicted = n_v * n_v
    return predicted * n_w * predicted


@exercise("beyond.failures", atol=1e-9,
          hint="Build the model with the scaled bounds (scaled_noise), run "
          "BoundedErrorFilter(on_inconsistent='raise') on each run, count the runs that raise "
          "InconsistentDataError and divide by the number of runs.")
def _() -> float:
    from dstoolkit.gauge._gauge_model import gauge_state_space_model
    from dstoolkit.studies._estimation import bounded_error_failures, scaled_noise, tracking_data

    data = tracking_data(*FIG10_CASE, runs=FAILURE_RUNS, seed=FAILURE_SEED)
    model = gauge_state_space_model(scaled_noise(data.state_noise, FAILURE_SCALE),
                                    scaled_noise(data.obs_noise, FAILURE_SCALE))
    return bounded_error_failures(model, data)[0]


@exercise("beyond.offset-ratio", atol=2e-3,
          hint="b = kL/c + kτ with k = 280 Hz/s and τ = 10 ms; f_F = c/(2L). Divide.",
          mistakes=((lambda: SWEEP_RATE * LONG_CASE[0] / _c(LONG_CASE) / _fundamental(LONG_CASE),
                     "You left out the latency's k τ."),))
def _() -> float:
    b = (float(sweep_rate_offset(SWEEP_RATE, _fundamental(LONG_CASE)))
         + latency_offset(SWEEP_RATE, GAUGE_LATENCY))
    return b / _fundamental(LONG_CASE)


__all__ = [
    "Exercise",
    "Feedback",
    "REGISTRY",
    "check",
    "exercise",
    "exercises",
    "solution",
]
