"""One answer per object.

The merged and the unmerged form of one evidence read alike, and copies (pickle, copy,
deepcopy) keep an evidence, or a noise, valid and read-only.
"""

from __future__ import annotations

import copy
import copyreg
import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import dstoolkit.evidence as ev
from dstoolkit.errors import EvidenceError
from dstoolkit.evidence import IntervalEvidence, MassFunction
from dstoolkit.filters import BoundedNoise

#: A few intervals, so that drawn evidence repeats some of them.
POOL = [(0.0, 1.0), (0.0, 2.0), (0.5, 1.5), (1.0, 3.0), (-1.0, 0.5), (2.0, 2.0)]
FRAME = ("a", "b", "c")
COPIERS = {
    "pickle": lambda o: pickle.loads(pickle.dumps(o)),
    "copy": copy.copy,
    "deepcopy": copy.deepcopy,
}


def _weights(draw, n: int) -> np.ndarray:
    w = np.array(draw(st.lists(st.integers(1, 9), min_size=n, max_size=n)), dtype=float)
    return w / w.sum()


@st.composite
def unmerged_intervals(draw) -> IntervalEvidence:
    """Interval evidence kept unmerged, with repeated focal elements."""
    rows = draw(st.lists(st.sampled_from(POOL), min_size=1, max_size=7))
    lo, hi = zip(*rows, strict=True)
    return IntervalEvidence(lo, hi, _weights(draw, len(rows)), merge=False)


@st.composite
def mass_functions(draw) -> MassFunction:
    subsets = draw(st.lists(st.integers(1, 7), min_size=1, max_size=4, unique=True))
    masses = _weights(draw, len(subsets))
    return MassFunction(
        {
            frozenset(h for i, h in enumerate(FRAME) if s >> i & 1): m
            for s, m in zip(subsets, masses, strict=True)
        },
        FRAME,
    )


@st.composite
def unmerged_mass_functions(draw) -> MassFunction:
    """Draw a mass function with repeated focal elements: an unmerged Dempster combination."""
    a, b = draw(mass_functions()), draw(mass_functions())
    try:
        return ev.dempster(a, b, merge=False)
    except ev.TotalConflictError:
        return ev.dempster(a, a, merge=False)


def _table(e) -> dict:
    """{focal element: total mass}, added up by hand from the stored rows."""
    out: dict = {}
    if isinstance(e, MassFunction):
        for f, m in zip(e.focal_elements, e.mass.tolist(), strict=True):
            out[f] = out.get(f, 0.0) + m
    else:
        for lo, hi, m in zip(
            e.boxes_lo.tolist(), e.boxes_hi.tolist(), e.mass.tolist(), strict=True
        ):
            out[(tuple(lo), tuple(hi))] = out.get((tuple(lo), tuple(hi)), 0.0) + m
    return out


def _close(a, b) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _close(a[k], b[k])
    elif isinstance(a, ev.Dependence):
        for name in ("energy1", "energy2", "joint_energy", "degree", "r12", "r21"):
            _close(getattr(a, name), getattr(b, name))
    elif isinstance(a, ev.Evidence):
        _close(_table(a), _table(b))
    elif isinstance(a, tuple | list) and not all(isinstance(x, int | float) for x in a):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _close(x, y)
    elif isinstance(a, tuple | list | np.ndarray):
        np.testing.assert_allclose(
            np.asarray(a, float), np.asarray(b, float), rtol=1e-9, atol=1e-12
        )
    elif isinstance(a, str):
        assert a == b
    else:
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12), (a, b)


