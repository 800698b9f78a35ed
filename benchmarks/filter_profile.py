"""Where one step of the paper's filter goes: time and numpy calls per block.

One run of the paper's 9.6 m case (83 resonances, 82 steps, p = 3, ε = 0.05) on the array
path of :class:`~dstoolkit.filters.DependentEvidenceFilter`. For each block of a step
(Steps 2–6 of §3.2) this prints

- the median time per step over ``--repeat`` runs (each block timed around its method);
- the numpy function calls it makes per step (counted in a separate run, by handing the
  modules a numpy that counts: ufunc calls and reductions, ``copyto``, ``matmul``...;
  array methods and indexing are not counted), the model's own calls (f, g, g⁻¹ of the
  gauge model) included;
- that count times the floor: the time of one numpy call on a one-element array in a
  loop (``np.add(a, b, out=c)``), what a block would cost if each call did no work.

"rest" is the run time per step minus the blocks (median over the runs): the loop of
``_run_arrays``, its views and the copy of the diagnostics, the start of a run (buffers,
x̂_1), and the block timers themselves. The compiled kernel
(``kernel="numba"``, extra ``speed``) replaces the three blocks of Step 6 by one call; its
line shows what it buys. Last, the same blocks in a batch of ``--runs`` runs, in CPU time
per run and step: there the passes over the arrays (Step 6's 65 × 17 products per run)
cost more than the calls. Run from the repository root:

    python benchmarks/filter_profile.py [--repeat 30] [--runs 1000]
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import statistics
import sys
import time
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dstoolkit.filters import DependentEvidenceFilter  # noqa: E402
from dstoolkit.gauge import gauge_state_space_model, simulate_gauge  # noqa: E402

#: The blocks of a step: label, method of the array path's StepArrays.
BLOCKS: tuple[tuple[str, str], ...] = (
    ("Step 2  prediction f(x̂ + V) + V (eqs. 13, 16–19)", "_predict"),
    ("Step 3  observation prediction g(·)", "_observe"),
    ("Step 4  Dempster's rule with z + W (eq. 1)", "_fuse_observation"),
    ("Step 5  g⁻¹ within the predicted boxes, snapping", "_map_back"),
    ("Step 6  dependence D, R12, R21 (eqs. A1–A6)", "_dependence"),
    ("Step 6  discounting onto Θ1, Θ2 (eqs. A7–A8)", "_discount"),
    ("Step 6  Dempster's rule, E (eq. 20), hull", "_combine"),
    ("Step 6  compiled kernel (numba)", "_fuse_compiled"),
)
#: Modules whose numpy calls are counted: the array path, its kernels, the gauge model.
MODULES = (
    "dstoolkit.filters._dependent_arrays",
    "dstoolkit.evidence._batch_kernels",
    "dstoolkit.evidence._boxes",
    "dstoolkit.filters._model",
    "dstoolkit.gauge._gauge_model",
    "dstoolkit.gauge._level",
)
STEP_CLASS = "dstoolkit.filters._dependent_arrays"


class _CountingUfunc:
    """A ufunc that counts its calls and reductions."""

    def __init__(self, ufunc: np.ufunc, counts: Counter[str]) -> None:
        self._ufunc, self._counts = ufunc, counts

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        self._counts["calls"] += 1
        return self._ufunc(*args, **kwargs)

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self._ufunc, name)
        if name in ("reduce", "reduceat", "accumulate", "outer", "at"):

            def counted(*args: Any, **kwargs: Any) -> Any:
                self._counts["calls"] += 1
                return attr(*args, **kwargs)

            return counted
        return attr


class _CountingNumpy:
    """The numpy module, with every function and ufunc counting its calls."""

    def __init__(self, counts: Counter[str]) -> None:
        self._counts = counts

    def __getattr__(self, name: str) -> Any:
        attr = getattr(np, name)
        if isinstance(attr, np.ufunc):
            return _CountingUfunc(attr, self._counts)
        if callable(attr) and not isinstance(attr, type):

            def counted(*args: Any, **kwargs: Any) -> Any:
                self._counts["calls"] += 1
                return attr(*args, **kwargs)

            return counted
        return attr


@contextmanager
def counting_numpy(counts: Counter[str]) -> Iterator[None]:
    """Hand :data:`MODULES` a numpy that counts calls into ``counts["calls"]``."""
    modules = [importlib.import_module(name) for name in MODULES]
    saved = [module.np for module in modules]  # type: ignore[attr-defined]
    for module in modules:
        module.np = _CountingNumpy(counts)  # type: ignore[attr-defined]
    try:
        yield
    finally:
        for module, original in zip(modules, saved, strict=True):
            module.np = original  # type: ignore[attr-defined]


@contextmanager
def timed_blocks(
    times: dict[str, list[int]],
    calls: dict[str, int],
    counts: Counter[str],
    clock: Callable[[], int] = time.perf_counter_ns,
) -> Iterator[None]:
    """Wrap each block's method to record its calls.

    Each call adds its time (ns of ``clock``) to ``times`` and the numpy calls it made to
    ``calls``.
    """
    step_arrays = importlib.import_module(STEP_CLASS).StepArrays
    saved = {name: getattr(step_arrays, name) for _, name in BLOCKS}

    def wrap(name: str, method: Callable[..., Any]) -> Callable[..., Any]:
        def timed(*args: Any, **kwargs: Any) -> Any:
            before, start = counts["calls"], clock()
            try:
                return method(*args, **kwargs)
            finally:
                times[name].append(clock() - start)
                calls[name] += counts["calls"] - before

        return timed

    for name, method in saved.items():
        setattr(step_arrays, name, wrap(name, method))
    try:
        yield
    finally:
        for name, method in saved.items():
            setattr(step_arrays, name, method)


def numpy_call_floor(repeat: int = 2000) -> float:
    """Median time (s) of one numpy call on one-element arrays, in a loop."""
    a, b, c = np.ones(1), np.ones(1), np.empty(1)
    samples = []
    for _ in range(25):
        start = time.perf_counter()
        for _ in range(repeat):
            np.add(a, b, out=c)
        samples.append((time.perf_counter() - start) / repeat)
    return statistics.median(samples)


def profile(
    flt: DependentEvidenceFilter, repeat: int
) -> tuple[float, float, dict[str, float], dict[str, float], float]:
    """Profile a filter's run, untimed and with the block timers.

    Return the median run time (s) untimed; with the block timers, the median run time (s)
    and each block's median µs per step; each block's numpy calls per step and the whole
    run's.
    """
    model, seq = gauge_state_space_model(), simulate_gauge(seed=0)
    steps = seq.orders.size - 1
    run = lambda: flt.run(model, seq.readings, seq.inputs)  # noqa: E731
    run()
    runs = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        runs.append(time.perf_counter() - start)
    counts: Counter[str] = Counter()
    calls: dict[str, int] = Counter()
    with counting_numpy(counts), timed_blocks({name: [] for _, name in BLOCKS}, calls, counts):
        run()
    total_calls = counts["calls"] / steps
    times: dict[str, list[int]] = {name: [] for _, name in BLOCKS}
    timed_runs, per_run = [], []
    with timed_blocks(times, Counter(), Counter()):
        for _ in range(repeat):
            for name in times:
                times[name].clear()
            start = time.perf_counter()
            run()
            timed_runs.append(time.perf_counter() - start)
            blocks = {name: sum(values) / steps / 1e3 for name, values in times.items()}
            blocks["rest"] = timed_runs[-1] / steps * 1e6 - sum(blocks.values())
            per_run.append(blocks)
    medians = {name: statistics.median(r[name] for r in per_run) for name in per_run[0]}
    return (
        statistics.median(runs),
        statistics.median(timed_runs),
        medians,
        {name: calls[name] / steps for _, name in BLOCKS},
        total_calls,
    )


def report(title: str, flt: DependentEvidenceFilter, repeat: int, floor: float) -> float:
    """Print one filter's table; returns its median µs per step."""
    median, timed, block_us, block_calls, total_calls = profile(flt, repeat)
    steps = simulate_gauge(seed=0).orders.size - 1
    per_step = median / steps * 1e6
    print(
        f"\n{title}: one run {median * 1e3:.2f} ms (median of {repeat}), "
        f"{per_step:.1f} µs per step, {total_calls:.0f} numpy calls per step "
        f"(≥ {total_calls * floor * 1e6:.1f} µs at the floor); with the block timers "
        f"{timed * 1e3:.2f} ms:"
    )
    print(f"  {'block':52s} {'µs/step':>8s} {'calls':>6s} {'µs/call':>8s} {'floor':>7s}")
    for label, name in BLOCKS:
        if not block_calls[name] and not block_us[name]:
            continue
        calls = block_calls[name]
        print(
            f"  {label:52s} {block_us[name]:8.1f} {calls:6.0f} "
            f"{block_us[name] / max(calls, 1):8.2f} {calls * floor * 1e6:7.1f}"
        )
    rest_calls = total_calls - sum(block_calls.values())
    print(
        f"  {'rest: loop, views, diagnostics table, timers':52s} {block_us['rest']:8.1f} "
        f"{rest_calls:6.0f} {'':8s} {rest_calls * floor * 1e6:7.1f}"
    )
    return per_step


