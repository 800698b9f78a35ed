"""Audio without a sound card: latency estimation and WAV files with metadata."""

from __future__ import annotations

import json
import struct
import wave

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.io import wavfile

from dstoolkit.audio import (
    RecordingFileError,
    RecordingMetadata,
    WavRecording,
    calibration_chirp,
    load_recording,
    save_recording,
)
from dstoolkit.errors import DetectionError
from dstoolkit.gauge import LatencyEstimate, estimate_latency

FS = 44100
CHIRP = calibration_chirp(FS)


def delayed(reference: np.ndarray, start: int, total: int) -> np.ndarray:
    """Return a recording of length ``total`` holding ``reference`` from sample ``start``."""
    out = np.zeros(total)
    out[start : start + reference.size] = reference
    return out


# --- latency ------------------------------------------------------------------------------


def test_chirp_is_tapered_and_in_range() -> None:
    assert CHIRP.size == round(0.25 * FS)
    assert np.max(np.abs(CHIRP)) <= 0.5
    assert abs(CHIRP[0]) < 1e-12 and abs(CHIRP[-1]) < 1e-12


@settings(max_examples=30, derandomize=True, deadline=None)
@given(offset=st.integers(0, 20000), lag=st.integers(-2000, 15000))
def test_known_delay_is_recovered_exactly(offset: int, lag: int) -> None:
    start = offset + lag
    if start < 0:
        lag, start = -offset, 0
    rec = delayed(CHIRP, start, start + CHIRP.size + 3000)
    est = estimate_latency(CHIRP, rec, FS, offset=offset)
    assert est.lag == lag
    assert est.seconds == pytest.approx(lag / FS)
    assert est.correlation == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("snr_db", [20.0, 0.0, -10.0])
def test_delay_found_in_noise_gain_and_polarity(snr_db: float) -> None:
    rng = np.random.default_rng(6)
    lag, offset = 8197, 22050
    rec = -0.3 * delayed(CHIRP, offset + lag, 3 * FS)  # quieter and inverted
    signal_power = np.mean((0.3 * CHIRP) ** 2)
    rec += rng.normal(0.0, np.sqrt(signal_power / 10 ** (snr_db / 10)), rec.size)
    est = estimate_latency(CHIRP, rec, FS, offset=offset)
    assert est.lag == lag
    assert est.correlation < 0  # inverted polarity is reported, not hidden
    # the normalised correlation falls with the noise as 1/sqrt(1 + 1/snr)
    expected = 1 / np.sqrt(1 + 10 ** (-snr_db / 10))
    assert abs(est.correlation) == pytest.approx(expected, rel=0.1)


def test_echo_after_the_direct_sound_does_not_move_the_estimate() -> None:
    lag = 4099
    rec = delayed(CHIRP, lag, 2 * FS) + 0.6 * delayed(CHIRP, lag + 900, 2 * FS)
    assert estimate_latency(CHIRP, rec, FS).lag == lag


@pytest.mark.parametrize("echo_delay", [130, 900, 4000])
def test_first_arrival_wins_over_a_louder_echo(echo_delay: int) -> None:
    """At a reflecting tube top the first echo can be 1.5 times the direct sound."""
    lag = 4099
    rec = delayed(CHIRP, lag, 2 * FS) + 1.5 * delayed(CHIRP, lag + echo_delay, 2 * FS)
    assert estimate_latency(CHIRP, rec, FS).lag == lag
    assert estimate_latency(CHIRP, rec, FS, first_arrival=None).lag == lag + echo_delay


def test_max_latency_restricts_the_search() -> None:
    rec = delayed(CHIRP, 1000, 2 * FS) + 0.4 * delayed(CHIRP, 30000, 2 * FS)
    assert estimate_latency(CHIRP, rec, FS).lag == 1000
    assert estimate_latency(CHIRP, rec, FS, offset=20000, max_latency_s=0.3).lag == 10000
    with pytest.raises(ValueError, match="no lag within"):
        estimate_latency(CHIRP, rec, FS, offset=80000, max_latency_s=0.01)


