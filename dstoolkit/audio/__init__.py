"""Real audio for the lab.

Sound devices (needs the ``audio`` extra: sounddevice), recordings in WAV files with
metadata, and the measure/analyze commands.
"""

from __future__ import annotations

from dstoolkit.errors import (
    AudioDropoutError,
    AudioDropoutWarning,
    AudioServerError,
    AudioStallError,
    AudioUnavailableError,
    NoAudioDeviceError,
    RecordingFileError,
)

from ._devices import (
    MIN_PADDING_S,
    STREAM_GRACE_S,
    STREAM_OPEN_TIMEOUT_S,
    STREAM_START_TIMEOUT_S,
    AudioDevice,
    PlayRecordResult,
    audio_available,
    calibration_chirp,
    check_calibration,
    check_sound_server,
    choose_device,
    list_devices,
    measure_latency,
    play_record,
    refresh_devices,
)
from ._measurement import (
    CALIBRATION_GAP_S,
    Analysis,
    LevelEstimate,
    add_analyze_arguments,
    add_measure_arguments,
    analyze,
    analyze_command,
    filter_levels,
    measure,
    measure_command,
    record_measurement,
    simulate_measurement,
)
from ._recording_io import (
    MAX_METADATA_BYTES,
    MAX_METADATA_DEPTH,
    MAX_RECORDING_BYTES,
    RecordingMetadata,
    WavRecording,
    load_recording,
    save_recording,
)

__all__ = [
    "MAX_METADATA_BYTES",
    "MAX_METADATA_DEPTH",
    "MAX_RECORDING_BYTES",
    "Analysis",
    "AudioDevice",
    "AudioDropoutError",
    "AudioDropoutWarning",
    "AudioServerError",
    "AudioStallError",
    "AudioUnavailableError",
    "CALIBRATION_GAP_S",
    "LevelEstimate",
    "MIN_PADDING_S",
    "NoAudioDeviceError",
    "PlayRecordResult",
    "RecordingFileError",
    "RecordingMetadata",
    "STREAM_GRACE_S",
    "STREAM_OPEN_TIMEOUT_S",
    "STREAM_START_TIMEOUT_S",
    "WavRecording",
    "add_analyze_arguments",
    "add_measure_arguments",
    "analyze",
    "analyze_command",
    "audio_available",
    "calibration_chirp",
    "check_calibration",
    "check_sound_server",
    "choose_device",
    "filter_levels",
    "list_devices",
    "load_recording",
    "measure",
    "measure_command",
    "measure_latency",
    "play_record",
    "record_measurement",
    "refresh_devices",
    "save_recording",
    "simulate_measurement",
]
