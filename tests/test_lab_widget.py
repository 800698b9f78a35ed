"""The lab's measuring station (dstoolkit.teaching.lab_widget) and its helpers (dstoolkit.teaching).

Through a Jupyter kernel (nbclient): the station is built (its first, virtual measurement
is made at once), controls are changed and the Record button's click handler is called, and
the level it prints must follow: a virtual level moved from 2.5 m to 7 m comes back within
1 cm (the virtual tube's error is a few mm, tests/test_measurement.py); a thermometer that
reads 2 °C high lengthens the level by L Δc/c (eq. 35, 24.8 mm at 7 m) within 2 mm; a new
temperature with a right thermometer changes c by 0.606 m/s per °C and not the level; bad
settings print the toolkit's message (clipping, too few resonances) instead of a level.

In-process, with sounddevice imitated: the device pickers list what PortAudio sees, and a
Record with devices calls dstoolkit.audio.measure with them (nothing is played).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from conftest import printed_json

import dstoolkit.audio as audio
from dstoolkit.audio import RecordingMetadata, WavRecording
from dstoolkit.errors import AudioUnavailableError
from dstoolkit.gauge import TubeSetup
from dstoolkit.studies import METHODS
from dstoolkit.teaching import (
    VIRTUAL,
    VIRTUAL_LABEL,
    LabSettings,
    LabWidget,
    imitate_audio_failure,
    lab_measurement,
    lab_widget,
    level_error_from_temperature,
    plot_calibration,
)
from dstoolkit.teaching import _lab as lab

matplotlib.use("Agg")
ROOT = Path(__file__).resolve().parents[1]

BUILD = """
import json
import matplotlib
matplotlib.use("Agg")
from dstoolkit.teaching import lab_widget

station = lab_widget(temperature_c=21.0, level_m=2.5)


def state():
    out = dict(station.numbers)
    out["readout"] = station.readout.value
    out["title"] = station.figure.axes[0].get_title() if station.figure is not None else None
    out["measurements"] = station.measurements
    out["button"] = [station.button.description, station.button.disabled]
    out["options"] = [label for label, _ in station.controls["input"].options]
    out["input"] = station.controls["input"].value
    out["continuous_update"] = [c.continuous_update for c in station.controls.values()
                                if hasattr(c, "continuous_update")]
    out["outputs"] = len(station.output.outputs)
    return json.dumps(out)


