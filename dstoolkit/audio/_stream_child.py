"""The audio stream of :func:`dstoolkit.audio.play_record`, run in a child process.

A stalled or dead sound server can block PortAudio for ever, in the stream and again in
every call that would stop it. So the stream runs here, in a process of its own, and the
parent waits with a deadline and kills this process when the deadline passes: nothing
that can hang runs in the caller's process.

Run as a script (``python _stream_child.py``; it imports only numpy and sounddevice).
Protocol, on stdin: one JSON line ``{"samplerate", "latency", "device", "frames"}`` then
``frames`` float32 samples; on stdout: ``ready`` once sounddevice is imported, ``started``
once the stream runs, then one JSON line
(``{"status", "dropped", "frames"}`` followed by the recorded float32 samples, or
``{"error", "message"}``).
"""

from __future__ import annotations

import importlib
import json
import sys
import time


def main() -> int:
    import numpy as np

    out = sys.stdout.buffer
    header = json.loads(sys.stdin.buffer.readline())
    played = np.frombuffer(sys.stdin.buffer.read(4 * header["frames"]), dtype=np.float32)
    try:
        sd = importlib.import_module("sounddevice")  # untyped: imported by name

        out.write(b"ready\n")
        out.flush()
        recorded = sd.playrec(
            played,
            header["samplerate"],
            channels=1,
            dtype="float32",
            latency=header["latency"],
            device=tuple(header["device"]),
            blocking=False,
        )
        out.write(b"started\n")
        out.flush()
        stream = sd.get_stream()
        while stream.active:
            time.sleep(0.02)
        sd.wait()
        flags = sd.get_status()
    except Exception as exc:  # reported to the parent, which raises the package's error
        out.write(json.dumps({"error": type(exc).__name__, "message": str(exc)}).encode() + b"\n")
        out.flush()
        return 1
    data = np.ascontiguousarray(recorded[:, 0], dtype=np.float32)
    result = {
        "status": str(flags),
        "frames": int(data.size),
        "dropped": bool(flags.input_overflow or flags.output_underflow),
    }
    out.write(json.dumps(result).encode() + b"\n")
    out.write(data.tobytes())
    out.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
