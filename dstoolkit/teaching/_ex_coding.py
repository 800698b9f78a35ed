"""Coding exercises: the learner writes the function; dstoolkit computes what it must give.

Each registration names the dstoolkit computation (the *reference*, on the same plain data
as the learner's function), fixed cases with their edge cases (total conflict, a vacuous
source, a degenerate interval, …) and seeded random ones, and wrong implementations standing
for named mistakes (built from the reference, so that no right plain function is in here).
"""

from __future__ import annotations

import itertools
import warnings
from typing import Any, cast

import numpy as np

from dstoolkit.evidence import (
    IntervalEvidence,
    MassFunction,
    cartesian_product,
    combine_dependent,
    dempster,
    dependence,
    discount,
    image,
    triangular_evidence,
)
from dstoolkit.evidence import energy as _energy
from dstoolkit.filters import BoundedNoise
from dstoolkit.gauge import level_from_resonance, orders_eq43, resonance_orders, speed_of_sound

from ._coding import Case, coding_exercise, seeded
from ._ex_filter import HAND_EPSILON, HAND_XHAT, HAND_Z

# -- data: finite frames ------------------------------------------------------------------

ABC = frozenset("abc")
LEVEL = ("low", "mid", "high")


def fs(*items: Any) -> frozenset:
    """Return a focal element: ``fs("low", "mid")``."""
    return frozenset(items)


#: The book's running example and the two sensors of combining evidence.
RUNNING = {fs("low"): 0.5, fs("low", "mid"): 0.3, frozenset(LEVEL): 0.2}
SENSOR1 = {fs("low"): 0.6, frozenset(LEVEL): 0.4}
SENSOR2 = {fs("high"): 0.7, fs("mid", "high"): 0.2, frozenset(LEVEL): 0.1}
E2_DEPENDENT = {fs("low"): 0.4, fs("mid"): 0.4, frozenset(LEVEL): 0.2}


def random_mass(rng: np.random.Generator, frame: frozenset = ABC) -> dict[frozenset, float]:
    """2–4 random non-empty focal elements of ``frame`` with random masses."""
    subsets = [
        frozenset(c)
        for r in range(1, len(frame) + 1)
        for c in itertools.combinations(sorted(frame), r)
    ]
    picks = rng.choice(len(subsets), size=int(rng.integers(2, 5)), replace=False)
    masses = np.round(rng.dirichlet(np.ones(picks.size)), 6)
    masses[-1] = 1.0 - masses[:-1].sum()
    return {subsets[i]: float(m) for i, m in zip(picks, masses, strict=True)}


def _mf(m: dict[frozenset, float], frame: Any = None) -> MassFunction:
    frame = tuple(sorted(frame or frozenset().union(*m)))
    return MassFunction({tuple(sorted(k)): v for k, v in m.items()}, frame)


def _as_dict(m: MassFunction) -> dict[frozenset, float]:
    return {frozenset(k): float(v) for k, v in m.as_dict().items()}


def _rows(ev: IntervalEvidence) -> list[tuple[float, float, float]]:
    return [(float(lo), float(hi), float(m)) for lo, hi, m in ev.to_rows()]


def sorted_rows(rows: Any) -> list[list[float]]:
    """Rows (lo, hi, mass) merged where equal within 1e-9, zero masses dropped, sorted."""
    merged: list[list[float]] = []
    for lo, hi, m in sorted((float(r[0]), float(r[1]), float(r[2])) for r in rows):
        if merged and abs(merged[-1][0] - lo) < 1e-9 and abs(merged[-1][1] - hi) < 1e-9:
            merged[-1][2] += m
        else:
            merged.append([lo, hi, m])
    return [r for r in merged if abs(r[2]) > 1e-12]


# -- mass functions -------------------------------------------------------------------------


def _bel_pl_cases() -> list[Case]:
    rng = seeded(31)
    cases = [
        Case("running example, A = {low, mid}", (RUNNING, {"low", "mid"})),
        Case("running example, A = {mid}", (RUNNING, {"mid"})),
        Case("A = Θ", (RUNNING, set(LEVEL))),
        Case("vacuous source", ({frozenset(LEVEL): 1.0}, {"high"})),
    ]
    for i in range(6):
        m = random_mass(rng)
        a = {h for h in sorted(ABC) if rng.random() < 0.5} or {"a"}
        cases.append(Case(f"random {i + 1}", (m, a)))
    return cases


def _bel_pl_reference(m: dict, a: Any) -> tuple[float, float]:
    mf = _mf(m, frozenset().union(*m, a))
    return mf.belief(tuple(sorted(a))), mf.plausibility(tuple(sorted(a)))


coding_exercise(
    "mass.bel-pl-code",
    reference=_bel_pl_reference,
    cases=_bel_pl_cases,
    arg_names=("m", "a"),
    hint="Bel adds the masses of the focal elements inside A (B ⊆ A); Pl those that meet A "
    "(B ∩ A ≠ ∅).",
    mistakes=(
        (
            lambda m, a: tuple(reversed(_bel_pl_reference(m, a))),
            "Bel and Pl are swapped: Bel(A) ≤ Pl(A) always.",
        ),
        (
            lambda m, a: (_bel_pl_reference(m, a)[0], sum(v for b, v in m.items() if b >= set(a))),
            "Your Pl counts only the focal elements that contain A (that is the commonality "
            "Q(A)); Pl counts every focal element that meets A.",
        ),
    ),
)


