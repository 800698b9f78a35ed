"""The exercises of the chapter on belief functions beyond Dempster (book/beyond_dempster.md).

Checked answers (a commonality, two conditionings, a canonical weight, a cautious
combination, a lower expectation, the choices of the explorer and of Appendix A) and two
coding exercises (the Möbius inversion of a belief function, the lower expectation), each
computed with dstoolkit.
"""

from __future__ import annotations

import itertools
from typing import Any

from dstoolkit.evidence import (
    MassFunction,
    appendix_pair,
    canonical_weights,
    cautious,
    combine_dependent,
    conditional,
    dempster,
    discount_to_nondogmatic,
    expected_utilities,
    set_function,
)

from ._checking import exercise
from ._coding import Case, coding_exercise, seeded

#: The frame of the chapter's examples: the level is low, as it should be, or high.
LEVELS = ("low", "ok", "high")
#: The gauge's evidence of the examples, m1, and a second source m2 (focal element: mass).
SOURCE1 = {("ok",): 0.4, ("ok", "high"): 0.3, LEVELS: 0.3}
SOURCE2 = {("ok", "high"): 0.6, LEVELS: 0.4}
#: The event of the conditioning exercise: the level is not high.
NOT_HIGH = ("low", "ok")
#: The utilities of the decision exercise: {action: {hypothesis: utility}}.
UTILITIES = {
    "fill": {"low": 1.0, "ok": 0.0, "high": -2.0},
    "wait": {"low": -1.0, "ok": 1.0, "high": -1.0},
    "drain": {"low": -2.0, "ok": 0.0, "high": 1.0},
}
#: The explorer prediction: combining this many copies of one source.
PREDICT_COPIES = 4
#: The answers of the choice exercises.
TRENDS = ("rises", "stays", "falls")
RULES = ("paper", "cautious", "dempster")


def mass(masses: dict) -> MassFunction:
    """Return a mass function on :data:`LEVELS` from ``{tuple of hypotheses: mass}``."""
    return MassFunction({frozenset(k): v for k, v in masses.items()}, LEVELS)


def _q_ok_high() -> float:
    q = set_function(mass(SOURCE1), "commonality")
    return float(q[0b110])  # bits: low 1, ok 2, high 4


@exercise(
    "belief.commonality",
    atol=1e-9,
    hint="Q(A) adds the masses of the focal elements that contain A (supersets), not of "
    "those inside it.",
    mistakes=(
        (
            lambda: mass(SOURCE1).belief({"ok", "high"}),
            "That is Bel({ok, high}): the masses "
            "of the focal elements inside the set. Q takes those that contain it.",
        ),
        (
            lambda: mass(SOURCE1).plausibility({"ok", "high"}),
            "That is Pl({ok, high}): the "
            "masses of the focal elements that meet the set. Q takes those that contain it.",
        ),
    ),
)
def _() -> float:
    return _q_ok_high()


def _conditional_beliefs() -> tuple[float, float]:
    m = mass(SOURCE1)
    return (
        conditional(m, NOT_HIGH).belief({"ok"}),
        conditional(m, NOT_HIGH, rule="geometric").belief({"ok"}),
    )


@exercise(
    "belief.condition",
    atol=1e-9,
    hint="Answer a pair (Dempster's, geometric). Dempster's rule moves each focal element "
    "to its intersection with A and divides by Pl(A); geometric conditioning keeps only "
    "the focal elements inside A and divides by Bel(A).",
    mistakes=(
        (
            lambda: tuple(reversed(_conditional_beliefs())),
            "The two are swapped: geometric "
            "conditioning drops the focal elements that leave A, Dempster's keeps their part "
            "inside A.",
        ),
        (
            lambda: (0.4, 0.4),
            "That is Bel({ok}) before conditioning: the focal elements that meet {low, ok} change.",
        ),
    ),
)
def _() -> tuple[float, float]:
    return _conditional_beliefs()


@exercise(
    "belief.weight",
    atol=1e-9,
    hint="Write m as {ok}^y ⊙ {ok, high}^x: m({ok}) = 1 − y, m({ok, high}) = (1 − x) y, "
    "m(Θ) = x y, and solve.",
    mistakes=(
        (
            lambda: 1.0 - SOURCE1[("ok", "high")],
            "1 − m(A) is the weight only when A is the "
            "one focal element besides Θ; here {ok} takes part of {ok, high}'s weight.",
        ),
    ),
)
def _() -> float:
    return canonical_weights(mass(SOURCE1))[frozenset({"ok", "high"})]


def _cautious_ok_high() -> float:
    return cautious(mass(SOURCE1), mass(SOURCE2)).mass_of({"ok", "high"})


