"""Hostile input through the public API (hypothesis): random and malformed arguments.

Every call must either return a valid result or raise the package's base error
(:class:`dstoolkit.errors.DstoolkitError`): never another exception, never NaN in an
estimate, never an evidence that the constructor would refuse. Arguments mix sensible
values with NaN, ±inf, ±1e308, zeros, strings, complex numbers, None, ragged lists and
arrays of the wrong shape.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hostile_inputs import valid
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dstoolkit.errors import DstoolkitError
from dstoolkit.evidence import (
    IntervalEvidence,
    MassFunction,
    alpha_cuts,
    combine_dependent,
    conflict,
    decorrelate,
    dempster,
    dependence,
    discount,
    energy,
    joint_energy,
    possibility,
    triangular_evidence,
    yager,
)
from dstoolkit.filters import (
    BoundedErrorFilter,
    BoundedNoise,
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    random_walk,
)
from dstoolkit.gauge import (
    fit_resonance_series,
    gauge_state_space_model,
    level_from_fundamental,
    orders_eq43,
    simulate_gauge,
    speed_of_sound,
)

SETTINGS = settings(
    max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)

# -- hostile values -----------------------------------------------------------------------
numbers = st.one_of(
    st.floats(-10, 10),
    st.sampled_from(
        [0.0, -0.0, 1.0, -1.0, 0.5, math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, 1e-300]
    ),
    st.integers(-5, 5),
)
junk = st.one_of(
    numbers,
    st.sampled_from(["x", "", "1.0", b"\x00", None, 1j, [1, [2, 3]], {"a": 1}, object(), True]),
    st.lists(numbers, max_size=4),
)
vectors = st.one_of(
    st.lists(numbers, min_size=0, max_size=5),
    st.lists(st.lists(numbers, min_size=1, max_size=3), min_size=1, max_size=3),
    junk,
)


def outcome(call: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Return the call's result (checked valid), or None when it raised a DstoolkitError."""
    try:
        result = call(*args, **kwargs)
    except DstoolkitError as exc:
        assert str(exc).strip(), "an error without a message"
        return None
    valid(result)
    return result


# -- sensible evidence to combine with hostile parameters ---------------------------------
@st.composite
def intervals(draw: Any) -> IntervalEvidence:
    n = draw(st.integers(1, 4))
    lo = np.array(draw(st.lists(st.floats(-5, 5), min_size=n, max_size=n)))
    width = np.array(draw(st.lists(st.floats(0, 3), min_size=n, max_size=n)))
    mass = np.array(draw(st.lists(st.floats(0.01, 1), min_size=n, max_size=n)))
    return IntervalEvidence(lo, lo + width, mass / mass.sum())


@st.composite
def mass_functions(draw: Any) -> MassFunction:
    keys = draw(
        st.lists(
            st.sampled_from(["a", "b", "ab", "bc", "abc"]), min_size=1, max_size=4, unique=True
        )
    )
    mass = np.array(draw(st.lists(st.floats(0.01, 1), min_size=len(keys), max_size=len(keys))))
    return MassFunction(dict(zip(keys, mass / mass.sum(), strict=True)), "abc")


# -- evidence -----------------------------------------------------------------------------
@SETTINGS
@given(vectors, vectors, vectors)
def test_interval_evidence_constructor(lo, hi, mass):
    outcome(IntervalEvidence, lo, hi, mass)
    outcome(IntervalEvidence.from_pairs, lo)


@SETTINGS
@given(
    st.dictionaries(
        st.one_of(st.sampled_from(["a", "ab", "", "abc", "z"]), st.tuples(st.sampled_from("ab"))),
        junk,
        max_size=4,
    ),
    st.one_of(st.none(), st.sampled_from(["abc", [[1], 2], (), "a"])),
)
def test_mass_function_constructor(masses, frame):
    outcome(MassFunction, masses, frame)


