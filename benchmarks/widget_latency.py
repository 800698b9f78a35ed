"""Latency of every explorer: a control's value changes → a new figure.

Every explorer of :mod:`dstoolkit.teaching` (the lab's measuring station aside: it measures
on a button press, not on a value change) is built in a Jupyter kernel (started by
nbclient, matplotlib's inline backend, as a reader of the notebooks meets it), then a
control's value is set ``--changes`` times, cycling through :data:`CHANGES`. Setting a
value runs the explorer's callback synchronously: the computation, the figure, its PNG
and the messages to the front end. The time from the assignment to its return is the
latency; the script prints its median (target < 80 ms), best and worst for every
explorer, then splits the filter widget's changes (the paper's 9.6 m case, 83
resonances, p = 3, ε = 0.05) into their parts in-process: the filter run, the figure
(kept and updated in place, as the widget does) and its PNG.

The changes of each explorer visit different values of several controls, so that no
change finds its whole result in a cache. The machine is shared: the load average is
printed with the figures. Run from the repository root:
    python benchmarks/widget_latency.py [--changes 12] [--only filter_widget ...]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import statistics
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

TARGET_S = 0.080

#: For each explorer (the call that builds it, as the chapters do), the (control, value)
#: changes applied in turn; every one changes the figure.
CHANGES: dict[str, tuple[tuple[str, object], ...]] = {
    "mass_function_explorer()": (
        ("low", 0.35),
        ("high", 0.15),
        ("mid", 0.05),
        ("low_mid", 0.25),
        ("low", 0.3),
        ("high", 0.05),
    ),
    "conflict_explorer()": (
        ("epsilon", 0.1),
        ("x", 0.9),
        ("rule", "Yager"),
        ("y", 0.8),
        ("epsilon", 0.2),
        ("rule", "Dempster"),
    ),
    "dependent_combination_explorer()": (
        ("a2", 0.5),
        ("b2", 0.2),
        ("mass_rule", "m1"),
        ("a3", 0.2),
        ("b3", 0.5),
        ("mass_rule", "min"),
    ),
    "noise_evidence_explorer()": (
        ("p", 4),
        ("epsilon", 0.1),
        ("upper", 0.4),
        ("mode", 0.1),
        ("p", 6),
        ("lower", -0.4),
    ),
    "bounded_error_explorer(v_half=0.1, w_half=1.0, steps=60, seed=7)": (
        ("scale", 0.5),
        ("scale", 0.8),
        ("scale", 1.5),
        ("scale", 2.0),
        ("scale", 0.6),
        ("scale", 2.5),
    ),
    "extension_explorer()": (
        ("hi", 2.5),
        ("function", "x²"),
        ("lo", -1.0),
        ("sign", -1),
        ("hi", 3.5),
        ("function", "exp(−x)"),
    ),
    "filter_widget()": (
        ("epsilon", 0.10),
        ("w_mode", -6.5),
        ("w_upper", -3.0),
        ("v_upper", 0.4),
        ("p", 4),
        ("start", "mean_corrected"),
    ),
    "filter_step_explorer()": (
        ("step", 3),
        ("step", 4),
        ("epsilon", 0.1),
        ("step", 5),
        ("start", "observation"),
        ("step", 6),
    ),
    "gauge_explorer()": (
        ("level", 4.0),
        ("temperature", 20.0),
        ("top_reflection", 0.5),
        ("background", 60.0),
        ("level", 6.0),
        ("temperature", 10.0),
    ),
    "level_estimation_explorer()": (
        ("level", 4.0),
        ("temperature", 20.0),
        ("seed", 1),
        ("figure", "Fig. 10: frequencies"),
        ("level", 6.0),
        ("order_rule", "true"),
    ),
    "noise_bounds_explorer()": (
        ("w_upper", -3.0),
        ("v_upper", 0.4),
        ("w_lower", -11.0),
        ("v_lower", -0.4),
        ("w_upper", -2.0),
        ("start", "observation"),
    ),
    "consistency_explorer(runs=20)": (
        ("scale", 0.75),
        ("orders", "eq43"),
        ("scale", 1.5),
        ("orders", "true"),
    ),
    "copies_explorer()": (
        ("shared", 0.7),
        ("copies", 5),
        ("shared", 0.2),
        ("copies", 2),
    ),
}

KERNEL_CODE = """
%matplotlib inline
import json, time
from dstoolkit import teaching as w
CHANGES = {changes!r}
out = {{}}
for call, changes in CHANGES.items():
    ex = eval("w." + call)
    display(ex)
    first = {{k: c.value for k, c in ex.controls.items()}}
    times = []
    for i in range({n}):
        name, value = changes[i % len(changes)]
        if ex.controls[name].value == value:  # a second round: go back to the start value
            value = first[name]
        before = ex.output.outputs
        start = time.perf_counter()
        ex.controls[name].value = value
        times.append(time.perf_counter() - start)
        assert ex.output.outputs is not before, "no new figure after changing " + name
    out[call] = times