def _betp_cases() -> list[Case]:
    rng = seeded(32)
    return [
        Case("running example", (RUNNING,)),
        Case("vacuous source", ({frozenset(LEVEL): 1.0},)),
        Case("Bayesian source", ({fs("a"): 0.2, fs("b"): 0.8},)),
    ] + [Case(f"random {i + 1}", (random_mass(rng),)) for i in range(6)]


coding_exercise(
    "mass.betp-code",
    reference=lambda m: _mf(m).pignistic(),
    cases=_betp_cases,
    arg_names=("m",),
    hint="Each focal element gives m(A)/|A| to each of its |A| members (eq. 3.4).",
    mistakes=(
        (
            lambda m: {h: sum(v for b, v in m.items() if h in b) for h in frozenset().union(*m)},
            "You gave each member the whole mass m(A): that is Pl({x}), and the "
            "probabilities add up to more than 1. Divide by |A|.",
        ),
    ),
)

# -- combining evidence -----------------------------------------------------------------------


def _dempster_cases() -> list[Case]:
    rng = seeded(41)
    z1 = {fs("meningitis"): 0.99, fs("tumour"): 0.01}
    z2 = {fs("concussion"): 0.99, fs("tumour"): 0.01}
    cases = [
        Case("the two sensors", (SENSOR1, SENSOR2)),
        Case("Zadeh's doctors", (z1, z2)),
        Case("vacuous source", (RUNNING, {frozenset(LEVEL): 1.0})),
        Case("a source with itself", (RUNNING, RUNNING)),
        Case("total conflict", ({fs("a"): 1.0}, {fs("b"): 1.0})),
    ]
    for i in range(6):
        m1, m2 = random_mass(rng), random_mass(rng)
        if not any(b & c for b in m1 for c in m2):
            continue  # total conflict is a chosen case above, not a random one
        cases.append(Case(f"random {i + 1}", (m1, m2)))
    return cases


def _unnormalised(m1: dict, m2: dict) -> dict:
    out: dict = {}
    for (b, mb), (c, mc) in itertools.product(m1.items(), m2.items()):
        if b & c:
            out[b & c] = out.get(b & c, 0.0) + mb * mc
    return out


def _yager(m1: dict, m2: dict) -> dict:
    out = _unnormalised(m1, m2)
    theta = frozenset().union(*m1, *m2)
    out[theta] = out.get(theta, 0.0) + 1.0 - sum(out.values())
    return out


def _dempster_reference(m1: dict, m2: dict) -> dict:
    frame = frozenset().union(*m1, *m2)
    return _as_dict(dempster(_mf(m1, frame), _mf(m2, frame)))


coding_exercise(
    "combine.dempster-code",
    reference=_dempster_reference,
    cases=_dempster_cases,
    arg_names=("m1", "m2"),
    hint="Multiply every pair of masses, put the product on the intersection, add up the "
    "products whose intersection is empty (K), and divide the others by 1 − K (eq. 1).",
    mistakes=(
        (
            _unnormalised,
            "You did not renormalise: divide every mass by 1 − K, so that the "
            "masses add up to 1 again.",
        ),
        (
            _yager,
            "You gave the conflict K to Θ: that is Yager's rule. Dempster's rule "
            "drops it and divides by 1 − K.",
        ),
    ),
)


def _discount_cases() -> list[Case]:
    rng = seeded(42)
    frame = set(LEVEL)
    return [
        Case("running example, rate 0.1", (RUNNING, 0.1, frame)),
        Case("rate 0 (fully reliable)", (SENSOR2, 0.0, frame)),
        Case("rate 1 (vacuous source)", (SENSOR1, 1.0, frame)),
        Case("no mass on Θ yet", ({fs("low"): 1.0}, 0.25, frame)),
    ] + [
        Case(f"random {i + 1}", (random_mass(rng), round(float(rng.random()), 3), set(ABC)))
        for i in range(5)
    ]


def _discount_reference(m: dict, rate: float, frame: Any) -> dict:
    return _as_dict(discount(_mf(m, frame), rate))


coding_exercise(
    "combine.discount-code",
    reference=_discount_reference,
    cases=_discount_cases,
    arg_names=("m", "rate", "frame"),
    hint="m'(A) = (1 − rate)·m(A) for every A, and m'(Θ) = (1 − rate)·m(Θ) + rate (eqs. 9–10).",
    mistakes=(
        (
            lambda m, rate, frame: {**m, frozenset(frame): m.get(frozenset(frame), 0.0) + rate},
            "You added the rate to Θ without scaling the other masses by 1 − rate: the masses "
            "now add up to 1 + rate.",
        ),
        (
            lambda m, rate, frame: _discount_reference(m, 1.0 - rate, frame),
            "You multiplied by the rate instead of 1 − rate: a rate is what is taken away.",
        ),
    ),
)

