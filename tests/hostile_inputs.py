"""Hostile inputs shared by the tests and ``benchmarks/hostile_probe.py``.

- :func:`valid`: whether a value returned by the public API is valid (no NaN, evidence
  that its constructor accepts, masses summing to 1, finite estimates);
- :func:`crafted_recordings`: a corpus of crafted recordings for ``analyze``, made on the
  spot from one good recording. Each case is a file (or a FIFO, a device, a folder) and
  what ``analyze`` must do with it: give the level (``expect="level"``, within
  :data:`LEVEL_TOLERANCE_M` of the truth) or refuse it with a one-line package error
  (``expect="error"``);
- :func:`table3_signalled`: ``table3`` in a child process, stopped by a signal halfway
  (its CSV written, its figure being drawn);
- :func:`special_output`: an output path that is not a regular file or a new path (a link
  through ``/proc``, a FIFO, a socket, a device), which no command may write over;
- :func:`frame_evidence`, :func:`boxes_evidence` and :func:`traced_peak`: large evidence
  and the peak memory tracemalloc measures, to hold the memory budget to the real peak.
"""

from __future__ import annotations

import json
import math
import os
import socket
import struct
import subprocess
import sys
import time
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from dstoolkit.evidence import Dependence, Evidence, IntervalEvidence, MassFunction
from dstoolkit.evidence import validate_masses as _validate_masses
from dstoolkit.filters import FilterResult

TRUE_LEVEL_M = 2.6
TEMPERATURE_C = 26.0
LEVEL_TOLERANCE_M = 0.01
#: The analysis of one sweep may use this much memory whatever the file (its FFTs and
#: envelopes); beyond it, at most 4x the file size.
ANALYSIS_ALLOWANCE_BYTES = 64 * 2**20


def valid(value: Any) -> None:
    """Raise AssertionError when a returned value is invalid.

    Invalid are NaN numbers, an evidence its constructor refuses or whose masses do not sum
    to 1, and non-finite estimates.
    """
    if isinstance(value, Evidence):
        _validate_masses(value.mass)
        assert abs(float(np.sum(value.mass)) - 1.0) <= 1e-9
        if isinstance(value, IntervalEvidence):
            IntervalEvidence(value.boxes_lo, value.boxes_hi, value.mass)
        else:
            assert isinstance(value, MassFunction)
            MassFunction(value.as_dict(), value.frame)
    elif isinstance(value, Dependence):
        for name in ("energy1", "energy2", "joint_energy", "degree", "r12", "r21"):
            assert math.isfinite(getattr(value, name)), name
    elif isinstance(value, FilterResult):
        assert np.all(np.isfinite(value.estimates)), "NaN or inf in the estimates"
    elif isinstance(value, np.ndarray) and value.dtype.kind == "f":
        assert not np.any(np.isnan(value)), "NaN in a returned array"
    elif isinstance(value, float):
        assert not math.isnan(value), "NaN returned"
    elif isinstance(value, tuple):
        for item in value:
            valid(item)


@dataclass(frozen=True)
class Crafted:
    name: str
    path: Path
    expect: str  # "level" or "error"


def _chunk(tag: bytes, payload: bytes, size: int | None = None) -> bytes:
    size = len(payload) if size is None else size
    return tag + struct.pack("<I", size) + payload + b"\0" * (len(payload) % 2)


def _fmt(
    tag: int = 3,
    channels: int = 1,
    rate: int = 44100,
    bits: int = 32,
    align: int | None = None,
    extra: bytes = b"",
) -> bytes:
    align = channels * bits // 8 if align is None else align
    body = struct.pack("<HHIIHH", tag, channels, rate, (rate * max(align, 1)) % 2**32, align, bits)
    return _chunk(b"fmt ", body + extra)


def _info(comment: bytes, declared: int | None = None) -> bytes:
    body = b"INFO" + _chunk(b"ICMT", comment + b"\0")
    return _chunk(b"LIST", body, declared)


def _riff(*chunks: bytes, declared: int | None = None) -> bytes:
    body = b"WAVE" + b"".join(chunks)
    return b"RIFF" + struct.pack("<I", len(body) if declared is None else declared) + body


def good_recording() -> tuple[np.ndarray, int, dict]:
    """Return samples, sample rate and metadata (as a JSON dict) of a simulated 2.6 m tube."""
    from dstoolkit.audio import simulate_measurement
    from dstoolkit.gauge import TubeSetup

    rec = simulate_measurement(TubeSetup(level_m=TRUE_LEVEL_M, temperature_c=TEMPERATURE_C))
    return rec.samples, rec.samplerate, json.loads(rec.metadata.to_json())


