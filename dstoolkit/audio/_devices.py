"""Real audio for the gauge: devices, simultaneous play and record, latency.

The gauge of the paper (§4) plays a sweep into the tube through a speaker and records the
standing wave with a microphone at the same time. This module does that with
`sounddevice <https://python-sounddevice.readthedocs.io>`_ (PortAudio). sounddevice is an
optional dependency: it is imported only by short-lived child processes that list the
devices (``_query_child.py``) or run a stream (``_stream_child.py``), so ``import
dstoolkit`` and every simulation work without it, the caller's process (a notebook's
kernel) never keeps PortAudio's memory, and an audio call without it raises
:class:`~dstoolkit.errors.AudioUnavailableError` saying what to install.

Latency. Between the first sample handed to the output and its arrival in the input lies
the audio path's delay τ (buffers of PortAudio, ALSA, the sound server and the sound card).
For a linear sweep of rate κ Hz/s it shifts every detected resonance by κ τ (paper §4.3),
so it must be measured and corrected: :func:`dstoolkit.gauge.estimate_latency` finds τ by
cross-correlating a known reference (the :func:`calibration_chirp`) with the recording (a
pure array function of the gauge layer, which also uses it on the sweep itself). The delay
changes each time a stream is opened, so the chirp belongs in the same stream as the sweep
it calibrates (:func:`play_record` of chirp + sweep).

Headless machines and CI reach a software loopback made by ``scripts/audio-loopback.sh``
(a PulseAudio null sink and its monitor, seen by PortAudio as the ALSA device ``pulse``).
"""

from __future__ import annotations

import importlib
import json
import os
import select
import socket
import subprocess
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any, Literal, NoReturn

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from dstoolkit.errors import (
    AudioDropoutWarning,
    AudioServerError,
    AudioStallError,
    AudioUnavailableError,
    DetectionError,
    InvalidInputError,
    NoAudioDeviceError,
)
from dstoolkit.gauge import LatencyEstimate, estimate_latency
from dstoolkit.utils.checks import as_signal

from ._query_child import answer

#: Silence played before and after a signal, in seconds, at least. The input stream may
#: start a little after the output stream and the delay τ may reach a few hundred ms: the
#: lead-in and the tail keep the whole signal inside the recording.
MIN_PADDING_S = 0.5
#: PortAudio's suggested latency (s) that returned the signal intact through the loopback.
DEFAULT_LATENCY_S = 0.25
#: Seconds allowed for the stream's process to start and import sounddevice.
STREAM_START_TIMEOUT_S = 30.0
#: Seconds allowed for PortAudio to open the stream (a stalled server never does).
STREAM_OPEN_TIMEOUT_S = 5.0
#: Seconds past its expected length after which a stream counts as stalled.
STREAM_GRACE_S = 3.0
#: Smallest |normalised correlation| at which a calibration chirp counts as found.
MIN_CALIBRATION_CORRELATION = 0.3

INSTALL_HINT = (
    "Install PortAudio and sounddevice: `apt-get install libportaudio2` (Debian/Ubuntu; "
    "`brew install portaudio` on macOS) and `pip install 'dstoolkit[audio]'`. Everything "
    "else in dstoolkit works without them, and the virtual tube simulates a measurement."
)
NO_DEVICE_HINT = (
    "Plug in a sound card, microphone and speaker and check they are not muted, or on a "
    "machine without sound hardware start the software loopback "
    "`export $(bash scripts/audio-loopback.sh)` in the shell that runs Python. "
    "dstoolkit.audio.list_devices() shows what PortAudio sees."
)


def _sounddevice() -> ModuleType:
    """Import sounddevice.

    Raise :class:`~dstoolkit.errors.AudioUnavailableError` saying what to install when it
    cannot be imported.

    Without the PortAudio library ``import sounddevice`` raises ``OSError`` (not
    ``ImportError``); without the package it raises ``ImportError``. Both are caught.
    """
    try:
        # by name: sounddevice ships no type information, and every use goes through here
        sounddevice = importlib.import_module("sounddevice")
    except (ImportError, OSError) as exc:
        raise _unavailable(f"{type(exc).__name__}: {exc}") from exc
    return sounddevice


