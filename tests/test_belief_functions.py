"""Belief functions beyond Dempster's rule, checked by hand and against pyds.

Set functions, conditioning, the cautious rule, least commitment and decisions; the peer is
py-dempster-shafer 0.7 (module pyds).
"""

import itertools

import numpy as np
import pyds
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit.errors import EvidenceError, TotalConflictError
from dstoolkit.evidence import (
    MassFunction,
    canonical_weights,
    cautious,
    conditional,
    decide,
    dempster,
    discount_to_nondogmatic,
    expected_utilities,
    from_set_function,
    more_committed,
    set_function,
)

FRAME = tuple("abcd")
# Masses from sums of a handful of products of numbers in [0, 1]: agreement to 1e-12 is
# rounding (two orders of summation), far below any mass these examples give.
TOL = 1e-12


@st.composite
def nondogmatic(draw, frame=FRAME):
    """Draw a random mass function on ``frame`` with m(Θ) ≥ 0.05."""
    n = draw(st.integers(1, 4))
    full = 2 ** len(frame) - 1
    masks = draw(st.lists(st.integers(1, full - 1), min_size=n, max_size=n, unique=True))
    weights = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n + 1, max_size=n + 1)))
    weights /= weights.sum()
    masses = {
        frozenset(h for i, h in enumerate(frame) if (m >> i) & 1): w
        for m, w in zip(masks, weights, strict=False)
    }
    masses[frozenset(frame)] = float(weights[-1])
    return MassFunction(masses, frame)


def random_nondogmatic(rng, frame=FRAME, n=4):
    full = 2 ** len(frame) - 1
    masks = rng.choice(np.arange(1, full), size=n, replace=False)
    w = rng.uniform(0.05, 1.0, n + 1)
    w /= w.sum()
    masses = {
        frozenset(h for i, h in enumerate(frame) if (int(m) >> i) & 1): x
        for m, x in zip(masks, w, strict=False)
    }
    masses[frozenset(frame)] = float(w[-1])
    return MassFunction(masses, frame)


def to_pyds(m):
    return pyds.MassFunction({frozenset(k): v for k, v in m.as_dict().items()})


def subsets(frame):
    for r in range(len(frame) + 1):
        yield from (frozenset(c) for c in itertools.combinations(frame, r))


def mask(frame, s):
    return sum(1 << frame.index(h) for h in s)


def assert_same(m, masses):
    got = m.as_dict()
    # a peer's alternating sums leave rounding-sized masses (below TOL) on sets ours zeroes
    want = {frozenset(k): v for k, v in masses.items() if v > TOL}
    assert set(got) == set(want), (got, want)
    for k, v in want.items():
        assert got[k] == pytest.approx(v, abs=TOL), k


# -- hand-worked examples -------------------------------------------------------------------
def test_set_functions_by_hand():
    m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    bel = set_function(m, "belief")
    pl = set_function(m, "plausibility")
    q = set_function(m, "commonality")
    fr = m.frame
    # Bel({a,b}) = m(a) + m(ab) = 0.5 + 0.3 = 0.8; Bel({b}) = 0 (no focal element inside {b})
    assert bel[mask(fr, "ab")] == pytest.approx(0.8, abs=TOL)
    assert bel[mask(fr, "b")] == 0.0
    # Pl({b}) = m(ab) + m(abc) = 0.3 + 0.2 = 0.5; Pl({c}) = m(abc) = 0.2
    assert pl[mask(fr, "b")] == pytest.approx(0.5, abs=TOL)
    assert pl[mask(fr, "c")] == pytest.approx(0.2, abs=TOL)
    # Q({a}) = m(a) + m(ab) + m(abc) = 1; Q({b}) = 0.3 + 0.2 = 0.5; Q({a,c}) = m(abc) = 0.2
    assert q[mask(fr, "a")] == pytest.approx(1.0, abs=TOL)
    assert q[mask(fr, "b")] == pytest.approx(0.5, abs=TOL)
    assert q[mask(fr, "ac")] == pytest.approx(0.2, abs=TOL)
    assert q[0] == 1.0 and bel[0] == 0.0 and pl[-1] == pytest.approx(1.0, abs=TOL)


def test_conditioning_by_hand():
    m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    # Dempster on {b,c}: {a}∩{b,c} = ∅ loses 0.5; {a,b} → {b} 0.3; Θ → {b,c} 0.2; ÷ Pl = 0.5
    assert_same(conditional(m, "bc"), {"b": 0.6, "bc": 0.4})
    # geometric on {a,b}: keep {a} 0.5 and {a,b} 0.3, ÷ Bel({a,b}) = 0.8: 0.625 and 0.375
    assert_same(conditional(m, "ab", rule="geometric"), {"a": 0.625, "ab": 0.375})
    # geometric on {b,c}: no focal element inside {b,c}, Bel = 0
    with pytest.raises(TotalConflictError, match="Bel"):
        conditional(m, "bc", rule="geometric")