def crafted_recordings(folder: Path) -> list[Crafted]:
    """Write the corpus into ``folder`` and list it."""
    samples, fs, meta = good_recording()
    f32 = samples.astype("<f4").tobytes()
    i16 = np.clip(np.round(samples * 32768), -32768, 32767).astype("<i2").tobytes()
    i24 = b"".join(
        int(v).to_bytes(3, "little", signed=True)
        for v in np.clip(np.round(samples[::1] * 2**23), -(2**23), 2**23 - 1).astype(int)
    )

    def comment(**changes: object) -> bytes:
        return json.dumps({**meta, **changes}).encode()

    good_info = _info(comment())
    good = _riff(_fmt(), _chunk(b"data", f32), good_info)
    cases: list[tuple[str, bytes | None, str]] = [
        ("good float32", good, "level"),
        ("16-bit PCM", _riff(_fmt(1, bits=16), _chunk(b"data", i16), good_info), "level"),
        ("24-bit PCM", _riff(_fmt(1, bits=24), _chunk(b"data", i24), good_info), "level"),
        (
            "unknown chunk first",
            _riff(_chunk(b"junk", b"x" * 301), _fmt(), _chunk(b"data", f32), good_info),
            "level",
        ),
        ("metadata before data", _riff(_fmt(), good_info, _chunk(b"data", f32)), "level"),
        (
            "odd RIFF size field",
            _riff(_fmt(), _chunk(b"data", f32), good_info, declared=7),
            "level",
        ),
        (
            "stereo, level on channel 0",
            _riff(
                _fmt(3, channels=2),
                _chunk(
                    b"data", np.stack([samples, np.zeros_like(samples)], 1).astype("<f4").tobytes()
                ),
                good_info,
            ),
            "level",
        ),
        (
            "unknown fields kept in extra",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(humidity=40, extra={"a": [1, 2]}))),
            "level",
        ),
        # truncated and bad chunk sizes
        ("empty file", b"", "error"),
        ("4 bytes", b"RIFF", "error"),
        ("header only", good[:12], "error"),
        ("cut inside fmt", good[:30], "error"),
        ("cut after fmt", good[:44], "error"),
        ("cut inside data", good[: len(good) // 2], "error"),
        ("data size beyond the file", _riff(_fmt(), _chunk(b"data", f32[:4000], 2**31)), "error"),
        ("data size 0xFFFFFFFF", _riff(_fmt(), b"data" + b"\xff" * 4 + f32[:4000]), "error"),
        ("no data chunk", _riff(_fmt(), good_info), "error"),
        ("no fmt chunk", _riff(_chunk(b"data", f32), good_info), "error"),
        (
            "two data chunks",
            _riff(_fmt(), _chunk(b"data", f32[:400]), _chunk(b"data", f32)),
            "error",
        ),
        (
            "two fmt chunks (rates differ)",
            _riff(_fmt(), _fmt(rate=fs + fs // 80), _chunk(b"data", f32), good_info),
            "error",
        ),
        (
            "two fmt chunks (the second after data)",
            _riff(_fmt(), _chunk(b"data", f32), _fmt(rate=fs - fs // 80), good_info),
            "error",
        ),
        (
            "data too short for the sweep",
            _riff(_fmt(), _chunk(b"data", f32[: 4 * fs]), good_info),
            "error",
        ),
        (
            "fmt size 8",
            _riff(_chunk(b"fmt ", b"\x01\x00\x01\x00abcd"), _chunk(b"data", f32)),
            "error",
        ),
        ("fmt size 2**31", _riff(b"fmt " + struct.pack("<I", 2**31) + b"\x01" * 16), "error"),
        (
            "many empty chunks",
            _riff(*[_chunk(b"pad ", b"")] * 5000, _fmt(), _chunk(b"data", f32)),
            "error",
        ),
        # bad fmt fields
        ("0 channels", _riff(_fmt(channels=0, align=4), _chunk(b"data", f32)), "error"),
        ("65535 channels", _riff(_fmt(channels=65535, align=4), _chunk(b"data", f32)), "error"),
        ("rate 0", _riff(_fmt(rate=0), _chunk(b"data", f32)), "error"),
        ("rate 4e9", _riff(_fmt(rate=4_000_000_000), _chunk(b"data", f32)), "error"),
        (
            "rate 8000 says metadata 44100",
            _riff(_fmt(rate=8000), _chunk(b"data", f32), good_info),
            "error",
        ),
        ("0 bits", _riff(_fmt(bits=0, align=4), _chunk(b"data", f32)), "error"),
        ("7 bits", _riff(_fmt(1, bits=7, align=1), _chunk(b"data", f32)), "error"),
        ("48-bit float", _riff(_fmt(3, bits=48), _chunk(b"data", f32)), "error"),
        ("block align 0", _riff(_fmt(align=0), _chunk(b"data", f32)), "error"),
        ("ADPCM", _riff(_fmt(2, bits=4, align=1), _chunk(b"data", f32)), "error"),
        ("silence", _riff(_fmt(), _chunk(b"data", bytes(len(f32))), good_info), "error"),
        (
            "NaN samples",
            _riff(
                _fmt(), _chunk(b"data", np.full(samples.size, np.nan, "<f4").tobytes()), good_info
            ),
            "error",
        ),
        # hostile metadata
        (
            "temperature a string",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(temperature_c="hot"))),
            "error",
        ),
        (
            "temperature 10**400",
            _riff(
                _fmt(),
                _chunk(b"data", f32),
                _info(
                    comment().replace(b'"temperature_c": 26.0', b'"temperature_c": 1' + b"0" * 400)
                ),
            ),
            "error",
        ),
        (
            "temperature NaN literal",
            _riff(
                _fmt(),
                _chunk(b"data", f32),
                _info(comment().replace(b'"temperature_c": 26.0', b'"temperature_c": NaN')),
            ),
            "error",
        ),
        (
            "temperature 1e6",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(temperature_c=1e6))),
            "error",
        ),
        (
            "extra a list",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(extra=[1, 2]))),
            "error",
        ),
        ("source a number", _riff(_fmt(), _chunk(b"data", f32), _info(comment(source=5))), "error"),
        (
            "onset +1e308",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(sweep_onset_s=1e308))),
            "error",
        ),
        (
            "onset -1e308",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(sweep_onset_s=-1e308))),
            "error",
        ),
        (
            "latency 1e308",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(latency_s=1e308))),
            "error",
        ),
        (
            "sweep 1e308 s",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(sweep_duration_s=1e308))),
            "error",
        ),
        (
            "sweep up to 1e9 Hz",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(f_stop_hz=1e9))),
            "error",
        ),
        (
            "taper -1",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(sweep_taper_s=-1.0))),
            "error",
        ),
        (
            "nested 200000 deep",
            _riff(
                _fmt(),
                _chunk(b"data", f32),
                _info(
                    b'{"dstoolkit_metadata": 1, "extra": ' + b"[" * 200_000 + b"]" * 200_000 + b"}"
                ),
            ),
            "error",
        ),
        (
            "nested 40 deep",
            _riff(
                _fmt(), _chunk(b"data", f32), _info(comment(extra=json.loads("[" * 40 + "]" * 40)))
            ),
            "error",
        ),
        (
            "metadata 1 MB",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(extra={"pad": "x" * 2**20}))),
            "error",
        ),
        (
            "LIST size 4 GB",
            _riff(
                _fmt(),
                _chunk(b"data", f32),
                good_info[:4] + struct.pack("<I", 2**32 - 2) + good_info[8:],
            ),
            "error",
        ),
        (
            "metadata not UTF-8",
            _riff(
                _fmt(),
                _chunk(b"data", f32),
                _info(b'{"dstoolkit_metadata": 1, "source": "\xff\xfe\x80", "temperature_c": 26}'),
            ),
            "error",
        ),
        (
            "metadata not JSON",
            _riff(_fmt(), _chunk(b"data", f32), _info(b"{dstoolkit_metadata: yes")),
            "error",
        ),
        (
            "metadata a list",
            _riff(_fmt(), _chunk(b"data", f32), _info(b'[{"dstoolkit_metadata": 1}]')),
            "error",
        ),
        (
            "no temperature",
            _riff(_fmt(), _chunk(b"data", f32), _info(comment(temperature_c=None))),
            "error",
        ),
        # not a recording at all
        ("random bytes", np.random.default_rng(0).bytes(100_000), "error"),
        ("an MP3", b"ID3\x03\x00" + bytes(5000), "error"),
        ("RIFF but AVI", b"RIFF" + struct.pack("<I", 4) + b"AVI ", "error"),
    ]
    out: list[Crafted] = []
    for i, (name, data, expect) in enumerate(cases):
        path = folder / f"case{i:02d}.wav"
        if data is not None:
            path.write_bytes(data)
        out.append(Crafted(name, path, expect))
    # things that are not regular files, and one too large to read
    fifo = folder / "fifo.wav"
    os.mkfifo(fifo)
    out.append(Crafted("a FIFO", fifo, "error"))
    out.append(Crafted("/dev/zero", Path("/dev/zero"), "error"))
    (folder / "folder.wav").mkdir()
    out.append(Crafted("a folder", folder / "folder.wav", "error"))
    huge = folder / "huge.wav"
    with open(huge, "wb") as fh:  # sparse: takes no disk space
        fh.write(good[:44])
        fh.truncate(2**31)
    out.append(Crafted("a 2 GiB file", huge, "error"))
    out.append(Crafted("a missing file", folder / "missing.wav", "error"))
    return out


