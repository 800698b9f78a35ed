"""In-process latency of the noise-bounds explorer, and the batch time of each of its filters.

The explorer of the chapter beyond the paper (``dstoolkit.teaching.noise_bounds_explorer``)
is built with matplotlib's Agg backend, then its controls are set as
``widget_latency.py``'s :data:`CHANGES` set them, ``--rounds`` times (a fresh explorer each
round, so that no change finds its result in the explorer's cache). For each value change
the script prints the median and best wall time and the median CPU time of the process
(every thread's). Then it times one batch of every filter of
:func:`dstoolkit.studies.all_filters` on the explorer's runs (20 runs of 40 steps) with the
bounds of one change, as ``noise_mismatch`` runs them. The machine is shared: the load
average is printed with the figures. Run from the repository root:
    python benchmarks/noise_bounds_profile.py [--rounds 6] [--repeat 15]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from widget_latency import CHANGES  # noqa: E402

from dstoolkit.filters import BoundedNoise  # noqa: E402
from dstoolkit.gauge import gauge_state_space_model  # noqa: E402
from dstoolkit.studies import all_filters, tracking_data  # noqa: E402
from dstoolkit.teaching import noise_bounds_explorer  # noqa: E402


def explorer_changes(rounds: int) -> tuple[list[float], list[float]]:
    """Wall and CPU seconds of every value change (the first round warms up, untimed)."""
    wall, cpu = [], []
    for rnd in range(rounds + 1):
        ex = noise_bounds_explorer()
        for name, value in CHANGES["noise_bounds_explorer()"]:
            began, began_cpu = time.perf_counter(), time.process_time()
            ex.controls[name].value = value
            if rnd:
                wall.append(time.perf_counter() - began)
                cpu.append(time.process_time() - began_cpu)
    return wall, cpu


def filter_batches(repeat: int) -> dict[str, tuple[float, float]]:
    """Median wall and CPU seconds of one batch of every filter, bounds of one change."""
    data = tracking_data()
    model = gauge_state_space_model(BoundedNoise(-0.4, 0.0, 0.4), BoundedNoise(-11.0, -7.0, -2.0))
    out = {}
    for name, flt in all_filters(0).items():
        flt.run_batch(model, data.readings, inputs=data.orders)  # compiles, fills caches
        wall, cpu = [], []
        for _ in range(repeat):
            began, began_cpu = time.perf_counter(), time.process_time()
            flt.run_batch(model, data.readings, inputs=data.orders)
            wall.append(time.perf_counter() - began)
            cpu.append(time.process_time() - began_cpu)
        out[name] = statistics.median(wall), statistics.median(cpu)
    return out


def main() -> None:
    """Print the explorer's latency and the filters' batch times."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=6, help="rounds of the value changes")
    parser.add_argument("--repeat", type=int, default=15, help="batches timed per filter")
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs, load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    wall, cpu = explorer_changes(args.rounds)
    print(
        f"noise_bounds_explorer, {len(wall)} value changes in-process: median "
        f"{1e3 * statistics.median(wall):.1f} ms, best {1e3 * min(wall):.1f} ms, "
        f"CPU median {1e3 * statistics.median(cpu):.1f} ms"
    )
    print("one batch (20 runs × 40 steps), median of", args.repeat)
    for name, (w, c) in filter_batches(args.repeat).items():
        print(f"  {name:<20} {1e3 * w:7.1f} ms   CPU {1e3 * c:7.1f} ms")
    print(f"load average after: {', '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