# -- dependent evidence -----------------------------------------------------------------------


def _interval_energy_cases() -> list[Case]:
    rng = seeded(51)
    cases = [
        Case("Appendix A, (A2)", ([(0.3, 1.9, 0.6), (0.3, 1.93, 0.3), (0.32, 1.93, 0.1)],)),
        Case("one interval", ([(0.0, 2.0, 1.0)],)),
        Case("degenerate interval (a point)", ([(1.0, 1.0, 0.5), (0.0, 2.0, 0.5)],)),
        Case("Table 1 evidence", (_rows(triangular_evidence(-0.3, 0.0, 0.3, theta=(-10, 10))),)),
    ]
    for i in range(5):
        lo = rng.uniform(-1, 0, 3)
        hi = lo + rng.uniform(0.1, 2, 3)
        m = rng.dirichlet(np.ones(3))
        cases.append(
            Case(
                f"random {i + 1}",
                ([(float(a), float(b), float(c)) for a, b, c in zip(lo, hi, m, strict=True)],),
            )
        )
    return cases


def _energy_reference(rows: list) -> float:
    return float(_energy(IntervalEvidence.from_pairs(rows, merge=False)))


coding_exercise(
    "dependent.energy-code",
    reference=_energy_reference,
    cases=_interval_energy_cases,
    arg_names=("rows",),
    hint="Eq. A1: Σ m(A_i)·w_min/w(A_i), w_min the smallest width of the evidence; a point "
    "(width 0) counts with weight 1.",
    mistakes=(
        (
            lambda rows: sum(m / (hi - lo) if hi > lo else m for lo, hi, m in rows),
            "You divided by the width alone: eq. A1 multiplies by w_min, so that the narrowest "
            "element counts 1 and the energy stays in [0, 1].",
        ),
        (
            lambda rows: (
                _energy_reference(rows)
                - rows[-1][2]
                * min(hi - lo for lo, hi, _ in rows)
                / (rows[-1][1] - rows[-1][0] or 1.0)
            ),
            "You left out the last (widest) element as if it were Θ of a finite frame: on "
            "intervals every focal element counts in En′ (eq. A1).",
        ),
    ),
)


def _pairs_cases() -> list[Case]:
    rng = seeded(52)
    frame = set(LEVEL)
    cases = [
        Case("the chapter's E1 and E2", (RUNNING, E2_DEPENDENT, frame)),
        Case("a source with itself", (RUNNING, RUNNING, frame)),
        Case(
            "nothing shared",
            (
                {fs("low"): 0.5, frozenset(LEVEL): 0.5},
                {fs("high"): 0.5, frozenset(LEVEL): 0.5},
                frame,
            ),
        ),
        Case("vacuous source", (RUNNING, {frozenset(LEVEL): 1.0}, frame)),
    ]
    for i in range(5):
        cases.append(Case(f"random {i + 1}", (random_mass(rng), random_mass(rng), set(ABC))))
    return cases


def _dependency_reference(m1: dict, m2: dict, frame: Any) -> tuple[float, float, float]:
    dep = dependence(_mf(m1, frame), _mf(m2, frame))
    return dep.degree, dep.r12, dep.r21


def _swapped_coefficients(m1: dict, m2: dict, frame: Any) -> tuple[float, float, float]:
    degree, r12, r21 = _dependency_reference(m1, m2, frame)
    return degree, r21, r12


coding_exercise(
    "dependent.coefficients-code",
    reference=_dependency_reference,
    cases=_pairs_cases,
    arg_names=("m1", "m2", "frame"),
    hint="En(E) leaves Θ out (eq. 2); the joint energy sums min(m1(A), m2(A))/|A| over the "
    "common focal elements A ≠ Θ (eq. 3); R12 = 1 − (D/2)·En(E2)/En(E1).",
    mistakes=(
        (
            _swapped_coefficients,
            "R12 and R21 are swapped: R12 = 1 − (D/2)·En(E2)/En(E1) discounts E1 by how much "
            "of it E2 already says.",
        ),
        (
            lambda m1, m2, frame: _dependency_reference(m1, m2, frozenset(frame) | {"?"}),
            "You counted Θ in the energies: its mass says nothing, so eq. 2 leaves it out.",
        ),
    ),
)


def _combine_dependent_reference(m1: dict, m2: dict, frame: Any) -> dict:
    return _as_dict(combine_dependent(_mf(m1, frame), _mf(m2, frame)))


def _discounted_at_r(m1: dict, m2: dict, frame: Any) -> dict:
    _, r12, r21 = _dependency_reference(m1, m2, frame)
    return _dempster_reference(
        _discount_reference(m1, r12, frame), _discount_reference(m2, r21, frame)
    )


