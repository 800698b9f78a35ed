"""Reference solutions of the coding exercises, written plainly (no dstoolkit inside).

These are what a teacher shows: the instructor sheets print each function's source as the
answer cell, and the check cells run them against dstoolkit in the tests. Each function is
self-contained (helpers it needs are listed in :data:`HELPERS`), with the signature and
docstring the learner's stub starts from; the stub is generated from them.

Evidence on a finite frame is a dict ``{frozenset of hypotheses: mass}``; evidence on
intervals is a list of rows ``(lo, hi, mass)``.
"""

from __future__ import annotations

import itertools
import math


def bel_pl(m, a):
    """Belief and plausibility of the set ``a``.

    m: dict {frozenset: mass}; a: a set of hypotheses. Returns (Bel(a),
    Pl(a)).
    """
    a = frozenset(a)
    bel = sum(mass for focal, mass in m.items() if focal <= a)
    pl = sum(mass for focal, mass in m.items() if focal & a)
    return bel, pl


def pignistic(m):
    """Return the pignistic probability BetP.

    BetP gives each member of a focal element an equal share of its mass. m: dict
    {frozenset: mass}. Returns {hypothesis: probability}.
    """
    betp: dict = {}
    for focal, mass in m.items():
        for h in focal:
            betp[h] = betp.get(h, 0.0) + mass / len(focal)
    return betp


def dempster_rule(m1, m2):
    """Dempster's rule m1 ⊕ m2 (eq. 1).

    Products on intersections, renormalised by 1 − K.

    m1, m2: dicts {frozenset: mass}. Returns the combined dict (no empty set
    in it). Raises ValueError when the sources are in total conflict (K =
    1).
    """
    combined: dict = {}
    k = 0.0
    for (b, mb), (c, mc) in itertools.product(m1.items(), m2.items()):
        meet = b & c
        if meet:
            combined[meet] = combined.get(meet, 0.0) + mb * mc
        else:
            k += mb * mc
    if k >= 1.0 - 1e-12:
        raise ValueError(f"total conflict (K = {k}): Dempster's rule is undefined")
    return {focal: mass / (1.0 - k) for focal, mass in combined.items()}


def discount_rule(m, rate, frame):
    """Discount m at ``rate`` (eqs. 9–10).

    Every mass times (1 − rate), and ``rate`` more on the whole frame Θ. m:
    dict {frozenset: mass}; frame: the set Θ. Returns a dict.
    """
    theta = frozenset(frame)
    out = {focal: (1.0 - rate) * mass for focal, mass in m.items()}
    out[theta] = out.get(theta, 0.0) + rate
    return out


def dependency(m1, m2, frame):
    """Degree of dependence D and dependency coefficients R12, R21 (eqs. 2–8).

    En(E) = Σ m(A)/|A| over the focal elements A ≠ Θ (eq. 2); the energy of
    the intersection sums min(m1(A), m2(A))/|A| over the focal elements A ≠
    Θ common to both (eq. 3); D = 2 En(E1, E2)/(En(E1) + En(E2)); R12 = 1 −
    (D/2) En(E2)/En(E1) and R21 the other way round (eqs. 7–8), both 1 when
    D = 0. Returns (D, R12, R21).
    """
    theta = frozenset(frame)

    def en(m):
        return sum(mass / len(a) for a, mass in m.items() if a != theta)

    joint = sum(min(m1[a], m2[a]) / len(a) for a in m1 if a in m2 and a != theta)
    en1, en2 = en(m1), en(m2)
    d = 2.0 * joint / (en1 + en2) if en1 + en2 > 0 else 0.0
    if d == 0.0:
        return 0.0, 1.0, 1.0
    return d, 1.0 - d / 2 * en2 / en1, 1.0 - d / 2 * en1 / en2


def dependent_rule(m1, m2, frame):
    """Combine dependent evidence (§2.2).

    Discount E1 at rate 1 − R12 and E2 at rate 1 − R21 (decorrelation,
    eqs. 9–10), then apply Dempster's rule (eq. 1).

    m1, m2: dicts {frozenset: mass}; frame: Θ. Returns the combined dict;
    raises ValueError under total conflict. Uses dependency, discount_rule and
    dempster_rule.
    """
    _, r12, r21 = dependency(m1, m2, frame)
    return dempster_rule(discount_rule(m1, 1.0 - r12, frame), discount_rule(m2, 1.0 - r21, frame))