def _unavailable(reason: str) -> AudioUnavailableError:
    """Return the error of a failed ``import sounddevice`` (``reason``: its type and message)."""
    return AudioUnavailableError(
        f"real audio is unavailable: importing sounddevice failed ({reason}). {INSTALL_HINT}"
    )


def _ask_portaudio(
    request: list[object], refused: Callable[[str], Exception] = NoAudioDeviceError
) -> Any:
    """Return PortAudio's answer to ``request`` (see ``_query_child.py``).

    When sounddevice is already imported in this process (or stands imitated in
    ``sys.modules``), it answers here; otherwise a short-lived child process imports it and
    answers, so that this process never loads PortAudio (tens of MiB kept for as long as
    the process lives). Each child initialises PortAudio afresh, so it sees the devices
    present now.

    Raises :class:`~dstoolkit.errors.AudioUnavailableError` when sounddevice cannot be
    imported, ``refused(message)`` with PortAudio's message when it refuses the query,
    :class:`~dstoolkit.errors.AudioStallError` when the child does not answer within
    :data:`STREAM_START_TIMEOUT_S` and :class:`~dstoolkit.errors.AudioServerError` when it
    ends without an answer.
    """
    if "sounddevice" in sys.modules:
        reply = answer(_sounddevice(), request)
    else:
        reply = _ask_child(request)
    if "refused" in reply:
        raise refused(reply["refused"])
    return reply["answer"]


def _ask_child(request: list[object]) -> dict[str, Any]:
    """Return the reply of a short-lived ``_query_child.py`` to ``request``."""
    child = Path(__file__).with_name("_query_child.py")
    try:
        proc = subprocess.run(
            [sys.executable, str(child), json.dumps(request)],
            capture_output=True,
            text=True,
            timeout=STREAM_START_TIMEOUT_S,
            check=False,
        )
    except subprocess.TimeoutExpired as exc:
        check_sound_server()
        raise AudioStallError(
            f"PortAudio did not list the sound devices within {STREAM_START_TIMEOUT_S:g} s: "
            "the sound server or a device stopped responding; restart it (for the software "
            "loopback: bash scripts/audio-loopback.sh stop, then start) and try again."
        ) from exc
    try:
        reply = json.loads(proc.stdout.strip().splitlines()[-1])
    except (IndexError, ValueError):
        said = proc.stderr.strip().splitlines()[-1:]
        check_sound_server()
        raise AudioServerError(
            f"the process asking PortAudio for the sound devices ended without an answer "
            f"(exit code {proc.returncode}{': ' + said[0] if said else ''}); check the sound "
            "server and try again"
        ) from None
    if "unavailable" in reply:
        raise _unavailable(reply["unavailable"])
    return dict(reply)


def audio_available() -> bool:
    """Whether real audio can be used here.

    Returns
    -------
    bool
        True when sounddevice imports and PortAudio sees at least one device; False when
        sounddevice or PortAudio is missing or there is no device. Never raises for those.

    See Also
    --------
    list_devices : The devices themselves.
    simulate_measurement : A measurement without any device.

    Examples
    --------
    >>> from dstoolkit.audio import audio_available
    >>> isinstance(audio_available(), bool)
    True
    """
    try:
        return len(list_devices()) > 0
    except AudioUnavailableError:
        return False


def refresh_devices() -> None:
    """Make PortAudio scan the devices again.

    PortAudio scans only when it is initialised, at ``import sounddevice``; call this after
    a sound server started or a USB card was plugged in, then :func:`list_devices`. When
    sounddevice is not imported in this process, every list is made by a new process that
    scans anyway: this only checks that sounddevice imports.

    Raises
    ------
    AudioUnavailableError
        sounddevice or PortAudio is not installed.

    See Also
    --------
    list_devices : What PortAudio sees after the scan.

    Examples
    --------
    >>> from dstoolkit.audio import list_devices, refresh_devices
    >>> from dstoolkit.errors import AudioUnavailableError
    >>> try:
    ...     refresh_devices()
    ...     found = list_devices()
    ... except AudioUnavailableError:  # no sounddevice or PortAudio on this machine
    ...     found = []
    >>> isinstance(found, list)
    True
    """
    if "sounddevice" not in sys.modules:
        # PortAudio is not loaded here: every list is made by a new process, which scans.
        _ask_portaudio(["import"])
        return
    sd = _sounddevice()
    # sounddevice has no public re-scan; terminate/initialise is its documented idiom.
    sd._terminate()
    sd._initialize()