#: The kinds of :func:`special_output`.
SPECIAL_OUTPUTS = (
    "a link to an open file's /proc entry",
    "a link to a FIFO",
    "a socket",
    "a link to /dev/null",
    "a FIFO",
    "a new file in /proc",
)


def special_output(kind: str, folder: Path) -> tuple[Path, Any]:
    """Make in ``folder`` an output path of a kind in :data:`SPECIAL_OUTPUTS`.

    Return it and what must stay open while it is used (an open file, a socket; close it
    after), or None.
    """
    path = folder / "fig.png"
    keep: Any = None
    if kind == SPECIAL_OUTPUTS[0]:
        keep = open(folder / "behind.txt", "w")  # noqa: SIM115 - held open on purpose
        path.symlink_to(f"/proc/self/fd/{keep.fileno()}")
    elif kind == SPECIAL_OUTPUTS[1]:
        os.mkfifo(folder / "fifo")
        path.symlink_to(folder / "fifo")
    elif kind == SPECIAL_OUTPUTS[2]:
        keep = socket.socket(socket.AF_UNIX)
        keep.bind(str(path))
    elif kind == SPECIAL_OUTPUTS[3]:
        path.symlink_to("/dev/null")
    elif kind == SPECIAL_OUTPUTS[4]:
        os.mkfifo(path)
    else:
        path = Path("/proc/dstoolkit-output.png")
    return path, keep


