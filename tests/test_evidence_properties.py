"""Property tests (hypothesis) on random evidence of both kinds."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dstoolkit import (
    IntervalEvidence,
    MassFunction,
    TotalConflictError,
    combine_dependent,
    dempster,
    dependence,
    energy,
)

FRAME = tuple("abcde")
GRID = np.linspace(0.0, 1.0, 9)  # interval ends on a grid of 9 points


@st.composite
def mass_functions(draw, frame=FRAME):
    n = draw(st.integers(1, 5))
    masks = draw(st.lists(st.integers(1, 2 ** len(frame) - 1), min_size=n, max_size=n, unique=True))
    weights = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    weights /= weights.sum()
    return MassFunction(
        {
            frozenset(h for i, h in enumerate(frame) if (m >> i) & 1): w
            for m, w in zip(masks, weights, strict=True)
        },
        frame,
    )


@st.composite
def grid_evidence(draw):
    """Interval evidence with ends on GRID, returned with its grid-index pairs."""
    n = draw(st.integers(1, 5))
    pairs = []
    for _ in range(n):
        i = draw(st.integers(0, GRID.size - 1))
        j = draw(st.integers(i, GRID.size - 1))
        pairs.append((i, j))
    weights = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    weights /= weights.sum()
    idx = np.array(pairs)
    return IntervalEvidence(GRID[idx[:, 0]], GRID[idx[:, 1]], weights), idx, weights


def to_finite(idx, weights):
    """Return the same evidence on the finite frame of grid points."""
    frame = tuple(range(GRID.size))
    masses: dict[frozenset, float] = {}
    for (i, j), w in zip(idx, weights, strict=True):
        key = frozenset(range(i, j + 1))
        masses[key] = masses.get(key, 0.0) + w
    return MassFunction(masses, frame)


@st.composite
def interval_evidence(draw):
    n = draw(st.integers(1, 6))
    lo = np.array(draw(st.lists(st.floats(-5, 5), min_size=n, max_size=n)))
    width = np.array(draw(st.lists(st.floats(0.01, 10), min_size=n, max_size=n)))
    weights = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    return IntervalEvidence(lo, lo + width, weights / weights.sum())


def safe_dempster(a, b):
    try:
        return dempster(a, b)
    except TotalConflictError:
        return None


def same(a, b):
    da = {k: v for k, v in a.as_dict().items()}
    db = {k: v for k, v in b.as_dict().items()}
    assert da.keys() == db.keys()
    for k in da:
        assert da[k] == pytest.approx(db[k], abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(mass_functions(), mass_functions())
def test_dempster_commutative_and_normalised(a, b):
    ab, ba = safe_dempster(a, b), safe_dempster(b, a)
    assert (ab is None) == (ba is None)
    if ab is not None:
        same(ab, ba)
        assert ab.mass.sum() == pytest.approx(1.0, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(mass_functions(), mass_functions(), mass_functions())
def test_dempster_associative(a, b, c):
    ab = safe_dempster(a, b)
    bc = safe_dempster(b, c)
    left = safe_dempster(ab, c) if ab is not None else None
    right = safe_dempster(a, bc) if bc is not None else None
    if left is not None and right is not None:
        same(left, right)
    else:
        # total conflict on one side implies total conflict of the triple on the other
        assert left is None and right is None


@settings(max_examples=60, deadline=None)
@given(mass_functions())
def test_vacuous_is_neutral_finite(a):
    same(dempster(a, MassFunction.vacuous(FRAME)), a)


@settings(max_examples=60, deadline=None)
@given(interval_evidence())
def test_vacuous_is_neutral_intervals(a):
    lo, hi = a.hull()
    v = IntervalEvidence.vacuous(lo - 1, hi + 1)
    c = dempster(a, v)
    np.testing.assert_allclose(c.to_rows(), a.to_rows())


@settings(max_examples=80, deadline=None)
@given(st.one_of(mass_functions(), interval_evidence()))
def test_energy_in_unit_interval(a):
    assert 0.0 <= energy(a) <= 1.0 + 1e-12


@settings(max_examples=80, deadline=None)
@given(
    st.one_of(
        st.tuples(mass_functions(), mass_functions()),
        st.tuples(interval_evidence(), interval_evidence()),
    )
)
def test_dependency_coefficients_in_range(pair):
    a, b = pair
    dep = dependence(a, b)
    assert dep.degree >= 0
    assert 0.0 < dep.r12 <= 1.0
    assert 0.0 < dep.r21 <= 1.0


@settings(max_examples=60, deadline=None)
@given(interval_evidence(), interval_evidence())
def test_no_common_focal_element_means_plain_dempster(a, b):
    b = b.shift(1e-3)  # make equal focal elements practically impossible
    if dependence(a, b).joint_energy > 0:
        return
    try:
        expected = dempster(a, b)
    except TotalConflictError:
        with pytest.raises(TotalConflictError):
            combine_dependent(a, b)
        return
    got = combine_dependent(a, b)
    np.testing.assert_allclose(got.to_rows(), expected.to_rows(), atol=1e-12)
    assert got.mass.sum() == pytest.approx(1.0, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(mass_functions(), mass_functions())
def test_dependent_combination_sums_to_one_finite(a, b):
    try:
        c = combine_dependent(a, b)
    except TotalConflictError:
        return
    assert c.mass.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.all(c.mass > 0)


@settings(max_examples=80, deadline=None)
@given(grid_evidence(), grid_evidence())
def test_intervals_on_grid_agree_with_finite_frame(ga, gb):
    (a, ia, wa), (b, ib, wb) = ga, gb
    fa, fb = to_finite(ia, wa), to_finite(ib, wb)
    for i, j in itertools.combinations_with_replacement(range(0, GRID.size, 2), 2):
        subset = frozenset(range(i, j + 1))
        assert a.belief(GRID[i], GRID[j]) == pytest.approx(fa.belief(subset), abs=1e-12)
        assert a.plausibility(GRID[i], GRID[j]) == pytest.approx(fa.plausibility(subset), abs=1e-12)
    ci, cf = safe_dempster(a, b), safe_dempster(fa, fb)
    assert (ci is None) == (cf is None)
    if ci is None:
        return
    as_sets = {}
    for lo, hi, m in ci.to_rows():
        key = frozenset(np.flatnonzero((GRID >= lo - 1e-12) & (GRID <= hi + 1e-12)).tolist())
        as_sets[key] = as_sets.get(key, 0.0) + m
    finite = cf.as_dict()
    assert as_sets.keys() == finite.keys()
    for k, v in finite.items():
        assert as_sets[k] == pytest.approx(v, abs=1e-9)