def test_unrelated_noise_gives_a_low_correlation() -> None:
    rng = np.random.default_rng(7)
    est = estimate_latency(CHIRP, rng.normal(size=2 * FS), FS)
    assert isinstance(est, LatencyEstimate)
    assert abs(est.correlation) < 0.1


def test_column_recording_is_accepted() -> None:
    rec = delayed(CHIRP, 500, FS)[:, None]
    assert estimate_latency(CHIRP, rec, FS).lag == 500


@pytest.mark.parametrize(
    ("reference", "recorded", "kwargs", "error", "match"),
    [
        (CHIRP, np.zeros(FS), {}, DetectionError, "silent"),
        (np.zeros(100), np.ones(FS), {}, ValueError, "reference is silent"),
        (CHIRP, CHIRP[:100], {}, ValueError, "shorter than the reference"),
        (CHIRP, np.full(FS, np.nan), {}, ValueError, "NaN"),
        (CHIRP, np.ones((FS, 2)), {}, ValueError, "one channel"),
        ([], np.ones(FS), {}, ValueError, "reference is empty"),
        (CHIRP, np.ones(FS), {"offset": -1}, ValueError, "offset"),
    ],
)
def test_bad_latency_inputs(reference, recorded, kwargs, error, match) -> None:
    with pytest.raises(error, match=match):
        estimate_latency(reference, recorded, FS, **kwargs)


def test_bad_samplerate_and_chirp_band() -> None:
    with pytest.raises(ValueError, match="samplerate"):
        estimate_latency(CHIRP, CHIRP, 0)
    with pytest.raises(ValueError, match="samplerate/2"):
        calibration_chirp(8000, f_stop_hz=5000)


# --- WAV files with metadata ----------------------------------------------------------------

META = RecordingMetadata(
    temperature_c=26.5,
    f_start_hz=1000.0,
    f_stop_hz=2400.0,
    sweep_duration_s=5.0,
    sweep_taper_s=0.01,
    sweep_onset_s=0.9734,
    latency_s=0.18587,
    level_m=2.6,
    source="loopback virtual tube",
    extra={"latency_setting": 0.25, "runs": [1, 2]},
)


def test_wav_round_trip_float32_keeps_samples_and_metadata(tmp_path) -> None:
    rng = np.random.default_rng(1)
    x = rng.uniform(-1, 1, 12345)
    path = tmp_path / "rec.wav"
    save_recording(path, x, 44100, META)
    rec = load_recording(path)
    assert isinstance(rec, WavRecording)
    assert rec.metadata == META
    assert rec.samplerate == 44100
    assert rec.duration_s == pytest.approx(12345 / 44100)
    np.testing.assert_allclose(rec.samples, x, atol=1e-7)  # float32 precision


def test_wav_round_trip_int16_is_a_plain_pcm_file(tmp_path) -> None:
    x = 0.8 * np.sin(2 * np.pi * 440 * np.arange(4410) / 44100)
    path = tmp_path / "rec16.wav"
    save_recording(path, x, 44100, META, sample_format="int16")
    rec = load_recording(path)
    assert rec.metadata == META
    np.testing.assert_allclose(rec.samples, x, atol=0.5 / 32768 + 1e-12)
    with wave.open(str(path)) as w:  # other readers skip the LIST chunk
        assert (w.getnchannels(), w.getframerate(), w.getnframes()) == (1, 44100, 4410)


