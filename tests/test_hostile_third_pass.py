"""Hostile input, third pass: the last silent wrong answers and raw exceptions of the API.

A WAV file with two format chunks, a particle filter whose model contradicts the readings,
model maps that return the wrong shape or not a pair, a step given another filter's state,
masked arrays, axes of a projection that do not exist, a socket as a recording, numbers
beyond a float: each ends in an error of the package's own that says what to do, or (for
a learner's answer) in a "wrong" verdict.
"""

from __future__ import annotations

import dataclasses
import socket
import struct

import numpy as np
import pytest

from answer_key import solution
from dstoolkit.audio import analyze, load_recording
from dstoolkit.errors import (
    EvidenceError,
    InconsistentDataError,
    InvalidInputError,
    RecordingFileError,
)
from dstoolkit.evidence import IntervalEvidence, appendix_pair, cartesian_product, projection
from dstoolkit.filters import (
    BoundedErrorFilter,
    DependentEvidenceFilter,
    KalmanFilter,
    NassreddineFilter,
    ParticleFilter,
    random_walk,
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge
from dstoolkit.teaching import check, set_time_limit
from dstoolkit.utils.checks import real_number, whole_number

GAUGE = gauge_state_space_model()
SEQ = simulate_gauge(level_m=2.6, temperature_c=26.0, seed=0)
FILTERS = [
    DependentEvidenceFilter(p=2),
    NassreddineFilter(p=2, max_focal=8),
    BoundedErrorFilter(),
    KalmanFilter(),
    ParticleFilter(n_particles=200),
]
IDS = [f.name for f in FILTERS]


# -- WAV files -----------------------------------------------------------------------------
def _wav(*chunks: bytes) -> bytes:
    body = b"WAVE" + b"".join(chunks)
    return b"RIFF" + struct.pack("<I", len(body)) + body


def _chunk(tag: bytes, payload: bytes) -> bytes:
    return tag + struct.pack("<I", len(payload)) + payload + b"\0" * (len(payload) % 2)


def _fmt(rate: int) -> bytes:
    return _chunk(b"fmt ", struct.pack("<HHIIHH", 3, 1, rate, rate * 4, 4, 32))


@pytest.mark.parametrize("second_after_data", [False, True], ids=["before", "after"])
def test_a_wav_with_two_fmt_chunks_is_refused_as_ambiguous(tmp_path, second_after_data):
    data = _chunk(b"data", np.zeros(4410, "<f4").tobytes())
    chunks = (
        (_fmt(44100), data, _fmt(44650)) if second_after_data else (_fmt(44100), _fmt(44650), data)
    )
    path = tmp_path / "two-fmt.wav"
    path.write_bytes(_wav(*chunks))
    with pytest.raises(RecordingFileError, match="two fmt chunks.*ambiguous"):
        load_recording(path)


def test_analyze_on_a_socket_is_a_recording_file_error(tmp_path):
    path = tmp_path / "rec.wav"
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(path))
        with pytest.raises(RecordingFileError, match="cannot open"):
            analyze(path)


def test_a_recording_behind_a_symlink_loop_is_a_recording_file_error(tmp_path):
    loop = tmp_path / "loop.wav"
    loop.symlink_to(loop)
    with pytest.raises(RecordingFileError, match="cannot open"):
        load_recording(loop)


# -- the particle filter refuses as the others do ------------------------------------------
CONTRADICTIONS = {
    "f returns inf": lambda x, u: np.full_like(x, np.inf),
    "f is 0": lambda x, u: np.zeros_like(x),
    "a decreasing f declared increasing": lambda x, u: 10.0 - x,
}


@pytest.mark.parametrize("f", CONTRADICTIONS.values(), ids=list(CONTRADICTIONS))
def test_the_particle_filter_refuses_a_model_that_contradicts_every_reading(f):
    model = dataclasses.replace(GAUGE, f=f)
    with pytest.raises(InconsistentDataError, match="on_inconsistent='reset'"):
        ParticleFilter(n_particles=200).run(model, SEQ.readings, SEQ.inputs)
    flt = ParticleFilter(n_particles=200)
    state = flt.initialize(model, SEQ.readings[0])
    with pytest.raises(InconsistentDataError):
        flt.step(state, SEQ.readings[1], SEQ.inputs[0])
    # asked to, it restarts from every reading, and says so at every step
    reset = ParticleFilter(n_particles=200, on_inconsistent="reset")
    result = reset.run(model, SEQ.readings, SEQ.inputs)
    assert result.diagnostics["reinitialised"][1:].all()


def test_the_particle_filter_on_its_own_model_is_not_refused():
    """Clouds that merely miss the consistent states are redrawn, as before."""
    redrawn = 0
    for seed in (1, 5, 13):  # seeds whose clouds narrow and miss (found by running them)
        seq = simulate_gauge(level_m=1.3, temperature_c=27.0, seed=seed)
        result = ParticleFilter().run(GAUGE, seq.readings, seq.inputs)
        redrawn += int(result.diagnostics["reinitialised"].sum())
        assert np.isfinite(result.estimates).all()
    assert redrawn > 0  # the narrowed clouds did miss, and were redrawn without an error


def test_the_particle_filter_refuses_an_unknown_policy():
    with pytest.raises(InvalidInputError, match="on_inconsistent"):
        ParticleFilter(on_inconsistent="restart")  # type: ignore[arg-type]