def interval_energy(rows):
    """Return the energy En′ of interval evidence (eq. A1).

    Σ m(A_i) · w_min / w(A_i).

    rows: list of (lo, hi, mass). w(A) = hi − lo is the width, w_min the
    smallest width among the rows. A row of width 0 counts with weight 1 (a
    point is fully specific).
    """
    w_min = min(hi - lo for lo, hi, _ in rows)
    total = 0.0
    for lo, hi, mass in rows:
        width = hi - lo
        total += mass * (1.0 if width == 0 else w_min / width)
    return total


def triangular_rows(lower, mode, upper, p, epsilon):
    """Evidence of a noise with triangular possibility (eqs. 22–26).

    The possibility is triangular on [lower, upper] with its peak at mode.

    The p α-cuts at α = 0, 1/p, …, (p − 1)/p are [lower + α(mode − lower),
    upper − α(upper − mode)], each with mass (1 − ε)/p; if ε > 0, Θ = [mode
    − 100σ, mode + 100σ] with σ = (upper − lower)/6 gets mass ε. Returns
    rows (lo, hi, mass), innermost cut first, Θ last.
    """
    rows = []
    for i in reversed(range(p)):
        alpha = i / p
        lo = lower + alpha * (mode - lower)
        rows.append((lo, upper - alpha * (upper - mode), (1.0 - epsilon) / p))
    if epsilon > 0:
        sigma = (upper - lower) / 6.0
        rows.append((mode - 100 * sigma, mode + 100 * sigma, epsilon))
    return rows


def cdf_bounds(rows, x):
    """Return the p-box of interval evidence at x.

    That is (Bel((−∞, x]), Pl((−∞, x])).

    rows: list of (lo, hi, mass). Bel counts the rows entirely at or left of
    x (hi ≤ x), Pl the rows that reach x or further left (lo ≤ x).
    """
    lower = sum(m for lo, hi, m in rows if hi <= x)
    upper = sum(m for lo, hi, m in rows if lo <= x)
    return lower, upper


def vertex_image(f, lo, hi):
    """Return the image of a box by the vertex method (Prop. 1).

    The image of the box [lo, hi] through f is (min, max) of f over the 2^n
    corners. lo, hi: sequences of n numbers; f takes a list of n numbers and
    returns a number.
    """
    values = [f(list(corner)) for corner in itertools.product(*zip(lo, hi, strict=True))]
    return min(values), max(values)


def product_relation(x1, x2):
    """Return the random relation of two independent marginals (eq. 16).

    Every pair of focal elements gives the box C1 × C2 with mass
    m1(C1)·m2(C2).

    x1, x2: lists of (lo, hi, mass). Returns a dict {((lo1, hi1), (lo2,
    hi2)): mass}.
    """
    return {((l1, h1), (l2, h2)): m1 * m2 for l1, h1, m1 in x1 for l2, h2, m2 in x2}


def bounded_step(box, v, w, z):
    """One step of the bounded-error filter.

    The model is x_{k+1} = x_k + v and g(x) = x = z + w.

    box, v, w: (lo, hi) pairs. Predict [box + v], intersect with what the
    reading allows, [z + w_lo, z + w_hi]. Returns (lo, hi); raises
    ValueError when the two do not meet.
    """
    lo, hi = box[0] + v[0], box[1] + v[1]
    lo, hi = max(lo, z + w[0]), min(hi, z + w[1])
    if lo > hi:
        raise ValueError("the prediction and the reading do not meet")
    return lo, hi


def orders_in_band(length, temperature, band):
    """Return the orders n of the resonances n·c/(2L) that lie in ``band``.

    ``band`` = (f_lo, f_hi), ends included, with c = 331.3 + 0.606·T (the
    paper's law). Returns a list of ints.
    """
    c = 331.3 + 0.606 * temperature
    f_f = c / (2.0 * length)
    return list(range(math.ceil(band[0] / f_f), math.floor(band[1] / f_f) + 1))


