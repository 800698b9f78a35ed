"""Save and load gauge recordings as WAV files that carry their metadata.

A recording is only useful with what was known when it was made: the air temperature
(sound speed, eq. 31), the sweep (band, duration, where it starts), the sample rate, the
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
import stat
import struct
from dataclasses import asdict, dataclass, field, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.io import wavfile

from dstoolkit._reprs import short_repr
from dstoolkit.errors import RecordingFileError, RecordingNotFoundError
from dstoolkit.utils.outputs import atomic_write, check_outputs

METADATA_VERSION = 1
_INT_SCALE = {np.dtype(np.int16): 32768.0, np.dtype(np.int32): 2147483648.0}


@dataclass(frozen=True)
class RecordingMetadata:
    """What is known about a recording besides its samples. Every field may be unknown.

    Parameters
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

    Raises
    ------
    RecordingFileError
        A field of the wrong type, not finite, a length or level that is not positive, or
        a band that does not rise.

    See Also
    --------
    save_recording, load_recording : Store it in a WAV file and read it back.

    Examples
    --------
    >>> from dstoolkit.audio import RecordingMetadata
    >>> meta = RecordingMetadata(temperature_c=20, level_m=9.6)
    >>> meta.temperature_c, meta.latency_s
    (20.0, None)
    >>> RecordingMetadata.from_json(meta.to_json()) == meta
    True
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

    def __repr__(self) -> str:
        return short_repr(self)

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("source", "extra") or value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RecordingFileError(f"{f.name} must be a number or None, got {value!r}")
            try:
                finite = math.isfinite(value)
            except OverflowError:  # an int beyond the float range
                finite = False
            if not finite:
                shown = str(value) if len(str(value)) < 20 else str(value)[:12] + "…"
                raise RecordingFileError(f"{f.name} must be finite or None, got {shown}")
            object.__setattr__(self, f.name, float(value))
        for name in ("f_start_hz", "f_stop_hz", "sweep_duration_s", "level_m"):
            value = getattr(self, name)
            if value is not None and value <= 0:
                raise RecordingFileError(f"{name} must be positive, got {value}")
        if (
            self.f_start_hz is not None
            and self.f_stop_hz is not None
            and self.f_start_hz >= self.f_stop_hz
        ):
            raise RecordingFileError(
                f"the sweep band must rise: f_start_hz {self.f_start_hz} >= f_stop_hz "
                f"{self.f_stop_hz}"
            )
        if self.source is not None and not isinstance(self.source, str):
            raise RecordingFileError(f"source must be a string or None, got {self.source!r}")
        if not isinstance(self.extra, dict):
            raise RecordingFileError(f"extra must be a dict, got {type(self.extra).__name__}")

    def to_json(self) -> str:
        """Return the metadata as one line of JSON, as stored in the WAV file's comment.

        Returns
        -------
        str
            A JSON object with every field and the format's version.

        Raises
        ------
        RecordingFileError
            ``extra`` holds something JSON cannot (a NaN, an object).
        """
        payload = {"dstoolkit_metadata": METADATA_VERSION, **asdict(self)}
        try:
            return json.dumps(payload, allow_nan=False, sort_keys=True)
        except (TypeError, ValueError) as exc:
            raise RecordingFileError(f"metadata cannot be stored as JSON: {exc}") from exc

    @classmethod
    def from_json(cls, text: str) -> RecordingMetadata:
        """Parse metadata written by :meth:`to_json`; a one-line error for anything else.

        Parameters
        ----------
        text : str
            The JSON text. Fields of a newer version go into ``extra``.

        Returns
        -------
        RecordingMetadata
            The metadata it holds.

        Raises
        ------
        RecordingFileError
            Not dstoolkit metadata: not JSON, too long or too deeply nested, a key given
            twice, or fields of the wrong type.
        """
        if len(text) > MAX_METADATA_BYTES:
            raise RecordingFileError(
                f"the metadata holds {len(text)} characters, more than {MAX_METADATA_BYTES}"
            )
        depth = _json_depth(text)
        if depth > MAX_METADATA_DEPTH:
            raise RecordingFileError(
                f"the metadata is nested {depth} levels deep, more than "
                f"{MAX_METADATA_DEPTH}; it is not dstoolkit metadata"
            )
        try:
            payload = json.loads(text, object_pairs_hook=_unique_keys)
        except (json.JSONDecodeError, RecursionError, ValueError) as exc:
            raise RecordingFileError(f"the WAV comment is not dstoolkit metadata: {exc}") from exc
        if not isinstance(payload, dict) or "dstoolkit_metadata" not in payload:
            raise RecordingFileError("the WAV comment is not dstoolkit metadata")
        known = {f.name for f in fields(cls)}
        unknown = set(payload) - known - {"dstoolkit_metadata"}
        extra = payload.get("extra") or {}
        if not isinstance(extra, dict):
            raise RecordingFileError(
                f"the metadata's extra must be an object, got {type(extra).__name__}"
            )
        extra = dict(extra)
        extra.update({k: payload[k] for k in unknown})  # fields of a newer version
        return cls(**{k: v for k, v in payload.items() if k in known - {"extra"}}, extra=extra)


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """Build a JSON object whose keys are all different.

    A key given twice makes the metadata ambiguous (which temperature holds?), so it is
    refused.
    """
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise RecordingFileError(
                f"the metadata gives the key {key!r} twice, so it is "
                "ambiguous; keep one value and save the recording again"
            )
        out[key] = value
    return out