coding_exercise(
    "dependent.combine-code",
    reference=_combine_dependent_reference,
    cases=lambda: [
        *_pairs_cases(),
        Case("total conflict, nothing shared", ({fs("low"): 1.0}, {fs("high"): 1.0}, set(LEVEL))),
    ],
    arg_names=("m1", "m2", "frame"),
    hint="Get D, R12, R21 (your dependency), discount E1 at rate 1 − R12 and E2 at rate "
    "1 − R21 (your discount), then combine with your dempster_rule.",
    mistakes=(
        (
            lambda m1, m2, frame: _dempster_reference(m1, m2),
            "You combined without decorrelating: Dempster's rule alone counts what both "
            "sources share twice.",
        ),
        (
            _discounted_at_r,
            "You discounted at rate R instead of 1 − R: R is the part of the evidence that is "
            "kept (eq. 9).",
        ),
    ),
)

# -- noise to evidence ------------------------------------------------------------------------


def _triangular_cases() -> list[Case]:
    rng = seeded(61)
    cases = [
        Case("Table 1 (p = 3, ε = 0.05)", (-0.3, 0.0, 0.3, 3, 0.05)),
        Case("Table 2", (-10.59, -6.9, -3.21, 3, 0.05)),
        Case("one cut (p = 1)", (-1.0, 0.0, 2.0, 1, 0.1)),
        Case("no discount (ε = 0)", (-1.0, 0.5, 1.0, 4, 0.0)),
        Case("one-sided noise (mode = lower)", (0.0, 0.0, 1.0, 2, 0.05)),
    ]
    for i in range(4):
        lo, mode, hi = np.sort(rng.uniform(-5, 5, 3))
        cases.append(
            Case(
                f"random {i + 1}",
                (
                    float(lo),
                    float(mode),
                    float(hi),
                    int(rng.integers(1, 6)),
                    round(float(rng.uniform(0, 0.3)), 3),
                ),
            )
        )
    return cases


def _cuts_from_one(lo: float, mode: float, hi: float, p: int, epsilon: float) -> list:
    shifted = [
        (lo + (i + 1) / p * (mode - lo), hi - (i + 1) / p * (hi - mode), (1 - epsilon) / p)
        for i in reversed(range(p))
    ]
    return [*shifted, _theta_row(_triangular_reference(lo, mode, hi, p, epsilon))]


def _triangular_reference(lo: float, mode: float, hi: float, p: int, epsilon: float) -> list:
    return _rows(triangular_evidence(lo, mode, hi, p, epsilon))


def _theta_row(rows: list) -> tuple[float, float, float]:
    """Return Θ's row of a triangular evidence: the widest."""
    return max(rows, key=lambda row: row[1] - row[0])


coding_exercise(
    "noise.triangular-code",
    reference=_triangular_reference,
    cases=_triangular_cases,
    normalise=sorted_rows,
    arg_names=("lower", "mode", "upper", "p", "epsilon"),
    hint="α runs over 0, 1/p, …, (p − 1)/p (eq. 23): α = 0 is the whole support, and the "
    "mode alone (α = 1) is not a cut. Each cut has (1 − ε)/p; Θ = mode ± 100σ, "
    "σ = (upper − lower)/6.",
    mistakes=(
        (
            _cuts_from_one,
            "Your cuts run α = 1/p … 1: the last one is the mode alone and the "
            "support [lower, upper] is missing. Take α = 0, 1/p, …, (p − 1)/p.",
        ),
        (
            lambda lo, mode, hi, p, epsilon: (
                lambda rows: [
                    (a, b, m if (a, b, m) == _theta_row(rows) else 1.0 / p) for a, b, m in rows
                ]
            )(_triangular_reference(lo, mode, hi, p, epsilon)),
            "Each cut gets (1 − ε)/p, not 1/p: Θ takes ε, and the masses must add up to 1.",
        ),
    ),
)


def _cdf_cases() -> list[Case]:
    rng = seeded(62)
    table1 = _rows(triangular_evidence(-0.3, 0.0, 0.3, theta=(-10, 10)))
    cases = [
        Case("Table 1 at x = 0.15", (table1, 0.15)),
        Case("x on an end point", (table1, 0.1)),
        Case("x left of everything", (table1, -20.0)),
        Case("degenerate interval", ([(0.5, 0.5, 0.4), (0.0, 1.0, 0.6)], 0.5)),
    ]
    for i in range(5):
        lo = rng.uniform(-1, 0, 3)
        rows = [
            (float(a), float(a + w), float(m))
            for a, w, m in zip(lo, rng.uniform(0, 1, 3), rng.dirichlet(np.ones(3)), strict=True)
        ]
        cases.append(Case(f"random {i + 1}", (rows, float(rng.uniform(-1, 1)))))
    return cases


def _cdf_reference(rows: list, x: float) -> tuple[float, float]:
    lower, upper = IntervalEvidence.from_pairs(rows, merge=False).cdf_bounds(x)
    return float(lower), float(upper)