print("LATENCY " + json.dumps(out))
"""


def in_kernel(changes: dict[str, tuple], n: int) -> dict[str, list[float]]:
    """Latencies (s) of ``n`` value changes of every explorer, made inside a kernel."""
    code = KERNEL_CODE.format(changes=changes, n=n)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    NotebookClient(
        nb, timeout=1800, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}
    ).execute()
    for out in nb.cells[0].outputs:
        if out.get("output_type") == "stream" and "LATENCY " in out.get("text", ""):
            line = next(t for t in out["text"].splitlines() if t.startswith("LATENCY "))
            return json.loads(line.removeprefix("LATENCY "))
    raise RuntimeError(f"the kernel printed no latencies: {nb.cells[0].outputs}")


def in_process(changes: int) -> dict[str, list[float]]:
    """Time the filter widget's changes without a kernel: filter run, figure and PNG."""
    import matplotlib

    matplotlib.use("Agg")

    from dstoolkit.plots import FilterErrorsFigure
    from dstoolkit.studies import filter_case
    from dstoolkit.teaching import filter_widget
    from dstoolkit.teaching._readouts import filter_summary

    with contextlib.redirect_stdout(io.StringIO()):  # no kernel: display() would print
        ex = filter_widget()
    values = ex.values()
    parts: dict[str, list[float]] = {"filter run": [], "figure": [], "PNG": []}
    kept = None  # the figure, kept and updated in place as the widget does
    pairs = CHANGES["filter_widget()"]
    for i in range(changes):
        name, value = pairs[i % len(pairs)]
        values[name] = value if values[name] != value else ex.controls[name].value
        start = time.perf_counter()
        seq, orders, result = filter_case(
            values["level"],
            values["temperature"],
            state_noise=(values["v_lower"], values["v_mode"], values["v_upper"]),
            obs_noise=(values["w_lower"], values["w_mode"], values["w_upper"]),
            p=values["p"],
            epsilon=values["epsilon"],
            start=values["start"],
            mass_rule=values["mass_rule"],
            orders=values["orders"],
        )
        run = time.perf_counter()
        if kept is None:
            kept = FilterErrorsFigure(result, seq.truth, seq.readings, title=name, pyplot=False)
        else:
            kept.update(result, seq.truth, seq.readings, title=name)
        fig = kept.figure
        filter_summary(seq, orders, result)
        drawn = time.perf_counter()
        ex.png(fig)
        done = time.perf_counter()
        parts["filter run"].append(run - start)
        parts["figure"].append(drawn - run)
        parts["PNG"].append(done - drawn)
    return parts


def _ms(values: list[float]) -> str:
    return (
        f"median {statistics.median(values) * 1e3:7.1f} ms   best "
        f"{min(values) * 1e3:7.1f} ms   worst {max(values) * 1e3:7.1f} ms"
    )


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--changes", type=int, default=12, help="value changes per explorer")
    parser.add_argument(
        "--only", nargs="*", default=None, help="explorer function names to time (default: all)"
    )
    args = parser.parse_args(argv)
    chosen = {
        call: pairs
        for call, pairs in CHANGES.items()
        if not args.only or call.split("(")[0] in args.only
    }
    print(
        f"{len(chosen)} explorers, {args.changes} value changes each; "
        f"{os.cpu_count()} CPUs, load average {_load()}\n"
    )
    print("in the kernel (value change → new figure displayed), target median < 80 ms:")
    for call, times in in_kernel(chosen, args.changes).items():
        verdict = "meets" if statistics.median(times) < TARGET_S else "MISSES"
        print(f"  {call.split('(')[0]:31s} {_ms(times)}   {verdict}")
    if "filter_widget()" in chosen:
        print("filter widget at the paper's 9.6 m case, in-process, by part:")
        for name, values in in_process(args.changes).items():
            print(f"  {name:11s} {_ms(values)}")
    print(f"load average after: {_load()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