def _json_depth(text: str) -> int:
    """Deepest nesting of [ and { in JSON text (outside strings)."""
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


@dataclass(frozen=True)
class WavRecording:
    """A mono recording as stored in a WAV file.

    :class:`dstoolkit.gauge.Recording` is the gauge's view of a recording, cropped to the
    sweep; :func:`analyze` converts.

    Parameters
    ----------
    samples : ndarray, shape (N,)
        The samples, float, full scale ±1.
    samplerate : int
        Hz.
    metadata : RecordingMetadata
        What is known about it besides the samples.

    See Also
    --------
    load_recording, save_recording : Read and write one.
    """

    samples: np.ndarray
    samplerate: int
    metadata: RecordingMetadata = field(default_factory=RecordingMetadata)

    @property
    def duration_s(self) -> float:
        """The length of the recording, s.

        Returns
        -------
        float
            ``samples.size / samplerate``.
        """
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
    overwrite: bool = False,
) -> None:
    """Write a mono recording and its metadata to a WAV file.

    Parameters
    ----------
    path : path-like
        The file to write, atomically (a temporary file renamed over it: a failure leaves
        no partial file).
    samples : array_like, 1-D
        Full scale ±1.
    samplerate : int
        Hz.
    metadata : RecordingMetadata, optional
        Stored as JSON in the LIST/INFO comment.
    sample_format : {"float32", "int16"}
        float32 keeps the samples as recorded; int16 is read by every program but
        quantises, and refuses samples beyond ±1.
    overwrite : bool
        Replace an existing file. By default an existing file is kept and
        :class:`~dstoolkit.errors.OutputExistsError` is raised.

    Raises
    ------
    RecordingFileError
        Samples that are not real, finite and 1-D, a sample rate outside 1 kHz–1 MHz, a
        peak beyond ±1 in int16, or a file :func:`load_recording` could not read back.
    OutputExistsError
        The file exists and ``overwrite`` is False.

    See Also
    --------
    load_recording : Reads it back.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from dstoolkit.audio import RecordingMetadata, load_recording, save_recording
    >>> path = os.path.join(tempfile.mkdtemp(), "tone.wav")
    >>> tone = 0.5 * np.sin(2 * np.pi * 440 * np.arange(8000) / 8000)
    >>> save_recording(path, tone, 8000, RecordingMetadata(temperature_c=21.0))
    >>> back = load_recording(path)
    >>> back.samplerate, back.duration_s, back.metadata.temperature_c
    (8000, 1.0, 21.0)
    >>> bool(np.array_equal(back.samples, tone.astype(np.float32)))
    True
    """
    given = np.asarray(samples)
    if given.dtype.kind not in "biuf":
        raise RecordingFileError(
            f"samples must be real numbers, got an array of {given.dtype} (complex samples "
            "would lose their imaginary part); give the real signal"
        )
    x = given.astype(float)
    if x.ndim == 2 and x.shape[1] == 1:
        x = x[:, 0]
    if x.ndim != 1 or x.size == 0:
        raise RecordingFileError(f"samples must be a non-empty 1-D array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise RecordingFileError("samples contain NaN or infinite values")
    limit = float(np.finfo(np.float32).max)
    if sample_format == "float32" and float(np.max(np.abs(x))) > limit:
        raise RecordingFileError(
            f"samples reach {float(np.max(np.abs(x))):.3g}, beyond what a 32-bit float WAV "
            f"holds ({limit:.3g}); scale them to full scale ±1"
        )
    if (
        isinstance(samplerate, bool)
        or not isinstance(samplerate, int | float | np.number)
        or not math.isfinite(samplerate)
        or int(samplerate) != samplerate
        or not 1000 <= samplerate <= 1_000_000
    ):
        raise RecordingFileError(
            f"samplerate must be a whole number of Hz from 1 kHz to 1 MHz "
            f"(what load_recording reads), got {samplerate!r}"
        )
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
    _readable(bytes(riff), path)
    if not overwrite:
        check_outputs({"the recording": path})
    atomic_write(path, lambda fh: fh.write(riff))


def _readable(riff: bytes, path: str | os.PathLike[str]) -> None:
    """Refuse to write a file that :func:`load_recording` would refuse.

    That is a file too large, or metadata over :data:`MAX_METADATA_BYTES` or nested too
    deep.
    """
    if len(riff) > MAX_RECORDING_BYTES:
        raise RecordingFileError(
            f"the recording would take {len(riff) / 2**20:.0f} MiB, more than the "
            f"{MAX_RECORDING_BYTES // 2**20} MiB load_recording reads; save a shorter one"
        )
    try:
        read_metadata(read_layout(io.BytesIO(riff), len(riff), path).info)
    except RecordingFileError as exc:
        raise RecordingFileError(f"not saved, as it could not be read back: {exc}") from None


#: Largest recording file read, bytes (256 MiB: 25 minutes of 32-bit float at 44.1 kHz);
#: the analysis needs a few times the file size in memory, and a gauge recording lasts
#: seconds.
MAX_RECORDING_BYTES = 256 * 2**20
#: Largest LIST (metadata) chunk read, bytes; dstoolkit writes well under 1 KiB.
MAX_METADATA_BYTES = 64 * 2**10
#: Deepest nesting of JSON arrays and objects accepted in the metadata.
MAX_METADATA_DEPTH = 32
#: Chunks walked in a RIFF file at most (a real WAV has 2 to 5).
MAX_CHUNKS = 1000
_FORMATS = {1: "PCM", 3: "float"}


@dataclass(frozen=True)
class WavLayout:
    """Where the samples of a WAV file are and how they are encoded (its fmt chunk)."""

    encoding: str  # "PCM" or "float"
    channels: int
    samplerate: int
    bits: int
    block_align: int
    data_offset: int
    frames: int
    big_endian: bool
    info: dict[bytes, str]


def _open_regular(path: str | os.PathLike[str]) -> tuple[Any, int]:
    """Open a regular file for reading without blocking (a FIFO would wait for a writer)."""
    name = os.fspath(path)
    try:
        fd = os.open(name, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise RecordingNotFoundError(f"{name!r}: No such file; check the path") from None
    except IsADirectoryError:
        raise RecordingFileError(f"{name!r} is a folder, not a WAV file") from None
    except OSError as exc:  # a socket, a symbolic link loop, no permission...
        raise RecordingFileError(
            f"cannot open {name!r}: {exc.strerror or exc}; give the path of a readable WAV file"
        ) from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise RecordingFileError(
            f"{name!r} is not a regular file (a pipe, a device or a folder); give the path "
            "of a WAV file"
        )
    if st.st_size > MAX_RECORDING_BYTES:
        os.close(fd)
        raise RecordingFileError(
            f"{name!r} holds {st.st_size / 2**20:.0f} MiB, more than the "
            f"{MAX_RECORDING_BYTES // 2**20} MiB a recording may have; cut the recording to "
            "the measurement (a few seconds)"
        )
    return os.fdopen(fd, "rb"), int(st.st_size)


def _bad(path: str | os.PathLike[str], why: str) -> RecordingFileError:
    return RecordingFileError(f"cannot read the WAV file {os.fspath(path)!r}: {why}")


def _parse_fmt(
    body: bytes, path: str | os.PathLike[str], endian: str
) -> tuple[str, int, int, int, int]:
    if len(body) < 16:
        raise _bad(path, f"its fmt chunk has {len(body)} bytes, fewer than 16 (truncated)")
    tag, channels, rate, _, align, bits = struct.unpack(endian + "HHIIHH", body[:16])
    if tag == 0xFFFE and len(body) >= 26:  # WAVE_FORMAT_EXTENSIBLE: the sub-format decides
        tag = struct.unpack(endian + "H", body[24:26])[0]
    if tag not in _FORMATS:
        raise _bad(path, f"encoding {tag:#x} is not supported; save it as PCM or float WAV")
    encoding = _FORMATS[tag]
    if not 1 <= channels <= 64:
        raise _bad(path, f"its fmt chunk says {channels} channels (need 1 to 64)")
    if not 1000 <= rate <= 1_000_000:
        raise _bad(path, f"its fmt chunk says a sample rate of {rate} Hz (need 1 kHz to 1 MHz)")
    allowed = (8, 16, 24, 32) if encoding == "PCM" else (32, 64)
    if bits not in allowed:
        raise _bad(
            path,
            f"{bits}-bit {encoding} samples are not supported (only "
            f"{', '.join(map(str, allowed))} bits)",
        )
    if align != channels * bits // 8:
        raise _bad(
            path,
            f"its fmt chunk's block size {align} does not match {channels} "
            f"channel(s) of {bits} bits",
        )
    return encoding, channels, rate, bits, align


def _parse_info(body: bytes, path: str | os.PathLike[str]) -> dict[bytes, str]:
    info: dict[bytes, str] = {}
    sub = 4
    for _ in range(MAX_CHUNKS):
        if sub + 8 > len(body):
            break
        stag, ssize = body[sub : sub + 4], struct.unpack("<I", body[sub + 4 : sub + 8])[0]
        text = body[sub + 8 : sub + 8 + ssize].rstrip(b"\0")
        if stag in info:
            raise _bad(
                path,
                f"its metadata gives the field {stag.decode('latin-1')!r} twice, "
                "so it is ambiguous; keep one and save the recording again",
            )
        info[stag] = text.decode("utf-8", errors="replace")
        sub += 8 + ssize + ssize % 2
    return info


def read_layout(fh: Any, size: int, path: str | os.PathLike[str]) -> WavLayout:
    """Walk the RIFF chunks of an open WAV file.

    Find the format, where the samples are, and the LIST/INFO text fields (at most
    :data:`MAX_METADATA_BYTES`). Reads no samples.
    """
    head = fh.read(12)
    if len(head) < 12 or head[:4] not in (b"RIFF", b"RIFX") or head[8:12] != b"WAVE":
        raise RecordingFileError(
            f"{os.fspath(path)!r} is not a WAV file (it starts with {head[:12]!r}); "
            "save recordings with dstoolkit.audio.save_recording"
        )
    endian = ">" if head[:4] == b"RIFX" else "<"
    fmt: tuple[str, int, int, int, int] | None = None
    data: tuple[int, int] | None = None
    info: dict[bytes, str] = {}
    seen_info = False
    pos = 12
    for _ in range(MAX_CHUNKS):
        if pos + 8 > size:
            break
        fh.seek(pos)
        tag, chunk = struct.unpack(endian[0] + "4sI", fh.read(8))
        body_at = pos + 8
        if tag == b"data":
            if data is not None:
                raise _bad(path, "it has two data chunks")
            if chunk > size - body_at:
                raise _bad(
                    path,
                    f"its data chunk claims {chunk} bytes but only "
                    f"{size - body_at} follow (the file is truncated)",
                )
            data = (body_at, chunk)
        elif tag == b"fmt ":
            if chunk > 1024 or chunk > size - body_at:
                raise _bad(path, f"its fmt chunk claims {chunk} bytes (truncated or corrupt)")
            if fmt is not None:
                raise _bad(
                    path,
                    "it has two fmt chunks, so its sample format is ambiguous; keep one and "
                    "save the recording again",
                )
            fmt = _parse_fmt(fh.read(chunk), path, endian)
        elif tag == b"LIST":
            if chunk > MAX_METADATA_BYTES:
                raise _bad(
                    path,
                    f"its LIST (metadata) chunk holds {chunk} bytes, more than "
                    f"the {MAX_METADATA_BYTES} a recording's metadata may have",
                )
            body = fh.read(min(chunk, size - body_at))
            if body[:4] == b"INFO":
                if seen_info:
                    raise _bad(
                        path,
                        "it has two LIST/INFO (metadata) chunks, so its metadata "
                        "is ambiguous; keep one and save the recording again",
                    )
                seen_info = True
                info.update(_parse_info(body, path))
        pos = body_at + chunk + chunk % 2
    else:
        raise _bad(path, f"it has more than {MAX_CHUNKS} chunks")
    if fmt is None:
        raise _bad(path, "it has no fmt chunk (truncated or not a WAV file)")
    if data is None:
        raise _bad(path, "it has no data chunk (truncated)")
    encoding, channels, rate, bits, align = fmt
    return WavLayout(
        encoding, channels, rate, bits, align, data[0], data[1] // align, endian == ">", info
    )


def read_samples(fh: Any, layout: WavLayout, channel: int, stop: int | None = None) -> np.ndarray:
    """Read frames [0, stop) of one channel as float64 at full scale ±1.

    PCM is scaled, unsigned 8-bit centred; memory: the raw frames plus 8 bytes per sample.
    """
    frames = layout.frames if stop is None else max(0, min(stop, layout.frames))
    fh.seek(layout.data_offset)
    raw = fh.read(frames * layout.block_align)
    width = layout.bits // 8
    end = ">" if layout.big_endian else "<"
    rows = np.frombuffer(raw, dtype=np.uint8).reshape(frames, layout.block_align)
    cell = np.ascontiguousarray(rows[:, channel * width : (channel + 1) * width])
    if layout.encoding == "float":
        return cell.view(f"{end}f{width}")[:, 0].astype(float)
    if width == 1:
        return (cell[:, 0].astype(float) - 128.0) / 128.0
    if width == 3:  # 24-bit: widen to int32 left-justified
        wide = np.zeros((frames, 4), dtype=np.uint8)
        wide[:, 1:] = cell if end == "<" else cell[:, ::-1]
        return wide.view("<i4")[:, 0] / 2147483648.0
    return cell.view(f"{end}i{width}")[:, 0] / {2: 32768.0, 4: 2147483648.0}[width]


def read_metadata(info: dict[bytes, str]) -> RecordingMetadata:
    """Read the dstoolkit metadata stored in the ICMT comment, or unknown metadata."""
    comment = info.get(b"ICMT")
    if comment is not None and comment.lstrip().startswith("{") and "dstoolkit_metadata" in comment:
        return RecordingMetadata.from_json(comment)
    return RecordingMetadata()


def open_recording(path: str | os.PathLike[str]) -> tuple[Any, WavLayout]:
    """Open a WAV file (regular, not too large) and read its layout; the caller closes it."""
    fh, size = _open_regular(path)
    try:
        return fh, read_layout(fh, size, path)
    except BaseException:
        fh.close()
        raise


def load_recording(
    path: str | os.PathLike[str], *, channel: int = 0, stop_s: float | None = None
) -> WavRecording:
    """Read a WAV file written by :func:`save_recording`, or any other WAV file.

    Samples come back as float64 at full scale ±1 (16/24/32-bit PCM are scaled, unsigned
    8-bit centred). A file without dstoolkit metadata loads with every metadata field
    unknown; a multichannel file gives its channel ``channel``. ``stop_s`` reads only the
    first ``stop_s`` seconds.

    Hostile files are refused with a one-line :class:`~dstoolkit.errors.RecordingFileError`: not a
    regular file (a pipe, a device), larger than :data:`MAX_RECORDING_BYTES`, truncated chunks, an
    impossible format, metadata over :data:`MAX_METADATA_BYTES` or nested deeper than
    :data:`MAX_METADATA_DEPTH`, fields of the wrong type.

    Parameters
    ----------
    path : path-like
        The WAV file.
    channel : int
        Which channel of a multichannel file to read (0 is the first).
    stop_s : float, optional
        Read only the first ``stop_s`` seconds; None reads the whole file.

    Returns
    -------
    WavRecording
        The samples as float64 at full scale ±1, the sample rate and the metadata.

    Raises
    ------
    RecordingFileError
        Not a WAV file, an unreadable one, or a channel it does not have.
    RecordingNotFoundError
        No such file (also a FileNotFoundError).

    See Also
    --------
    save_recording : Writes one.

    Examples
    --------
    A file without dstoolkit metadata loads with every field unknown:

    >>> import os, tempfile
    >>> import numpy as np
    >>> from scipy.io import wavfile
    >>> from dstoolkit.audio import load_recording
    >>> path = os.path.join(tempfile.mkdtemp(), "plain.wav")
    >>> wavfile.write(path, 16000, np.full(1600, 16384, dtype=np.int16))
    >>> rec = load_recording(path)
    >>> rec.duration_s, float(rec.samples[0]), rec.metadata.temperature_c
    (0.1, 0.5, None)
    """
    fh, layout = open_recording(path)
    with fh:
        if isinstance(channel, bool) or not isinstance(channel, int | np.integer):
            raise RecordingFileError(f"channel must be a whole number, got {channel!r}")
        if not 0 <= channel < layout.channels:
            raise RecordingFileError(
                f"{os.fspath(path)!r} has {layout.channels} channels; channel {channel} does "
                "not exist"
                if layout.channels > 1
                else f"{os.fspath(path)!r} is mono; channel {channel} does not exist"
            )
        metadata = read_metadata(layout.info)
        stop = None
        if stop_s is not None:
            if not (isinstance(stop_s, int | float) and stop_s > 0 and math.isfinite(stop_s)):
                raise RecordingFileError(
                    f"stop_s must be a positive number of seconds, got {stop_s!r}"
                )
            wanted = stop_s * layout.samplerate
            stop = layout.frames if wanted >= layout.frames else math.ceil(wanted)
        samples = read_samples(fh, layout, channel, stop)
    if samples.size == 0:
        raise _bad(path, "it holds no samples")
    return WavRecording(samples=samples, samplerate=layout.samplerate, metadata=metadata)
