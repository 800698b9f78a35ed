"""sounddevice is optional: dstoolkit works without it, and audio calls say what to install.

Each case runs in a fresh Python whose ``import sounddevice`` fails the way it does in the
wild (a fake ``sounddevice`` module first on PYTHONPATH): OSError when the PortAudio
library is missing (sounddevice is installed but libportaudio2 is not), ImportError when
the package itself is missing. A machine without a sound device is imitated in-process by
a fake module whose calls raise PortAudioError as sounddevice's do.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import types
from pathlib import Path

import numpy as np
import pytest

from dstoolkit import audio
from dstoolkit.errors import AudioUnavailableError

ROOT = Path(__file__).resolve().parents[1]

CHILD = textwrap.dedent(
    """
    import sys
    import dstoolkit
    from dstoolkit import audio
    from dstoolkit.audio import analyze, measure, simulate_measurement
    from dstoolkit.gauge import TubeSetup, estimate_latency, synthesize_recording

    assert "sounddevice" not in sys.modules, "import dstoolkit must not import sounddevice"
    # a simulation runs without audio
    rec = synthesize_recording(TubeSetup(level_m=2.6, temperature_c=26.5), seed=1)
    assert rec.samples.size > 0 and abs(rec.samples).max() > 0
    # so does the whole measurement chain with simulated audio (the lab without a device)
    setup = TubeSetup(level_m=2.6, temperature_c=26.5)
    assert abs(analyze(simulate_measurement(setup)).error_m) < 0.01
    # the array functions of the audio module work too
    chirp = audio.calibration_chirp(44100)
    assert estimate_latency(chirp, chirp, 44100).lag == 0
    assert audio.audio_available() is False
    for call in (audio.list_devices, lambda: audio.play_record(chirp, 44100),
                 lambda: audio.measure_latency(44100),
                 lambda: measure(virtual_tube=setup)):
        try:
            call()
        except dstoolkit.AudioUnavailableError as exc:
            print("MESSAGE:", exc)
        else:
            raise SystemExit("an audio call did not raise AudioUnavailableError")
    """
)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("failure", "shown"),
    [
        ("raise OSError('PortAudio library not found')", "OSError: PortAudio library not found"),
        ("raise ModuleNotFoundError(\"No module named 'sounddevice'\")", "ModuleNotFoundError"),
    ],
)
def test_dstoolkit_works_when_sounddevice_cannot_be_imported(tmp_path, failure, shown) -> None:
    (tmp_path / "sounddevice.py").write_text(failure + "\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), str(ROOT)]))
    proc = subprocess.run(
        [sys.executable, "-c", CHILD],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr + proc.stdout
    messages = [line for line in proc.stdout.splitlines() if line.startswith("MESSAGE:")]
    assert len(messages) == 4
    for message in messages:
        assert shown in message  # the cause, as Python reported it
        assert "apt-get install libportaudio2" in message
        assert "pip install 'dstoolkit[audio]'" in message


class FakePortAudioError(Exception):
    pass


def fake_sounddevice_without_devices() -> types.ModuleType:
    """Imitate what sounddevice does on a machine where PortAudio finds no device."""
    sd = types.ModuleType("sounddevice")
    sd.PortAudioError = FakePortAudioError
    sd.default = types.SimpleNamespace(device=[-1, -1])

    def query_devices(device=None, kind=None):
        if device is None and kind is None:
            return []
        if isinstance(device, str):
            raise ValueError(f"No {kind} device matching {device!r}")
        raise FakePortAudioError("Error querying device -1")

    def playrec(*args, **kwargs):
        raise FakePortAudioError("Error querying device -1")

    sd.query_devices = query_devices
    sd.query_hostapis = lambda: [{"name": "ALSA"}]
    sd.playrec = playrec
    return sd


@pytest.fixture
def no_device(monkeypatch):
    monkeypatch.setitem(sys.modules, "sounddevice", fake_sounddevice_without_devices())


def test_no_device_gives_a_clear_error(no_device) -> None:
    assert audio.list_devices() == []
    assert audio.audio_available() is False
    with pytest.raises(audio.NoAudioDeviceError) as info:
        audio.play_record(np.zeros(100), 44100)
    message = str(info.value)
    assert "no input device for the default" in message
    assert "Error querying device -1" in message
    assert "audio-loopback.sh" in message and "(none)" in message
    assert isinstance(info.value, AudioUnavailableError)


def test_unknown_device_name_lists_what_exists(no_device) -> None:
    with pytest.raises(audio.NoAudioDeviceError, match="no output device for 'USB mic'"):
        audio.choose_device("USB mic", "output")


def test_play_record_checks_its_arguments_before_touching_audio(no_device) -> None:
    with pytest.raises(ValueError, match="would clip"):
        audio.play_record(np.array([0.0, 1.2]), 44100)
    with pytest.raises(ValueError, match="at least 0.5 s"):
        audio.play_record(np.zeros(10), 44100, tail_s=0.1)
    with pytest.raises(ValueError, match="samplerate"):
        audio.play_record(np.zeros(10), 44100.5)