@dataclass(frozen=True)
class AudioDevice:
    """One PortAudio device, as :func:`list_devices` reports it.

    Parameters
    ----------
    index : int
        PortAudio's index of the device (what :func:`choose_device` returns).
    name : str
        The device's name, e.g. ``"pulse"`` for the software loopback.
    hostapi : str
        The host API that reaches it (ALSA, PulseAudio, Core Audio, WASAPI, ...).
    max_input_channels, max_output_channels : int
        Channels it records and plays (0: it does not record, or does not play).
    default_samplerate : float
        Its default sample rate, Hz.
    default_input, default_output : bool
        Whether it is the system's default input or output device.

    See Also
    --------
    list_devices : Every device PortAudio sees.

    Examples
    --------
    >>> from dstoolkit.audio import AudioDevice
    >>> print(AudioDevice(4, "pulse", "ALSA", 32, 32, 44100.0, True, True))
    <>  4 pulse (ALSA, 32 in, 32 out, 44100 Hz)
    """

    index: int
    name: str
    hostapi: str
    max_input_channels: int
    max_output_channels: int
    default_samplerate: float
    default_input: bool
    default_output: bool

    def __str__(self) -> str:
        mark = ("<" if self.default_input else " ") + (">" if self.default_output else " ")
        return (
            f"{mark} {self.index:2d} {self.name} ({self.hostapi}, "
            f"{self.max_input_channels} in, {self.max_output_channels} out, "
            f"{self.default_samplerate:g} Hz)"
        )


def list_devices(kind: Literal["input", "output"] | None = None) -> list[AudioDevice]:
    """List the sound devices PortAudio sees.

    Parameters
    ----------
    kind : {"input", "output"}, optional
        Keep only devices with input (microphone) or output (speaker) channels.

    Returns
    -------
    list of AudioDevice
        Possibly empty. ``default_input``/``default_output`` mark the system defaults.

    Raises
    ------
    AudioUnavailableError
        sounddevice or PortAudio is not installed.
    NoAudioDeviceError
        PortAudio could not list the devices.
    InvalidInputError
        ``kind`` is neither "input", "output" nor None.

    See Also
    --------
    choose_device : One device by index or name.
    refresh_devices : Scan again after plugging a device in.

    Examples
    --------
    >>> from dstoolkit.audio import list_devices
    >>> from dstoolkit.errors import AudioUnavailableError
    >>> try:
    ...     inputs = list_devices("input")
    ... except AudioUnavailableError:  # no sounddevice or PortAudio on this machine
    ...     inputs = []
    >>> all(device.max_input_channels > 0 for device in inputs)
    True
    """
    if kind not in (None, "input", "output"):
        raise InvalidInputError(f"kind must be 'input', 'output' or None, not {kind!r}")
    seen = _ask_portaudio(
        ["devices"],
        lambda said: NoAudioDeviceError(
            f"PortAudio could not list devices: {said}. {NO_DEVICE_HINT}"
        ),
    )
    default_in, default_out = seen["default"]
    devices = [
        AudioDevice(
            **info,
            default_input=info["index"] == default_in,
            default_output=info["index"] == default_out,
        )
        for info in seen["devices"]
    ]
    if kind == "input":
        return [d for d in devices if d.max_input_channels > 0]
    if kind == "output":
        return [d for d in devices if d.max_output_channels > 0]
    return devices