def _readers(other):
    """Every public function that reads one evidence (with ``other`` as a partner)."""

    def safe(fn):
        def call(e):
            try:
                return fn(e)
            except ev.TotalConflictError:
                return "total conflict"
            except EvidenceError as exc:
                return f"refused: {exc}"

        return call

    return {
        "repr": repr,
        "energy": ev.energy,
        "len of merged": lambda e: len(e.merged()),
        "dependence with itself": lambda e: ev.dependence(e, e),
        "dependence": safe(lambda e: ev.dependence(e, other)),
        "dependence, m1": safe(lambda e: ev.dependence(e, other, mass_rule="m1")),
        "joint_energy": lambda e: ev.joint_energy(e, other),
        "joint_energy reversed": lambda e: ev.joint_energy(other, e, mass_rule="m2"),
        "conflict": lambda e: ev.conflict(e, other),
        "dempster": safe(lambda e: ev.dempster(e, other)),
        "dempster unmerged": safe(lambda e: ev.dempster(e, other, merge=False)),
        "combine_dependent": safe(lambda e: ev.combine_dependent(e, other)),
        "decorrelate": safe(lambda e: ev.decorrelate(e, other)[:2]),
        "yager": lambda e: ev.yager(e, other),
        "discount": lambda e: ev.discount(e, 0.3),
    }


@settings(max_examples=25, deadline=None)
@given(unmerged_intervals(), unmerged_intervals())
def test_every_reader_of_interval_evidence_ignores_the_merging(e, other):
    merged = e.merged()
    assert len(set(map(tuple, merged.to_rows()[:, :2].tolist()))) == len(merged)
    _close(_table(e), _table(merged))
    readers = {
        **_readers(other),
        "belief": lambda x: x.belief(0.0, 1.5),
        "plausibility": lambda x: x.plausibility(0.5, 1.0),
        "cdf_bounds": lambda x: x.cdf_bounds(np.linspace(-2, 4, 13)),
        "pignistic_expectation": lambda x: x.pignistic_expectation(),
        "hull": lambda x: x.hull(),
    }
    for name, read in readers.items():
        try:
            _close(read(e), read(merged))
        except AssertionError as exc:
            raise AssertionError(f"{name} differs for the unmerged form") from exc


@settings(max_examples=25, deadline=None)
@given(unmerged_mass_functions(), mass_functions())
def test_every_reader_of_a_mass_function_ignores_the_merging(m, other):
    merged = m.merged()
    assert sum(m.as_dict().values()) == pytest.approx(1.0)
    _close(m.as_dict(), _table(m))
    readers = {
        **_readers(other),
        "as_dict": lambda x: x.as_dict(),
        "mass_of": lambda x: [x.mass_of(s) for s in ("a", "ab", "abc", "bc")],
        "belief": lambda x: [x.belief(s) for s in ("a", "ab", "bc")],
        "plausibility": lambda x: [x.plausibility(s) for s in ("a", "c")],
        "commonality": lambda x: [x.commonality(s) for s in ("a", "ab")],
        "pignistic": lambda x: x.pignistic(),
        "condition": lambda x: x.condition("ab") if x.plausibility("ab") > 0 else 0.0,
    }
    for name, read in readers.items():
        try:
            _close(read(m), read(merged))
        except AssertionError as exc:
            raise AssertionError(f"{name} differs for the unmerged form") from exc


def test_the_issue_cases_one_answer():
    m1 = MassFunction({"a": 0.5, "ab": 0.5})
    m2 = MassFunction({"a": 0.5, "ab": 0.5}, frame=m1.frame)
    split = ev.dempster(m1, m2, merge=False)
    assert len(split) == 4  # the products kept in order, as the paper's worked example
    assert split.as_dict() == {frozenset("a"): 0.75, frozenset("ab"): 0.25}
    assert split.mass_of("a") == 0.75 and repr(split) == repr(ev.dempster(m1, m2))
    e = IntervalEvidence([0.0, 0.0], [1.0, 1.0], [0.5, 0.5], merge=False)
    assert ev.dependence(e, e).degree == ev.dependence(e.merged(), e.merged()).degree == 1.0