def test_weights_by_hand():
    # m = {a}: 0.3, {a,b}: 0.3, Θ: 0.4 is {a,b}^x ⊙ {a}^y with m(a) = 1 − y = 0.3 (y = 0.7),
    # m(ab) = (1 − x) y = 0.3 (x = 4/7) and m(Θ) = x y = 0.4
    m = MassFunction({"a": 0.3, "ab": 0.3, "abc": 0.4})
    w = canonical_weights(m)
    assert set(w) == {frozenset("a"), frozenset("ab")}
    assert w[frozenset("a")] == pytest.approx(0.7, abs=TOL)
    assert w[frozenset("ab")] == pytest.approx(4 / 7, abs=TOL)


def test_cautious_rule_by_hand():
    frame = tuple("abc")
    m1 = MassFunction({"a": 0.6, "abc": 0.4}, frame)  # w1(a) = 0.4
    m2 = MassFunction({"a": 0.3, "ab": 0.3, "abc": 0.4}, frame)  # w2(a) = 0.7, w2(ab) = 4/7
    # cautious: w(a) = min(0.4, 0.7) = 0.4, w(ab) = min(1, 4/7) = 4/7, so
    # {a}^0.4 ⊙ {a,b}^(4/7): m(a) = 1 − 0.4 = 0.6, m(ab) = 0.4 · 3/7 = 12/70,
    # m(Θ) = 0.4 · 4/7 = 16/70
    assert_same(cautious(m1, m2), {"a": 0.6, "ab": 12 / 70, "abc": 16 / 70})
    # Dempster counts {a} twice: m(a) = 0.6 · 1 + 0.4 · 0.3 = 0.72, m(ab) = 0.4 · 0.3 = 0.12,
    # m(Θ) = 0.4 · 0.4 = 0.16
    assert_same(dempster(m1, m2), {"a": 0.72, "ab": 0.12, "abc": 0.16})


def test_cautious_rule_normalises_by_hand():
    frame = tuple("ab")
    m1 = MassFunction({"a": 0.5, "ab": 0.5}, frame)
    m2 = MassFunction({"b": 0.5, "ab": 0.5}, frame)
    # weights on different sets: {a}^0.5 ⊙ {b}^0.5 gives ∅, a, b, Θ 0.25 each; ÷ 0.75
    assert_same(cautious(m1, m2), {"a": 1 / 3, "b": 1 / 3, "ab": 1 / 3})


def test_least_commitment_by_hand():
    frame = tuple("abc")
    vacuous = MassFunction.vacuous(frame)
    m = MassFunction({"a": 0.5, "abc": 0.5}, frame)
    sharper = MassFunction({"a": 0.8, "abc": 0.2}, frame)
    # Q_m = 1 on ∅, {a}; 0.5 elsewhere; Q_sharper = 0.2 elsewhere ≤ 0.5 ≤ Q_vacuous = 1
    assert more_committed(sharper, m) and more_committed(m, vacuous)
    assert not more_committed(m, sharper) and not more_committed(vacuous, m)
    assert more_committed(sharper, m, ordering="w") and not more_committed(m, sharper, ordering="w")
    # the cautious combination is more committed than both of its operands
    other = MassFunction({"ab": 0.5, "abc": 0.5}, frame)
    both = cautious(m, other)
    assert more_committed(both, m, ordering="w") and more_committed(both, other, ordering="w")


def test_decisions_by_hand():
    m = MassFunction({"a": 0.5, "ab": 0.5})
    u = {"act": {"a": 1.0, "b": 0.0}, "wait": {"a": 0.6, "b": 0.6}}
    # BetP(a) = 0.5 + 0.5/2 = 0.75: E[act] = 0.75 > E[wait] = 0.6
    assert expected_utilities(m, u)["act"] == pytest.approx(0.75, abs=TOL)
    assert decide(m, u, "pignistic") == ("act",)
    # lower expectation of act: 0.5 · 1 + 0.5 · min(1, 0) = 0.5 < 0.6: maximin waits
    assert decide(m, u, "maximin") == ("wait",)
    # upper expectation of act: 0.5 · 1 + 0.5 · max(1, 0) = 1.0 > 0.6: maximax acts
    assert decide(m, u, "maximax") == ("act",)
    # [0.5, 1.0] and [0.6, 0.6] overlap: neither dominates the other
    assert expected_utilities(m, u, "interval")["act"] == pytest.approx((0.5, 1.0), abs=TOL)
    assert decide(m, u, "interval") == ("act", "wait")
    # with m(a) = 0.9, act's interval [0.9, 1.0] lies above wait's 0.6: act dominates
    assert decide(MassFunction({"a": 0.9, "ab": 0.1}), u, "interval") == ("act",)