def choose_device(device: int | str | None, kind: Literal["input", "output"]) -> int:
    """Resolve a device given by index, by (part of) its name, or None for the default.

    Parameters
    ----------
    device : int or str or None
        PortAudio index, (part of) a name as :func:`list_devices` shows it, or None for
        the system's default device of that kind.
    kind : {"input", "output"}
        Whether the device must record or play.

    Returns
    -------
    int
        The PortAudio index of the device.

    Raises
    ------
    NoAudioDeviceError
        There is no such device (or no default one); the message lists the devices that
        exist.
    AudioUnavailableError
        sounddevice or PortAudio is not installed.
    InvalidInputError
        ``kind`` is neither "input" nor "output".

    See Also
    --------
    list_devices : The devices to choose from.

    Examples
    --------
    The kind is checked before any device is looked at:

    >>> from dstoolkit.audio import choose_device
    >>> choose_device(None, "speaker")
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: kind must be 'input' or 'output', not 'speaker'
    """
    if kind not in ("input", "output"):
        raise InvalidInputError(f"kind must be 'input' or 'output', not {kind!r}")

    def no_such_device(said: str) -> NoAudioDeviceError:
        available = list_devices(kind)
        listing = "\n".join(str(d) for d in available) or "  (none)"
        wanted = "the default" if device is None else repr(device)
        advice = "Pass one of these indices or names." if available else NO_DEVICE_HINT
        return NoAudioDeviceError(
            f"no {kind} device for {wanted}: {said}. {kind.capitalize()} devices PortAudio "
            f"sees:\n{listing}\n{advice}"
        )

    return int(_ask_portaudio(["device", device, kind], no_such_device))


def calibration_chirp(
    samplerate: float,
    *,
    duration_s: float = 0.25,
    f_start_hz: float = 500.0,
    f_stop_hz: float = 5000.0,
    amplitude: float = 0.5,
) -> np.ndarray:
    """Make a short windowed linear chirp whose autocorrelation has one sharp peak.

    Played before the sweep in the same stream, its position in the recording gives the
    audio latency τ that shifts every detected resonance (the paper's §4.3;
    :func:`~dstoolkit.gauge.estimate_latency`). The band suits laptop speakers and
    microphones; its ends are tapered (Tukey window) so it starts and stops without clicks.

    Parameters
    ----------
    samplerate : float
        Sample rate, Hz.
    duration_s : float
        Length of the chirp, s.
    f_start_hz, f_stop_hz : float
        Band of the chirp, Hz; 0 < f_start_hz < f_stop_hz < samplerate / 2.
    amplitude : float
        Peak amplitude, full scale.

    Returns
    -------
    ndarray, shape (round(duration_s * samplerate),)
        The samples, full scale.

    Raises
    ------
    InvalidInputError
        A sample rate or duration that is not positive, or a band outside (0, samplerate/2).

    See Also
    --------
    dstoolkit.gauge.estimate_latency : Finds the chirp in a recording.
    measure_latency : Plays the chirp and finds it.

    Examples
    --------
    A chirp found again in a recording that lags by 0.1 s (no sound device needed):

    >>> import numpy as np
    >>> from dstoolkit.audio import calibration_chirp
    >>> from dstoolkit.gauge import estimate_latency
    >>> chirp = calibration_chirp(16000)
    >>> chirp.shape
    (4000,)
    >>> recorded = np.concatenate([np.zeros(1600), chirp, np.zeros(1600)])
    >>> estimate_latency(chirp, recorded, 16000).seconds
    0.1
    """
    if samplerate <= 0 or duration_s <= 0:
        raise InvalidInputError(
            f"samplerate ({samplerate}) and duration_s ({duration_s}) must be positive"
        )
    if not 0 < f_start_hz < f_stop_hz < samplerate / 2:
        raise InvalidInputError(
            f"need 0 < f_start_hz ({f_start_hz}) < f_stop_hz ({f_stop_hz}) < samplerate/2 "
            f"({samplerate / 2})"
        )
    n = int(round(duration_s * samplerate))
    t = np.arange(n) / samplerate
    chirp = signal.chirp(t, f_start_hz, duration_s, f_stop_hz, method="linear")
    return amplitude * chirp * signal.windows.tukey(n, 0.2)


