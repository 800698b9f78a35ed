"""A silent take is tried once more; a second silent take fails with the reason.

A sound server under load can deliver one take of silence while it starts a stream (seen
in CI at load 10–20). :func:`dstoolkit.audio.record_measurement` records again once; two
silent takes are a wiring fault and raise :class:`~dstoolkit.errors.DetectionError`. The
sound path here is a stand-in for ``play_record``: a perfect loopback that returns what
was played, delayed by 40 ms, or silence for the takes asked to be silent.
"""

from __future__ import annotations

import numpy as np
import pytest

from dstoolkit import audio
from dstoolkit.audio import _measurement
from dstoolkit.errors import DetectionError
from dstoolkit.gauge import TubeSetup

FS = 44100


def fake_sound_path(monkeypatch: pytest.MonkeyPatch, silent_takes: int) -> list[bool]:
    """Replace play_record by a loopback whose first ``silent_takes`` takes are silent."""
    takes: list[bool] = []

    def play_record(x, samplerate, **kwargs) -> audio.PlayRecordResult:
        pad = int(audio.MIN_PADDING_S * samplerate)
        played = np.concatenate([np.zeros(pad), np.asarray(x, dtype=float), np.zeros(pad)])
        silent = len(takes) < silent_takes
        takes.append(silent)
        delay = int(0.04 * samplerate)
        recorded = np.zeros_like(played)
        if not silent:
            recorded[delay:] = played[:-delay]
        return audio.PlayRecordResult(
            played, recorded, samplerate, pad, 0.25, 0, 0, "", dropped_samples=False
        )

    monkeypatch.setattr(_measurement.audio, "play_record", play_record)
    monkeypatch.setattr(_measurement.audio, "list_devices", lambda *a, **k: [])
    monkeypatch.setattr(_measurement.audio, "check_sound_server", lambda: None)
    return takes


def test_one_silent_take_is_recorded_again(monkeypatch):
    takes = fake_sound_path(monkeypatch, silent_takes=1)
    rec = _measurement.record_measurement(virtual_tube=TubeSetup(2.6, 26.0))
    assert takes == [True, False]
    assert rec.metadata.extra["attempt"] == 2
    assert np.any(rec.samples)


def test_two_silent_takes_fail_with_the_reason(monkeypatch):
    takes = fake_sound_path(monkeypatch, silent_takes=2)
    with pytest.raises(DetectionError, match="silent"):
        _measurement.record_measurement(virtual_tube=TubeSetup(2.6, 26.0))
    assert takes == [True, True]  # and no third take: two silent takes are the wiring
