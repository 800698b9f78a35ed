"""Wall time of the full Table 3 reproduction.

10 levels × 100 runs × all methods, frequency-level and waveform-level. Run: python
benchmarks/table3.py [--runs N] [--only K]
"""

from __future__ import annotations

import argparse
import time

from dstoolkit.studies import run_table3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--runs", type=int, default=100)
    parser.add_argument("--only", choices=("frequency", "waveform"), default=None)
    args = parser.parse_args()
    kinds = (args.only,) if args.only else ("frequency", "waveform")
    for simulation in kinds:
        start = time.perf_counter()
        table = run_table3(runs=args.runs, seed=0, simulation=simulation, progress=True)
        elapsed = time.perf_counter() - start
        per_method: dict[str, float] = {}
        for r in table.rows:
            per_method[r.method] = per_method.get(r.method, 0.0) + r.seconds_per_run * r.runs
        print(f"{simulation}-level Table 3, {args.runs} runs x 10 levels: {elapsed:.1f} s wall")
        for m, s in per_method.items():
            print(f"    {m:<20} {s:8.2f} s in the method")


if __name__ == "__main__":
    main()