@SETTINGS
@given(intervals(), intervals(), junk, junk, vectors, st.sampled_from(["min", "m1", "m2", "x"]))
def test_interval_algebra(a, b, rate, energy1, theta, rule):
    for call in (dempster, conflict, yager, combine_dependent, joint_energy, dependence):
        outcome(call, a, b)
    outcome(dependence, a, b, energy1=energy1, mass_rule=rule)
    outcome(combine_dependent, a, b, energy2=energy1)
    outcome(decorrelate, a, b, mass_rule=rule)
    outcome(discount, a, rate)
    outcome(discount, a, 0.5, theta)
    outcome(energy, a)
    outcome(a.shift, rate)
    outcome(a.belief, rate, energy1)
    outcome(a.plausibility, theta, rate)
    outcome(a.cdf_bounds, theta)
    outcome(a.pignistic_expectation)
    outcome(dempster, a, "not evidence")


@SETTINGS
@given(mass_functions(), mass_functions(), junk, junk)
def test_mass_function_algebra(a, b, rate, subset):
    for call in (dempster, conflict, yager, combine_dependent, dependence):
        outcome(call, a, b)
    outcome(discount, a, rate)
    outcome(discount, a, 0.3, subset)
    outcome(a.belief, subset)
    outcome(a.plausibility, subset)
    outcome(a.condition, subset)
    outcome(energy, a)


@SETTINGS
@given(junk, junk, junk, junk, junk, vectors)
def test_possibility_and_noise_evidence(lower, mode, upper, p, epsilon, theta):
    outcome(possibility, theta, lower, mode, upper)
    outcome(alpha_cuts, lower, mode, upper, p)
    outcome(triangular_evidence, lower, mode, upper, p, epsilon)
    outcome(triangular_evidence, -1.0, 0.0, 1.0, 3, 0.05, theta)
    outcome(BoundedNoise, lower, mode, upper)


# -- filters ------------------------------------------------------------------------------
WALK = random_walk(0.1, 0.5)
GAUGE = gauge_state_space_model()
GAUGE_SEQ = simulate_gauge(level_m=4.6, temperature_c=26.5, runs=2, seed=3)
FILTERS = [
    DependentEvidenceFilter(p=2),
    NassreddineFilter(p=2, max_focal=8),
    BoundedErrorFilter(on_inconsistent="reset"),
    KalmanFilter(),
    ParticleFilter(n_particles=50),
]


@pytest.mark.parametrize("flt", FILTERS, ids=[f.name for f in FILTERS])
@settings(
    max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)
@given(z=vectors, u=vectors, hostile_step=st.integers(0, 12), value=numbers)
def test_filters_take_hostile_readings_and_inputs(flt, z, u, hostile_step, value):
    outcome(flt.run, WALK, z)
    outcome(flt.run_batch, WALK, z)
    readings = GAUGE_SEQ.readings[:, :12].astype(float)
    inputs = GAUGE_SEQ.inputs[:, :11].astype(float)
    outcome(flt.run, GAUGE, readings[0], u)
    spoiled = inputs.copy()
    spoiled[0, min(hostile_step, 10)] = value
    outcome(flt.run, GAUGE, readings[0], spoiled[0])
    outcome(flt.run_batch, GAUGE, readings, spoiled)
    bad_z = readings.copy()
    bad_z[1, hostile_step % 12] = value
    outcome(flt.run_batch, GAUGE, bad_z, inputs)
    outcome(flt.run, "not a model", readings[0], inputs[0])


@SETTINGS
@given(junk, junk, junk, vectors)
def test_filter_options(a, b, c, box):
    for make in (
        lambda: DependentEvidenceFilter(p=a, epsilon=b),
        lambda: DependentEvidenceFilter(start=box, on_conflict=c),
        lambda: DependentEvidenceFilter(theta=(box, None), chunk_size=a),
        lambda: NassreddineFilter(max_focal=a, epsilon=b, initial_box=(box, box)),
        lambda: NassreddineFilter(theta=(box, None), on_conflict=c),
        lambda: BoundedErrorFilter(on_inconsistent=c, initial_box=(a, b)),
        lambda: KalmanFilter(initial_box=(box, a)),
        lambda: ParticleFilter(n_particles=a, seed=b, initial_box=box),
    ):
        flt = outcome(make)
        if flt is not None:
            outcome(flt.run, WALK, [0.0, 0.1, 0.2])


# -- gauge --------------------------------------------------------------------------------
@SETTINGS
@given(junk, junk, vectors, vectors)
def test_gauge_functions(a, b, z, steps):
    outcome(speed_of_sound, a)
    outcome(level_from_fundamental, a, b)
    outcome(orders_eq43, z)
    outcome(fit_resonance_series, z, steps)