_SLOW_FIGURE = """
import pathlib, sys, time
import dstoolkit.plots
def slow(table):
    pathlib.Path(sys.argv[1]).write_text("ready")
    time.sleep(600)
dstoolkit.plots.plot_table3 = slow
from dstoolkit.cli import main
raise SystemExit(main(sys.argv[2:]))
"""


def table3_signalled(
    work: Path, sig: int, wait_s: float = 600.0, *, overwrite: bool = False
) -> tuple[int | None, str, bool]:
    """Run ``table3 --out work/out/t.csv`` in a child process and send ``sig`` to it.

    The run is one run of the direct method, and its figure never finishes; ``sig`` is sent
    once the CSV is written. Returns the exit status, what it printed on stderr, and whether
    the new CSV was in place when the signal went. The child uses the dstoolkit this process
    imported; ``overwrite`` adds ``--overwrite``.
    """
    import dstoolkit

    ready = work.parent / f".{work.name}.ready"
    csv = work / "out" / "t.csv"
    before = csv.read_bytes() if csv.is_file() else None
    env = {**os.environ, "PYTHONPATH": str(Path(dstoolkit.__file__).resolve().parents[1])}
    proc = subprocess.Popen(
        [
            sys.executable,
            "-c",
            _SLOW_FIGURE,
            str(ready),
            "table3",
            "--out",
            str(work / "out" / "t.csv"),
            "--runs",
            "1",
            "--methods",
            "direct",
            "--quiet",
            *(["--overwrite"] if overwrite else []),
        ],
        cwd=work,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    written = False
    try:
        deadline = time.monotonic() + wait_s
        while not ready.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        written = csv.is_file() and csv.read_bytes() != before  # the new CSV in place
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        ready.unlink(missing_ok=True)
    return proc.returncode, err, written


def frame_evidence(n: int, hypotheses: int = 24, seed: int = 0) -> MassFunction:
    """Make a mass function of ``n`` random focal sets on a frame of ``hypotheses``."""
    frame = [f"h{i}" for i in range(hypotheses)]
    rng = np.random.default_rng(seed)
    sets: set[frozenset[str]] = set()
    while len(sets) < n:
        keep = rng.random(hypotheses) < 0.5
        chosen = frozenset(h for h, k in zip(frame, keep, strict=True) if k)
        if chosen:
            sets.add(chosen)
    mass = rng.random(n)
    masses = dict(zip(sorted(sets, key=sorted), mass / mass.sum(), strict=True))
    return MassFunction(masses, frame=frame)


def boxes_evidence(n: int, dim: int = 1, seed: int = 0) -> IntervalEvidence:
    """Make interval evidence of ``n`` random boxes in ``dim`` dimensions (none equal)."""
    rng = np.random.default_rng(seed)
    lo = rng.random((n, dim))
    mass = rng.random(n)
    return IntervalEvidence(lo, lo + rng.random((n, dim)), mass / mass.sum(), merge=False)


def traced_peak(work: Callable[[], Any]) -> tuple[Any, int]:
    """Run ``work()`` and return its result and the peak memory tracemalloc saw, bytes."""
    tracemalloc.start()
    try:
        result = work()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return result, peak