@dataclass(frozen=True)
class PlayRecordResult:
    """What :func:`play_record` played and recorded, sample for sample from the start.

    Parameters
    ----------
    played : ndarray, shape (N,)
        The signal with its lead-in and tail of silence, full scale.
    recorded : ndarray, shape (N,)
        What the input recorded meanwhile, full scale; as long as ``played``.
    samplerate : float
        Hz, both directions.
    signal_start : int
        Index in ``played`` of the signal's first sample.
    latency_setting : float or str
        The latency asked of PortAudio (s, or "low"/"high").
    input_device, output_device : int
        PortAudio indices of the devices used.
    status : str
        PortAudio's summary of the stream's flags.
    dropped_samples : bool
        True when the flags say input was lost or output was late (the recording then has
        gaps).

    See Also
    --------
    play_record : Makes it.
    """

    played: np.ndarray
    recorded: np.ndarray
    samplerate: float
    signal_start: int
    latency_setting: float | str
    input_device: int
    output_device: int
    status: str
    dropped_samples: bool

    def segment(self, start: int, length: int, latency: LatencyEstimate) -> np.ndarray:
        """Return the recording of ``played[start:start + length]``, corrected for the latency.

        Parameters
        ----------
        start : int
            Index in ``played`` of the first sample wanted.
        length : int
            Number of samples.
        latency : LatencyEstimate
            The latency τ of this stream (:func:`~dstoolkit.gauge.estimate_latency`).

        Returns
        -------
        ndarray, shape (length,)
            ``recorded[start + lag : start + lag + length]``, full scale (a view).

        Raises
        ------
        DetectionError
            The recording does not cover it (a recording too short for the sweep: play a
            longer tail).
        """
        first = start + latency.lag
        if first < 0 or first + length > self.recorded.size:
            raise DetectionError(
                f"the recording does not hold the whole signal: it needs samples "
                f"{first}..{first + length} after a latency of {latency.seconds:.3f} s, the "
                f"recording has 0..{self.recorded.size}. Play a longer lead-in/tail "
                f"(at least the latency plus {MIN_PADDING_S} s)."
            )
        return self.recorded[first : first + length]


def play_record(
    x: ArrayLike,
    samplerate: int,
    *,
    input_device: int | str | None = None,
    output_device: int | str | None = None,
    lead_in_s: float = MIN_PADDING_S,
    tail_s: float = MIN_PADDING_S,
    latency: float | Literal["low", "high"] = DEFAULT_LATENCY_S,
) -> PlayRecordResult:
    """Play a signal and record at the same time (``sounddevice.playrec``), mono.

    Silence of ``lead_in_s`` before and ``tail_s`` after the signal makes sure the
    recording holds all of it whatever the latency (both at least ``MIN_PADDING_S``).

    Parameters
    ----------
    x : array_like, 1-D
        Samples in [-1, 1] (a larger peak would clip in the sound card).
    samplerate : int
        Hz, for both directions.
    input_device, output_device : int or str, optional
        Index or (part of a) name, see :func:`list_devices`; None for the defaults.
    lead_in_s, tail_s : float
        Silence before and after, seconds.
    latency : float or "low" or "high"
        PortAudio's suggested latency (s). ``DEFAULT_LATENCY_S`` worked through the
        PulseAudio loopback; very low values risk dropped samples.

    Returns
    -------
    PlayRecordResult
        What was played and recorded, sample for sample.

    Raises
    ------
    AudioUnavailableError
        sounddevice/PortAudio missing (``INSTALL_HINT``); its subclass
        NoAudioDeviceError when there is no device or it fails to open;
        AudioStallError when the stream stops moving (it does not open within
        :data:`STREAM_OPEN_TIMEOUT_S`, or it runs :data:`STREAM_GRACE_S` past its length:
        the stream runs in a child process, which is then killed);
        AudioServerError when the PulseAudio server died (:func:`check_sound_server`).
    InvalidInputError
        Bad signal or settings (also a ValueError); checked before any device is opened.

    Warns
    -----
    AudioDropoutWarning
        The stream dropped samples: the recording has gaps.

    See Also
    --------
    simulate_measurement : The same programme through a simulated loopback, no device.
    measure_latency : Play and record a calibration chirp.

    Examples
    --------
    The signal is checked before any device is opened (a measurement without a sound
    device goes through :func:`simulate_measurement` instead):

    >>> from dstoolkit.audio import play_record
    >>> play_record([0.0, 1.5, 0.0], 44100)
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: the signal peaks at 1.5 > 1 and would clip: scale it down
    """
    sig = as_signal(x, "signal")
    peak = float(np.max(np.abs(sig)))
    if peak > 1.0:
        raise InvalidInputError(f"the signal peaks at {peak:.3g} > 1 and would clip: scale it down")
    if samplerate <= 0 or int(samplerate) != samplerate:
        raise InvalidInputError(
            f"samplerate must be a positive whole number of Hz, got {samplerate}"
        )
    if lead_in_s < MIN_PADDING_S or tail_s < MIN_PADDING_S:
        raise InvalidInputError(
            f"lead_in_s ({lead_in_s}) and tail_s ({tail_s}) must be at least {MIN_PADDING_S} s "
            "so that the latency cannot push the signal out of the recording"
        )
    device_in = choose_device(input_device, "input")
    device_out = choose_device(output_device, "output")
    lead = int(round(lead_in_s * samplerate))
    played = np.concatenate(
        [np.zeros(lead), sig, np.zeros(int(round(tail_s * samplerate)))]
    ).astype(np.float32)
    recorded, status, dropped = _stream(played, int(samplerate), latency, device_in, device_out)
    if dropped:
        warnings.warn(
            f"the audio stream dropped samples ({status}): the recording has gaps. "
            "Use a larger latency (e.g. 0.5) and close other programs using audio.",
            AudioDropoutWarning,
            stacklevel=2,
        )
    return PlayRecordResult(
        played=played.astype(float),
        recorded=np.asarray(recorded, dtype=float),
        samplerate=float(samplerate),
        signal_start=lead,
        latency_setting=latency,
        input_device=device_in,
        output_device=device_out,
        status=status,
        dropped_samples=dropped,
    )


