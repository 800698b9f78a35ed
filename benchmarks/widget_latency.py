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
change finds its whole result in a cache.

Then a drag: the explorer's first slider of :data:`CHANGES` is dragged for :data:`DRAG_S`
seconds, from its minimum to its maximum and back to its value in :data:`CHANGES` (a valid
setting), and released there. A front end sends a slider's value
every :data:`DRAG_GAP_S` while it is dragged if the slider has ``continuous_update``, else
once, on release; the kernel handles the messages in order, one at a time (a message that
arrives while a callback runs waits for it). The script sends them on that schedule and
prints the time from the release (the last message) to the final figure (the explorer's
``wait()``, where it has one: its work goes on after the callback returns), the renders
run during the drag and the worst time a message waited before its callback started.
``--follow-drag`` sends every value of the drag whatever the sliders say (what a slider
that follows the drag costs without a worker that drops the values in between).

The machine is shared: the load average is printed with the figures. Run from the
repository root:
    python benchmarks/widget_latency.py [--changes 12] [--only filter_widget ...] [--follow-drag]
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
#: How long the slider is dragged (minimum → maximum → a valid setting).
DRAG_S = 2.0
#: The gap between two values a front end sends while a slider is dragged (pointer events
#: come at the screen's 60 Hz; 50 Hz allows for the front end's own work).
DRAG_GAP_S = 0.020

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
    "consistency_explorer()": (
        ("scale", 0.55),
        ("orders", "eq43"),
        ("scale", 1.5),
        ("scale", 0.75),
        ("orders", "true"),
        ("scale", 1.25),
    ),
    "noise_bounds_explorer()": (
        ("w_upper", -3.0),
        ("v_upper", 0.4),
        ("w_lower", -11.0),
        ("v_lower", -0.4),
        ("w_upper", -2.0),
        ("start", "observation"),
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


DRAG_CODE = """
%matplotlib inline
import json, time
from dstoolkit import teaching as w
CHANGES = {changes!r}
out = {{}}
for call, changes in CHANGES.items():
    ex = eval("w." + call)
    display(ex)
    name = next(n for n, _ in changes if hasattr(ex.controls[n], "step"))
    c = ex.controls[name]
    target = next(v for n, v in changes if n == name)
    count = int(round({drag} / {gap}))
    half = count // 2  # minimum to maximum, then back to a valid setting
    values = [c.min + (c.max - c.min) * i / half for i in range(half)] + [
        c.max + (target - c.max) * (i + 1) / (count - half) for i in range(count - half)]
    values = [min(c.max, max(c.min, round(v / c.step) * c.step)) for v in values]
    if not ({follow} or c.continuous_update):
        values = values[-1:]  # the slider sends its value on release only
    renders = []
    ex.output.observe(lambda change: renders.append(1), "outputs")
    start = time.perf_counter()
    late = 0.0
    for i, value in enumerate(values, start=count - len(values)):
        due = start + i * {gap}
        now = time.perf_counter()
        if now < due:
            time.sleep(due - now)
        late = max(late, time.perf_counter() - due)
        c.value = value
    released = start + (count - 1) * {gap}
    getattr(ex, "wait", lambda: None)()
    done = time.perf_counter()
    out[call] = {{"control": name, "final": done - released, "renders": len(renders),
                 "sent": len(values), "late": late}}
print("DRAG " + json.dumps(out))
"""


def _run_in_kernel(code: str, tag: str) -> dict:
    """Run ``code`` in a fresh kernel at the repository root; return its ``tag`` line's JSON."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    NotebookClient(
        nb, timeout=1800, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}
    ).execute()
    for out in nb.cells[0].outputs:
        if out.get("output_type") == "stream" and f"{tag} " in out.get("text", ""):
            line = next(t for t in out["text"].splitlines() if t.startswith(f"{tag} "))
            return json.loads(line.removeprefix(f"{tag} "))
    raise RuntimeError(f"the kernel printed no {tag} line: {nb.cells[0].outputs}")


def drag(changes: dict[str, tuple], follow: bool) -> dict[str, dict]:
    """Drag every explorer's first slider for ``DRAG_S`` and release it, inside a kernel."""
    code = DRAG_CODE.format(changes=changes, drag=DRAG_S, gap=DRAG_GAP_S, follow=follow)
    return _run_in_kernel(code, "DRAG")


def in_kernel(changes: dict[str, tuple], n: int) -> dict[str, list[float]]:
    """Latencies (s) of ``n`` value changes of every explorer, made inside a kernel."""
    return _run_in_kernel(KERNEL_CODE.format(changes=changes, n=n), "LATENCY")


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
    parser.add_argument(
        "--follow-drag",
        action="store_true",
        help="send every value of the drag, whatever the sliders' continuous_update",
    )
    parser.add_argument("--drag-only", action="store_true", help="time the drag only")
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
    if not args.drag_only:
        print("in the kernel (value change → new figure displayed), target median < 80 ms:")
        for call, times in in_kernel(chosen, args.changes).items():
            verdict = "meets" if statistics.median(times) < TARGET_S else "MISSES"
            print(f"  {call.split('(')[0]:31s} {_ms(times)}   {verdict}")
    sends = "every value" if args.follow_drag else "as the sliders send them"
    print(
        f"drag the first slider {DRAG_S:.0f} s ({sends}, every {DRAG_GAP_S * 1e3:.0f} ms), "
        "release: time to the final figure"
    )
    for call, got in drag(chosen, args.follow_drag).items():
        print(
            f"  {call.split('(')[0]:31s} {got['control']:10s} final {got['final'] * 1e3:8.1f} ms"
            f"   {got['renders']:3d} renders of {got['sent']:3d} values sent"
            f"   worst wait for the callback {got['late'] * 1e3:7.1f} ms"
        )
    if "filter_widget()" in chosen and not args.drag_only:
        print("filter widget at the paper's 9.6 m case, in-process, by part:")
        for name, values in in_process(args.changes).items():
            print(f"  {name:11s} {_ms(values)}")
    print(f"load average after: {_load()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