coding_exercise(
    "noise.cdf-code",
    reference=_cdf_reference,
    cases=_cdf_cases,
    arg_names=("rows", "x"),
    hint="Bel((−∞, x]) needs the whole interval at or left of x (hi ≤ x); Pl((−∞, x]) needs "
    "only a part of it there (lo ≤ x). End points count.",
    mistakes=(
        (
            lambda rows, x: tuple(reversed(_cdf_reference(rows, x))),
            "Lower and upper are swapped: the lower bound Bel counts the intervals entirely "
            "left of x.",
        ),
        (
            lambda rows, x: (
                sum(m for lo, hi, m in rows if hi < x),
                sum(m for lo, hi, m in rows if lo < x),
            ),
            "You used strict inequalities: (−∞, x] contains x, so an interval ending at x is "
            "inside it.",
        ),
    ),
)

# -- random sets ------------------------------------------------------------------------------


def tilted(xi: Any) -> Any:
    """ξ1 + 2ξ2 − ξ3 (the chapter's monotone example)."""
    return xi[0] + 2 * xi[1] - xi[2]


def saddle(xi: Any) -> Any:
    """ξ1·ξ2, neither increasing nor decreasing on boxes that straddle 0."""
    return xi[0] * xi[1]


def square(xi: Any) -> Any:
    """ξ1²."""
    return xi[0] ** 2


def difference(xi: Any) -> Any:
    """ξ1 − ξ2."""
    return xi[0] - xi[1]


def _vectorised(f: Any) -> Any:
    return lambda x: f(np.moveaxis(np.asarray(x), -1, 0))


def _vertex_cases() -> list[Case]:
    rng = seeded(71)
    cases = [
        Case("monotone, 3-D", (tilted, [0.0, 1.0, 2.0], [1.0, 2.0, 4.0])),
        Case("difference", (difference, [0.0, 0.0], [1.0, 2.0])),
        Case("a saddle", (saddle, [-1.0, -2.0], [2.0, 1.0])),
        Case("x² across 0 (vertex misses the minimum)", (square, [-1.0], [2.0])),
        Case("degenerate box (a point)", (tilted, [1.0, 1.0, 1.0], [1.0, 1.0, 1.0])),
    ]
    for i, f in enumerate((saddle, difference, tilted)):
        n = 3 if f is tilted else 2
        lo = rng.uniform(-2, 1, n)
        cases.append(
            Case(
                f"random {i + 1}",
                (f, [float(v) for v in lo], [float(v) for v in lo + rng.uniform(0, 2, n)]),
            )
        )
    return cases


def _vertex_reference(f: Any, lo: list, hi: list) -> tuple[float, float]:
    with warnings.catch_warnings():  # the vertex method's warning is the point of case 4
        warnings.simplefilter("ignore")
        a, b = cast(
            tuple[np.ndarray, np.ndarray],
            image((np.array(lo), np.array(hi)), _vectorised(f), method="vertex"),
        )
    return float(a[0]), float(b[0])


coding_exercise(
    "random.vertex-code",
    reference=_vertex_reference,
    cases=_vertex_cases,
    arg_names=("f", "lo", "hi"),
    hint="A box in n dimensions has 2^n corners: every choice of lo or hi per coordinate "
    "(itertools.product). Evaluate f at each and take the smallest and largest value.",
    mistakes=(
        (
            lambda f, lo, hi: tuple(sorted((f(list(lo)), f(list(hi))))),
            "You evaluated f at two corners only, all-lower and all-upper: that is enough when "
            "f increases in every coordinate, not when it decreases in one (Prop. 2).",
        ),
    ),
)


def _product_cases() -> list[Case]:
    rng = seeded(72)
    x1 = [(0.0, 1.0, 0.6), (1.5, 3.0, 0.4)]
    x2 = [(0.0, 2.0, 0.7), (1.0, 4.0, 0.3)]
    cases = [
        Case("the chapter's marginals", (x1, x2)),
        Case("vacuous second marginal", (x1, [(-5.0, 5.0, 1.0)])),
        Case("degenerate interval", ([(1.0, 1.0, 1.0)], x2)),
    ]
    for i in range(4):
        rows = [
            [
                (float(a), float(a + 1), float(m))
                for a, m in zip(rng.uniform(-2, 2, k), rng.dirichlet(np.ones(k)), strict=True)
            ]
            for k in (2, 3)
        ]
        cases.append(Case(f"random {i + 1}", tuple(rows)))
    return cases


def _product_reference(x1: list, x2: list) -> dict:
    rel = cartesian_product(
        [
            IntervalEvidence.from_pairs(x1, merge=False),
            IntervalEvidence.from_pairs(x2, merge=False),
        ],
        merge=False,
    )
    return {
        ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))): float(m)
        for lo, hi, m in zip(rel.boxes_lo, rel.boxes_hi, rel.mass, strict=True)
    }


def _boxes(d: Any) -> dict:
    if not isinstance(d, dict):
        raise TypeError("return a dict {((lo1, hi1), (lo2, hi2)): mass}")
    return {tuple(tuple(float(v) for v in side) for side in box): float(m) for box, m in d.items()}


coding_exercise(
    "random.product-code",
    reference=_product_reference,
    cases=_product_cases,
    normalise=_boxes,
    arg_names=("x1", "x2"),
    hint="Every pair (C1, C2) of focal elements gives one box C1 × C2; independence makes "
    "its mass the product m1(C1)·m2(C2) (eq. 16).",
    mistakes=(
        (
            lambda x1, x2: {((a, b), (c, d)): (m + n) / 2 for a, b, m in x1 for c, d, n in x2},
            "You averaged the masses: for independent marginals the mass of a box is the "
            "product m1(C1)·m2(C2), and the masses then add up to 1.",
        ),
    ),
)