def level_from_two_readings(z1, z2, temperature):
    """Return the order of z1 (eq. 43) and the level L (eq. 32).

    n1 = round(z1/(z2 − z1)) and L = n1·c/(2 z1) with c = 331.3 + 0.606·T.
    Returns (n1, L).
    """
    n1 = round(z1 / (z2 - z1))
    return n1, n1 * (331.3 + 0.606 * temperature) / (2.0 * z1)


def triangle_sigma(lower, mode, upper):
    """Return the standard deviation of the triangular density.

    The density is on [lower, upper] with its peak at mode; writing a, b, m
    for the three, its standard deviation is the square root of
    (a² + b² + m² − ab − am − bm)/18.
    """
    a, b, m = lower, upper, mode
    return math.sqrt((a * a + b * b + m * m - a * b - a * m - b * m) / 18.0)


def filter_step(xhat, z, f, g, g_inv, v_rows, w_rows):
    """One step of the paper's filter (Steps 2–6) for a scalar model.

    The model is x_{k+1} = f(x_k) + v_k and g(x_k) = z_k + w_k (eq. 21),
    with f and g increasing.

    xhat: the estimate x̂_k; z: the next reading z_{k+1}; f, g, g_inv:
    functions of one number (g_inv the inverse of g); v_rows, w_rows: E_v
    and E_w of Step 1 as rows (lo, hi, mass). Returns (rows, estimate): the
    final evidence as (lo, hi, mass) and x̂_{k+1}, its pignistic expectation
    (eq. 20). Raises ValueError under total conflict.
    """

    def merged(rows):  # equal focal elements merge, their masses add (eq. 14)
        out: dict = {}
        for lo, hi, m in rows:
            out[(lo, hi)] = out.get((lo, hi), 0.0) + m
        return [(lo, hi, m) for (lo, hi), m in out.items()]

    def dempster(e1, e2):  # eq. 1 on intervals: products on intersections
        kept, k = [], 0.0
        for (l1, h1, m1), (l2, h2, m2) in itertools.product(e1, e2):
            lo, hi = max(l1, l2), min(h1, h2)
            if lo <= hi:
                kept.append((lo, hi, m1 * m2))
            else:
                k += m1 * m2
        if k >= 1.0 - 1e-12:
            raise ValueError("total conflict")
        return [(lo, hi, m / (1.0 - k)) for lo, hi, m in kept]

    def energy(rows):  # eq. A1
        w_min = min(hi - lo for lo, hi, _ in rows)
        return sum(m * (1.0 if hi == lo else w_min / (hi - lo)) for lo, hi, m in rows)

    def discounted(rows, r):  # eqs. A7–A8: rate 1 − r onto Θ = the hull of the rows
        hull = (min(lo for lo, _, _ in rows), max(hi for _, hi, _ in rows))
        return merged([(lo, hi, r * m) for lo, hi, m in rows] + [(*hull, 1.0 - r)])

    # Step 2: state evidence x̂ + V through f, then the noise v once more (eq. 16)
    pred = merged(
        [
            (f(xhat + vl) + ul, f(xhat + vh) + uh, mv * mu)
            for vl, vh, mv in v_rows
            for ul, uh, mu in v_rows
        ]
    )
    # Steps 3-4: g of each predicted box, fused with the reading's evidence z + W
    fused, k = [], 0.0
    for lo, hi, m in pred:
        for wl, wh, mw in w_rows:
            a, b = max(g(lo), z + wl), min(g(hi), z + wh)
            if a <= b:  # Step 5: back through g⁻¹, within the predicted box
                fused.append((max(lo, g_inv(a)), min(hi, g_inv(b)), m * mw))
            else:
                k += m * mw
    if k >= 1.0 - 1e-12:
        raise ValueError("total conflict in Step 4")
    e1 = merged([(lo, hi, m / (1.0 - k)) for lo, hi, m in fused])
    # Step 6: dependence of E1 (mapped back) and E2 (prediction), eqs. A1-A6
    common = {(lo, hi): m for lo, hi, m in pred}
    w_min = min(min(hi - lo for lo, hi, _ in e1), min(hi - lo for lo, hi, _ in pred))
    joint = sum(
        min(m, common[(lo, hi)]) * (1.0 if hi == lo else w_min / (hi - lo))
        for lo, hi, m in e1
        if (lo, hi) in common
    )
    en1, en2 = energy(e1), energy(pred)
    d = 2.0 * joint / (en1 + en2)
    r12, r21 = (1.0 - d / 2 * en2 / en1, 1.0 - d / 2 * en1 / en2) if d > 0 else (1.0, 1.0)
    final = merged(dempster(discounted(e1, r12), discounted(pred, r21)))
    return final, sum(m * (lo + hi) / 2 for lo, hi, m in final)


