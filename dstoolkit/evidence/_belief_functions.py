"""Belief functions beyond Dempster's rule, on finite frames.

The set functions of a mass function (belief, plausibility, commonality) as arrays over all
2^|Θ| subsets and the Möbius inversion back to a mass; Dempster's and geometric
conditioning; the canonical decomposition into simple mass functions and its weights
(Denœux 2008); the cautious rule for non-distinct evidence; the least-commitment
orderings; and decisions with belief functions (pignistic, maximin, maximax, interval
dominance). A subset is its bit mask, bit i standing for the frame's i-th hypothesis, as in
:class:`~dstoolkit.evidence.MassFunction`.

References
----------
T. Denœux, "Conjunctive and disjunctive combination of belief functions induced by
nondistinct bodies of evidence", Artificial Intelligence 172 (2008) 234–264.
P. Smets, "Decision making in the TBM: the necessity of the pignistic transformation",
International Journal of Approximate Reasoning 38 (2005) 133–147.
G. Shafer, *A Mathematical Theory of Evidence*, Princeton University Press (1976).
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping
from typing import Any, Literal

import numpy as np

from dstoolkit.errors import EvidenceError, TotalConflictError
from dstoolkit.utils.checks import real_number

from ._combination import discount
from ._finite_frame import MassFunction

#: The largest frame whose set functions (2^|Θ| numbers each) this module builds.
MAX_SET_FUNCTION_FRAME = 20

#: Masses from a Möbius inversion within this of 0 are rounding (alternating sums of up to
#: 2^20 terms of size at most 1 lose about 1e-12); they are set to 0, and a mass below
#: minus this is a set function that no mass function has.
MOBIUS_TOLERANCE = 1e-9

#: Two commonalities, weights or expected utilities closer than this count as equal in the
#: orderings and decisions (so that no decision rests on the last bits of a float).
COMPARE_TOLERANCE = 1e-9

#: The set functions :func:`set_function` and :func:`from_set_function` know.
SetFunction = Literal["mass", "belief", "plausibility", "commonality"]
SET_FUNCTIONS: tuple[str, ...] = ("mass", "belief", "plausibility", "commonality")
#: The conditioning rules of :func:`conditional`.
CONDITIONING_RULES: tuple[str, ...] = ("dempster", "geometric")
#: The decision criteria of :func:`expected_utilities` and :func:`decide`.
CRITERIA: tuple[str, ...] = ("pignistic", "maximin", "maximax", "interval")


def _check_mass_function(m: object, name: str = "the mass function") -> MassFunction:
    if not isinstance(m, MassFunction):
        raise EvidenceError(
            f"{name} must be a MassFunction on a finite frame, got {type(m).__name__}; "
            "interval evidence has no finite power set (discretise it on cells first)"
        )
    if len(m.frame) > MAX_SET_FUNCTION_FRAME:
        raise EvidenceError(
            f"{name} lives on a frame of {len(m.frame)} hypotheses: its set functions would "
            f"hold 2^{len(m.frame)} numbers; coarsen the frame to at most "
            f"{MAX_SET_FUNCTION_FRAME} hypotheses"
        )
    return m


def _superset_sum(values: np.ndarray, n: int, sign: float = 1.0) -> np.ndarray:
    """f(A) = Σ_{B ⊇ A} sign^{|B∖A|} values(B), one bit at a time (fast zeta/Möbius)."""
    out = np.array(values, dtype=float)
    for i in range(n):
        view = out.reshape(-1, 2, 1 << i)
        view[:, 0, :] += sign * view[:, 1, :]
    return out


def _subset_sum(values: np.ndarray, n: int, sign: float = 1.0) -> np.ndarray:
    """f(A) = Σ_{B ⊆ A} sign^{|A∖B|} values(B), one bit at a time."""
    out = np.array(values, dtype=float)
    for i in range(n):
        view = out.reshape(-1, 2, 1 << i)
        view[:, 1, :] += sign * view[:, 0, :]
    return out


def _mass_vector(m: MassFunction) -> np.ndarray:
    vec = np.zeros(1 << len(m.frame))
    np.add.at(vec, m._focal.astype(np.int64), m._mass)
    return vec


def set_function(m: MassFunction, kind: SetFunction = "belief") -> np.ndarray:
    """Return m, Bel, Pl or Q on every subset of the frame, indexed by bit mask.

    Bel(A) = Σ_{B ⊆ A} m(B) and Pl(A) = Σ_{B ∩ A ≠ ∅} m(B) (the paper's Def. 3);
    Q(A) = Σ_{B ⊇ A} m(B), the commonality (Shafer 1976, ch. 2), with Q(∅) = 1.

    Parameters
    ----------
    m : MassFunction
        On a frame of at most :data:`MAX_SET_FUNCTION_FRAME` hypotheses.
    kind : {"mass", "belief", "plausibility", "commonality"}
        Which set function.

    Returns
    -------
    numpy.ndarray, shape (2^|Θ|,)
        Entry ``a`` is the function's value on the subset with bit mask ``a``.

    Raises
    ------
    EvidenceError
        For something other than a MassFunction, a frame too large, or an unknown kind.

    See Also
    --------
    from_set_function : the Möbius inversion back to the mass.

    References
    ----------
    G. Shafer (1976), *A Mathematical Theory of Evidence*, ch. 2; the paper's Def. 3.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    >>> set_function(m, "commonality").round(3).tolist()
    [1.0, 1.0, 0.5, 0.5, 0.2, 0.2, 0.2, 0.2]
    """
    m = _check_mass_function(m)
    n = len(m.frame)
    vec = _mass_vector(m)
    if kind == "mass":
        return vec
    if kind == "belief":
        return _subset_sum(vec, n)
    if kind == "commonality":
        return _superset_sum(vec, n)
    if kind == "plausibility":
        bel = _subset_sum(vec, n)
        full = (1 << n) - 1
        return 1.0 - bel[full ^ np.arange(1 << n)]
    raise EvidenceError(f"kind must be one of {SET_FUNCTIONS}, got {kind!r}")


def from_set_function(
    values: Any, frame: Iterable[Hashable], kind: SetFunction = "belief"
) -> MassFunction:
    """Recover the mass function from its belief, plausibility or commonality (Möbius inversion).

    m(A) = Σ_{B ⊆ A} (−1)^{|A∖B|} Bel(B), Bel(A) = 1 − Pl(Θ∖A), and
    m(A) = Σ_{B ⊇ A} (−1)^{|B∖A|} Q(B).

    Parameters
    ----------
    values : array_like
        The set function, 2^|Θ| values: entry ``a`` its value on the subset with bit
        mask ``a``.
    frame : iterable of hashable
        Θ, whose i-th hypothesis is bit i.
    kind : {"mass", "belief", "plausibility", "commonality"}
        Which set function ``values`` is.

    Returns
    -------
    MassFunction
        The mass function whose set function ``values`` is.

    Raises
    ------
    EvidenceError
        For values of the wrong length or not finite, or values that no mass function has
        (a negative mass, mass on ∅, masses not summing to 1).

    See Also
    --------
    set_function : the other way.

    References
    ----------
    G. Shafer (1976), *A Mathematical Theory of Evidence*, ch. 2.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    >>> from_set_function(set_function(m, "commonality"), m.frame, "commonality")
    MassFunction({a}: 0.5, {a, b}: 0.3, {a, b, c}: 0.2)
    """
    frame = tuple(frame)
    probe = MassFunction.vacuous(frame)  # checks the frame
    _check_mass_function(probe, "the frame's mass function")
    n = len(frame)
    try:
        vec = np.asarray(values, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise EvidenceError(f"values must be an array of numbers: {exc}") from None
    if vec.size != 1 << n or not np.all(np.isfinite(vec)):
        raise EvidenceError(
            f"values must be {1 << n} finite numbers (one per subset of a frame of {n}), got "
            f"{vec.size} (finite: {bool(np.all(np.isfinite(vec)))})"
        )
    if kind == "mass":
        mass = vec
    elif kind == "belief":
        mass = _subset_sum(vec, n, -1.0)
    elif kind == "plausibility":
        full = (1 << n) - 1
        mass = _subset_sum(1.0 - vec[full ^ np.arange(1 << n)], n, -1.0)
    elif kind == "commonality":
        mass = _superset_sum(vec, n, -1.0)
    else:
        raise EvidenceError(f"kind must be one of {SET_FUNCTIONS}, got {kind!r}")
    return _mass_from_vector(mass, probe, f"these {kind} values")


def _mass_from_vector(mass: np.ndarray, probe: MassFunction, what: str) -> MassFunction:
    mass = np.where(np.abs(mass) <= MOBIUS_TOLERANCE, 0.0, mass)
    if mass.min() < 0.0 or mass[0] != 0.0:
        worst = int(np.argmin(mass)) if mass.min() < 0.0 else 0
        raise EvidenceError(
            f"{what} are not those of a mass function: the Möbius inversion gives mass "
            f"{mass[worst]:.3g} to the subset with bit mask {worst}; check the values (a "
            "belief function is ∞-monotone, Bel(∅) = 0 and Bel(Θ) = 1)"
        )
    focal = np.flatnonzero(mass)
    if not focal.size or abs(mass.sum() - 1.0) > MOBIUS_TOLERANCE:
        raise EvidenceError(f"{what} give masses summing to {mass.sum():.6g}, not 1")
    kept = mass[focal] / mass[focal].sum()
    return probe._with(focal.astype(np.uint64), kept)


def conditional(m: MassFunction, subset: Any, *, rule: str = "dempster") -> MassFunction:
    """Condition m on the event A by Dempster's rule or geometrically.

    Dempster's conditioning transfers each m(B) to B ∩ A and renormalises by Pl(A):
    Bel(C | A) = (Bel(C ∪ Ā) − Bel(Ā)) / Pl(A). Geometric conditioning keeps only the
    focal elements inside A: m(B | A) = m(B)/Bel(A) for B ⊆ A, so Bel(C | A) =
    Bel(C ∩ A)/Bel(A).

    Parameters
    ----------
    m : MassFunction
        The evidence.
    subset : iterable of hypotheses, or a single hypothesis
        A, the event learnt for sure.
    rule : {"dempster", "geometric"}
        The conditioning rule.

    Returns
    -------
    MassFunction
        m(· | A).

    Raises
    ------
    TotalConflictError
        When Pl(A) = 0 (Dempster's) or Bel(A) = 0 (geometric): nothing supports A.
    EvidenceError
        For an unknown rule or A outside the frame.

    References
    ----------
    G. Shafer (1976), ch. 3; P. Suppes and M. Zanotti, "On using random relations to
    generate upper and lower probabilities", Synthese 36 (1977) 427–440 (geometric).

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    >>> conditional(m, "bc").as_dict() == {frozenset("b"): 0.6, frozenset("bc"): 0.4}
    True
    >>> conditional(m, "ab", rule="geometric")
    MassFunction({a}: 0.625, {a, b}: 0.375)
    """
    _check_mass_function(m)
    if rule == "dempster":
        return m.condition(subset)
    if rule != "geometric":
        raise EvidenceError(f"rule must be one of {CONDITIONING_RULES}, got {rule!r}")
    a = m._query(subset)[0]
    inside = (m._focal & ~a) == 0
    if not inside.any():
        raise TotalConflictError(
            f"no focal element lies inside {set(m._decode(a))!r}: Bel(A) = 0, so geometric "
            "conditioning on A is undefined; condition by Dempster's rule or on a larger A"
        )
    kept = m._mass[inside]
    return m._with(m._focal[inside], kept / kept.sum())


def _log_weights(m: MassFunction) -> np.ndarray:
    """Return g(A) = Σ_{B ⊇ A} (−1)^{|B∖A|} ln Q(B), so that ln w(A) = −g(A) for A ≠ Θ."""
    if m.mass_of(frozenset(m.frame)) <= 0.0:
        raise EvidenceError(
            f"{m!r} is dogmatic (m(Θ) = 0): some commonality is 0 and its weights are not "
            "defined; discount it first (discount_to_nondogmatic)"
        )
    q = set_function(m, "commonality")
    return _superset_sum(np.log(q), len(m.frame), -1.0)


def canonical_weights(m: MassFunction) -> dict[frozenset, float]:
    """Return the weights w(A) of the canonical conjunctive decomposition m = ⊙_{A ≠ Θ} A^{w(A)}.

    A^w is the simple mass function m(A) = 1 − w, m(Θ) = w; w(A) > 1 makes it a
    "generalised" one. ln w(A) = −Σ_{B ⊇ A} (−1)^{|B∖A|} ln Q(B) (Denœux 2008, eq. 12),
    defined when m is non-dogmatic (m(Θ) > 0).

    Parameters
    ----------
    m : MassFunction
        A non-dogmatic mass function.

    Returns
    -------
    dict of frozenset to float
        w(A) for every A ≠ Θ (the empty set included) whose weight is not 1.

    Raises
    ------
    EvidenceError
        When m(Θ) = 0 (use :func:`discount_to_nondogmatic`).

    See Also
    --------
    cautious : combines two mass functions weight by weight.

    References
    ----------
    T. Denœux (2008), Artificial Intelligence 172, 234–264, §3.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "abc": 0.5})
    >>> canonical_weights(m) == {frozenset("a"): 0.5}
    True
    """
    m = _check_mass_function(m)
    g = _log_weights(m)
    w = np.exp(-g[:-1])
    keep = np.flatnonzero(np.abs(w - 1.0) > COMPARE_TOLERANCE)
    return {m._decode(int(a)): float(w[a]) for a in keep}


def discount_to_nondogmatic(m: MassFunction, rate: float = 0.01) -> MassFunction:
    """Return m if m(Θ) > 0, else m discounted at ``rate`` (eqs. 9–10) so that m(Θ) = rate.

    The cautious rule and the weights need non-dogmatic mass functions.

    Parameters
    ----------
    m : MassFunction
        The evidence.
    rate : float in (0, 1]
        The discount rate used when m(Θ) = 0.

    Returns
    -------
    MassFunction
        A non-dogmatic mass function.

    Raises
    ------
    EvidenceError
        For a rate outside (0, 1].

    References
    ----------
    The paper's eqs. (9)–(10); T. Denœux (2008), §3.

    Examples
    --------
    >>> discount_to_nondogmatic(MassFunction({"a": 0.6, "b": 0.4}), 0.1)
    MassFunction({a}: 0.54, {b}: 0.36, {a, b}: 0.1)
    """
    m = _check_mass_function(m)
    rate = real_number(rate, "rate", low=0.0, high=1.0, low_open=True, error=EvidenceError)
    if m.mass_of(frozenset(m.frame)) > 0.0:
        return m
    return discount(m, rate)


def cautious(a: MassFunction, b: MassFunction) -> MassFunction:
    """Combine non-distinct evidence by the cautious rule: w(A) = min(w1(A), w2(A)).

    The result is the conjunctive combination ⊙_{A ≠ Θ} A^{min(w1(A), w2(A))},
    normalised (mass on ∅ shared out as in Dempster's rule). It is idempotent (a ∧ a = a),
    commutative and associative, and the w-least committed mass function more committed
    than both a and b: it counts evidence the two share once.

    Parameters
    ----------
    a, b : MassFunction
        Non-dogmatic mass functions on the same frame.

    Returns
    -------
    MassFunction
        The normalised cautious combination.

    Raises
    ------
    EvidenceError
        For dogmatic inputs or different frames.
    TotalConflictError
        When the combination puts all its mass on ∅.

    See Also
    --------
    canonical_weights : the weights.
    dempster : the rule for distinct evidence.

    References
    ----------
    T. Denœux (2008), Artificial Intelligence 172, 234–264, §4 (the rule ∧ and its
    normalised version).

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "abc": 0.5})
    >>> cautious(m, m)
    MassFunction({a}: 0.5, {a, b, c}: 0.5)
    >>> from dstoolkit.evidence import dempster
    >>> dempster(m, m)
    MassFunction({a}: 0.75, {a, b, c}: 0.25)
    """
    _check_mass_function(a, "the first mass function")
    _check_mass_function(b, "the second mass function")
    a._check_same_frame(b)
    n = len(a.frame)
    g = np.maximum(_log_weights(a), _log_weights(b))  # ln w = −g: the smaller weight
    g[-1] = 0.0
    g[-1] = -g.sum()  # Σ_A g(A) = ln Q(∅) = 0
    q = np.exp(_superset_sum(g, n))
    mass = _superset_sum(q, n, -1.0)
    # the masses of non-empty sets come from commonalities no larger than the largest Q of
    # a non-empty set: rounding is relative to it, and the kept mass is their sum (not
    # 1 − m(∅), which would lose a small kept mass to cancellation)
    scale = q[1:].max()
    mass[0] = 0.0
    mass = np.where(np.abs(mass) <= MOBIUS_TOLERANCE * scale, 0.0, mass)
    kept = mass.sum()
    if not kept > 0.0:
        raise TotalConflictError(
            "the cautious combination puts all its mass on ∅: the two bodies of evidence "
            "contradict each other completely"
        )
    return _mass_from_vector(mass / kept, a, "the cautious combination's masses")


def more_committed(a: MassFunction, b: MassFunction, *, ordering: str = "q") -> bool:
    """Whether a is at least as committed as b (a ⊑ b) in the q- or w-ordering.

    q-ordering: Q_a(A) ≤ Q_b(A) for every A (a's focal elements are smaller); w-ordering:
    w_a(A) ≤ w_b(A) for every A ≠ Θ (a is b combined with more simple evidence). The
    least-commitment principle picks, among the mass functions a constraint allows, the
    least committed one. Comparisons allow :data:`COMPARE_TOLERANCE`.

    Parameters
    ----------
    a, b : MassFunction
        On the same frame (non-dogmatic for ``ordering="w"``).
    ordering : {"q", "w"}
        Which ordering.

    Returns
    -------
    bool
        True when a ⊑ b.

    Raises
    ------
    EvidenceError
        For different frames, an unknown ordering, or dogmatic inputs with ``"w"``.

    References
    ----------
    D. Dubois and H. Prade, "A set-theoretic view of belief functions", International
    Journal of General Systems 12 (1986) 193–226; T. Denœux (2008), §2.3.

    Examples
    --------
    >>> m, vacuous = MassFunction({"a": 0.5, "abc": 0.5}), MassFunction.vacuous("abc")
    >>> more_committed(m, vacuous), more_committed(vacuous, m)
    (True, False)
    """
    _check_mass_function(a, "the first mass function")
    _check_mass_function(b, "the second mass function")
    a._check_same_frame(b)
    if ordering == "q":
        fa, fb = set_function(a, "commonality"), set_function(b, "commonality")
    elif ordering == "w":
        fa, fb = -_log_weights(a)[:-1], -_log_weights(b)[:-1]  # ln w: monotone in w
    else:
        raise EvidenceError(f"ordering must be 'q' or 'w', got {ordering!r}")
    return bool(np.all(fa <= fb + COMPARE_TOLERANCE))


def _utility_table(m: MassFunction, utility: Any) -> tuple[list[Hashable], np.ndarray]:
    if not isinstance(utility, Mapping) or not utility:
        raise EvidenceError(
            "utility must be a non-empty mapping {action: {hypothesis: utility}}, got "
            f"{type(utility).__name__}"
        )
    actions = list(utility)
    rows = []
    for act in actions:
        row = utility[act]
        if not isinstance(row, Mapping) or set(row) != set(m.frame):
            raise EvidenceError(
                f"the utilities of action {act!r} must be a mapping with one value for each "
                f"hypothesis of the frame {m.frame!r}"
            )
        rows.append(
            [
                real_number(row[h], f"utility of {act!r} under {h!r}", error=EvidenceError)
                for h in m.frame
            ]
        )
    return actions, np.array(rows, dtype=float)


def expected_utilities(
    m: MassFunction,
    utility: Mapping[Any, Mapping[Any, float]],
    criterion: str = "pignistic",
) -> dict[Any, Any]:
    """Return the expected utility of each action under m, by a criterion.

    ``"pignistic"``: Σ_θ BetP(θ) u(a, θ) (Smets). ``"maximin"``: the lower expectation
    Σ_A m(A) min_{θ∈A} u(a, θ). ``"maximax"``: the upper expectation Σ_A m(A) max_{θ∈A}
    u(a, θ). ``"interval"``: the pair (lower, upper).

    Parameters
    ----------
    m : MassFunction
        The evidence.
    utility : dict
        u(a, θ): for every action a, a dict of the utility of each hypothesis θ of the
        frame.
    criterion : {"pignistic", "maximin", "maximax", "interval"}
        Which expectation.

    Returns
    -------
    dict of action to float, or to (float, float) for ``"interval"``
        The expected utility of each action.

    Raises
    ------
    EvidenceError
        For utilities missing a hypothesis or not finite, or an unknown criterion.

    See Also
    --------
    decide : the chosen action(s).

    References
    ----------
    P. Smets (2005), IJAR 38, 133–147; T. Denœux, "Decision-making with belief functions:
    a review", IJAR 109 (2019) 87–110.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.5})
    >>> u = {"act": {"a": 1.0, "b": 0.0}, "wait": {"a": 0.6, "b": 0.6}}
    >>> expected_utilities(m, u, "interval")
    {'act': (0.5, 1.0), 'wait': (0.6, 0.6)}
    """
    _check_mass_function(m)
    if criterion not in CRITERIA:
        raise EvidenceError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    actions, table = _utility_table(m, utility)
    bits = ((m._focal[:, None] >> np.arange(len(m.frame), dtype=np.uint64)) & 1).astype(bool)
    if criterion == "pignistic":
        betp = np.array(list(m.pignistic().values()))
        values = table @ betp
        return {a: float(v) for a, v in zip(actions, values, strict=True)}
    lows = np.where(bits[None], table[:, None, :], np.inf).min(axis=2) @ m._mass
    highs = np.where(bits[None], table[:, None, :], -np.inf).max(axis=2) @ m._mass
    if criterion == "maximin":
        return {a: float(v) for a, v in zip(actions, lows, strict=True)}
    if criterion == "maximax":
        return {a: float(v) for a, v in zip(actions, highs, strict=True)}
    return {a: (float(lo), float(hi)) for a, lo, hi in zip(actions, lows, highs, strict=True)}


def decide(
    m: MassFunction,
    utility: Mapping[Any, Mapping[Any, float]],
    criterion: str = "pignistic",
) -> tuple[Hashable, ...]:
    """Return the action(s) a criterion chooses under m.

    ``"pignistic"``, ``"maximin"``, ``"maximax"``: the actions of greatest expected utility
    (:func:`expected_utilities`), all of them when several tie within
    :data:`COMPARE_TOLERANCE`. ``"interval"``: interval dominance keeps every action whose
    upper expectation is not below another action's lower expectation: a set of
    undominated actions, which may hold more than one when the evidence cannot tell.

    Parameters
    ----------
    m : MassFunction
        The evidence.
    utility : dict
        u(a, θ): for every action a, a dict of the utility of each hypothesis θ.
    criterion : {"pignistic", "maximin", "maximax", "interval"}
        The criterion.

    Returns
    -------
    tuple of action
        The chosen actions, in the order of ``utility``.

    Raises
    ------
    EvidenceError
        As :func:`expected_utilities` raises.

    References
    ----------
    T. Denœux (2019), IJAR 109, 87–110, §3.

    Examples
    --------
    >>> m = MassFunction({"a": 0.5, "ab": 0.5})
    >>> u = {"act": {"a": 1.0, "b": 0.0}, "wait": {"a": 0.6, "b": 0.6}}
    >>> decide(m, u, "pignistic"), decide(m, u, "maximin"), decide(m, u, "interval")
    (('act',), ('wait',), ('act', 'wait'))
    """
    values = expected_utilities(m, utility, criterion)
    if criterion == "interval":
        best_low = max(v[0] for v in values.values())
        return tuple(a for a, v in values.items() if v[1] >= best_low - COMPARE_TOLERANCE)
    best = max(values.values())
    return tuple(a for a, v in values.items() if v >= best - COMPARE_TOLERANCE)