# -- why bounded noise ------------------------------------------------------------------------


def _bounded_reference(box: Any, v: Any, w: Any, z: float) -> tuple[float, float]:
    pred = IntervalEvidence.vacuous(box[0] + v[0], box[1] + v[1])
    ev = dempster(pred, IntervalEvidence.vacuous(z + w[0], z + w[1]))
    return float(ev.lo_1d[0]), float(ev.hi_1d[0])


def _bounded_cases() -> list[Case]:
    rng = seeded(81)
    cases = [
        Case("the chapter's step", ((1.2, 2.0), (-0.3, 0.3), (-0.5, 0.5), 2.6)),
        Case("bounds too tight: empty", ((1.2, 2.0), (-0.3, 0.3), (-0.2, 0.2), 2.6)),
        Case("asymmetric w", ((0.0, 1.0), (-0.1, 0.1), (-0.5, 0.1), 0.8)),
        Case("touching: a single point", ((0.0, 1.0), (0.0, 0.0), (0.0, 1.0), 1.0)),
        Case("degenerate box", ((1.0, 1.0), (0.0, 0.0), (-1.0, 1.0), 1.5)),
    ]
    for i in range(4):
        a = float(rng.uniform(-1, 1))
        cases.append(
            Case(
                f"random {i + 1}",
                ((a, a + 1.0), (-0.2, 0.2), (-0.5, 0.3), round(float(rng.uniform(-1, 2.5)), 3)),
            )
        )
    return cases


coding_exercise(
    "bounded.step-code",
    reference=_bounded_reference,
    cases=_bounded_cases,
    arg_names=("box", "v", "w", "z"),
    hint="x = z + w puts x in [z + w_lo, z + w_hi]; intersect that with the predicted "
    "[lo + v_lo, hi + v_hi], and raise ValueError when nothing is left.",
    mistakes=(
        (
            lambda box, v, w, z: (min(box[0] + v[0], z + w[0]), max(box[1] + v[1], z + w[1])),
            "You took the hull (union) of the prediction and the reading; the state must be "
            "in both, so intersect.",
        ),
        (
            lambda box, v, w, z: _bounded_reference(box, (0.0, 0.0), w, z),
            "You forgot the prediction: the state moves by v before the reading, so widen the "
            "box by v first.",
        ),
    ),
)

# -- the level gauge and estimating the level ---------------------------------------------------


def _orders_cases() -> list[Case]:
    rng = seeded(91)
    cases = [
        Case("9.6 m at 23.9 °C", (9.6, 23.9, (1000.0, 2500.0))),
        Case("1.3 m at 27 °C", (1.3, 27.0, (1000.0, 2500.0))),
        Case("a band narrower than f_F: no order", (0.5, 20.0, (1000.0, 1100.0))),
        Case("band edge on a resonance", (343.42 / 200.0, 20.0, (1000.0, 1800.0))),
    ]
    for i in range(4):
        cases.append(
            Case(
                f"random {i + 1}",
                (
                    round(float(rng.uniform(0.5, 10)), 3),
                    round(float(rng.uniform(0, 35)), 1),
                    (1000.0, 2400.0),
                ),
            )
        )
    return cases


def _orders_reference(length: float, temperature: float, band: Any) -> list[int]:
    return [int(n) for n in resonance_orders(length, float(speed_of_sound(temperature)), band)]


coding_exercise(
    "gauge.orders-code",
    reference=_orders_reference,
    cases=_orders_cases,
    arg_names=("length", "temperature", "band"),
    hint="f_F = c/(2L) with c = 331.3 + 0.606 T; the orders run from ⌈f_lo/f_F⌉ to "
    "⌊f_hi/f_F⌋, both ends included.",
    mistakes=(
        (
            lambda length, temperature, band: _orders_reference(length / 2, temperature, band),
            "Your f_F is c/L: the sound goes down the tube and back, so f_F = c/(2L).",
        ),
        (
            lambda length, temperature, band: _orders_reference(length, temperature, band)[1:-1],
            "You left out the orders at the ends of the band: a resonance exactly on f_lo or "
            "f_hi is in the band.",
        ),
    ),
)


def _eq43_cases() -> list[Case]:
    rng = seeded(92)
    c = float(speed_of_sound(23.9))
    cases = [
        Case(
            "9.6 m: z1 = 57 f_F + 0.2, z2 = 58 f_F − 0.2",
            (57 * c / 19.2 + 0.2, 58 * c / 19.2 - 0.2, 23.9),
        ),
        Case(
            "exact readings, 1.3 m at 27 °C",
            (9 * float(speed_of_sound(27.0)) / 2.6, 10 * float(speed_of_sound(27.0)) / 2.6, 27.0),
        ),
    ]
    for i in range(4):
        length, n = float(rng.uniform(1, 10)), int(rng.integers(5, 60))
        f_f = c / (2 * length)
        cases.append(Case(f"random {i + 1}", (n * f_f, (n + 1) * f_f, 23.9)))
    return cases


