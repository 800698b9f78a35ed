"""Measure virtual-tube levels through the PulseAudio loopback, repeatedly.

This is the lab's measurement path end to end, without a speaker or microphone.

Starts the loopback (scripts/audio-loopback.sh; stops it again if it started it), then for
each of the paper's levels runs ``--repeat`` measurements with the paper's sweep
(1000 → 2400 Hz, 5 s, 44.1 kHz) played through the virtual tube and prints the measured
latency, the level error, the stated uncertainty, the time of one measurement (audio and
analysis) and of the analysis alone, and how many tries it took (a try whose stream
dropped samples is repeated). Run: python benchmarks/audio_loopback.py
"""

from __future__ import annotations

import argparse
import os
import subprocess
import time
from pathlib import Path

import numpy as np

from dstoolkit import audio
from dstoolkit.audio import analyze, record_measurement
from dstoolkit.gauge import TubeSetup

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "audio-loopback.sh"
LEVELS = [(1.3, 27.0), (2.6, 26.5), (5.6, 26.5), (7.6, 26.5), (9.6, 23.9)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--device", default="pulse")
    args = parser.parse_args()
    proc = subprocess.run(["bash", str(SCRIPT)], capture_output=True, text=True, check=True)
    state = dict(line.split("=", 1) for line in proc.stdout.splitlines() if "=" in line)
    os.environ.update({k: v for k, v in state.items() if k.startswith("PULSE_")})
    audio.refresh_devices()
    print(
        f"{'level m':>8} {'run':>4} {'latency ms':>11} {'error mm':>9} {'sigma mm':>9} "
        f"{'measure s':>10} {'analyse s':>10} {'tries':>6}"
    )
    errors, latencies, totals = [], [], []
    try:
        for level, temperature in LEVELS:
            for run in range(args.repeat):
                t0 = time.perf_counter()
                rec = record_measurement(
                    virtual_tube=TubeSetup(level_m=level, temperature_c=temperature),
                    input_device=args.device,
                    output_device=args.device,
                )
                t1 = time.perf_counter()
                result = analyze(rec)
                t2 = time.perf_counter()
                errors.append(result.error_m)
                latencies.append(result.latency_s)
                totals.append(t2 - t0)
                print(
                    f"{level:>8.1f} {run + 1:>4d} {1e3 * result.latency_s:>11.1f} "
                    f"{1e3 * result.error_m:>+9.1f} {1e3 * result.level.uncertainty_m:>9.1f} "
                    f"{t2 - t0:>10.2f} {t2 - t1:>10.3f} {rec.metadata.extra['attempt']:>6}"
                )
    finally:
        if state.get("DSTOOLKIT_LOOPBACK_STATE") == "started":
            subprocess.run(
                ["bash", str(SCRIPT), "stop"], capture_output=True, env={**os.environ, **state}
            )
    e = 1e3 * np.abs(errors)
    print(
        f"\n{len(errors)} measurements: |error| mean {e.mean():.1f} mm, max {e.max():.1f} mm; "
        f"latency {1e3 * min(latencies):.1f}..{1e3 * max(latencies):.1f} ms; "
        f"one measurement {np.median(totals):.2f} s (median)"
    )


if __name__ == "__main__":
    main()