@exercise(
    "belief.cautious",
    atol=1e-9,
    hint="Take each weight's minimum over the two sources (a weight of 1 where a source has "
    "none), then combine the simple mass functions A^w conjunctively.",
    mistakes=(
        (
            lambda: dempster(mass(SOURCE1), mass(SOURCE2)).mass_of({"ok", "high"}),
            "That is Dempster's rule: it multiplies the weights of {ok, high} (0.5 · 0.4), "
            "counting what the sources share twice; the cautious rule takes the smaller.",
        ),
    ),
)
def _() -> float:
    return _cautious_ok_high()


def _fused() -> MassFunction:
    return cautious(mass(SOURCE1), mass(SOURCE2))


@exercise(
    "belief.maximin",
    atol=1e-9,
    hint="For each focal element take the worst utility of 'wait' over its hypotheses, "
    "weigh it by the element's mass, and add.",
    mistakes=(
        (
            lambda: expected_utilities(_fused(), UTILITIES)["wait"],
            "That is the pignistic "
            "expectation: it shares each mass among the hypotheses; the lower expectation "
            "takes each focal element's worst case.",
        ),
        (
            lambda: expected_utilities(_fused(), UTILITIES, "maximax")["wait"],
            "That is the upper expectation (each focal element's best case).",
        ),
    ),
)
def _() -> float:
    return float(expected_utilities(_fused(), UTILITIES, "maximin")["wait"])


def copies_belief(shared: float, copies: int, rule: str) -> float:
    """Return Bel({ok}) after fusing ``copies`` copies of one source by ``rule``.

    The source is m({ok}) = ``shared``, m({ok, high}) = (1 − shared)/2, m(Θ) the rest:
    the explorer's evidence. ``rule`` is one of :data:`RULES`; the paper's rule fuses the
    copies one after the other (eqs. 9–10).

    Parameters
    ----------
    shared : float in [0, 1)
        m({ok}).
    copies : int
        How many copies (1 is the source itself).
    rule : {"paper", "cautious", "dempster"}
        The combination rule.

    Returns
    -------
    float
        Bel({ok}) of the fused evidence.

    Examples
    --------
    >>> round(copies_belief(0.4, 3, "cautious"), 6), round(copies_belief(0.4, 3, "dempster"), 3)
    (0.4, 0.784)
    """
    source = copies_source(shared)
    fuse = {"paper": combine_dependent, "cautious": cautious, "dempster": dempster}[rule]
    out = source
    for _ in range(int(copies) - 1):
        out = fuse(out, source)
    return out.belief({"ok"})


def copies_source(shared: float) -> MassFunction:
    """Return the explorer's source: m({ok}) = shared, m({ok, high}) = m(Θ) = (1 − shared)/2."""
    rest = (1.0 - float(shared)) / 2.0
    return mass({("ok",): float(shared), ("ok", "high"): rest, LEVELS: rest})


@exercise(
    "belief.predict-choice",
    hint=f"Answer one of {TRENDS}. The copies say nothing new: which rule notices?",
    mistakes=(
        (
            lambda: "rises",
            "Rising is what Dempster's rule does: it counts every copy as a new "
            "witness. The cautious rule is idempotent.",
        ),
    ),
)
def _() -> str:
    one = copies_belief(0.4, 1, "cautious")
    many = copies_belief(0.4, PREDICT_COPIES, "cautious")
    return "rises" if many > one + 1e-9 else "falls" if many < one - 1e-9 else "stays"


@exercise(
    "belief.self-choice",
    hint=f"Answer one of {RULES}. Fuse Appendix A's E1 with itself on its cells: which rule "
    "gives E1 back?",
    mistakes=(
        (
            lambda: "paper",
            "The paper's rule sees D = 1 and discounts both copies by half "
            "before Dempster's rule: the result is not E1.",
        ),
        (
            lambda: "dempster",
            "Dempster's rule squares the masses of E1's focal elements "
            "with themselves: it sharpens E1.",
        ),
    ),
)
def _() -> str:
    from dstoolkit.studies import cell_frame

    e1, _ = appendix_pair()
    _, m1, _ = cell_frame(e1, e1)
    m1 = discount_to_nondogmatic(m1)
    fused = {
        "paper": combine_dependent(m1, m1),
        "cautious": cautious(m1, m1),
        "dempster": dempster(m1, m1),
    }
    same = [
        r
        for r, f in fused.items()
        if set(f.as_dict()) == set(m1.as_dict())
        and all(abs(f.as_dict()[k] - v) < 1e-9 for k, v in m1.as_dict().items())
    ]
    return same[0]


