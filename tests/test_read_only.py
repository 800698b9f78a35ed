"""Objects hand out read-only arrays: changing one can never change the object."""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit.evidence import IntervalEvidence, MassFunction, dempster, energy
from dstoolkit.filters import LOTKA_VOLTERRA_X0, BoundedNoise
from dstoolkit.gauge import GAUGE_OBS_NOISE, PAPER_CALIBRATION_LEVELS


def test_interval_ends_and_masses_cannot_be_written() -> None:
    e = IntervalEvidence([-0.3, 0.3], [2.6, 1.9], [0.3, 0.7])
    for view in (e.lo_1d, e.hi_1d, e.mass, e.boxes_lo, e.boxes_hi):
        with pytest.raises(ValueError, match="read-only"):
            view[0] = 5.0
    assert e.lo_1d.tolist() == [-0.3, 0.3] and e.hi_1d.tolist() == [2.6, 1.9]
    assert e.mass.tolist() == [0.3, 0.7]


def test_box_evidence_views_are_read_only() -> None:
    e = IntervalEvidence([[0.0, 0.0]], [[1.0, 2.0]], [1.0])
    with pytest.raises(ValueError, match="read-only"):
        e.lo[0, 1] = 3.0
    with pytest.raises(ValueError, match="read-only"):
        e.hi[...] = 0.0
    assert e.hi.tolist() == [[1.0, 2.0]]


def test_results_of_combination_are_read_only_too() -> None:
    a = IntervalEvidence([0.0, 1.0], [2.0, 3.0], [0.5, 0.5])
    combined = dempster(a, a)
    with pytest.raises(ValueError, match="read-only"):
        combined.mass[0] = 1.0


def test_mass_function_masses_cannot_be_written() -> None:
    m = MassFunction({"a": 0.5, "ab": 0.3, "abc": 0.2})
    before = energy(m)
    with pytest.raises(ValueError, match="read-only"):
        m.mass[0] = 1.0
    assert m.mass.tolist() == [0.5, 0.3, 0.2] and energy(m) == before
    # the focal elements are handed out as frozensets
    with pytest.raises(AttributeError):
        m.focal_elements[0].add("c")  # type: ignore[attr-defined]


def test_constructor_input_is_copied_not_frozen() -> None:
    lo = np.array([0.0, 1.0])
    e = IntervalEvidence(lo, [2.0, 3.0], [0.5, 0.5], merge=False)
    lo[0] = -7.0  # the caller's array stays theirs, writable, and the evidence is unchanged
    assert e.lo_1d.tolist() == [0.0, 1.0]


def test_noise_bounds_and_module_constants_are_read_only() -> None:
    given = np.array([-1.0, -2.0])
    noise = BoundedNoise(given, [0.0, 0.0], [1.0, 2.0])
    given[0] = 9.0
    assert noise.lower.tolist() == [-1.0, -2.0]
    for array in (
        noise.lower,
        noise.mode,
        noise.upper,
        GAUGE_OBS_NOISE.lower,
        LOTKA_VOLTERRA_X0,
        PAPER_CALIBRATION_LEVELS,
    ):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 0.0
