"""Hostile input, second pass.

Gauge numbers, ambiguous recordings, the memory budget that nothing bypasses, and
explorers used from two threads.
"""

from __future__ import annotations

import io
import math
import os
import struct
import threading
import time
import tracemalloc
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.io import wavfile

import dstoolkit.evidence as ev
from dstoolkit import cli
from dstoolkit.audio import (
    RecordingMetadata,
    analyze,
    load_recording,
    save_recording,
    simulate_measurement,
)
from dstoolkit.errors import (
    DstoolkitError,
    EvidenceError,
    InvalidInputError,
    MemoryBudgetError,
    RecordingFileError,
)
from dstoolkit.evidence import IntervalEvidence, memory_budget, set_memory_budget
from dstoolkit.gauge import (
    LinearSweep,
    TubeSetup,
    fit_resonance_series,
    level_from_fundamental,
    level_from_resonance,
    simulate_gauge,
    synthesize_recording,
)


# -- gauge and numbers -------------------------------------------------------------------
@pytest.mark.parametrize(
    "make",
    [
        lambda: LinearSweep(sample_rate=math.nan, duration=math.inf),
        lambda: LinearSweep(duration=math.nan),
        lambda: LinearSweep(taper=math.nan),
        lambda: LinearSweep(f_start="1000"),
        lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k=-3),
        lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k=math.nan),
        lambda: ev.triangular_from_samples([0.1, -0.2, 0.3], k="3"),
        lambda: ev.triangular_from_samples([1e308, -1e308, 1e308]),
        lambda: simulate_gauge(runs=0),
        lambda: simulate_gauge(runs=2.5),
        lambda: simulate_gauge(runs="3"),
        lambda: TubeSetup(level_m="2"),
        lambda: TubeSetup(level_m=2.0, temperature_c="20"),
        lambda: TubeSetup(level_m=2.0, diameter_m=math.nan),
        lambda: IntervalEvidence(np.zeros((2, 0)), np.zeros((2, 0)), [0.5, 0.5]),
        lambda: level_from_fundamental(1e308, 1e-308),
        lambda: level_from_fundamental(1e-300, 1e300),
    ],
    ids=[
        "sweep nan/inf",
        "sweep duration nan",
        "sweep taper nan",
        "sweep string",
        "k = -3",
        "k = nan",
        "k string",
        "samples 1e308",
        "runs 0",
        "runs 2.5",
        "runs string",
        "level string",
        "temperature string",
        "diameter nan",
        "(2, 0) boxes",
        "level overflows",
        "level underflows",
    ],
)
def test_numbers_that_never_should_have_passed_are_refused(make):
    with pytest.raises(DstoolkitError) as info:
        make()
    assert str(info.value).strip() and "\n" not in str(info.value)


def test_the_level_of_huge_but_consistent_numbers_is_right():
    assert float(level_from_fundamental(1e308, 1e308)) == 0.5
    assert float(level_from_resonance(1e308, 1, 1e308)) == 0.5
    assert float(level_from_resonance(1320.0, 10, 343.2)) == pytest.approx(1.3)


def test_triangular_bounds_keep_lower_below_upper():
    b = ev.triangular_from_samples([0.1, -0.2, 0.3], k=0)
    assert b.lower == b.mode == b.upper
    b = ev.triangular_from_samples([0.1, -0.2, 0.3], k=3)
    assert b.lower < b.mode < b.upper


@pytest.mark.parametrize(
    "f",
    [lambda x: np.sqrt(x - 5.0), lambda x: x + 1e-3j, lambda x: np.where(x > 1.5, np.inf, x)],
    ids=["NaN", "complex", "inf"],
)
def test_image_refuses_what_is_no_image(f):
    lo, hi = np.array([[0.0], [1.0]]), np.array([[1.0], [2.0]])
    with pytest.raises(EvidenceError, match="f returned"):
        ev.image((lo, hi), f)
    with pytest.raises(EvidenceError, match="f returned"):
        ev.image(IntervalEvidence(lo[:, 0], hi[:, 0], [0.5, 0.5]), f)
    with pytest.raises(EvidenceError, match="NaN"):
        ev.image((np.array([[math.nan]]), np.array([[1.0]])), lambda x: x)