print(state())
"""


def _record(**values: float) -> str:
    sets = "".join(f"station.controls[{k!r}].value = {v!r}\n" for k, v in values.items())
    return sets + "station.button.click()\nprint(state())"


@pytest.fixture(scope="module")
def states() -> list[dict]:
    return printed_json(
        [
            BUILD,
            _record(level=7.0),
            _record(thermometer_error=2.0),
            _record(thermometer_error=0.0, temperature=11.0),
            _record(room_noise=-10.0),
            _record(room_noise=-60.0, level=0.5),
            _record(level=4.0, temperature=21.0),
        ]
    )[0]


@pytest.mark.slow
def test_first_state_is_a_virtual_measurement(states: list[dict]) -> None:
    first = states[0]
    assert "error" not in first, first
    assert first["options"][0] == VIRTUAL_LABEL and first["input"] == VIRTUAL
    assert abs(first["level (m)"] - 2.5) < 0.01 and first["true level (m)"] == 2.5
    assert first["resonances"] == 20 and first["missed"] == 0
    assert 50.0 <= first["latency (ms)"] <= 200.0
    assert set(first) >= {f"{m} (m)" for m in METHODS}
    assert f"L = {first['level (m)']:.4f} m" in first["readout"]
    assert "true 2.5 m" in first["title"]
    assert first["measurements"] == 1 and first["button"] == ["● Record", False]
    assert first["outputs"] == 2  # the analysis figure and the methods' levels
    # the sliders follow the drag, and only a click of Record measures (measurements == 1)
    assert first["continuous_update"] and all(first["continuous_update"])


@pytest.mark.slow
def test_moving_the_virtual_level_and_recording_moves_the_printed_level(states: list[dict]) -> None:
    before, after = states[0], states[1]
    assert "error" not in after, after
    assert abs(after["level (m)"] - 7.0) < 0.01 and after["true level (m)"] == 7.0
    assert after["resonances"] > 2 * before["resonances"]
    assert f"L = {after['level (m)']:.4f} m" in after["readout"]
    assert "true 7 m" in after["title"] and after["measurements"] == 2
    # a new stream, a new latency: the calibration finds it
    assert after["latency (ms)"] != before["latency (ms)"]


@pytest.mark.slow
def test_a_thermometer_that_reads_high_lengthens_the_level_by_l_dc_over_c(
    states: list[dict],
) -> None:
    right, high = states[1], states[2]
    expected = level_error_from_temperature(7.0, 21.0 - 2.0, 2.0)  # air 19 °C, read 21 °C
    assert abs((high["level (m)"] - right["level (m)"]) - expected) < 0.002, (right, high)
    assert high["c (m/s)"] == right["c (m/s)"]  # the analysis trusts the thermometer


@pytest.mark.slow
def test_a_new_temperature_changes_c_but_not_the_level(states: list[dict]) -> None:
    warm, cold = states[1], states[3]
    assert cold["c (m/s)"] == pytest.approx(warm["c (m/s)"] - 0.606 * 10.0, abs=1e-9)
    assert abs(cold["level (m)"] - 7.0) < 0.01


@pytest.mark.slow
def test_bad_settings_print_the_toolkits_message(states: list[dict]) -> None:
    loud, short, again = states[4], states[5], states[6]
    assert "clipping" in loud["error"] and "clipping" in loud["readout"]
    assert "too few resonances" in short["error"]
    assert loud["outputs"] == short["outputs"] == 0  # no stale figure
    assert loud["button"] == ["● Record", False]  # the button works again
    assert abs(again["level (m)"] - 4.0) < 0.01 and again["measurements"] == 7


# -- in-process: device pickers and the record call, with sounddevice imitated ---------------


def _devices(kind=None):
    both = [
        audio.AudioDevice(3, "USB microphone", "ALSA", 1, 0, 48000.0, True, False),
        audio.AudioDevice(5, "Speakers", "ALSA", 0, 2, 48000.0, False, True),
    ]
    if kind == "input":
        return both[:1]
    if kind == "output":
        return both[1:]
    return both


@pytest.fixture
def fake_audio(monkeypatch: pytest.MonkeyPatch) -> list[dict]:
    """Two devices, and a measure() that records its arguments and simulates instead."""
    monkeypatch.setattr(audio, "audio_available", lambda: True)
    monkeypatch.setattr(audio, "list_devices", _devices)
    calls: list[dict] = []

    def fake_measure(temperature_c, **kwargs):
        calls.append({"temperature_c": temperature_c, **kwargs})
        tube = kwargs["virtual_tube"] or TubeSetup(level_m=3.0, temperature_c=temperature_c)
        return audio.analyze(audio.simulate_measurement(tube))

    monkeypatch.setattr(audio, "measure", fake_measure)
    return calls


def test_device_pickers_list_the_devices_after_the_virtual_tube(fake_audio) -> None:
    station = LabWidget(record_now=False)
    inputs = station.controls["input"].options
    outputs = station.controls["output"].options
    assert inputs[0] == (VIRTUAL_LABEL, VIRTUAL) and outputs[0] == (VIRTUAL_LABEL, VIRTUAL)
    assert inputs[1] == ("3: USB microphone (default)", 3)
    assert outputs[1] == ("5: Speakers (default)", 5)
    assert station.controls["input"].value == VIRTUAL and station.analysis is None
    assert not fake_audio  # building the station plays nothing


def test_recording_with_devices_calls_measure_with_them(fake_audio) -> None:
    station = LabWidget(record_now=False)
    station.controls["input"].value = 3
    station.controls["output"].value = 5
    station.controls["temperature"].value = 18.5
    station.controls["volume"].value = 0.2
    # with devices and no virtual tube the virtual controls do not apply
    assert station.controls["level"].disabled and station.controls["room_noise"].disabled
    assert not station.controls["through_virtual_tube"].disabled
    station.button.click()
    call = fake_audio[-1]
    assert call["input_device"] == 3 and call["output_device"] == 5
    assert call["temperature_c"] == 18.5 and call["amplitude"] == 0.2
    assert call["virtual_tube"] is None
    assert abs(station.numbers["level (m)"] - 3.0) < 0.01
    station.controls["through_virtual_tube"].value = True
    station.controls["level"].value = 4.2
    assert not station.controls["level"].disabled
    station.button.click()
    assert fake_audio[-1]["virtual_tube"] == TubeSetup(level_m=4.2, temperature_c=18.5)
    assert abs(station.numbers["level (m)"] - 4.2) < 0.01


def test_an_audio_failure_is_shown_not_raised(fake_audio, monkeypatch) -> None:
    def broken(*args, **kwargs):
        raise AudioUnavailableError("PortAudio failed to play and record: unplugged")

    monkeypatch.setattr(audio, "measure", broken)
    station = LabWidget(record_now=False)
    station.controls["input"].value = 3
    station.controls["output"].value = 5
    station.button.click()
    assert station.numbers == {"error": "PortAudio failed to play and record: unplugged"}
    assert "unplugged" in station.readout.value and station.analysis is None
    assert station.button.description == "● Record" and not station.button.disabled


def test_without_audio_only_the_virtual_tube_is_offered() -> None:
    with imitate_audio_failure("no device"):
        station = lab_widget(record_now=False)
    assert station.controls["input"].options == ((VIRTUAL_LABEL, VIRTUAL),)
    assert station.controls["output"].options == ((VIRTUAL_LABEL, VIRTUAL),)


# -- the lab helpers (dstoolkit.teaching) ----------------------------------------------------


def test_imitated_failures_raise_the_real_messages_and_restore_sounddevice() -> None:
    before = sys.modules.get("sounddevice")
    with (
        imitate_audio_failure("no sounddevice"),
        pytest.raises(AudioUnavailableError, match="pip install"),
    ):
        audio.list_devices()
    with (
        imitate_audio_failure("no device"),
        pytest.raises(audio.NoAudioDeviceError, match="no input device"),
    ):
        audio.choose_device(None, "input")
    assert sys.modules.get("sounddevice") is before
    with pytest.raises(ValueError, match="kind must be"), imitate_audio_failure("loud"):
        pass


def test_lab_measurement_with_a_thermometer_error() -> None:
    right = lab_measurement(LabSettings(level_m=3.0, seed=4))
    high = lab_measurement(LabSettings(level_m=3.0, thermometer_error_c=3.0, seed=4))
    assert abs(right.error_m) < 0.01
    expected = level_error_from_temperature(3.0, 18.0, 3.0)
    assert abs((high.level.level_m - right.level.level_m) - expected) < 1e-3
    assert right.latency_s == pytest.approx(LabSettings(seed=4).simulated_latency_s, abs=1 / 44100)
    assert LabSettings(seed=4).simulated_latency_s != LabSettings(seed=5).simulated_latency_s


def test_calibration_figure_needs_the_calibration_metadata() -> None:
    rec = audio.simulate_measurement(TubeSetup(level_m=2.0), latency_s=0.08)
    fig = plot_calibration(rec)
    assert "τ = 80.00 ms" in [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    bare = WavRecording(rec.samples, rec.samplerate, RecordingMetadata())
    with pytest.raises(ValueError, match="calibration"):
        plot_calibration(bare)
    # the matched filter peaks where the opening chirp starts: after the lead-in and τ
    c = lab.calibration_correlation(rec)
    assert int(np.argmax(c[: c.size // 2])) == round((audio.MIN_PADDING_S + 0.08) * rec.samplerate)
    assert c.max() == 1.0
