"""Time the filters on a gauge-like sequence: one run, and a batch of runs.

The sequence is the paper's 9.6 m case: 23.9 °C, band 1000–2500 Hz, f_F ≈ 18 Hz, 83
resonances read with the paper's observation noise, orders n_k from the readings (eq. 43).
For each filter in :data:`REGISTRY` this prints

- one run: the median and best wall time of ``run`` over ``--repeat`` runs, and the median
  CPU time of the process (the machine is shared: the wall time also counts waits for a
  core);
- per step: the one-run median divided by the 82 steps, beside the floor this machine
  sets (the table's first row): the time per iteration of an empty loop of the same
  length that makes one numpy call on one-element arrays (``np.add(a, b, out=c)``); the
  column "× floor" is their ratio, the number of such calls a step costs;
- a batch: the wall and CPU time of ``run_batch`` on ``--runs`` sequences and the
  throughput in filter steps per second (wall, then CPU), one step = one transition
  k → k+1 (82 per sequence).

Each filter runs on two models of eqs. 39–40: the package's gauge model
(``gauge_state_space_model``) and the same maps written by a user with the public
:class:`~dstoolkit.filters.StateSpaceModel` (plain numpy ``f``, ``g``, ``g_inverse``, the
monotonicity declared, no Jacobians): the column "model" says which.
Targets: the paper's filter < 5 ms per run and > 100,000 steps/s in a batch of 1000;
Kalman < 0.5 ms per run; a user's model within 1.5× of the package's. The machine is
shared: the load average is printed before and after the figures. Where a step of the
paper's filter goes, block by block (time and numpy calls per step against the floor, and
what the compiled kernel of Step 6 buys):
``benchmarks/filter_profile.py``. Run from the repository root:

    python benchmarks/filters.py [--runs 1000] [--repeat 30] [--filters a,b] [--models a,b]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dstoolkit.filters import (
    BoundedErrorFilter,  # noqa: E402
    ComparisonSettings,  # noqa: E402
    DependentEvidenceFilter,  # noqa: E402
    Filter,  # noqa: E402
    KalmanFilter,  # noqa: E402
    NassreddineFilter,  # noqa: E402
    ParticleFilter,  # noqa: E402
    StateSpaceModel,  # noqa: E402
    registered_filters,  # noqa: E402
)
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge  # noqa: E402


@dataclass(frozen=True)
class Entry:
    """A filter to time: how to build it, and what its settings are."""

    make: Callable[[], Filter[Any, Any]]
    settings: str


#: Filters timed by this script; add rivals with :func:`register`.
REGISTRY: dict[str, Entry] = {}


def register(name: str, make: Callable[[], Filter[Any, Any]], settings: str) -> None:
    """Add a filter under ``name``: ``make()`` returns an object with run/run_batch."""
    REGISTRY[name] = Entry(make, settings)


register(
    "dependent_evidence",
    DependentEvidenceFilter,
    "paper's filter, p = 3, ε = 0.05, m(D) = min, start z_1",
)
if importlib.util.find_spec("numba") is not None:
    register(
        "dependent_numba",
        lambda: DependentEvidenceFilter(kernel="numba"),
        "the same, Step 6 compiled (extra speed: numba)",
    )
register(
    "nassreddine",
    NassreddineFilter,
    "Nassreddine et al. 2010, p = 3, ε = 0.05, ≤ 32 focal elements (clustering)",
)
if importlib.util.find_spec("numba") is not None:
    register(
        "nassreddine_numba",
        lambda: NassreddineFilter(kernel="numba"),
        "the same, merge and clustering compiled (extra speed: numba), same numbers",
    )
register(
    "nassreddine_restart",
    lambda: NassreddineFilter(restart=True),
    "the same, state evidence rebuilt as x̂_k + E_v each step",
)
register("bounded_error", BoundedErrorFilter, "one box, interval image ∩ reading box")
register("kalman", KalmanFilter, "(extended) Kalman on the noises' means and variances")
register("particle", ParticleFilter, "bootstrap, 1000 particles, systematic resampling")
# every other filter of the comparisons (dstoolkit.filters.registered_filters), as they run it
for _entry in registered_filters():
    if _entry.name not in REGISTRY:
        register(
            _entry.name,
            lambda entry=_entry: entry.make(ComparisonSettings()),
            f"{_entry.label}, with the comparisons' settings",
        )


def user_gauge_model() -> StateSpaceModel:
    """Build eqs. 39–40 as a user writes them with the public StateSpaceModel.

    Plain numpy maps, no Jacobians (finite differences).
    """

    def f(x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return x * (u + 1.0) / u

    def g_inverse(
        lo: np.ndarray, hi: np.ndarray, x_lo: np.ndarray, x_hi: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        return np.maximum(lo, x_lo), np.minimum(hi, x_hi)

    package = gauge_state_space_model()
    return StateSpaceModel(
        f=f,
        g=lambda x: x + 0.0,
        g_inverse=g_inverse,
        state_noise=package.state_noise,
        obs_noise=package.obs_noise,
        f_monotone=(1, 1),
        g_monotone=(1,),
        name="user's gauge",
    )


#: The two models every filter is timed on.
MODELS: dict[str, Callable[[], StateSpaceModel]] = {
    "package": gauge_state_space_model,
    "user": user_gauge_model,
}


def time_single(
    flt: Filter[Any, Any], model: StateSpaceModel, z: np.ndarray, u: np.ndarray, repeat: int
) -> tuple[float, float, float]:
    """Time one run: median and best wall time (s), after a warm-up run, and median CPU time.

    The CPU time (s) is this process's: on a shared machine the wall time also counts the
    waits for a core, the CPU time does not.
    """
    flt.run(model, z, u)
    times, cpu = [], []
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        flt.run(model, z, u)
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return statistics.median(times), min(times), statistics.median(cpu)


def numpy_call_floor(steps: int, repeat: int = 200) -> float:
    """Measure the median time (s) per iteration of a loop making one numpy call each.

    The loop has ``steps`` iterations, each making one numpy call on one-element arrays:
    what a step costs per numpy call it makes.
    """
    a, b, c = np.ones(1), np.ones(1), np.empty(1)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(steps):
            np.add(a, b, out=c)
        times.append(time.perf_counter() - start)
    return statistics.median(times) / steps


def load_average() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def time_batch(
    flt: Filter[Any, Any], model: StateSpaceModel, z: np.ndarray, u: np.ndarray, repeat: int = 2
) -> tuple[float, float]:
    """Best wall time and best CPU time (s) of one batch run."""
    best, best_cpu = np.inf, np.inf
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        flt.run_batch(model, z, u)
        best = min(best, time.perf_counter() - start)
        best_cpu = min(best_cpu, time.process_time() - start_cpu)
    return best, best_cpu


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1000, help="sequences in the batch")
    parser.add_argument("--repeat", type=int, default=30, help="timed single runs")
    parser.add_argument(
        "--filters",
        default=",".join(REGISTRY),
        help=f"comma-separated names among {', '.join(REGISTRY)}",
    )
    parser.add_argument(
        "--models",
        default=",".join(MODELS),
        help=f"comma-separated models among {', '.join(MODELS)}",
    )
    args = parser.parse_args(argv)
    names = [name for name in args.filters.split(",") if name]
    unknown = sorted(set(names) - set(REGISTRY))
    if unknown:
        parser.error(f"unknown filter(s) {unknown}; known: {sorted(REGISTRY)}")

    models = [name for name in args.models.split(",") if name]
    if set(models) - set(MODELS):
        parser.error(
            f"unknown model(s) {sorted(set(models) - set(MODELS))}; known: {sorted(MODELS)}"
        )
    one = simulate_gauge(seed=0)
    many = simulate_gauge(runs=args.runs, seed=1)
    steps = one.orders.size - 1
    print(
        f"gauge-like sequence: L = {one.level_m} m, T = {one.temperature_c} °C, "
        f"f_F = {one.fundamental_hz:.2f} Hz, {one.orders.size} resonances "
        f"(n = {one.orders[0]}..{one.orders[-1]}), {steps} filter steps per run"
    )
    floor = numpy_call_floor(steps)
    print(f"numpy {np.__version__}, {os.cpu_count()} CPUs, load average {load_average()}")
    print(
        f"per step = one-run median / {steps} steps; × floor = per step / the time per "
        f"iteration of an empty {steps}-step loop\nmaking one numpy call on one-element "
        "arrays (the first row): how many such calls a step costs\n"
    )
    print(
        f"{'filter':20s} {'model':8s} {'one run: median':>15s} {'best':>8s} {'CPU':>8s} "
        f"{'per step':>9s} {'× floor':>7s} {'batch of':>8s} {'time':>7s} {'CPU':>7s} "
        f"{'steps/s':>10s} {'(CPU)':>10s}  settings"
    )
    print(
        f"{'floor':20s} {'':8s} {'':15s} {'':8s} {'':8s} {floor * 1e6:6.2f} µs {1:7.0f}"
        f"{'':47s}  one numpy call per step, np.add(a, b, out=c)"
    )
    for name, model_name in ((n, m) for n in names for m in models):
        entry, model = REGISTRY[name], MODELS[model_name]()
        flt = entry.make()
        median, best, cpu = time_single(flt, model, one.readings, one.inputs, args.repeat)
        batch, batch_cpu = time_batch(flt, model, many.readings, many.inputs)
        print(
            f"{name:20s} {model_name:8s} {median * 1e3:12.2f} ms {best * 1e3:5.2f} ms "
            f"{cpu * 1e3:5.2f} ms "
            f"{median / steps * 1e6:6.2f} µs {median / steps / floor:7.0f} {args.runs:8d} "
            f"{batch:5.2f} s {batch_cpu:5.2f} s {args.runs * steps / batch:10,.0f} "
            f"{args.runs * steps / batch_cpu:10,.0f}  {entry.settings}"
        )
    print(
        f"\nload average after: {load_average()}; floor again: "
        f"{numpy_call_floor(steps) * 1e6:.2f} µs per step"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