# -- coding -----------------------------------------------------------------------------------


def _subsets(frame: tuple) -> list[frozenset]:
    return [frozenset(c) for r in range(len(frame) + 1) for c in itertools.combinations(frame, r)]


def _belief_table(m: dict) -> dict:
    """Return {A: Bel(A)} over every subset of the union of the focal elements of m."""
    frame = tuple(sorted(set().union(*m)))
    return {a: sum(v for f, v in m.items() if f <= a) for a in _subsets(frame)}


def _mobius_reference(bel: dict[frozenset, float]) -> dict:
    from dstoolkit.evidence import from_set_function

    frame = tuple(sorted(frozenset().union(*bel)))
    values = [0.0] * (1 << len(frame))
    for a, v in bel.items():
        values[sum(1 << frame.index(h) for h in a)] = v
    return from_set_function(values, frame, "belief").as_dict()


def _random_mass(rng: Any, frame: tuple) -> dict:
    subsets = [s for s in _subsets(frame) if s]
    picked = rng.choice(len(subsets), size=int(rng.integers(1, 5)), replace=False)
    w = rng.dirichlet([1.0] * (len(picked) + 1))
    m = {subsets[int(i)]: float(x) for i, x in zip(picked, w, strict=False)}
    m[frozenset(frame)] = m.get(frozenset(frame), 0.0) + float(w[-1])
    return m


def _mobius_cases() -> list[Case]:
    rng = seeded(141)
    cases = [
        Case("the chapter's m1", (_belief_table(mass(SOURCE1).as_dict()),)),
        Case(
            "a probability (singletons)",
            (_belief_table({frozenset("a"): 0.3, frozenset("b"): 0.7}),),
        ),
        Case("the vacuous mass function", (_belief_table({frozenset("abc"): 1.0}),)),
    ]
    for i in range(3):
        cases.append(Case(f"random {i + 1}", (_belief_table(_random_mass(rng, tuple("abcd"))),)))
    return cases


coding_exercise(
    "belief.mobius-code",
    reference=_mobius_reference,
    cases=_mobius_cases,
    arg_names=("bel",),
    hint="For each A add Bel(B) over the subsets B of A, with the sign (−1)^(|A| − |B|); "
    "keep the non-zero results.",
    mistakes=(
        (
            lambda bel: {a: v for a, v in bel.items() if v},
            "You returned Bel itself: a mass is what Bel(A) adds beyond the beliefs of A's "
            "proper subsets.",
        ),
        (
            lambda bel: {
                a: v
                for a in bel
                if abs(
                    v := sum(x for b, x in bel.items() if b <= a and len(b) == len(a) - 1) * -1
                    + bel[a]
                )
                > 1e-12
            },
            "You subtracted only the subsets one element smaller: the inclusion–exclusion "
            "runs over every subset, with alternating signs.",
        ),
    ),
)


def _lower_reference(m: dict, u: dict) -> float:
    frame = tuple(u)
    ev = MassFunction(m, frame)
    return float(expected_utilities(ev, {"act": u}, "maximin")["act"])


def _lower_cases() -> list[Case]:
    rng = seeded(142)
    cases = [
        Case("the chapter's fused evidence, 'wait'", (_fused().as_dict(), dict(UTILITIES["wait"]))),
        Case(
            "a probability: the plain expectation",
            ({frozenset({"low"}): 0.2, frozenset({"ok"}): 0.8}, dict(UTILITIES["fill"])),
        ),
        Case(
            "total ignorance: the worst utility",
            ({frozenset(LEVELS): 1.0}, dict(UTILITIES["drain"])),
        ),
    ]
    for i in range(3):
        m = _random_mass(rng, LEVELS)
        u = {h: float(x) for h, x in zip(LEVELS, rng.normal(0.0, 2.0, 3), strict=True)}
        cases.append(Case(f"random {i + 1}", (m, u)))
    return cases


coding_exercise(
    "belief.lower-code",
    reference=_lower_reference,
    cases=_lower_cases,
    arg_names=("m", "u"),
    hint="Loop over the focal elements: each adds its mass times the smallest utility among "
    "its hypotheses.",
    mistakes=(
        (
            lambda m, u: sum(v * max(u[h] for h in f) for f, v in m.items()),
            "You took each focal element's best utility: that is the upper expectation (maximax).",
        ),
        (
            lambda m, u: sum(v * sum(u[h] for h in f) / len(f) for f, v in m.items()),
            "You shared each mass equally among its hypotheses: that is the pignistic "
            "expectation, not the lower one.",
        ),
    ),
)