# -- recordings ------------------------------------------------------------------------
@pytest.fixture(scope="module")
def recording():
    return simulate_measurement(TubeSetup(level_m=2.6, temperature_c=26.0))


def _chunk(tag: bytes, payload: bytes) -> bytes:
    return tag + struct.pack("<I", len(payload)) + payload + b"\0" * (len(payload) % 2)


def _info(*fields: tuple[bytes, str]) -> bytes:
    return _chunk(b"LIST", b"INFO" + b"".join(_chunk(t, s.encode() + b"\0") for t, s in fields))


def _wav(samples: np.ndarray, rate: int, *chunks: bytes) -> bytes:
    buffer = io.BytesIO()
    wavfile.write(buffer, rate, samples.astype(np.float32))
    riff = bytearray(buffer.getvalue()) + b"".join(chunks)
    riff[4:8] = struct.pack("<I", len(riff) - 8)
    return bytes(riff)


def test_an_ambiguous_recording_is_refused(tmp_path, recording):
    meta = recording.metadata.to_json()
    hot = meta.replace('"temperature_c": 26.0', '"temperature_c": 40.0')
    twice = meta.replace('"temperature_c": 26.0', '"temperature_c": 26.0, "temperature_c": 40.0')
    assert hot != meta != twice
    cases = {
        "a key given twice": [_info((b"ICMT", twice))],
        "two LIST/INFO chunks": [_info((b"ICMT", meta)), _info((b"ICMT", hot))],
        "two comments in one chunk": [_info((b"ICMT", meta), (b"ICMT", hot))],
    }
    for name, chunks in cases.items():
        path = tmp_path / "r.wav"
        path.write_bytes(_wav(recording.samples, recording.samplerate, *chunks))
        with pytest.raises(RecordingFileError, match="twice|two") as info:
            load_recording(path)
        assert "ambiguous" in str(info.value), name
        with pytest.raises(RecordingFileError):
            analyze(path, methods=())
    path.write_bytes(_wav(recording.samples, recording.samplerate, _info((b"ICMT", hot))))
    assert load_recording(path).metadata.temperature_c == 40.0  # one chunk: fine


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda x, r, m: (np.append(x, 1e39), r, m), "32-bit float"),
        (lambda x, r, m: (x + 0.5j, r, m), "complex"),
        (lambda x, r, m: (x.astype(object), r, m), "real numbers"),
        (lambda x, r, m: (x, 500, m), "1 kHz to 1 MHz"),
        (lambda x, r, m: (x, math.nan, m), "1 kHz to 1 MHz"),
        (lambda x, r, m: (x, "44100", m), "1 kHz to 1 MHz"),
        (lambda x, r, m: (x, r, RecordingMetadata(extra={"note": "x" * 70_000})), "more than"),
        (lambda x, r, m: (x, r, RecordingMetadata(extra={"deep": _nested(40)})), "nested"),
    ],
    ids=["1e39", "complex", "objects", "500 Hz", "nan Hz", "string rate", "64 KiB", "nested"],
)
def test_save_recording_refuses_what_load_recording_would_refuse(
    tmp_path, recording, change, match
):
    samples, rate, metadata = change(recording.samples, recording.samplerate, recording.metadata)
    with pytest.raises(RecordingFileError, match=match):
        save_recording(tmp_path / "r.wav", samples, rate, metadata)
    assert list(tmp_path.iterdir()) == []


def _nested(depth: int) -> object:
    value: object = 0
    for _ in range(depth):
        value = [value]
    return value


# -- the memory budget ---------------------------------------------------------------------
@pytest.fixture
def budget():
    yield
    set_memory_budget(None)


@pytest.mark.parametrize(
    "work",
    [
        lambda: ev.cartesian_product(
            [IntervalEvidence(np.arange(12.0), np.arange(12.0) + 0.5, np.full(12, 1 / 12))] * 6
        ),
        lambda: fit_resonance_series(1000.0 + 18.0 * np.arange(400_000)),
        lambda: simulate_gauge(runs=10**9),
        lambda: synthesize_recording(TubeSetup(level_m=2.0), LinearSweep(duration=1e6)),
    ],
    ids=["cartesian product", "series fit", "simulated runs", "synthesis"],
)
def test_growing_work_is_refused_before_it_allocates(work):
    tracemalloc.start()
    try:
        with pytest.raises(MemoryBudgetError, match="memory budget"):
            work()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20  # refused before the big allocation, nothing kept