def _eq43_reference(z1: float, z2: float, temperature: float) -> tuple[int, float]:
    n = int(orders_eq43(np.array([z1, z2]))[0])
    return n, float(level_from_resonance(z1, n, float(speed_of_sound(temperature))))


def _twice_the_level(z1: float, z2: float, temperature: float) -> tuple[int, float]:
    order, length = _eq43_reference(z1, z2, temperature)
    return order, 2 * length


coding_exercise(
    "estimating.eq43-code",
    reference=_eq43_reference,
    cases=_eq43_cases,
    arg_names=("z1", "z2", "temperature"),
    hint="Neighbouring resonances are f_F apart, so z1/(z2 − z1) ≈ n1 (eq. 43); round it, "
    "then L = n1·c/(2 z1) (eq. 32).",
    mistakes=(
        (
            _twice_the_level,
            "Your level is twice too long: eq. 32 divides by 2 z1 (down and back).",
        ),
        (
            lambda z1, z2, temperature: _eq43_reference(z2, z2 + (z2 - z1), temperature),
            "You found the order of z2, not of z1: z2/(z2 − z1) is n1 + 1.",
        ),
    ),
)

# -- beyond the paper -------------------------------------------------------------------------


def _sigma_cases() -> list[Case]:
    rng = seeded(101)
    cases = [
        Case("the paper's w", (-10.59, -6.9, -3.21)),
        Case("symmetric", (-0.3, 0.0, 0.3)),
        Case("one-sided (mode = lower)", (0.0, 0.0, 1.0)),
    ]
    for i in range(4):
        lo, mode, hi = np.sort(rng.uniform(-3, 3, 3))
        cases.append(Case(f"random {i + 1}", (float(lo), float(mode), float(hi))))
    return cases


def _sigma_reference(lo: float, mode: float, hi: float) -> float:
    return float(np.sqrt(BoundedNoise(lo, mode, hi).variance[0]))


coding_exercise(
    "beyond.sigma-code",
    reference=_sigma_reference,
    cases=_sigma_cases,
    arg_names=("lower", "mode", "upper"),
    hint="Var = (a² + b² + m² − ab − am − bm)/18 for the triangle on [a, b] with mode m; "
    "σ is its square root.",
    mistakes=(
        (
            lambda lo, mode, hi: (hi - lo) / 6.0,
            "(upper − lower)/6 is the σ of the measured errors from which the bounds were made "
            "(±3σ); the triangle on those bounds has a smaller σ.",
        ),
        (
            lambda lo, mode, hi: _sigma_reference(lo, mode, hi) ** 2,
            "That is the variance; σ is its square root.",
        ),
    ),
)

# -- the recursive filter ---------------------------------------------------------------------


def drift(x: Any) -> Any:
    """f(x) = x + 0.5 (a level that rises by 0.5 per step)."""
    return x + 0.5


def double(x: Any) -> Any:
    """g(x) = 2x (a sensor that reads twice the state)."""
    return 2.0 * x


def half(y: Any) -> Any:
    """g⁻¹(y) = y/2."""
    return y / 2.0


def same_value(x: Any) -> Any:
    """f(x) = x (a random walk) or g(x) = x."""
    return x


def shrink(x: Any) -> Any:
    """f(x) = 0.5x + 1."""
    return 0.5 * x + 1.0


def noise_rows(
    lower: float,
    mode: float,
    upper: float,
    p: int,
    epsilon: float,
    theta: tuple[float, float] | None = None,
) -> list[tuple[float, float, float]]:
    """E_v or E_w of Step 1 as rows (lo, hi, mass), computed with dstoolkit."""
    return _rows(triangular_evidence(lower, mode, upper, p, epsilon, theta))


#: The hand example of the chapter: x̂_k, z_{k+1}, f, g and p = 1 noise evidence.
HAND_STEP = (
    HAND_XHAT,
    HAND_Z,
    same_value,
    same_value,
    same_value,
    noise_rows(-0.5, 0.0, 0.5, 1, HAND_EPSILON, (-2.0, 2.0)),
    noise_rows(-0.5, 0.0, 0.5, 1, HAND_EPSILON, (-2.0, 2.0)),
)


