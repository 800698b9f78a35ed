"""The sound devices are listed in a child process: PortAudio never loads in the caller.

A fake ``sounddevice`` module first on the child's PYTHONPATH stands for PortAudio with two
devices (or with a query it refuses, or with a hanging one); the caller's process must give
the same devices, the same errors, and must not import sounddevice itself.
"""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

import pytest

from dstoolkit import audio
from dstoolkit.audio import _devices
from dstoolkit.errors import AudioStallError, AudioUnavailableError, NoAudioDeviceError

ROOT = Path(__file__).resolve().parents[1]

FAKE = textwrap.dedent(
    """
    import types

    class PortAudioError(Exception):
        pass

    default = types.SimpleNamespace(device=(3, 5))
    DEVICES = [
        {"index": 3, "name": "USB microphone", "hostapi": 0, "max_input_channels": 1,
         "max_output_channels": 0, "default_samplerate": 48000.0},
        {"index": 5, "name": "Speakers", "hostapi": 1, "max_input_channels": 0,
         "max_output_channels": 2, "default_samplerate": 44100.0},
    ]

    def query_devices(device=None, kind=None):
        if device is None and kind is None:
            return DEVICES
        if device == "broken":
            raise PortAudioError("Error querying device 7")
        for info in DEVICES:
            if (device is None and info["index"] == default.device[kind == "output"]) or (
                isinstance(device, str) and device in info["name"]
            ) or info["index"] == device:
                return info
        raise ValueError(f"No {kind} device matching {device!r}")

    def query_hostapis():
        return [{"name": "ALSA"}, {"name": "PulseAudio"}]
    """
)


@pytest.fixture
def fake_portaudio(tmp_path, monkeypatch) -> Path:
    """Put the fake sounddevice first on the child's path; none is imported here."""
    (tmp_path / "sounddevice.py").write_text(FAKE)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), str(ROOT)]))
    monkeypatch.delitem(sys.modules, "sounddevice", raising=False)
    return tmp_path


def test_the_child_lists_the_devices(fake_portaudio) -> None:
    devices = audio.list_devices()
    assert devices == [
        audio.AudioDevice(3, "USB microphone", "ALSA", 1, 0, 48000.0, True, False),
        audio.AudioDevice(5, "Speakers", "PulseAudio", 0, 2, 44100.0, False, True),
    ]
    assert [d.index for d in audio.list_devices("output")] == [5]
    assert audio.audio_available() is True
    audio.refresh_devices()  # nothing loaded here to re-scan: only checks the import
    assert "sounddevice" not in sys.modules


def test_the_child_resolves_a_device(fake_portaudio) -> None:
    assert audio.choose_device("Speak", "output") == 5
    assert audio.choose_device(None, "input") == 3
    assert audio.choose_device(3, "input") == 3
    with pytest.raises(NoAudioDeviceError, match="no input device for 'headset'") as info:
        audio.choose_device("headset", "input")
    # the message lists the devices that exist, as the child sees them
    assert "3 USB microphone (ALSA, 1 in, 0 out, 48000 Hz)" in str(info.value)
    with pytest.raises(NoAudioDeviceError, match="Error querying device 7"):
        audio.choose_device("broken", "input")
    assert "sounddevice" not in sys.modules


def test_a_refused_list_is_a_no_device_error(fake_portaudio) -> None:
    text = FAKE + "\ndef query_hostapis():\n    raise PortAudioError('PortAudio not initialized')\n"
    (fake_portaudio / "sounddevice.py").write_text(text)
    with pytest.raises(NoAudioDeviceError, match="could not list devices: PortAudio not init"):
        audio.list_devices()


def test_a_failed_import_in_the_child_says_what_to_install(fake_portaudio) -> None:
    (fake_portaudio / "sounddevice.py").write_text("raise OSError('PortAudio library not found')\n")
    calls = (audio.list_devices, audio.refresh_devices, lambda: audio.choose_device(0, "input"))
    for call in calls:
        with pytest.raises(AudioUnavailableError) as info:
            call()
        message = str(info.value)
        assert "importing sounddevice failed (OSError: PortAudio library not found)" in message
        assert "apt-get install libportaudio2" in message


def test_a_hanging_child_is_a_stall(fake_portaudio, monkeypatch) -> None:
    (fake_portaudio / "sounddevice.py").write_text("import time\ntime.sleep(60)\n")
    monkeypatch.setattr(_devices, "STREAM_START_TIMEOUT_S", 1.0)  # the import never ends
    with pytest.raises(AudioStallError, match="did not list the sound devices within 1 s"):
        audio.list_devices()


def test_a_child_that_dies_is_a_server_error(fake_portaudio) -> None:
    (fake_portaudio / "sounddevice.py").write_text("import os\nos._exit(3)\n")
    with pytest.raises(audio.AudioServerError, match="exit code 3"):
        audio.list_devices()