# -- properties -----------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["mass", "belief", "plausibility", "commonality"])
@pytest.mark.parametrize("seed", range(10))
def test_mobius_round_trip(kind, seed):
    m = random_nondogmatic(np.random.default_rng(seed))
    back = from_set_function(set_function(m, kind), m.frame, kind)
    assert set(back.as_dict()) == set(m.as_dict())
    for k, v in m.as_dict().items():
        assert back.as_dict()[k] == pytest.approx(v, abs=TOL)


@settings(max_examples=40, deadline=None)
@given(nondogmatic())
def test_cautious_rule_is_idempotent(m):
    assert_same(cautious(m, m), m.as_dict())


@settings(max_examples=40, deadline=None)
@given(nondogmatic(), nondogmatic())
def test_cautious_rule_is_commutative(a, b):
    try:
        ab = cautious(a, b)
    except TotalConflictError:
        with pytest.raises(TotalConflictError):
            cautious(b, a)
        return
    assert_same(cautious(b, a), ab.as_dict())


@settings(max_examples=40, deadline=None)
@given(nondogmatic(), nondogmatic(), nondogmatic())
def test_cautious_rule_is_associative(a, b, c):
    # the normalised cautious rule keeps the weights min(w1, w2) of non-empty sets, so both
    # groupings have the weights min(w1, w2, w3): compare their masses (rounding of three
    # Möbius transforms on 16 subsets: well below 1e-9)
    left = cautious(cautious(a, b), c)
    right = cautious(a, cautious(b, c))
    assert set(left.as_dict()) == set(right.as_dict())
    for k, v in left.as_dict().items():
        assert right.as_dict()[k] == pytest.approx(v, abs=1e-9)


# -- against pyds -----------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(20))
def test_set_functions_and_pignistic_equal_pyds(seed):
    m = random_nondogmatic(np.random.default_rng(seed))
    peer = to_pyds(m)
    bel, pl, q = (set_function(m, k) for k in ("belief", "plausibility", "commonality"))
    for s in subsets(m.frame):
        if not s:
            continue
        i = mask(m.frame, s)
        assert bel[i] == pytest.approx(peer.bel(s), abs=TOL)
        assert pl[i] == pytest.approx(peer.pl(s), abs=TOL)
        assert q[i] == pytest.approx(peer.q(s), abs=TOL)
    betp = peer.pignistic()
    for h, p in m.pignistic().items():
        assert p == pytest.approx(betp[frozenset([h])], abs=TOL)


@pytest.mark.parametrize("seed", range(20))
def test_combination_conditioning_and_weights_equal_pyds(seed):
    rng = np.random.default_rng(100 + seed)
    a, b = random_nondogmatic(rng), random_nondogmatic(rng)
    pa, pb = to_pyds(a), to_pyds(b)
    assert_same(dempster(a, b), dict(pa.combine_conjunctive(pb)))
    # the cautious combination has weights min(w1, w2) on every non-empty A ≠ Θ (pyds's
    # weights; ratios of products of commonalities: relative 1e-9 is rounding)
    w1, w2, w12 = pa.weight_function(), pb.weight_function(), canonical_weights(cautious(a, b))
    for s in w1:
        if s:
            assert w12.get(s, 1.0) == pytest.approx(min(w1[s], w2[s]), rel=1e-9)
    event = frozenset("bc")
    assert_same(conditional(a, event), dict(pa.condition(event)))
    peer_w = pa.weight_function()
    ours = canonical_weights(a)
    for s, w in peer_w.items():
        assert ours.get(s, 1.0) == pytest.approx(w, rel=1e-9)  # ratios of products of Q


def separable(rng, frame=FRAME, n=3):
    """Return a ⊕ of n simple mass functions A^w, w in (0, 1), every A holding ``frame[0]``.

    No product is empty, so every weight (w(∅) = 1 included) is at most 1.
    """
    full = 2 ** len(frame) - 1
    out = MassFunction.vacuous(frame)
    for a in rng.choice(np.arange(1, full, 2), size=n, replace=False):
        s = frozenset(h for i, h in enumerate(frame) if (int(a) >> i) & 1)
        w = float(rng.uniform(0.2, 0.9))
        out = dempster(out, MassFunction({s: 1 - w, frozenset(frame): w}, frame))
    return out