def test_the_budget_applies_to_small_budgets_too(budget):
    twelve = IntervalEvidence(np.arange(12.0), np.arange(12.0) + 0.5, np.full(12, 1 / 12))
    assert len(ev.cartesian_product([twelve] * 3)) == 12**3
    set_memory_budget(2**20)
    with pytest.raises(MemoryBudgetError):
        ev.cartesian_product([twelve] * 4)


def test_table3_runs_beyond_the_budget_is_one_clear_error(tmp_path, capsys):
    status = cli.main(
        ["table3", "--runs", str(10**9), "--out", str(tmp_path / "n" / "t.csv"), "--quiet"]
    )
    err = capsys.readouterr().err
    assert status == 2 and err.startswith("error: table3 --runs") and "budget" in err
    assert list(tmp_path.iterdir()) == []


@settings(max_examples=40, deadline=None)
@given(
    st.one_of(
        st.sampled_from(
            [
                "inf",
                "-inf",
                "nan",
                "1e400",
                "0",
                "-1",
                "12",
                "1e30",
                "lots",
                "G",
                "1.5.2M",
                "∞",
                "2**30",
                " ",
            ]
        ),
        st.floats(allow_nan=True, allow_infinity=True)
        .filter(lambda v: not 2**20 <= v <= 2**50)
        .map(repr),
    )
)
def test_a_budget_from_the_environment_is_validated(text):
    with (
        mock.patch.dict(os.environ, {"DSTOOLKIT_MEMORY_BUDGET": text}),
        pytest.raises(InvalidInputError, match="DSTOOLKIT_MEMORY_BUDGET"),
    ):
        memory_budget()


@pytest.mark.parametrize(
    ("text", "nbytes"),
    [("512M", 2**29), ("2G", 2**31), ("1.5GiB", 3 * 2**29), ("1048576", 2**20), ("4 MB", 2**22)],
)
def test_a_valid_budget_from_the_environment(monkeypatch, text, nbytes):
    monkeypatch.setenv("DSTOOLKIT_MEMORY_BUDGET", text)
    assert memory_budget() == nbytes


# -- explorers from two threads ------------------------------------------------------------
def test_an_explorer_renders_one_refresh_at_a_time():
    widgets = pytest.importorskip("ipywidgets")
    from dstoolkit.teaching import Explorer

    busy = {"now": 0, "most": 0}
    guard = threading.Lock()

    def render(x: float):
        with guard:
            busy["now"] += 1
            busy["most"] = max(busy["most"], busy["now"])
        time.sleep(0.001)  # gives the other thread every chance to come in
        with guard:
            busy["now"] -= 1
        return None, {"x": x}

    explorer = Explorer({"x": widgets.FloatSlider(value=0.0, max=1000)}, render, static=False)

    def work(offset: int) -> None:
        for i in range(30):
            explorer.refresh(x=float(offset + i))
            assert explorer.numbers["x"] >= 0  # a whole state, never a torn one

    threads = [threading.Thread(target=work, args=(k * 100,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert busy["most"] == 1


@pytest.mark.parametrize(
    "error",
    [
        MemoryBudgetError("too big for the budget"),
        InvalidInputError("not a setting"),
        EvidenceError("total conflict"),
    ],
)
def test_explorer_refresh_shows_every_package_error(error):
    widgets = pytest.importorskip("ipywidgets")
    from dstoolkit.teaching import Explorer

    def render(x: float):
        if x > 1:
            raise error
        return None, {"x": x}

    explorer = Explorer({"x": widgets.FloatSlider(value=0.0, max=5)}, render, static=False)
    assert explorer.numbers == {"x": 0.0}
    explorer.refresh(x=3.0)
    assert explorer.numbers == {"error": str(error)}
    assert str(error) in explorer.readout.value
