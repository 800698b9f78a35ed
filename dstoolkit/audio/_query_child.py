"""PortAudio's answers about the sound devices, asked in a child process.

Loading PortAudio (``import sounddevice``) costs a process tens of MiB that it keeps until
it ends. Listing the devices needs it only for a moment, so :mod:`dstoolkit.audio`
asks here, in a short-lived process of its own, as it runs the stream itself
(``_stream_child.py``); the caller's process (a notebook's kernel) never loads PortAudio.
:func:`answer` is also what the caller runs in its own process when sounddevice is
already imported there.

Run as a script (``python _query_child.py REQUEST``; it imports only sounddevice).
``REQUEST`` is a JSON list: ``["import"]`` (sounddevice imports), ``["devices"]`` (every
device and the default input and output) or ``["device", device, kind]`` (the index of
one device, as ``sounddevice.query_devices(device, kind)`` resolves it). On stdout, one
JSON object: ``{"answer": ...}``, ``{"unavailable": "ExceptionType: message"}`` (the import
failed) or ``{"refused": message}`` (PortAudio refused the query).
"""

from __future__ import annotations

import importlib
import json
import sys
from types import ModuleType
from typing import Any


def answer(sd: ModuleType, request: list[Any]) -> dict[str, Any]:
    """Answer ``request`` (see the module's docstring) with the sounddevice module ``sd``.

    Returns the reply: ``{"answer": ...}``, or ``{"refused": message}`` with sounddevice's
    message when PortAudio refuses the query.
    """
    if request[0] == "import":
        return {"answer": None}
    if request[0] == "devices":
        try:
            infos = sd.query_devices()
            hostapis = sd.query_hostapis()
        except sd.PortAudioError as exc:
            return {"refused": str(exc)}
        default_in, default_out = sd.default.device
        devices = [
            {
                "index": int(info["index"]),
                "name": str(info["name"]),
                "hostapi": str(hostapis[info["hostapi"]]["name"]),
                "max_input_channels": int(info["max_input_channels"]),
                "max_output_channels": int(info["max_output_channels"]),
                "default_samplerate": float(info["default_samplerate"]),
            }
            for info in infos
        ]
        return {"answer": {"devices": devices, "default": [int(default_in), int(default_out)]}}
    _, device, kind = request
    try:
        info = sd.query_devices(device, kind)
    except (ValueError, sd.PortAudioError) as exc:
        return {"refused": str(exc)}
    return {"answer": int(info["index"])}


def main() -> int:
    request = json.loads(sys.argv[1])
    try:
        sd = importlib.import_module("sounddevice")  # untyped: imported by name
    except (ImportError, OSError) as exc:
        reply: dict[str, Any] = {"unavailable": f"{type(exc).__name__}: {exc}"}
    else:
        reply = answer(sd, request)
    sys.stdout.write(json.dumps(reply) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