@pytest.mark.parametrize("seed", range(20))
def test_cautious_rule_equals_pyds(seed):
    # pyds builds the simple mass functions A^w themselves, so it needs weights at most 1:
    # separable mass functions have them
    rng = np.random.default_rng(300 + seed)
    a, b = separable(rng), separable(rng)
    try:
        ours = cautious(a, b)
    except TotalConflictError:
        pytest.fail("separable inputs with m(Θ) > 0 cannot conflict totally")
    assert_same(ours, dict(peer_cautious(to_pyds(a), to_pyds(b))))


def peer_cautious(pa, pb):
    """Run pyds's combine_cautious, its weights clipped to 1 when rounding puts them above.

    pyds builds each A^w as {Θ: w, A: 1 − w} and refuses 1 − w = −2e-16; the weights of
    separable inputs are at most 1, so anything above is rounding (within 1e-12).
    """
    w1, w2 = pa.weight_function(), pb.weight_function()
    theta = pa.frame()
    out = pyds.MassFunction({theta: 1.0})
    for h in w1:
        w = min(w1[h], w2[h])
        assert w <= 1.0 + 1e-12
        w = min(w, 1.0)
        out = out.combine_conjunctive(
            pyds.MassFunction({theta: w, h: 1.0 - w}), normalization=False
        )
    return out.normalize()


@pytest.mark.parametrize("seed", range(5))
def test_from_set_function_equals_pyds(seed):
    m = random_nondogmatic(np.random.default_rng(200 + seed))
    peer = to_pyds(m)
    assert_same(
        from_set_function(set_function(m, "commonality"), m.frame, "commonality"),
        dict(pyds.MassFunction.from_q(peer.q())),
    )
    assert_same(
        from_set_function(set_function(m, "belief"), m.frame, "belief"),
        dict(pyds.MassFunction.from_bel(peer.bel())),
    )


# -- bad input --------------------------------------------------------------------------------
def test_bad_input_is_refused():
    m = MassFunction({"a": 0.6, "b": 0.4})
    with pytest.raises(EvidenceError, match="dogmatic"):
        cautious(m, m)
    with pytest.raises(EvidenceError, match="dogmatic"):
        canonical_weights(m)
    fixed = discount_to_nondogmatic(m, 0.1)
    assert fixed.mass_of("ab") == pytest.approx(0.1, abs=TOL)
    assert discount_to_nondogmatic(fixed) is fixed
    with pytest.raises(EvidenceError, match="rate"):
        discount_to_nondogmatic(m, 0.0)
    with pytest.raises(EvidenceError, match="frames differ"):
        cautious(fixed, MassFunction.vacuous("abc"))
    with pytest.raises(EvidenceError, match="MassFunction"):
        set_function({"a": 1.0})
    with pytest.raises(EvidenceError, match="kind"):
        set_function(m, "doubt")
    with pytest.raises(EvidenceError, match="4 finite numbers"):
        from_set_function([0.0, 0.5], "ab")
    with pytest.raises(EvidenceError, match="not those of a mass function"):
        from_set_function([0.0, 0.9, 0.9, 1.0], "ab")  # m(ab) = 1 − 0.9 − 0.9 < 0
    with pytest.raises(EvidenceError, match="summing"):
        from_set_function([0.0, 0.2, 0.2, 0.5], "ab")
    with pytest.raises(EvidenceError, match="rule"):
        conditional(m, "a", rule="jeffrey")
    with pytest.raises(EvidenceError, match="ordering"):
        more_committed(m, m, ordering="z")
    with pytest.raises(EvidenceError, match="hypothesis of the frame"):
        expected_utilities(m, {"act": {"a": 1.0}})
    with pytest.raises(EvidenceError, match="criterion"):
        decide(m, {"act": {"a": 1.0, "b": 0.0}}, "hurwicz")
    with pytest.raises(EvidenceError, match="finite"):
        expected_utilities(m, {"act": {"a": float("nan"), "b": 0.0}})
    with pytest.raises(EvidenceError, match="hypotheses"):
        set_function(MassFunction.vacuous(range(21)))


def test_cautious_rule_keeps_a_small_kept_mass():
    eps = 1e-12
    m1 = MassFunction({"a": 1 - eps, "ab": eps}, "ab")  # {a}^ε
    m2 = MassFunction({"b": 1 - eps, "ab": eps}, "ab")  # {b}^ε
    # {a}^ε ⊙ {b}^ε: ∅ (1 − ε)², {a} and {b} ε(1 − ε) each, Θ ε²; kept 2ε(1 − ε) + ε²,
    # so {a} and {b} get (1 − ε)/(2 − ε) ≈ 1/2 each: not 1 − m(∅), which cancels to noise
    m = cautious(m1, m2)
    assert m.mass_of("a") == pytest.approx(0.5, abs=1e-9)  # 1/2 − (1−ε)/(2−ε) ≈ ε/4
    assert m.mass_of("b") == pytest.approx(0.5, abs=1e-9)