#: The plain solutions each coding solution calls (shown before it in instructor sheets).
HELPERS: dict[str, tuple[str, ...]] = {
    "dependent_rule": ("dependency", "discount_rule", "dempster_rule"),
}


def unscented_moments(f, mean, var, alpha, beta, kappa):
    """Return the unscented transform's mean and variance of f(x), x of mean and var.

    One dimension (n = 1): lam = alpha²(1 + kappa) − 1, the three sigma
    points mean and mean ± sqrt((1 + lam) var), the mean weights lam/(1 + lam)
    and 1/(2(1 + lam)) twice, the variance weights the same but the centre's
    plus 1 − alpha² + beta. Returns (mean of f, variance of f).
    """
    lam = alpha * alpha * (1.0 + kappa) - 1.0
    spread = math.sqrt((1.0 + lam) * var)
    points = [mean, mean + spread, mean - spread]
    w_mean = [lam / (1.0 + lam), 0.5 / (1.0 + lam), 0.5 / (1.0 + lam)]
    w_var = [w_mean[0] + 1.0 - alpha * alpha + beta, w_mean[1], w_mean[2]]
    images = [f(p) for p in points]
    m = sum(w * y for w, y in zip(w_mean, images, strict=True))
    v = sum(w * (y - m) ** 2 for w, y in zip(w_var, images, strict=True))
    return m, v


def rts_scalar(x, p, a, q):
    """Return the Rauch–Tung–Striebel smoothing of a scalar Kalman filter's run.

    x, p: the filtered estimates and variances (lists of T numbers); the
    model is x_{k+1} = a x_k + v_k with Var v = q. Going backwards from the
    last step: the prediction a x[k] with variance a² p[k] + q, the gain
    J = p[k] a / (a² p[k] + q), then xs[k] = x[k] + J (xs[k+1] − a x[k]) and
    ps[k] = p[k] + J² (ps[k+1] − (a² p[k] + q)). Returns (xs, ps), lists.
    """
    xs, ps = list(x), list(p)
    for k in range(len(x) - 2, -1, -1):
        p_pred = a * a * p[k] + q
        gain = p[k] * a / p_pred
        xs[k] = x[k] + gain * (xs[k + 1] - a * x[k])
        ps[k] = p[k] + gain * gain * (ps[k + 1] - p_pred)
    return xs, ps


def mass_from_belief(bel):
    """Return the mass function whose belief function is ``bel`` (Möbius inversion).

    bel: dict {frozenset: Bel(A)} for every subset A of the frame, the
    empty set included. m(A) = sum over B ⊆ A of (−1)^(|A| − |B|) Bel(B).
    Returns {frozenset: mass} with the non-zero masses (|m| > 1e-12 kept).
    """
    m = {}
    for a in bel:
        value = sum((-1) ** (len(a) - len(b)) * bel_b for b, bel_b in bel.items() if b <= a)
        if abs(value) > 1e-12:
            m[a] = value
    return m


def lower_expectation(m, u):
    """Return the lower expected utility of an action under the evidence m.

    m: dict {frozenset: mass}; u: dict {hypothesis: utility}. Each focal
    element counts with its worst utility: sum of m(A) · min of u over A.
    """
    return sum(mass * min(u[h] for h in focal) for focal, mass in m.items())