def sound_server_problem() -> str | None:
    """Say what is wrong with the PulseAudio server the environment points at, or None.

    Returns
    -------
    str or None
        A sentence naming the server and what is wrong with it, or None.

    Notes
    -----
    Checks each ``unix:`` socket of ``PULSE_SERVER`` (else ``$PULSE_RUNTIME_PATH/native``
    or ``$XDG_RUNTIME_DIR/pulse/native``): a socket that is missing or refuses connections
    means the server is not running. A server that accepts connections may still be
    stalled (stopped): that shows as an :class:`~dstoolkit.errors.AudioStallError` instead.
    """
    server = os.environ.get("PULSE_SERVER", "")
    paths = [part[5:] for part in server.split() if part.startswith("unix:")]
    if not server:
        for base in (os.environ.get("PULSE_RUNTIME_PATH"), os.environ.get("XDG_RUNTIME_DIR")):
            if base:
                native = (
                    Path(base) / "native"
                    if base == os.environ.get("PULSE_RUNTIME_PATH")
                    else Path(base) / "pulse" / "native"
                )
                if native.exists():
                    paths.append(str(native))
    for path in paths:
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
            sock.settimeout(1.0)
            try:
                sock.connect(path)
            except (FileNotFoundError, ConnectionRefusedError) as exc:
                return f"the PulseAudio sound server at unix:{path} is not running ({exc.strerror})"
            except OSError:
                continue
    return None


def check_sound_server() -> None:
    """Raise :class:`~dstoolkit.errors.AudioServerError` when the sound server has gone away.

    Each ``unix:`` socket of ``PULSE_SERVER`` (else ``$PULSE_RUNTIME_PATH/native`` or
    ``$XDG_RUNTIME_DIR/pulse/native``) is tried: a socket that is missing or refuses
    connections means the server is not running. Without PulseAudio nothing is checked.

    Raises
    ------
    AudioServerError
        The PulseAudio server the environment points at is not running.

    See Also
    --------
    play_record : Calls it when a stream fails.

    Examples
    --------
    A server whose socket does not exist:

    >>> import os, tempfile
    >>> from dstoolkit.audio import check_sound_server
    >>> from dstoolkit.errors import AudioServerError
    >>> saved = os.environ.get("PULSE_SERVER")
    >>> missing = os.path.join(tempfile.mkdtemp(), "native")
    >>> os.environ["PULSE_SERVER"] = "unix:" + missing
    >>> try:
    ...     check_sound_server()
    ... except AudioServerError as exc:
    ...     print("is not running" in str(exc))
    ... finally:
    ...     if saved is None:
    ...         del os.environ["PULSE_SERVER"]
    ...     else:
    ...         os.environ["PULSE_SERVER"] = saved
    True
    """
    problem = sound_server_problem()
    if problem is not None:
        raise AudioServerError(
            f"the sound server died during the measurement: {problem}. Restart it (for the "
            "software loopback: bash scripts/audio-loopback.sh start) and measure again."
        )