def batch_blocks(flt: DependentEvidenceFilter, runs: int) -> tuple[float, dict[str, float]]:
    """Time ``run_batch`` on ``runs`` sequences, in CPU time (s), and each block within it.

    Each block's time is in CPU µs per run and step (a batch is bound by the passes over its
    arrays, not by the calls).
    """
    model, seq = gauge_state_space_model(), simulate_gauge(runs=runs, seed=1)
    steps = runs * (seq.orders.size - 1)
    flt.run_batch(model, seq.readings[:2], seq.inputs[:2])
    times: dict[str, list[int]] = {name: [] for _, name in BLOCKS}
    with timed_blocks(times, Counter(), Counter(), clock=time.process_time_ns):
        start = time.process_time()
        flt.run_batch(model, seq.readings, seq.inputs)
        total = time.process_time() - start
    blocks = {name: sum(values) / steps / 1e3 for name, values in times.items()}
    blocks["rest"] = total / steps * 1e6 - sum(blocks.values())
    return total, blocks


def report_batch(filters: dict[str, DependentEvidenceFilter], runs: int) -> None:
    """Print the blocks of a batch, CPU µs per run and step, one column per filter."""
    results = {title: batch_blocks(flt, runs) for title, flt in filters.items()}
    steps = runs * (simulate_gauge(seed=0).orders.size - 1)
    chunk = next(iter(filters.values())).chunk_size
    print(f"\na batch of {runs} runs (chunks of {chunk}), CPU µs per run and step:")
    print(f"  {'block':52s}" + "".join(f" {title:>10s}" for title in results))
    for label, name in (*BLOCKS, ("rest: loop, run starts, timers", "rest")):
        values = [blocks[name] for _, blocks in results.values()]
        if any(values):
            print(f"  {label:52s}" + "".join(f" {value:10.2f}" for value in values))
    print(
        f"  {'steps per second (CPU)':52s}"
        + "".join(f" {steps / total:10,.0f}" for total, _ in results.values())
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=30, help="timed runs per filter")
    parser.add_argument("--runs", type=int, default=1000, help="runs in the batch (0: none)")
    args = parser.parse_args(argv)
    floor = numpy_call_floor()
    print(
        f"numpy {np.__version__}, {os.cpu_count()} CPUs, load average "
        f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}; floor: one numpy call on a "
        f"one-element array = {floor * 1e6:.2f} µs"
    )
    numpy_step = report("numpy path", DependentEvidenceFilter(), args.repeat, floor)
    if importlib.util.find_spec("numba") is not None:
        compiled_step = report(
            "compiled Step 6 (kernel='numba', extra speed)",
            DependentEvidenceFilter(kernel="numba"),
            args.repeat,
            floor,
        )
        print(
            f"\nthe compiled kernel saves {numpy_step - compiled_step:.1f} µs per step "
            f"({numpy_step / compiled_step:.2f}× faster per run)"
        )
    else:
        print("\n(numba not installed: pip install dstoolkit[speed] to time the compiled kernel)")
    if args.runs:
        filters = {"numpy": DependentEvidenceFilter()}
        if importlib.util.find_spec("numba") is not None:
            filters["numba"] = DependentEvidenceFilter(kernel="numba")
        report_batch(filters, args.runs)
    print(f"load average after: {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
