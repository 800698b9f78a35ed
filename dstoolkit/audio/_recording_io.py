"""Save and load gauge recordings as WAV files that carry their metadata.

A recording is only useful with what was known when it was made: the air temperature
(sound speed), the sweep (band, duration, where it starts), the sample rate, the
measured audio latency, and the level when it is known (a virtual tube, a reference
measurement). They travel inside the WAV file, so a file copied alone stays analysable.

Format. A standard RIFF/WAVE file (32-bit float samples by default, or 16-bit PCM)
followed by a ``LIST``/``INFO`` chunk with two text fields: ``ISFT`` (the software,
"dstoolkit <version>") and ``ICMT`` (comment) holding the metadata as JSON. ``LIST``/
``INFO`` is the standard place for text in a WAV: audio editors show the comment, and
readers that do not know it skip it (scipy.io.wavfile reads such files without a warning,
a custom chunk makes it warn). Why not a library: ``scipy.io.wavfile.write`` writes no
metadata and the stdlib ``wave`` module writes only the format and data chunks (and only
PCM); a JSON sidecar file is lost when the WAV is copied alone. So scipy writes the
samples and this module appends the ``LIST`` chunk and patches the RIFF size (a few lines
of :mod:`struct`), and reads it back by walking the RIFF chunks.
"""

from __future__ import annotations

import io
import json
import math
import os
import struct
from dataclasses import asdict, dataclass, field, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.io import wavfile

from dstoolkit.errors import RecordingFileError

METADATA_VERSION = 1
_INT_SCALE = {np.dtype(np.int16): 32768.0, np.dtype(np.int32): 2147483648.0}


@dataclass(frozen=True)
class RecordingMetadata:
    """What is known about a recording besides its samples. Every field may be unknown.

    Attributes
    ----------
    temperature_c : float or None
        Air temperature in the tube, °C (sound speed c = 331.3 + 0.606 T).
    f_start_hz : float or None
        Start of the sweep's band (the paper swept 1000 → 2400 Hz).
    f_stop_hz : float or None
        End of the sweep's band.
    sweep_duration_s : float or None
        Length of the sweep (5 s in the paper).
    sweep_taper_s : float or None
        Raised-cosine fade at each end of the sweep (:class:`dstoolkit.gauge.LinearSweep`).
    sweep_onset_s : float or None
        Time in the recording at which the sweep's first sample arrives, latency included:
        the analysis maps recording time to sweep frequency from here.
    latency_s : float or None
        Measured audio latency (calibration chirp), already included in sweep_onset_s.
    level_m : float or None
        The true level when known (virtual tube, reference measurement), metres.
    source : str or None
        How the recording was made, e.g. "loopback virtual tube" or a device name.
    extra : dict
        Anything else that JSON can hold.
    """

    temperature_c: float | None = None
    f_start_hz: float | None = None
    f_stop_hz: float | None = None
    sweep_duration_s: float | None = None
    sweep_taper_s: float | None = None
    sweep_onset_s: float | None = None
    latency_s: float | None = None
    level_m: float | None = None
    source: str | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("source", "extra") or value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RecordingFileError(f"{f.name} must be a number or None, got {value!r}")
            if not math.isfinite(value):
                raise RecordingFileError(f"{f.name} must be finite or None, got {value}")
            object.__setattr__(self, f.name, float(value))
        for name in ("f_start_hz", "f_stop_hz", "sweep_duration_s", "level_m"):
            value = getattr(self, name)
            if value is not None and value <= 0:
                raise RecordingFileError(f"{name} must be positive, got {value}")
        if (self.f_start_hz is not None and self.f_stop_hz is not None
                and self.f_start_hz >= self.f_stop_hz):
            raise RecordingFileError(
                f"the sweep band must rise: f_start_hz {self.f_start_hz} >= f_stop_hz "
                f"{self.f_stop_hz}"
            )
        if self.source is not None and not isinstance(self.source, str):
            raise RecordingFileError(f"source must be a string or None, got {self.source!r}")
        if not isinstance(self.extra, dict):
            raise RecordingFileError(f"extra must be a dict, got {type(self.extra).__name__}")

    def to_json(self) -> str:
        payload = {"dstoolkit_metadata": METADATA_VERSION, **asdict(self)}
        try:
            return json.dumps(payload, allow_nan=False, sort_keys=True)
        except (TypeError, ValueError) as exc:
            raise RecordingFileError(f"metadata cannot be stored as JSON: {exc}") from exc

    @classmethod
    def from_json(cls, text: str) -> RecordingMetadata:
        try:
            payload = json.loads(text)
        except json.JSONDecodeError as exc:
            raise RecordingFileError(f"the WAV comment is not dstoolkit metadata: {exc}") from exc
        if not isinstance(payload, dict) or "dstoolkit_metadata" not in payload:
            raise RecordingFileError("the WAV comment is not dstoolkit metadata")
        known = {f.name for f in fields(cls)}
        unknown = set(payload) - known - {"dstoolkit_metadata"}
        extra = dict(payload.get("extra") or {})
        extra.update({k: payload[k] for k in unknown})  # fields of a newer version
        return cls(**{k: v for k, v in payload.items() if k in known - {"extra"}}, extra=extra)