def _stream(
    played: np.ndarray, samplerate: int, latency: float | str, device_in: int, device_out: int
) -> tuple[np.ndarray, str, bool]:
    """Play and record in a child process (``_stream_child.py``) under a deadline.

    Returns the recording (float32, as long as ``played``), PortAudio's status and whether
    samples were dropped. Raises :class:`~dstoolkit.errors.AudioStallError` when the stream does not
    open within :data:`STREAM_OPEN_TIMEOUT_S` (the process itself may take
    :data:`STREAM_START_TIMEOUT_S` to start) or does not end within its length plus
    :data:`STREAM_GRACE_S`, :class:`~dstoolkit.errors.AudioServerError` when the sound server died,
    and :class:`~dstoolkit.errors.NoAudioDeviceError` when PortAudio refuses the stream.
    """
    expected = played.size / samplerate
    child = Path(__file__).with_name("_stream_child.py")
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(
            [sys.executable, str(child)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log
        )
        assert proc.stdin is not None and proc.stdout is not None
        try:
            header = {
                "samplerate": samplerate,
                "latency": latency,
                "device": [device_in, device_out],
                "frames": int(played.size),
            }
            try:
                proc.stdin.write(
                    json.dumps(header).encode() + b"\n" + played.astype(np.float32).tobytes()
                )
                proc.stdin.close()
            except BrokenPipeError:
                pass  # the child died at once: reported below
            reader = _Reader(proc.stdout.fileno())
            first = reader.line(time.monotonic() + STREAM_START_TIMEOUT_S)
            if first == b"ready":
                first = reader.line(time.monotonic() + STREAM_OPEN_TIMEOUT_S)
            if first == b"started":
                end = time.monotonic() + expected + STREAM_GRACE_S
                first = reader.line(end)
                if first is None:
                    _stalled(
                        proc,
                        f"no samples came back for {STREAM_GRACE_S:g} s past the "
                        f"stream's expected length of {expected:.1f} s",
                    )
            elif first is None and reader.open:
                _stalled(proc, "the stream did not start")
            if not first:
                proc.kill()
                proc.wait()
                log.seek(0)
                said = log.read().decode(errors="replace").strip().splitlines()[-1:]
                check_sound_server()
                raise AudioServerError(
                    f"the audio stream's process ended without a recording (exit code "
                    f"{proc.returncode}{': ' + said[0] if said else ''}); check the sound "
                    "server and measure again"
                )
            result = json.loads(first)
            if "error" in result:
                proc.wait(timeout=5)
                check_sound_server()
                raise NoAudioDeviceError(
                    f"PortAudio failed to play and record at {samplerate} Hz on input "
                    f"{device_in}, output {device_out}: {result['message']}. Try another "
                    f"sample rate or device. {NO_DEVICE_HINT}"
                )
            data = reader.exact(4 * int(result["frames"]), time.monotonic() + 10.0)
            if data is None:
                _stalled(proc, "the recording did not arrive")
            proc.wait(timeout=5)
            # a server killed mid-stream ends the stream early with silence: say so
            check_sound_server()
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            proc.stdout.close()
    recorded = np.frombuffer(data, dtype=np.float32)
    return recorded, str(result["status"]), bool(result["dropped"])


def _stalled(proc: subprocess.Popen[bytes], what: str) -> NoReturn:
    proc.kill()
    proc.wait()
    check_sound_server()
    raise AudioStallError(
        f"the audio stream stalled: {what}. The sound server or the device stopped "
        "responding; restart it (for the software loopback: bash scripts/audio-loopback.sh "
        "stop, then start) and measure again."
    )


class _Reader:
    """Reads lines and byte counts from a pipe, each by a deadline (None when it passes)."""

    def __init__(self, fd: int) -> None:
        self.fd, self.buffer, self.open = fd, b"", True

    def _fill(self, deadline: float) -> bool:
        timeout = deadline - time.monotonic()
        if timeout <= 0 or not select.select([self.fd], [], [], timeout)[0]:
            return False
        chunk = os.read(self.fd, 1 << 20)
        if not chunk:
            self.open = False
            return False
        self.buffer += chunk
        return True

    def line(self, deadline: float) -> bytes | None:
        while b"\n" not in self.buffer:
            if not self._fill(deadline):
                return b"" if not self.open else None
        line, _, self.buffer = self.buffer.partition(b"\n")
        return line

    def exact(self, n: int, deadline: float) -> bytes | None:
        while len(self.buffer) < n:
            if not self._fill(deadline):
                return None
        data, self.buffer = self.buffer[:n], self.buffer[n:]
        return data


def measure_latency(
    samplerate: int = 44100,
    *,
    input_device: int | str | None = None,
    output_device: int | str | None = None,
    latency: float | Literal["low", "high"] = DEFAULT_LATENCY_S,
    min_correlation: float = MIN_CALIBRATION_CORRELATION,
) -> LatencyEstimate:
    """Play a :func:`calibration_chirp` and find it in the recording.

    The delay differs each time a stream is opened (it did by tens of ms through the
    PulseAudio loopback), so a measurement should carry its own chirp; this function is
    for checking a set-up.

    Parameters
    ----------
    samplerate : int
        Hz, both directions.
    input_device, output_device : int or str, optional
        Index or (part of a) name, see :func:`list_devices`; None for the defaults.
    latency : float or "low" or "high"
        PortAudio's suggested latency, s.
    min_correlation : float
        Smallest |normalised correlation| at which the chirp counts as found.

    Returns
    -------
    LatencyEstimate
        The delay τ (``lag`` in samples, ``seconds``) and how well the chirp matched.

    Raises
    ------
    DetectionError
        The chirp is not found (|correlation| below ``min_correlation``): the microphone
        does not hear the speaker.
    AudioUnavailableError
        No sounddevice/PortAudio or no device (see :func:`play_record`).
    InvalidInputError
        A sample rate that is not positive.

    See Also
    --------
    calibration_chirp : The signal played.
    check_calibration : The test applied to the estimate.

    Examples
    --------
    The settings are checked before any device is opened:

    >>> from dstoolkit.audio import measure_latency
    >>> measure_latency(0)
    Traceback (most recent call last):
    ...
    dstoolkit.errors.InvalidInputError: samplerate (0) and duration_s (0.25) must be positive
    """
    chirp = calibration_chirp(samplerate)
    result = play_record(
        chirp, samplerate, input_device=input_device, output_device=output_device, latency=latency
    )
    estimate = estimate_latency(chirp, result.recorded, samplerate, offset=result.signal_start)
    check_calibration(estimate, min_correlation)
    return estimate


def check_calibration(
    estimate: LatencyEstimate, min_correlation: float = MIN_CALIBRATION_CORRELATION
) -> None:
    """Raise :class:`~dstoolkit.errors.DetectionError` when the calibration chirp was not found.

    Parameters
    ----------
    estimate : LatencyEstimate
        Where the chirp was found and how well it matched
        (:func:`~dstoolkit.gauge.estimate_latency`).
    min_correlation : float
        Smallest |normalised correlation| at which the chirp counts as found.

    Raises
    ------
    DetectionError
        |``estimate.correlation``| is below ``min_correlation``: the input does not hear the
        output.

    See Also
    --------
    measure_latency : Plays the chirp, finds it and checks it.

    Examples
    --------
    >>> from dstoolkit.audio import check_calibration
    >>> from dstoolkit.gauge import LatencyEstimate
    >>> check_calibration(LatencyEstimate(lag=4410, samplerate=44100.0, correlation=0.93,
    ...                                   significance=40.0))
    >>> check_calibration(LatencyEstimate(lag=12, samplerate=44100.0, correlation=0.05,
    ...                                   significance=1.2))
    Traceback (most recent call last):
    ...
    dstoolkit.errors.DetectionError: the calibration chirp was not found in the recording ...
    """
    if abs(estimate.correlation) < min_correlation:
        raise DetectionError(
            f"the calibration chirp was not found in the recording (correlation "
            f"{estimate.correlation:.2f}, need at least {min_correlation}): the input does "
            "not hear the output. Check the wiring, the volume and the chosen devices."
        )