def test_tuple_hypotheses_of_the_frame_are_hypotheses():
    m = MassFunction({(0, 1): 0.5, 0: 0.3, frozenset({0, 1}): 0.2}, frame=[0, 1, (0, 1)])
    assert m.as_dict() == {frozenset({(0, 1)}): 0.5, frozenset({0}): 0.3, frozenset({0, 1}): 0.2}
    assert m.belief((0, 1)) == 0.5 and m.belief([0, 1]) == pytest.approx(0.5)
    # without that hypothesis in the frame, a tuple is still the set of its members
    assert MassFunction({(0, 1): 1.0}).as_dict() == {frozenset({0, 1}): 1.0}


# -- copies --------------------------------------------------------------------------------
@settings(max_examples=15, deadline=None)
@given(
    st.one_of(
        unmerged_intervals(),
        unmerged_intervals().map(lambda e: e.merged()),
        unmerged_mass_functions(),
        mass_functions(),
    )
)
def test_copies_of_evidence_stay_read_only_and_equal(e):
    for name, copier in COPIERS.items():
        c = copier(e)
        arrays = [c.mass] + ([c.lo, c.hi, c.boxes_lo] if isinstance(c, IntervalEvidence) else [])
        for arr in arrays:
            with pytest.raises(ValueError, match="read-only"):
                arr[0] = 5.0
        assert repr(c) == repr(e) and len(c) == len(e), name
        np.testing.assert_array_equal(c.mass, e.mass)
        _close(_table(c), _table(e))


@pytest.mark.parametrize("copier", list(COPIERS))
def test_copies_of_noise_bounds_stay_read_only_and_valid(copier):
    noise = BoundedNoise([-1.0, -2.0], [0.0, 0.5], [1.0, 2.0])
    c = COPIERS[copier](noise)
    for arr in (c.lower, c.mode, c.upper):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 9.0
    assert c == noise and hash(c) == hash(noise) and c.upper.tolist() == [1.0, 2.0]


class _Plain:
    """Pickles as a plain object of ``cls`` with the attributes ``state`` (no constructor).

    That is what a crafted, or an old, pickle holds.
    """

    def __init__(self, cls: type, state: dict) -> None:
        self.cls, self.state = cls, state

    def __reduce__(self):
        return (copyreg._reconstructor, (self.cls, object, None), self.state)


@pytest.mark.parametrize(
    ("cls", "state", "match"),
    [
        (
            BoundedNoise,
            {"lower": np.array([1.0]), "mode": np.array([0.0]), "upper": np.array([-1.0])},
            "lower <= mode <= upper",
        ),
        (
            IntervalEvidence,
            {"_focal": np.array([[0.0, 1.0], [1.0, 2.0]]), "_mass": np.array([0.7, 0.7])},
            "sum to 1.4",
        ),
        (IntervalEvidence, {"_focal": np.array([[2.0, 1.0]]), "_mass": np.array([1.0])}, "lo > hi"),
        (
            MassFunction,
            {
                "frame": ("a", "b"),
                "_focal": np.array([1, 3], dtype=np.uint64),
                "_mass": np.array([0.7, 0.7]),
            },
            "sum to 1.4",
        ),
        (
            MassFunction,
            {
                "frame": ("a", "b"),
                "_focal": np.array([8], dtype=np.uint64),
                "_mass": np.array([1.0]),
            },
            "bit masks",
        ),
        (MassFunction, {"_mass": np.array([1.0])}, "cannot unpickle"),
    ],
)
def test_a_crafted_pickle_is_checked_like_a_constructor_call(cls, state, match):
    with pytest.raises(EvidenceError, match=match):
        pickle.loads(pickle.dumps(_Plain(cls, state)))


def test_a_plain_pickle_of_valid_attributes_loads_read_only():
    e = pickle.loads(
        pickle.dumps(
            _Plain(
                IntervalEvidence,
                {"_focal": np.array([[0.0, 1.0], [0.0, 1.0]]), "_mass": np.array([0.25, 0.75])},
            )
        )
    )
    assert repr(e) == "IntervalEvidence([0, 1]: 1)"
    with pytest.raises(ValueError, match="read-only"):
        e.mass[0] = 1.0