def test_file_layout_is_standard_riff_with_an_info_comment(tmp_path) -> None:
    path = tmp_path / "rec.wav"
    save_recording(path, np.zeros(101), 8000, META)
    raw = path.read_bytes()
    assert raw[:4] == b"RIFF" and raw[8:12] == b"WAVE"
    assert struct.unpack("<I", raw[4:8])[0] == len(raw) - 8
    i = raw.index(b"LIST")
    assert raw[i + 8 : i + 12] == b"INFO" and b"ISFT" in raw[i:] and b"ICMT" in raw[i:]
    comment = raw[raw.index(b"ICMT") + 8 :].split(b"\0")[0]
    assert json.loads(comment)["temperature_c"] == 26.5
    fs, data = wavfile.read(path)  # scipy reads it, no warning (pytest -W error below)
    assert fs == 8000 and data.shape == (101,)


@pytest.mark.filterwarnings("error")
def test_scipy_reads_without_warning(tmp_path) -> None:
    path = tmp_path / "rec.wav"
    save_recording(path, np.zeros(10), 8000, META)
    wavfile.read(path)


def test_foreign_wav_loads_with_unknown_metadata(tmp_path) -> None:
    path = tmp_path / "plain.wav"
    stereo = np.stack([np.full(100, 16384), np.full(100, -8192)], axis=1).astype(np.int16)
    wavfile.write(path, 22050, stereo)
    rec = load_recording(path, channel=1)
    assert rec.metadata == RecordingMetadata()
    assert rec.samplerate == 22050
    np.testing.assert_allclose(rec.samples, -0.25)
    with pytest.raises(RecordingFileError, match="2 channels; channel 2"):
        load_recording(path, channel=2)


def test_unknown_fields_of_a_newer_version_are_kept_in_extra() -> None:
    text = META.to_json().replace('"level_m"', '"humidity": 40, "level_m"')
    assert RecordingMetadata.from_json(text).extra["humidity"] == 40


def test_not_a_wav_file(tmp_path) -> None:
    path = tmp_path / "notes.wav"
    path.write_bytes(b"ID3\x03 this is an mp3")
    with pytest.raises(RecordingFileError, match="not a WAV file"):
        load_recording(path)
    with pytest.raises(FileNotFoundError):
        load_recording(tmp_path / "missing.wav")


def test_truncated_wav_file(tmp_path) -> None:
    path = tmp_path / "cut.wav"
    save_recording(path, np.ones(1000) * 0.1, 8000, META)
    path.write_bytes(path.read_bytes()[:30])
    with pytest.raises(RecordingFileError, match="cannot read"):
        load_recording(path)


@pytest.mark.parametrize(
    ("samples", "samplerate", "kwargs", "match"),
    [
        (np.zeros(0), 8000, {}, "non-empty 1-D"),
        (np.zeros((10, 2)), 8000, {}, "non-empty 1-D"),
        (np.array([0.0, np.inf]), 8000, {}, "NaN or infinite"),
        (np.zeros(10), 0, {}, "samplerate"),
        (np.zeros(10), 44100.5, {}, "samplerate"),
        (np.array([0.0, 1.5]), 8000, {"sample_format": "int16"}, "clip"),
        (np.zeros(10), 8000, {"sample_format": "mp3"}, "sample_format"),
        (np.zeros(10), 8000, {"metadata": {"temperature_c": 20}}, "RecordingMetadata"),
    ],
)
def test_bad_save_inputs(tmp_path, samples, samplerate, kwargs, match) -> None:
    with pytest.raises(RecordingFileError, match=match):
        save_recording(tmp_path / "x.wav", samples, samplerate, **kwargs)
    assert not (tmp_path / "x.wav").exists()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"temperature_c": float("nan")}, "finite"),
        ({"temperature_c": "warm"}, "number"),
        ({"level_m": -1.0}, "positive"),
        ({"f_start_hz": 2400.0, "f_stop_hz": 1000.0}, "must rise"),
        ({"extra": {"x": object()}}, None),
    ],
)
def test_bad_metadata(kwargs, match) -> None:
    if match is None:  # valid fields, but not storable as JSON
        with pytest.raises(RecordingFileError, match="JSON"):
            RecordingMetadata(**kwargs).to_json()
    else:
        with pytest.raises(RecordingFileError, match=match):
            RecordingMetadata(**kwargs)