def _filter_cases() -> list[Case]:
    """Numbers exact in binary (multiples of 1/8, p = 1, 2 or 4).

    Boxes that are equal on paper are equal in floating point, so the common focal elements of Step
    6 are found.
    """
    rng = seeded(111)
    v4 = noise_rows(-0.5, 0.0, 0.5, 4, 0.05, (-8.0, 8.0))
    w4 = noise_rows(-1.0, -0.5, 0.0, 4, 0.05, (-16.0, 16.0))
    v2, w2 = noise_rows(-0.5, 0, 0.5, 2, 0.0), noise_rows(-0.25, 0, 0.25, 2, 0.0)
    cases = [
        Case("the chapter's hand example (p = 1)", HAND_STEP),
        Case("p = 4, random walk", (2.0, 2.375, same_value, same_value, same_value, v4, w4)),
        Case("drift, g = 2x", (1.0, 3.5, drift, double, half, v4, w4)),
        Case("ε = 0, consistent reading", (0.0, 0.125, same_value, same_value, same_value, v2, w2)),
        Case(
            "total conflict (ε = 0, reading far off)",
            (0.0, 5.0, same_value, same_value, same_value, v2, w2),
        ),
    ]
    for i in range(3):
        x = float(rng.integers(-16, 16)) / 8
        z = float(shrink(x)) + float(rng.integers(-8, 8)) / 8
        cases.append(
            Case(
                f"random {i + 1}",
                (
                    x,
                    z,
                    shrink,
                    same_value,
                    same_value,
                    noise_rows(-0.5, 0.0, 0.5, 2, 0.1, (-8, 8)),
                    noise_rows(-0.5, 0.0, 0.5, 4, 0.05, (-8, 8)),
                ),
            )
        )
    return cases


def filter_record(
    xhat: float, z: float, f: Any, g: Any, g_inv: Any, v_rows: list, w_rows: list
) -> Any:
    """Every evidence of one step of dstoolkit's filter from x̂ with reading z.

    The :class:`~dstoolkit.filters.DependentRecord` of step 2, by the public ``initialize``/``step``
    with the noise evidence of the rows.
    """
    import dataclasses

    from dstoolkit.evidence import Boxes
    from dstoolkit.filters import DependentEvidenceFilter, NoiseEvidence, StateSpaceModel

    model = StateSpaceModel(
        f=lambda x, u: f(x),
        g=g,
        state_noise=BoundedNoise(-1.0, 0.0, 1.0),
        obs_noise=BoundedNoise(-1.0, 0.0, 1.0),
        f_monotone=(1, 1),
        g_monotone=(1,),
        g_inverse=lambda lo, hi, x_lo, x_hi: (
            np.maximum(x_lo, g_inv(lo)),
            np.minimum(x_hi, g_inv(hi)),
        ),
    )
    ev = IntervalEvidence.from_pairs(v_rows, merge=False)
    ew = IntervalEvidence.from_pairs(w_rows, merge=False)
    noise = NoiseEvidence(
        ev,
        ew,
        Boxes(ev.boxes_lo[None], ev.boxes_hi[None], ev.mass[None]),
        Boxes(ew.boxes_lo[None], ew.boxes_hi[None], ew.mass[None]),
        np.multiply.outer(ev.mass, ev.mass).reshape(1, -1),
    )
    flt = DependentEvidenceFilter(start=[xhat])
    state = dataclasses.replace(flt.initialize(model, z), noise=noise)
    return flt.step(state, z)[1]


def _filter_reference(
    xhat: float, z: float, f: Any, g: Any, g_inv: Any, v_rows: list, w_rows: list
) -> tuple[list, float]:
    step = filter_record(xhat, z, f, g, g_inv, v_rows, w_rows)
    return _rows(step.final), float(step.estimate[0])


def _filter_outcome(result: Any) -> list:
    rows, estimate = result
    return [sorted_rows(rows), float(estimate)]


def _plain_dempster_step6(
    xhat: float, z: float, f: Any, g: Any, g_inv: Any, v_rows: list, w_rows: list
) -> tuple[list, float]:
    """Return the step with plain Dempster in Step 6 (no decorrelation): the classic mistake.

    Steps 2–5 are the reference's (:func:`filter_record`); Step 6 combines its mapped-back
    evidence and its prediction by Dempster's rule alone (eq. 1).
    """
    step = filter_record(xhat, z, f, g, g_inv, v_rows, w_rows)
    final = dempster(step.mapped_back, step.prediction)
    return _rows(final), float(np.ravel(final.pignistic_expectation())[0])


coding_exercise(
    "filter.step-code",
    reference=_filter_reference,
    cases=_filter_cases,
    normalise=_filter_outcome,
    arg_names=("xhat", "z", "f", "g", "g_inv", "v_rows", "w_rows"),
    hint="Step 2 maps x̂ + V_i through f and adds V_j (masses m_i·m_j, equal boxes merge); "
    "Step 4 meets g(P) with z + W_j (eq. 1); Step 5 maps back within P; Step 6 discounts the "
    "mapped-back evidence and the prediction by R12, R21 (Θ = hull of each) and combines.",
    mistakes=(
        (
            lambda xhat, z, f, g, g_inv, v_rows, w_rows: _filter_reference(
                xhat, z, lambda x: f(xhat), g, g_inv, v_rows, w_rows
            ),
            "Your prediction adds the noise once, f(x̂) + V; the paper's Step 2 maps the state "
            "evidence x̂ + V through f and then adds V again (the noise enters twice).",
        ),
        (
            _plain_dempster_step6,
            "Step 6 needs the decorrelation: the mapped-back evidence and the prediction share "
            "focal elements, so discount each by its dependency coefficient before Dempster's "
            "rule (eqs. A7–A8).",
        ),
    ),
)