# -- model maps of the wrong shape ----------------------------------------------------------
@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_a_g_with_two_columns_for_one_reading_is_refused_by_name(flt):
    model = dataclasses.replace(GAUGE, g=lambda x: np.concatenate([GAUGE.g(x), x], axis=-1))
    with pytest.raises(EvidenceError, match=r"model's g returned shape .*\(the last axis: 1"):
        flt.run(model, SEQ.readings, SEQ.inputs)


@pytest.mark.parametrize(
    "g_inverse",
    [lambda lo, hi, x_lo, x_hi: x_lo, lambda lo, hi, x_lo, x_hi: (x_lo, x_hi, x_lo)],
    ids=["one array", "a triple"],
)
@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_a_g_inverse_that_returns_no_pair_is_refused_by_name(flt, g_inverse):
    model = dataclasses.replace(GAUGE, g_inverse=g_inverse)
    with pytest.raises(EvidenceError, match="must return a pair"):
        flt.run(model, SEQ.readings, SEQ.inputs)


@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_a_g_inverse_with_the_wrong_signature_is_refused_by_name(flt):
    model = dataclasses.replace(GAUGE, g_inverse=lambda lo, hi: (lo, hi))
    with pytest.raises(EvidenceError, match=r"g_inverse failed .*TypeError.*g_inverse\(lo, hi"):
        flt.run(model, SEQ.readings, SEQ.inputs)


@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_step_refuses_another_filters_state(flt):
    walk = random_walk(0.1, 0.5)
    other = ParticleFilter if not isinstance(flt, ParticleFilter) else KalmanFilter
    foreign = other().initialize(walk, 1.0)
    with pytest.raises(EvidenceError, match="step\\(\\) needs the .*State"):
        flt.step(foreign, 1.1)
    with pytest.raises(EvidenceError, match="step\\(\\) needs"):
        flt.step({"model": walk}, 1.1)


# -- masked arrays ---------------------------------------------------------------------------
@pytest.mark.parametrize("flt", FILTERS, ids=IDS)
def test_masked_readings_are_refused_not_used(flt):
    z = np.ma.masked_array(SEQ.readings.copy(), mask=False)
    z[3] = -999.0
    z[3] = np.ma.masked
    with pytest.raises(EvidenceError, match="1 masked entry"):
        flt.run(GAUGE, z, SEQ.inputs)
    state = flt.initialize(GAUGE, SEQ.readings[0])
    with pytest.raises(EvidenceError, match="masked"):
        flt.step(state, np.ma.masked_array([1000.0], mask=[True]), SEQ.inputs[0])
    # a masked array with nothing masked is plain data
    plain = flt.run(GAUGE, SEQ.readings, SEQ.inputs)
    unmasked = flt.run(GAUGE, np.ma.masked_array(SEQ.readings, mask=False), SEQ.inputs)
    assert np.array_equal(plain.estimates, unmasked.estimates)


@pytest.mark.parametrize("which", ["mass", "lo", "hi"])
def test_interval_evidence_refuses_masked_entries(which):
    args = {"lo": [0.0, 1.0], "hi": [1.0, 2.0], "mass": [0.5, 0.5]}
    args[which] = np.ma.masked_array(args[which], mask=[False, True])
    with pytest.raises(EvidenceError, match="masked"):
        IntervalEvidence(args["lo"], args["hi"], args["mass"])


def test_check_says_wrong_for_a_masked_answer():
    right = solution("mass.bel")
    verdict = check("mass.bel", np.ma.masked_array([right], mask=[True]))
    assert not verdict and "masked" in str(verdict)
    assert check("mass.bel", np.ma.masked_array([right], mask=[False]))


# -- raw exceptions -------------------------------------------------------------------------
@pytest.mark.parametrize("axes", [[5], [0, 0], [], [-1], [0.5], "0", 3])
def test_projection_refuses_axes_that_do_not_name_distinct_dimensions(axes):
    e1, e2 = appendix_pair()
    with pytest.raises(EvidenceError, match="distinct dimensions among 0..1"):
        projection(cartesian_product([e1, e2]), axes)


def test_projection_takes_axes_as_a_list_a_tuple_or_an_array():
    e1, e2 = appendix_pair()
    joint = cartesian_product([e1, e2])
    masses = [projection(joint, axes).mass.tolist() for axes in ([1], (1,), np.array([1]))]
    assert masses[0] == masses[1] == masses[2]


def test_check_refuses_an_exercise_id_that_is_not_a_string():
    with pytest.raises(InvalidInputError, match="exercise id is a string"):
        check(5, 1.0)  # type: ignore[arg-type]


def test_numbers_beyond_a_float_are_refused_or_wrong_not_overflow():
    verdict = check("mass.bel", 10**400)
    assert not verdict and "too large" in str(verdict)
    with pytest.raises(InvalidInputError, match="time limit"):
        set_time_limit(10**400)
    with pytest.raises(InvalidInputError, match="too large for a float"):
        real_number(10**400, "alpha")
    with pytest.raises(InvalidInputError, match="a number of 401 digits"):
        whole_number(10**400, "runs", high=100)
    assert whole_number(10**30, "seed") == 10**30  # exact, not through a float