@dataclass(frozen=True)
class WavRecording:
    """A mono recording as stored in a WAV file: samples (float, full scale ±1), sample
    rate (Hz) and metadata. (:class:`dstoolkit.gauge.Recording` is the gauge's view of a
    recording, cropped to the sweep; :mod:`dstoolkit.audio` converts.)"""

    samples: np.ndarray
    samplerate: int
    metadata: RecordingMetadata = field(default_factory=RecordingMetadata)

    @property
    def duration_s(self) -> float:
        return self.samples.size / self.samplerate


def _chunk(tag: bytes, payload: bytes) -> bytes:
    """One RIFF chunk: tag, little-endian size, payload, pad byte to an even length."""
    return tag + struct.pack("<I", len(payload)) + payload + b"\0" * (len(payload) % 2)


def _info_chunk(metadata: RecordingMetadata) -> bytes:
    from dstoolkit import __version__

    fields_ = [(b"ISFT", f"dstoolkit {__version__}"), (b"ICMT", metadata.to_json())]
    body = b"".join(_chunk(tag, text.encode("utf-8") + b"\0") for tag, text in fields_)
    return _chunk(b"LIST", b"INFO" + body)


def save_recording(
    path: str | os.PathLike[str],
    samples: ArrayLike,
    samplerate: int,
    metadata: RecordingMetadata | None = None,
    *,
    sample_format: Literal["float32", "int16"] = "float32",
) -> None:
    """Write a mono recording and its metadata to a WAV file.

    Parameters
    ----------
    path : path-like
        The file to write (overwritten).
    samples : array_like, 1-D
        Full scale ±1.
    samplerate : int
        Hz.
    metadata : RecordingMetadata, optional
        Stored as JSON in the LIST/INFO comment.
    sample_format : {"float32", "int16"}
        float32 keeps the samples as recorded; int16 is read by every program but
        quantises, and refuses samples beyond ±1.
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim == 2 and x.shape[1] == 1:
        x = x[:, 0]
    if x.ndim != 1 or x.size == 0:
        raise RecordingFileError(f"samples must be a non-empty 1-D array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise RecordingFileError("samples contain NaN or infinite values")
    if isinstance(samplerate, bool) or int(samplerate) != samplerate or samplerate <= 0:
        raise RecordingFileError(f"samplerate must be a positive whole number, got {samplerate}")
    metadata = RecordingMetadata() if metadata is None else metadata
    if not isinstance(metadata, RecordingMetadata):
        raise RecordingFileError(
            f"metadata must be a RecordingMetadata, got {type(metadata).__name__}"
        )
    if sample_format == "float32":
        data: np.ndarray = x.astype(np.float32)
    elif sample_format == "int16":
        peak = float(np.max(np.abs(x)))
        if peak > 1.0:
            raise RecordingFileError(
                f"samples peak at {peak:.3g} > 1 and would clip in 16-bit PCM; "
                "use sample_format='float32' or scale them"
            )
        # the scale load_recording divides by; +1.0 itself saturates at 32767/32768
        data = np.clip(np.round(x * 32768.0), -32768, 32767).astype(np.int16)
    else:
        raise RecordingFileError(
            f"sample_format must be 'float32' or 'int16', not {sample_format!r}"
        )
    buffer = io.BytesIO()
    wavfile.write(buffer, int(samplerate), data)
    riff = bytearray(buffer.getvalue())
    riff += _info_chunk(metadata)
    riff[4:8] = struct.pack("<I", len(riff) - 8)
    with open(path, "wb") as fh:
        fh.write(riff)


def _read_info(raw: bytes, path: str | os.PathLike[str]) -> dict[bytes, str]:
    """The LIST/INFO text fields of a RIFF/WAVE file ({} when it has none)."""
    if len(raw) < 12 or raw[:4] not in (b"RIFF", b"RIFX") or raw[8:12] != b"WAVE":
        raise RecordingFileError(
            f"{os.fspath(path)!r} is not a WAV file (it starts with {raw[:12]!r}); "
            "save recordings with dstoolkit.audio.save_recording"
        )
    info: dict[bytes, str] = {}
    pos = 12
    while pos + 8 <= len(raw):
        tag, size = raw[pos : pos + 4], struct.unpack("<I", raw[pos + 4 : pos + 8])[0]
        body = raw[pos + 8 : pos + 8 + size]
        if tag == b"LIST" and body[:4] == b"INFO":
            sub = 4
            while sub + 8 <= len(body):
                stag, ssize = body[sub : sub + 4], struct.unpack("<I", body[sub + 4 : sub + 8])[0]
                text = body[sub + 8 : sub + 8 + ssize].rstrip(b"\0")
                info[stag] = text.decode("utf-8", errors="replace")
                sub += 8 + ssize + ssize % 2
        pos += 8 + size + size % 2
    return info


def load_recording(path: str | os.PathLike[str], *, channel: int = 0) -> WavRecording:
    """Read a WAV file written by :func:`save_recording`, or any other WAV file.

    Samples come back as float64 at full scale ±1 (16/32-bit PCM are scaled, unsigned
    8-bit centred). A file without dstoolkit metadata loads with every metadata field
    unknown; a multichannel file gives its channel ``channel``.

    Raises
    ------
    RecordingFileError
        Not a WAV file, an unreadable one, or a channel it does not have.
    FileNotFoundError
        No such file.
    """
    with open(path, "rb") as fh:
        raw = fh.read()
    info = _read_info(raw, path)
    try:
        samplerate, data = wavfile.read(io.BytesIO(raw))
    except (ValueError, struct.error, EOFError) as exc:  # struct.error: a truncated file
        raise RecordingFileError(f"cannot read the WAV file {os.fspath(path)!r}: {exc}") from exc
    if data.ndim == 2:
        if not 0 <= channel < data.shape[1]:
            raise RecordingFileError(
                f"{os.fspath(path)!r} has {data.shape[1]} channels; channel {channel} does "
                "not exist"
            )
        data = data[:, channel]
    elif channel != 0:
        raise RecordingFileError(f"{os.fspath(path)!r} is mono; channel {channel} does not exist")
    if data.dtype in _INT_SCALE:
        samples = data / _INT_SCALE[data.dtype]
    elif data.dtype == np.uint8:
        samples = (data.astype(float) - 128.0) / 128.0
    else:
        samples = data.astype(float)
    comment = info.get(b"ICMT")
    if comment is not None and comment.lstrip().startswith("{") and "dstoolkit_metadata" in comment:
        metadata = RecordingMetadata.from_json(comment)
    else:
        metadata = RecordingMetadata()
    return WavRecording(samples=samples, samplerate=int(samplerate), metadata=metadata)
