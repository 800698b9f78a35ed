"""Time the gauge: synthesise one recording and detect its resonances.

The recording lasts 5 s at 44.1 kHz with the paper's sweep, at three levels, noise-free and
noisy: its synthesis in a new tube each time (the sound is computed; the noise draws of the
seed are kept, as when the gauge explorer's level moves), the same recording again (its
sound is kept) and its detection; then one observation-noise characterisation over the
paper's 30 calibration levels (what Table 3's waveform-level simulation repeats for every
run). The machine may be shared: the load average is printed with the figures.

Prints medians of repeated runs. Run: python benchmarks/gauge_synthesis.py
"""

from __future__ import annotations

import itertools
import os
import time
import timeit
from dataclasses import replace

import numpy as np

from dstoolkit.gauge import (
    PAPER_SWEEP,
    RecordingConditions,
    TubeSetup,
    characterise_observation_noise,
    detect_resonances,
    spl_to_pa,
    synthesize_recording,
)

CONDITIONS = {
    "noise-free": RecordingConditions(),
    "noisy": RecordingConditions(
        speaker_jitter_hz=0.1,
        microphone_noise_pa=spl_to_pa(40.0),
        background_noise_pa=spl_to_pa(70.0),
        latency_s=0.02,
    ),
}


def median_ms(fn, repeat: int = 7) -> float:
    return 1e3 * float(np.median(timeit.repeat(fn, number=1, repeat=repeat)))


def main() -> None:
    print(
        f"sweep {PAPER_SWEEP.f_start:g} → {PAPER_SWEEP.f_stop:g} Hz in "
        f"{PAPER_SWEEP.duration:g} s at {PAPER_SWEEP.sample_rate:g} Hz"
    )
    print(f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(
        f"{'level':>6} {'conditions':>11} {'echoes':>6} {'synthesis ms':>13} "
        f"{'again ms':>9} {'detection ms':>13} {'resonances':>10}"
    )
    nudge = itertools.count(1)  # a new tube every run: 1 nm deeper
    for level, temp in [(1.3, 27.0), (4.6, 26.5), (9.6, 23.9)]:
        setup = TubeSetup(level, temp)
        for name, cond in CONDITIONS.items():
            rec = synthesize_recording(setup, PAPER_SWEEP, cond, seed=0)
            t_new = median_ms(
                lambda s=setup, c=cond: synthesize_recording(
                    replace(s, level_m=s.level_m + 1e-9 * next(nudge)), PAPER_SWEEP, c
                )
            )
            t_syn = median_ms(lambda s=setup, c=cond: synthesize_recording(s, PAPER_SWEEP, c))
            t_det = median_ms(lambda r=rec: detect_resonances(r))
            det = detect_resonances(rec)
            print(
                f"{level:6.1f} {name:>11} {setup.echo_count(PAPER_SWEEP.f_start):6d} "
                f"{t_new:13.1f} {t_syn:9.1f} {t_det:13.1f} {det.frequencies.size:10d}"
            )
    start = time.perf_counter()
    w = characterise_observation_noise(seed=0)
    print(
        f"observation-noise characterisation, 30 levels: {time.perf_counter() - start:.2f} s"
        f" ({w.summary()})"
    )
    print(f"load average after {', '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
